// EPPM block behaviour at the pins: decoder truth table, glitch filter,
// latency, counter wrap flags, read-increment, and a waveform dump.
#include <gtest/gtest.h>

#include <array>
#include <set>
#include <sstream>
#include <utility>

#include "eppm_bench.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/rtl/vcd.hpp"
#include "vcd_check.hpp"

namespace {

using odoloc::rtl::DecodeMode;
using odoloc::rtl::UInt;
using odoloc::tb::EppmBench;
using odoloc::world::QuadratureSource;

// The quadrature specification, written as the list of forward steps (A leads
// B, A in bit 1) rather than the model's phase arithmetic.
const std::set<std::pair<unsigned, unsigned>> kForwardSteps = {
    {0b00, 0b10}, {0b10, 0b11}, {0b11, 0b01}, {0b01, 0b00}};

int expected_count(unsigned prev, unsigned curr, DecodeMode mode) {
  const int dir = kForwardSteps.contains({prev, curr})   ? 1
                  : kForwardSteps.contains({curr, prev}) ? -1
                                                         : 0;
  const bool a_edge = ((prev ^ curr) & 0b10) != 0;
  const bool b_low_both = (prev & 1) == 0 && (curr & 1) == 0;
  switch (mode) {
    case DecodeMode::kX4:
      return dir;
    case DecodeMode::kX2:
      return a_edge ? dir : 0;
    case DecodeMode::kX1:
      return a_edge && b_low_both ? dir : 0;
  }
  return 0;
}

// Holds `ab` at the pins long enough to pass the pipeline.
void settle(EppmBench& tb, unsigned ab) {
  tb.set_pins(ab);
  tb.clock(tb.latency() + 2);
}

TEST(EppmDecoder, AllSixteenTransitionsInEveryMode) {
  for (const DecodeMode mode : {DecodeMode::kX4, DecodeMode::kX2, DecodeMode::kX1}) {
    for (unsigned prev = 0; prev < 4; ++prev) {
      for (unsigned curr = 0; curr < 4; ++curr) {
        SCOPED_TRACE(testing::Message()
                     << "mode " << static_cast<int>(mode) << " prev " << prev << " curr " << curr);
        EppmBench tb;
        tb.cfg.cfg.filter_clocks = UInt<8>{0};
        tb.cfg.cfg.decode_mode = UInt<2>{static_cast<unsigned>(mode)};
        // Reach `prev` by legal forward steps from 00, then start clean.
        for (unsigned ab : {0b10U, 0b11U, 0b01U}) {
          if (prev == 0)
            break;
          settle(tb, ab);
          if (ab == prev)
            break;
        }
        tb.latch_clear();
        tb.clear_flags();
        ASSERT_EQ(tb.dut.decoder().prev.value(), prev);
        const unsigned direction_before = static_cast<unsigned>(tb.dut.decoder().direction.value());

        settle(tb, curr);
        const bool illegal = (prev ^ curr) == 0b11;
        EXPECT_EQ(tb.count(), expected_count(prev, curr, mode));
        EXPECT_EQ(tb.dut.decoder().phase_error.value(), illegal ? 1U : 0U);
        EXPECT_EQ(tb.dut.decoder().error_count.value(), illegal ? 1U : 0U);
        const int x4 = expected_count(prev, curr, DecodeMode::kX4);
        const unsigned direction = x4 > 0 ? 1U : x4 < 0 ? 0U : direction_before;
        EXPECT_EQ(tb.dut.decoder().direction.value(), direction);
      }
    }
  }
}

TEST(EppmDecoder, X1AndX2CountAFractionOfX4AndNetZeroBackAndForth) {
  for (const DecodeMode mode : {DecodeMode::kX4, DecodeMode::kX2, DecodeMode::kX1}) {
    EppmBench tb;
    tb.cfg.cfg.decode_mode = UInt<2>{static_cast<unsigned>(mode)};
    QuadratureSource source{0.05};
    tb.run(source, 80'000);  // about 4000 edges = 1000 cycles
    tb.clock(tb.latency());
    // Edge k leaves quarter k: x2 counts the A edges (k even), x1 the first.
    std::int64_t expected = 0;
    for (std::int64_t k = 0; k < source.edges(); ++k) {
      expected += mode == DecodeMode::kX4 || (mode == DecodeMode::kX2 && k % 2 == 0) || k % 4 == 0;
    }
    EXPECT_EQ(tb.count(), expected);
    source.set_rate(-0.05);
    tb.run(source, 80'000);
    tb.clock(tb.latency());
    EXPECT_EQ(tb.count(), 0);
  }
}

TEST(EppmDecoder, IllegalTransitionsAreCountedAndSaturate) {
  EppmBench tb;
  tb.cfg.cfg.filter_clocks = UInt<8>{0};
  for (int i = 0; i < 70'000; ++i)
    settle(tb, i % 2 == 0 ? 0b11 : 0b00);
  EXPECT_EQ(tb.dut.decoder().error_count.value(), 65'535U);
  EXPECT_EQ(tb.dut.decoder().phase_error.value(), 1U);
  EXPECT_EQ(tb.count(), 0);
  tb.clear_flags();
  EXPECT_EQ(tb.dut.decoder().error_count.value(), 0U);
  EXPECT_EQ(tb.dut.decoder().phase_error.value(), 0U);
}

// A pulse of `width` clocks on A from rest; returns whether it reached the counter.
bool pulse_passes(unsigned filter_clocks, unsigned width) {
  EppmBench tb;
  tb.cfg.cfg.filter_clocks = UInt<8>{filter_clocks};
  tb.clock(10);
  tb.set_pins(0b10);
  tb.clock(width);
  tb.set_pins(0b00);
  bool moved = false;
  for (int i = 0; i < 600; ++i) {
    tb.clock();
    moved = moved || tb.count() != 0;
  }
  EXPECT_EQ(tb.count(), 0);  // whatever passed came back
  return moved;
}

TEST(EppmFilter, PassesNClocksRejectsNMinusOne) {
  for (unsigned n : {2U, 3U, 4U, 8U, 100U, 255U}) {
    SCOPED_TRACE(n);
    EXPECT_TRUE(pulse_passes(n, n));
    EXPECT_FALSE(pulse_passes(n, n - 1));
  }
}

TEST(EppmFilter, OffPassesSingleClockPulses) {
  EXPECT_TRUE(pulse_passes(0, 1));
  EXPECT_TRUE(pulse_passes(1, 1));
}

TEST(EppmFilter, LatencyIsNPlusThreeClocks) {
  for (unsigned n : {0U, 1U, 2U, 3U, 7U, 255U}) {
    SCOPED_TRACE(n);
    EppmBench tb;
    tb.cfg.cfg.filter_clocks = UInt<8>{n};
    tb.clock(5);
    tb.set_pins(0b10);
    tb.clock(tb.latency() - 1);
    EXPECT_EQ(tb.count(), 0);
    tb.clock();
    EXPECT_EQ(tb.count(), 1);
  }
}

TEST(EppmFilter, GlitchTrainShorterThanNNeverCounts) {
  EppmBench tb;
  tb.cfg.cfg.filter_clocks = UInt<8>{5};
  for (int i = 0; i < 1000; ++i) {
    tb.set_pins(i % 3 == 0 ? 0b10 : 0b01);  // each channel high for 1..4 clocks, then low
    tb.clock(1 + static_cast<unsigned>(i % 4));
    tb.set_pins(0b00);
    tb.clock(1 + static_cast<unsigned>(i % 5));
  }
  tb.clock(20);
  EXPECT_EQ(tb.count(), 0);
  EXPECT_EQ(tb.dut.decoder().error_count.value(), 0U);
}

TEST(EppmCounter, WrapsWithStickyCarryAndBorrow) {
  EppmBench tb;
  tb.cfg.cfg.filter_clocks = UInt<8>{0};
  QuadratureSource source{0.5};
  constexpr std::int64_t kMax = (1 << 19) - 1;
  // Up to +max: no carry yet.
  while (source.edges() < kMax) {
    tb.set_pins(static_cast<unsigned>(odoloc::board::encoder_pins(source.tick()).value()));
    tb.clock();
  }
  tb.clock(tb.latency());
  EXPECT_EQ(tb.count(), kMax);
  EXPECT_EQ(tb.dut.counter().carry.value(), 0U);
  tb.run(source, 2);  // one more edge
  tb.clock(tb.latency());
  EXPECT_EQ(tb.count(), -kMax - 1);
  EXPECT_EQ(tb.dut.counter().carry.value(), 1U);
  EXPECT_EQ(tb.dut.counter().borrow.value(), 0U);
  tb.clear_flags();
  EXPECT_EQ(tb.dut.counter().carry.value(), 0U);
  // Back down across the wrap: a borrow.
  source.set_rate(-0.5);
  tb.run(source, 2);
  tb.clock(tb.latency());
  EXPECT_EQ(tb.count(), kMax);
  EXPECT_EQ(tb.dut.counter().borrow.value(), 1U);
  EXPECT_EQ(tb.dut.counter().carry.value(), 0U);
}

// The clear lands at every phase around the clock where an edge reaches the
// counter: the edge must end up in exactly one of latched and count.
TEST(EppmCounter, LatchClearNeverLosesAnEdge) {
  for (int offset = -3; offset <= 3; ++offset) {
    SCOPED_TRACE(offset);
    EppmBench tb;
    tb.clock(5);
    tb.set_pins(0b10);
    const std::uint64_t edge_step = tb.steps + tb.latency() - 1;  // the step that counts it
    tb.clock(static_cast<std::uint64_t>(static_cast<std::int64_t>(edge_step - tb.steps) + offset));
    tb.latch_clear();
    tb.clock(10);
    const std::int64_t latched = tb.dut.counter().latched.value();
    EXPECT_EQ(latched + tb.count(), 1);
    EXPECT_EQ(latched, offset >= 0 ? 1 : 0);
  }
}

TEST(EppmCounter, IncrementsSumToTheTruthAtFullRate) {
  EppmBench tb;
  tb.cfg.cfg.filter_clocks = UInt<8>{0};
  QuadratureSource source{0.999};  // an edge almost every clock
  std::int64_t sum = 0;
  for (int i = 0; i < 200'000; ++i) {
    if (i == 100'000)
      source.set_rate(-0.7);
    tb.set_pins(static_cast<unsigned>(odoloc::board::encoder_pins(source.tick()).value()));
    tb.in.latch_clear = UInt<1>::truncate(i % 7 == 0 || i % 11 == 0);
    tb.clock();
    if (i % 7 == 0 || i % 11 == 0)
      sum += tb.dut.counter().latched.value();
  }
  tb.clock(tb.latency());
  EXPECT_EQ(sum + tb.count(), source.edges());
  EXPECT_EQ(tb.dut.decoder().error_count.value(), 0U);
}

// A mirrored wheel's encoder turns the other way for the same motion: its
// quadrature sequence is the twin's with A and B exchanged. With cfg.reverse
// it counts like the twin: every count, the speed word and the direction
// bits, in every decode mode, across a reversal.
TEST(EppmReverse, AMirroredWheelCountsLikeItsTwin) {
  for (const unsigned mode : {0U, 1U, 2U}) {
    EppmBench twin, mirrored;
    twin.cfg.cfg.decode_mode = mirrored.cfg.cfg.decode_mode = UInt<2>{mode};
    mirrored.cfg.cfg.reverse = UInt<1>{1};
    QuadratureSource wheel{0.013};
    for (int i = 0; i < 300'000; ++i) {
      if (i == 150'000)
        wheel.set_rate(-0.004);
      const auto levels = wheel.tick();
      twin.set_pins(static_cast<unsigned>(odoloc::board::encoder_pins(levels).value()));
      mirrored.set_pins(static_cast<unsigned>(
          odoloc::board::encoder_pins({.a = levels.b, .b = levels.a}).value()));
      twin.clock();
      mirrored.clock();
      ASSERT_EQ(mirrored.count(), twin.count()) << "mode " << mode << " clock " << i;
      ASSERT_EQ(mirrored.dut.status(mirrored.cfg), twin.dut.status(twin.cfg))
          << "mode " << mode << " clock " << i;
    }
    EXPECT_GT(twin.count(), 100) << mode;  // it moved (1950 x4 edges out, 600 back)
  }
}

// Without reverse the same mirrored wheel counts backwards: the bit matters.
TEST(EppmReverse, WithoutTheBitAMirroredWheelCountsBackwards) {
  EppmBench mirrored;
  QuadratureSource wheel{0.013};
  for (int i = 0; i < 10'000; ++i) {
    const auto levels = wheel.tick();
    mirrored.set_pins(
        static_cast<unsigned>(odoloc::board::encoder_pins({.a = levels.b, .b = levels.a}).value()));
    mirrored.clock();
  }
  EXPECT_LT(mirrored.count(), -100);
}

TEST(EppmReset, SynchronousResetClearsEveryRegister) {
  EppmBench tb;
  QuadratureSource source{0.1};
  tb.run(source, 100'000);
  tb.in.reset = UInt<1>{1};
  tb.clock();
  const EppmBench fresh;
  EXPECT_EQ(tb.dut.conditioner(), fresh.dut.conditioner());
  EXPECT_EQ(tb.dut.decoder(), fresh.dut.decoder());
  EXPECT_EQ(tb.dut.counter(), fresh.dut.counter());
  EXPECT_EQ(tb.dut.timebase(), fresh.dut.timebase());
  EXPECT_EQ(tb.dut.pulse(), fresh.dut.pulse());
  EXPECT_EQ(tb.dut.period(), fresh.dut.period());
}

TEST(EppmWaveform, VcdOfAShortRunIsWellFormedAndMatchesTheModel) {
  EppmBench tb;
  std::ostringstream text;
  odoloc::rtl::VcdWriter vcd(text, "eppm");
  vcd.declare(tb.dut);
  QuadratureSource source{0.2};
  std::array<std::int64_t, 400> count_after{};
  for (std::uint64_t c = 0; c < count_after.size(); ++c) {
    tb.run(source, 1);
    vcd.sample(tb.dut, c);
    count_after[c] = tb.count();
  }
  const auto result = odoloc::tb::check_vcd(text.str());
  ASSERT_TRUE(result.ok()) << result.error_text();
  const auto* count = result.find("eppm.counter.count");
  ASSERT_NE(count, nullptr);
  EXPECT_EQ(count->width, 20);
  ASSERT_NE(result.find("eppm.period.count"), nullptr);
  EXPECT_EQ(result.find("eppm.period.count")->width, 23);
  for (std::uint64_t c = 0; c < count_after.size(); c += 37) {
    const auto v = result.value_at("eppm.counter.count", c * 20);
    ASSERT_TRUE(v.has_value());
    EXPECT_EQ(static_cast<std::int64_t>(*v), count_after[c]) << "cycle " << c;
  }
}

}  // namespace
