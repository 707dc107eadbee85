// VcdWriter: its output passes the independent checker, reads back as the
// block's state cycle by cycle, and misuse throws. The checker itself is shown
// to reject broken files, and vcd2fst (GTKWave) must accept the output.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "odoloc/process/run_program.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/vcd.hpp"
#include "vcd_check.hpp"

namespace {

using odoloc::rtl::SInt;
using odoloc::rtl::TraceVisitor;
using odoloc::rtl::UInt;
using odoloc::rtl::VcdWriter;
using odoloc::tb::check_vcd;
using odoloc::tb::VcdCheckResult;

// A 4-bit wrapping counter with a wrap flag, and a level that steps down by 3
// a clock in a nested scope, saturating at SInt<6>'s minimum.
class DemoBlock {
 public:
  struct Regs {
    UInt<4> count;
    UInt<1> wrapped;
    SInt<6> level;
  };
  using Next = Regs;

  [[nodiscard]] Next eval(UInt<1> enable) const {
    if (!enable)
      return r_;
    Regs n;
    n.count = (r_.count + UInt<1>{1}).wrap<4>();
    n.wrapped = r_.count == UInt<4>{15} ? UInt<1>{1} : UInt<1>{0};
    n.level = (r_.level - SInt<3>{3}).sat<6>();
    return n;
  }
  void commit(const Next& n) { r_ = n; }
  void reset_now() { r_ = Regs{}; }

  template <TraceVisitor V>
  void trace(V& v) const {
    v.signal("count", r_.count);
    v.signal("wrapped", r_.wrapped);
    v.enter("filter");
    v.signal("level", r_.level);
    v.leave();
  }

