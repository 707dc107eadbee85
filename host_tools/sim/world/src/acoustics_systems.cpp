// The three papers' set-ups for the acoustic world; readings of the papers
// in docs/acoustic-world.md.
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "odoloc/world/acoustic_systems.hpp"

namespace odoloc::world {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180;
constexpr double kInset = 0.05;  // beacons stand 5 cm in front of the walls

}  // namespace

Schedule kleeman_schedule(const KleemanTiming& timing, std::size_t cycles, double start_s) {
  if (timing.beacon_count + timing.reserved_slots == 0 || !(timing.pulse_s > 0) ||
      !(timing.timer_tick_s > 0) || timing.double_pulse_s < timing.pulse_s ||
      timing.double_pulse_s + timing.pulse_s > timing.fire_s() || timing.cycle_sync_s < 0)
    throw std::invalid_argument("kleeman_schedule: the pulses do not fit in a slot");
  Schedule s;
  for (std::size_t cycle = 0; cycle < cycles; ++cycle) {
    const double cycle_start = start_s + static_cast<double>(cycle) * timing.cycle_s();
    if (timing.cycle_sync_s > 0)
      s.sync.push_back({0, cycle_start, timing.cycle_sync_s});
    for (std::size_t b = 0; b < timing.beacon_count; ++b) {
      const double slot = cycle_start + static_cast<double>(b) * timing.fire_s();
      s.emissions.push_back({b, slot, timing.pulse_s});
      if (b == 0)
        s.emissions.push_back({b, slot + timing.double_pulse_s, timing.pulse_s});
    }
  }
  return s;
}

Schedule triggered_schedule(const TriggeredTiming& timing, std::size_t beacon_count,
                            std::size_t cycles, double start_s) {
  if (timing.repeats == 0 || !(timing.pulse_s > 0) || !(timing.sync_pulse_s > 0) ||
      timing.period_s < timing.pulse_s || !(timing.cycle_gap_s >= 0))
    throw std::invalid_argument("triggered_schedule: inconsistent timing");
  Schedule s;
  for (std::size_t cycle = 0; cycle < cycles; ++cycle)
    for (std::size_t b = 0; b < beacon_count; ++b)
      for (std::size_t r = 0; r < timing.repeats; ++r) {
        const double t = start_s + static_cast<double>(cycle) * timing.cycle_s(beacon_count) +
                         static_cast<double>(b * timing.repeats + r) * timing.period_s;
        s.sync.push_back({b, t, timing.sync_pulse_s});
        s.emissions.push_back({b, t, timing.pulse_s});
      }
  return s;
}

Room kleeman_room() {
  return Room{};  // 10 m x 10 m, reflection 0.9
}

std::vector<Beacon> kleeman_beacons(const Room& room) {
  const double w = room.width_m;
  const double d = room.depth_m;
  const auto beacon = [](Vec2 p, std::vector<double> axes_deg) {
    Beacon b;
    b.position = p;
    b.axes_rad.clear();
    for (const double a : axes_deg)
      b.axes_rad.push_back(a * kDegree);
    b.piston_radius_m = 6.6e-3;
    return b;
  };
  return {
      beacon({kInset, kInset}, {45}),           beacon({w / 2, kInset}, {45, 135}),
      beacon({w - kInset, kInset}, {135}),      beacon({w - kInset, d - kInset}, {-135}),
      beacon({w / 2, d - kInset}, {-45, -135}), beacon({kInset, d - kInset}, {-45}),
  };
}

std::vector<Receiver> kleeman_octagon(Vec2 centre, double side_m) {
  const double apothem = side_m / (2 * std::tan(kPi / 8));
  std::vector<Receiver> receivers;
  for (int i = 0; i < 8; ++i) {
    const double axis = i * 45 * kDegree;
    Receiver r;
    r.position = {centre.x_m + apothem * std::cos(axis), centre.y_m + apothem * std::sin(axis)};
    r.axis_rad = axis;
    r.piston_radius_m = 5.75e-3;
    receivers.push_back(r);
  }
  return receivers;
}

AcousticWorld kleeman_world() {
  AcousticWorld w;
  w.room = kleeman_room();
  w.beacons = kleeman_beacons(*w.room);
  w.receivers = kleeman_octagon();
  return w;
}

Obstacle direct_path_blocker(const AcousticWorld& world, Vec2 robot, std::size_t beacon,
                             double distance_m, double radius_m) {
  const Vec2 b = world.beacons.at(beacon).position;
  const double dx = b.x_m - robot.x_m;
  const double dy = b.y_m - robot.y_m;
  const double length = std::hypot(dx, dy);
  const Vec2 at{robot.x_m + distance_m * dx / length, robot.y_m + distance_m * dy / length};
  return {at, at, radius_m};
}

std::vector<Beacon> thamma_stations(const Room& room, double electronics_delay_s) {
  const double w = room.width_m;
  const double d = room.depth_m;
  const auto station = [electronics_delay_s](Vec2 p, double diagonal_deg, double carrier_hz) {
    Beacon b;
    b.position = p;
    b.axes_rad = {(diagonal_deg - 60) * kDegree, (diagonal_deg + 60) * kDegree};
    b.carrier_hz = carrier_hz;
    b.electronics_delay_s = electronics_delay_s;
    return b;
  };
  return {
      station({kInset, kInset}, 45, 40e3),
      station({w - kInset, kInset}, 135, 40e3),
      station({kInset, d - kInset}, -45, 32.5e3),
      station({w - kInset, d - kInset}, -135, 32.5e3),
  };
}

std::vector<Receiver> thamma_boxes(Vec2 head, Vec2 tail) {
  constexpr double kHalfLength = 0.06;  // 120 x 80 mm box
  constexpr double kHalfWidth = 0.04;
  std::vector<Receiver> receivers;
  for (const auto& [centre, resonance] : {std::pair{head, 40e3}, std::pair{tail, 32.5e3}})
    for (int side = 0; side < 4; ++side) {
      const double axis = side * 90 * kDegree;
      const double offset = side % 2 == 0 ? kHalfLength : kHalfWidth;
      Receiver r;
      r.position = {centre.x_m + offset * std::cos(axis), centre.y_m + offset * std::sin(axis)};
      r.axis_rad = axis;
      r.resonance_hz = resonance;
      receivers.push_back(r);
    }
  return receivers;
}

AcousticWorld thamma_world() {
  AcousticWorld w;
  w.room = kleeman_room();
  w.beacons = thamma_stations(*w.room);
  w.receivers = thamma_boxes();
  return w;
}

std::vector<Receiver> binaural_pair(double baseline_m) {
  std::vector<Receiver> receivers;
  for (const double x : {-baseline_m / 2, baseline_m / 2}) {
    Receiver r;
    r.position = {x, 0};
    r.axis_rad = kPi / 2;
    r.piston_radius_m = 19e-3;
    receivers.push_back(r);
  }
  return receivers;
}

AcousticWorld binaural_world(Trajectory transmitter_robot, double baseline_m) {
  AcousticWorld w;
  Beacon transmitter;
  transmitter.axes_rad = {kPi / 2};
  transmitter.piston_radius_m = 19e-3;
  transmitter.mount = std::move(transmitter_robot);
  w.beacons = {transmitter};
  w.receivers = binaural_pair(baseline_m);
  return w;
}

}  // namespace odoloc::world
