// The host tool's logic, in process: name resolution and closest matches,
// value parsing in every base (signed, enums, range errors), formatting, and
// every command run through run_cli() against an in-memory register file
// that records the bus traffic. Expected values come from odoloc/regs.hpp.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "enum_name.hpp"
#include "odoloc/cli/app.hpp"
#include "odoloc/cli/commands.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/cli/names.hpp"
#include "odoloc/cli/target.hpp"
#include "odoloc/cli/values.hpp"
#include "odoloc/regs.hpp"
#include "usage_message.hpp"

namespace {

namespace regs = odoloc::regs;
namespace cli = odoloc::cli;
using cli::UsageError;
using nlohmann::json;

// ---------------------------------------------------------------- helpers

std::string field_path(const regs::Register& r, const regs::Field& f) {
  return std::string{r.path} + "." + std::string{f.name};
}

using odoloc::tb::enum_name;
using odoloc::tb::message_of;

// The fabric's register semantics from the generated masks: rw bits store,
// w1c bits clear where 1 is written, w1p bits pulse (read 0), rc registers
// clear when read. Every transfer is logged.
class FakeBus final : public odoloc::sw::RegisterBus {
 public:
  struct Transfer {
    bool read;
    std::uint16_t address;
    std::vector<std::uint32_t> words;
  };

  FakeBus() {
    for (const regs::Register& r : regs::kRegisters)
      words_[r.address] = r.reset;
  }
  using RegisterBus::read;
  using RegisterBus::write;
  void read(std::uint16_t address, std::span<std::uint32_t> out) override {
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto a = static_cast<std::uint16_t>(address + i);
      const regs::Register* r = regs::find(std::uint32_t{a});
      out[i] = r != nullptr ? words_[a] : 0;
      if (r != nullptr && r->access == regs::Access::kRc)
        words_[a] = 0;
    }
    log.push_back({true, address, {out.begin(), out.end()}});
  }
  void write(std::uint16_t address, std::span<const std::uint32_t> in) override {
    log.push_back({false, address, {in.begin(), in.end()}});
    if (fail_writes)
      throw odoloc::sw::BusError("SPI write failed: write_refused");
    for (std::size_t i = 0; i < in.size(); ++i) {
      const auto a = static_cast<std::uint16_t>(address + i);
      const regs::Register* r = regs::find(std::uint32_t{a});
      if (r == nullptr)
        throw odoloc::sw::BusError("unmapped");
      std::uint32_t& w = words_[a];
      w = (w & ~r->rw_mask) | (in[i] & r->rw_mask);
      w &= ~(in[i] & r->w1c_mask);
    }
  }
  std::uint32_t& word(std::uint16_t address) { return words_.at(address); }

  std::vector<Transfer> log;
  bool fail_writes = false;

 private:
  std::map<std::uint16_t, std::uint32_t> words_;
};

// The bus and the log of waits outlive the target, which run_cli destroys.
class FakeTarget final : public cli::Target {
 public:
  FakeTarget(FakeBus& bus, std::vector<std::chrono::nanoseconds>& waits)
      : bus_(bus), waits_(waits) {}
  odoloc::sw::RegisterBus& bus() override { return bus_; }
  void wait(std::chrono::nanoseconds interval) override {
    waits_.push_back(interval);
    now_ += interval;
  }
  [[nodiscard]] std::chrono::nanoseconds elapsed() const override { return now_; }

 private:
  FakeBus& bus_;
  std::vector<std::chrono::nanoseconds>& waits_;
  std::chrono::nanoseconds now_{};
};

// run_cli in process on one FakeBus; counts how often a target was opened.
struct Harness {
  FakeBus bus;
  std::vector<std::chrono::nanoseconds> waits;
  int opened = 0;
  std::string last_spec;
  bool last_crc = false;
  std::string out, err;

  int run(std::vector<std::string> args, const std::string& input = {}) {
    std::istringstream in(input);
    std::ostringstream o, e;
    const cli::TargetOpener opener = [this](std::string_view spec,
                                            const cli::TargetOptions& options) {
      ++opened;
      last_spec = spec;
      last_crc = options.crc;
      return std::make_unique<FakeTarget>(bus, waits);
    };
    const int code = cli::run_cli(args, {in, o, e}, opener);
    out = o.str();
    err = e.str();
    return code;
  }
  std::vector<json> json_lines() const {
    std::vector<json> docs;
    std::istringstream s(out);
    for (std::string line; std::getline(s, line);)
      docs.push_back(json::parse(line));
    return docs;
  }
};

// Consecutive-address runs of the register map, the bursts `reg dump` uses.
std::vector<std::pair<std::uint16_t, std::size_t>> address_runs() {
  std::vector<std::uint16_t> a;
  for (const regs::Register& r : regs::kRegisters)
    a.push_back(r.address);
  std::ranges::sort(a);
  std::vector<std::pair<std::uint16_t, std::size_t>> runs;
  for (const std::uint16_t x : a) {
    if (!runs.empty() && runs.back().first + runs.back().second == x)
      ++runs.back().second;
    else
      runs.emplace_back(x, 1);
  }
  return runs;
}

// ---------------------------------------------------------------- names

TEST(CliNames, EveryRegisterAndFieldPathResolves) {
  for (const regs::Register& r : regs::kRegisters) {
    const cli::Location loc = cli::resolve(r.path);
    EXPECT_EQ(loc.reg, &r);
    EXPECT_EQ(loc.field, nullptr);
    EXPECT_EQ(loc.path(), r.path);
    for (const regs::Field& f : r.fields) {
      const cli::Location fl = cli::resolve(field_path(r, f));
      EXPECT_EQ(fl.reg, &r);
      ASSERT_NE(fl.field, nullptr);
      EXPECT_EQ(fl.field->name, f.name);
      EXPECT_EQ(fl.field->lsb, f.lsb);
      EXPECT_EQ(fl.path(), field_path(r, f));
    }
  }
}

// A bare number that is also the byte address (odoloc.rdl: 4 × word) of a
// different register.
bool ambiguous(std::uint32_t address) {
  return address != 0 && address % 4 == 0 && regs::find(address / 4) != nullptr &&
         regs::find(address / 4) != regs::find(address);
}

TEST(CliNames, AddressesInEveryBaseResolveToTheRegisterThere) {
  for (const regs::Register& r : regs::kRegisters) {
    std::string bin;
    for (unsigned v = r.address; v != 0; v >>= 1)
      bin.insert(bin.begin(), static_cast<char>('0' + (v & 1U)));
    for (const std::string& text :
         {std::to_string(r.address), fmt::format("0x{:x}", r.address),
          fmt::format("0X{:03X}", r.address), "0b" + (bin.empty() ? "0" : bin)}) {
      SCOPED_TRACE(text);
      EXPECT_EQ(cli::resolve("w:" + text).reg, &r);
      EXPECT_EQ(cli::resolve(fmt::format("b:0x{:x}", r.address * 4U)).reg, &r);
      if (!ambiguous(r.address)) {
        EXPECT_EQ(cli::resolve(text).reg, &r);
      }
    }
  }
}

