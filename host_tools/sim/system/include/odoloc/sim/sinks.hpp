// What the localisation system's frames go to (docs/simulator.md): the
// error report, the CSV files and the LCM channels. Each sink sees every
// frame in order, then finish() once.
#pragma once

#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odoloc/lcm/connection.hpp"
#include "odoloc/sim/report.hpp"
#include "odoloc/sim/system.hpp"

namespace odoloc::sim {

class FrameSink {
 public:
  FrameSink() = default;
  FrameSink(const FrameSink&) = delete;
  FrameSink& operator=(const FrameSink&) = delete;
  virtual ~FrameSink() = default;
  virtual void frame(const Frame& frame, LocalisationSystem& system) = 0;
  virtual void finish(LocalisationSystem& /*system*/) {}
};

// A reference run's sample at simulated time_s (its track is every 10 ms),
// or nullopt when it has none within half a sample.
std::optional<board::PosePoint> reference_at(const board::RunResult& run, double time_s);

// The fused estimate and the fabric's odometry as read, in world poses.
world::Pose fused_pose(const sw::LocaliserStep& step);
world::Pose odometry_pose(const sw::LocaliserStep& step);

// The sources `system` has: the ultrasonic fixes with beacons, Liu's
// filter where the scenario runs it, the others always.
std::vector<Source> table_rows(const LocalisationSystem& system);

// Every source's error against the truth (report.hpp), from the tour's
// start, with the system's rows.
class ErrorSink final : public FrameSink {
 public:
  explicit ErrorSink(const LocalisationSystem& system);
  void frame(const Frame& frame, LocalisationSystem& system) override;
  // A run cut short (LocalisationSystem::cut_short) has no return to start.
  void finish(LocalisationSystem& system) override;
  [[nodiscard]] const ErrorReport& report() const { return report_; }
  // With Thamma's stations: their poses' errors against the distance from
  // the stations (nullptr otherwise).
  [[nodiscard]] const DistanceStudy* distance_study() const { return study_ ? &*study_ : nullptr; }

 private:
  // A return is marked when the robot leaves the start again after
  // standing on it (or the run ends there), having been away.
  [[nodiscard]] bool standing_at_start(const world::Pose& truth) const;
  ErrorReport report_;
  world::Pose start_;
  world::Pose last_truth_;
  bool away_ = false, standing_ = false;
  std::vector<world::Vec2> stations_;  // Thamma's, the truth
  std::optional<DistanceStudy> study_;
};

// Two CSV files (comma-separated, a header line, SI units: m, rad, s of
// simulated time): `trajectories`, one row per frame (truth, the three
// odometries, the fused estimate with its standard deviations), and
// `fixes`, one row per beacon cycle (the fix, its covariance, the truth at
// its time, what the filter did). Throws std::runtime_error naming a file
// that cannot be opened or written.
class CsvSink final : public FrameSink {
 public:
  CsvSink(const std::string& trajectories_path, const std::string& fixes_path);
  void frame(const Frame& frame, LocalisationSystem& system) override;
  void finish(LocalisationSystem& system) override;

 private:
  std::string trajectories_path_, fixes_path_;
  std::ofstream trajectories_, fixes_;
};

// Every stage on LCM (docs/lcm.md): the truth, the encoder modules, the
// odometry read, the capture unit's events and the fix of each beacon
// cycle, the base station's measurements, the poses (fused, min-select
// odometry, rear-only, front-only).
// Message times are simulated microseconds. Either published on a live
// connection, or written to an LCM event log whose event timestamps are the
// simulated times of publication (the frame's; never decreasing), so
// lcm-logplayer replays the run at the robot's pace (LCM's own file://
// provider would stamp the wall clock of a simulator running many times
// faster). A message's utime is when its data was measured, which for a
// fix or a cycle's events is up to a beacon cycle before its publication.
class LcmSink final : public FrameSink {
 public:
  // Publishes on `connection`, which must outlive the sink.
  explicit LcmSink(lcm::Connection& connection);
  // Writes the log `path` (replaced); std::runtime_error naming the file
  // when it cannot be opened, or in finish() when writing failed.
  explicit LcmSink(const std::string& path);
  ~LcmSink() override;
  void frame(const Frame& frame, LocalisationSystem& system) override;
  void finish(LocalisationSystem& system) override;
  [[nodiscard]] std::uint64_t published() const { return published_; }

 private:
  template <class Message>
  void publish(const char* channel, const Message& message);
  // The capture unit's events gathered since the last cycle, published as
  // one tof_measurement_set_t when the decoder completes a cycle.
  void publish_events(const Frame& frame, LocalisationSystem& system);
  lcm::Connection* lcm_ = nullptr;
  std::string log_path_;
  std::unique_ptr<::lcm::LogFile> log_;
  bool log_failed_ = false;
  std::int64_t publish_utime_ = 0;  // the frame being published, µs
  std::int64_t event_utime_ = 0;    // the last log event's timestamp, µs
  std::uint64_t published_ = 0;
  std::uint64_t cycles_ = 0;
  std::vector<std::vector<std::int64_t>> rises_;  // per channel, unwrapped ticks
  std::optional<std::int64_t> sync_tick_;
};

}  // namespace odoloc::sim
