// The register map's single source: the generated C++ header, C header,
// SystemRDL and the checked-in docs/register-map.md all agree with
// regmap/odoloc.yaml (read here independently with yaml-cpp), and the
// generator refuses inconsistent descriptions.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <bit>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include "odoloc/logic/regfile_map.hpp"
#include "odoloc/ports.hpp"
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
unsigned odoloc_c_fabric_clock_period_ns(void);
unsigned odoloc_c_spi_max_sclk_hz(void);
unsigned odoloc_c_spi_crc_polynomial(void);
}

namespace {

namespace regs = odoloc::regs;
namespace ports = odoloc::ports;
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
  if (a == "rpop")
    return regs::Access::kRpop;
  return regs::Access::kW1p;
}

regs::HwAccess hw_named(const std::string& h) {
  if (h == "r")
    return regs::HwAccess::kR;
  if (h == "w")
    return regs::HwAccess::kW;
  if (h == "set")
    return regs::HwAccess::kSet;
  if (h == "count")
    return regs::HwAccess::kCount;
  return regs::HwAccess::kNone;
}

std::uint64_t ones(unsigned width) {
  return width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
}

// The description as this test reads it, independently of the generator:
// one entry per register word at its address, register arrays and wide
// registers split by hand.
struct YField {
  std::string name;
  unsigned lsb = 0, width = 0;  // in the register word
  regs::Access access{};
  regs::HwAccess hw{};
  bool is_signed = false;
  std::uint32_t reset = 0;
  unsigned port_width = 0, port_shift = 0;  // the hardware port and this slice's place in it
  bool port_signed = false;
  [[nodiscard]] std::uint32_t mask() const {
    return static_cast<std::uint32_t>(ones(width) << lsb);
  }
};
struct YRegister {
  std::string path, block, port_register;  // port_register: the wide or array name
  int instance = -1;
  int element = -1;  // the index in a register array
  int count = 0;     // the array's elements
  unsigned address = 0;
  regs::Access access{};
  std::vector<YField> fields;
};

std::vector<YRegister> read_description() {
  const YAML::Node root = YAML::LoadFile(ODOLOC_REGMAP_YAML);
  std::vector<YRegister> out;
  for (const auto& block : root["blocks"]) {
    if (block["reserved"])
      continue;
    std::vector<std::string> instances;
    for (const auto& i : block["instances"])
      instances.push_back(i.as<std::string>());
    const auto count = std::max<std::size_t>(1, instances.size());
    const auto stride = block["stride"] ? block["stride"].as<unsigned>() : 0U;
    for (std::size_t i = 0; i < count; ++i) {
      for (const auto& reg : block["registers"]) {
        const unsigned words = reg["words"] ? reg["words"].as<unsigned>() : 1U;
        const int elements = reg["count"] ? reg["count"].as<int>() : 0;
        for (int e = elements == 0 ? -1 : 0; e < elements; ++e) {
          for (unsigned w = 0; w < words; ++w) {
            YRegister r;
            r.block = block["name"].as<std::string>();
            r.instance = instances.empty() ? -1 : static_cast<int>(i);
            r.element = e;
            r.count = elements;
            r.port_register = reg["name"].as<std::string>();
            const std::string name = r.port_register + (e < 0 ? "" : std::to_string(e)) +
                                     (words == 1 ? ""
                                      : w == 0   ? "_lo"
                                                 : "_hi");
            r.path = r.block + "." + (instances.empty() ? "" : instances[i] + ".") + name;
            r.address = block["base"].as<unsigned>() + static_cast<unsigned>(i) * stride +
                        reg["offset"].as<unsigned>() +
                        static_cast<unsigned>(std::max(e, 0)) * words + w;
            r.access = access_named(reg["access"].as<std::string>());
            for (const auto& yf : reg["fields"]) {
              const unsigned msb = yf["bits"][0].as<unsigned>(), lsb = yf["bits"][1].as<unsigned>();
              const unsigned lo = 32 * w, hi = lo + 31;
              if (msb < lo || lsb > hi)
                continue;
              YField f;
              f.name = yf["name"].as<std::string>();
              f.lsb = std::max(lsb, lo) - lo;
              f.width = std::min(msb, hi) - lo - f.lsb + 1;
              f.port_width = msb - lsb + 1;
              f.port_shift = std::max(lsb, lo) - lsb;
              f.port_signed = yf["signed"] && yf["signed"].as<bool>();
              f.is_signed = f.port_signed && msb <= hi;
              const std::uint64_t reset = yf["reset"] ? yf["reset"].as<std::uint64_t>() : 0U;
              f.reset = static_cast<std::uint32_t>((reset >> f.port_shift) & ones(f.width));
              f.access =
                  access_named((yf["access"] ? yf["access"] : reg["access"]).as<std::string>());
              f.hw = hw_named((yf["hw"] ? yf["hw"] : reg["hw"]).as<std::string>());
              r.fields.push_back(f);
            }
            out.push_back(std::move(r));
          }
        }
      }
    }
  }
  return out;
}

const std::vector<YRegister>& description_registers() {
  static const std::vector<YRegister> registers = read_description();
  return registers;
}

// Walks the YAML by hand and finds each register in the generated table.
TEST(RegisterMap, GeneratedCppHeaderMatchesTheDescription) {
  std::set<std::string> seen;
  for (const YRegister& y : description_registers()) {
    SCOPED_TRACE(y.path);
    const regs::Register* r = regs::find(y.path);
    ASSERT_NE(r, nullptr);
    EXPECT_EQ(r->address, y.address);
    EXPECT_EQ(r->access, y.access);
    std::uint32_t reset = 0, rw = 0, w1c = 0, w1p = 0, constant = 0;
    ASSERT_EQ(r->fields.size(), y.fields.size());
    for (std::size_t f = 0; f < r->fields.size(); ++f) {
      const YField& yf = y.fields[f];
      const auto& field = r->fields[f];
      EXPECT_EQ(field.name, yf.name);
      EXPECT_EQ(field.lsb, yf.lsb);
      EXPECT_EQ(field.width, yf.width);
      EXPECT_EQ(field.is_signed, yf.is_signed) << yf.name;
      EXPECT_EQ(field.reset, yf.reset) << yf.name;
      EXPECT_EQ(field.access, yf.access);
      EXPECT_EQ(field.hw, yf.hw) << yf.name;
      reset |= yf.reset << yf.lsb;
      if (yf.access == regs::Access::kRw)
        rw |= yf.mask();
      if (yf.access == regs::Access::kW1c)
        w1c |= yf.mask();
      if (yf.access == regs::Access::kW1p)
        w1p |= yf.mask();
      if (yf.access == regs::Access::kRo && yf.hw == regs::HwAccess::kNone)
        constant |= yf.mask();
    }
    EXPECT_EQ(r->reset, reset);
    EXPECT_EQ(r->rw_mask, rw);
    EXPECT_EQ(r->w1c_mask, w1c);
    EXPECT_EQ(r->w1p_mask, w1p);
    EXPECT_EQ(r->const_mask, constant);
    seen.insert(y.path);
  }
  EXPECT_EQ(seen.size(), std::size(regs::kRegisters));
  EXPECT_EQ(odoloc_c_register_count(), std::size(regs::kRegisters));
}

