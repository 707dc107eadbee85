// The register map's single source: the generated C++ header, C header,
// SystemRDL and the checked-in docs/register-map.md all agree with
// regmap/odoloc.yaml (read here independently with yaml-cpp), and the
// generator refuses inconsistent descriptions.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "odoloc/regmap/regmap.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/eppm.hpp"
#include "odoloc/rtl/odometry.hpp"

extern "C" {
unsigned odoloc_c_register_count(void);
unsigned odoloc_c_eppm_steering_speed_addr(void);
unsigned odoloc_c_speed_mode_mask(void);
unsigned odoloc_c_odometry_cfg_reset(void);
unsigned odoloc_c_policy_rear_only(void);
unsigned odoloc_c_set_decode(unsigned word, unsigned value);
}

namespace {

namespace regs = odoloc::regs;
using odoloc::regmap::RegmapError;

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

regs::Access access_named(const std::string& a) {
  if (a == "ro")
    return regs::Access::kRo;
  if (a == "rw")
    return regs::Access::kRw;
  if (a == "w1c")
    return regs::Access::kW1c;
  if (a == "rc")
    return regs::Access::kRc;
  return regs::Access::kW1p;
}

// Walks the YAML by hand and finds each register in the generated table.
TEST(RegisterMap, GeneratedCppHeaderMatchesTheDescription) {
  const YAML::Node root = YAML::LoadFile(ODOLOC_REGMAP_YAML);
  std::set<std::string> seen;
  for (const auto& block : root["blocks"]) {
    if (block["reserved"])
      continue;
    std::vector<std::string> instances;
    for (const auto& i : block["instances"])
      instances.push_back(i.as<std::string>());
    const auto count = std::max<std::size_t>(1, instances.size());
    for (std::size_t i = 0; i < count; ++i) {
      for (const auto& reg : block["registers"]) {
        const std::string path = block["name"].as<std::string>() + "." +
                                 (instances.empty() ? "" : instances[i] + ".") +
                                 reg["name"].as<std::string>();
        SCOPED_TRACE(path);
        const regs::Register* r = regs::find(path);
        ASSERT_NE(r, nullptr);
        const auto stride = block["stride"] ? block["stride"].as<unsigned>() : 0U;
        EXPECT_EQ(r->address,
                  block["base"].as<unsigned>() + i * stride + reg["offset"].as<unsigned>());
        EXPECT_EQ(r->access, access_named(reg["access"].as<std::string>()));
        std::uint32_t reset = 0, rw = 0, w1c = 0;
        ASSERT_EQ(r->fields.size(), reg["fields"].size());
        for (std::size_t f = 0; f < r->fields.size(); ++f) {
          const auto& yf = reg["fields"][f];
          const auto& field = r->fields[f];
          const unsigned msb = yf["bits"][0].as<unsigned>(), lsb = yf["bits"][1].as<unsigned>();
          EXPECT_EQ(field.name, yf["name"].as<std::string>());
          EXPECT_EQ(field.lsb, lsb);
          EXPECT_EQ(field.width, msb - lsb + 1);
          const std::uint32_t value = yf["reset"] ? yf["reset"].as<std::uint32_t>() : 0U;
          reset |= value << lsb;
          const auto access =
              access_named((yf["access"] ? yf["access"] : reg["access"]).as<std::string>());
          EXPECT_EQ(field.access, access);
          if (access == regs::Access::kRw)
            rw |= field.mask();
          if (access == regs::Access::kW1c)
            w1c |= field.mask();
        }
        EXPECT_EQ(r->reset, reset);
        EXPECT_EQ(r->rw_mask, rw);
        EXPECT_EQ(r->w1c_mask, w1c);
        seen.insert(path);
      }
    }
  }
  EXPECT_EQ(seen.size(), std::size(regs::kRegisters));
  EXPECT_EQ(odoloc_c_register_count(), std::size(regs::kRegisters));
}

// The model's configuration resets are the register map's reset values.
TEST(RegisterMap, ModelResetValuesMatchTheRegisterMap) {
  const odoloc::rtl::EppmConfig eppm;
  EXPECT_EQ(eppm.filter_clocks.value(), regs::eppm::cfg::filter_clocks.reset);
  EXPECT_EQ(eppm.decode_mode.value(), regs::eppm::cfg::decode_mode.reset);
  EXPECT_EQ(eppm.speed_mode_select.value(), regs::eppm::cfg::speed_mode_select.reset);
  EXPECT_EQ(eppm.window_clocks.value(), regs::eppm::window::clocks.reset);
  EXPECT_EQ(eppm.prescale.value(), regs::eppm::prescale::divider.reset);
  EXPECT_EQ(eppm.to_period_below.value(), regs::eppm::to_period_below::edges.reset);
  EXPECT_EQ(eppm.to_pulse_at.value(), regs::eppm::to_pulse_at::edges.reset);
  EXPECT_EQ(eppm.stall_ticks.value(), regs::eppm::stall_ticks::ticks.reset);
  EXPECT_EQ(regs::eppm::window::clocks.width, decltype(eppm.window_clocks)::width);
  const odoloc::rtl::OdometryConfig odo;
  EXPECT_EQ(odo.update_clocks.value(), regs::odometry::cfg::update_clocks.reset);
  EXPECT_EQ(odo.policy.value(), regs::odometry::cfg::policy.reset);
  EXPECT_EQ(odo.select_shift.value(), regs::odometry::cfg::select_shift.reset);
  EXPECT_EQ(odo.steer_limit.value(), regs::odometry::steer_limit::value.reset);
  EXPECT_EQ(static_cast<unsigned>(odoloc::rtl::MinSelectPolicy::kFrontOnly),
            static_cast<unsigned>(regs::odometry::cfg::Policy::kFrontOnly));
  EXPECT_EQ(static_cast<unsigned>(odoloc::rtl::DecodeMode::kX1),
            static_cast<unsigned>(regs::eppm::cfg::DecodeMode::kX1));
}

TEST(RegisterMap, CHeaderAgreesWithTheCppHeader) {
  EXPECT_EQ(odoloc_c_eppm_steering_speed_addr(), regs::eppm::speed::address(3));
  EXPECT_EQ(odoloc_c_speed_mode_mask(), regs::eppm::speed::mode.mask());
  EXPECT_EQ(odoloc_c_odometry_cfg_reset(), regs::odometry::cfg::kReset);
  EXPECT_EQ(odoloc_c_policy_rear_only(),
            static_cast<unsigned>(regs::odometry::cfg::Policy::kRearOnly));
  for (unsigned v = 0; v < 4; ++v) {
    EXPECT_EQ(odoloc_c_set_decode(0xFFFFFFFFU, v),
              regs::eppm::cfg::decode_mode.set(0xFFFFFFFFU, v));
  }
}

TEST(RegisterMap, FieldHelpersAreMaskBased) {
  constexpr auto& f = regs::eppm::speed::value;  // bits 23:0, signed
  EXPECT_EQ(f.mask(), 0x00FFFFFFU);
  EXPECT_EQ(f.get_signed(0x07FFFFFFU), -1);
  EXPECT_EQ(f.get_signed(0x00800000U), -8388608);
  EXPECT_EQ(f.set(0xFF000000U, 5), 0xFF000005U);
  EXPECT_EQ(regs::find(0x3FFU), nullptr);
  EXPECT_EQ(regs::find("eppm.left_rear.nope"), nullptr);
  for (const auto& reserved : regs::kReserved) {
    for (unsigned a = reserved.base; a < reserved.base + reserved.size; ++a) {
      EXPECT_EQ(regs::find(a), nullptr);
    }
  }
}

TEST(RegisterMap, CheckedInDocsAreUpToDate) {
  EXPECT_EQ(read_file(ODOLOC_SOURCE_DIR "/docs/register-map.md"), read_file(ODOLOC_REGMAP_MARKDOWN))
      << "docs/register-map.md is stale: cmake --build --preset default --target regmap_docs";
}

TEST(RegisterMap, SystemRdlPlacesEveryRegisterAtItsByteAddress) {
  const auto map = odoloc::regmap::load(ODOLOC_REGMAP_YAML);
  const std::string rdl = odoloc::regmap::emit_systemrdl(map);
  long depth = 0;
  for (const char c : rdl) {
    depth += c == '{' ? 1 : c == '}' ? -1 : 0;
    ASSERT_GE(depth, 0);
  }
  EXPECT_EQ(depth, 0);
  for (const auto& block : map.blocks) {
    for (const auto& r : block.registers) {
      std::ostringstream want;
      want << "} " << r.name << " @ 0x" << std::hex << 4 * r.offset << ";";
      EXPECT_NE(rdl.find(want.str()), std::string::npos) << want.str();
    }
  }
}

// A minimal valid description to break one way at a time.
std::string description(const std::string& blocks) {
  return "map: {name: t, address_bits: 8, data_bits: 32}\nblocks:\n" + blocks;
}
const std::string kGoodBlock =
    "  - name: a\n    base: 0x10\n    registers:\n"
    "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: [7, 0], reset: 1}]}\n";

void expect_rejected(const std::string& yaml, const std::string& reason) {
  try {
    odoloc::regmap::parse(yaml);
    ADD_FAILURE() << "accepted: " << yaml;
  } catch (const RegmapError& e) {
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

TEST(RegisterMapGenerator, AcceptsAMinimalDescription) {
  EXPECT_NO_THROW(odoloc::regmap::parse(description(kGoodBlock)));
}

TEST(RegisterMapGenerator, RejectsInconsistentDescriptions) {
  expect_rejected(description(kGoodBlock + kGoodBlock), "duplicate block 'a'");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: [0, 0]}]}\n"
                  "      - {name: r, offset: 1, access: rw, fields: [{name: f, bits: [0, 0]}]}\n"),
      "duplicate register 'r'");
  expect_rejected(
      description(kGoodBlock +
                  "  - name: b\n    base: 0x10\n    registers:\n"
                  "      - {name: s, offset: 0, access: ro, fields: [{name: f, bits: [0, 0]}]}\n"),
      "overlaps a.r");
  expect_rejected(
      description(kGoodBlock + "  - {name: u, base: 0x8, size: 0x10, reserved: true}\n"),
      "overlaps");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: [32, 0]}]}\n"),
      "wider than the 32-bit register");
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n"
                              "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: "
                              "[7, 0]}, {name: g, bits: [8, 7]}]}\n"),
                  "overlaps another field");
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n"
                              "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: "
                              "[3, 0], reset: 16}]}\n"),
                  "reset value does not fit");
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n"
                              "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: "
                              "[0, 0], enum: {x: 2}}]}\n"),
                  "enum value does not fit");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rx, fields: [{name: f, bits: [0, 0]}]}\n"),
      "unknown access 'rx'");
  expect_rejected(
      description("  - name: a\n    base: 0x100\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: [0, 0]}]}\n"),
      "outside the 8-bit space");
  expect_rejected(
      description("  - name: a\n    base: 0\n    stride: 2\n    instances: [p, p]\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: [0, 0]}]}\n"),
      "duplicate instance");
  expect_rejected("map: [unterminated", "YAML");
  expect_rejected(description("  - name: A\n    base: 0\n    registers: []\n"), "lower_snake_case");
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n"
                              "      - {name: r, offset: 0, access: rw, fields: [{name: f, bits: "
                              "[0, 0], description: one, two}]}\n"),
                  "unknown key 'two'");
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n"
                              "      - {name: r, offest: 0, access: rw, fields: []}\n"),
                  "unknown key 'offest'");
}

}  // namespace
