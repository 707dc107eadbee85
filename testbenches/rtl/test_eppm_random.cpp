// Long seeded random runs of one EPPM against the untimed reference
// (support/eppm_reference.hpp), compared at every clock: count, wrap flags,
// error count, phase error and direction; latched increments; pulse and period
// samples; the speed word. Plus constant-rate runs against the QuadratureSource
// ground truth.
//
// ODOLOC_TEST_SCALE multiplies the clock budgets (e.g. 0.1 for a quick run).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <ostream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "eppm_reference.hpp"
#include "issue_stimulus.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/rtl/eppm.hpp"
#include "odoloc/world/quadrature_source.hpp"
#include "test_scale.hpp"

namespace {

using odoloc::tb::scaled;

using odoloc::rtl::Eppm;
using odoloc::rtl::EppmConfig;
using odoloc::rtl::EppmFlagClear;
using odoloc::rtl::EppmInputs;
using odoloc::rtl::UInt;
using odoloc::world::QuadratureSource;

EppmInputs pins_input(unsigned ab) {
  EppmInputs in;
  in.a = UInt<1>::truncate(ab >> 1);
  in.b = UInt<1>::truncate(ab);
  return in;
}

// kDisturbed: jittered walk with reversals, glitches and illegal steps, with
// latch_clear and clear_flags strobes. The runs step every 1-2 clocks and are
// never latched: kRunForward/kRunBackward wrap the 20-bit count,
// kIllegalRun (A and B always together) saturates the error counter.
enum class Walk : std::uint8_t { kDisturbed, kRunForward, kRunBackward, kIllegalRun };

// A/B pin levels per step, A in bit 1.
std::vector<std::uint8_t> random_walk(std::mt19937_64& rng, std::uint64_t clocks,
                                      std::uint64_t filter_len, Walk walk) {
  constexpr std::array<std::uint8_t, 4> kAbOfPhase = {0b00, 0b10, 0b11, 0b01};
  const auto below = [&](std::uint64_t n) { return rng() % n; };
  std::vector<std::uint8_t> pins;
  pins.reserve(clocks);
  const auto hold = [&](unsigned ab, std::uint64_t n) {
    pins.insert(pins.end(), std::min(n, clocks - pins.size()), static_cast<std::uint8_t>(ab));
  };
  unsigned phase = 0;
  // Phase increment mod 4: 1 forward, 3 backward, 2 both pins at once.
  unsigned dir = walk == Walk::kRunBackward ? 3 : walk == Walk::kIllegalRun ? 2 : 1;
  while (pins.size() < clocks) {
    if (walk != Walk::kDisturbed) {
      phase = (phase + dir) % 4;
      hold(kAbOfPhase[phase], 1 + below(2));
      continue;
    }
    const std::uint64_t action = below(1000);
    if (action < 15) {  // a pulse on one channel, from 1 to N+1 clocks: some pass the filter
      hold(kAbOfPhase[phase] ^ (1U << below(2)), 1 + below(filter_len + 1));
    } else if (action < 20) {  // A and B change together: illegal
      phase = (phase + 2) % 4;
    } else {
      if (action < 40)
        dir = 4 - dir;  // reversal
      phase = (phase + dir) % 4;
    }
    // Gaps around the filter length (channel runs shorter than N are
    // filtered out), sometimes longer, rarely long enough to stall.
    const std::uint64_t gap_kind = below(1000);
    const std::uint64_t max_gap = gap_kind < 800 ? 2 * filter_len + 1 : gap_kind < 997 ? 64 : 4000;
    hold(kAbOfPhase[phase], 1 + below(max_gap));
  }
  return pins;
}

// Ascending strobe steps, sometimes on consecutive clocks.
std::vector<std::uint64_t> random_strobes(std::mt19937_64& rng, std::uint64_t clocks,
                                          std::uint64_t mean_gap) {
  std::vector<std::uint64_t> steps;
  for (std::uint64_t k = rng() % mean_gap; k < clocks;
       k += rng() % 20 == 0 ? 1 : 1 + rng() % (2 * mean_gap)) {
    steps.push_back(k);
  }
  return steps;
}

struct RandomCase {
  std::uint64_t seed;
  unsigned filter_clocks, decode_mode, speed_mode_select;
  std::uint32_t window_clocks;
  std::uint16_t prescale;
  std::uint32_t stall_ticks, to_period_below, to_pulse_at;
  Walk walk;
  std::uint64_t clocks;

