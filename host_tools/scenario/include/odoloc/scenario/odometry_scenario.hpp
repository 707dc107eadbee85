// Odometry scenarios: the ground-truth tricycle drives a path, its encoder
// waveforms go clock by clock into the odometry fabric, and the fabric's pose
// is compared with the truth. Used by the demo (the main job) and by the
// scenario testbenches.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/sim/tricycle.hpp"
#include "odoloc/sw/odometry_setup.hpp"

namespace odoloc::scenario {

struct Scenario {
  std::string name;
  sim::Geometry geometry;
  sim::Path path;
  sim::Disturbances disturbances;
  sim::Pose start;
};

// The paper's Fig. 4 disturbances on a straight run, and no disturbance.
enum class BumpCase : std::uint8_t { kNone, kBothRear, kOneRear, kFront };
const char* name(BumpCase c);

// A straight drive of `metres` at `heading_rad` with the case's bumps.
Scenario bump_scenario(BumpCase c, double metres = 2.0, double heading_rad = 0.5);
// The default of the demo: a 24 m square (6 m sides, rounded corners) with
// one disturbance of each kind along the way.
Scenario default_square();

// What the fabric should be told about the vehicle: the nominal geometry.
sw::VehicleGeometry nominal_geometry(const sim::Geometry& g);
// The odometry registers for a vehicle; min-select tuned by
// sw::min_select_setup unless `paper_min_select` asks for the paper's rule.
rtl::OdometryConfig odometry_config(const sw::VehicleGeometry& v, rtl::MinSelectPolicy policy,
                                    bool paper_min_select = false);

struct PosePoint {
  double time_s;
  sim::Pose truth;
  sim::Pose fabric;
};

struct RunResult {
  rtl::MinSelectPolicy policy;
  sim::Pose truth;   // final
  sim::Pose fabric;  // final, after the last update
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

RunResult run(const Scenario& scenario, const RunOptions& options);

}  // namespace odoloc::scenario
