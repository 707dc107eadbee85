// The scenario runner: the ground-truth tricycle drives a scenario
// (odoloc/world/scenarios.hpp), its encoder waveforms go clock by clock into
// the odometry fabric, and the fabric's pose is compared with the truth. Used
// by the demo (the main job) and by the scenario testbenches.
#pragma once

#include <cstdint>
#include <vector>

#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/sw/odometry_setup.hpp"
#include "odoloc/world/scenarios.hpp"
#include "odoloc/world/tricycle.hpp"

namespace odoloc::board {

// What the fabric should be told about the vehicle: the nominal geometry.
sw::VehicleGeometry nominal_geometry(const world::Geometry& g);
// The odometry registers for a vehicle; min-select tuned by
// sw::min_select_setup unless `paper_min_select` asks for the paper's rule.
rtl::OdometryConfig odometry_config(const sw::VehicleGeometry& v, rtl::MinSelectPolicy policy,
                                    bool paper_min_select = false);

struct PosePoint {
  double time_s;
  world::Pose truth;
  world::Pose fabric;
};

struct RunResult {
  rtl::MinSelectPolicy policy;
  world::Pose truth;   // final
  world::Pose fabric;  // final, after the last update
  double position_error_m;
  double heading_error_rad;
  double distance_m;  // rear-midpoint path length
  std::uint64_t clocks;
  std::uint64_t updates;
  std::uint64_t front_wins_ds;   // updates whose distance came from the front unit
  std::vector<PosePoint> track;  // every `record_every_clocks`
};

struct RunOptions {
  rtl::MinSelectPolicy policy = rtl::MinSelectPolicy::kPerComponent;
  bool paper_min_select = false;          // the memoryless rule instead of the leaky one
  std::uint64_t record_every_clocks = 0;  // 0: no track
};

RunResult run_scenario(const world::Scenario& scenario, const RunOptions& options);

}  // namespace odoloc::board
