// The fabric's odometry over the register bus (docs/odometry.md): the
// vehicle's scales and min-select setup written once, the pose set, and
// each read one snapshot of the pose, the last update's increments and
// min-select's choices, in SI units. What the fusion filter predicts from
// (increment_between two reads' poses, docs/fusion.md).
#pragma once

#include <cstdint>

#include "odoloc/regs.hpp"
#include "odoloc/sw/odometry_setup.hpp"
#include "odoloc/sw/register_bus.hpp"

namespace odoloc::sw {

using OdometryPolicy = regs::odometry::cfg::Policy;

// One read of the odometry block. Poses: x, y in m, theta in rad in
// [-pi, pi); increments of the last update: ds in m, dtheta in rad.
struct FabricOdometry {
  std::uint32_t updates = 0;  // completed pose updates (wraps at 2^32)
  double x_m = 0, y_m = 0, theta_rad = 0;
  double rear_ds_m = 0, rear_dtheta_rad = 0;    // the rear unit's
  double front_ds_m = 0, front_dtheta_rad = 0;  // the front unit's
  double ds_m = 0, dtheta_rad = 0;              // min-select's (integrated)
  double steer_rad = 0;                         // clamped steering angle of the update
  bool ds_from_front = false, dtheta_from_front = false;
  bool overrun = false, steer_clamped = false;  // sticky flags
};

class OdometryDriver {
 public:
  explicit OdometryDriver(RegisterBus& bus) : bus_(bus) {}

  // Writes the scales (odometry_scales: std::domain_error if the geometry
  // does not fit), the min-select thresholds, the control period (fabric
  // clocks, 0 stops updates) and the policy; BusError if refused.
  void configure(const VehicleGeometry& vehicle, const MinSelectSetup& select,
                 std::uint16_t update_clocks = 5000,
                 OdometryPolicy policy = OdometryPolicy::kPerComponent);
  // Loads (x m, y m, theta rad) into the fabric's pose (command.set_pose).
  void set_pose(double x_m, double y_m, double theta_rad);
  // One burst read of the snapshot registers, from `updates` to `steer_phi`.
  [[nodiscard]] FabricOdometry read();

 private:
  RegisterBus& bus_;
};

}  // namespace odoloc::sw
