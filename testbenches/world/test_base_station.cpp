// Liu's base station (the world side) against independent references: the
// scanning laser's triangle wave at known instants and its encoder's edges,
// laser hits against the times the sweep reaches a fixed bearing (solved by
// hand) and against a brute-force scan on a 10x finer grid for a moving
// robot, decoded counts against bearings computed from the trajectory,
// ranging bursts against reserved slots computed from the Kleeman timing in
// long double, the RF strobes' spacing, Kleeman's schedule with a reserved
// slot, and parameter checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <vector>

#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"
#include "odoloc/world/base_station.hpp"
#include "odoloc/world/tricycle.hpp"

namespace {

using odoloc::world::AcousticRun;
using odoloc::world::AcousticWorld;
using odoloc::world::BaseStation;
using odoloc::world::Beacon;
using odoloc::world::Emission;
using odoloc::world::KleemanTiming;
using odoloc::world::plan_base_station;
using odoloc::world::Pose;
using odoloc::world::ScanningLaser;
using odoloc::world::Schedule;
using odoloc::world::stationary;
using odoloc::world::StationPlan;
using odoloc::world::StationReport;
using odoloc::world::StationReportKind;
using odoloc::world::Trajectory;
using odoloc::world::Vec2;

constexpr double kPi = std::numbers::pi;

double deg(double degrees) {
  return degrees * kPi / 180;
}

// (-pi, pi], by hand (no std::remainder, unlike the implementation).
double wrap(double a) {
  while (a > kPi)
    a -= 2 * kPi;
  while (a <= -kPi)
    a += 2 * kPi;
  return a;
}

// The bearings, from the trajectory.
double alpha_of(Vec2 station, const Pose& p) {
  return std::atan2(p.y_m - station.y_m, p.x_m - station.x_m);
}
double beta_of(Vec2 station, const Pose& p) {
  return wrap(std::atan2(station.y_m - p.y_m, station.x_m - p.x_m) - p.theta_rad);
}

// The fraction of the way along the sweep at which the laser points at
// `bearing`, or -1 if it never does. The sweep covers [start, start + width]
// (unwrapped); the bearing may be any turn of the circle.
double sweep_point(const ScanningLaser& l, double bearing) {
  double rel = bearing - l.sweep_start_rad;
  while (rel < 0)
    rel += 2 * kPi;
  while (rel >= 2 * kPi)
    rel -= 2 * kPi;
  return rel <= l.sweep_width_rad ? rel / l.sweep_width_rad : -1;
}

// Every instant in [0, end] at which a laser sweeping as described passes a
// fixed bearing: out at -phase + k T + p T/2, back at -phase + (k+1) T - p T/2.
std::vector<double> fixed_hits(const ScanningLaser& l, double bearing, double end_s) {
  std::vector<double> out;
  const double p = sweep_point(l, bearing);
  if (p < 0)
    return out;
  const long double T = l.period_s;
  for (long k = -2; static_cast<long double>(k) * T < end_s + T; ++k) {
    const long double base = -static_cast<long double>(l.phase_s) + k * T;
    for (const long double t : {base + p * T / 2, base + T - p * T / 2})
      if (t >= 0 && t <= end_s)
        out.push_back(static_cast<double>(t));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<StationReport> of_kind(const StationPlan& plan, StationReportKind kind) {
  std::vector<StationReport> out;
  for (const StationReport& r : plan.reports)
    if (r.kind == kind)
      out.push_back(r);
  return out;
}

// The encoder's decoded angle: the middle of the count's step.
double decoded(const ScanningLaser& l, std::uint32_t count) {
  const double step = 2 * kPi / l.counts_per_rev;
  return l.sweep_start_rad + (count + 0.5) * step;
}

// A 10 m room with a station on the wall x = 0; the station laser sweeps
// 120 degrees about +x, the robot laser the robot's front +-100 degrees.
struct Rig {
  AcousticWorld world = odoloc::world::kleeman_world();
  BaseStation station;
  KleemanTiming timing;
  double t0 = 0.8e-3;

  Rig() {
    station.position = {0.05, 5.0};
    Beacon tx;
    tx.position = station.position;
    tx.electronics_delay_s = t0;
    station.transmitter = world.beacons.size();
    world.beacons.push_back(tx);
    station.station_laser.sweep_start_rad = deg(-60);
    station.station_laser.sweep_width_rad = deg(120);
    station.station_laser.phase_s = 0.37;
    station.robot_laser.sweep_start_rad = deg(-100);
    station.robot_laser.sweep_width_rad = deg(200);
    station.robot_laser.period_s = 3.0;
    station.robot_laser.phase_s = 1.1;
    timing.reserved_slots = 1;
  }
};

// Checks shared by every plan: reports sorted by strobe, one sync pulse per
// report at its strobe, strobes rf_spacing apart and inside the run, a hit's
// strobe never before its hit, its count the laser's at the hit.
void check_plan_invariants(const StationPlan& plan, const BaseStation& st, double end_s) {
  ASSERT_EQ(plan.schedule.sync.size(), plan.reports.size());
  std::size_t rangings = 0;
  for (std::size_t i = 0; i < plan.reports.size(); ++i) {
    const StationReport& r = plan.reports[i];
    EXPECT_EQ(plan.schedule.sync[i].beacon, st.transmitter);
    EXPECT_EQ(plan.schedule.sync[i].start_s, r.strobe_s);
    EXPECT_EQ(plan.schedule.sync[i].duration_s, st.rf_pulse_s);
    EXPECT_LE(r.strobe_s, end_s);
    EXPECT_GE(r.strobe_s, 0.0);
    if (i > 0) {
      EXPECT_GE(r.strobe_s - plan.reports[i - 1].strobe_s, st.rf_spacing_s) << "report " << i;
    }
    if (r.kind == StationReportKind::kRanging) {
      ++rangings;
      EXPECT_EQ(r.count, 0U);
      EXPECT_TRUE(std::isnan(r.true_angle_rad));
    } else {
      EXPECT_GE(r.strobe_s, r.hit_s);
      const ScanningLaser& l =
          r.kind == StationReportKind::kStationSawRobot ? st.station_laser : st.robot_laser;
      EXPECT_EQ(r.count, l.count(r.hit_s));
    }
  }
  EXPECT_EQ(plan.schedule.emissions.size(), rangings);
}

// ScanningLaser ---------------------------------------------------------------

TEST(BaseStation, LaserIsATriangleWaveBetweenItsEnds) {
  ScanningLaser l;
  l.sweep_start_rad = 0.3;
  l.sweep_width_rad = 1.2;
  l.period_s = 4.0;
  l.phase_s = 1.0;  // at the start at t = -1, 3, 7, ...
  for (const double k : {0.0, 1.0, 5.0}) {
    const double t = -1 + 4 * k;
    EXPECT_NEAR(l.angle_rad(t), 0.3, 1e-12) << "start, k " << k;
    EXPECT_NEAR(l.angle_rad(t + 2), 1.5, 1e-12) << "turnaround";
    EXPECT_NEAR(l.angle_rad(t + 1), 0.9, 1e-12) << "half way out";
    EXPECT_NEAR(l.angle_rad(t + 3), 0.9, 1e-12) << "half way back";
    EXPECT_NEAR(l.angle_rad(t + 0.5), 0.3 + 0.3, 1e-12) << "a quarter out";
    EXPECT_NEAR(l.angle_rad(t + 3.5), 0.3 + 0.3, 1e-12) << "a quarter back";
  }
  EXPECT_NEAR(l.angle_rad(-5), 0.3, 1e-12);  // negative times too
  EXPECT_NEAR(l.angle_rad(-4), 0.9, 1e-12);
}

TEST(BaseStation, EncoderCountsFloorOfStepsSinceTheStart) {
  ScanningLaser l;
  l.counts_per_rev = 360;  // a degree a count
  l.sweep_start_rad = deg(-20);
  l.sweep_width_rad = deg(90);
  l.period_s = 9.0;  // 20 degrees a second: edge k at t = k / 20 s out
  l.phase_s = 0;
  EXPECT_NEAR(l.step_rad(), deg(1), 1e-15);
  for (std::uint32_t k = 1; k < 90; ++k) {
    const double out = k / 20.0;
    const double back = 9.0 - k / 20.0;
    EXPECT_EQ(l.count(out), k) << "on edge " << k << " going out";
    EXPECT_EQ(l.count(out - 1e-6), k - 1) << "just before edge " << k;
    EXPECT_EQ(l.count(out + 0.025), k) << "mid-step";
    EXPECT_EQ(l.count(back), k) << "on edge " << k << " coming back";
    EXPECT_EQ(l.count(back + 1e-6), k - 1) << "just past edge " << k << " coming back";
  }
  EXPECT_EQ(l.count(0), 0U);
  EXPECT_EQ(l.count(4.5), 90U);  // the far end is an edge
  // Monotone along each half sweep, within [0, width / step].
  std::uint32_t prev = 0;
  for (int i = 0; i <= 4500; ++i) {
    const std::uint32_t c = l.count(i * 1e-3);
    EXPECT_GE(c, prev);
    EXPECT_LE(c, 90U);
    prev = c;
  }
  for (int i = 4500; i <= 9000; ++i) {
    const std::uint32_t c = l.count(i * 1e-3);
    EXPECT_LE(c, prev);
    prev = c;
  }
  EXPECT_EQ(prev, 0U);
  // A width that is not a whole number of steps tops out at its floor.
  l.sweep_width_rad = deg(90.5);
  std::uint32_t top = 0;
  for (int i = 0; i <= 9000; ++i)
    top = std::max(top, l.count(i * 1e-3));
  EXPECT_EQ(top, 90U);
  // Liu's encoder.
  EXPECT_NEAR(ScanningLaser{}.step_rad(), deg(0.36), 1e-15);
}

// Laser hits ------------------------------------------------------------------

TEST(BaseStation, StationaryRobotIsHitTwicePerPeriodInsideTheSweepOnly) {
  Rig s;
  const double end_s = 21.0;
  // Inside: 5 and -40 degrees from the station; outside: 75 degrees.
  for (const double bearing_deg : {5.0, -40.0, 75.0}) {
    const double b = deg(bearing_deg);
    const Pose robot{s.station.position.x_m + 4 * std::cos(b),
                     s.station.position.y_m + 4 * std::sin(b), 0.0};
    const StationPlan plan =
        plan_base_station(s.station, s.world, s.timing, stationary(robot), 0.25, end_s);
    check_plan_invariants(plan, s.station, end_s);
    const std::vector<StationReport> alpha = of_kind(plan, StationReportKind::kStationSawRobot);
    const std::vector<double> expect = fixed_hits(s.station.station_laser, b, end_s);
    if (bearing_deg > 60) {
      EXPECT_TRUE(expect.empty());
    } else {
      EXPECT_GE(expect.size(), 8U);  // 2 per 5 s over 21 s
    }
    ASSERT_EQ(alpha.size(), expect.size()) << bearing_deg;
    for (std::size_t i = 0; i < alpha.size(); ++i) {
      EXPECT_NEAR(alpha[i].hit_s, expect[i], 1e-8) << bearing_deg << " hit " << i;
      EXPECT_NEAR(alpha[i].true_angle_rad, b, 1e-12);
      EXPECT_LE(std::abs(wrap(decoded(s.station.station_laser, alpha[i].count) - b)),
                s.station.station_laser.step_rad() / 2 + 1e-9);
    }
  }
}

TEST(BaseStation, TargetsNearTheSweepsEndsAreHitTwicePerPeriod) {
  Rig s;
  // Turnarounds half-way between the search's 1 ms samples; targets 0.1 mrad
  // inside the ends: the laser passes them 0.12 ms either side of the turn.
  s.station.station_laser.phase_s = 0.3705;
  const double end_s = 16.0;
  const ScanningLaser& l = s.station.station_laser;
  for (const double b : {l.sweep_start_rad + 1e-4, l.sweep_start_rad + l.sweep_width_rad - 1e-4}) {
    const Pose robot{s.station.position.x_m + 3 * std::cos(b),
                     s.station.position.y_m + 3 * std::sin(b), 0.0};
    const StationPlan plan =
        plan_base_station(s.station, s.world, s.timing, stationary(robot), 0.25, end_s);
    const std::vector<StationReport> alpha = of_kind(plan, StationReportKind::kStationSawRobot);
    const std::vector<double> expect = fixed_hits(l, b, end_s);
    ASSERT_GE(expect.size(), 6U);
    ASSERT_EQ(alpha.size(), expect.size()) << b;
    for (std::size_t i = 0; i < alpha.size(); ++i)
      EXPECT_NEAR(alpha[i].hit_s, expect[i], 1e-8) << b << " hit " << i;
  }
}

TEST(BaseStation, RobotLaserHitsInTheBodyFrameAtSeveralHeadings) {
  Rig s;
  const double end_s = 13.0;
  const Pose at{3.0, 2.0, 0.0};
  // The station seen from the robot: 134.5 degrees in the world frame.
  const double world_bearing = std::atan2(5.0 - 2.0, 0.05 - 3.0);
  for (const double heading_deg : {0.0, 60.0, 150.0, -120.0, -170.0, 200.0}) {
    const Pose robot{at.x_m, at.y_m, deg(heading_deg)};
    const double body = wrap(world_bearing - robot.theta_rad);
    const StationPlan plan =
        plan_base_station(s.station, s.world, s.timing, stationary(robot), 0.25, end_s);
    check_plan_invariants(plan, s.station, end_s);
    const std::vector<StationReport> beta = of_kind(plan, StationReportKind::kRobotSawStation);
    const std::vector<double> expect = fixed_hits(s.station.robot_laser, body, end_s);
    const bool inside = std::abs(body) <= deg(100);
    if (inside) {
      EXPECT_GE(expect.size(), 8U) << heading_deg;
    } else {
      EXPECT_TRUE(expect.empty()) << heading_deg;
    }
    ASSERT_EQ(beta.size(), expect.size()) << heading_deg;
    for (std::size_t i = 0; i < beta.size(); ++i) {
      EXPECT_NEAR(beta[i].hit_s, expect[i], 1e-8) << heading_deg << " hit " << i;
      EXPECT_NEAR(beta[i].true_angle_rad, body, 1e-12);
      EXPECT_LE(std::abs(wrap(decoded(s.station.robot_laser, beta[i].count) - body)),
                s.station.robot_laser.step_rad() / 2 + 1e-9)
          << heading_deg;
    }
  }
}

// A moving robot: hits against a brute-force scan of the sign of
// wrap(angle - bearing) on a 0.1 ms grid, counts against the bearing at the hit.
void check_moving(const Trajectory& robot, double end_s) {
  Rig s;
  const StationPlan plan = plan_base_station(s.station, s.world, s.timing, robot, 0.25, end_s);
  check_plan_invariants(plan, s.station, end_s);
  for (const StationReportKind kind :
       {StationReportKind::kStationSawRobot, StationReportKind::kRobotSawStation}) {
    const bool by_station = kind == StationReportKind::kStationSawRobot;
    const ScanningLaser& l = by_station ? s.station.station_laser : s.station.robot_laser;
    const auto bearing = [&](double t) {
      return by_station ? alpha_of(s.station.position, robot(t))
                        : beta_of(s.station.position, robot(t));
    };
    std::vector<double> brute;
    double prev = wrap(l.angle_rad(0) - bearing(0));
    for (long i = 1; static_cast<double>(i) * 1e-4 <= end_s; ++i) {
      const double t = static_cast<double>(i) * 1e-4;
      const double f = wrap(l.angle_rad(t) - bearing(t));
      if (std::abs(f) < 1 && std::abs(prev) < 1 && ((prev < 0) != (f < 0)))
        brute.push_back(t);
      prev = f;
    }
    const std::vector<StationReport> got = of_kind(plan, kind);
    EXPECT_GE(brute.size(), 4U) << by_station;
    // Hits whose strobe would leave the run are dropped: only the last few ms.
    std::size_t matched = 0;
    for (const double t : brute) {
      const auto near = std::find_if(got.begin(), got.end(), [&](const StationReport& r) {
        return std::abs(r.hit_s - t) <= 1e-4;
      });
      if (near == got.end()) {
        EXPECT_GT(t, end_s - 0.01) << "missed hit at " << t;
        continue;
      }
      ++matched;
    }
    EXPECT_EQ(matched, got.size()) << "a report without a brute-force crossing";
    for (const StationReport& r : got) {
      const double truth = bearing(r.hit_s);
      EXPECT_NEAR(r.true_angle_rad, truth, 1e-12);
      EXPECT_LE(std::abs(wrap(l.angle_rad(r.hit_s) - truth)), 1e-6) << "hit at " << r.hit_s;
      EXPECT_LE(std::abs(wrap(decoded(l, r.count) - truth)), l.step_rad() / 2 + 1e-6)
          << by_station << " hit at " << r.hit_s;
    }
  }
}

TEST(BaseStation, RobotDrivingAStraightLine) {
  check_moving([](double t) { return Pose{1.5 + 0.4 * t, 2.0 + 0.25 * t, 2.3}; }, 16.0);
}

TEST(BaseStation, RobotDrivingACircle) {
  check_moving(
      [](double t) {
        const double a = 0.3 * t;  // 2 m radius about (5, 5), CCW, heading the tangent
        return Pose{5 + 2 * std::cos(a), 5 + 2 * std::sin(a), a + kPi / 2};
      },
      21.0);
}

// Ranging ---------------------------------------------------------------------

TEST(BaseStation, RangingFiresInTheReservedSlotAfterItsRequest) {
  Rig s;
  const double first = 0.25;
  const double end_s = 40.0;
  const Trajectory robot = [](double t) { return Pose{3.0 + 0.1 * t, 5.5 - 0.05 * t, 0.4}; };
  const StationPlan plan = plan_base_station(s.station, s.world, s.timing, robot, first, end_s);
  check_plan_invariants(plan, s.station, end_s);

  // Reserved slot of cycle k: slot 6 of 7, 150 ms each, from `first`.
  const long double fire = 0.150L;
  const auto reserved_start = [&](long k) { return first + (7.0L * k + 6) * fire; };
  const std::vector<StationReport> alpha = of_kind(plan, StationReportKind::kStationSawRobot);
  std::set<long> expect;
  for (const StationReport& a : alpha) {
    long k = 0;
    while (reserved_start(k) - s.t0 < a.hit_s + s.station.request_margin_s)
      ++k;
    if (reserved_start(k) - s.t0 <= end_s)
      expect.insert(k);
  }
  ASSERT_GE(expect.size(), 10U);

  const std::vector<StationReport> ranging = of_kind(plan, StationReportKind::kRanging);
  ASSERT_EQ(plan.schedule.emissions.size(), ranging.size());
  std::set<long> got;
  for (std::size_t i = 0; i < ranging.size(); ++i) {
    const StationReport& r = ranging[i];
    const long k = std::lround((r.hit_s - first) / (7 * 0.150) - 6.0 / 7);
    EXPECT_NEAR(r.hit_s, static_cast<double>(reserved_start(k)), 1e-9) << "sound at a slot start";
    EXPECT_NEAR(r.strobe_s, r.hit_s - s.t0, 1e-12) << "trigger t0 before the slot";
    EXPECT_TRUE(got.insert(k).second) << "two rangings in slot " << k;
    const Emission& e = plan.schedule.emissions[i];
    EXPECT_EQ(e.beacon, s.station.transmitter);
    EXPECT_EQ(e.trigger_s, r.strobe_s);
    EXPECT_EQ(e.duration_s, s.station.pulse_s);
    // Its request: an alpha hit at least the margin earlier for which the
    // previous reserved slot came too soon.
    EXPECT_TRUE(std::any_of(alpha.begin(), alpha.end(),
                            [&](const StationReport& a) {
                              const long double earliest = a.hit_s + s.station.request_margin_s;
                              return earliest <= r.strobe_s &&
                                     (k == 0 || reserved_start(k - 1) - s.t0 < earliest);
                            }))
        << "ranging at " << r.strobe_s;
  }
  EXPECT_EQ(got, expect);

  // Kleeman's beacons never sound in a reserved slot; the ranging sounds
  // inside its own.
  const std::size_t cycles = 40;
  const Schedule beacons = odoloc::world::kleeman_schedule(s.timing, cycles, first);
  for (const long k : got) {
    const double lo = static_cast<double>(reserved_start(k));
    const double hi = static_cast<double>(reserved_start(k) + fire);
    for (const Emission& e : beacons.emissions) {
      const double on = e.trigger_s + s.world.beacons[e.beacon].electronics_delay_s;
      EXPECT_FALSE(on < hi && on + e.duration_s > lo) << "beacon " << e.beacon << " in slot " << k;
    }
    EXPECT_LE(lo + s.station.pulse_s, hi);
  }

  // The plan drives the acoustic world: merged with the beacons, each
  // ranging's sound leaves at its slot's start.
  Schedule merged = beacons;
  merged.emissions.insert(merged.emissions.end(), plan.schedule.emissions.begin(),
                          plan.schedule.emissions.end());
  merged.sync = plan.schedule.sync;
  const AcousticRun run = odoloc::world::simulate(s.world, merged, robot, 12.0, 1);
  std::size_t heard = 0;
  for (const auto& rec : run.emissions) {
    if (rec.emission.beacon != s.station.transmitter)
      continue;
    ++heard;
    const long k = std::lround((rec.emission_s - first) / (7 * 0.150) - 6.0 / 7);
    EXPECT_NEAR(rec.emission_s, static_cast<double>(reserved_start(k)), 1e-9);
  }
  EXPECT_GE(heard, 3U);
  EXPECT_EQ(run.sync.size(), static_cast<std::size_t>(std::count_if(
                                 plan.reports.begin(), plan.reports.end(),
                                 [](const StationReport& r) { return r.strobe_s < 12.0; })));
}

TEST(BaseStation, RangingWaitsForTheRequestMargin) {
  Rig s;
  const Pose robot{4.05, 5.0, 0.0};  // bearing 0: hit 1.25 s after the sweep's start
  // Cycle k's reserved slot is triggered at 0.25 + (7k + 6) 0.15 s - t0.
  const double trigger0 = 0.25 + 6 * 0.150 - s.t0;
  const double trigger1 = 0.25 + 13 * 0.150 - s.t0;
  // An alpha hit 2 ms before cycle 0's trigger (inside the 5 ms margin) waits
  // for cycle 1; one 6 ms before makes cycle 0.
  for (const double lead : {2e-3, 6e-3}) {
    s.station.station_laser.phase_s = 1.25 - (trigger0 - lead);
    const StationPlan plan =
        plan_base_station(s.station, s.world, s.timing, stationary(robot), 0.25, 2.5);
    check_plan_invariants(plan, s.station, 2.5);
    const std::vector<StationReport> alpha = of_kind(plan, StationReportKind::kStationSawRobot);
    ASSERT_GE(alpha.size(), 1U);
    EXPECT_NEAR(alpha[0].hit_s, trigger0 - lead, 1e-8);
    const std::vector<StationReport> ranging = of_kind(plan, StationReportKind::kRanging);
    ASSERT_GE(ranging.size(), 1U) << lead;
    EXPECT_NEAR(ranging[0].strobe_s, lead < s.station.request_margin_s ? trigger1 : trigger0, 1e-12)
        << lead;
  }
}

TEST(BaseStation, StrobesKeepTheirSpacingByDelayingHits) {
  Rig s;
  s.station.rf_spacing_s = 0.3;  // wide: collisions are many
  s.station.robot_laser.period_s = 1.3;
  const double end_s = 40.0;
  const Trajectory robot = [](double t) { return Pose{2.0 + 0.1 * t, 4.0 + 0.02 * t, 2.9}; };
  const StationPlan plan = plan_base_station(s.station, s.world, s.timing, robot, 0.25, end_s);
  check_plan_invariants(plan, s.station, end_s);
  std::size_t delayed = 0;
  std::set<double> strobes;
  for (const StationReport& r : plan.reports)
    strobes.insert(r.strobe_s);
  for (const StationReport& r : plan.reports) {
    if (r.kind == StationReportKind::kRanging || r.strobe_s == r.hit_s)
      continue;
    ++delayed;
    // Delayed no further than needed: right behind another strobe.
    const auto it = strobes.find(r.strobe_s);
    ASSERT_NE(it, strobes.begin());
    EXPECT_NEAR(r.strobe_s - *std::prev(it), s.station.rf_spacing_s, 1e-12);
    EXPECT_LT(r.hit_s, *std::prev(it) + s.station.rf_spacing_s);
  }
  EXPECT_GE(delayed, 3U);
  // Angles are the truth at the hit, not at the (later) strobe.
  for (const StationReport& r : plan.reports) {
    const Pose p = robot(r.hit_s);
    if (r.kind == StationReportKind::kStationSawRobot) {
      EXPECT_NEAR(r.true_angle_rad, alpha_of(s.station.position, p), 1e-12);
    } else if (r.kind == StationReportKind::kRobotSawStation) {
      EXPECT_NEAR(r.true_angle_rad, beta_of(s.station.position, p), 1e-12);
    }
  }
  EXPECT_GE(of_kind(plan, StationReportKind::kRobotSawStation).size(), 50U);
}

TEST(BaseStation, AHitDelayedPastTheEndIsDropped) {
  Rig s;
  // The robot 4 m along the station's sweep middle, facing the station: the
  // station laser hits it at 0.88 s (-0.37 + 5/4), which asks for the
  // reserved slot of cycle 0 (sound at 0.25 + 6 x 0.15 s, trigger t0 sooner).
  const Pose robot{4.05, 5.0, kPi};
  const double ranging = 0.25 + 6 * 0.150 - s.t0;
  ASSERT_NEAR(fixed_hits(s.station.station_laser, 0.0, 2.0).at(0), 0.88, 1e-12);
  // The robot laser meets the station (body bearing 0, the middle of its
  // sweep, 0.75 s after the sweep's start) 0.1 ms after the ranging's strobe.
  s.station.robot_laser.phase_s = 0.75 - (ranging + 1e-4);
  for (const double end_s : {ranging + 5e-4, ranging + 2e-3}) {
    const StationPlan plan =
        plan_base_station(s.station, s.world, s.timing, stationary(robot), 0.25, end_s);
    check_plan_invariants(plan, s.station, end_s);
    ASSERT_EQ(of_kind(plan, StationReportKind::kRanging).size(), 1U);
    EXPECT_NEAR(of_kind(plan, StationReportKind::kRanging)[0].strobe_s, ranging, 1e-12);
    const std::vector<StationReport> beta = of_kind(plan, StationReportKind::kRobotSawStation);
    if (end_s < ranging + s.station.rf_spacing_s) {
      EXPECT_TRUE(beta.empty()) << "its strobe, 1 ms after the ranging's, is after the end";
    } else {
      ASSERT_EQ(beta.size(), 1U);
      EXPECT_NEAR(beta[0].hit_s, ranging + 1e-4, 1e-8);
      EXPECT_NEAR(beta[0].strobe_s, ranging + s.station.rf_spacing_s, 1e-12);
    }
  }
}

// Kleeman's schedule with reserved slots ----------------------------------------

TEST(BaseStation, KleemanScheduleLeavesTheReservedSlotsSilent) {
  KleemanTiming timing;
  EXPECT_NEAR(timing.cycle_s(), 0.9, 1e-12);  // unchanged without reserved slots
  timing.reserved_slots = 1;
  EXPECT_NEAR(timing.cycle_s(), 1.05, 1e-12);
  timing.reserved_slots = 3;
  EXPECT_NEAR(timing.cycle_s(), 1.35, 1e-12);
  timing.reserved_slots = 1;
  const Schedule s = odoloc::world::kleeman_schedule(timing, 4, 0.25);
  ASSERT_EQ(s.emissions.size(), 4U * 7);  // 6 beacons, beacon 0 twice
  std::size_t i = 0;
  for (long k = 0; k < 4; ++k)
    for (std::size_t b = 0; b < 6; ++b) {
      const long double slot = 0.25L + (7.0L * k + static_cast<long double>(b)) * 0.150L;
      EXPECT_EQ(s.emissions[i].beacon, b);
      EXPECT_NEAR(s.emissions[i].trigger_s, static_cast<double>(slot), 1e-12) << k << " " << b;
      ++i;
      if (b == 0) {
        EXPECT_NEAR(s.emissions[i].trigger_s, static_cast<double>(slot + 0.0055L), 1e-12);
        ++i;
      }
    }
}

// Parameters ------------------------------------------------------------------

TEST(BaseStation, BadParametersThrow) {
  const Rig good;
  const Trajectory robot = stationary({3, 4, 0});
  const auto plan = [&](const Rig& s, const Trajectory& r = {}, double end_s = 10) {
    return plan_base_station(s.station, s.world, s.timing, r ? r : robot, 0.25, end_s);
  };
  EXPECT_NO_THROW(plan(good));
  const auto bad = [&](auto change) {
    Rig s = good;
    change(s);
    EXPECT_THROW(plan(s), std::invalid_argument);
  };
  bad([](Rig& s) { s.station.transmitter = s.world.beacons.size(); });
  bad([](Rig& s) { s.timing.reserved_slots = 0; });
  bad([](Rig& s) { s.station.position.x_m = std::numeric_limits<double>::quiet_NaN(); });
  bad([](Rig& s) { s.station.position.y_m += 0.01; });  // transmitter elsewhere
  bad([](Rig& s) { s.world.beacons.back().mount = stationary({}); });
  bad([](Rig& s) { s.world.beacons.back().electronics_delay_s = -1e-3; });
  bad([](Rig& s) { s.station.station_laser.sweep_width_rad = 0; });
  bad([](Rig& s) { s.station.robot_laser.sweep_width_rad = 7; });
  bad([](Rig& s) { s.station.station_laser.period_s = 0; });
  bad([](Rig& s) { s.station.robot_laser.period_s = std::numeric_limits<double>::infinity(); });
  bad([](Rig& s) { s.station.robot_laser.phase_s = std::numeric_limits<double>::quiet_NaN(); });
  bad([](Rig& s) { s.station.station_laser.counts_per_rev = 0; });
  bad([](Rig& s) { s.station.rf_pulse_s = 0; });
  bad([](Rig& s) { s.station.rf_spacing_s = s.station.rf_pulse_s; });
  bad([](Rig& s) { s.station.pulse_s = 0.2; });  // longer than a 150 ms slot
  bad([](Rig& s) { s.station.request_margin_s = -1; });
  EXPECT_THROW(plan(good, robot, std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(plan(good, robot, -1), std::invalid_argument);
  EXPECT_THROW(plan_base_station(good.station, good.world, good.timing, Trajectory{}, 0.25, 10),
               std::invalid_argument);
  EXPECT_THROW(plan_base_station(good.station, good.world, good.timing, robot,
                                 std::numeric_limits<double>::quiet_NaN(), 10),
               std::invalid_argument);
}

}  // namespace
