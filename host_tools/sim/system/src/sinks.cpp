#include "odoloc/sim/sinks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>

#include "odoloc/lcm/channels.hpp"
#include "odoloc_lcm/beacon_fix_t.hpp"
#include "odoloc_lcm/encoder_state_t.hpp"
#include "odoloc_lcm/odometry_increment_t.hpp"
#include "odoloc_lcm/pose_estimate_t.hpp"
#include "odoloc_lcm/station_measurement_t.hpp"
#include "odoloc_lcm/tof_measurement_set_t.hpp"

namespace odoloc::sim {

namespace {

constexpr double kReferencePeriodS = 0.01;  // LocalisationSystem::reference's track

std::int64_t utime(double seconds) {
  return std::llround(seconds * 1e6);
}

world::Pose pose_of(double x, double y, double theta) {
  return {x, y, theta};
}

world::Pose fix_pose(const sw::locate::Fix& fix) {
  return pose_of(fix.position_m.x, fix.position_m.y, 0);
}

double residual_rms_m(const sw::locate::Fix& fix) {
  double sum = 0;
  int n = 0;
  for (const sw::locate::BeaconUse& u : fix.beacons)
    if (u.status == sw::locate::BeaconStatus::kUsed && std::isfinite(u.residual_m)) {
      sum += u.residual_m * u.residual_m;
      ++n;
    }
  return n == 0 ? 0.0 : std::sqrt(sum / n);
}

// One fix of the robot origin as the outputs record it: a beacon cycle's
// (locked cycles only) or a Thamma cycle's pose (both boxes' ranges).
struct FixRecord {
  double time_s;  // robot clock
  sw::locate::Fix fix;
  sw::fuse::Outcome fused;
};
std::vector<FixRecord> fixes_of(const sw::LocaliserStep& step) {
  std::vector<FixRecord> out;
  for (const sw::CycleResult& c : step.cycles)
    if (c.measurement.locked())
      out.push_back({c.time_s, c.fix, c.fused});
  for (const sw::ThammaResult& t : step.thamma) {
    sw::locate::Fix f = t.pose.head;
    f.valid = t.pose.valid;
    f.position_m = t.pose.position_m;
    f.covariance_m2 = t.pose.covariance.topLeftCorner<2, 2>();
    f.beacons.insert(f.beacons.end(), t.pose.tail.beacons.begin(), t.pose.tail.beacons.end());
    out.push_back({t.time_s, std::move(f), t.head});
  }
  return out;
}

}  // namespace

std::optional<board::PosePoint> reference_at(const board::RunResult& run, double time_s) {
  const long index = std::lround(time_s / kReferencePeriodS) - 1;  // the first sample is at 10 ms
  if (index < 0 || static_cast<std::size_t>(index) >= run.track.size())
    return std::nullopt;
  const board::PosePoint& p = run.track[static_cast<std::size_t>(index)];
  if (std::abs(p.time_s - time_s) > kReferencePeriodS / 2)
    return std::nullopt;
  return p;
}

world::Pose fused_pose(const sw::LocaliserStep& step) {
  const sw::fuse::Vector3& x = step.estimate.pose.x;
  return pose_of(x(0), x(1), x(2));
}
world::Pose odometry_pose(const sw::LocaliserStep& step) {
  return pose_of(step.odometry.x_m, step.odometry.y_m, step.odometry.theta_rad);
}

// ------------------------------------------------------------------ errors

std::vector<Source> table_rows(const LocalisationSystem& system) {
  std::vector<Source> rows;
  for (const Source s : kAllSources)
    if ((s != Source::kUltrasonic || system.tour().timing.beacon_count > 0 ||
         system.tour().thamma) &&
        (s != Source::kLiuFilter || system.localiser().liu_filter() != nullptr))
      rows.push_back(s);
  return rows;
}

ErrorSink::ErrorSink(const LocalisationSystem& system)
    : report_(system.tour().drive.start, table_rows(system)),
      start_(system.tour().drive.start),
      last_truth_(start_) {
  if (system.tour().thamma) {
    for (const world::Beacon& b : system.tour().acoustics.beacons)
      stations_.push_back(b.position);
    study_.emplace();
  }
}

bool ErrorSink::standing_at_start(const world::Pose& truth) const {
  // Within 1 cm of the mark, not moved by 0.1 mm since the last frame.
  return std::hypot(truth.x_m - start_.x_m, truth.y_m - start_.y_m) < 0.01 &&
         std::hypot(truth.x_m - last_truth_.x_m, truth.y_m - last_truth_.y_m) < 1e-4;
}

void ErrorSink::finish(LocalisationSystem& system) {
  if (system.cut_short())
    report_.cut_short();
  else if (standing_ && away_)
    report_.mark_return();
}

void ErrorSink::frame(const Frame& frame, LocalisationSystem& system) {
  const bool standing = standing_at_start(frame.truth);
  if (standing_ && !standing && away_) {  // the previous frame ended a stop
    report_.mark_return();
    away_ = false;
  }
  standing_ = standing;
  away_ = away_ || std::hypot(frame.truth.x_m - start_.x_m, frame.truth.y_m - start_.y_m) > 1.0;
  last_truth_ = frame.truth;
  report_.add(Source::kMinSelect, frame.truth, odometry_pose(frame.soc));
  for (const auto& [source, policy] :
       {std::pair{Source::kRearOdometry, rtl::MinSelectPolicy::kRearOnly},
        std::pair{Source::kFrontOdometry, rtl::MinSelectPolicy::kFrontOnly}})
    if (const auto p = reference_at(system.reference(policy), frame.time_s))
      report_.add(source, p->truth, p->fabric);
  for (const sw::CycleResult& c : frame.soc.cycles)
    if (c.fix.valid)
      report_.add(Source::kUltrasonic, system.truth_at(system.to_sim_time(c.time_s)),
                  fix_pose(c.fix), false);
  for (const sw::ThammaResult& t : frame.soc.thamma) {
    study_->count_cycle();
    if (!t.pose.valid)
      continue;
    const world::Pose truth = system.truth_at(system.to_sim_time(t.time_s));
    const world::Pose pose = pose_of(t.pose.position_m.x, t.pose.position_m.y, t.pose.heading_rad);
    report_.add(Source::kUltrasonic, truth, pose);
    double nearest = std::numeric_limits<double>::infinity();
    for (const world::Vec2& s : stations_)
      nearest = std::min(nearest, std::hypot(truth.x_m - s.x_m, truth.y_m - s.y_m));
    study_->add(nearest, std::hypot(pose.x_m - truth.x_m, pose.y_m - truth.y_m),
                std::remainder(pose.theta_rad - truth.theta_rad, 2 * std::numbers::pi));
  }
  if (frame.soc.estimate.initialised)
    report_.add(Source::kFused, frame.truth, fused_pose(frame.soc));
  if (frame.soc.liu && frame.soc.liu->initialised) {
    const sw::fuse::Vector3& x = frame.soc.liu->pose.x;
    report_.add(Source::kLiuFilter, frame.truth, pose_of(x(0), x(1), x(2)));
  }
}

// --------------------------------------------------------------------- CSV

CsvSink::CsvSink(const std::string& trajectories_path, const std::string& fixes_path)
    : trajectories_path_(trajectories_path),
      fixes_path_(fixes_path),
      trajectories_(trajectories_path),
      fixes_(fixes_path) {
  if (!trajectories_)
    throw std::runtime_error("cannot write " + trajectories_path);
  if (!fixes_)
    throw std::runtime_error("cannot write " + fixes_path);
  trajectories_ << "time_s,truth_x,truth_y,truth_theta,odometry_x,odometry_y,odometry_theta,"
                   "rear_x,rear_y,rear_theta,front_x,front_y,front_theta,fused_x,fused_y,"
                   "fused_theta,fused_sd_x,fused_sd_y,fused_sd_theta,odometry_only\n";
  fixes_ << "time_s,valid,x,y,var_xx,var_xy,var_yy,beacons_used,solver,truth_x,truth_y,"
            "fused\n";
}

void CsvSink::frame(const Frame& frame, LocalisationSystem& system) {
  const auto pose = [](const std::optional<world::Pose>& p) {
    return p ? fmt::format("{:.6f},{:.6f},{:.6f}", p->x_m, p->y_m, p->theta_rad)
             : std::string(",,");
  };
  const auto reference = [&](rtl::MinSelectPolicy policy) -> std::optional<world::Pose> {
    if (const auto p = reference_at(system.reference(policy), frame.time_s))
      return p->fabric;
    return std::nullopt;
  };
  const sw::fuse::Estimate& e = frame.soc.estimate;
  std::string fused = ",,,,,";
  if (e.initialised)
    fused = fmt::format("{},{:.6f},{:.6f},{:.6f}", pose(fused_pose(frame.soc)),
                        std::sqrt(e.covariance(0, 0)), std::sqrt(e.covariance(1, 1)),
                        std::sqrt(e.covariance(2, 2)));
  trajectories_ << fmt::format(
      "{:.4f},{},{},{},{},{},{:d}\n", frame.time_s, pose(frame.truth),
      pose(odometry_pose(frame.soc)), pose(reference(rtl::MinSelectPolicy::kRearOnly)),
      pose(reference(rtl::MinSelectPolicy::kFrontOnly)), fused, e.odometry_only);
  for (const FixRecord& r : fixes_of(frame.soc)) {
    const double t = system.to_sim_time(r.time_s);
    const world::Pose truth = system.truth_at(t);
    const Eigen::Matrix2d& p = r.fix.covariance_m2;
    fixes_ << fmt::format("{:.4f},{:d},{:.6f},{:.6f},{:.4g},{:.4g},{:.4g},{},{},{:.6f},{:.6f},{}\n",
                          t, r.fix.valid, r.fix.position_m.x, r.fix.position_m.y, p(0, 0), p(0, 1),
                          p(1, 1), r.fix.used(), sw::locate::name(r.fix.solver), truth.x_m,
                          truth.y_m, sw::fuse::name(r.fused));
  }
}

void CsvSink::finish(LocalisationSystem& /*system*/) {
  trajectories_.close();
  fixes_.close();
  if (trajectories_.fail())
    throw std::runtime_error("writing " + trajectories_path_ + " failed");
  if (fixes_.fail())
    throw std::runtime_error("writing " + fixes_path_ + " failed");
}

// --------------------------------------------------------------------- LCM

LcmSink::LcmSink(lcm::Connection& connection) : lcm_(&connection) {}

LcmSink::LcmSink(const std::string& path)
    : log_path_(path), log_(std::make_unique<::lcm::LogFile>(path, "w")) {
  if (!log_->good())
    throw std::runtime_error("cannot write the LCM log " + path);
}

LcmSink::~LcmSink() = default;

template <class Message>
void LcmSink::publish(const char* channel, const Message& message) {
  ++published_;
  if (lcm_ != nullptr) {
    lcm_->publish(channel, message);
    return;
  }
  std::vector<std::uint8_t> bytes = lcm::encode(message);
  ::lcm::LogEvent event{};
  // Publish order, never backwards (a fix is published a cycle after its
  // ranges' capture time, which its utime keeps).
  event.timestamp = std::max(event_utime_, publish_utime_);
  event_utime_ = event.timestamp;
  event.channel = channel;
  event.datalen = static_cast<std::int32_t>(bytes.size());
  event.data = bytes.data();
  log_failed_ = log_failed_ || log_->writeEvent(&event) != 0;
}

void LcmSink::finish(LocalisationSystem& /*system*/) {
  if (!log_)
    return;
  log_.reset();  // closes (flushes) the file
  if (log_failed_)
    throw std::runtime_error("writing the LCM log " + log_path_ + " failed");
}

namespace {

odoloc_lcm::pose_estimate_t pose_message(double time_s, const char* source, const world::Pose& p) {
  odoloc_lcm::pose_estimate_t m{};
  m.utime = utime(time_s);
  m.source = source;
  m.x = p.x_m;
  m.y = p.y_m;
  m.theta = std::remainder(p.theta_rad, 2 * std::numbers::pi);
  return m;
}

}  // namespace

void LcmSink::frame(const Frame& frame, LocalisationSystem& system) {
  namespace channel = lcm::channel;
  publish_utime_ = utime(frame.time_s);
  publish(channel::kTruth, pose_message(frame.time_s, "truth", frame.truth));

  if (frame.encoders) {
    odoloc_lcm::encoder_state_t encoders{};
    encoders.utime = utime(frame.time_s);
    for (std::size_t i = 0; i < frame.encoders->size(); ++i) {
      const EncoderRead& r = (*frame.encoders)[i];
      encoders.position_count[i] = r.count;
      encoders.speed_value[i] = r.speed;
      encoders.speed_mode[i] = r.pulse_mode ? odoloc_lcm::encoder_state_t::SPEED_MODE_PULSE
                                            : odoloc_lcm::encoder_state_t::SPEED_MODE_PERIOD;
      encoders.valid[i] = r.valid;
      encoders.stalled[i] = r.stalled;
      encoders.forward[i] = r.forward;
    }
    publish(channel::kEncoders, encoders);
  }

  const sw::FabricOdometry& o = frame.soc.odometry;
  odoloc_lcm::odometry_increment_t odometry{};
  odometry.utime = utime(frame.time_s);
  odometry.updates = o.updates;
  odometry.dx = frame.soc.increment(0);
  odometry.dy = frame.soc.increment(1);
  odometry.dtheta = frame.soc.increment(2);
  odometry.ds = sw::fuse::arc_length(frame.soc.increment);
  odometry.last_rear_ds = o.rear_ds_m;
  odometry.last_rear_dtheta = o.rear_dtheta_rad;
  odometry.last_front_ds = o.front_ds_m;
  odometry.last_front_dtheta = o.front_dtheta_rad;
  odometry.last_ds = o.ds_m;
  odometry.last_dtheta = o.dtheta_rad;
  odometry.ds_from_front = o.ds_from_front;
  odometry.dtheta_from_front = o.dtheta_from_front;
  odometry.steer_phi = o.steer_rad;
  odometry.x = o.x_m;
  odometry.y = o.y_m;
  odometry.theta = o.theta_rad;
  publish(channel::kOdometry, odometry);

  for (const FixRecord& r : fixes_of(frame.soc)) {
    odoloc_lcm::beacon_fix_t fix{};
    fix.utime = utime(system.to_sim_time(r.time_s));
    fix.solver = std::string(sw::locate::name(r.fix.solver));
    fix.x = r.fix.position_m.x;
    fix.y = r.fix.position_m.y;
    for (int k = 0; k < 4; ++k)
      fix.covariance[k] = r.fix.covariance_m2(k / 2, k % 2);
    fix.beacons_used = static_cast<std::int16_t>(r.fix.used());
    fix.residual_rms = residual_rms_m(r.fix);
    fix.valid = r.fix.valid;
    publish(channel::kFix, fix);
  }
  for (const sw::StationUpdate& u : frame.soc.station) {
    odoloc_lcm::station_measurement_t m{};
    m.utime = utime(system.to_sim_time(u.time_s));
    m.kind = std::string(sw::fuse::name(sw::fuse::type_of(u.measurement)));
    std::visit(
        [&](const auto& z) {
          using Z = std::decay_t<decltype(z)>;
          if constexpr (std::is_same_v<Z, sw::fuse::StationRange>) {
            m.value = z.distance_m, m.sd = z.sd_m;
            m.station_x = z.station_m.x(), m.station_y = z.station_m.y();
          } else if constexpr (std::is_same_v<Z, sw::fuse::StationBearing> ||
                               std::is_same_v<Z, sw::fuse::RobotBearing>) {
            m.value = z.bearing_rad, m.sd = z.sd_rad;
            m.station_x = z.station_m.x(), m.station_y = z.station_m.y();
          }
        },
        u.measurement);
    m.outcome = std::string(sw::fuse::name(u.fused));
    publish(channel::kStation, m);
  }
  publish_events(frame, system);

  publish(channel::kPoseOdometry, pose_message(frame.time_s, "odometry", odometry_pose(frame.soc)));
  for (const auto& [name, source, policy] :
       {std::tuple{channel::kPoseRear, "rear", rtl::MinSelectPolicy::kRearOnly},
        std::tuple{channel::kPoseFront, "front", rtl::MinSelectPolicy::kFrontOnly}})
    if (const auto p = reference_at(system.reference(policy), frame.time_s))
      publish(name, pose_message(frame.time_s, source, p->fabric));
  const sw::fuse::Estimate& e = frame.soc.estimate;
  if (e.initialised) {
    odoloc_lcm::pose_estimate_t fused = pose_message(frame.time_s, "fused", fused_pose(frame.soc));
    for (int k = 0; k < 9; ++k)
      fused.covariance[k] = e.covariance(k / 3, k % 3);
    fused.odometry_only = e.odometry_only;
    fused.last_update_utime =
        e.last_absolute_s < 0 ? 0 : utime(system.to_sim_time(e.last_absolute_s));
    publish(channel::kPoseFused, fused);
  }
  if (frame.soc.liu && frame.soc.liu->initialised) {
    const sw::fuse::LiuEstimate& l = *frame.soc.liu;
    odoloc_lcm::pose_estimate_t liu =
        pose_message(frame.time_s, "liu", pose_of(l.pose.x(0), l.pose.x(1), l.pose.x(2)));
    // Liu's filter carries no heading variance: the position's only.
    for (int k = 0; k < 4; ++k)
      liu.covariance[(k / 2) * 3 + k % 2] = l.covariance_m2(k / 2, k % 2);
    publish(channel::kPoseLiu, liu);
  }
}

void LcmSink::publish_events(const Frame& frame, LocalisationSystem& system) {
  if (!frame.soc.batch)
    return;
  const sw::tof::CaptureBatch& batch = *frame.soc.batch;
  rises_.resize(std::max(rises_.size(), batch.channels.size()));
  for (std::size_t c = 0; c < batch.channels.size(); ++c)
    for (const sw::tof::EnvelopeEvent& e : batch.channels[c].envelope)
      rises_[c].push_back(static_cast<std::int64_t>(e.rise));
  if (!sync_tick_ && !batch.sync.empty())
    sync_tick_ = static_cast<std::int64_t>(batch.sync.front());
  const double tick_s = batch.timebase.tick_s();
  for (std::size_t k = 0; k < frame.soc.cycles.size(); ++k) {
    odoloc_lcm::tof_measurement_set_t set{};
    set.cycle = static_cast<std::int64_t>(cycles_++);
    set.tick_s = tick_s;
    std::int64_t first = -1;
    for (std::size_t c = 0; c < rises_.size(); ++c) {
      odoloc_lcm::tof_channel_events_t events{};
      events.channel = static_cast<std::int8_t>(c);
      events.rise_ticks = std::move(rises_[c]);
      events.num_events = static_cast<std::int16_t>(events.rise_ticks.size());
      if (!events.rise_ticks.empty() && (first < 0 || events.rise_ticks.front() < first))
        first = events.rise_ticks.front();
      set.channels.push_back(std::move(events));
      rises_[c].clear();
    }
    set.num_channels = static_cast<std::int16_t>(set.channels.size());
    set.utime =
        utime(system.to_sim_time(static_cast<double>(std::max<std::int64_t>(first, 0)) * tick_s));
    set.has_sync = sync_tick_.has_value();
    set.sync_tick = sync_tick_.value_or(0);
    sync_tick_.reset();
    publish(lcm::channel::kTof, set);
  }
}

}  // namespace odoloc::sim