// The global facts: the clock and the SPI limits come from the YAML; the
// derived ones are computed by the generator.
TEST(RegisterMap, GlobalFactsComeFromTheDescription) {
  const YAML::Node root = YAML::LoadFile(ODOLOC_REGMAP_YAML);
  const auto clock = root["map"]["clock_hz"].as<std::uint32_t>();
  EXPECT_EQ(regs::kFabricClockHz, clock);
  EXPECT_EQ(regs::kFabricClockPeriodNs * clock, 1000000000U);
  const YAML::Node spi = root["spi"];
  EXPECT_EQ(regs::spi::kMaxBurst, spi["max_burst"].as<unsigned>());
  EXPECT_EQ(regs::spi::kMinLevelClocks, spi["min_level_clocks"].as<unsigned>());
  EXPECT_EQ(regs::spi::kMaxSclkHz, clock / (2 * spi["min_level_clocks"].as<unsigned>()));
  EXPECT_EQ(regs::spi::kCrcPolynomial, spi["crc"]["polynomial"].as<unsigned>());
  EXPECT_EQ(regs::spi::kCrcInit, spi["crc"]["init"].as<unsigned>());
  EXPECT_EQ(regs::spi::kCrcXorOut, spi["crc"]["xor_out"].as<unsigned>());
  static_assert(std::is_same_v<decltype(regs::spi::kCrcPolynomial), const std::uint8_t>);
  EXPECT_EQ(regs::kFabricClockHz, 50000000U);
  EXPECT_EQ(regs::kFabricClockPeriodNs, 20U);
  EXPECT_EQ(regs::spi::kMaxSclkHz, 6250000U);
  EXPECT_EQ(odoloc_c_fabric_clock_period_ns(), regs::kFabricClockPeriodNs);
  EXPECT_EQ(odoloc_c_spi_max_sclk_hz(), regs::spi::kMaxSclkHz);
  EXPECT_EQ(odoloc_c_spi_crc_polynomial(), regs::spi::kCrcPolynomial);
}

// The model takes its configuration, status and enums from the generated
// headers, so its resets are the register map's (FabricPorts.DefaultsAreTheResetValues).
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

