#include "odoloc/world/room_tour.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace odoloc::world {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// How long a path takes: each segment's distance over its speed, its
// duration, or its steering move at the path's rate (the steering starts
// straight and carries over).
double path_seconds(const Path& path) {
  double seconds = 0;
  double steer = 0;
  for (const Segment& s : path.segments) {
    switch (s.end) {
      case Segment::End::kDistance:
        seconds += s.amount / std::abs(s.speed_mps);
        break;
      case Segment::End::kDuration:
        seconds += s.amount;
        break;
      case Segment::End::kSteered:
        seconds += std::abs(s.steer_rad - steer) / path.steer_rate_radps;
        break;
    }
    if (s.end == Segment::End::kSteered)
      steer = s.steer_rad;
  }
  return seconds;
}

}  // namespace

StationPlan RoomTour::station_plan(const Trajectory& robot) const {
  if (!station)
    return {};
  return plan_base_station(*station, acoustics, timing, robot, first_burst_s, duration_s);
}

Schedule RoomTour::schedule(const StationPlan& plan) const {
  const auto cycles =
      static_cast<std::size_t>(std::ceil((duration_s - first_burst_s) / timing.cycle_s()));
  Schedule s = kleeman_schedule(timing, cycles, first_burst_s);
  s.emissions.insert(s.emissions.end(), plan.schedule.emissions.begin(),
                     plan.schedule.emissions.end());
  s.sync.insert(s.sync.end(), plan.schedule.sync.begin(), plan.schedule.sync.end());
  return s;
}

RoomTour room_tour(std::size_t laps, double speed_mps, double wait_s) {
  if (laps < 1)
    throw std::invalid_argument("room_tour: at least one lap");
  if (!(speed_mps > 0 && speed_mps <= 1.5))
    throw std::invalid_argument("room_tour: the speed must be in (0, 1.5] m/s");
  if (!(wait_s >= 0))
    throw std::invalid_argument("room_tour: the wait must be >= 0 s");
  RoomTour tour;
  tour.name = std::to_string(laps) + " laps of the 6 m square in Kleeman's room";
  Scenario& drive = tour.drive;
  drive.name = tour.name;
  drive.start = {2.0, 2.0, 0.0};
  drive.geometry.left_rear.true_radius_m = drive.geometry.left_rear.nominal_radius_m * 1.002;
  drive.geometry.right_rear.true_radius_m = drive.geometry.right_rear.nominal_radius_m * 0.999;
  drive.geometry.front.true_radius_m = drive.geometry.front.nominal_radius_m * 1.004;
  const Path lap = square_path(drive.geometry, 6.0, speed_mps, 30.0 * kDeg);
  drive.path.steer_rate_radps = lap.steer_rate_radps;
  drive.path.segments.push_back(Segment::duration(0, 0, wait_s));
  // The odometer of one lap: four straights and four quarter turns.
  const double radius = drive.geometry.wheelbase_m / std::tan(30.0 * kDeg);
  const double lap_m = 4 * (6.0 - 2 * radius) + 2 * std::numbers::pi * radius;
  for (std::size_t l = 0; l < laps; ++l) {
    drive.path.segments.insert(drive.path.segments.end(), lap.segments.begin(), lap.segments.end());
    const double at = static_cast<double>(l) * lap_m;
    constexpr double kHeight = 0.025, kLength = 0.30;  // as the demo's square
    for (const Disturbances& d :
         {bump_under_both_rear(at + 2.0, kHeight, kLength),
          bump_under_one_rear(Wheel::kRightRear, at + 9.0, kHeight, kLength),
          bump_under_front(at + 15.0, kHeight, kLength)})
      drive.disturbances.bumps.insert(drive.disturbances.bumps.end(), d.bumps.begin(),
                                      d.bumps.end());
    drive.disturbances.slips.push_back(Slip{Wheel::kFront, at + 19.0, at + 20.0, 0.05});
  }
  drive.path.segments.push_back(Segment::duration(0, 0, wait_s));
  tour.duration_s = path_seconds(drive.path);

  tour.acoustics = kleeman_world();
  tour.acoustics.noise.path_jitter_sd_s = 3e-6;
  tour.acoustics.noise.receiver_jitter_sd_s = 1e-6;
  tour.acoustics.noise.noise_rate_hz = 0.5;
  // Kleeman's transmitters give 12.5 V at 1 m: from the path's corners the
  // far corner beacons (up to 11.3 m) would reach the threshold on one
  // receiver at most. Driven 6 dB harder, two or three receivers hear them.
  for (Beacon& b : tour.acoustics.beacons)
    b.amplitude_1m_v = 25;
  // A cabinet front across the line from the path's (8, 2) corner to
  // beacon 2 (the (10, 0) corner), 1.2 m beyond the corner: off the line
  // from the start.
  tour.acoustics.obstacles.push_back({{8.75, 0.55}, {9.45, 1.25}, 0.02});

  // Liu's base station. Its transmitter rotates with its laser in Liu's;
  // here it bursts up to a cycle after the hit, so five transducers 45
  // degrees apart face the whole room (as Kleeman's mid-wall pairs, wider),
  // at the beacons' height.
  BaseStation& station = tour.station.emplace();
  station.position = {0.3, 5.0};
  station.transmitter = tour.acoustics.beacons.size();
  Beacon transmitter = tour.acoustics.beacons.front();
  transmitter.position = station.position;
  transmitter.axes_rad = {-90 * kDeg, -45 * kDeg, 0, 45 * kDeg, 90 * kDeg};
  transmitter.electronics_delay_s = 2e-3;  // Liu's t0
  tour.acoustics.beacons.push_back(transmitter);
  tour.timing.reserved_slots = 1;
  station.station_laser.sweep_start_rad = -80 * kDeg;
  station.station_laser.sweep_width_rad = 160 * kDeg;
  station.robot_laser.sweep_start_rad = -170 * kDeg;
  station.robot_laser.sweep_width_rad = 340 * kDeg;
  station.robot_laser.phase_s = 1.3;  // not in step with the station's
  return tour;
}

}  // namespace odoloc::world
