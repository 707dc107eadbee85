// The whole localisation system's world (the main job and `odoloc sim`):
// the ground-truth tricycle driving its path in a room, with Kleeman's
// beacons, the receivers, wall echoes, obstacles, turbulence and noise
// pulses, and optionally Liu's base station (scanning lasers, a ranging
// burst in a reserved slot). Scenario files describe it
// (odoloc/sim/scenario_file.hpp, docs/scenarios.md); the main job's is
// examples/scenarios/room-tour.yaml.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"
#include "odoloc/world/base_station.hpp"
#include "odoloc/world/scenarios.hpp"

namespace odoloc::world {

// Thamma's RF-triggered stations: every acoustics.beacons entry is one, in
// firing order (the tour then has no Kleeman beacons and no base station).
struct ThammaStations {
  TriggeredTiming timing;
  double first_trigger_s = 0.013;  // the first cycle's first trigger
};

struct RoomTour {
  std::string name;
  Scenario drive;  // the robot, its path (waits, laps) and the disturbances
  AcousticWorld acoustics;
  KleemanTiming timing;
  // Its transmitter is acoustics.beacons[station->transmitter], after
  // Kleeman's (timing.beacon_count); it bursts in timing's reserved slot.
  std::optional<BaseStation> station;
  std::optional<ThammaStations> thamma;
  double first_burst_s = 0.013;  // the beacons' first cycle, not at the chip's reset
  double duration_s = 0;         // the path's length in time, with the waits: the run ends here

  // The base station's packets and bursts for the robot's trajectory (none
  // without a station).
  [[nodiscard]] StationPlan station_plan(const Trajectory& robot) const;
  // Every burst and RF strobe of the run: Kleeman's beacons', then the
  // plan's, or Thamma's stations' triggers.
  [[nodiscard]] Schedule schedule(const StationPlan& plan) const;
};

}  // namespace odoloc::world