// The HLS kernels' C++14 map (odoloc/logic/regfile_map.hpp) holds the same
// registers, masks, resets, FIFOs and SPI facts as odoloc/regs.hpp; its
// hw_mask is every field the hardware drives.
TEST(RegisterMap, HlsMapAgreesWithTheCppHeader) {
  namespace hm = odoloc::logic::regfile_map;
  ASSERT_EQ(static_cast<std::size_t>(hm::kRegisterCount), std::size(regs::kRegisters));
  for (std::size_t i = 0; i < std::size(regs::kRegisters); ++i) {
    const regs::Register& r = regs::kRegisters[i];
    const hm::Register& h = hm::kRegisters[i];
    std::uint32_t driven = 0;
    for (const regs::Field& f : r.fields)
      if (f.hw == regs::HwAccess::kW || f.hw == regs::HwAccess::kSet ||
          f.hw == regs::HwAccess::kCount)
        driven |= f.mask();
    std::string name(r.path);
    std::replace(name.begin(), name.end(), '.', '_');
    EXPECT_EQ(h.address, r.address) << r.path;
    EXPECT_EQ(h.reset, r.reset) << r.path;
    EXPECT_EQ(h.rw_mask, r.rw_mask) << r.path;
    EXPECT_EQ(h.w1c_mask, r.w1c_mask) << r.path;
    EXPECT_EQ(h.w1p_mask, r.w1p_mask) << r.path;
    EXPECT_EQ(h.const_mask, r.const_mask) << r.path;
    EXPECT_EQ(h.hw_mask, driven) << r.path;
    EXPECT_EQ(h.snapshot, r.snapshot) << r.path;
    EXPECT_EQ(h.pop_window, r.pop_window) << r.path;
    EXPECT_EQ(hm::kRegisterNames[i], name);
  }
  ASSERT_EQ(static_cast<std::size_t>(hm::kPopWindowCount), std::size(regs::kPopWindows));
  for (std::size_t w = 0; w < std::size(regs::kPopWindows); ++w) {
    const regs::PopWindow& r = regs::kPopWindows[w];
    EXPECT_EQ(hm::kPopWindows[w].first, r.first);
    EXPECT_EQ(hm::kPopWindows[w].entries, r.entries);
    EXPECT_EQ(hm::kPopWindows[w].words, r.words);
    std::string name(r.path);
    std::replace(name.begin(), name.end(), '.', '_');
    EXPECT_EQ(hm::kPopWindowNames[w], name);
  }
  EXPECT_EQ(hm::kAddressBits, static_cast<int>(regs::kAddressBits));
  EXPECT_EQ(hm::spi::kMaxBurst, static_cast<int>(regs::spi::kMaxBurst));
  EXPECT_EQ(hm::spi::kCrcPolynomial, regs::spi::kCrcPolynomial);
  EXPECT_EQ(hm::spi::kCrcInit, regs::spi::kCrcInit);
  EXPECT_EQ(hm::spi::kCrcXorOut, regs::spi::kCrcXorOut);
  EXPECT_EQ(hm::eppm::speed::address(3), regs::eppm::speed::address(3));
  EXPECT_EQ(hm::tof_channel::entry::address(2, 5), regs::tof_channel::entry::address(2, 5));
  EXPECT_EQ(hm::odometry::command::kAddress, regs::odometry::command::kAddress);
  EXPECT_EQ(hm::odometry::cfg::kReset, regs::odometry::cfg::kReset);
  EXPECT_EQ(hm::eppm::speed::mode.mask(), regs::eppm::speed::mode.mask());
  EXPECT_EQ(hm::odometry::cfg::select_shift.reset, regs::odometry::cfg::select_shift.reset);
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

// ---- odoloc/ports.hpp ------------------------------------------------------

template <class T>
struct PortTraits;
template <int W>
struct PortTraits<odoloc::rtl::UInt<W>> {
  static constexpr bool kSigned = false;
  static constexpr unsigned kWidth = W;
  static std::uint64_t raw(odoloc::rtl::UInt<W> v) { return v.value(); }
  static void assign(odoloc::rtl::UInt<W>& p, std::uint64_t bits) {
    p = odoloc::rtl::UInt<W>::truncate(bits);
  }
};
template <int W>
struct PortTraits<odoloc::rtl::SInt<W>> {
  static constexpr bool kSigned = true;
  static constexpr unsigned kWidth = W;
  static std::uint64_t raw(odoloc::rtl::SInt<W> v) { return v.raw_bits(); }
  static void assign(odoloc::rtl::SInt<W>& p, std::uint64_t bits) {
    p = odoloc::rtl::UInt<W>::truncate(bits).as_sint();
  }
};

// Which struct a field belongs to, by the test's own reading of the rules.
bool in_config(const YField& f) {
  return f.access == regs::Access::kRw && f.hw == regs::HwAccess::kR;
}
bool in_pulses(const YField& f) {
  return (f.access == regs::Access::kW1c && f.hw == regs::HwAccess::kSet) ||
         (f.access == regs::Access::kW1p && f.hw == regs::HwAccess::kR);
}
bool in_status(const YField& f) {
  return f.hw == regs::HwAccess::kW || f.hw == regs::HwAccess::kSet ||
         f.hw == regs::HwAccess::kCount;
}

// A port's place: block, instance, register (wide or array name), element
// (-1: not in an array), field.
std::string port_key(std::string_view block, int instance, std::string_view reg, int element,
                     std::string_view field) {
  return std::string(block) + "/" + std::to_string(instance) + "/" + std::string(reg) + "/" +
         std::to_string(element) + "/" + std::string(field);
}
std::string port_key(const YRegister& r, const YField& f) {
  return port_key(r.block, r.instance, r.port_register, r.element, f.name);
}

// Every port of a struct, by key, as raw bits.
template <class S>
std::map<std::string, std::uint64_t> raw_ports(const S& s) {
  std::map<std::string, std::uint64_t> out;
  S::for_each_port(s, [&](std::string_view b, int i, std::string_view r, int e, std::string_view f,
                          const auto& port) {
    out[port_key(b, i, r, e, f)] = PortTraits<std::remove_cvref_t<decltype(port)>>::raw(port);
  });
  return out;
}

template <class S>
void randomise(S& s, std::mt19937_64& rng) {
  S::for_each_port(s,
                   [&](std::string_view, int, std::string_view, int, std::string_view, auto& port) {
                     PortTraits<std::remove_cvref_t<decltype(port)>>::assign(port, rng());
                   });
}

// Every struct has exactly the ports the description gives it, with the
// field's full width and signedness; Pulses also one `pops` per rpop array
// (as wide as its element count needs).
template <class S>
void expect_ports(bool (*belongs)(const YField&), bool pops = false) {
  std::map<std::string, std::pair<unsigned, bool>> want;
  for (const YRegister& r : description_registers()) {
    for (const YField& f : r.fields) {
      if (belongs(f))
        want[port_key(r, f)] = {f.port_width, f.port_signed};
    }
    if (pops && r.access == regs::Access::kRpop) {
      want[port_key(r.block, r.instance, r.port_register, -1, "pops")] = {
          std::bit_width(static_cast<unsigned>(r.count)), false};
    }
  }
  std::map<std::string, std::pair<unsigned, bool>> got;
  const S s{};
  S::for_each_port(s, [&](std::string_view b, int i, std::string_view r, int e, std::string_view f,
                          const auto& port) {
    using T = PortTraits<std::remove_cvref_t<decltype(port)>>;
    EXPECT_TRUE(got.emplace(port_key(b, i, r, e, f), std::pair{T::kWidth, T::kSigned}).second);
  });
  EXPECT_EQ(got, want);
}

TEST(FabricPorts, StructsHoldExactlyTheDescribedPorts) {
  expect_ports<ports::Config>(in_config);
  expect_ports<ports::Pulses>(in_pulses, true);
  expect_ports<ports::Status>(in_status);
  static_assert(
      std::is_same_v<decltype(ports::Status{}.odometry.pose_x.bits), odoloc::rtl::SInt<64>>);
  static_assert(
      std::is_same_v<decltype(ports::Config{}.eppm[0].window.clocks), odoloc::rtl::UInt<23>>);
  static_assert(std::is_same_v<ports::eppm::DecodeMode, regs::eppm::cfg::DecodeMode>);
  static_assert(std::is_same_v<ports::odometry::Phase, regs::odometry::status::Phase>);
  EXPECT_EQ(static_cast<unsigned>(ports::odometry::Phase::kThetaWait), 8U);
}

// The default initialisers are the reset values: decoding every rw
// register's reset word changes nothing, and a reset Status encodes to the
// hardware-driven bits of each reset word.
TEST(FabricPorts, DefaultsAreTheResetValues) {
  const ports::Config defaults{};
  ports::Config c{};
  for (const YRegister& r : description_registers()) {
    std::uint32_t reset = 0, driven = 0;
    for (const YField& f : r.fields) {
      reset |= f.reset << f.lsb;
      driven |= in_status(f) ? f.mask() : 0U;
    }
    ports::decode_config(static_cast<std::uint16_t>(r.address), reset, c);
    EXPECT_EQ(ports::encode_status(static_cast<std::uint16_t>(r.address), ports::Status{}),
              reset & driven)
        << r.path;
  }
  EXPECT_TRUE(c == defaults);
  EXPECT_EQ(defaults.eppm[2].cfg.filter_clocks.value(), 3U);
  EXPECT_EQ(defaults.odometry.steer_limit.value.value(), 477218588U);
}

constexpr int kTrials = 200;

TEST(FabricPorts, DecodeConfigSetsExactlyTheRegistersPorts) {
  std::mt19937_64 rng(20240611);
  for (const YRegister& r : description_registers()) {
    SCOPED_TRACE(r.path);
    for (int t = 0; t < kTrials; ++t) {
      ports::Config c;
      randomise(c, rng);
      auto want = raw_ports(c);
      const auto word = static_cast<std::uint32_t>(rng());
      for (const YField& f : r.fields) {
        if (!in_config(f))
          continue;
        const std::uint64_t slice = ones(f.width) << f.port_shift;
        auto& port = want[port_key(r, f)];
        port = (port & ~slice) | ((std::uint64_t{(word & f.mask()) >> f.lsb} << f.port_shift));
      }
      ports::decode_config(static_cast<std::uint16_t>(r.address), word, c);
      ASSERT_EQ(raw_ports(c), want);
    }
  }
}

TEST(FabricPorts, DecodePulsesRaisesTheWrittenOnes) {
  std::mt19937_64 rng(7);
  for (const YRegister& r : description_registers()) {
    SCOPED_TRACE(r.path);
    for (int t = 0; t < kTrials; ++t) {
      ports::Pulses p;
      if (t % 2 == 1)
        randomise(p, rng);  // half the time from idle, half on top of other pulses
      auto want = raw_ports(p);
      const auto written = static_cast<std::uint32_t>(rng());
      for (const YField& f : r.fields) {
        if (in_pulses(f))
          want[port_key(r, f)] |= (written & f.mask()) >> f.lsb;
      }
      ports::decode_pulses(static_cast<std::uint16_t>(r.address), written, p);
      ASSERT_EQ(raw_ports(p), want);
    }
  }
}

TEST(FabricPorts, EncodeStatusPlacesTheDrivenFields) {
  std::mt19937_64 rng(99);
  for (int t = 0; t < kTrials; ++t) {
    ports::Status s;
    randomise(s, rng);
    const auto raw = raw_ports(s);
    for (const YRegister& r : description_registers()) {
      std::uint32_t want = 0;
      for (const YField& f : r.fields) {
        if (in_status(f)) {
          const std::uint64_t v = (raw.at(port_key(r, f)) >> f.port_shift) & ones(f.width);
          want |= static_cast<std::uint32_t>(v) << f.lsb;
        }
      }
      ASSERT_EQ(ports::encode_status(static_cast<std::uint16_t>(r.address), s), want) << r.path;
    }
  }
  ports::Status s;
  EXPECT_EQ(ports::encode_status(0x3FF, s), 0U);
}

// Wide ports: the two words assemble one value, sign included.
TEST(FabricPorts, WidePortsAssembleTheirWords) {
  namespace o = regs::odometry;
  ports::Config c;
  ports::decode_config(o::set_x_lo::kAddress, 0x89ABCDEFU, c);
  ports::decode_config(o::set_x_hi::kAddress, 0xFEDCBA98U, c);
  EXPECT_EQ(c.odometry.set_x.bits.value(), static_cast<std::int64_t>(0xFEDCBA9889ABCDEFULL));
  ports::decode_config(o::set_x_lo::kAddress, 1U, c);  // the other word stays
  EXPECT_EQ(c.odometry.set_x.bits.value(), static_cast<std::int64_t>(0xFEDCBA9800000001ULL));
  ports::decode_config(o::set_theta_hi::kAddress, 0xFFFFFFA5U, c);  // bits 39:32 only
  ports::decode_config(o::set_theta_lo::kAddress, 0x12345678U, c);
  EXPECT_EQ(c.odometry.set_theta.bits.value(), 0xA512345678ULL);

  ports::Status s;
  s.odometry.pose_x.bits = odoloc::rtl::SInt<64>{-2};
  s.odometry.rear_ds.bits = odoloc::rtl::SInt<48>{-1};
  s.odometry.pose_theta.bits = odoloc::rtl::UInt<40>{0xC3'0000'0001ULL};
  EXPECT_EQ(ports::encode_status(o::pose_x_lo::kAddress, s), 0xFFFFFFFEU);
  EXPECT_EQ(ports::encode_status(o::pose_x_hi::kAddress, s), 0xFFFFFFFFU);
  EXPECT_EQ(ports::encode_status(o::rear_ds_hi::kAddress, s), 0x0000FFFFU);
  EXPECT_EQ(ports::encode_status(o::pose_theta_lo::kAddress, s), 1U);
  EXPECT_EQ(ports::encode_status(o::pose_theta_hi::kAddress, s), 0xC3U);
  // The sign of a 48-bit value read back from its words, as software does.
  const std::int64_t hi = o::rear_ds_hi::bits.get_signed(0x0000FFFFU);
  EXPECT_EQ(hi * (std::int64_t{1} << 32) + 0xFFFFFFFFLL, -1);
}

TEST(FabricPorts, PulsesAndPerBlockFunctions) {
  ports::Pulses p;
  ports::decode_pulses(regs::odometry::command::kAddress, 0x2U, p);
  EXPECT_EQ(p.odometry.command.clear_flags.value(), 1U);
  EXPECT_EQ(p.odometry.command.set_pose.value(), 0U);
  ports::decode_pulses(regs::eppm::status::address(1), 0xFFFFFFFFU, p);
  EXPECT_EQ(p.eppm[1].status.period_overflow.value(), 1U);
  EXPECT_EQ(p.eppm[0].status.period_overflow.value(), 0U);
  ports::eppm::Config e;
  ports::eppm::decode_config(regs::eppm::cfg::kOffset, 0x0000'0105U, e);
  EXPECT_EQ(e.cfg.filter_clocks.value(), 5U);
  EXPECT_EQ(e.cfg.decode_mode.value(), static_cast<unsigned>(ports::eppm::DecodeMode::kX2));
}

// ---- Register arrays and rpop (the tof blocks) ------------------------------

// An array is one namespace in regs.hpp and one member in ports.hpp; its
// elements are ordinary registers.
TEST(RegisterArrays, NamespacesGiveEveryElementsAddress) {
  namespace ch = regs::tof_channel;
  static_assert(ch::entry::kOffset == 0x8 && ch::entry::kCount == 8 && ch::entry::kWords == 2);
  static_assert(regs::tof::sync_entry::kCount == 8 && regs::tof::sync_entry::kWords == 1);
  for (unsigned i = 0; i < ch::kInstances; ++i) {
    EXPECT_EQ(ch::entry::address(i, 0), ch::entry0_lo::address(i));
    EXPECT_EQ(ch::entry::address(i, 5), ch::entry5_lo::address(i));
    EXPECT_EQ(ch::entry::address(i, 5) + 1U, ch::entry5_hi::address(i));
    EXPECT_EQ(ch::entry::address(i, 7), 0x110U + i * 0x18U + 0x8U + 14U);
  }
  EXPECT_EQ(regs::tof::sync_entry::address(0), regs::tof::sync_entry0::kAddress);
  EXPECT_EQ(regs::tof::sync_entry::address(7), 0x10FU);
  const regs::Register* r = regs::find("tof_channel.rx3.entry5_hi");
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->access, regs::Access::kRpop);
  EXPECT_TRUE(r->snapshot);
  EXPECT_EQ(r->element, 5);
  EXPECT_EQ(r->rw_mask | r->w1c_mask | r->w1p_mask | r->const_mask, 0U);  // writes refused
  EXPECT_NE(std::string_view(r->description).find("Element 5 of entry[8]"), std::string_view::npos);
  for (const char* path : {"tof.cfg", "tof.sync_status", "tof_channel.rx3.status"}) {
    const regs::Register* other = regs::find(path);
    ASSERT_NE(other, nullptr) << path;
    EXPECT_EQ(other->element, -1) << path;
    EXPECT_EQ(other->pop_window, -1) << path;
  }
}

TEST(RegisterArrays, PopWindowsListEveryRpopArrayOfEveryInstance) {
  ASSERT_EQ(std::size(regs::kPopWindows), 1U + regs::tof_channel::kInstances);
  const regs::PopWindow& sync = regs::kPopWindows[0];
  EXPECT_EQ(sync.path, "tof.sync_entry");
  EXPECT_EQ(sync.first, 0x108U);
  EXPECT_EQ(sync.entries, 8U);
  EXPECT_EQ(sync.words, 1U);
  for (unsigned i = 0; i < regs::tof_channel::kInstances; ++i) {
    const regs::PopWindow& w = regs::kPopWindows[1 + i];
    EXPECT_EQ(w.path,
              "tof_channel." + std::string(regs::tof_channel::kInstanceNames[i]) + ".entry");
    EXPECT_EQ(w.first, 0x110U + i * 0x18U + 8U);  // element 0's lo word
    EXPECT_EQ(w.entries, 8U);
    EXPECT_EQ(w.words, 2U);
  }
  EXPECT_EQ(regs::kPopWindows[4].first, 0x160U);  // rx3
  // Every word of every window, and nothing else, maps back to its window.
  std::set<std::uint32_t> in_windows;
  for (std::size_t i = 0; i < std::size(regs::kPopWindows); ++i) {
    const regs::PopWindow& w = regs::kPopWindows[i];
    for (unsigned k = 0; k < unsigned{w.entries} * w.words; ++k) {
      const auto place = regs::find_pop_word(w.first + k);
      ASSERT_TRUE(place.has_value());
      EXPECT_EQ(place->window, i);
      EXPECT_EQ(place->word, k);
      const regs::Register* r = regs::find(w.first + k);
      ASSERT_NE(r, nullptr);
      EXPECT_EQ(r->pop_window, static_cast<int>(i));
      EXPECT_EQ(r->element, static_cast<int>(k / w.words));
      EXPECT_EQ(r->access, regs::Access::kRpop);
      in_windows.insert(w.first + k);
    }
  }
  for (const regs::Register& r : regs::kRegisters) {
    EXPECT_EQ(in_windows.count(r.address) == 1, r.access == regs::Access::kRpop) << r.path;
    if (in_windows.count(r.address) == 0) {
      EXPECT_FALSE(regs::find_pop_word(r.address).has_value()) << r.path;
      EXPECT_EQ(r.pop_window, -1) << r.path;
    }
  }
}

TEST(RegisterArrays, StatusHoldsTheArrayAtFullWidth) {
  using Entry = std::remove_cvref_t<decltype(ports::Status{}.tof_channel[0].entry)>;
  static_assert(std::tuple_size_v<Entry> == 8);
  static_assert(std::is_same_v<decltype(Entry{}[0].ticks), odoloc::rtl::UInt<32>>);
  static_assert(std::is_same_v<decltype(Entry{}[0].width), odoloc::rtl::UInt<24>>);
  static_assert(std::is_same_v<decltype(Entry{}[0].valid), odoloc::rtl::UInt<1>>);
  static_assert(std::tuple_size_v<decltype(ports::Status{}.tof.sync_entry)> == 8);
  static_assert(
      std::is_same_v<decltype(ports::Pulses{}.tof_channel[0].entry.pops), odoloc::rtl::UInt<4>>);
  static_assert(
      std::is_same_v<decltype(ports::Pulses{}.tof.sync_entry.pops), odoloc::rtl::UInt<4>>);

  namespace ch = regs::tof_channel;
  ports::Status s;
  for (unsigned k = 0; k < 8; ++k) {  // every element different
    auto& e = s.tof_channel[2].entry[k];
    e.ticks = odoloc::rtl::UInt<32>{0x1000U + k};
    e.width = odoloc::rtl::UInt<24>{0xA00000U + k};
    e.valid = odoloc::rtl::UInt<1>{k % 2};
  }
  s.tof_channel[2].entry[5].valid = odoloc::rtl::UInt<1>{1};
  const std::uint32_t width_mask = ch::entry5_hi::width.mask();
  EXPECT_EQ(ports::encode_status(ch::entry5_lo::address(2), s), 0x1005U);
  EXPECT_EQ(ports::encode_status(ch::entry5_hi::address(2), s) & width_mask, 0xA00005U);
  EXPECT_EQ(ch::entry5_hi::valid.get(ports::encode_status(ch::entry5_hi::address(2), s)), 1U);
  EXPECT_EQ(ports::encode_status(ch::entry0_lo::address(2), s), 0x1000U);
  EXPECT_EQ(ports::encode_status(ch::entry5_lo::address(3), s), 0U);  // another channel
  s.tof.sync_entry[6].ticks = odoloc::rtl::UInt<32>{0xDEADBEEFU};
  EXPECT_EQ(ports::encode_status(regs::tof::sync_entry6::kAddress, s), 0xDEADBEEFU);
  EXPECT_EQ(ports::tof::encode_status(regs::tof::sync_entry6::kOffset, s.tof), 0xDEADBEEFU);
}

TEST(RegisterArrays, DecodePopsSetsOnlyItsWindowsPops) {
  for (const regs::PopWindow& w : regs::kPopWindows) {
    SCOPED_TRACE(w.path);
    for (unsigned entries = 0; entries <= w.entries + 2U; ++entries) {
      ports::Pulses p;
      auto want = raw_ports(p);
      ports::decode_pops(w.first, entries, p);
      const regs::Register* r = regs::find(w.first);
      ASSERT_NE(r, nullptr);
      // "tof_channel.rx3.entry" -> block tof_channel, instance 3, array entry
      std::string_view path = w.path;
      const std::string block(path.substr(0, path.find('.')));
      const std::string array(path.substr(path.rfind('.') + 1));
      int instance = -1;
      if (block == "tof_channel") {
        for (unsigned i = 0; i < regs::tof_channel::kInstances; ++i) {
          if (path.find(regs::tof_channel::kInstanceNames[i]) != std::string_view::npos)
            instance = static_cast<int>(i);
        }
      }
      want[port_key(block, instance, array, -1, "pops")] = std::min(entries, unsigned{w.entries});
      EXPECT_EQ(raw_ports(p), want);
      ports::Pulses q;
      ports::decode_pops(static_cast<std::uint16_t>(w.first + 1U), entries, q);  // not element 0
      EXPECT_TRUE(q == ports::Pulses{});
    }
  }
  ports::Pulses p;
  ports::decode_pops(regs::tof_channel::entry::address(3, 0), 5, p);
  EXPECT_EQ(p.tof_channel[3].entry.pops.value(), 5U);
  EXPECT_EQ(p.tof_channel[2].entry.pops.value(), 0U);
  ports::tof::Pulses t;
  ports::tof::decode_pops(regs::tof::sync_entry::kOffset, 8, t);
  EXPECT_EQ(t.sync_entry.pops.value(), 8U);
  ports::decode_pulses(regs::tof_channel::entry0_lo::address(3), 0xFFFFFFFFU, p);  // no pulse
  EXPECT_EQ(p.tof_channel[3].entry.pops.value(), 5U);
}

// A minimal valid description to break one way at a time.
const std::string kSpi =
    "spi: {max_burst: 32, min_level_clocks: 4, crc: {polynomial: 0x1D, init: 0xFF, xor_out: "
    "0xFF}}\n";
std::string description(const std::string& blocks, const std::string& spi = kSpi,
                        const std::string& clock = "50000000") {
  return "map: {name: t, address_bits: 8, data_bits: 32, clock_hz: " + clock + "}\n" + spi +
         "blocks:\n" + blocks;
}
const std::string kGoodBlock =
    "  - name: a\n    base: 0x10\n    registers:\n"
    "      - {name: rg, offset: 0, access: rw, hw: r, fields: [{name: f, bits: [7, 0], reset: "
    "1}]}\n";
// One register of block a at offset 0.
std::string one(const std::string& reg) {
  return description("  - name: a\n    base: 0\n    registers:\n      - " + reg + "\n");
}

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
      description(
          "  - name: a\n    base: 0\n    registers:\n"
          "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: [0, 0]}]}\n"
          "      - {name: r, offset: 1, access: rw, hw: r, fields: [{name: f, bits: [0, 0]}]}\n"),
      "duplicate register 'r'");
  expect_rejected(
      description(
          kGoodBlock +
          "  - name: b\n    base: 0x10\n    registers:\n"
          "      - {name: s, offset: 0, access: ro, hw: w, fields: [{name: f, bits: [0, 0]}]}\n"),
      "overlaps a.rg");
  expect_rejected(
      description(kGoodBlock + "  - {name: u, base: 0x8, size: 0x10, reserved: true}\n"),
      "overlaps");
  expect_rejected(
      description(
          "  - name: a\n    base: 0\n    registers:\n"
          "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: [32, 0]}]}\n"),
      "wider than the 32-bit register");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: "
                  "[7, 0]}, {name: g, bits: [8, 7]}]}\n"),
      "overlaps another field");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: "
                  "[3, 0], reset: 16}]}\n"),
      "reset value does not fit");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: "
                  "[0, 0], enum: {x: 2}}]}\n"),
      "enum value does not fit");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rx, fields: [{name: f, bits: [0, 0]}]}\n"),
      "unknown access 'rx'");
  expect_rejected(
      description(
          "  - name: a\n    base: 0x100\n    registers:\n"
          "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: [0, 0]}]}\n"),
      "outside the 8-bit space");
  expect_rejected(
      description(
          "  - name: a\n    base: 0\n    stride: 2\n    instances: [p, p]\n    registers:\n"
          "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: [0, 0]}]}\n"),
      "duplicate instance");
  expect_rejected("map: [unterminated", "YAML");
  expect_rejected(description(kGoodBlock) + "---\nmap: {}\n", "a second document");
  expect_rejected(description(kGoodBlock) + "...\nextra: 1\n", "a second document");
  expect_rejected(description("  - name: A\n    base: 0\n    registers: []\n"), "lower_snake_case");
  expect_rejected(
      description("  - name: a\n    base: 0\n    registers:\n"
                  "      - {name: r, offset: 0, access: rw, hw: r, fields: [{name: f, bits: "
                  "[0, 0], description: one, two}]}\n"),
      "unknown key 'two'");
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n"
                              "      - {name: r, offest: 0, access: rw, hw: r, fields: []}\n"),
                  "unknown key 'offest'");
}

