// Activity gating is invisible: an EPPM stepped with Gating::kOn, and one
// switching between kOn and kOff in runs, match one stepped with
// Gating::kOff register for register, clock for clock, under random pins,
// strobes, resets and configuration changes; and every leaf
// block keeps its contract "idle(in) implies eval(in) == regs()".
//
// ODOLOC_TEST_SCALE multiplies the clock budgets (e.g. 0.1 for a quick run).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "idle_contract.hpp"
#include "odoloc/rtl/eppm.hpp"
#include "test_scale.hpp"

namespace {

using odoloc::tb::scaled;

using odoloc::rtl::Eppm;
using odoloc::rtl::EppmConfig;
using odoloc::rtl::EppmInputs;
using odoloc::rtl::Gating;
using InputConditioner = odoloc::rtl::QuadratureConditioner;
using odoloc::rtl::PeriodMeter;
using odoloc::rtl::PositionCounter;
using odoloc::rtl::PulseMeter;
using odoloc::rtl::QuadratureDecoder;
using odoloc::rtl::SInt;
using odoloc::rtl::SpeedTimebase;
using odoloc::rtl::UInt;
using odoloc::tb::check_idle_contract;
using odoloc::tb::one_in;
using odoloc::tb::pick;
using odoloc::tb::random_sint;
using odoloc::tb::random_uint;
using odoloc::tb::Rng;

// Short windows and prescalers keep the full path busy, long ones let the
// settled fast path run for thousands of clocks.
EppmConfig random_config(Rng& rng) {
  EppmConfig cfg;
  cfg.cfg.filter_clocks = one_in(rng, 4) ? random_uint<8>(rng) : UInt<8>::truncate(rng() % 8);
  cfg.cfg.decode_mode = random_uint<2>(rng);
  cfg.cfg.speed_mode_select = random_uint<2>(rng);
  cfg.window.clocks = pick<23>(rng, std::array<std::uint32_t, 7>{0, 1, 2, 7, 100, 1000, 50'000});
  cfg.prescale.divider = pick<16>(rng, std::array<std::uint32_t, 5>{0, 1, 3, 49, 999});
  cfg.to_period_below.edges = UInt<23>::truncate(rng() % 40);
  cfg.to_pulse_at.edges = UInt<23>::truncate(rng() % 60);
  cfg.stall_ticks.ticks = pick<23>(rng, std::array<std::uint32_t, 5>{0, 1, 3, 50, 50'000});
  return cfg;
}

// Rewrites a random subset of the fields.
void change_config(Rng& rng, EppmConfig& cfg) {
  const EppmConfig fresh = random_config(rng);
  const auto maybe = [&rng](auto& field, auto value) {
    if (one_in(rng, 3))
      field = value;
  };
  maybe(cfg.cfg.filter_clocks, fresh.cfg.filter_clocks);
  maybe(cfg.cfg.decode_mode, fresh.cfg.decode_mode);
  maybe(cfg.cfg.speed_mode_select, fresh.cfg.speed_mode_select);
  maybe(cfg.window.clocks, fresh.window.clocks);
  maybe(cfg.prescale.divider, fresh.prescale.divider);
  maybe(cfg.to_period_below.edges, fresh.to_period_below.edges);
  maybe(cfg.to_pulse_at.edges, fresh.to_pulse_at.edges);
  maybe(cfg.stall_ticks.ticks, fresh.stall_ticks.ticks);
}

TEST(EppmGating, GatedAndUngatedAgreeEveryClock) {
  const std::uint64_t clocks_per_seed = scaled(1'000'000);
  for (const std::uint64_t seed : {11U, 12U, 13U, 14U}) {
    Rng rng(seed);
    Eppm gated;
    Eppm ungated;
    Eppm mixed;  // the gating's bookkeeping survives ungated runs
    bool mixed_gated = true;
    EppmConfig cfg = random_config(rng);
    bool busy = false;
    unsigned pins = 0;
    std::uint64_t quiet_clocks = 0;  // clocks that changed nothing but timebase and period
    for (std::uint64_t k = 0; k < clocks_per_seed; ++k) {
      if (one_in(rng, 10'000))
        change_config(rng, cfg);
      if (one_in(rng, 3000))
        busy = !busy;
      if (one_in(rng, busy ? 3 : 3000))
        pins ^= one_in(rng, 10) ? 0b11U : 1U << (rng() % 2);
      EppmInputs in;
      in.a = UInt<1>::truncate(pins >> 1);
      in.b = UInt<1>::truncate(pins);
      in.latch_clear = UInt<1>::truncate(one_in(rng, 500));
      // Each flag's clear on its own, so the gating sees every combination.
      const auto clear = [&] { return UInt<1>::truncate(one_in(rng, 2000)); };
      in.clear = {clear(), clear(), clear(), clear()};
      in.reset = UInt<1>::truncate(one_in(rng, 50'000));

      const auto before =
          std::tuple(ungated.conditioner(), ungated.decoder(), ungated.counter(), ungated.pulse());
      gated.step<Gating::kOn>(in, cfg);
      ungated.step<Gating::kOff>(in, cfg);
      if (one_in(rng, 5000))
        mixed_gated = !mixed_gated;
      if (mixed_gated)
        mixed.step<Gating::kOn>(in, cfg);
      else
        mixed.step<Gating::kOff>(in, cfg);
      if (before == std::tuple(ungated.conditioner(), ungated.decoder(), ungated.counter(),
                               ungated.pulse())) {
        ++quiet_clocks;
      }
      const auto same = [&](const Eppm& e) {
        return e.conditioner() == ungated.conditioner() && e.decoder() == ungated.decoder() &&
               e.counter() == ungated.counter() && e.timebase() == ungated.timebase() &&
               e.pulse() == ungated.pulse() && e.period() == ungated.period() &&
               e.status(cfg).speed == ungated.status(cfg).speed;
      };
      ASSERT_TRUE(same(gated)) << "seed " << seed << " step " << k << ": "
                               << odoloc::tb::first_difference(gated, ungated);
      ASSERT_TRUE(same(mixed)) << "seed " << seed << " step " << k << ", mixed gating: "
                               << odoloc::tb::first_difference(mixed, ungated);
    }
    EXPECT_GT(quiet_clocks, clocks_per_seed / 4) << "seed " << seed << ": too little gating";
  }
}

// Inputs mostly hold their value or stay quiet, so idle clocks are common.
SInt<2> random_step(Rng& rng) {
  return SInt<2>::truncate(one_in(rng, 4) ? (rng() % 2 == 0 ? 1 : -1) : 0);
}

TEST(LeafIdleContract, InputConditioner) {
  UInt<2> pins;
  const double idle_share = check_idle_contract<InputConditioner>(
      21,
      [](Rng& rng) {
        return InputConditioner::Regs{random_uint<2>(rng),
                                      random_uint<2>(rng),
                                      random_uint<2>(rng),
                                      {random_uint<8>(rng), random_uint<8>(rng)}};
      },
      [&pins](Rng& rng) {
        if (one_in(rng, 8))
          pins = random_uint<2>(rng);
        return InputConditioner::In{.pins = pins,
                                    .filter_clocks = UInt<8>::truncate(rng() % 5),
                                    .reset = UInt<1>::truncate(one_in(rng, 100))};
      });
  EXPECT_GT(idle_share, 0.05);
}

TEST(LeafIdleContract, QuadratureDecoder) {
  UInt<2> filtered;
  const double idle_share = check_idle_contract<QuadratureDecoder>(
      22,
      [](Rng& rng) {
        return QuadratureDecoder::Regs{random_uint<2>(rng), random_uint<1>(rng),
                                       random_uint<1>(rng), random_uint<16>(rng)};
      },
      [&filtered](Rng& rng) {
        if (one_in(rng, 4))
          filtered = random_uint<2>(rng);
        return QuadratureDecoder::In{.filtered = filtered,
                                     .clear_phase_error = UInt<1>::truncate(one_in(rng, 20)),
                                     .reset = UInt<1>::truncate(one_in(rng, 100))};
      });
  EXPECT_GT(idle_share, 0.05);
}

TEST(LeafIdleContract, PositionCounter) {
  const double idle_share = check_idle_contract<PositionCounter>(
      23,
      [](Rng& rng) {
        return PositionCounter::Regs{random_sint<20>(rng), random_sint<20>(rng),
                                     random_uint<1>(rng), random_uint<1>(rng)};
      },
      [](Rng& rng) {
        return PositionCounter::In{.step = random_step(rng),
                                   .latch_clear = UInt<1>::truncate(one_in(rng, 20)),
                                   .clear_carry = UInt<1>::truncate(one_in(rng, 40)),
                                   .clear_borrow = UInt<1>::truncate(one_in(rng, 40)),
                                   .reset = UInt<1>::truncate(one_in(rng, 100))};
      });
  EXPECT_GT(idle_share, 0.05);
}

// The timebase counts every clock (idle() is always false): checked for
// completeness, no idle clocks to expect.
TEST(LeafIdleContract, SpeedTimebase) {
  check_idle_contract<SpeedTimebase>(
      24,
      [](Rng& rng) {
        return SpeedTimebase::Regs{random_uint<23>(rng), random_uint<16>(rng)};
      },
      [](Rng& rng) {
        return SpeedTimebase::In{.window_clocks = UInt<23>::truncate(rng() % 100),
                                 .prescale = UInt<16>::truncate(rng() % 10),
                                 .reset = UInt<1>::truncate(one_in(rng, 100))};
      });
}

TEST(LeafIdleContract, PulseMeter) {
  const double idle_share = check_idle_contract<PulseMeter>(
      25,
      [](Rng& rng) {
        return PulseMeter::Regs{random_sint<24>(rng), random_sint<24>(rng), random_uint<1>(rng),
                                random_uint<1>(rng)};
      },
      [](Rng& rng) {
        return PulseMeter::In{.step = random_step(rng),
                              .window_end = one_in(rng, 8),
                              .select = random_uint<2>(rng),
                              .to_period_below = UInt<23>::truncate(rng() % 40),
                              .to_pulse_at = UInt<23>::truncate(rng() % 60),
                              .reset = UInt<1>::truncate(one_in(rng, 100))};
      });
  EXPECT_GT(idle_share, 0.05);
}

TEST(LeafIdleContract, PeriodMeter) {
  const double idle_share = check_idle_contract<PeriodMeter>(
      26,
      [](Rng& rng) {
        return PeriodMeter::Regs{random_uint<23>(rng), random_uint<23>(rng), random_uint<1>(rng),
                                 random_uint<1>(rng),  random_uint<1>(rng),  random_uint<1>(rng),
                                 random_uint<1>(rng)};
      },
      [](Rng& rng) {
        return PeriodMeter::In{.step = random_step(rng),
                               .tick = one_in(rng, 4),
                               .stall_ticks = random_uint<23>(rng),
                               .clear_overflow = UInt<1>::truncate(one_in(rng, 20)),
                               .reset = UInt<1>::truncate(one_in(rng, 100))};
      });
  EXPECT_GT(idle_share, 0.05);
}

}  // namespace
