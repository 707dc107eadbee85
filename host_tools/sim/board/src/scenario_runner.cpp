#include "odoloc/board/scenario_runner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "odoloc/board/encoder_pins.hpp"

namespace odoloc::board {

namespace {

sw::EncoderGeometry nominal(const world::WheelEncoder& w) {
  return {w.nominal_radius_m, static_cast<double>(w.lines), w.gear, 4};
}

world::Pose fabric_pose(const rtl::PoseIntegrator::Regs& p) {
  return {sw::pose_metres(rtl::pose_coordinate(p.x).value()),
          sw::pose_metres(rtl::pose_coordinate(p.y).value()), sw::heading_radians(p.theta.value())};
}

}  // namespace

sw::VehicleGeometry nominal_geometry(const world::Geometry& g) {
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
                                    MinSelectTuning tuning) {
  using rtl::UInt;
  const sw::OdometryScales s = sw::odometry_scales(v);
  rtl::OdometryConfig o;
  o.cfg.policy = UInt<2>{rtl::encoding(policy)};
  o.rear_ds_scale.value = UInt<32>{s.rear_ds};
  o.rear_dtheta_scale.value = UInt<32>{s.rear_dtheta};
  o.front_ds_scale.value = UInt<32>{s.front_ds};
  o.front_dtheta_scale.value = UInt<32>{s.front_dtheta};
  o.steer_scale.value = UInt<32>{s.steer};
  o.steer_limit.value = UInt<32>{s.steer_limit};
  if (tuning == MinSelectTuning::kReset)
    return o;
  const sw::MinSelectSetup m =
      tuning == MinSelectTuning::kPaper ? sw::MinSelectSetup{0, 0, 0} : sw::min_select_setup(v);
  o.cfg.select_shift = UInt<4>{m.shift};
  o.select_ds_threshold.value = UInt<32>{m.ds_threshold};
  o.select_dtheta_threshold.value = UInt<32>{m.dtheta_threshold};
  return o;
}

RunResult run_scenario(const world::Scenario& scenario, const RunOptions& options) {
  world::Options truth_options;
  truth_options.start = scenario.start;
  world::TricycleSimulator truth(scenario.geometry, scenario.path, scenario.disturbances,
                                 truth_options);
  // The fabric's configuration ports, set directly (no register traffic):
  // the vehicle, and the start pose that command.set_pose loads.
  rtl::OdometryFabric::Config cfg;
  cfg.odometry =
      odometry_config(nominal_geometry(scenario.geometry), options.policy, options.tuning);
  cfg.odometry.set_x.bits = rtl::SInt<64>{sw::metres_to_pose(scenario.start.x_m)};
  cfg.odometry.set_y.bits = rtl::SInt<64>{sw::metres_to_pose(scenario.start.y_m)};
  cfg.odometry.set_theta.bits = rtl::UInt<40>{sw::radians_to_heading(scenario.start.theta_rad)};
  rtl::OdometryFabric fabric;
  rtl::OdometryFabric::In in{};
  in.odometry.command.set_pose = rtl::UInt<1>{1};
  fabric.step(in, cfg);
  in.odometry.command.set_pose = rtl::UInt<1>{};

  RunResult result{};
  result.policy = options.policy;
  std::uint64_t updates_seen = 0;
  const std::uint64_t update_clocks = cfg.odometry.cfg.update_clocks.value();
  // n clocks with the pins held, fast-forwarded (or stepped) in pieces that
  // end at each period end and each track point, so that every update's
  // report and every track point is seen.
  const auto run = [&](std::uint64_t n) {
    while (n != 0) {
      std::uint64_t piece = n;
      if (update_clocks != 0)
        piece = std::min(piece, 1 + rtl::clocks_to_fire(fabric.sequencer().period_count.value(),
                                                        update_clocks - 1));
      if (options.record_every_clocks != 0)
        piece = std::min(piece,
                         options.record_every_clocks - result.clocks % options.record_every_clocks);
      if (options.cycle_step) {
        for (std::uint64_t k = 0; k < piece; ++k)
          fabric.step(in, cfg);
      } else {
        result.skipped_clocks += rtl::fast_forward(fabric, piece, in, cfg);
      }
      n -= piece;
      result.clocks += piece;
      const std::uint64_t updates = fabric.sequencer().updates.value();
      if (updates != updates_seen) {  // at most one update per piece
        updates_seen = updates;
        result.front_wins_ds += fabric.report().ds_from_front.value();
      }
      if (options.record_every_clocks != 0 && result.clocks % options.record_every_clocks == 0) {
        result.track.push_back({static_cast<double>(result.clocks) / sw::kFabricClockHz,
                                truth.pose().pose, fabric_pose(fabric.pose())});
      }
    }
  };
  const std::uint64_t end_clock =
      options.max_seconds > 0
          ? static_cast<std::uint64_t>(std::ceil(options.max_seconds * sw::kFabricClockHz))
          : std::numeric_limits<std::uint64_t>::max();
  const auto stopped = [&] { return options.stop != nullptr && options.stop->load(); };
  while (!truth.done() && result.clocks < end_clock && !stopped()) {
    drive_encoder_pins(in.pins, truth.tick());
    run(1);
    // The ticks that repeat these levels, at once.
    const std::uint64_t hold = truth.hold_ticks();
    truth.skip(hold);
    run(hold);
  }
  // Standing still: two more periods take in every edge still in flight.
  run(2 * update_clocks);

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

}  // namespace odoloc::board
