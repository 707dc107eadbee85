// Kurian et al.'s odometry as shipped (examples/scenarios/
// kurian-odometry.yaml), through the whole system: the final errors of
// rear-only, front-only and min-select odometry against what the humps and
// the slip put into each set of wheels (raised-cosine arc lengths and the
// slip ratio, computed here; nominal wheels, so nothing else).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "odoloc/sim/system.hpp"
#include "odoloc/world/tricycle.hpp"

namespace {

TEST(KurianOdometry, EachSetOfWheelsCarriesItsOwnOverCountsAndMinSelectDropsThem) {
  const odoloc::sim::BuiltinScenario* file =
      odoloc::sim::find_builtin_scenario("kurian-odometry.yaml");
  ASSERT_NE(file, nullptr);
  odoloc::sim::Scenario scenario = odoloc::sim::parse_scenario(std::string(file->text), file->key);
  const odoloc::world::Disturbances d = scenario.tour.drive.disturbances;
  const double track_m = scenario.tour.drive.geometry.track_m;
  odoloc::sim::LocalisationSystem system(std::move(scenario), {.encoder_period_s = 1.0});
  odoloc::sim::Frame last;
  while (!system.done())
    last = system.step();
  const odoloc::world::Pose truth = last.truth;
  const auto& odometry = last.soc.odometry;
  const double min_select_m = std::hypot(odometry.x_m - truth.x_m, odometry.y_m - truth.y_m);
  const odoloc::board::RunResult& rear = system.reference(odoloc::rtl::MinSelectPolicy::kRearOnly);
  const odoloc::board::RunResult& front =
      system.reference(odoloc::rtl::MinSelectPolicy::kFrontOnly);

  // The over-counts: each hump's arc length beyond its base, per wheel;
  // the slip's ratio times its stretch.
  ASSERT_EQ(d.bumps.size(), 4U);
  ASSERT_EQ(d.slips.size(), 1U);
  const double hump_m = odoloc::world::bump_extra_length(d.bumps[0].height_m, d.bumps[0].length_m);
  const double slip_m = d.slips[0].ratio * (d.slips[0].end_m - d.slips[0].start_m);
  std::printf(
      "hump %.2f mm, slip %.1f mm; final errors: rear-only %.1f mm %.3f deg, front-only "
      "%.1f mm, min-select %.1f mm\n",
      hump_m * 1e3, slip_m * 1e3, rear.position_error_m * 1e3,
      rear.heading_error_rad * 180 / std::numbers::pi, front.position_error_m * 1e3,
      min_select_m * 1e3);
  // Rear-only: the hump under one rear wheel (Fig. 4b) turns the heading by
  // hump / track (the one under both, 4a, adds distance only).
  EXPECT_NEAR(std::abs(rear.heading_error_rad), hump_m / track_m, 0.1 * hump_m / track_m);
  // Front-only: the front hump's (4c) over-count and the slip's, each along
  // the path where it happens. A side of the square is (6 - 2 r) +
  // (pi/2) r = 5.63 m of odometer (r = L / tan 30 deg = 0.866 m): the hump
  // at 15 m is on the third side's straight, the slip at 19 to 20 m on the
  // fourth's, at right angles, so the two add as hypot.
  EXPECT_NEAR(front.position_error_m, std::hypot(slip_m, hump_m), 1e-3);
  // Min-select keeps neither set's over-counts: below the smallest of them.
  EXPECT_LT(min_select_m, 0.2 * front.position_error_m);
  EXPECT_LT(min_select_m, 0.2 * rear.position_error_m);
  EXPECT_LT(min_select_m, 2 * hump_m);
}

}  // namespace
