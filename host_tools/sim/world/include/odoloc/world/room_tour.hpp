// The whole localisation system's world (the main job and `odoloc sim`):
// the ground-truth tricycle driving a closed path in Kleeman's 10 m room,
// with its six beacons, the receiver octagon, wall echoes, a cabinet that
// hides a beacon from part of the path, turbulence and noise pulses, and
// Liu's base station (scanning lasers, a ranging burst in a reserved slot).
// Choices and their sources: docs/simulator.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"
#include "odoloc/world/base_station.hpp"
#include "odoloc/world/scenarios.hpp"

namespace odoloc::world {

struct RoomTour {
  std::string name;
  Scenario drive;  // the robot, its path (waits, laps) and the disturbances
  AcousticWorld acoustics;
  KleemanTiming timing;
  // Its transmitter is acoustics.beacons[station->transmitter], after
  // Kleeman's (timing.beacon_count); it bursts in timing's reserved slot.
  std::optional<BaseStation> station;
  double first_burst_s = 0.013;  // the beacons' first cycle, not at the chip's reset
  double duration_s = 0;         // the path's length in time, with the waits: the run ends here

  // The base station's packets and bursts for the robot's trajectory (none
  // without a station).
  [[nodiscard]] StationPlan station_plan(const Trajectory& robot) const;
  // Every burst and RF strobe of the run: Kleeman's beacons', then the
  // plan's.
  [[nodiscard]] Schedule schedule(const StationPlan& plan) const;
};

// Laps of the 6 m square (rounded corners, 30 degree steering) at
// speed_mps, starting and ending at (2 m, 2 m, heading 0) inside Kleeman's
// room: the robot waits wait_s at the start (the first ultrasonic fix is
// taken standing) and at the end (the return-to-start reading). Per lap a
// bump under both rear wheels, one under the right rear, one under the
// front and a front-wheel slip (the demo's); the wheels' true radii differ
// from the nominal ones the odometry knows (left rear +0.2 %, right rear
// -0.1 %, front +0.4 %), as real wheels do (Borenstein's systematic errors).
// The acoustics: Kleeman's world with turbulence (3 us per path, 1 us per
// receiver), two noise pulses per second per channel and a cabinet beyond
// the path's (8, 2) corner that hides beacon 2 (the (10, 0) corner) from
// the robot as it rounds that corner: its first arrival is then an echo.
// Liu's base station stands at the middle of the x = 0 wall, 0.3 m out
// (where no beacon is), its laser sweeping the room (160 degrees), the
// robot's laser sweeping 340 degrees of its own frame, both in Liu's 5 s
// with Liu's 1000-count encoders; its ranging burst goes in a seventh,
// reserved slot of the beacon cycle (1.05 s).
// Throws std::invalid_argument for laps < 1 or a speed outside (0, 1.5].
RoomTour room_tour(std::size_t laps = 2, double speed_mps = 0.5, double wait_s = 3.0);

}  // namespace odoloc::world
