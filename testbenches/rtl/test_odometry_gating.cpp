// Activity gating of the odometry fabric is invisible: a fabric stepped with
// Gating::kOn matches one stepped with Gating::kOff, every register of every
// block after every clock, under moving encoders, frequent updates and random
// set-pose, clear-flags and reset strobes.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "odometry_bench.hpp"

namespace {

using odoloc::rtl::Gating;
using odoloc::rtl::kWheelCount;
using odoloc::rtl::OdometryFabric;
using odoloc::rtl::UInt;
using odoloc::rtl::Wheel;

void expect_same(const OdometryFabric& gated, const OdometryFabric& full, std::uint64_t clock) {
  for (std::size_t w = 0; w < kWheelCount; ++w) {
    const auto& g = gated.encoders().eppm(static_cast<Wheel>(w));
    const auto& f = full.encoders().eppm(static_cast<Wheel>(w));
    ASSERT_EQ(g.conditioner(), f.conditioner()) << "clock " << clock << " wheel " << w;
    ASSERT_EQ(g.decoder(), f.decoder()) << "clock " << clock << " wheel " << w;
    ASSERT_EQ(g.counter(), f.counter()) << "clock " << clock << " wheel " << w;
    ASSERT_EQ(g.timebase(), f.timebase()) << "clock " << clock << " wheel " << w;
    ASSERT_EQ(g.pulse(), f.pulse()) << "clock " << clock << " wheel " << w;
    ASSERT_EQ(g.period(), f.period()) << "clock " << clock << " wheel " << w;
  }
  ASSERT_EQ(gated.sequencer(), full.sequencer()) << "clock " << clock;
  ASSERT_EQ(gated.cordic(), full.cordic()) << "clock " << clock;
  ASSERT_EQ(gated.rear(), full.rear()) << "clock " << clock;
  ASSERT_EQ(gated.front(), full.front()) << "clock " << clock;
  ASSERT_EQ(gated.select(), full.select()) << "clock " << clock;
  ASSERT_EQ(gated.pose(), full.pose()) << "clock " << clock;
}

TEST(OdometryGating, GatedAndUngatedAgreeEveryClock) {
  std::mt19937_64 rng(2026);
  odoloc::tb::OdometryBench bench;  // its configuration, two fabrics of our own
  auto cfg = bench.cfg;
  cfg.odometry.update_clocks = UInt<16>{300};
  OdometryFabric gated, full;
  OdometryFabric::Inputs in{};
  std::array<odoloc::sim::QuadratureSource, kWheelCount> sources{};
  std::uniform_real_distribution<double> rate(-0.02, 0.02);
  std::uint64_t updates = 0, last = 0;
  for (std::uint64_t clock = 0; clock < 600'000; ++clock) {
    if (clock % 20'000 == 0) {
      for (auto& s : sources)
        s.set_rate(rng() % 4 == 0 ? 0.0 : rate(rng));
    }
    for (std::size_t w = 0; w < kWheelCount; ++w)
      in.pins[w] = sources[w].tick();
    const auto strobe = [&](unsigned one_in) { return UInt<1>::truncate(rng() % one_in == 0); };
    in.set_pose = strobe(50'000);
    in.pose = {odoloc::rtl::SInt<64>::truncate(static_cast<std::int64_t>(rng())),
               odoloc::rtl::SInt<64>::truncate(static_cast<std::int64_t>(rng())),
               UInt<40>::truncate(rng())};
    for (auto& clear : in.eppm_clear)
      clear = {strobe(100'000), strobe(100'000), strobe(100'000), strobe(100'000)};
    in.odometry_clear = {strobe(60'000), strobe(60'000)};
    in.reset = strobe(200'000);
    gated.step<Gating::kOn>(in, cfg);
    full.step<Gating::kOff>(in, cfg);
    expect_same(gated, full, clock);
    if (HasFatalFailure())
      return;
    const std::uint64_t now = full.sequencer().updates.value();
    updates += now > last ? now - last : 0;
    last = now;
  }
  EXPECT_GT(updates, 100U);  // the comparison covered many complete updates
}

}  // namespace