TEST(RegisterMapGenerator, RejectsIllegalHardwareAccess) {
  expect_rejected(one("{name: r, offset: 0, access: rw, fields: [{name: f, bits: [0, 0]}]}"),
                  "missing 'hw'");
  expect_rejected(
      one("{name: r, offset: 0, access: rw, hw: rd, fields: [{name: f, bits: [0, 0]}]}"),
      "unknown hw 'rd'");
  for (const auto& [access, hw] :
       std::vector<std::pair<std::string, std::string>>{{"rw", "w"},
                                                        {"rw", "set"},
                                                        {"ro", "r"},
                                                        {"ro", "count"},
                                                        {"w1c", "none"},
                                                        {"w1c", "w"},
                                                        {"rc", "w"},
                                                        {"rc", "none"},
                                                        {"w1p", "none"},
                                                        {"w1p", "set"}}) {
    expect_rejected(one("{name: r, offset: 0, access: " + access + ", hw: " + hw +
                        ", fields: [{name: f, bits: [1, 0]}]}"),
                    "access " + access + " cannot have hw " + hw);
  }
  // A field overriding the access must give a hw that goes with it.
  expect_rejected(one("{name: r, offset: 0, access: w1c, hw: set, fields: [{name: f, bits: [0, "
                      "0]}, {name: g, bits: [1, 1], access: ro}]}"),
                  "r.g: access ro cannot have hw set");
  EXPECT_NO_THROW(odoloc::regmap::parse(
      one("{name: rg, offset: 0, access: w1c, hw: set, fields: [{name: f, bits: [0, 0]}, {name: "
          "g, bits: [1, 1], access: ro, hw: w}]}")));
  expect_rejected(one("{name: r, offset: 0, access: ro, hw: w, fields: [{name: f, bits: [0, 0], "
                      "signed: true}]}"),
                  "signed field needs at least 2 bits");
}