// Issue 9: 0x40 is eppm.steering.cfg as a word address and
// eppm_left_rear.cfg as odoloc.rdl's byte address. A bare number never picks
// one silently; w:/b: and the RDL name say which.
TEST(CliNames, BareNumbersThatAreAlsoByteAddressesOfAnotherRegisterAreRefused) {
  std::size_t refused = 0;
  for (std::uint32_t a = 0; a < (std::uint32_t{1} << regs::kAddressBits) * 4; a += 4) {
    const regs::Register* as_byte = regs::find(a / 4);
    if (!ambiguous(a))
      continue;
    ++refused;
    const std::string text = fmt::format("0x{:x}", a);
    const std::string m = message_of([&] { (void)cli::resolve(text); });
    EXPECT_NE(m.find("ambiguous"), std::string::npos) << m;
    EXPECT_NE(m.find(fmt::format("is {} at word 0x{:03x}", as_byte->path, as_byte->address)),
              std::string::npos)
        << m;
    if (const regs::Register* as_word = regs::find(a); as_word != nullptr) {
      EXPECT_NE(m.find(fmt::format("word address 0x{:03x} is {}", a, as_word->path)),
                std::string::npos)
          << m;
    }
    EXPECT_NE(m.find(fmt::format("w:{} or b:{}", text, text)), std::string::npos) << m;
    // Through a write too: nothing is written.
    EXPECT_THROW((void)cli::parse_assignment(text + "=1"), UsageError);
  }
  EXPECT_GT(refused, 0U);
  const regs::Register& left_rear_cfg = *regs::find("eppm.left_rear.cfg");
  EXPECT_EQ(cli::resolve(fmt::format("b:0x{:x}", left_rear_cfg.address * 4U)).reg, &left_rear_cfg);
  EXPECT_EQ(cli::resolve("B:0x000").reg, regs::find("top.id"));
  EXPECT_NE(message_of([] { (void)cli::resolve("b:0x41"); }).find("multiple of 4"),
            std::string::npos);
  EXPECT_NE(message_of([] { (void)cli::resolve("b:0x1000"); }).find("out of range"),
            std::string::npos);
  EXPECT_THROW((void)cli::resolve("w:0x400"), UsageError);
  EXPECT_THROW((void)cli::resolve("w:top.id"), UsageError);
}

// The names of odoloc.rdl / PeakRDL (block_instance.register) and of the C
// header (ODOLOC_BLOCK_INSTANCE_REGISTER_ADDR) name the same register here.
TEST(CliNames, NamesFromTheGeneratedArtefactsResolveToTheSameRegister) {
  for (const regs::Register& r : regs::kRegisters) {
    // eppm.left_rear.cfg -> eppm_left_rear.cfg; top.id stays top.id.
    std::string rdl{r.path};
    const std::size_t last = rdl.rfind('.');
    for (std::size_t i = 0; i < last; ++i)
      if (rdl[i] == '.')
        rdl[i] = '_';
    std::string macro = "ODOLOC_" + std::string{r.path} + "_ADDR";
    for (char& c : macro)
      c = c == '.' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (const std::string& name : {rdl, "odoloc." + rdl, macro}) {
      SCOPED_TRACE(name);
      const cli::Location loc = cli::resolve(name);
      EXPECT_EQ(loc.reg, &r);
      EXPECT_EQ(loc.field, nullptr);
    }
    for (const regs::Field& f : r.fields) {
      const cli::Location fl = cli::resolve(rdl + "." + std::string{f.name});
      EXPECT_EQ(fl.reg, &r);
      ASSERT_NE(fl.field, nullptr);
      EXPECT_EQ(fl.field->name, f.name);
    }
  }
  EXPECT_EQ(cli::resolve("eppm_left_rear.cfg").reg, regs::find("eppm.left_rear.cfg"));
}

TEST(CliNames, UnmappedReservedAndOutOfRangeAddressesAreClearErrors) {
  std::uint16_t hole = 0;
  while (regs::find(std::uint32_t{hole}) != nullptr)
    ++hole;
  EXPECT_NE(message_of([&] { (void)cli::resolve(std::to_string(hole)); }).find("unmapped"),
            std::string::npos);
  const regs::Reserved& reserved = regs::kReserved[0];
  const std::string m =
      message_of([&] { (void)cli::resolve(fmt::format("0x{:x}", reserved.base + 1)); });
  EXPECT_NE(m.find(reserved.name), std::string::npos) << m;
  const auto space = std::uint32_t{1} << regs::kAddressBits;
  // Beyond the word addresses and not the byte address of a register either.
  std::uint32_t beyond = space;
  while (regs::find(beyond / 4) != nullptr)
    beyond += 4;
  EXPECT_NE(message_of([&] { (void)cli::resolve(std::to_string(beyond)); }).find("out of range"),
            std::string::npos);
  EXPECT_NO_THROW((void)cli::parse_address(std::to_string(space - 1)));
  EXPECT_THROW((void)cli::resolve("-1"), UsageError);
}

