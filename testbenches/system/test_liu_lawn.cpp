// Liu et al.'s lawn as shipped (examples/scenarios/liu-lawn.yaml), the
// whole system: the base station alone, no beacons, the 24 m square. The
// bounds come from the station's geometry and noise, not from a run:
//   - its laser crosses the robot twice a sweep period, and each crossing
//     asks for a burst that the robot hears (the square is within range);
//   - an alpha count is good to half an encoder step, so a fix at range rho
//     is off across the line of sight by up to rho step / 2 (sd rho
//     sigma_angle); Liu's fix pairs alpha with a range that comes up to a
//     slot later, so a moving robot's fix is also off along its path by up
//     to v (t_slot + margin + rho_max / c);
//   - Liu's filter with the paper's settings fuses a fix with the gain K of
//     its Riccati fixed point; standing at the start after each lap (the
//     paper's returns), its error is at most (1 - K) times a moving fix's
//     bound plus K times a standing fix's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <variant>
#include <vector>

#include "odoloc/sim/sinks.hpp"
#include "odoloc/sim/system.hpp"

namespace {

using odoloc::sw::fuse::Outcome;

TEST(LiuLawn, BothFiltersWithinTheStationsGeometryAndNoise) {
  const odoloc::sim::BuiltinScenario* file = odoloc::sim::find_builtin_scenario("liu-lawn.yaml");
  ASSERT_NE(file, nullptr);
  odoloc::sim::Scenario scenario = odoloc::sim::parse_scenario(std::string(file->text), file->key);
  const odoloc::world::RoomTour tour = scenario.tour;
  odoloc::sim::LocalisationSystem system(std::move(scenario), {.encoder_period_s = 1.0});
  odoloc::sim::ErrorSink returns(system);
  const odoloc::sw::station::StationConfig station = *system.localiser().config().station;
  const odoloc::sw::fuse::LiuFilterOptions liu = *system.localiser().config().liu_filter;

  double v_max = 0, rho_max = 0;
  for (const odoloc::world::Segment& s : tour.drive.path.segments)
    v_max = std::max(v_max, std::abs(s.speed_mps));
  double ekf2 = 0, liu2 = 0, odometry2 = 0;
  std::size_t n = 0, bearings = 0, ranges = 0;
  odoloc::sim::Frame last;
  while (!system.done()) {
    last = system.step();
    returns.frame(last, system);
    const odoloc::world::Pose& t = last.truth;
    rho_max = std::max(rho_max,
                       std::hypot(t.x_m - station.position_m.x(), t.y_m - station.position_m.y()));
    for (const odoloc::sw::StationUpdate& u : last.soc.station) {
      bearings += std::holds_alternative<odoloc::sw::fuse::StationBearing>(u.measurement) &&
                  u.fused == Outcome::kAccepted;
      ranges += std::holds_alternative<odoloc::sw::fuse::StationRange>(u.measurement) &&
                u.fused == Outcome::kAccepted;
    }
    const auto error2 = [&](double x, double y) {
      return (x - t.x_m) * (x - t.x_m) + (y - t.y_m) * (y - t.y_m);
    };
    ASSERT_TRUE(last.soc.estimate.initialised);  // from the start mark on
    ASSERT_TRUE(last.soc.liu && last.soc.liu->initialised);
    ekf2 += error2(last.soc.estimate.pose.x(0), last.soc.estimate.pose.x(1));
    liu2 += error2(last.soc.liu->pose.x(0), last.soc.liu->pose.x(1));
    odometry2 += error2(last.soc.odometry.x_m, last.soc.odometry.y_m);
    ++n;
  }
  returns.finish(system);
  const double duration_s = last.time_s;
  const double ekf_rms = std::sqrt(ekf2 / static_cast<double>(n));
  const double liu_rms = std::sqrt(liu2 / static_cast<double>(n));
  const double odometry_rms = std::sqrt(odometry2 / static_cast<double>(n));
  const odoloc::world::Pose start = tour.drive.start;
  const auto returned = [&](const odoloc::sw::fuse::Pose& p) {
    return std::hypot(p.x(0) - start.x_m, p.x(1) - start.y_m);
  };
  const double ekf_return = returned(last.soc.estimate.pose);
  const double liu_return = returned(last.soc.liu->pose);

  // The geometry's error figures.
  const double step = station.station_laser.step_rad();
  const double sigma_angle = std::hypot(station.station_laser.sd_rad(), station.bearing_sd_rad);
  const double rho_start =
      std::hypot(start.x_m - station.position_m.x(), start.y_m - station.position_m.y());
  const double c = system.localiser().config().kleeman.speed_of_sound_mps;
  const double pairing_s = tour.timing.cycle_s() + tour.station->request_margin_s + rho_max / c;
  const double moving_fix_m = std::hypot(rho_max * step / 2, v_max * pairing_s);
  const double standing_m = 3 * std::hypot(rho_start * sigma_angle, station.chain_sd_m);
  const double q = liu.process_var_m2, r = liu.fix_var_m2;
  const double p = (-q + std::sqrt(q * q + 4 * q * r)) / 2;
  const double gain = (p + q) / (p + q + r);
  const double sweeps = duration_s / tour.station->station_laser.period_s;
  std::printf(
      "%.1f s, %zu bearings, %zu ranges (2 per sweep: %.1f); RMS: EKF %.1f mm, Liu %.1f mm, "
      "odometry %.1f mm; return: EKF %.1f mm, Liu %.1f mm; bounds: moving fix %.1f mm, "
      "standing %.1f mm, K %.3f\n",
      duration_s, bearings, ranges, 2 * sweeps, ekf_rms * 1e3, liu_rms * 1e3, odometry_rms * 1e3,
      ekf_return * 1e3, liu_return * 1e3, moving_fix_m * 1e3, standing_m * 1e3, gain);

  // Every crossing of the laser gives a bearing, and each its range.
  EXPECT_GE(static_cast<double>(bearings), 2 * sweeps - 2);
  EXPECT_LE(static_cast<double>(bearings), 2 * sweeps + 2);
  EXPECT_GE(ranges + 2, bearings);
  // The EKF: within the station's sd across the line of sight at the
  // farthest point, and back at the start within a standing fix's 3 sigma.
  EXPECT_LT(ekf_rms, rho_max * sigma_angle);
  EXPECT_LT(ekf_return, standing_m);
  // Liu's filter: within a moving fix's bound, and at the start within
  // (1 - K) of it plus K of a standing fix's; both far better than the
  // odometry it corrects.
  EXPECT_LT(liu_rms, moving_fix_m);
  EXPECT_LT(liu_return, (1 - gain) * moving_fix_m + gain * standing_m);
  // The same at every stop back at the start, one a lap (Liu's statistic:
  // the estimate against where the robot stopped).
  const auto laps = static_cast<std::size_t>(
      std::round(std::abs(last.truth.theta_rad - start.theta_rad) / (2 * std::numbers::pi)));
  const odoloc::sim::ErrorReport& report = returns.report();
  for (const auto& [source, bound] :
       {std::pair{odoloc::sim::Source::kLiuFilter, (1 - gain) * moving_fix_m + gain * standing_m},
        std::pair{odoloc::sim::Source::kFused, standing_m}}) {
    const std::vector<double> at_stops = report.errors(source).returns_m;
    EXPECT_EQ(at_stops.size(), laps) << odoloc::sim::name(source);
    for (const double at_stop : at_stops)
      EXPECT_LT(at_stop, bound) << odoloc::sim::name(source);
  }
  EXPECT_LT(liu_rms, 0.5 * odometry_rms);
  EXPECT_LT(ekf_rms, liu_rms);
  const odoloc::sw::fuse::LiuFilter* filter = system.localiser().liu_filter();
  ASSERT_NE(filter, nullptr);
  const odoloc::sw::fuse::LiuStats stats = filter->stats();
  // Each range pairs with the alpha that asked for it: one fix each.
  EXPECT_GE(stats.fixes + stats.fixes_gated + 1, ranges);
  EXPECT_GT(stats.fixes, stats.fixes_gated);
  EXPECT_GT(stats.headings, 0U);
}

}  // namespace
