// The world's fast-forward contract: a source that says its pins hold for h
// clocks must produce exactly those levels when ticked clock by clock, and
// its skip(h) must leave it where h ticks would. Checked against plain
// ticking: QuadratureSource's next-edge prediction over random rates and
// phases (both directions, up to one edge per clock, standing still), and
// the TricycleSimulator's hold_ticks/skip over drives with every disturbance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "odoloc/world/quadrature_source.hpp"
#include "odoloc/world/scenarios.hpp"
#include "odoloc/world/tricycle.hpp"

namespace {

using odoloc::world::QuadratureSource;

TEST(PinHold, QuadratureSourcePredictsItsNextEdge) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> exponent(-9.0, 0.0);
  for (int trial = 0; trial < 3000; ++trial) {
    const double sign = rng() % 2 ? 1.0 : -1.0;
    const double rate = trial < 10 ? sign : sign * std::pow(10.0, exponent(rng));
    QuadratureSource source(rate);
    for (std::uint64_t k = rng() % 1000; k > 0; --k)  // a random phase
      source.tick();
    const std::uint64_t next = source.ticks_to_next_edge();
    ASSERT_GE(next, 1U);
    const std::int64_t edges = source.edges();
    // By skipping: the edge comes on tick `next`, not before.
    QuadratureSource jumped = source;
    jumped.skip(next - 1);
    ASSERT_EQ(jumped.edges(), edges) << "rate " << rate;
    jumped.tick();
    ASSERT_NE(jumped.edges(), edges) << "rate " << rate;
    // By ticking (up to 100k ticks): the same levels until then, and skip()
    // lands where ticking does.
    const std::uint64_t checked = std::min<std::uint64_t>(next - 1, 100'000);
    QuadratureSource skipped = source;
    for (std::uint64_t k = 0; k < checked; ++k)
      ASSERT_EQ(source.tick(), skipped.level()) << "rate " << rate << ", tick " << k;
    skipped.skip(checked);
    EXPECT_EQ(skipped.edges(), source.edges()) << "rate " << rate;
    EXPECT_EQ(skipped.level(), source.level()) << "rate " << rate;
  }
  EXPECT_EQ(QuadratureSource(0.0).ticks_to_next_edge(), QuadratureSource::kNever);
}

TEST(PinHold, TricycleHoldsItsLevelsAsTicked) {
  using odoloc::world::BumpCase;
  for (const BumpCase bump :
       {BumpCase::kNone, BumpCase::kBothRear, BumpCase::kOneRear, BumpCase::kFront}) {
    const odoloc::world::Scenario s = odoloc::world::bump_scenario(bump, 0.4, -2.0);
    odoloc::world::Options options;
    options.start = s.start;
    odoloc::world::TricycleSimulator ticked(s.geometry, s.path, s.disturbances, options);
    odoloc::world::TricycleSimulator held(s.geometry, s.path, s.disturbances, options);
    std::uint64_t skipped = 0;
    while (!held.done()) {
      const auto levels = held.tick();
      ASSERT_EQ(ticked.tick(), levels) << "clock " << held.clock();
      const std::uint64_t hold = held.hold_ticks();
      for (std::uint64_t k = 0; k < hold; ++k)
        ASSERT_EQ(ticked.tick(), levels) << "clock " << ticked.clock() << " in a hold of " << hold;
      held.skip(hold);
      skipped += hold;
    }
    EXPECT_TRUE(ticked.done());
    EXPECT_EQ(held.clock(), ticked.clock());
    EXPECT_EQ(held.true_edges(), ticked.true_edges());
    EXPECT_EQ(held.pose().pose.x_m, ticked.pose().pose.x_m);
    EXPECT_GT(skipped, held.clock() / 2) << odoloc::world::name(bump);
  }
}

}  // namespace