  [[nodiscard]] EppmConfig config() const {
    EppmConfig cfg;
    cfg.cfg.filter_clocks = UInt<8>{filter_clocks};
    cfg.cfg.decode_mode = UInt<2>{decode_mode};
    cfg.cfg.speed_mode_select = UInt<2>{speed_mode_select};
    cfg.window.clocks = UInt<23>{window_clocks};
    cfg.prescale.divider = UInt<16>{prescale};
    cfg.stall_ticks.ticks = UInt<23>{stall_ticks};
    cfg.to_period_below.edges = UInt<23>{to_period_below};
    cfg.to_pulse_at.edges = UInt<23>{to_pulse_at};
    return cfg;
  }
};

void PrintTo(const RandomCase& c, std::ostream* os) {
  *os << "seed " << c.seed << " filter " << c.filter_clocks << " decode " << c.decode_mode
      << " select " << c.speed_mode_select << " window " << c.window_clocks << " prescale "
      << c.prescale << " stall " << c.stall_ticks << " thresholds " << c.to_period_below << "/"
      << c.to_pulse_at << " walk " << static_cast<int>(c.walk);
}

// Filter lengths around the reset value, all decode and select codes, windows
// of 1 (also given as 0) to 65 536 clocks, prescalers from 1 to 50 clocks.
const std::vector<RandomCase> kCases = {
    // seed, filter, decode, select, window, prescale, stall, thresholds, walk, clocks
    {1, 0, 0, 0, 1000, 0, 0, 25, 40, Walk::kDisturbed, 2'000'000},
    {2, 1, 0, 0, 37, 3, 40, 2, 4, Walk::kDisturbed, 2'000'000},
    {3, 2, 1, 1, 5000, 49, 20, 25, 40, Walk::kDisturbed, 2'000'000},
    {4, 3, 2, 0, 50'000, 49, 50'000, 25, 40, Walk::kDisturbed, 2'000'000},
    {5, 7, 3, 2, 1, 1, 5, 25, 40, Walk::kDisturbed, 600'000},
    {6, 7, 1, 3, 0, 0, 8, 1, 1, Walk::kDisturbed, 600'000},
    {7, 3, 2, 3, 2000, 5, 0, 3, 6, Walk::kDisturbed, 2'000'000},
    {8, 0, 0, 0, 100'000, 49, 50'000, 25, 40, Walk::kRunForward, 900'000},
    {9, 2, 3, 1, 65'536, 7, 0, 25, 40, Walk::kRunBackward, 900'000},
    {10, 0, 0, 0, 1000, 49, 0, 25, 40, Walk::kIllegalRun, 300'000},
};

class EppmRandom : public testing::TestWithParam<RandomCase> {};

TEST_P(EppmRandom, MatchesReferenceEveryClock) {
  using odoloc::tb::Motion;
  const RandomCase& c = GetParam();
  const EppmConfig cfg = c.config();
  std::mt19937_64 rng(c.seed);
  // A run must stay long enough to reach the wrap or the saturation.
  const std::uint64_t clocks = c.walk == Walk::kDisturbed ? scaled(c.clocks) : c.clocks;
  const auto pins = random_walk(rng, clocks, std::max(c.filter_clocks, 1U), c.walk);
  const auto moves = odoloc::tb::transitions(pins, odoloc::tb::EppmRefConfig(cfg));
  std::vector<std::uint64_t> latch_steps;
  std::vector<std::uint64_t> clear_steps;
  if (c.walk == Walk::kDisturbed) {
    latch_steps = random_strobes(rng, clocks, 2000);
    // clear_flags at random, and on a quarter of the illegal transitions: the
    // event must set its flag again in the clearing clock.
    clear_steps = random_strobes(rng, clocks, 5000);
    for (const auto& t : moves) {
      if (t.motion == Motion::kIllegal && rng() % 4 == 0)
        clear_steps.push_back(t.step);
    }
    std::sort(clear_steps.begin(), clear_steps.end());
    clear_steps.erase(std::unique(clear_steps.begin(), clear_steps.end()), clear_steps.end());
  } else {
    clear_steps = random_strobes(rng, clocks, 50'000);  // rare, so the sticky flags get set
  }
  const auto exp = odoloc::tb::expect_eppm(pins, latch_steps, clear_steps, cfg);
  const std::uint64_t window = exp.cfg.window;

  Eppm dut;
  auto latch = latch_steps.begin();
  auto clear = clear_steps.begin();
  auto latched = exp.latched.begin();
  auto edge = exp.edges.begin();
  for (std::uint64_t k = 0; k < clocks; ++k) {
    EppmInputs in = pins_input(pins[k]);
    const bool latching = latch != latch_steps.end() && *latch == k;
    const bool clearing = clear != clear_steps.end() && *clear == k;
    in.latch_clear = UInt<1>::truncate(latching);
    const UInt<1> clearing_bit = UInt<1>::truncate(clearing);
    in.clear.status = {.phase_error = clearing_bit,
                       .carry = clearing_bit,
                       .borrow = clearing_bit,
                       .period_overflow = clearing_bit};
    if (latching)
      ++latch;
    if (clearing)
      ++clear;
    dut.step(in, cfg);
    const auto where = [&] {
      return "seed " + std::to_string(c.seed) + " step " + std::to_string(k);
    };

    const auto& counter = dut.counter();
    const auto& decoder = dut.decoder();
    const auto& state = exp.after[k];
    ASSERT_EQ(std::tuple(counter.count.value(), counter.carry.value(), counter.borrow.value(),
                         decoder.error_count.value(), decoder.phase_error.value(),
                         decoder.direction.value()),
              std::tuple(std::int64_t{state.count}, state.carry, state.borrow,
                         std::uint64_t{state.error_count}, state.phase_error, state.forward))
        << where() << " (count, carry, borrow, error_count, phase_error, direction)";
    if (latching) {
      ASSERT_EQ(counter.latched.value(), *latched++) << where() << " (latched)";
    }

    const auto& pulse = dut.pulse();
    const bool window_end = (k + 1) % window == 0;
    ASSERT_EQ(pulse.sampled.value(), window_end) << where() << " (pulse.sampled)";
    if (window_end) {
      const auto& w = exp.windows[(k + 1) / window - 1];
      ASSERT_EQ(std::tuple(pulse.last.value(), pulse.mode.value()),
                std::tuple(w.edges, w.pulse_mode))
          << where() << " (pulse.last, mode)";
    }

    const auto& period = dut.period();
    const bool edge_now = edge != exp.edges.end() && edge->step == k;
    ASSERT_EQ(period.sampled.value(), edge_now) << where() << " (period.sampled)";
    if (edge_now) {
      ASSERT_EQ(std::tuple(period.last.value(), period.valid.value(), period.last_dir.value()),
                std::tuple(edge->ticks, edge->valid, edge->forward))
          << where() << " (period.last, valid, last_dir)";
      ++edge;
    }

    const auto speed = dut.status(cfg).speed;
    const auto want = exp.speed_after(k);
    ASSERT_EQ(std::tuple(speed.value.value(), speed.mode.value(), speed.valid.value(),
                         speed.stalled.value(), speed.bound.value()),
              std::tuple(want.value, want.pulse_mode, want.valid, want.stalled, want.bound))
        << where() << " (speed value, mode, valid, stalled, bound)";
  }
  // Non-vacuity: a full-length run reaches what it was designed for.
  const auto ever = [&](auto pred) {
    return std::any_of(exp.after.begin(), exp.after.end(), pred);
  };
  switch (c.walk) {
    case Walk::kDisturbed:
      if (clocks == c.clocks) {
        EXPECT_GT(std::count_if(moves.begin(), moves.end(),
                                [](const auto& t) { return t.motion == Motion::kIllegal; }),
                  10);
        EXPECT_GT(exp.latched.size(), 10U);
      }
      break;
    case Walk::kIllegalRun:
      EXPECT_TRUE(ever([](const auto& s) { return s.error_count == 65535; }));
      break;
    default:
      EXPECT_TRUE(ever([](const auto& s) { return s.carry || s.borrow; }));
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, EppmRandom, testing::ValuesIn(kCases), [](const auto& param_info) {
  return "seed" + std::to_string(param_info.param.seed);
});

// Ground truth of a constant-rate encoder: x4 edges e -> x2 counts the A
// edges (phase boundaries 0|1 and 2|3), x1 the 0|1 boundary only.
std::int64_t floor_div(std::int64_t a, std::int64_t positive) {
  return (a >= 0 ? a : a - (positive - 1)) / positive;
}
std::int64_t decoded_edges(std::int64_t x4_edges, unsigned decode_mode) {
  switch (decode_mode) {
    case 1:
      return floor_div(x4_edges + 1, 2);
    case 2:
      return floor_div(x4_edges + 3, 4);
    default:
      return x4_edges;
  }
}

// Undisturbed constant rates up to the filter's limit (each channel level
// lasts 2/rate clocks >= N): the count after step k equals the source's edges
// after step k-(N+2), i.e. latency N+3 clocks counting the sampling clock.
TEST(EppmRandom, ConstantRateCountsEqualSourceEdges) {
  const std::uint64_t clocks = scaled(20'000);
  for (const unsigned filter_clocks : {0U, 1U, 2U, 3U, 7U}) {
    const unsigned n = std::max(filter_clocks, 1U);
    const double max_rate = 0.99 * std::min(1.0, 2.0 / n);
    for (const double rate : {max_rate, -0.37 / n, 0.0123}) {
      for (const unsigned decode_mode : {0U, 1U, 2U}) {
        EppmConfig cfg;
        cfg.cfg.filter_clocks = UInt<8>{filter_clocks};
        cfg.cfg.decode_mode = UInt<2>{decode_mode};
        QuadratureSource source(rate);
        Eppm dut;
        std::vector<std::int64_t> source_edges;  // after each step
        for (std::uint64_t k = 0; k < clocks; ++k) {
          dut.step(
              pins_input(static_cast<unsigned>(odoloc::board::encoder_pins(source.tick()).value())),
              cfg);
          source_edges.push_back(source.edges());
          const std::int64_t want =
              k < n + 2 ? 0 : decoded_edges(source_edges[k - n - 2], decode_mode);
          ASSERT_EQ(dut.count().value(), want) << "filter " << filter_clocks << " rate " << rate
                                               << " decode " << decode_mode << " step " << k;
        }
        EXPECT_EQ(dut.decoder().error_count.value(), 0U);
      }
    }
  }
}

// The benchmarks' event-scheduled stimulus gives, every clock, the pins of
// four sources ticked every clock at its rates (three steering reversals).
TEST(EppmRandom, BenchmarkStimulusIsItsSourcesTickedEveryClock) {
  using odoloc::tb::IssueStimulus;
  IssueStimulus stimulus;
  std::array<QuadratureSource, 4> sources;
  for (std::uint64_t clock = 0; clock < 4 * IssueStimulus::kSteeringReversalClocks; ++clock) {
    const IssueStimulus::Pins before = stimulus.pins();
    const bool changed = stimulus.tick();
    for (std::size_t w = 0; w < sources.size(); ++w) {
      sources[w].set_rate(IssueStimulus::rate(w, clock));
      const auto pins = odoloc::board::encoder_pins(sources[w].tick());
      ASSERT_EQ(stimulus.pins()[w], pins) << "encoder " << w << ", clock " << clock;
    }
    ASSERT_EQ(changed, stimulus.pins() != before) << "clock " << clock;
  }
  // 5.24 ms at 50 k, 20 k, 125 k edges/s; the steering encoder back at 0.
  EXPECT_EQ(sources[0].edges(), 262);
  EXPECT_EQ(sources[1].edges(), 104);
  EXPECT_EQ(sources[2].edges(), 655);
  EXPECT_EQ(sources[3].edges(), 0);
}

}  // namespace
