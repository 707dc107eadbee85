// Liu's scanning-laser + ultrasonic base station (Liu et al., sec. 14.2 and
// 14.3.2; paper: ../shared/papers/liu-scanning-laser-ultrasonic-ekf.txt), the
// world side: when the lasers hit and which RF packets, sync pulses and
// ultrasonic bursts follow. Physical signals and ground truth only, like the
// rest of the acoustic world; docs/acoustic-world.md, "Liu's base station".
//
// Conventions as in acoustics.hpp: world frame in metres, angles in radians
// counter-clockwise from +x, the robot's body frame from the tricycle's Pose
// (x forward), time in seconds from the start of the run. The lasers are
// mounted above the furniture: Obstacles never occlude them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"

namespace odoloc::world {

// A laser line swept side to side by a motor, its direction read by an
// incremental encoder whose index is at the sweep's start.
struct ScanningLaser {
  // The sweep's end where the encoder counts 0 (the station's laser: world
  // frame; the robot's: body frame, CCW from the robot's x axis).
  double sweep_start_rad = 0;
  // Sweeps start -> start + width -> start; in (0, 2 pi].
  double sweep_width_rad = std::numbers::pi;
  double period_s = 5.0;  // there and back (Liu: 5 s)
  // The sweep is at its start at t = -phase_s (+ k period_s).
  double phase_s = 0;
  std::uint32_t counts_per_rev = 1000;  // Liu's encoder: 0.36 degrees a count

  // The encoder's step, 2 pi / counts_per_rev.
  [[nodiscard]] double step_rad() const;
  // The laser's direction at time_s: a triangle wave from the start (at
  // -phase_s) to start + width (half a period later) and back. Not wrapped.
  [[nodiscard]] double angle_rad(double time_s) const;
  // The encoder's count since its index at the start:
  // floor((angle - start) / step), in [0, floor(width / step)]. An angle
  // within 1e-9 of a step below an edge counts as on it, so an edge that a
  // rounded angle misses by an ulp still counts (1e-9 step is 6 prad at Liu's
  // 1000 counts).
  [[nodiscard]] std::uint32_t count(double time_s) const;
};

// Liu's base station: a scanning laser whose encoder gives the robot's
// bearing alpha, a laser receiver that sees the robot's scanning laser (the
// robot latches its own encoder, beta), an RF link to the robot and an
// ultrasonic transmitter for the range.
struct BaseStation {
  // World frame: the station laser's axis, its laser receiver and its
  // ultrasonic transmitter (Liu's transmitter rides on the laser's turret).
  Vec2 position;
  // Index of its ultrasonic transmitter in AcousticWorld::beacons (fixed, at
  // `position` within 1 mm); that Beacon's electronics_delay_s is Liu's t0.
  std::size_t transmitter = 0;
  ScanningLaser station_laser;  // world frame, aimed at the robot's laser receiver
  // Body frame, at the robot's origin (the Pose's reference point), aimed at
  // the station's laser receiver.
  ScanningLaser robot_laser;
  double rf_pulse_s = 10e-6;  // width of each packet's sync pulse
  // Sync pulses start at least this far apart (the robot pairs packets with
  // sync edges in order); must exceed rf_pulse_s.
  double rf_spacing_s = 1e-3;
  double pulse_s = 2.5e-3;  // the ranging burst (Kleeman's pulse length)
  // The station's turnaround: a ranging is triggered at least this long
  // after the alpha hit that asks for it.
  double request_margin_s = 5e-3;
};

enum class StationReportKind : std::uint8_t {
  kStationSawRobot,  // the station's laser hit the robot: alpha's count
  kRanging,          // the ultrasonic transmitter is triggered (Liu: RF then sound after t0)
  kRobotSawStation,  // the robot's laser hit the station: beta's count
};

// One RF packet as the robot receives it.
struct StationReport {
  StationReportKind kind = StationReportKind::kStationSawRobot;
  // The encoder count latched at the hit: alpha's (station laser) or beta's
  // (robot laser); 0 for a ranging.
  std::uint32_t count = 0;
  // Its sync pulse's rising edge at the station (world time; the RF flight
  // to the robot is simulate()'s): the hit, or later when another strobe is
  // within rf_spacing_s; a ranging's trigger.
  double strobe_s = 0;
  // Ground truth, for tests: when the laser hit (a ranging: when its sound
  // leaves the transmitter, the reserved slot's start).
  double hit_s = 0;
  // Ground truth at hit_s: alpha = atan2(robot - station) (world frame),
  // beta = atan2(station - robot) - heading (body frame, wrapped to
  // (-pi, pi]); NaN for a ranging.
  double true_angle_rad = 0;
};

struct StationPlan {
  std::vector<StationReport> reports;  // by strobe time
  // The transmitter's emissions (one per ranging) and one sync pulse per
  // report, in the same order; merge it with the beacons' schedule.
  Schedule schedule;
};

// Every laser hit in [0, end_s] of a robot on `robot` and what the station
// sends for it. Hits: the laser's angle crosses the target's bearing (found
// on a 1 ms grid plus the sweeps' turnarounds, refined by bisection to
// 1 ns). A ranging takes the first reserved slot (KleemanTiming's first slot
// after the beacons', cycles from first_burst_s as kleeman_schedule's
// start_s) whose trigger, slot start - t0, is at least request_margin_s after
// an alpha hit, at most one per slot: an RF sync at the trigger and a burst
// of pulse_s whose sound leaves at the slot start. Ranging strobes are fixed;
// a hit's strobe is delayed until rf_spacing_s clear of every other (its
// count stays the one latched at the hit); reports whose strobe falls after
// end_s are dropped. Throws std::invalid_argument for bad parameters
// (non-finite values, a transmitter the world does not have, or not at the
// station, a timing with no reserved slot, a burst longer than a slot, ...).
StationPlan plan_base_station(const BaseStation& station, const AcousticWorld& world,
                              const KleemanTiming& timing, const Trajectory& robot,
                              double first_burst_s, double end_s);

}  // namespace odoloc::world