 private:
  Regs r_;
};

constexpr std::uint64_t kPeriod = odoloc::rtl::kFabricClockPeriodNs;

// Declares, then samples `cycles` clocks with enable high.
std::string run_demo(int cycles) {
  std::ostringstream out;
  DemoBlock block;
  VcdWriter vcd(out);
  vcd.declare(block);
  for (int c = 0; c < cycles; ++c) {
    block.commit(block.eval(UInt<1>{1}));
    vcd.sample(block, static_cast<std::uint64_t>(c));
  }
  return out.str();
}

TEST(VcdWriter, OutputPassesTheChecker) {
  const auto vcd = check_vcd(run_demo(40));
  ASSERT_TRUE(vcd.ok()) << vcd.error_text();
  EXPECT_EQ(vcd.timestamps, 80U);
}

TEST(VcdWriter, DeclaresScopedNamesAndWidths) {
  const auto vcd = check_vcd(run_demo(3));
  ASSERT_TRUE(vcd.ok()) << vcd.error_text();
  ASSERT_EQ(vcd.vars.size(), 4U);
  const std::vector<std::pair<std::string, int>> expected{
      {"odoloc.clk", 1}, {"odoloc.count", 4}, {"odoloc.wrapped", 1}, {"odoloc.filter.level", 6}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(vcd.vars[i].name, expected[i].first);
    EXPECT_EQ(vcd.vars[i].width, expected[i].second) << expected[i].first;
  }
}

TEST(VcdWriter, HeaderHasTheFixedParts) {
  const std::string text = run_demo(1);
  EXPECT_EQ(text.rfind("$date\n", 0), 0U);
  EXPECT_NE(text.find("$version\n"), std::string::npos);
  EXPECT_NE(text.find("\n$timescale 1ns $end\n"), std::string::npos);
  EXPECT_NE(text.find("\n$scope module odoloc $end\n"), std::string::npos);
  EXPECT_NE(text.find("\n$enddefinitions $end\n#0\n$dumpvars\n"), std::string::npos);
}

TEST(VcdWriter, TopScopeIsConfigurable) {
  std::ostringstream out;
  VcdWriter vcd(out, "wheel0");
  vcd.declare(DemoBlock{});
  const auto result = check_vcd(out.str());
  ASSERT_TRUE(result.ok()) << result.error_text();
  EXPECT_NE(result.find("wheel0.filter.level"), nullptr);
  EXPECT_THROW(VcdWriter(out, "has space"), std::invalid_argument);
}

TEST(VcdWriter, ClockRisesAtEachCommitAndFallsHalfAPeriodLater) {
  constexpr int kCycles = 30;
  const auto vcd = check_vcd(run_demo(kCycles));
  ASSERT_TRUE(vcd.ok()) << vcd.error_text();
  for (std::uint64_t c = 0; c < kCycles; ++c) {
    EXPECT_EQ(vcd.value_at("odoloc.clk", c * kPeriod), 1U) << "cycle " << c;
    EXPECT_EQ(vcd.value_at("odoloc.clk", c * kPeriod + 9), 1U) << "cycle " << c;
    EXPECT_EQ(vcd.value_at("odoloc.clk", c * kPeriod + 10), 0U) << "cycle " << c;
    EXPECT_EQ(vcd.value_at("odoloc.clk", c * kPeriod + 19), 0U) << "cycle " << c;
  }
  // Two edges per cycle, each at its own timestamp.
  const auto& clk = vcd.history[0];
  ASSERT_EQ(clk.size(), 1U + 2 * kCycles);  // $dumpvars value, then the edges
  for (std::size_t i = 1; i < clk.size(); ++i) {
    EXPECT_EQ(clk[i].time, (i - 1) * kPeriod / 2);
  }
}

TEST(VcdWriter, CounterReadsBackIncludingTheWrap) {
  constexpr int kCycles = 40;
  const auto vcd = check_vcd(run_demo(kCycles));
  ASSERT_TRUE(vcd.ok()) << vcd.error_text();
  EXPECT_EQ(vcd.value_at("odoloc.count", 0), 1U);  // the commit of cycle 0 is at t = 0
  for (std::uint64_t c = 0; c < kCycles; ++c) {
    const std::uint64_t count = (c + 1) % 16;
    EXPECT_EQ(vcd.value_at("odoloc.count", c * kPeriod), count) << "cycle " << c;
    EXPECT_EQ(vcd.value_at("odoloc.count", c * kPeriod + 15), count) << "cycle " << c;
    EXPECT_EQ(vcd.value_at("odoloc.wrapped", c * kPeriod), count == 0 ? 1U : 0U) << "cycle " << c;
  }
  EXPECT_EQ(vcd.value_at("odoloc.count", 14 * kPeriod), 15U);
  EXPECT_EQ(vcd.value_at("odoloc.count", 15 * kPeriod), 0U);
}

TEST(VcdWriter, NegativeSIntDumpsItsTwosComplementPattern) {
  const std::string text = run_demo(12);
  const auto vcd = check_vcd(text);
  ASSERT_TRUE(vcd.ok()) << vcd.error_text();
  const auto* level = vcd.find("odoloc.filter.level");
  ASSERT_NE(level, nullptr);
  EXPECT_EQ(vcd.value_at(level->name, 0), 0b111101U);             // -3
  EXPECT_EQ(vcd.value_at(level->name, 1 * kPeriod), 0b111010U);   // -6
  EXPECT_EQ(vcd.value_at(level->name, 11 * kPeriod), 0b100000U);  // saturated at -32
  EXPECT_NE(text.find("\nb111101 " + level->id + "\n"), std::string::npos);
}

TEST(VcdWriter, WritesOnlyChanges) {
  const auto vcd = check_vcd(run_demo(40));
  ASSERT_TRUE(vcd.ok()) << vcd.error_text();
  // level: initial value, then -3 ... -30, then -32 (cycle 10), then constant.
  EXPECT_EQ(vcd.history[3].size(), 1U + 11U);
  // wrapped: initial 0, then 1 and 0 again around each of the two wraps.
  EXPECT_EQ(vcd.history[2].size(), 1U + 4U);
}

struct Wide {
  UInt<64> u = UInt<64>::truncate(~std::uint64_t{0});
  SInt<64> s = SInt<64>::truncate(std::numeric_limits<std::int64_t>::min());
  SInt<2> small = SInt<2>{-1};
  template <class V>
  void trace(V& v) const {
    v.signal("u", u);
    v.signal("s", s);
    v.signal("small", small);
  }
};

TEST(VcdWriter, FullWidthValues) {
  std::ostringstream out;
  VcdWriter vcd(out);
  vcd.declare(Wide{});
  vcd.sample(Wide{}, 0);
  const auto result = check_vcd(out.str());
  ASSERT_TRUE(result.ok()) << result.error_text();
  EXPECT_EQ(result.value_at("odoloc.u", 0), ~std::uint64_t{0});
  EXPECT_EQ(result.value_at("odoloc.s", 0), std::uint64_t{1} << 63);
  EXPECT_EQ(result.value_at("odoloc.small", 0), 0b11U);
}

// More signals than one-character identifiers: codes grow to two characters.
std::string reg_name(std::size_t i) {
  std::string name = "r";  // not "r" + ...: GCC 12 -Wrestrict false positive
  name += std::to_string(i);
  return name;
}
struct Many {
  std::array<UInt<9>, 300> regs{};
  template <class V>
  void trace(V& v) const {
    for (std::size_t i = 0; i < regs.size(); ++i) {
      v.signal(reg_name(i), regs[i]);
    }
  }
};

TEST(VcdWriter, ManySignalsGetUniqueIds) {
  constexpr std::size_t kSignals = std::tuple_size_v<decltype(Many::regs)>;
  std::ostringstream out;
  VcdWriter vcd(out);
  Many block;
  vcd.declare(block);
  for (std::size_t i = 0; i < kSignals; ++i) {
    block.regs[i] = UInt<9>{i};
  }
  vcd.sample(block, 0);
  const auto result = check_vcd(out.str());
  ASSERT_TRUE(result.ok()) << result.error_text();  // the checker rejects duplicate ids
  ASSERT_EQ(result.vars.size(), kSignals + 1);
  for (std::size_t i = 0; i < kSignals; ++i) {
    EXPECT_EQ(result.value_at("odoloc." + reg_name(i), 0), i);
  }
}

TEST(VcdWriter, SampleBeforeDeclareThrows) {
  std::ostringstream out;
  VcdWriter vcd(out);
  EXPECT_THROW(vcd.sample(DemoBlock{}, 0), std::logic_error);
}

TEST(VcdWriter, DeclareTwiceThrows) {
  std::ostringstream out;
  VcdWriter vcd(out);
  vcd.declare(DemoBlock{});
  EXPECT_THROW(vcd.declare(DemoBlock{}), std::logic_error);
}

TEST(VcdWriter, CyclesMustIncrease) {
  std::ostringstream out;
  VcdWriter vcd(out);
  const DemoBlock block;
  vcd.declare(block);
  vcd.sample(block, 5);
  EXPECT_THROW(vcd.sample(block, 5), std::logic_error);
  EXPECT_THROW(vcd.sample(block, 4), std::logic_error);
  vcd.sample(block, 7);  // gaps are fine
  const auto result = check_vcd(out.str());
  EXPECT_TRUE(result.ok()) << result.error_text();
}

// A block whose trace visits a different number of signals than it declared.
struct Shifty {
  int extra = 0;
  template <class V>
  void trace(V& v) const {
    v.signal("a", UInt<3>{1});
    if (extra > 0)
      v.signal("b", UInt<3>{2});
    if (extra > 1)
      v.signal("c", UInt<3>{3});
  }
};

TEST(VcdWriter, TraceMismatchThrows) {
  std::ostringstream out;
  VcdWriter vcd(out);
  vcd.declare(Shifty{1});
  EXPECT_THROW(vcd.sample(Shifty{2}, 0), std::logic_error);
  EXPECT_THROW(vcd.sample(Shifty{0}, 1), std::logic_error);
  vcd.sample(Shifty{1}, 2);
}

struct NoLeave {
  template <class V>
  void trace(V& v) const {
    v.enter("x");
  }
};
struct NoEnter {
  template <class V>
  void trace(V& v) const {
    v.leave();
  }
};

TEST(VcdWriter, UnbalancedScopesThrow) {
  std::ostringstream out;
  EXPECT_THROW(VcdWriter(out).declare(NoLeave{}), std::logic_error);
  EXPECT_THROW(VcdWriter(out).declare(NoEnter{}), std::logic_error);
}

// ---- the checker must be able to fail ----------------------------------------

const std::string kGoodVcd = R"($date today $end
$version test $end
$timescale 1ns $end
$scope module top $end
$var wire 1 ! clk $end
$scope module sub $end
$var wire 4 " count $end
$upscope $end
$upscope $end
$enddefinitions $end
#0
$dumpvars
0!
b0 "
$end
1!
b101 "
#10
0!
)";