TEST(RegisterMapGenerator, ExpandsWideRegisters) {
  const auto map = odoloc::regmap::parse(
      one("{name: p, offset: 2, words: 2, access: ro, hw: w, snapshot: true, description: "
          "Pose., fields: [{name: bits, bits: [39, 0], signed: true, reset: 0x8000000001, "
          "description: X.}]}"));
  const auto& regs_ = map.blocks.at(0).registers;
  ASSERT_EQ(regs_.size(), 2U);
  EXPECT_EQ(regs_[0].name, "p_lo");
  EXPECT_EQ(regs_[0].offset, 2U);
  EXPECT_EQ(regs_[1].name, "p_hi");
  EXPECT_EQ(regs_[1].offset, 3U);
  EXPECT_TRUE(regs_[1].snapshot);
  EXPECT_EQ(regs_[0].description, "Pose. Bits 31:0.");
  EXPECT_EQ(regs_[1].description, "Pose. Bits 39:32.");
  const auto& lo = regs_[0].fields.at(0);
  const auto& hi = regs_[1].fields.at(0);
  EXPECT_EQ(lo.name, "bits");
  EXPECT_EQ(lo.width(), 32);
  EXPECT_FALSE(lo.is_signed);
  EXPECT_EQ(lo.reset, 1U);
  EXPECT_EQ(hi.name, "bits");
  EXPECT_EQ(hi.width(), 8);
  EXPECT_TRUE(hi.is_signed);
  EXPECT_EQ(hi.reset, 0x80U);
  EXPECT_EQ(hi.port_shift, 32);
  EXPECT_EQ(hi.port_width, 40);
}

