// Thamma's system as shipped (examples/scenarios/thamma-room.yaml), the
// whole system: four RF-triggered stations, the head and tail boxes, the
// capture unit at 25 MHz, each cycle's pose fused as two body points. The
// bounds come from the protocol and the poses' own covariances, not from a
// run:
//   - one cycle every (stations x repeats) periods plus the gap, each
//     measured once its last window is read;
//   - each pose's position error is consistent with its covariance (the
//     ranges' noise and the capture chain's floor through the geometry):
//     its NEES, chi^2 with 2 degrees of freedom, averages at most about 2
//     (less: every range has the capture chain's floor) and none is beyond
//     the 99.99 % point (18.4);
//   - the heading from two fixes 0.8 m apart is off by at most their
//     errors across the body, (e_head + e_tail) / 0.8 m;
//   - the filter that fuses them is within the poses' errors plus the
//     odometry's between two cycles, far from the odometry alone.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "odoloc/sim/sinks.hpp"
#include "odoloc/sim/system.hpp"

namespace {

TEST(ThammaRoom, PosesAndTheFilterWithinTheirOwnUncertainty) {
  const odoloc::sim::BuiltinScenario* file = odoloc::sim::find_builtin_scenario("thamma-room.yaml");
  ASSERT_NE(file, nullptr);
  odoloc::sim::Scenario scenario = odoloc::sim::parse_scenario(std::string(file->text), file->key);
  const odoloc::world::RoomTour tour = scenario.tour;
  odoloc::sim::LocalisationSystem system(std::move(scenario), {.encoder_period_s = 1.0});
  odoloc::sim::ErrorSink errors(system);
  const std::size_t stations = tour.acoustics.beacons.size();

  std::size_t cycles = 0, poses = 0, above = 0;
  double nees_sum = 0, worst_heading_excess = -1e9, fused2 = 0, odometry2 = 0;
  std::size_t samples = 0;
  while (!system.done()) {
    const odoloc::sim::Frame f = system.step();
    errors.frame(f, system);
    for (const odoloc::sw::ThammaResult& t : f.soc.thamma) {
      ++cycles;
      if (!t.pose.valid)
        continue;
      ++poses;
      const odoloc::world::Pose truth = system.truth_at(system.to_sim_time(t.time_s));
      const Eigen::Vector2d e(t.pose.position_m.x - truth.x_m, t.pose.position_m.y - truth.y_m);
      const double nees =
          e.dot(Eigen::Matrix2d(t.pose.covariance.topLeftCorner<2, 2>()).inverse() * e);
      nees_sum += nees;
      above += nees > 18.4 ? 1 : 0;
      // Each box's reference point against the truth's.
      const auto box_error = [&](const odoloc::sw::locate::Fix& fix, double body_x) {
        return std::hypot(fix.position_m.x - (truth.x_m + body_x * std::cos(truth.theta_rad)),
                          fix.position_m.y - (truth.y_m + body_x * std::sin(truth.theta_rad)));
      };
      const double across = box_error(t.pose.head, 0.6) + box_error(t.pose.tail, -0.2);
      const double heading_error =
          std::abs(std::remainder(t.pose.heading_rad - truth.theta_rad, 2 * std::numbers::pi));
      worst_heading_excess = std::max(worst_heading_excess, heading_error - across / 0.8);
    }
    if (f.soc.estimate.initialised) {
      const auto& x = f.soc.estimate.pose.x;
      fused2 += std::pow(x(0) - f.truth.x_m, 2) + std::pow(x(1) - f.truth.y_m, 2);
      odometry2 += std::pow(f.soc.odometry.x_m - f.truth.x_m, 2) +
                   std::pow(f.soc.odometry.y_m - f.truth.y_m, 2);
      ++samples;
    }
  }
  errors.finish(system);
  const double cycle_s = tour.thamma->timing.cycle_s(stations);
  const double expected = std::floor((tour.duration_s - tour.thamma->first_trigger_s) / cycle_s);
  const double nees_mean = nees_sum / static_cast<double>(poses);
  const double fused_rms = std::sqrt(fused2 / static_cast<double>(samples));
  const double odometry_rms = std::sqrt(odometry2 / static_cast<double>(samples));
  const odoloc::sim::SourceErrors fixes = errors.report().errors(odoloc::sim::Source::kUltrasonic);
  std::printf(
      "%zu cycles (%.0f by the schedule), %zu poses; pose NEES mean %.2f, %zu above 18.4; "
      "poses RMS %.1f mm %.2f deg; fused RMS %.1f mm, odometry %.1f mm\n",
      cycles, expected, poses, nees_mean, above, fixes.rms_position_m * 1e3,
      fixes.rms_heading_rad * 180 / std::numbers::pi, fused_rms * 1e3, odometry_rms * 1e3);

  // Every cycle the schedule fits is measured (the last may end past the run).
  EXPECT_GE(static_cast<double>(cycles), expected - 1);
  EXPECT_LE(static_cast<double>(cycles), expected);
  EXPECT_GT(poses, cycles / 2);
  EXPECT_EQ(fixes.samples, poses);
  EXPECT_GT(nees_mean, 0.2);  // conservative: the capture chain's floor on every range
  EXPECT_LT(nees_mean, 6.0);
  EXPECT_EQ(above, 0U);
  EXPECT_LE(worst_heading_excess, 1e-3);
  EXPECT_LT(fused_rms, 0.1 * odometry_rms);
  ASSERT_NE(errors.distance_study(), nullptr);
  EXPECT_EQ(errors.distance_study()->poses(), poses);
  EXPECT_EQ(errors.distance_study()->cycles(), cycles);
}

}  // namespace