VcdCheckResult check_edited(const std::string& from, const std::string& to) {
  std::string text = kGoodVcd;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  return check_vcd(text);
}

TEST(VcdCheck, AcceptsTheReferenceText) {
  const auto vcd = check_vcd(kGoodVcd);
  EXPECT_TRUE(vcd.ok()) << vcd.error_text();
  EXPECT_EQ(vcd.timestamps, 2U);
  EXPECT_EQ(vcd.value_at("top.sub.count", 0), 5U);
  EXPECT_EQ(vcd.value_at("top.clk", 10), 0U);
  EXPECT_EQ(check_edited("1ns", "1 ns").errors.size(), 0U);
}

TEST(VcdCheck, RejectsBrokenText) {
  struct Edit {
    std::string from, to, expected_error;
  };
  const std::vector<Edit> edits{
      {"b101 \"", "b101 #", "undeclared id '#'"},
      {"b101 \"", "b10101 \"", "5 bits for 4-bit top.sub.count"},
      {"1!\nb101", "1\"\nb101", "scalar change for 4-bit"},
      {"#10", "#0", "time 0 does not follow 0"},
      {"#10", "#5\n0!\n#3", "time 3 does not follow 5"},
      {"$upscope $end\n$upscope $end\n", "$upscope $end\n", "1 $scope(s) still open"},
      {"$enddefinitions", "$upscope $end\n$enddefinitions", "$upscope without an open $scope"},
      {"$timescale 1ns $end\n", "", "missing $timescale"},
      {"1ns", "1ps", "$timescale is '1ps'"},
      {"$var wire 4 \"", "$var wire 0 \"", "no positive width"},
      {"$var wire 4 \"", "$var wire 4 !", "reuses id '!'"},
      {"b0 \"\n", "", "$dumpvars gives no value to top.sub.count"},
      {"$enddefinitions $end\n", "", "missing $enddefinitions"},
      {"$dumpvars\n0!\nb0 \"\n$end\n", "0!\nb0 \"\n", "missing $dumpvars"},
      {"b101 \"", "b1x2 \"", "bad vector value"},
      {"$enddefinitions $end\n#0\n", "$enddefinitions $end\n", "before the first timestamp"},
  };
  for (const auto& edit : edits) {
    const auto vcd = check_edited(edit.from, edit.to);
    EXPECT_NE(vcd.error_text().find(edit.expected_error), std::string::npos)
        << "after replacing '" << edit.from << "', errors were:\n"
        << vcd.error_text();
  }
}