TEST(CliNames, UnknownRegisterSuggestsTheClosest) {
  const std::string m = message_of([] { (void)cli::resolve("eppm.left_rear.cnt"); });
  EXPECT_NE(m.find("unknown register 'eppm.left_rear.cnt'"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean eppm.left_rear.count"), std::string::npos) << m;
  // Bare tails find their register.
  EXPECT_NE(message_of([] { (void)cli::resolve("scratch"); }).find("top.scratch"),
            std::string::npos);
  EXPECT_NE(message_of([] { (void)cli::resolve("scartch"); }).find("top.scratch"),
            std::string::npos);
  // Far from everything: no wild guess, a pointer to the list.
  const std::string far = message_of([] { (void)cli::resolve("zzz"); });
  EXPECT_EQ(far.find("did you mean"), std::string::npos) << far;
  EXPECT_NE(far.find("reg list"), std::string::npos) << far;
}

TEST(CliNames, EveryPathWithOneTypoIsSuggestedBack) {
  for (const std::string& path : cli::all_paths()) {
    // Drop a letter from the last component, and swap two letters there.
    const std::size_t pos = path.rfind('.') + 2;
    if (pos + 1 >= path.size())
      continue;
    std::string dropped = path;
    dropped.erase(pos, 1);
    std::string swapped = path;
    std::swap(swapped[pos], swapped[pos + 1]);
    for (const std::string& typo : {dropped, swapped}) {
      if (typo == path || regs::find(typo) != nullptr)
        continue;
      SCOPED_TRACE(typo);
      const std::vector<std::string> near = cli::closest_paths(typo);
      EXPECT_NE(std::ranges::find(near, path), near.end());
      const std::string m = message_of([&] { (void)cli::resolve(typo); });
      EXPECT_NE(m.find(path), std::string::npos) << m;
    }
  }
}

TEST(CliNames, UnknownFieldOfAKnownRegisterNamesItsFields) {
  const std::string near = message_of([] { (void)cli::resolve("eppm.left_rear.cfg.decode"); });
  EXPECT_NE(near.find("unknown field"), std::string::npos) << near;
  EXPECT_NE(near.find("eppm.left_rear.cfg.decode_mode"), std::string::npos) << near;
  const std::string far = message_of([] { (void)cli::resolve("eppm.left_rear.cfg.xyzzy"); });
  for (const regs::Field& f : regs::eppm::cfg::kFields)
    EXPECT_NE(far.find(f.name), std::string::npos) << far;
}

TEST(CliNames, EditDistance) {
  EXPECT_EQ(cli::edit_distance("", ""), 0U);
  EXPECT_EQ(cli::edit_distance("abc", ""), 3U);
  EXPECT_EQ(cli::edit_distance("kitten", "sitting"), 3U);
  EXPECT_EQ(cli::edit_distance("scratch", "scartch"), 1U);  // one transposition
  EXPECT_EQ(cli::edit_distance("Count", "count"), 0U);      // case-insensitive
  EXPECT_EQ(cli::edit_distance("cnt", "count"), 2U);
}

TEST(CliNames, FiltersAreSubstringsOrPerComponentGlobs) {
  EXPECT_TRUE(cli::path_matches("eppm.left_rear.count", "left"));
  EXPECT_FALSE(cli::path_matches("top.id", "left"));
  EXPECT_TRUE(cli::path_matches("eppm.left_rear.count", "eppm.*.count"));
  EXPECT_FALSE(cli::path_matches("eppm.left_rear.error_count.count", "eppm.*.count"));
  EXPECT_TRUE(cli::path_matches("top.id", "top.?d"));
  EXPECT_TRUE(cli::path_matches("top.id", ""));
  // A register matches through its fields too.
  EXPECT_TRUE(cli::register_matches(*regs::find("eppm.left_rear.cfg"), "decode_mode"));
  std::size_t counts = 0;
  for (const regs::Register& r : regs::kRegisters)
    counts += cli::register_matches(r, "eppm.*.count") ? 1U : 0U;
  EXPECT_EQ(counts, regs::eppm::kInstances);
}

// ---------------------------------------------------------------- values

TEST(CliValues, NumbersInEveryBase) {
  EXPECT_EQ(cli::parse_number("0").magnitude, 0U);
  EXPECT_EQ(cli::parse_number("42").magnitude, 42U);
  EXPECT_EQ(cli::parse_number("007").magnitude, 7U);  // decimal, never octal
  EXPECT_EQ(cli::parse_number("0x2A").magnitude, 42U);
  EXPECT_EQ(cli::parse_number("0Xff").magnitude, 255U);
  EXPECT_EQ(cli::parse_number("0b101010").magnitude, 42U);
  EXPECT_EQ(cli::parse_number("0b1010_1010").magnitude, 0xAAU);
  EXPECT_EQ(cli::parse_number("0x0D01_0001").magnitude, 0x0D010001U);
  EXPECT_EQ(cli::parse_number("18446744073709551615").magnitude, UINT64_MAX);
  const cli::Number neg = cli::parse_number("-0x10");
  EXPECT_TRUE(neg.negative);
  EXPECT_EQ(neg.magnitude, 16U);
  EXPECT_EQ(neg.base, 16U);
  for (const char* bad : {"", "-", "0x", "0b2", "12a", "0xfg", "1__0", "_1", "1_", "abc"})
    EXPECT_THROW((void)cli::parse_number(bad), UsageError) << bad;
  EXPECT_NE(message_of([] { (void)cli::parse_number("18446744073709551616"); }).find("too large"),
            std::string::npos);
}

// Every field of the map: the full range in, one past either end out.
TEST(CliValues, EveryFieldIsRangeCheckedAgainstItsWidth) {
  for (const regs::Register& r : regs::kRegisters) {
    for (const regs::Field& f : r.fields) {
      const std::string path = field_path(r, f);
      SCOPED_TRACE(path);
      const std::uint64_t max_raw = (std::uint64_t{1} << f.width) - 1;
      if (!f.enums.empty()) {
        for (const regs::Enumerator& e : f.enums) {
          EXPECT_EQ(cli::parse_field_value(f, path, e.name), e.value);
          EXPECT_EQ(cli::parse_field_value(f, path, std::to_string(e.value)), e.value);
        }
        const std::string m = message_of([&] { (void)cli::parse_field_value(f, path, "bogus"); });
        for (const regs::Enumerator& e : f.enums)
          EXPECT_NE(m.find(e.name), std::string::npos) << m;
        continue;
      }
      if (f.is_signed) {
        const std::int64_t min = -(std::int64_t{1} << (f.width - 1));
        const std::int64_t max = (std::int64_t{1} << (f.width - 1)) - 1;
        // Two's complement: max is 0b0111..., min 0b1000..., -1 all ones.
        EXPECT_EQ(cli::parse_field_value(f, path, std::to_string(max)), max_raw >> 1);
        EXPECT_EQ(cli::parse_field_value(f, path, std::to_string(min)), (max_raw >> 1) + 1);
        EXPECT_EQ(cli::parse_field_value(f, path, "-1"), max_raw);
        EXPECT_EQ(cli::field_signed(f, f.set(0, static_cast<std::uint32_t>(max_raw >> 1) + 1U)),
                  min);
        EXPECT_EQ(cli::field_signed(f, f.mask()), -1);
        EXPECT_EQ(cli::parse_field_value(f, path, fmt::format("0x{:x}", max_raw)), max_raw);
        EXPECT_THROW((void)cli::parse_field_value(f, path, std::to_string(max + 1)), UsageError);
        EXPECT_THROW((void)cli::parse_field_value(f, path, std::to_string(min - 1)), UsageError);
        EXPECT_THROW((void)cli::parse_field_value(f, path, fmt::format("0x{:x}", max_raw + 1)),
                     UsageError);
        continue;
      }
      EXPECT_EQ(cli::parse_field_value(f, path, std::to_string(max_raw)), max_raw);
      EXPECT_EQ(cli::parse_field_value(f, path, fmt::format("0x{:x}", max_raw)), max_raw);
      EXPECT_EQ(cli::parse_field_value(f, path, "0b" + std::string(f.width, '1')), max_raw);
      EXPECT_EQ(cli::parse_field_value(f, path, std::to_string(f.reset)), f.reset);
      const std::string over =
          message_of([&] { (void)cli::parse_field_value(f, path, std::to_string(max_raw + 1)); });
      EXPECT_NE(over.find("out of range"), std::string::npos) << over;
      EXPECT_NE(over.find(path), std::string::npos) << over;
      EXPECT_NE(over.find(std::to_string(max_raw)), std::string::npos) << over;
      EXPECT_THROW((void)cli::parse_field_value(f, path, "-1"), UsageError);
      EXPECT_THROW((void)cli::parse_field_value(f, path, "x2"), UsageError);
    }
  }
}

TEST(CliValues, EnumNumbersMustBeEncodings) {
  const regs::Field& f = regs::eppm::cfg::decode_mode;
  std::uint32_t unused = 0;
  while (std::ranges::any_of(f.enums, [&](const regs::Enumerator& e) { return e.value == unused; }))
    ++unused;
  ASSERT_LT(unused, 1U << f.width);
  EXPECT_THROW((void)cli::parse_field_value(f, "d", std::to_string(unused)), UsageError);
  EXPECT_EQ(cli::parse_field_value(f, "d", "X2"),
            static_cast<std::uint32_t>(regs::eppm::cfg::DecodeMode::kX2));
}

TEST(CliValues, RegisterWords) {
  const regs::Register& scratch = *regs::find("top.scratch");
  EXPECT_EQ(cli::parse_register_value(scratch, "0xffffffff"), 0xffffffffU);
  EXPECT_EQ(cli::parse_register_value(scratch, "4294967295"), 0xffffffffU);
  EXPECT_THROW((void)cli::parse_register_value(scratch, "0x100000000"), UsageError);
  EXPECT_THROW((void)cli::parse_register_value(scratch, "-1"), UsageError);
  EXPECT_THROW((void)cli::parse_register_value(scratch, "five"), UsageError);
  // Bits outside every field of the register are refused.
  const regs::Register& cfg = *regs::find("eppm.left_rear.cfg");
  std::uint32_t fields = 0;
  for (const regs::Field& f : cfg.fields)
    fields |= f.mask();
  ASSERT_NE(~fields, 0U);
  EXPECT_EQ(cli::parse_register_value(cfg, fmt::format("{}", fields)), fields);
  const std::uint32_t rest = ~fields;
  const std::uint32_t outside = rest & (0U - rest);  // the lowest bit outside the fields
  EXPECT_THROW((void)cli::parse_register_value(cfg, fmt::format("0x{:x}", outside)), UsageError);
}

TEST(CliValues, Intervals) {
  using std::chrono::nanoseconds;
  EXPECT_EQ(cli::parse_interval("100ms"), nanoseconds{100'000'000});
  EXPECT_EQ(cli::parse_interval("1s"), nanoseconds{1'000'000'000});
  EXPECT_EQ(cli::parse_interval("250us"), nanoseconds{250'000});
  EXPECT_EQ(cli::parse_interval("20ns"), nanoseconds{20});
  EXPECT_EQ(cli::parse_interval("1.5s"), nanoseconds{1'500'000'000});
  EXPECT_EQ(cli::parse_interval("0.25ms"), nanoseconds{250'000});
  EXPECT_EQ(cli::parse_interval("10MS"), nanoseconds{10'000'000});
  for (const char* bad : {"100", "ms", "0ms", "-1s", "1h", "1.s.", "", "1 s", "99999999999s"})
    EXPECT_THROW((void)cli::parse_interval(bad), UsageError) << bad;
  // The largest that fits, and overflows in every part of the number (issue
  // 9: "18446744073.999999999s" wrapped to 0.29 s).
  EXPECT_EQ(cli::parse_interval("9223372036.854775807s").count(),
            std::numeric_limits<std::int64_t>::max());
  for (const char* overflow :
       {"18446744073.999999999s", "9223372036.854775808s", "18446744073709551616ns",
        "18446744073709551615ns", "18446744073709.551616ms", "99999999999999999999999s",
        "18446744073709551.999us"}) {
    const std::string m = message_of([&] { (void)cli::parse_interval(overflow); });
    EXPECT_NE(m.find("too long"), std::string::npos) << overflow << ": " << m;
  }
  // Below the resolution: refused, never rounded to a different time.
  for (const char* fine : {"1.5ns", "0.0000000001s", "1.0001us"}) {
    const std::string m = message_of([&] { (void)cli::parse_interval(fine); });
    EXPECT_NE(m.find("resolution"), std::string::npos) << fine << ": " << m;
  }
  EXPECT_EQ(cli::parse_interval("1.000us").count(), 1000);
}

TEST(CliValues, CountsAndFrequencies) {
  EXPECT_EQ(cli::parse_count("3"), 3U);
  for (const char* bad : {"0", "-1", "x", ""})
    EXPECT_THROW((void)cli::parse_count(bad), UsageError) << bad;
  EXPECT_EQ(cli::parse_frequency("1000000"), 1'000'000U);
  EXPECT_EQ(cli::parse_frequency("500k"), 500'000U);
  EXPECT_EQ(cli::parse_frequency("2M"), 2'000'000U);
  EXPECT_EQ(cli::parse_frequency("2MHz"), 2'000'000U);
  EXPECT_EQ(cli::parse_frequency("1.5M"), 1'500'000U);
  for (const char* bad : {"0", "fast", "1G", "", "5000000000"})
    EXPECT_THROW((void)cli::parse_frequency(bad), UsageError) << bad;
  // Overflow anywhere (issue 9: "18446744073709.999999M" passed as 448 kHz).
  EXPECT_EQ(cli::parse_frequency("4294967295"), 4'294'967'295U);
  for (const char* overflow : {"18446744073709.999999M", "4294967296", "4294967.296k",
                               "18446744073709551616", "99999999999999999999999MHz"}) {
    const std::string m = message_of([&] { (void)cli::parse_frequency(overflow); });
    EXPECT_NE(m.find("too large"), std::string::npos) << overflow << ": " << m;
  }
  EXPECT_THROW((void)cli::parse_spidev_spec("/dev/x@18446744073709.999999M"), UsageError);
  EXPECT_NE(message_of([] { (void)cli::parse_frequency("1.5"); }).find("finer"), std::string::npos);
  EXPECT_EQ(cli::parse_frequency("0.5k"), 500U);
  // Counts: a number too large for 64 bits is refused, not wrapped.
  EXPECT_THROW((void)cli::parse_count("18446744073709551616"), UsageError);
  EXPECT_EQ(cli::parse_count("18446744073709551615"), std::numeric_limits<std::uint64_t>::max());
}

// ---------------------------------------------------------------- targets

TEST(CliTargets, SpecsAreCheckedWithoutOpening) {
  for (const char* good : {"sim", "sim:straight", "spidev:/dev/spidev0.0", "lcm", "lcm:udpm://x"})
    EXPECT_NO_THROW(cli::check_target_spec(good)) << good;
  for (const char* bad : {"", "foo", "simulator", "spi:/dev/spidev0.0", "lcmx"})
    EXPECT_THROW(cli::check_target_spec(bad), UsageError) << bad;
  // The lcm target frames nothing itself: the SPI options are refused before
  // LCM is opened.
  cli::TargetOptions crc, vcd, vcd_pins, cycle_step;
  crc.crc = true;
  vcd.vcd = "x.vcd";
  vcd_pins.vcd_pins = "p.vcd";
  cycle_step.cycle_step = true;
  for (const cli::TargetOptions* options : {&crc, &vcd, &vcd_pins, &cycle_step})
    EXPECT_NE(message_of([&] {
                (void)cli::open_target("lcm", *options);
              }).find("--crc, --vcd, --vcd-pins and --cycle-step"),
              std::string::npos);
  EXPECT_NE(message_of([] {
              (void)cli::open_target("lcm:nowhere://", {});
            }).find("cannot open 'nowhere://'"),
            std::string::npos);
}

TEST(CliTargets, SpidevSpecs) {
  const cli::SpidevSpec plain = cli::parse_spidev_spec("/dev/spidev0.0");
  EXPECT_EQ(plain.device, "/dev/spidev0.0");
  EXPECT_EQ(plain.speed_hz, cli::kSpidevDefaultHz);
  const cli::SpidevSpec fast = cli::parse_spidev_spec("/dev/spidev1.2@2M");
  EXPECT_EQ(fast.device, "/dev/spidev1.2");
  EXPECT_EQ(fast.speed_hz, 2'000'000U);
  EXPECT_EQ(cli::parse_spidev_spec(fmt::format("/dev/x@{}", cli::kSpidevMaxHz)).speed_hz,
            cli::kSpidevMaxHz);
  EXPECT_THROW((void)cli::parse_spidev_spec(fmt::format("/dev/x@{}", cli::kSpidevMaxHz + 1)),
               UsageError);
  EXPECT_THROW((void)cli::parse_spidev_spec(""), UsageError);
  EXPECT_THROW((void)cli::parse_spidev_spec("@1M"), UsageError);
  EXPECT_THROW((void)cli::parse_spidev_spec("/dev/x@fast"), UsageError);
}

TEST(CliTargets, MissingSpidevDeviceIsAClearError) {
  const std::string device = "/nonexistent-odoloc/spidev0.0";
  const std::string m = message_of([&] { (void)cli::open_target("spidev:" + device, {}); });
  EXPECT_EQ(m, "cannot open " + device + ": " + std::strerror(ENOENT));
}

// ---------------------------------------------------------------- formatting

TEST(CliFormat, FieldsDecodeThroughTheMap) {
  using namespace regs::eppm;
  const std::uint32_t cfg_word = cfg::decode_mode.set(cfg::kReset, 1);
  EXPECT_EQ(cli::field_compact(cfg::decode_mode, cfg_word), cfg::kDecodeModeNames[1].name);
  EXPECT_EQ(cli::field_text(cfg::decode_mode, cfg_word),
            fmt::format("{} (1)", cfg::kDecodeModeNames[1].name));
  EXPECT_EQ(cli::field_json(cfg::decode_mode, cfg_word), json(cfg::kDecodeModeNames[1].name));
  const std::uint32_t unnamed = cfg::decode_mode.set(0, 3);
  EXPECT_EQ(cli::field_json(cfg::decode_mode, unnamed), json(3));
  EXPECT_NE(cli::field_text(cfg::decode_mode, unnamed).find("no enumerator"), std::string::npos);

  const std::uint32_t minus5 = count::value.set(0, static_cast<std::uint32_t>(-5));
  EXPECT_EQ(cli::field_compact(count::value, minus5), "-5");
  EXPECT_EQ(cli::field_json(count::value, minus5), json(-5));
  EXPECT_EQ(cli::field_text(count::value, minus5),
            fmt::format("-5 (0x{:05x})", count::value.get(minus5)));

  const auto& magic = regs::top::id::magic;
  EXPECT_EQ(cli::field_text(magic, regs::top::id::kReset),
            fmt::format("{} (0x{:04x})", magic.reset, magic.reset));
  EXPECT_EQ(cli::field_text(regs::top::ctrl::crc_enable, 1), "1");
  EXPECT_EQ(cli::bit_range(magic), "31:16");
  EXPECT_EQ(cli::bit_range(regs::top::ctrl::spi_mode3), "1");
  EXPECT_EQ(cli::access_name(regs::Access::kW1c), "w1c");
}

// Every signed field of the map, 32-bit ones included: -1, min and max.
TEST(CliFormat, SignedFieldsOfEveryWidthDecode) {
  std::size_t seen = 0;
  for (const regs::Register& r : regs::kRegisters) {
    for (const regs::Field& f : r.fields) {
      if (!f.is_signed)
        continue;
      ++seen;
      SCOPED_TRACE(field_path(r, f));
      const std::int64_t min = -(std::int64_t{1} << (f.width - 1));
      const std::uint32_t min_word =
          f.set(0, static_cast<std::uint32_t>(std::uint64_t{1} << (f.width - 1)));
      EXPECT_EQ(cli::field_json(f, f.mask()), json(-1));
      EXPECT_EQ(cli::field_json(f, min_word), json(min));
      EXPECT_EQ(cli::field_json(f, f.mask() & ~min_word), json(-min - 1));
      EXPECT_EQ(cli::field_compact(f, ~f.mask()), "0");
      EXPECT_EQ(cli::field_text(f, f.mask()),
                fmt::format("-1 (0x{:0{}x})", f.get(f.mask()), (f.width + 3) / 4));
    }
  }
  EXPECT_GT(seen, 0U);
}

TEST(CliFormat, ValueJsonOfRegistersAndFields) {
  const regs::Register& id = *regs::find("top.id");
  const json r = cli::value_json({&id, nullptr}, id.reset);
  EXPECT_EQ(r["path"], "top.id");
  EXPECT_EQ(r["address"], id.address);
  EXPECT_EQ(r["value"], id.reset);
  for (const regs::Field& f : id.fields)
    EXPECT_EQ(r["fields"][std::string{f.name}], f.get(id.reset));
  const json f = cli::value_json(cli::resolve("top.id.magic"), id.reset);
  EXPECT_EQ(f["register"], "top.id");
  EXPECT_EQ(f["value"], regs::top::id::magic.reset);
  EXPECT_EQ(f["word"], id.reset);
}

TEST(CliFormat, DescribeJsonCarriesEveryField) {
  for (const regs::Register& r : regs::kRegisters) {
    const json d = cli::describe_json(r);
    EXPECT_EQ(d["path"], std::string{r.path});
    EXPECT_EQ(d["address"], r.address);
    EXPECT_EQ(d["reset"], r.reset);
    EXPECT_EQ(d["access"], std::string{cli::access_name(r.access)});
    ASSERT_EQ(d["fields"].size(), r.fields.size());
    for (std::size_t i = 0; i < r.fields.size(); ++i) {
      const regs::Field& f = r.fields[i];
      const json& jf = d["fields"][i];
      EXPECT_EQ(jf["name"], std::string{f.name});
      EXPECT_EQ(jf["bits"], json({f.lsb + f.width - 1, f.lsb}));
      EXPECT_EQ(jf["signed"], f.is_signed);
      EXPECT_EQ(jf["reset"], f.reset);
      EXPECT_EQ(jf["enums"].size(), f.enums.size());
    }
  }
}

// ---------------------------------------------------------------- commands

TEST(CliCommands, AssignmentsPickTheWriteMode) {
  EXPECT_EQ(cli::parse_assignment("top.scratch=5").mode(), cli::WriteMode::kWord);
  EXPECT_EQ(cli::parse_assignment("eppm.left_rear.cfg.decode_mode=x2").mode(),
            cli::WriteMode::kReadModifyWrite);
  EXPECT_EQ(cli::parse_assignment("eppm.left_rear.status.carry=1").mode(),
            cli::WriteMode::kFieldOnly);
  EXPECT_EQ(cli::parse_assignment("odometry.command.set_pose=1").mode(),
            cli::WriteMode::kFieldOnly);
  EXPECT_EQ(
      cli::parse_assignment(fmt::format("w:0x{:x}=7", regs::top::scratch::kAddress)).target.reg,
      regs::find("top.scratch"));
  for (const char* bad :
       {"top.scratch", "top.scratch=", "=5", "top.id=1", "top.id.magic=1", "top.frame_errors=0",
        "eppm.left_rear.status.forward=1", "eppm.left_rear.count=-1"})
    EXPECT_THROW((void)cli::parse_assignment(bad), UsageError) << bad;
  EXPECT_NE(message_of([] { (void)cli::parse_assignment("top.id=1"); }).find("read-only"),
            std::string::npos);
}

TEST(CliCommands, ScriptLinesSplitLikeAShell) {
  EXPECT_EQ(cli::split_line("  reg   write top.scratch=5  # comment"),
            (std::vector<std::string>{"reg", "write", "top.scratch=5"}));
  EXPECT_EQ(cli::split_line("# only a comment"), std::vector<std::string>{});
  EXPECT_EQ(cli::split_line("reg list --filter 'a b'"),
            (std::vector<std::string>{"reg", "list", "--filter", "a b"}));
  EXPECT_EQ(cli::split_line("a#b"), std::vector<std::string>{"a#b"});
  EXPECT_THROW((void)cli::split_line("reg list --filter 'x"), UsageError);
}

TEST(CliRun, ListOpensNoTargetAndCountsEveryRegister) {
  Harness h;
  ASSERT_EQ(h.run({"--json", "reg", "list"}), cli::kExitOk) << h.err;
  EXPECT_EQ(h.opened, 0);
  const std::vector<json> docs = h.json_lines();
  ASSERT_EQ(docs.size(), 1U);
  EXPECT_EQ(docs[0]["registers"].size(), std::size(regs::kRegisters));
  ASSERT_EQ(h.run({"reg", "list", "--filter", "eppm.*.count"}), cli::kExitOk);
  EXPECT_EQ(static_cast<std::size_t>(std::ranges::count(h.out, '\n')),
            1 + regs::eppm::kInstances);  // header + rows
}

TEST(CliRun, RegisterFieldWritesReadModifyWriteTheRwBitsOnly) {
  Harness h;
  const auto& cfg = regs::eppm::cfg::decode_mode;
  const std::uint16_t address = regs::eppm::cfg::address(0);
  ASSERT_EQ(h.run({"reg", "write", "eppm.left_rear.cfg.decode_mode=x2"}), cli::kExitOk) << h.err;
  ASSERT_EQ(h.bus.log.size(), 2U);
  EXPECT_TRUE(h.bus.log[0].read);
  EXPECT_EQ(h.bus.log[0].address, address);
  EXPECT_FALSE(h.bus.log[1].read);
  const std::uint32_t expected = cfg.set(
      regs::eppm::cfg::kReset, static_cast<std::uint32_t>(regs::eppm::cfg::DecodeMode::kX2));
  EXPECT_EQ(h.bus.log[1].words, std::vector<std::uint32_t>{expected});
  EXPECT_EQ(h.bus.word(address), expected);
}

TEST(CliRun, W1cAndW1pFieldWritesWriteOnlyTheirBitsWithoutReading) {
  Harness h;
  const std::uint16_t status = regs::eppm::status::address(0);
  h.bus.word(status) = regs::eppm::status::carry.mask() | regs::eppm::status::borrow.mask();
  ASSERT_EQ(h.run({"reg", "write", "eppm.left_rear.status.carry=1", "odometry.command.set_pose=1"}),
            cli::kExitOk)
      << h.err;
  ASSERT_EQ(h.bus.log.size(), 2U);
  for (const auto& t : h.bus.log)
    EXPECT_FALSE(t.read);
  EXPECT_EQ(h.bus.log[0].words, std::vector<std::uint32_t>{regs::eppm::status::carry.mask()});
  EXPECT_EQ(h.bus.log[1].address, regs::odometry::command::kAddress);
  EXPECT_EQ(h.bus.log[1].words,
            std::vector<std::uint32_t>{regs::odometry::command::set_pose.mask()});
  // borrow, not written, is still set.
  EXPECT_EQ(h.bus.word(status), regs::eppm::status::borrow.mask());
}

TEST(CliRun, RefusedWritesCauseNoBusTraffic) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"reg", "write", "top.scratch=1", "top.id=1"},
        {"reg", "write", "top.scratch=1", "eppm.left_rear.cfg.filter_clocks=256"},
        {"reg", "write", "top.scratch=1", "eppm.left_rear.cnt=1"},
        {"reg", "write", "eppm.left_rear.count.value=-1"}}) {
    Harness h;
    EXPECT_EQ(h.run(args), cli::kExitUsage) << args.back();
    EXPECT_EQ(h.opened, 0);
    EXPECT_TRUE(h.bus.log.empty());
    EXPECT_TRUE(h.err.starts_with("odoloc: ")) << h.err;
    EXPECT_EQ(std::ranges::count(h.err, '\n'), 1) << h.err;
  }
}

TEST(CliRun, ReadBurstsConsecutiveAddressesAndKeepsArgumentOrder) {
  Harness h;
  const auto x_lo = regs::odometry::pose_x_lo::kAddress;
  const auto x_hi = regs::odometry::pose_x_hi::kAddress;
  ASSERT_EQ(x_hi, x_lo + 1);
  h.bus.word(x_lo) = 0x11111111;
  h.bus.word(x_hi) = 0x22222222;
  ASSERT_EQ(h.run({"--json", "reg", "read", "odometry.pose_x_hi", "odometry.pose_x_lo", "top.id"}),
            cli::kExitOk)
      << h.err;
  ASSERT_EQ(h.bus.log.size(), 2U);  // top.id, then pose_x_lo..hi in one burst
  EXPECT_EQ(h.bus.log[1].address, x_lo);
  EXPECT_EQ(h.bus.log[1].words.size(), 2U);
  const json values = h.json_lines().at(0)["values"];
  EXPECT_EQ(values[0]["path"], "odometry.pose_x_hi");
  EXPECT_EQ(values[0]["value"], 0x22222222U);
  EXPECT_EQ(values[1]["value"], 0x11111111U);
  EXPECT_EQ(values[2]["fields"]["magic"], regs::top::id::magic.reset);
}

TEST(CliRun, SignedAndEnumFieldsReadDecoded) {
  Harness h;
  const auto& v = regs::eppm::count::value;
  h.bus.word(regs::eppm::count::address(0)) = v.set(0, static_cast<std::uint32_t>(-7));
  ASSERT_EQ(h.run({"--json", "reg", "read", "eppm.left_rear.count.value",
                   "eppm.left_rear.cfg.decode_mode"}),
            cli::kExitOk)
      << h.err;
  const json values = h.json_lines().at(0)["values"];
  EXPECT_EQ(values[0]["value"], -7);
  EXPECT_EQ(values[1]["value"],
            enum_name(regs::eppm::cfg::decode_mode, regs::eppm::cfg::decode_mode.reset));
  ASSERT_EQ(h.run({"reg", "read", "eppm.left_rear.count.value"}), cli::kExitOk);
  EXPECT_EQ(h.out, fmt::format("eppm.left_rear.count.value = -7 (0x{:05x})\n",
                               v.get(v.set(0, static_cast<std::uint32_t>(-7)))));
}

TEST(CliRun, DumpReadsEveryRegisterOnceInContiguousBursts) {
  Harness h;
  ASSERT_EQ(h.run({"--json", "reg", "dump"}), cli::kExitOk) << h.err;
  const auto runs = address_runs();
  ASSERT_EQ(h.bus.log.size(), runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    EXPECT_TRUE(h.bus.log[i].read);
    EXPECT_EQ(h.bus.log[i].address, runs[i].first);
    EXPECT_EQ(h.bus.log[i].words.size(), runs[i].second);
  }
  const json values = h.json_lines().at(0)["values"];
  ASSERT_EQ(values.size(), std::size(regs::kRegisters));
  for (const json& v : values)
    EXPECT_EQ(v["value"], regs::find(v["path"].get<std::string>())->reset);
  ASSERT_EQ(h.run({"reg", "dump"}), cli::kExitOk);
  EXPECT_EQ(static_cast<std::size_t>(std::ranges::count(h.out, '\n')), std::size(regs::kRegisters));
}

TEST(CliRun, WatchSamplesCountTimesAndWaitsTheIntervalBetween) {
  Harness h;
  ASSERT_EQ(h.run({"--json", "reg", "watch", "top.scratch", "--count", "3", "--interval", "250us"}),
            cli::kExitOk)
      << h.err;
  const std::vector<json> lines = h.json_lines();
  ASSERT_EQ(lines.size(), 3U);
  EXPECT_EQ(h.waits, std::vector<std::chrono::nanoseconds>(2, std::chrono::microseconds{250}));
  for (std::size_t i = 0; i < lines.size(); ++i) {
    EXPECT_EQ(lines[i]["sample"], i);
    EXPECT_EQ(lines[i]["time_ns"], static_cast<std::int64_t>(i) * 250'000);
    EXPECT_EQ(lines[i]["values"][0]["path"], "top.scratch");
  }
  EXPECT_EQ(h.run({"reg", "watch", "top.scratch", "--interval", "100"}), cli::kExitUsage);
  EXPECT_EQ(h.run({"reg", "watch", "top.scratch", "--count", "0"}), cli::kExitUsage);
}

TEST(CliRun, WatchStopsWhenInterrupted) {
  Harness h;
  std::atomic<bool> stop{true};
  std::istringstream in;
  std::ostringstream out, err;
  FakeBus bus;
  std::vector<std::chrono::nanoseconds> waits;
  const int code = cli::run_cli(
      std::vector<std::string>{"reg", "watch", "top.id"}, {in, out, err},
      [&](std::string_view, const cli::TargetOptions&) {
        return std::make_unique<FakeTarget>(bus, waits);
      },
      &stop);
  EXPECT_EQ(code, cli::kExitInterrupted);
  EXPECT_TRUE(out.str().empty());
}

// A target whose wait() sees Ctrl-C half way, as SimBoard and SpidevTarget do.
class InterruptingTarget final : public cli::Target {
 public:
  InterruptingTarget(FakeBus& bus, std::atomic<bool>& stop) : bus_(bus), stop_(stop) {}
  odoloc::sw::RegisterBus& bus() override { return bus_; }
  void wait(std::chrono::nanoseconds /*interval*/) override {
    stop_.store(true);
    throw cli::Interrupted();
  }
  [[nodiscard]] std::chrono::nanoseconds elapsed() const override { return {}; }

 private:
  FakeBus& bus_;
  std::atomic<bool>& stop_;
};

// Issue 9: an interrupted wait exited 0, a script 130. Every command ends
// with 130 on Ctrl-C, in or out of a script.
TEST(CliRun, CtrlCEndsEveryCommandWith130) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"wait", "5s"},
                                             {"reg", "watch", "top.id"},
                                             {"reg", "watch", "top.id", "--count", "5"},
                                             {"script", "-"}}) {
    SCOPED_TRACE(args.front());
    std::atomic<bool> stop{false};
    std::istringstream in("reg read top.id\nwait 1s\nreg write top.scratch=1\n");
    std::ostringstream out, err;
    FakeBus bus;
    const int code = cli::run_cli(
        args, {in, out, err},
        [&](std::string_view, const cli::TargetOptions&) {
          return std::make_unique<InterruptingTarget>(bus, stop);
        },
        &stop);
    EXPECT_EQ(code, cli::kExitInterrupted) << err.str();
    EXPECT_TRUE(err.str().empty()) << err.str();
    EXPECT_EQ(bus.word(regs::top::scratch::kAddress), regs::top::scratch::kReset);
  }
}

TEST(CliRun, ScriptRunsEveryLineOnOneTarget) {
  Harness h;
  const std::string script =
      "# set and check\n"
      "reg write top.scratch=0x1234  # trailing comment\n"
      "\n"
      "reg read top.scratch\n"
      "--json reg read top.scratch.value\n"
      "wait 1ms\n";
  ASSERT_EQ(h.run({"--target", "sim:straight", "--crc", "script", "-"}, script), cli::kExitOk)
      << h.err;
  EXPECT_EQ(h.opened, 1);
  EXPECT_EQ(h.last_spec, "sim:straight");
  EXPECT_TRUE(h.last_crc);
  EXPECT_EQ(h.bus.word(regs::top::scratch::kAddress), 0x1234U);
  EXPECT_NE(h.out.find("top.scratch @ 0x004 = 0x00001234"), std::string::npos) << h.out;
  ASSERT_EQ(h.waits.size(), 1U);
  EXPECT_EQ(h.waits[0], std::chrono::milliseconds{1});
  const std::string last_line = h.out.substr(h.out.rfind('\n', h.out.size() - 2) + 1);
  EXPECT_EQ(json::parse(last_line)["values"][0]["value"], 0x1234);
}

TEST(CliRun, ScriptIsCheckedWholeBeforeAnythingRuns) {
  Harness h;
  ASSERT_EQ(
      h.run({"script", "-"}, "reg write top.scratch=1\nreg read top.scratch\nreg write top.id=2\n"),
      cli::kExitUsage);
  EXPECT_EQ(h.opened, 0);
  EXPECT_TRUE(h.bus.log.empty());
  EXPECT_NE(h.err.find("<stdin>:3: "), std::string::npos) << h.err;
  for (const char* bad : {"--target sim reg dump", "--crc reg dump", "script other.txt",
                          "reg frobnicate", "reg read 'unterminated"}) {
    EXPECT_EQ(h.run({"script", "-"}, bad), cli::kExitUsage) << bad;
    EXPECT_NE(h.err.find("<stdin>:1: "), std::string::npos) << h.err;
  }
  EXPECT_EQ(h.run({"script", "/nonexistent-odoloc/script.txt"}), cli::kExitUsage);
  EXPECT_NE(h.err.find(std::strerror(ENOENT)), std::string::npos) << h.err;
  // Issue 9: a directory ran as an empty script, exit 0.
  EXPECT_EQ(h.run({"script", ::testing::TempDir()}), cli::kExitUsage);
  EXPECT_NE(h.err.find("directory"), std::string::npos) << h.err;
}

// Issue 9: `reg watch top.id --interval 600s --count 3` ran 20 minutes of
// CPU. Simulated time beyond the limit per command is refused up front: 120 s
// fast-forwarding, 10 s with --cycle-step (issue 13).
TEST(CliRun, SimulatedTimeBeyondTheLimitIsRefusedBeforeAnythingRuns) {
  EXPECT_EQ(cli::simulated_limit(false).max, std::chrono::seconds{120});
  EXPECT_EQ(cli::simulated_limit(true).max, std::chrono::seconds{10});
  for (const bool cycle_step : {false, true}) {
    SCOPED_TRACE(cycle_step ? "--cycle-step" : "fast-forward");
    Harness h;
    const std::vector<std::string> mode =
        cycle_step ? std::vector<std::string>{"--cycle-step"} : std::vector<std::string>{};
    const auto with_mode = [&](std::vector<std::string> args) {
      args.insert(args.begin(), mode.begin(), mode.end());
      return args;
    };
    const auto max_s = cli::simulated_limit(cycle_step).max.count();
    const std::string over = fmt::format("{}.000000001s", max_s);
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"wait", over},
             {"reg", "watch", "top.id", "--interval", "600s", "--count", "3"},
             {"reg", "watch", "top.id", "--interval", over},
             {"reg", "watch", "top.id", "--interval", "1s", "--count", std::to_string(max_s + 2)},
             {"reg", "watch", "top.id", "--interval", "1s", "--count", "18446744073709551615"},
             {"--target", "sim:straight", "wait", over}}) {
      SCOPED_TRACE(args.back());
      EXPECT_EQ(h.run(with_mode(args)), cli::kExitUsage);
      EXPECT_NE(h.err.find("simulated"), std::string::npos) << h.err;
      EXPECT_NE(h.err.find(fmt::format("at most {} s per command", max_s)), std::string::npos)
          << h.err;
      EXPECT_EQ(h.err.find("--cycle-step") != std::string::npos, cycle_step) << h.err;
    }
    EXPECT_EQ(h.run(with_mode({"script", "-"}), "reg write top.scratch=1\nwait " + over + "\n"),
              cli::kExitUsage);
    EXPECT_NE(h.err.find("<stdin>:2: "), std::string::npos) << h.err;
    EXPECT_EQ(h.opened, 0);
    EXPECT_TRUE(h.waits.empty());
    // At the limit it runs; on spidev (wall-clock sleeps) there is no limit
    // (this opener never sleeps).
    EXPECT_EQ(h.run(with_mode({"wait", fmt::format("{}s", max_s)})), cli::kExitOk) << h.err;
    EXPECT_EQ(h.run(with_mode({"reg", "watch", "top.id", "--interval", "1s", "--count",
                               std::to_string(max_s + 1)})),
              cli::kExitOk)
        << h.err;
  }
  Harness h;
  EXPECT_EQ(h.run({"-t", "spidev:/dev/spidev0.0", "wait", "600s"}), cli::kExitOk) << h.err;
}

// Output that cannot be written (a full disk behind a redirection, a
// waveform file) is an error with exit 1, never a silent loss.
TEST(CliRun, FailedWritesAreErrors) {
  struct FullBuf : std::streambuf {
    int overflow(int /*c*/) override { return traits_type::eof(); }
  } full;
  std::ostream out(&full);
  std::ostringstream err;
  FakeBus bus;
  std::vector<std::chrono::nanoseconds> waits;
  const cli::TargetOpener fake = [&](std::string_view, const cli::TargetOptions&) {
    return std::make_unique<FakeTarget>(bus, waits);
  };
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"reg", "read", "top.id"}, {"reg", "list"}, {"--version"}, {"script", "-"}}) {
    err.str("");
    out.clear();
    std::istringstream script("reg read top.id\n");
    EXPECT_EQ(cli::run_cli(args, {script, out, err}, fake), cli::kExitBus) << args.back();
    EXPECT_NE(err.str().find("writing standard output failed"), std::string::npos) << err.str();
  }

  struct LosingTarget final : cli::Target {
    FakeBus& b;
    explicit LosingTarget(FakeBus& bus) : b(bus) {}
    odoloc::sw::RegisterBus& bus() override { return b; }
    void wait(std::chrono::nanoseconds /*interval*/) override {}
    [[nodiscard]] std::chrono::nanoseconds elapsed() const override { return {}; }
    void finish() override { throw cli::FileError("writing the waveform to 'x.vcd' failed"); }
  };
  std::ostringstream ok;
  const cli::TargetOpener losing = [&](std::string_view, const cli::TargetOptions&) {
    return std::make_unique<LosingTarget>(bus);
  };
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"reg", "read", "top.id"}, {"script", "-"}}) {
    err.str("");
    std::istringstream script("reg read top.id\n");
    EXPECT_EQ(cli::run_cli(args, {script, ok, err}, losing), cli::kExitBus) << args.back();
    EXPECT_EQ(err.str(), "odoloc: writing the waveform to 'x.vcd' failed\n");
  }
}

