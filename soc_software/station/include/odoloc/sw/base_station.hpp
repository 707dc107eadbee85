// Liu's base station on the SoC (Liu et al., section 14.2 and 14.3.2;
// docs/fusion.md, "Liu's base station"): what the robot receives from it and
// how that becomes filter measurements.
//
// The station scans the room with a laser on an incremental encoder. When
// the laser hits the robot, the station sends its encoder count alpha over
// RF; when the robot's own scanning laser hits the station, the station
// sends an RF packet and the robot latches its laser's count beta. A
// ranging packet announces an ultrasonic burst t0 after it (Liu eq. 14.8:
// t_f = t_ul - t_rf - t0; burst_listener.hpp hears it). Where the robot's
// receiver octagon also serves Kleeman's beacons, the station bursts only
// in the beacon cycle's reserved slot (tof::BeaconSchedule::reserved_slots),
// so the decoder never takes it for a beacon; on a lawn with the station
// alone, the slot is its own timer's.
//
// Every RF packet pulses the capture unit's sync input as it arrives: the
// packets and the sync FIFO's rising edges pair up in order, so each
// report is timed on the robot clock by the capture unit, like the
// ultrasound.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <span>

#include "odoloc/sw/pose_ekf.hpp"

namespace odoloc::sw::station {

enum class ReportKind : std::uint8_t {
  kStationSawRobot,  // count: the station laser's alpha
  kRanging,          // the burst leaves the station t0 after this packet
  kRobotSawStation,  // count: the robot laser's beta, latched at the packet
};

// One RF packet as the robot's radio hands it over.
struct Report {
  ReportKind kind = ReportKind::kRanging;
  std::uint32_t count = 0;  // encoder counts since the laser's index (ranging: unused)
};

// The receive side of the RF link (a serial radio on a board, a queue in
// the simulator): packets in arrival order, each having pulsed the sync
// input once.
class Link {
 public:
  virtual ~Link() = default;
  // The next packet received, if any. Never blocks.
  virtual std::optional<Report> receive() = 0;
};

// A packet with its time on the robot clock (its sync edge).
struct TimedReport {
  Report report;
  double time_s = 0;
};

// Pairs the RF packets with the sync input's rising edges, in order (each
// packet pulsed the input once as it arrived; a packet the radio drops
// makes no edge). A lost edge (the sync FIFO overflowed: the capture
// driver reports an incident on the sync input) would shift every later
// pair, so the pairing starts again from the next batch: what is waiting,
// and that batch's edges, are dropped.
class PacketTimer {
 public:
  void add_packet(const Report& packet) { packets_.push_back(packet); }
  // One capture batch's sync edges (robot-clock seconds, oldest first);
  // `edges_lost`: the batch reports an incident on the sync input.
  void add_edges(std::span<const double> edges_s, bool edges_lost);
  // The oldest packet with its edge's time, once both have come.
  std::optional<TimedReport> next();
  // Packets dropped when the pairing started again.
  [[nodiscard]] std::uint64_t dropped() const { return dropped_; }

 private:
  std::deque<double> edges_s_;
  std::deque<Report> packets_;
  std::uint64_t dropped_ = 0;
};

// A scanning laser's incremental encoder: count n means the laser pointed
// in [start + n step, start + (n + 1) step), step = 2 pi / counts_per_rev
// (Liu: 1000 counts, 0.36 degrees). The best angle is the interval's middle;
// its error is uniform, sd step / sqrt(12) (0.10 degrees for Liu's).
struct LaserEncoder {
  double sweep_start_rad = 0;  // where the count is 0 (station: world frame; robot: robot frame)
  std::uint32_t counts_per_rev = 1000;

  [[nodiscard]] double step_rad() const;
  [[nodiscard]] double angle_rad(std::uint32_t count) const;
  [[nodiscard]] double sd_rad() const;
};

struct StationConfig {
  fuse::Vector2 position_m =
      fuse::Vector2::Zero();  // world frame: the lasers' axes, the transmitter
  // The transmitter above the robot's receivers (the range is
  // sqrt(planar^2 + h^2), fuse::StationRange).
  double height_m = 0;
  double t0_s = 2e-3;  // Liu's t0: the ranging packet's arrival to the burst (calibrated)
  LaserEncoder station_laser;
  LaserEncoder robot_laser;
  // Ranges longer than this are not looked for (Liu: 35 m outdoors).
  double max_range_m = 15;
  // The station asks for a burst after each hit of its laser: the ranging
  // packet comes at most this long after the alpha packet (its timer's next
  // slot after its turnaround; the device's data). Liu's fix pairs them.
  double ranging_after_alpha_s = 0.2;
  // Range error besides the arrival's timing noise and the timestamps'
  // quantisation (the capture chain's, as LocaliserConfig::chain_sd_m).
  double chain_sd_m = 0.002;
  // Angle error besides the encoder's quantisation (the laser's beam and
  // the receivers' spread).
  double bearing_sd_rad = 0.5e-3;

  // Throws std::invalid_argument naming the first bad field.
  void validate() const;
};

// The measurements of one packet that carries a bearing, at the packet's
// time (alpha: the robot seen from the station, world frame; beta: the
// station seen from the robot, robot frame).
[[nodiscard]] fuse::StationBearing station_bearing(const StationConfig& config,
                                                   std::uint32_t count);
[[nodiscard]] fuse::RobotBearing robot_bearing(const StationConfig& config, std::uint32_t count);

}  // namespace odoloc::sw::station
