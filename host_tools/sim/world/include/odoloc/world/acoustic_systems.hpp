// The three papers' ultrasonic set-ups for the acoustic world
// (acoustics.hpp): Kleeman's sequenced beacons and receiver octagon,
// Thamma's RF-triggered base stations and head/tail receiver boxes, and the
// binaural pair. Readings of the papers and every default:
// docs/acoustic-world.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "odoloc/world/acoustics.hpp"

namespace odoloc::world {

// Kleeman: N beacons fire in strict sequence, one every t_fire = 2^16 timer
// ticks; each sends a 2.5 ms pulse, beacon 0 a double pulse whose second
// pulse starts t_double = 5.5 ms after the first (start to start).
struct KleemanTiming {
  std::size_t beacon_count = 6;
  double timer_tick_s = 0.150 / 65536;  // t_fire = 150 ms exactly
  std::uint32_t fire_ticks = 65536;     // t_fire in timer ticks
  double pulse_s = 2.5e-3;
  double double_pulse_s = 5.5e-3;
  // > 0: a sync pulse of this width from beacon 0 at each cycle start (a test
  // aid: Kleeman's robot has no link to the beacons).
  double cycle_sync_s = 0;
  // Slots after the last beacon's in which no beacon fires: a cycle lasts
  // (beacon_count + reserved_slots) t_fire. A base station's ranging pulse
  // (base_station.hpp) goes in the first one, so the receivers that also
  // serve the beacons never hear it in a beacon's slot.
  std::size_t reserved_slots = 0;

  [[nodiscard]] double fire_s() const { return timer_tick_s * fire_ticks; }
  [[nodiscard]] double cycle_s() const {
    return fire_s() * static_cast<double>(beacon_count + reserved_slots);
  }
};
// `cycles` beacon cycles from start_s: beacon i of cycle k is triggered at
// start_s + (k (N + R) + i) t_fire, R = reserved_slots (whose slots stay
// silent). N = 0 with R > 0 is a base station's timer alone (no
// emissions). Throws std::invalid_argument when the pulses do not fit in a
// slot or the cycle has no slot.
Schedule kleeman_schedule(const KleemanTiming& timing, std::size_t cycles, double start_s = 0);

// An RF-triggered transmitter: an RF sync pulse at each trigger, the
// ultrasound after the beacon's electronics delay. Thamma: each base station
// in turn, four times (the paper averages four times of flight); the
// binaural pair: one transmitter.
struct TriggeredTiming {
  std::size_t repeats = 4;
  double period_s = 0.1;  // trigger to trigger
  double pulse_s = 1e-3;
  double sync_pulse_s = 10e-6;
  // Silence after each cycle's last period: the robot frames the cycles on
  // it (which station a trigger is, by its place in the cycle).
  double cycle_gap_s = 0;

  // beacon_count stations, `repeats` triggers each, then the gap.
  [[nodiscard]] double cycle_s(std::size_t beacon_count) const {
    return static_cast<double>(beacon_count * repeats) * period_s + cycle_gap_s;
  }
};
// Beacon b, repeat r of a cycle is triggered at
// start_s + cycle * cycle_s(beacon_count) + (b * repeats + r) period_s.
Schedule triggered_schedule(const TriggeredTiming& timing, std::size_t beacon_count,
                            std::size_t cycles, double start_s = 0);

// Kleeman's laboratory: a 10 m square room, walls reflecting 0.9.
Room kleeman_room();
// Six beacons 5 cm in front of the walls, counter-clockwise from the corner
// (0, 0): corners 0, 2, 3, 5 aim along the diagonal; 1 and 4 sit mid-wall
// with two transducers at +-45 degrees from the wall's normal. Transmitter
// piston radius 6.6 mm: 20 dB down at 45 degrees off axis (Kleeman).
std::vector<Beacon> kleeman_beacons(const Room& room);
// Eight receivers on the faces of a regular octagon (side 50 mm) centred at
// `centre` (body frame), axes outward along the faces' normals, receiver i at
// i x 45 degrees (receiver 0 facing forward). Piston radius 5.75 mm: 3 dB down
// at 22.5 degrees (Kleeman).
std::vector<Receiver> kleeman_octagon(Vec2 centre = {}, double side_m = 0.05);
// Room, beacons and octagon at the robot's reference point.
AcousticWorld kleeman_world();
// An obstacle that hides beacon `beacon`'s direct path from a robot at
// `robot` (world frame): a disc of radius_m on the line of sight, distance_m
// from the robot, wide enough to shadow a receiver array of Kleeman's
// octagon's size. The first wavefront the robot hears from that beacon is
// then a wall echo, or nothing. Throws std::out_of_range for a beacon the
// world does not have.
Obstacle direct_path_blocker(const AcousticWorld& world, Vec2 robot, std::size_t beacon,
                             double distance_m = 0.4, double radius_m = 0.1);

// Thamma: four base stations at the room's corners (5 cm in), each a pair of
// transducers 120 degrees apart aimed about the diagonal; stations 0, 1 (at
// y = 0) at 40 kHz, stations 2, 3 at 32.5 kHz.
std::vector<Beacon> thamma_stations(const Room& room, double electronics_delay_s = 100e-6);
// Two 120 x 80 mm boxes with a receiver on each side (axes forward, left,
// back, right): the head box (channels 0-3) at 40 kHz, the tail box
// (channels 4-7) at 32.5 kHz.
std::vector<Receiver> thamma_boxes(Vec2 head = {0.6, 0}, Vec2 tail = {-0.2, 0});
// Kleeman's room, the four stations and the two boxes.
AcousticWorld thamma_world();

// The binaural pair in the paper's frame: receivers at (-b/2, 0) and
// (+b/2, 0), both looking along +y; Polaroid-size pistons (19 mm radius).
std::vector<Receiver> binaural_pair(double baseline_m = 0.35);
// Free field: the transmitter at the origin of the other robot's frame
// (`transmitter_robot`), looking along its +y, and the pair on this robot.
AcousticWorld binaural_world(Trajectory transmitter_robot, double baseline_m = 0.35);

}  // namespace odoloc::world
