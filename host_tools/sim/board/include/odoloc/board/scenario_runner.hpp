// The scenario runner: the ground-truth tricycle drives a scenario
// (odoloc/world/scenarios.hpp), its encoder waveforms go clock by clock into
// the odometry fabric, and the fabric's pose is compared with the truth. Used
// by the demo (the main job) and by the scenario testbenches.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/sw/odometry_setup.hpp"
#include "odoloc/world/scenarios.hpp"
#include "odoloc/world/tricycle.hpp"

namespace odoloc::board {

// What the fabric should be told about the vehicle: the nominal geometry.
sw::VehicleGeometry nominal_geometry(const world::Geometry& g);
// How min-select's memory and thresholds are set: for the vehicle
// (sw::min_select_setup), the paper's memoryless rule, or left at the
// register resets (tuned for the reference sw::VehicleGeometry).
enum class MinSelectTuning : std::uint8_t { kVehicle, kPaper, kReset };
// The odometry registers for a vehicle.
rtl::OdometryConfig odometry_config(const sw::VehicleGeometry& v, rtl::MinSelectPolicy policy,
                                    MinSelectTuning tuning = MinSelectTuning::kVehicle);

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
  std::uint64_t skipped_clocks;  // fast-forwarded rather than stepped (0 with cycle_step)
  std::uint64_t updates;
  std::uint64_t front_wins_ds;   // updates whose distance came from the front unit
  std::vector<PosePoint> track;  // every `record_every_clocks`
};

struct RunOptions {
  rtl::MinSelectPolicy policy = rtl::MinSelectPolicy::kPerComponent;
  MinSelectTuning tuning = MinSelectTuning::kVehicle;
  std::uint64_t record_every_clocks = 0;  // 0: no track
  bool cycle_step = false;  // step every clock instead of fast-forwarding (bit-identical, slower)
  double max_seconds = 0;   // > 0: stop the drive after this much simulated time
  // Set meanwhile (a signal): the drive ends at the next tick, the result
  // covers the time run so far.
  const std::atomic<bool>* stop = nullptr;
};

RunResult run_scenario(const world::Scenario& scenario, const RunOptions& options);

}  // namespace odoloc::board