TEST(RegisterMapGenerator, RejectsBadWideRegisters) {
  const std::string wide =
      "{name: p, offset: 0, words: 2, access: rw, hw: r, fields: [{name: f, bits: [63, 0]}]}";
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n      - " + wide +
                              "\n      - {name: p_hi, offset: 4, access: rw, hw: r, fields: "
                              "[{name: f, bits: [0, 0]}]}\n"),
                  "duplicate register 'p_hi'");
  expect_rejected(description("  - name: a\n    base: 0\n    registers:\n      - " + wide +
                              "\n      - {name: q, offset: 1, access: rw, hw: r, fields: "
                              "[{name: f, bits: [0, 0]}]}\n"),
                  "overlaps a.p_hi");
  expect_rejected(
      one("{name: p, offset: 0, words: 3, access: rw, hw: r, fields: [{name: f, bits: [0, 0]}]}"),
      "words must be 1 or 2");
  expect_rejected(
      one("{name: p, offset: 0, words: 2, access: w1c, hw: set, fields: [{name: f, bits: [40, "
          "0]}]}"),
      "must be ro, rw or rpop");
  expect_rejected(
      one("{name: p, offset: 0, words: 2, access: rw, hw: r, fields: [{name: f, bits: [64, 0]}]}"),
      "wider than the 64-bit register");
  expect_rejected(
      one("{name: p, offset: 0, words: 2, access: rw, hw: r, fields: [{name: f, bits: [31, 0]}]}"),
      "no field has a bit in bits 63:32");
  expect_rejected(one("{name: p, offset: 0, words: 2, access: rw, hw: r, fields: [{name: f, "
                      "bits: [33, 30], enum: {a: 1}}]}"),
                  "enum field cannot span two words");
}