// A var's waveform as a viewer shows it: per time, the last value written
// then, as a number (x/z bits: nullopt); repeats of the same value dropped.
using Waveform = std::vector<std::pair<std::uint64_t, std::optional<std::uint64_t>>>;

Waveform waveform_of(const VcdCheckResult& vcd, std::size_t var) {
  Waveform wave;
  for (const auto& change : vcd.history[var]) {
    std::optional<std::uint64_t> value = 0;
    for (const char c : change.bits) {
      if (c != '0' && c != '1') {
        value.reset();
        break;
      }
      *value = (*value << 1) | (c == '1' ? 1U : 0U);
    }
    if (!wave.empty() && wave.back().first == change.time)
      wave.pop_back();
    if (wave.empty() || wave.back().second != value)
      wave.emplace_back(change.time, value);
  }
  return wave;
}

// fst2vcd names a vector "count [3:0]": the name without the range.
std::string without_range(const std::string& name) {
  const auto bracket = name.find('[');
  return bracket == std::string::npos ? name : name.substr(0, bracket);
}

// GTKWave's own reader as an outside opinion: vcd2fst then fst2vcd must give
// back every value change of every signal, the initial values at time 0
// included (they were lost while $dumpvars came before the first #0).
TEST(VcdWriter, Vcd2FstRoundTripKeepsEveryValueChange) {
  const std::filesystem::path dir = testing::TempDir();
  if (!odoloc::process::run_program("vcd2fst", {"--help"}, dir).launched ||
      !odoloc::process::run_program("fst2vcd", {"--help"}, dir).launched) {
    GTEST_SKIP() << "vcd2fst/fst2vcd (Debian package gtkwave) not on PATH";
  }
  const auto vcd_path = dir / "odoloc_test_vcd.vcd";
  const auto fst_path = dir / "odoloc_test_vcd.fst";
  const auto back_path = dir / "odoloc_test_vcd_back.vcd";
  const std::string written = run_demo(40);
  std::ofstream(vcd_path) << written;
  const auto converted =
      odoloc::process::run_program("vcd2fst", {vcd_path.string(), fst_path.string()}, dir);
  ASSERT_TRUE(converted.ok()) << converted.message;
  const auto back = odoloc::process::run_program(
      "fst2vcd", {"-f", fst_path.string(), "-o", back_path.string()}, dir);
  ASSERT_TRUE(back.ok()) << back.message;
  std::ifstream back_file(back_path);
  const auto theirs = check_vcd(back_file);
  for (const auto& path : {vcd_path, fst_path, back_path})
    std::filesystem::remove(path);

  const auto ours = check_vcd(written);
  ASSERT_TRUE(ours.ok()) << ours.error_text();
  ASSERT_EQ(theirs.vars.size(), ours.vars.size()) << theirs.error_text();
  std::size_t changes = 0;
  for (std::size_t i = 0; i < ours.vars.size(); ++i) {
    const auto& name = ours.vars[i].name;
    const auto match = std::find_if(theirs.vars.begin(), theirs.vars.end(),
                                    [&](const auto& v) { return without_range(v.name) == name; });
    ASSERT_NE(match, theirs.vars.end()) << name << " is missing after the round trip";
    const Waveform expected = waveform_of(ours, i);
    EXPECT_EQ(waveform_of(theirs, static_cast<std::size_t>(match - theirs.vars.begin())), expected)
        << name;
    ASSERT_FALSE(expected.empty());
    EXPECT_EQ(expected.front(),
              (std::pair{std::uint64_t{0}, std::optional<std::uint64_t>{expected.front().second}}))
        << name << " has no value at time 0";
    changes += expected.size();
  }
  EXPECT_GT(changes, 80U);  // clk alone toggles 80 times
}

}  // namespace
