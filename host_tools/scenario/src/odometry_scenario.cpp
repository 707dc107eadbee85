#include "odoloc/scenario/odometry_scenario.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace odoloc::scenario {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

sw::EncoderGeometry nominal(const sim::WheelEncoder& w) {
  return {w.nominal_radius_m, static_cast<double>(w.lines), w.gear, 4};
}

sim::Disturbances merged(std::initializer_list<sim::Disturbances> parts) {
  sim::Disturbances all;
  for (const auto& p : parts) {
    all.bumps.insert(all.bumps.end(), p.bumps.begin(), p.bumps.end());
    all.slips.insert(all.slips.end(), p.slips.begin(), p.slips.end());
  }
  return all;
}

sim::Pose fabric_pose(const rtl::PoseIntegrator::Regs& p) {
  return {sw::pose_metres(p.x.value()), sw::pose_metres(p.y.value()),
          sw::heading_radians(p.theta.value())};
}

// Bumps of 2.5 cm over 30 cm: each adds bump_extra_length (about 5 mm) of roll.
constexpr double kBumpHeight = 0.025;
constexpr double kBumpLength = 0.30;

}  // namespace

const char* name(BumpCase c) {
  switch (c) {
    case BumpCase::kNone:
      return "no disturbance";
    case BumpCase::kBothRear:
      return "both rear wheels over bumps";
    case BumpCase::kOneRear:
      return "one rear wheel over bumps";
    case BumpCase::kFront:
      return "front wheel over bumps";
  }
  return "?";
}

Scenario bump_scenario(BumpCase c, double metres, double heading_rad) {
  Scenario s{name(c), {}, sim::straight_path(metres, 1.0), {}, {0.5, -0.25, heading_rad}};
  for (const double at : {0.2 * metres, 0.5 * metres, 0.8 * metres}) {
    switch (c) {
      case BumpCase::kNone:
        break;
      case BumpCase::kBothRear:
        s.disturbances =
            merged({s.disturbances, sim::bump_under_both_rear(at, kBumpHeight, kBumpLength)});
        break;
      case BumpCase::kOneRear:
        s.disturbances =
            merged({s.disturbances,
                    sim::bump_under_one_rear(sim::Wheel::kLeftRear, at, kBumpHeight, kBumpLength)});
        break;
      case BumpCase::kFront:
        s.disturbances =
            merged({s.disturbances, sim::bump_under_front(at, kBumpHeight, kBumpLength)});
        break;
    }
  }
  return s;
}

Scenario default_square() {
  Scenario s;
  s.name = "6 m square (24 m perimeter, rounded corners) with bumps and slip";
  s.path = sim::square_path(s.geometry, 6.0, 1.0, 30.0 * kDeg);
  s.disturbances = merged({
      sim::bump_under_both_rear(2.0, kBumpHeight, kBumpLength),
      sim::bump_under_one_rear(sim::Wheel::kRightRear, 9.0, kBumpHeight, kBumpLength),
      sim::bump_under_front(15.0, kBumpHeight, kBumpLength),
      sim::Disturbances{{}, {sim::Slip{sim::Wheel::kFrontDrive, 19.0, 20.0, 0.05}}},
  });
  return s;
}

sw::VehicleGeometry nominal_geometry(const sim::Geometry& g) {
  if (g.left_rear.nominal_radius_m != g.right_rear.nominal_radius_m ||
      g.left_rear.lines != g.right_rear.lines || g.left_rear.gear != g.right_rear.gear) {
    throw std::invalid_argument("the rear unit has one scale: rear wheels must be nominally equal");
  }
  sw::VehicleGeometry v;
  v.rear_track_m = g.track_m;
  v.wheelbase_m = g.wheelbase_m;
  v.rear = nominal(g.left_rear);
  v.front = nominal(g.front);
  v.steering = {static_cast<double>(g.steering.lines), g.steering.gear, 4};
  v.steer_limit_rad = g.steering.limit_rad;
  return v;
}

rtl::OdometryConfig odometry_config(const sw::VehicleGeometry& v, rtl::MinSelectPolicy policy,
                                    bool paper_min_select) {
  const sw::OdometryScales s = sw::odometry_scales(v);
  const sw::MinSelectSetup m =
      paper_min_select ? sw::MinSelectSetup{0, 0, 0} : sw::min_select_setup(v);
  rtl::OdometryConfig o;
  o.rear_ds_scale = rtl::UInt<32>{s.rear_ds};
  o.rear_dtheta_scale = rtl::UInt<32>{s.rear_dtheta};
  o.front_ds_scale = rtl::UInt<32>{s.front_ds};
  o.front_dtheta_scale = rtl::UInt<32>{s.front_dtheta};
  o.steer_scale = rtl::UInt<32>{s.steer};
  o.steer_limit = rtl::UInt<32>{s.steer_limit};
  o.policy = rtl::UInt<2>{static_cast<unsigned>(policy)};
  o.select_shift = rtl::UInt<4>{m.shift};
  o.select_ds_threshold = rtl::UInt<32>{m.ds_threshold};
  o.select_dtheta_threshold = rtl::UInt<32>{m.dtheta_threshold};
  return o;
}

RunResult run(const Scenario& scenario, const RunOptions& options) {
  sim::Options sim_options;
  sim_options.start = scenario.start;
  sim::TricycleSimulator truth(scenario.geometry, scenario.path, scenario.disturbances,
                               sim_options);
  rtl::OdometryFabricConfig cfg;
  cfg.odometry = odometry_config(nominal_geometry(scenario.geometry), options.policy,
                                 options.paper_min_select);
  rtl::OdometryFabric fabric;
  rtl::OdometryFabric::Inputs in{};
  in.set_pose = rtl::UInt<1>{1};
  in.pose = {rtl::SInt<64>{sw::metres_to_pose(scenario.start.x_m)},
             rtl::SInt<64>{sw::metres_to_pose(scenario.start.y_m)},
             rtl::UInt<40>{sw::radians_to_heading(scenario.start.theta_rad)}};
  fabric.step(in, cfg);
  in.set_pose = rtl::UInt<1>{};

  RunResult result{};
  result.policy = options.policy;
  std::uint64_t updates_seen = 0;
  const auto clock_once = [&] {
    fabric.step(in, cfg);
    const std::uint64_t updates = fabric.sequencer().updates.value();
    if (updates != updates_seen) {
      updates_seen = updates;
      result.front_wins_ds += fabric.select().ds_from_front.value();
    }
    ++result.clocks;
    if (options.record_every_clocks != 0 && result.clocks % options.record_every_clocks == 0) {
      result.track.push_back({static_cast<double>(result.clocks) / sw::kFabricClockHz,
                              truth.pose().pose, fabric_pose(fabric.pose())});
    }
  };
  while (!truth.done()) {
    in.pins = truth.tick();
    clock_once();
  }
  // Standing still: two more periods take in every edge still in flight.
  for (std::uint64_t i = 0; i < 2 * cfg.odometry.update_clocks.value(); ++i)
    clock_once();

  result.truth = truth.pose().pose;
  result.fabric = fabric_pose(fabric.pose());
  result.position_error_m =
      std::hypot(result.fabric.x_m - result.truth.x_m, result.fabric.y_m - result.truth.y_m);
  result.heading_error_rad =
      std::remainder(result.fabric.theta_rad - result.truth.theta_rad, 2 * std::numbers::pi);
  result.distance_m = truth.distance();
  result.updates = updates_seen;
  return result;
}

}  // namespace odoloc::scenario