TEST(RegisterMapGenerator, ExpandsRegisterArrays) {
  const auto map = odoloc::regmap::parse(
      one("{name: e, offset: 4, count: 3, words: 2, access: rpop, hw: w, snapshot: true, "
          "description: Entry., fields: [{name: t, bits: [31, 0]}, {name: v, bits: [63, 63]}]}") +
      "      - {name: s, offset: 16, count: 2, access: rw, hw: r, fields: [{name: f, bits: [7, "
      "0], reset: 3}]}\n");
  const auto& r = map.blocks.at(0).registers;
  ASSERT_EQ(r.size(), 8U);
  const char* names[] = {"e0_lo", "e0_hi", "e1_lo", "e1_hi", "e2_lo", "e2_hi", "s0", "s1"};
  const std::uint32_t offsets[] = {4, 5, 6, 7, 8, 9, 16, 17};
  for (std::size_t i = 0; i < r.size(); ++i) {
    EXPECT_EQ(r[i].name, names[i]);
    EXPECT_EQ(r[i].offset, offsets[i]);
  }
  EXPECT_EQ(r[3].array, "e");
  EXPECT_EQ(r[3].element, 1);
  EXPECT_EQ(r[3].count, 3);
  EXPECT_EQ(r[3].array_words, 2);
  EXPECT_EQ(r[3].word, 1);
  EXPECT_EQ(r[3].wide, "e1");
  EXPECT_EQ(r[3].port_name(), "e");
  EXPECT_EQ(r[3].port_member(), "e[1]");
  EXPECT_EQ(r[3].array_offset(), 4U);
  EXPECT_EQ(r[3].description, "Entry. Bits 63:32. Element 1 of e[3].");
  EXPECT_EQ(r[3].array_description, "Entry. Bits 63:32.");
  EXPECT_TRUE(r[0].array_head());
  EXPECT_FALSE(r[1].array_head());
  EXPECT_EQ(r[7].name, "s1");
  EXPECT_EQ(r[7].wide, "");
  EXPECT_EQ(r[7].fields.at(0).reset, 3U);
  EXPECT_EQ(r[7].port_member(), "s[1]");
  EXPECT_EQ(r[0].fields.at(0).access, odoloc::regmap::Access::kRpop);
  EXPECT_EQ(r[0].fields.at(0).hw, odoloc::regmap::Hw::kW);

  // One pop window per rpop array and block instance, by address.
  const auto inst = odoloc::regmap::parse(description(
      "  - name: b\n    base: 0x90\n    stride: 0x10\n    instances: [x, y]\n    registers:\n"
      "      - {name: q, offset: 2, count: 4, access: rpop, hw: w, snapshot: true, fields: "
      "[{name: t, bits: [15, 0]}]}\n"
      "  - name: a\n    base: 0\n    registers:\n"
      "      - {name: e, offset: 1, count: 64, words: 2, access: rpop, hw: w, snapshot: true, "
      "fields: [{name: t, bits: [40, 0]}]}\n"));
  const auto windows = odoloc::regmap::pop_windows(inst);
  ASSERT_EQ(windows.size(), 3U);
  EXPECT_EQ(windows[0].path, "a.e");
  EXPECT_EQ(windows[0].first, 1U);
  EXPECT_EQ(windows[0].entries, 64);
  EXPECT_EQ(windows[0].words, 2);
  EXPECT_EQ(windows[1].path, "b.x.q");
  EXPECT_EQ(windows[1].first, 0x92U);
  EXPECT_EQ(windows[1].words, 1);
  EXPECT_EQ(windows[2].path, "b.y.q");
  EXPECT_EQ(windows[2].first, 0xA2U);
  EXPECT_EQ(windows[2].instance, 1);
  // Its pops: 7 bits for 0..64, 3 bits for 0..4.
  const std::string ports_hpp = odoloc::regmap::emit_ports(inst);
  EXPECT_NE(ports_hpp.find("UInt<7> pops{};"), std::string::npos);
  EXPECT_NE(ports_hpp.find("UInt<3> pops{};"), std::string::npos);
  EXPECT_NE(ports_hpp.find("std::array<EReg, 64> e;"), std::string::npos);
  EXPECT_NE(ports_hpp.find("case 0x0a2:  // b.y.q\n      b::decode_pops(0x2, entries, p.b[1]);"),
            std::string::npos);
  const std::string rdl = odoloc::regmap::emit_systemrdl(inst);
  EXPECT_NE(rdl.find("sw = r; hw = w; swacc = true;"), std::string::npos);
  EXPECT_NE(odoloc::regmap::emit_markdown(inst).find("`rpop` read pops"), std::string::npos);
}

