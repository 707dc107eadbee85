// Scenario definitions: a vehicle, a path, its disturbances and its start
// pose, ready for the ground-truth tricycle. The demo, the host tool's
// simulated board and the scenario testbenches drive them; the board's
// scenario runner (odoloc/board/scenario_runner.hpp) feeds them to the fabric.
#pragma once

#include <cstdint>
#include <string>

#include "odoloc/world/tricycle.hpp"

namespace odoloc::world {

struct Scenario {
  std::string name;
  Geometry geometry;
  Path path;
  Disturbances disturbances;
  Pose start;
};

// The paper's Fig. 4 disturbances on a straight run, and no disturbance.
enum class BumpCase : std::uint8_t { kNone, kBothRear, kOneRear, kFront };
const char* name(BumpCase c);

// A straight drive of `metres` at `heading_rad` with the case's bumps.
Scenario bump_scenario(BumpCase c, double metres = 2.0, double heading_rad = 0.5);
// The default of the demo: a 24 m square (6 m sides, rounded corners) with
// one disturbance of each kind along the way.
Scenario default_square();
// Laps of the same square at 1 m/s, without disturbances, for at least
// `seconds` (whole laps): the long drive of the fast-forward benchmark.
Scenario patrol(double seconds);

}  // namespace odoloc::world
