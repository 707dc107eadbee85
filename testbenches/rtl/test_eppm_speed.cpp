// EPPM speed meter: accuracy of both modes over the whole speed range against
// the paper's quantisation bounds, the automatic switch, hysteresis, signs,
// reversals, stall and overflow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

#include "eppm_bench.hpp"
#include "odoloc/sw/eppm_units.hpp"

namespace {

using odoloc::rtl::SpeedMode;
using odoloc::rtl::SpeedModeSelect;
using odoloc::rtl::UInt;
using odoloc::sw::SpeedTiming;
using odoloc::tb::EppmBench;
using odoloc::world::QuadratureSource;

constexpr double kClockHz = odoloc::sw::kFabricClockHz;

double window_of(const EppmBench& tb) {
  return static_cast<double>(tb.cfg.window.clocks.value());
}
double speed_of(const EppmBench& tb) {
  return static_cast<double>(tb.dut.status(tb.cfg).speed.value.value());
}

void select(EppmBench& tb, SpeedModeSelect mode) {
  tb.cfg.cfg.speed_mode_select = UInt<2>{static_cast<unsigned>(mode)};
}

// Edge rates from 200 edges/s to 5 M edges/s, log spaced.
std::vector<double> speed_sweep(double from, double to, int points) {
  std::vector<double> rates;
  for (int i = 0; i < points; ++i) {
    rates.push_back(from * std::pow(to / from, static_cast<double>(i) / (points - 1)));
  }
  return rates;
}

TEST(EppmSpeed, PulseModeIsWithinOneEdgePerWindowOverTheRange) {
  for (const double edges_per_s : speed_sweep(2e3, 5e6, 25)) {
    SCOPED_TRACE(edges_per_s);
    EppmBench tb;
    select(tb, SpeedModeSelect::kPulse);
    QuadratureSource source{edges_per_s / kClockHz};
    const double window = window_of(tb);
    const double truth = source.rate() * window;  // edges per window
    int samples = 0;
    for (int w = 0; w < 4 * static_cast<int>(window); ++w) {
      tb.run(source, 1);
      if (!tb.dut.pulse().sampled || static_cast<double>(tb.steps) <= window)
        continue;  // start-up
      ++samples;
      const auto speed = tb.dut.status(tb.cfg).speed;
      ASSERT_EQ(speed.mode.value(), static_cast<unsigned>(SpeedMode::kPulse));
      EXPECT_LE(std::abs(static_cast<double>(speed.value.value()) - truth), 1.0);
    }
    EXPECT_EQ(samples, 3);
  }
}

TEST(EppmSpeed, PeriodModeIsWithinOneTickPerEdgeOverTheRange) {
  for (const std::uint32_t prescale : {0U, 49U}) {
    for (const double edges_per_s : speed_sweep(500, 1e6, 20)) {
      SCOPED_TRACE(testing::Message() << edges_per_s << " edges/s, prescale " << prescale);
      EppmBench tb;
      select(tb, SpeedModeSelect::kPeriod);
      tb.cfg.prescale.divider = UInt<16>{prescale};
      tb.cfg.stall_ticks.ticks = UInt<23>{0};
      QuadratureSource source{edges_per_s / kClockHz};
      const double ticks_per_clock = 1.0 / (prescale + 1.0);
      const double truth = ticks_per_clock / source.rate();  // ticks per edge
      const double bound = 1.0 + ticks_per_clock;            // docs/eppm.md
      int samples = 0;
      while (samples < 6) {
        tb.run(source, 1);
        if (!tb.dut.period().sampled)
          continue;
        const auto speed = tb.dut.status(tb.cfg).speed;
        if (!speed.valid)
          continue;  // the first edge only starts a measurement
        ++samples;
        EXPECT_LE(std::abs(static_cast<double>(speed.value.value()) - truth), bound);
        // The paper's relative error f_edge / f_ref, up to the same factor.
        const SpeedTiming timing{50'000, prescale};
        EXPECT_LE(std::abs(speed_of(tb) - truth) / truth,
                  bound * timing.period_relative_error(edges_per_s) * (1 + 1e-9));
      }
    }
  }
}

TEST(EppmSpeed, AutomaticSwitchChoosesTheMoreAccurateMode) {
  const SpeedTiming timing;
  const auto thresholds = odoloc::sw::switch_thresholds(timing);
  for (const double edges_per_s : speed_sweep(2e3, 2e6, 31)) {
    const double per_window = edges_per_s * timing.window_s();
    const double pulse_error = timing.pulse_relative_error(edges_per_s);
    const double period_error = timing.period_relative_error(edges_per_s);
    // Inside the hysteresis band either mode is acceptable.
    if (per_window >= thresholds.to_period_below - 1 && per_window <= thresholds.to_pulse_at + 1) {
      continue;
    }
    SCOPED_TRACE(testing::Message() << edges_per_s << " edges/s, " << per_window << " per window");
    for (const SpeedMode start : {SpeedMode::kPeriod, SpeedMode::kPulse}) {
      EppmBench tb;
      tb.cfg.to_period_below.edges = UInt<23>{thresholds.to_period_below};
      tb.cfg.to_pulse_at.edges = UInt<23>{thresholds.to_pulse_at};
      select(tb, start == SpeedMode::kPulse ? SpeedModeSelect::kPulse : SpeedModeSelect::kPeriod);
      QuadratureSource source{edges_per_s / kClockHz};
      tb.run(source, timing.window_clocks);
      select(tb, SpeedModeSelect::kAuto);
      tb.run(source, 3 * timing.window_clocks);
      const auto speed = tb.dut.status(tb.cfg).speed;
      const auto expected = pulse_error < period_error ? SpeedMode::kPulse : SpeedMode::kPeriod;
      EXPECT_EQ(speed.mode.value(), static_cast<unsigned>(expected));
      // The chosen reading is within its own bound, which beats the other's.
      const bool pulse = speed.mode.value() == static_cast<unsigned>(SpeedMode::kPulse);
      const double truth = pulse ? source.rate() * timing.window_clocks
                                 : 1.0 / (source.rate() * (timing.prescale + 1.0));
      const double error = std::abs(speed_of(tb) - truth) / truth;
      EXPECT_LE(error, 2.0 * std::min(pulse_error, period_error));
    }
  }
}

// A speed whose window count alternates between to_pulse_at - 1 and
// to_pulse_at: with a band the mode settles, without one it chatters.
int mode_changes(std::uint32_t to_period_below, std::uint32_t to_pulse_at) {
  EppmBench tb;
  tb.cfg.to_period_below.edges = UInt<23>{to_period_below};
  tb.cfg.to_pulse_at.edges = UInt<23>{to_pulse_at};
  const double window = window_of(tb);
  QuadratureSource source{(to_pulse_at - 0.5) / window};
  int changes = 0;
  auto mode = tb.dut.pulse().mode;
  for (int i = 0; i < 60; ++i) {
    tb.run(source, tb.cfg.window.clocks.value());
    changes += tb.dut.pulse().mode != mode;
    mode = tb.dut.pulse().mode;
  }
  return changes;
}

TEST(EppmSpeed, HysteresisPreventsChatterAtTheThreshold) {
  EXPECT_LE(mode_changes(25, 40), 1);
  EXPECT_GT(mode_changes(40, 40), 10);  // the same stimulus chatters with no band
}

TEST(EppmSpeed, ForcedModeTakesEffectAtTheWindowEnd) {
  EppmBench tb;
  tb.clock(100);
  select(tb, SpeedModeSelect::kPulse);
  tb.clock(tb.cfg.window.clocks.value() - 101);
  EXPECT_EQ(tb.dut.pulse().mode.value(), static_cast<unsigned>(SpeedMode::kPeriod));
  tb.clock();
  EXPECT_EQ(tb.dut.pulse().mode.value(), static_cast<unsigned>(SpeedMode::kPulse));
}

TEST(EppmSpeed, BackwardSpeedsAreNegativeInBothModes) {
  for (const auto mode : {SpeedModeSelect::kPulse, SpeedModeSelect::kPeriod}) {
    EppmBench tb;
    select(tb, mode);
    QuadratureSource source{-0.001};
    tb.run(source, 3 * tb.cfg.window.clocks.value());
    const auto speed = tb.dut.status(tb.cfg).speed;
    EXPECT_TRUE(speed.valid);
    EXPECT_LT(speed.value.value(), 0);
    const double truth =
        mode == SpeedModeSelect::kPulse ? -0.001 * window_of(tb) : -1.0 / (0.001 * 50);
    EXPECT_LE(std::abs(speed_of(tb) - truth), 1.02);
  }
}

TEST(EppmSpeed, ReversalInsideAPeriodMarksTheSampleInvalid) {
  EppmBench tb;
  select(tb, SpeedModeSelect::kPeriod);
  QuadratureSource source{0.0005};
  tb.run(source, 20'000);  // ~10 edges
  ASSERT_TRUE(tb.dut.status(tb.cfg).speed.valid);
  source.set_rate(-0.0005);
  while (!tb.dut.period().sampled)
    tb.run(source, 1);  // the first edge after the reversal
  EXPECT_FALSE(tb.dut.status(tb.cfg).speed.valid);
  EXPECT_EQ(tb.dut.status(tb.cfg).speed.value.value(), 0);
  tb.run(source, 1);
  while (!tb.dut.period().sampled)
    tb.run(source, 1);
  EXPECT_TRUE(tb.dut.status(tb.cfg).speed.valid);
  EXPECT_LT(tb.dut.status(tb.cfg).speed.value.value(), 0);
}

TEST(EppmSpeed, StallReadsZeroAfterExactlyStallTicks) {
  EppmBench tb;
  tb.cfg.stall_ticks.ticks = UInt<23>{1000};
  select(tb, SpeedModeSelect::kPeriod);
  QuadratureSource source{0.01};
  tb.run(source, 10'000);
  source.set_rate(0.0);
  // Wait for the last edge to reach the meter, then count ticks.
  std::uint64_t since_edge = 0;
  while (since_edge < 2 * tb.latency() + 100) {
    tb.run(source, 1);
    since_edge = tb.dut.period().sampled ? 0 : since_edge + 1;
  }
  ASSERT_FALSE(tb.dut.status(tb.cfg).speed.stalled);
  while (tb.dut.period().count.value() < 999)
    tb.clock();
  EXPECT_FALSE(tb.dut.status(tb.cfg).speed.stalled);
  tb.clock(tb.cfg.prescale.divider.value() + 1);
  const auto speed = tb.dut.status(tb.cfg).speed;
  EXPECT_TRUE(speed.stalled);
  EXPECT_TRUE(speed.valid);
  EXPECT_EQ(speed.value.value(), 0);
  // The first edge after a stall only starts a new measurement.
  source.set_rate(0.01);
  while (!tb.dut.period().sampled)
    tb.run(source, 1);
  EXPECT_FALSE(tb.dut.status(tb.cfg).speed.valid);
  EXPECT_FALSE(tb.dut.status(tb.cfg).speed.stalled);
}

// The speed word as signed edges per second (pulse: edges per window over
// the window; period: the reference rate over the ticks per edge).
double edges_per_second(const EppmBench& tb) {
  const auto speed = tb.dut.status(tb.cfg).speed;
  const double value = static_cast<double>(speed.value.value());
  if (value == 0.0)
    return 0.0;
  if (speed.mode.value() == odoloc::rtl::encoding(SpeedMode::kPulse))
    return value / (window_of(tb) / kClockHz);
  return kClockHz / (static_cast<double>(tb.cfg.prescale.divider.value()) + 1.0) / value;
}

// A moving wheel whose edges come faster than one reference tick apart never
// reads as standing still: the period saturates at one tick, flagged as a
// bound. Field report: prescale 4999 (10 kHz) and an edge every 4000 clocks
// read 0 once in five; the default prescale did the same above 1 M edges/s.
TEST(EppmSpeed, EdgesWithinOneTickReadTheShortestPeriodNotStandstill) {
  struct Case {
    unsigned prescale;
    double edges_per_clock;
  };
  for (const Case c : {Case{4999, 1.0 / 4000}, Case{49, 0.03}, Case{49, -0.03}}) {
    EppmBench tb;
    select(tb, SpeedModeSelect::kPeriod);
    tb.cfg.prescale.divider = UInt<16>{c.prescale};
    QuadratureSource source{c.edges_per_clock};
    tb.run(source, 100'000);
    unsigned bounded = 0;
    for (int i = 0; i < 400'000; ++i) {
      tb.run(source, 1);
      const auto speed = tb.dut.status(tb.cfg).speed;
      ASSERT_TRUE(speed.valid) << i;
      ASSERT_NE(speed.value.value(), 0) << "prescale " << c.prescale << " clock " << i;
      ASSERT_EQ(speed.value.value() > 0, c.edges_per_clock > 0);
      if (tb.dut.period().last.is_zero()) {
        EXPECT_EQ(std::abs(speed.value.value()), 1);
        EXPECT_TRUE(speed.bound);
        ++bounded;
      }
    }
    EXPECT_GT(bounded, 0U) << c.prescale;  // the case happened
  }
}

// After the wheel stops the reading decays toward zero: once the time since
// the last edge exceeds the last period, at most one edge per elapsed time.
// Field report: automatic mode, 500 k edges/s for 15 ms, then the pins freeze:
// 2, 10, 40 and 49 ms later the meter still read the old speed.
TEST(EppmSpeed, AfterAStopTheReadingDecaysWithTheTimeSinceTheLastEdge) {
  for (const double rate : {0.01, -0.01}) {  // 500 k edges/s, both directions
    EppmBench tb;
    QuadratureSource source{rate};
    tb.run(source, 750'000);  // 15 ms
    source.set_rate(0.0);
    const std::int64_t edges_at_stop = source.edges();
    double previous = std::abs(edges_per_second(tb));
    std::uint64_t since_stop = 0;
    for (const double ms : {2.0, 10.0, 40.0, 49.0}) {
      const auto until = static_cast<std::uint64_t>(ms * 1e-3 * kClockHz);
      for (; since_stop < until; ++since_stop) {
        tb.run(source, 1);
        const double now = std::abs(edges_per_second(tb));
        ASSERT_LE(now, previous * (1 + 1e-12) + 1e-9) << "clock " << since_stop;  // never rises
        previous = now;
      }
      ASSERT_EQ(source.edges(), edges_at_stop);
      const auto speed = tb.dut.status(tb.cfg).speed;
      ASSERT_FALSE(speed.stalled) << ms;
      // At most one edge in the time since the last edge (within a tick).
      const double elapsed_s = static_cast<double>(since_stop) / kClockHz;
      EXPECT_LE(std::abs(edges_per_second(tb)), 1.0 / (elapsed_s - 2e-6)) << ms << " ms";
      EXPECT_TRUE(speed.bound) << ms << " ms";
      EXPECT_EQ(speed.value.value() > 0, rate > 0) << ms << " ms";
    }
  }
}

// Over a start, a ramp through the automatic mode switch and a stop, in both
// directions, against the true edge rate: the sign is the motion's, a moving
// wheel never reads zero, and no reading exceeds the fastest true rate of the
// last stall time by more than the quantisation of its mode.
TEST(EppmSpeed, StartRampAndStopTrackTheTrueSpeedInBothDirections) {
  for (const double direction : {1.0, -1.0}) {
    EppmBench tb;
    tb.cfg.stall_ticks.ticks = UInt<23>{20'000};  // 20 ms
    QuadratureSource source;
    const double top = 0.004;              // 200 k edges/s: pulse mode
    const std::uint64_t ramp = 5'000'000;  // 100 ms up, 100 ms down
    // The true rates of the last 20 ms (the stall time: no measurement the
    // meter still shows is older), sampled every 1000 clocks.
    std::deque<double> recent;
    std::uint64_t last_edge = 0;
    for (std::uint64_t k = 0; k < 2 * ramp + 1'500'000; ++k) {
      const double rate = k < ramp       ? top * static_cast<double>(k) / ramp
                          : k < 2 * ramp ? top * static_cast<double>(2 * ramp - k) / ramp
                                         : 0.0;
      source.set_rate(direction * rate);
      const std::int64_t edges_before = source.edges();
      tb.run(source, 1);
      if (source.edges() != edges_before)
        last_edge = k;
      if (k % 1000 != 0)
        continue;
      recent.push_back(rate);
      if (recent.size() > 1000)
        recent.pop_front();
      const double fastest_recent = *std::max_element(recent.begin(), recent.end());
      const auto speed = tb.dut.status(tb.cfg).speed;
      const double read = edges_per_second(tb);
      // A bound after a stop may read up to one edge per time since the last.
      const double fastest_s =
          std::max(fastest_recent * kClockHz, kClockHz / static_cast<double>(k - last_edge + 1));
      if (read != 0.0) {
        ASSERT_EQ(read > 0, direction > 0) << "clock " << k;
      }
      // Pulse: one edge per window; period: the reading is at least one tick.
      const double quantum = speed.mode.value() == odoloc::rtl::encoding(SpeedMode::kPulse)
                                 ? kClockHz / window_of(tb)
                                 : fastest_s * fastest_s * 50e-6 + 1.0;
      ASSERT_LE(std::abs(read), fastest_s + quantum) << "clock " << k;
      // Faster than 2 edges per stall time and past the first periods: moving.
      if (rate * kClockHz > 200 && k > 200'000 && speed.valid) {
        ASSERT_NE(read, 0.0) << "clock " << k << " rate " << rate * kClockHz;
      }
    }
    EXPECT_TRUE(tb.dut.status(tb.cfg).speed.stalled);  // and at rest it stalls
  }
}

TEST(EppmSpeed, PeriodCounterSaturatesAndFlagsOverflow) {
  EppmBench tb;
  tb.cfg.prescale.divider = UInt<16>{0};  // a tick every clock
  tb.cfg.stall_ticks.ticks = UInt<23>{0};
  select(tb, SpeedModeSelect::kPeriod);
  tb.set_pins(0b10);  // one edge arms the measurement
  tb.clock(tb.latency());
  ASSERT_TRUE(tb.dut.period().armed);
  constexpr std::uint64_t kMax = (1U << 23) - 1;
  tb.clock(kMax - 1);
  EXPECT_EQ(tb.dut.period().count.value(), kMax);
  EXPECT_FALSE(tb.dut.period().overflow);
  tb.clock(5);
  EXPECT_EQ(tb.dut.period().count.value(), kMax);
  EXPECT_TRUE(tb.dut.period().overflow);
  // The next edge reads the saturated count: a bound, not a measurement.
  tb.set_pins(0b11);
  tb.clock(tb.latency());
  EXPECT_EQ(tb.dut.period().last.value(), kMax);
  EXPECT_FALSE(tb.dut.status(tb.cfg).speed.valid);
  EXPECT_TRUE(tb.dut.period().overflow);
  tb.clear_flags();
  EXPECT_FALSE(tb.dut.period().overflow);
}

TEST(EppmUnits, SpeedWordConvertsToMetresPerSecond) {
  const odoloc::sw::EncoderGeometry geometry{0.1, 500, 30, 4};
  const SpeedTiming timing;
  // 1 m/s = 1 / (2 pi 0.1 / 60000) edges/s = 95 493 edges/s.
  const double edges_per_s = 1.0 / geometry.metres_per_edge();
  EXPECT_NEAR(edges_per_s, 60000.0 / (2 * M_PI * 0.1), 1e-9);
  EXPECT_NEAR(odoloc::sw::speed_mps(static_cast<std::int32_t>(std::lround(edges_per_s * 1e-3)),
                                    true, geometry, timing),
              1.0, 1.0 / 95.0);
  EXPECT_NEAR(odoloc::sw::speed_mps(-static_cast<std::int32_t>(std::lround(1e6 / edges_per_s)),
                                    false, geometry, timing),
              -1.0, 0.1);
  EXPECT_EQ(odoloc::sw::speed_mps(0, false, geometry, timing), 0.0);
  const auto t = odoloc::sw::switch_thresholds(timing);
  EXPECT_EQ(t.to_period_below, 25U);
  EXPECT_EQ(t.to_pulse_at, 40U);
}

}  // namespace