TEST(RegisterMapGenerator, RejectsBadRegisterArrays) {
  const auto array = [](const std::string& count) {
    return "{name: e, offset: 0, count: " + count +
           ", access: ro, hw: w, fields: [{name: f, bits: [0, 0]}]}";
  };
  expect_rejected(one(array("0")), "a.e: count must be 1..64");
  expect_rejected(one(array("65")), "a.e: count must be 1..64");
  expect_rejected(one(array("-1")), "a.e: count must be 1..64");
  expect_rejected(one(array("two")), "a.e count: not a valid value");
  EXPECT_NO_THROW(odoloc::regmap::parse(one(array("1"))));
  EXPECT_NO_THROW(odoloc::regmap::parse(one(array("64"))));
  // Names and addresses are checked on the elements.
  expect_rejected(one(array("4")) +
                      "      - {name: e3, offset: 8, access: ro, hw: w, fields: "
                      "[{name: f, bits: [0, 0]}]}\n",
                  "duplicate register 'e3' in a (element 3 of the register array 'e')");
  expect_rejected(one("{name: e3, offset: 8, access: ro, hw: w, fields: [{name: f, bits: [0, "
                      "0]}]}") +
                      "      - " + array("4") + "\n",
                  "duplicate register 'e3' in a (element 3 of the register array 'e')");
  expect_rejected(one("{name: e, offset: 0, count: 2, words: 2, access: ro, hw: w, fields: "
                      "[{name: f, bits: [40, 0]}]}") +
                      "      - {name: e1_hi, offset: 8, access: ro, hw: w, fields: [{name: f, "
                      "bits: [0, 0]}]}\n",
                  "duplicate register 'e1_hi'");
  expect_rejected(one(array("4")) +
                      "      - {name: g, offset: 3, access: ro, hw: w, fields: "
                      "[{name: f, bits: [0, 0]}]}\n",
                  "a.g overlaps a.e3");
  expect_rejected(description("  - name: a\n    base: 0\n    stride: 4\n    instances: [p, q]\n"
                              "    registers:\n      - " +
                              array("5") + "\n"),
                  "a.e4: offset is outside the instance stride");
  // The array's own name is taken: a register of that name collides in regs.hpp.
  expect_rejected(one(array("2")) +
                      "      - {name: e, offset: 8, access: ro, hw: w, fields: "
                      "[{name: f, bits: [0, 0]}]}\n",
                  "a.e (register array)");
}

TEST(RegisterMapGenerator, RejectsBadRpop) {
  const std::string fields = "fields: [{name: f, bits: [7, 0]}]";
  expect_rejected(one("{name: e, offset: 0, count: 4, access: rpop, hw: w, " + fields + "}"),
                  "a.e: an rpop register must be snapshot: true");
  expect_rejected(one("{name: e, offset: 0, access: rpop, hw: w, snapshot: true, " + fields + "}"),
                  "a.e: an rpop register needs count: N");
  for (const std::string hw : {"r", "none", "set", "count"}) {
    expect_rejected(one("{name: e, offset: 0, count: 4, access: rpop, hw: " + hw +
                        ", snapshot: true, " + fields + "}"),
                    "a.e: access rpop cannot have hw " + hw + " (legal: ");
  }
  // Every field of an rpop register is rpop, and no other field is.
  expect_rejected(one("{name: e, offset: 0, count: 4, access: rpop, hw: w, snapshot: true, "
                      "fields: [{name: f, bits: [7, 0]}, {name: g, bits: [8, 8], access: ro}]}"),
                  "a.e.g: every field of an rpop register is rpop");
  expect_rejected(one("{name: e, offset: 0, count: 4, access: rpop, hw: w, snapshot: true, "
                      "fields: [{name: f, bits: [7, 0], hw: none}]}"),
                  "a.e.f: access rpop cannot have hw none");
  expect_rejected(one("{name: s, offset: 0, count: 4, access: ro, hw: w, snapshot: true, "
                      "fields: [{name: f, bits: [7, 0]}, {name: g, bits: [8, 8], access: rpop}]}"),
                  "a.s.g: only the fields of an rpop register can be rpop");
  expect_rejected(one("{name: s, offset: 0, access: w1c, hw: set, fields: [{name: g, bits: [8, "
                      "8], access: rpop, hw: w}]}"),
                  "a.s.g: only the fields of an rpop register can be rpop");
  expect_rejected(one("{name: e, offset: 0, count: 2, words: 2, access: w1p, hw: r, fields: "
                      "[{name: f, bits: [40, 0]}]}"),
                  "a words: 2 register must be ro, rw or rpop");
  EXPECT_NO_THROW(odoloc::regmap::parse(
      one("{name: e, offset: 0, count: 4, access: rpop, hw: w, snapshot: true, fields: [{name: f, "
          "bits: [7, 0], access: rpop, hw: w}]}")));
}

TEST(RegisterMapGenerator, RejectsBadClockAndSpiFacts) {
  expect_rejected(description(kGoodBlock, kSpi, "30000000"), "whole number of ns");
  expect_rejected(description(kGoodBlock, kSpi, "0"), "whole number of ns");
  expect_rejected(description(kGoodBlock, ""), "missing 'spi'");
  const auto spi = [](const std::string& body) { return "spi: {" + body + "}\n"; };
  const std::string crc = "crc: {polynomial: 0x1D, init: 0xFF, xor_out: 0xFF}";
  expect_rejected(description(kGoodBlock, spi("max_bursts: 32, min_level_clocks: 4, " + crc)),
                  "spi: unknown key 'max_bursts'");
  expect_rejected(description(kGoodBlock, spi("max_burst: 33, min_level_clocks: 4, " + crc)),
                  "max_burst must be 1..32");
  expect_rejected(description(kGoodBlock, spi("max_burst: 0, min_level_clocks: 4, " + crc)),
                  "max_burst must be 1..32");
  expect_rejected(description(kGoodBlock, spi("max_burst: 8, min_level_clocks: 0, " + crc)),
                  "min_level_clocks must be");
  expect_rejected(
      description(kGoodBlock, spi("max_burst: 8, min_level_clocks: 4, crc: {polynomial: 0x107, "
                                  "init: 0, xor_out: 0}")),
      "polynomial must fit 8 bits");
  expect_rejected(
      description(kGoodBlock, spi("max_burst: 8, min_level_clocks: 4, crc: {polynomial: 7, "
                                  "init: 0, xor_out: 0, reflect: true}")),
      "spi.crc: unknown key 'reflect'");
  expect_rejected(description(kGoodBlock) + "extra: 1\n", "top level: unknown key 'extra'");
}

}  // namespace