TEST(CliRun, DumpFilterVersionAndNegativeWordHints) {
  Harness h;
  ASSERT_EQ(h.run({"reg", "dump", "--filter", "eppm.*.count"}), cli::kExitOk) << h.err;
  EXPECT_EQ(static_cast<std::size_t>(std::ranges::count(h.out, '\n')), regs::eppm::kInstances)
      << h.out;
  ASSERT_EQ(h.run({"--json", "reg", "dump", "--filter", "decode_mode"}), cli::kExitOk);
  EXPECT_EQ(json::parse(h.out)["values"].size(), regs::eppm::kInstances);
  ASSERT_EQ(h.run({"reg", "dump", "--filter", "zzz"}), cli::kExitOk);
  EXPECT_EQ(h.out, "no register or field matches 'zzz'\n");

  const int opened = h.opened;
  ASSERT_EQ(h.run({"--version"}), cli::kExitOk);
  EXPECT_TRUE(h.out.starts_with("odoloc ")) << h.out;
  EXPECT_NE(h.out.find(fmt::format("0x{:08x}", regs::top::id::kReset)), std::string::npos);
  EXPECT_EQ(h.opened, opened);

  // The hint for a negative word names the register's signed writable
  // fields, and only those that exist.
  for (const regs::Register& r : regs::kRegisters) {
    if (r.access == regs::Access::kRo || r.access == regs::Access::kRc)
      continue;
    const std::string m = message_of([&] { (void)cli::parse_register_value(r, "-1"); });
    std::vector<std::string> signed_rw;
    for (const regs::Field& f : r.fields)
      if (f.is_signed && f.access == regs::Access::kRw)
        signed_rw.push_back(field_path(r, f));
    if (signed_rw.empty()) {
      EXPECT_EQ(m.find("signed field"), std::string::npos) << m;
    } else {
      for (const std::string& p : signed_rw)
        EXPECT_NE(m.find(p), std::string::npos) << m;
    }
  }
}

