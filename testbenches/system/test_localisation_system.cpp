// The whole localisation system (docs/simulator.md): the room tour's world,
// the chip at the pin level, the SoC software over the register bus (label
// scenario). Against the ground truth:
//   - the fused estimate beats every single source (RMS, final and return
//     to start) and returns to the start within 5 cm (Liu et al.: 10 cm);
//   - its covariance is honest: the average NEES over the run is near its
//     dimension, and no sample is wildly outside it;
//   - the occluded beacon's echo reaches the filter and is gated;
//   - Liu's base station: every bearing and range the SoC makes of it
//     matches the truth at its time (so its packets pair with the right
//     sync edges), the filter takes them, and with the station alone after
//     the first fix the robot still ends within 5 cm;
//   - the run is reproducible, and the seed changes it.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "odoloc/sim/sinks.hpp"
#include "odoloc/sim/system.hpp"

namespace {

using namespace odoloc;
using sim::Source;

// The fused estimate minus the truth (heading wrapped).
sw::fuse::Vector3 error(const sim::Frame& f) {
  const sw::fuse::Vector3 x = f.soc.estimate.pose.x;
  return {x(0) - f.truth.x_m, x(1) - f.truth.y_m,
          std::remainder(x(2) - f.truth.theta_rad, 2 * std::numbers::pi)};
}

// The base station's measurements against the truth at their times: the
// largest error of each kind (alpha rad, range m, beta rad) and how many
// there were.
struct StationCheck {
  std::array<double, 3> worst{};
  std::array<int, 3> count{};

