// Kleeman's stationary experiment (docs/scenarios.md, "stationary"): the
// robot standing at a point while the whole system runs (the world, the
// chip at its pins, the SoC software), and the spread of the ultrasonic
// fixes alone there, measured as Kleeman measures it: the standard
// deviations in x and y of his N fixes at the point.
#pragma once

#include <cstddef>
#include <vector>

#include "odoloc/sim/scenario_file.hpp"
#include "odoloc/sim/system.hpp"

namespace odoloc::sim {

struct Standing {
  world::Vec2 truth;               // where the robot stands
  std::vector<world::Vec2> fixes;  // the valid ultrasonic fixes, in order
  std::size_t cycles = 0;          // the beacon cycles the SoC decoded meanwhile
  world::Vec2 mean_m;              // the fixes' mean (NaN without fixes)
  world::Vec2 sd_m;    // their sample standard deviations in x and y (n - 1; NaN below 2)
  double worst_m = 0;  // the largest distance of a fix from the truth (NaN without)
};

// `scenario`'s world with its robot set down at `point` (heading 0, the
// start mark the SoC is told), standing long enough for `fixes` fixes (a
// quarter more beacon cycles, and five, for the first cycles, which the
// decoder needs to find beacon 0, and the cycles without a fix).
[[nodiscard]] Scenario standing_at(const Scenario& scenario, world::Vec2 point, std::size_t fixes);
// Runs standing_at() until `fixes` valid fixes (or its end: fewer then).
// Throws what LocalisationSystem throws; process::Interrupted at options.stop.
[[nodiscard]] Standing measure_standing(const Scenario& scenario, world::Vec2 point,
                                        std::size_t fixes, const SystemOptions& options);

}  // namespace odoloc::sim