TEST(CliRun, BusErrorsExitWithOneAndNameTheLine) {
  Harness h;
  h.bus.fail_writes = true;
  EXPECT_EQ(h.run({"reg", "write", "top.scratch=1"}), cli::kExitBus);
  EXPECT_NE(h.err.find("bus error"), std::string::npos) << h.err;
  EXPECT_EQ(h.run({"script", "-"}, "reg read top.id\nreg write top.scratch=1\nreg read top.id\n"),
            cli::kExitBus);
  EXPECT_NE(h.err.find("<stdin>:2: "), std::string::npos) << h.err;
}

TEST(CliRun, UsageErrorsAndHelp) {
  Harness h;
  EXPECT_EQ(h.run({}), cli::kExitUsage);
  EXPECT_EQ(h.run({"reg"}), cli::kExitUsage);
  EXPECT_EQ(h.run({"reg", "read"}), cli::kExitUsage);
  EXPECT_EQ(h.run({"--target", "nowhere", "reg", "list"}), cli::kExitUsage);
  EXPECT_NE(h.err.find("unknown target 'nowhere'"), std::string::npos) << h.err;
  EXPECT_EQ(h.run({"--help"}), cli::kExitOk);
  EXPECT_NE(h.out.find("Usage"), std::string::npos);
  EXPECT_EQ(h.run({"reg", "write", "--help"}), cli::kExitOk);
  EXPECT_NE(h.out.find("NAME.FIELD=VALUE"), std::string::npos) << h.out;
  EXPECT_EQ(h.run({"reg", "--help"}), cli::kExitOk);
  // Issue 9: an unknown command with --help printed the general help, exit 0.
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"frobnicate", "--help"},
                                             {"--help", "frobnicate"},
                                             {"frobnicate", "-h"},
                                             {"reg", "frobnicate", "--help"},
                                             {"-t", "sim", "frobnicate", "--help"},
                                             {"frobnicate"}}) {
    EXPECT_EQ(h.run(args), cli::kExitUsage) << args.front();
    EXPECT_TRUE(h.out.empty()) << h.out;
    EXPECT_NE(h.err.find("unknown"), std::string::npos) << h.err;
  }
  EXPECT_EQ(h.run({"scirpt", "--help"}), cli::kExitUsage);
  EXPECT_NE(h.err.find("did you mean script?"), std::string::npos) << h.err;
  EXPECT_EQ(h.run({"reg", "wacth", "--help"}), cli::kExitUsage);
  EXPECT_NE(h.err.find("did you mean watch?"), std::string::npos) << h.err;
  EXPECT_EQ(h.run({"read", "top.id"}), cli::kExitUsage);
  EXPECT_NE(h.err.find("did you mean reg read?"), std::string::npos) << h.err;
  EXPECT_EQ(h.opened, 0);
  // Global options may follow the subcommand.
  EXPECT_EQ(h.run({"reg", "read", "top.id", "--json"}), cli::kExitOk) << h.err;
  EXPECT_EQ(json::parse(h.out)["values"][0]["value"], regs::top::id::kReset);
}

}  // namespace