  void add(const sim::LocalisationSystem& system, const sw::StationUpdate& u) {
    const sw::station::StationConfig& st = *system.localiser().config().station;
    const world::Pose p = system.truth_at(system.to_sim_time(u.time_s));
    const double dx = p.x_m - st.position_m.x(), dy = p.y_m - st.position_m.y();
    const auto wrap = [](double a) { return std::remainder(a, 2 * std::numbers::pi); };
    double e = 0;
    std::size_t k = 0;
    if (const auto* a = std::get_if<sw::fuse::StationBearing>(&u.measurement))
      e = wrap(a->bearing_rad - std::atan2(dy, dx));
    else if (const auto* r = std::get_if<sw::fuse::StationRange>(&u.measurement))
      e = r->distance_m - std::sqrt(dx * dx + dy * dy + st.height_m * st.height_m), k = 1;
    else if (const auto* b = std::get_if<sw::fuse::RobotBearing>(&u.measurement))
      e = wrap(b->bearing_rad - (std::atan2(-dy, -dx) - p.theta_rad)), k = 2;
    else
      ADD_FAILURE() << "not a base-station measurement";
    worst[k] = std::max(worst[k], std::abs(e));
    ++count[k];
  }
};

// Normalised estimation error squared of the fused estimate (3 dof).
double nees(const sim::Frame& f) {
  const sw::fuse::Vector3 e = error(f);
  return e.dot(f.soc.estimate.covariance.ldlt().solve(e));
}

TEST(LocalisationSystem, FusedEstimateBeatsEverySourceOnTheRoomTour) {
  sim::LocalisationSystem system(sim::default_scenario(), {});
  sim::ErrorSink errors(system);
  double nees_sum = 0;
  std::size_t nees_n = 0, nees_wild = 0;
  double max_fused_error = 0;
  std::array<double, 3> per_state{};  // normalised squared error per state
  StationCheck station;
  std::size_t cycles = 0, ambiguous = 0;
  while (!system.done()) {
    const sim::Frame f = system.step();
    errors.frame(f, system);
    for (const sw::StationUpdate& u : f.soc.station)
      station.add(system, u);
    // A cycle two beacon sets explain is never fused; only such a cycle is
    // marked so.
    for (const sw::CycleResult& c : f.soc.cycles) {
      ++cycles;
      const bool refused = c.fix.reason == sw::locate::NoFixReason::kAmbiguousBeaconSets;
      ambiguous += refused ? 1 : 0;
      if (c.fused == sw::fuse::Outcome::kAmbiguous) {
        EXPECT_TRUE(refused) << c.time_s;
      }
      if (refused) {
        EXPECT_TRUE(c.fused == sw::fuse::Outcome::kAmbiguous ||
                    c.fused == sw::fuse::Outcome::kNotInitialised)
            << c.time_s;
      }
    }
    if (!f.soc.estimate.initialised)
      continue;
    const double n = nees(f);
    nees_sum += n;
    ++nees_n;
    const sw::fuse::Matrix3& P = f.soc.estimate.covariance;
    for (int i = 0; i < 3; ++i)
      per_state[i] += error(f)(i) * error(f)(i) / P(i, i);
    nees_wild += n > 30 ? 1 : 0;  // chi-square 3 dof: P(> 30) = 1.4e-6
    max_fused_error = std::max(max_fused_error, std::hypot(f.soc.estimate.pose.x(0) - f.truth.x_m,
                                                           f.soc.estimate.pose.x(1) - f.truth.y_m));
  }
  const sim::ErrorReport& report = errors.report();
  std::printf("%s", report.table().c_str());
  std::printf("beacon cycles: %zu, refused as ambiguous (not fused): %zu\n", cycles, ambiguous);
  const double mean_nees = nees_sum / static_cast<double>(nees_n);
  const auto n = static_cast<double>(nees_n);
  std::printf("fused: e_i^2 / P_ii on average %.2f (x), %.2f (y), %.2f (heading)\n",
              per_state[0] / n, per_state[1] / n, per_state[2] / n);
  std::printf("fused: average NEES %.2f over %zu samples (%zu above 30), largest error %.1f mm\n",
              mean_nees, nees_n, nees_wild, max_fused_error * 1e3);

  // The path closes: the truth ends where it started.
  const world::Pose end = system.truth_at(system.tour().duration_s);
  EXPECT_LT(std::hypot(end.x_m - 2.0, end.y_m - 2.0), 1e-3);

  const sim::SourceErrors fused = report.errors(Source::kFused);
  EXPECT_LT(fused.return_to_start_m, 0.05);
  EXPECT_LT(fused.rms_position_m, 0.05);
  EXPECT_LT(max_fused_error, 0.05);
  for (const Source s :
       {Source::kRearOdometry, Source::kFrontOdometry, Source::kMinSelect, Source::kUltrasonic}) {
    const sim::SourceErrors other = report.errors(s);
    ASSERT_GT(other.samples, 0U) << sim::name(s);
    EXPECT_LT(fused.rms_position_m, other.rms_position_m) << sim::name(s);
    EXPECT_LT(fused.final_position_m, other.final_position_m) << sim::name(s);
    EXPECT_LT(fused.return_to_start_m, other.return_to_start_m) << sim::name(s);
  }
  // The odometry drifts (the wheels' true radii are not the nominal ones):
  // without the beacons the robot would be lost by decimetres.
  EXPECT_GT(report.errors(Source::kMinSelect).final_position_m, 0.1);

  // Consistent: near 3 on average (correlated samples of one run: a loose
  // band), and never far out.
  EXPECT_GT(mean_nees, 0.5);
  EXPECT_LT(mean_nees, 6.0);
  EXPECT_EQ(nees_wild, 0U);

  // The cabinet hides beacon 2 at the (8, 2) corner: its echo comes first,
  // and the filter's gate turns it away.
  const sw::fuse::TypeStats& ranges =
      system.localiser().filter().stats(sw::fuse::MeasurementType::kBeaconRange);
  std::printf("beacon ranges: %llu accepted, %llu gated, %llu sets reopened\n",
              static_cast<unsigned long long>(ranges.accepted),
              static_cast<unsigned long long>(ranges.gated),
              static_cast<unsigned long long>(ranges.reopened));
  EXPECT_GT(ranges.gated, 0U);

  // Liu's base station. A bearing's count is the angle at the hit floored
  // to a step (0.36 degrees): off by half a step at most, plus the robot's
  // motion while a strobe waits for another (1 ms: 0.3 mrad). A range is
  // off by the turbulence and the capture chain: 1 to 2 mm mostly, 7.3 mm
  // at worst on this tour; 1 cm allowed.
  std::printf("%s", sim::update_summary(system.localiser().filter()).c_str());
  const double half_step = std::numbers::pi / 1000;
  std::printf(
      "base station: %d alpha (worst %.2f mrad), %d ranges (worst %.1f mm), %d beta "
      "(worst %.2f mrad) against the truth\n",
      station.count[0], station.worst[0] * 1e3, station.count[1], station.worst[1] * 1e3,
      station.count[2], station.worst[2] * 1e3);
  for (const int seen : station.count)
    EXPECT_GE(seen, 20);  // two hits of each laser per 5 s sweep, over 104 s
  EXPECT_LT(station.worst[0], half_step + 1e-3);
  EXPECT_LT(station.worst[1], 0.01);
  EXPECT_LT(station.worst[2], half_step + 1e-3);
  for (const auto type :
       {sw::fuse::MeasurementType::kStationBearing, sw::fuse::MeasurementType::kStationRange,
        sw::fuse::MeasurementType::kRobotBearing})
    EXPECT_GT(system.localiser().filter().stats(type).accepted, 15U) << sw::fuse::name(type);
}

// Kleeman's beacons only initialise the filter; after that Liu's base
// station alone corrects the odometry: far better than the odometry, within
// 5 cm of the truth at the end.
TEST(LocalisationSystem, BaseStationAloneKeepsTheRobotLocalised) {
  sim::LocalisationSystem system(sim::default_scenario(), {.fuse_beacon_ranges = false});
  sim::ErrorSink errors(system);
  while (!system.done())
    errors.frame(system.step(), system);
  const sim::ErrorReport& report = errors.report();
  std::printf("%s", report.table().c_str());
  std::printf("%s", sim::update_summary(system.localiser().filter()).c_str());
  const sim::SourceErrors fused = report.errors(Source::kFused);
  const sim::SourceErrors odometry = report.errors(Source::kMinSelect);
  EXPECT_EQ(system.localiser().filter().stats(sw::fuse::MeasurementType::kBeaconRange).accepted,
            0U);
  EXPECT_LT(fused.final_position_m, 0.05);
  EXPECT_LT(fused.rms_position_m, 0.05);
  EXPECT_LT(fused.rms_position_m, odometry.rms_position_m / 3);
  EXPECT_LT(std::abs(fused.final_heading_rad), 0.01);
}

// Two short runs with one seed are identical; another seed changes the
// acoustic world's draws, so the fixes.
TEST(LocalisationSystem, RunsAreReproducible) {
  const auto run = [](std::uint64_t seed) {
    sim::LocalisationSystem system(sim::default_scenario(), {.seed = seed, .until_s = 3.0});
    std::vector<double> xs;
    while (!system.done()) {
      const sim::Frame f = system.step();
      for (const sw::CycleResult& c : f.soc.cycles)
        xs.push_back(c.fix.position_m.x);
      xs.push_back(f.soc.estimate.pose.x(0));
    }
    return xs;
  };
  const std::vector<double> a = run(1);
  EXPECT_EQ(a, run(1));
  EXPECT_NE(a, run(2));
}

}  // namespace
