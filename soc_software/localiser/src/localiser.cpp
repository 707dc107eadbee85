// The SoC's localisation loop (localiser.hpp).
#include "odoloc/sw/localiser.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <iterator>
#include <numbers>
#include <utility>

#include "odoloc/sw/detail/config_checks.hpp"

namespace odoloc::sw {

namespace {

bool usable(const tof::Arrival& a) {
  return std::isfinite(a.distance_m) && std::isfinite(a.sd_m) &&
         (a.flags.bits() & locate::kUnusableFlags.bits()) == 0;
}

// The robot-clock time at which beacon `beacon`'s candidate `a` reached the
// robot origin: its slot's start plus its time in the slot.
double capture_time_s(const tof::CycleMeasurement& cycle, int beacon, const tof::Arrival& a) {
  return cycle.anchor_s + beacon * cycle.fire_period_s + a.time_s;
}

// The fix's time: the mean capture time of the ranges it used (the middle
// of the cycle when it used none).
double fix_time_s(const tof::CycleMeasurement& cycle, const locate::Fix& fix) {
  double sum = 0;
  int n = 0;
  for (const locate::BeaconUse& u : fix.beacons) {
    if (u.status != locate::BeaconStatus::kUsed || u.candidate < 0)
      continue;
    const tof::BeaconMeasurement& m = cycle.beacons[static_cast<std::size_t>(u.beacon)];
    sum += capture_time_s(cycle, u.beacon, m.candidates[static_cast<std::size_t>(u.candidate)]);
    ++n;
  }
  if (n > 0)
    return sum / n;
  return cycle.anchor_s + 0.5 * static_cast<double>(cycle.beacons.size()) * cycle.fire_period_s;
}

}  // namespace

void LocaliserConfig::validate() const {
  constexpr std::string_view kOwner = "LocaliserConfig";
  detail::require(start_pose.allFinite(), kOwner, "start_pose must be finite");
  detail::require(detail::finite_non_negative(chain_sd_m), kOwner,
                  "chain_sd_m must be finite and >= 0");
  // The capture driver unwraps 32-bit timestamps: at least one drain
  // every 85 s (tof_capture_driver.hpp); far less keeps the FIFOs short.
  detail::require(capture_period_s >= 0 && capture_period_s <= 1, kOwner,
                  "capture_period_s must be in [0, 1] s");
  detail::require(static_cast<int>(layout.beacons.size()) == kleeman.schedule.beacons, kOwner,
                  "layout must have one beacon per kleeman.schedule.beacons");
  const bool beacons = kleeman.schedule.beacons > 0;
  detail::require(beacons || (station && start_covariance) || thamma, kOwner,
                  "without beacons the base station and start_covariance, or Thamma's "
                  "stations, are needed");
  if (thamma) {
    detail::require(!beacons && !station, kOwner,
                    "Thamma's stations exclude beacons and the base station (the sync input)");
    detail::require(capture.sync_enable, kOwner,
                    "Thamma's stations need capture.sync_enable (their triggers)");
    detail::require(static_cast<int>(thamma->stations.beacons.size()) == thamma->schedule.stations,
                    kOwner, "thamma.stations must have one station per thamma.schedule.stations");
    thamma->measure.validate();
    thamma->schedule.validate();
    thamma->stations.validate();
    thamma->body.validate();
    thamma->pose.validate();
  }
  detail::require(!start_covariance || start_covariance->allFinite(), kOwner,
                  "start_covariance must be finite");
  detail::require(!liu_filter || station, kOwner, "liu_filter needs the base station");
  if (liu_filter)
    liu_filter->validate();
  // A cycle's ranges are fused when the cycle is complete, up to two
  // cycles after beacon 0's arrival: the filter must keep that much.
  detail::require(ekf.history_s >= 2 * kleeman.schedule.cycle_s(), kOwner,
                  "ekf.history_s must cover two beacon cycles (the ranges are fused late)");
  if (station) {
    station->validate();
    detail::require(capture.sync_enable, kOwner,
                    "the base station needs capture.sync_enable (its packets' strobes)");
    detail::require(!beacons || kleeman.schedule.reserved_slots >= 1, kOwner,
                    "the base station needs kleeman.schedule.reserved_slots >= 1 (its bursts)");
  }
  if (beacons) {
    layout.validate();
    kleeman.validate();
  }
  multilateration.validate();
  ekf.validate();
}

Localiser::Localiser(RegisterBus& bus, const LocaliserConfig& config, station::Link* link)
    : config_((config.validate(), config)),
      odometry_(bus),
      capture_(bus, config.capture),
      ekf_(config.ekf),
      link_(link) {
  detail::require(!config_.station || link_ != nullptr, "Localiser",
                  "a base station (config.station) needs a station::Link");
  if (config_.kleeman.schedule.beacons > 0) {
    tof::KleemanConfig k = config_.kleeman;
    k.timebase = capture_.timebase();
    decoder_.emplace(std::move(k));
  }
  if (config_.station) {
    const tof::KleemanConfig& k = config_.kleeman;
    listener_.emplace(station::BurstListenerConfig{.array = k.array,
                                                   .envelope = k.envelope,
                                                   .speed_of_sound_mps = k.speed_of_sound_mps,
                                                   .max_range_m = config_.station->max_range_m,
                                                   .min_width_s = k.min_width_s,
                                                   .timing_sd_s = k.timing_sd_s,
                                                   .group_margin_s = k.group_margin_s,
                                                   .min_receivers = k.min_receivers});
  }
  if (config_.liu_filter)
    liu_.emplace(*config_.liu_filter);
  if (config_.thamma)
    thamma_.emplace(config_.thamma->measure, config_.thamma->schedule);
  odometry_.configure(config_.vehicle, config_.min_select, config_.update_clocks, config_.policy);
  odometry_.set_pose(config_.start_pose.x(), config_.start_pose.y(), config_.start_pose.z());
  std::uint32_t armed = 0;
  for (unsigned c = 0; c < tof::kCaptureChannels; ++c)
    armed |= config_.capture.channels[c].enabled ? 1U << c : 0U;
  capture_.arm(armed);
}

double Localiser::now_s() {
  return static_cast<double>(capture_.now()) * capture_.timebase().tick_s();
}

LocaliserStep Localiser::step() {
  LocaliserStep out;
  out.odometry = odometry_.read();
  out.time_s = now_s();
  const fuse::Pose pose{{out.odometry.x_m, out.odometry.y_m, out.odometry.theta_rad}};
  out.increment = fuse::increment_between(
      track_.empty() ? fuse::Pose{config_.start_pose} : track_.back().pose, pose);
  if (!track_.empty()) {
    ekf_.predict(out.time_s, fuse::Increment{out.increment});
    if (liu_)
      liu_->predict(out.time_s, out.increment);
  } else if (config_.start_covariance) {
    ekf_.initialise(out.time_s, pose, *config_.start_covariance);
    start_liu_filter();
  }
  track_.push_back({out.time_s, pose});
  // Kept: the filter's history and the cycle being decoded.
  const double keep_s = config_.ekf.history_s + config_.kleeman.schedule.cycle_s();
  while (track_.size() > 2 && track_[1].time_s < out.time_s - keep_s)
    track_.pop_front();

  if (last_drain_s_ < 0 || out.time_s - last_drain_s_ >= config_.capture_period_s) {
    last_drain_s_ = out.time_s;
    out.batch = capture_.read();
    if (config_.station)
      take_packets(*out.batch, out);
    if (decoder_)
      for (tof::CycleMeasurement& m : decoder_->push(*out.batch)) {
        CycleResult& cycle = out.cycles.emplace_back();
        cycle.measurement = std::move(m);
        process(cycle);
      }
    if (config_.station) {
      listener_->push(*out.batch);
      take_ranges(out);
    }
    if (thamma_)
      for (tof::ThammaCycle& c : thamma_->push(*out.batch)) {
        ThammaResult& r = out.thamma.emplace_back();
        r.cycle = std::move(c);
        process(r);
      }
  }
  out.estimate = ekf_.estimate();
  if (liu_)
    out.liu = liu_->estimate();
  return out;
}

fuse::Pose Localiser::odometry_at(double time_s) const {
  const auto after = std::ranges::upper_bound(track_, time_s, {}, &OdometrySample::time_s);
  if (after == track_.begin())
    return track_.front().pose;
  if (after == track_.end())
    return track_.back().pose;
  const OdometrySample& a = *std::prev(after);
  const OdometrySample& b = *after;
  const double f = (time_s - a.time_s) / (b.time_s - a.time_s);
  return fuse::compose(a.pose, f * fuse::increment_between(a.pose, b.pose));
}

void Localiser::process(CycleResult& cycle) {
  const tof::CycleMeasurement& m = cycle.measurement;
  if (!m.locked())
    return;
  cycle.fix = locate::multilaterate(config_.layout, locate::range_set(m), config_.multilateration);
  cycle.time_s = fix_time_s(m, cycle.fix);
  if (cycle.fix.valid)
    cycle.heading = locate::beacon_heading(cycle.fix, config_.layout,
                                           locate::used_directions(m, cycle.fix), config_.heading);
  if (!ekf_.estimate().initialised) {
    if (cycle.fix.valid && cycle.heading.valid) {
      initialise_from(cycle);
      cycle.fused = fuse::Outcome::kAccepted;
    }
    return;
  }
  if (!config_.fuse_beacon_ranges)
    return;
  // Two places explain the cycle: its ranges would pull towards either.
  if (cycle.fix.reason == locate::NoFixReason::kAmbiguousBeaconSets) {
    cycle.fused = fuse::Outcome::kAmbiguous;
    return;
  }
  cycle.fused = ekf_.update(m.anchor_s, motion_compensated(m));
}

void Localiser::initialise_from(const CycleResult& cycle) {
  fuse::Matrix3 covariance = fuse::Matrix3::Zero();
  covariance.topLeftCorner<2, 2>() = cycle.fix.covariance_m2;
  covariance(2, 2) = cycle.heading.sd_rad * cycle.heading.sd_rad;
  const fuse::Pose fix{{cycle.fix.position_m.x, cycle.fix.position_m.y, cycle.heading.heading_rad}};
  initialise_at(cycle.time_s, fix, covariance);
}

void Localiser::initialise_at(double time_s, const fuse::Pose& pose,
                              const fuse::Matrix3& covariance) {
  ekf_.initialise(time_s, pose, covariance);
  // The odometry since then, onto the new pose.
  fuse::Pose from = odometry_at(time_s);
  for (const OdometrySample& s : track_) {
    if (s.time_s <= time_s)
      continue;
    ekf_.predict(s.time_s, fuse::Increment{fuse::increment_between(from, s.pose)});
    from = s.pose;
  }
  start_liu_filter();
}

void Localiser::process(ThammaResult& result) {
  const LocaliserConfig::Thamma& th = *config_.thamma;
  const tof::ThammaCycle& cycle = result.cycle;
  // The pose at the middle of the cycle; each station's range from where
  // the odometry puts each box at that station's time.
  result.time_s = (cycle.station_time_s.front() + cycle.station_time_s.back()) / 2;
  const fuse::Pose at_pose = odometry_at(result.time_s);
  locate::ThammaMotion motion;
  for (const double t : cycle.station_time_s) {
    const fuse::Vector3 d = fuse::increment_between(at_pose, odometry_at(t));
    const Eigen::Rotation2Dd turn(d(2));
    for (const auto& [point, out] :
         {std::pair{th.body.head_m, &motion.head}, std::pair{th.body.tail_m, &motion.tail}}) {
      const fuse::Vector2 o{point.x, point.y};
      const fuse::Vector2 moved = d.head<2>() + turn * o - o;
      out->push_back({moved.x(), moved.y()});
    }
  }
  result.pose = locate::thamma_pose(th.stations, cycle.per_station, th.body, th.pose, motion);
  if (!result.pose.valid)
    return;
  if (!ekf_.estimate().initialised) {
    const fuse::Pose pose{
        {result.pose.position_m.x, result.pose.position_m.y, result.pose.heading_rad}};
    initialise_at(result.time_s, pose, result.pose.covariance);
    result.head = result.tail = fuse::Outcome::kAccepted;
    return;
  }
  const auto body_point = [](const locate::Fix& fix, const tof::Vec2& point) {
    fuse::BodyPointFix f;
    f.body_point_m = {point.x, point.y};
    f.position_m = {fix.position_m.x, fix.position_m.y};
    f.covariance_m2 = fix.covariance_m2;
    return f;
  };
  result.head = ekf_.update(result.time_s, body_point(result.pose.head, th.body.head_m));
  result.tail = ekf_.update(result.time_s, body_point(result.pose.tail, th.body.tail_m));
}

void Localiser::start_liu_filter() {
  if (liu_) {
    const fuse::Estimate e = ekf_.estimate();
    liu_->initialise(e.time_s, e.pose);
  }
}

fuse::RangeSet Localiser::motion_compensated(const tof::CycleMeasurement& cycle) const {
  fuse::RangeSet set;
  const fuse::Pose at_set = odometry_at(cycle.anchor_s);
  const double along = config_.ekf.odometry.along_sd_per_sqrt_m;
  for (const tof::BeaconMeasurement& b : cycle.beacons) {
    const tof::Arrival* a = b.direct();
    if (a == nullptr || !usable(*a))
      continue;
    const locate::Beacon& beacon = config_.layout.beacons[static_cast<std::size_t>(b.beacon)];
    const fuse::Vector2 motion =
        fuse::increment_between(at_set, odometry_at(capture_time_s(cycle, b.beacon, *a))).head<2>();
    const double variance =
        a->sd_m * a->sd_m + config_.chain_sd_m * config_.chain_sd_m + along * along * motion.norm();
    fuse::BeaconRange r;
    r.beacon_m = {beacon.position_m.x, beacon.position_m.y};
    r.height_m = beacon.height_m;
    r.distance_m = a->distance_m;
    r.sd_m = std::sqrt(variance);
    r.motion_m = motion;
    set.ranges.push_back(r);
  }
  return set;
}

void Localiser::take_packets(const tof::CaptureBatch& batch, LocaliserStep& out) {
  while (std::optional<station::Report> r = link_->receive())
    packets_.add_packet(*r);
  std::vector<double> edges_s;
  for (const tof::Tick t : batch.sync)
    edges_s.push_back(batch.timebase.edge_time_s(t, 0));
  packets_.add_edges(edges_s, std::ranges::any_of(batch.incidents, [](const tof::Incident& i) {
                       return i.channel == tof::kSyncChannel;
                     }));
  const station::StationConfig& st = *config_.station;
  while (const std::optional<station::TimedReport> p = packets_.next()) {
    const station::Report& r = p->report;
    switch (r.kind) {
      case station::ReportKind::kStationSawRobot: {
        const fuse::StationBearing alpha = station::station_bearing(st, r.count);
        if (liu_)
          alphas_.push_back({p->time_s, alpha.bearing_rad});
        fuse_station({p->time_s, alpha}, out);
        break;
      }
      case station::ReportKind::kRobotSawStation: {
        const fuse::RobotBearing beta = station::robot_bearing(st, r.count);
        if (liu_)
          liu_->fuse_heading(beta.bearing_rad, beta.station_m);
        fuse_station({p->time_s, beta}, out);
        break;
      }
      case station::ReportKind::kRanging:
        rangings_.push_back(p->time_s);
        break;
    }
  }
}

void Localiser::take_ranges(LocaliserStep& out) {
  const station::StationConfig& st = *config_.station;
  const double c = config_.kleeman.speed_of_sound_mps;
  // Quantisation of the two timestamps (the packet's edge, the arrival's).
  const double tick_sd_m = c * std::sqrt(2.0) * capture_.timebase().quantisation_sd_s();
  while (!rangings_.empty()) {
    const double ranging_s = rangings_.front();
    const double sent_s = ranging_s + st.t0_s;  // the burst leaves the station
    const station::BurstResult heard = listener_->listen(sent_s);
    if (heard.status == station::BurstStatus::kPending)
      break;
    rangings_.pop_front();
    if (heard.status != station::BurstStatus::kHeard)
      continue;
    const double arrival_s = heard.burst.arrival_s;
    fuse::StationRange range;
    range.station_m = st.position_m;
    range.height_m = st.height_m;
    range.distance_m = c * (arrival_s - sent_s);  // Liu eq. 14.8
    const double timing_sd_m = c * heard.burst.sd_s;
    range.sd_m = std::sqrt(timing_sd_m * timing_sd_m + st.chain_sd_m * st.chain_sd_m +
                           tick_sd_m * tick_sd_m);
    fuse_liu_fix(ranging_s, arrival_s, range);
    fuse_station({arrival_s, range}, out);
  }
  // Kept: the bursts of the rangings still waiting, and the next ones'.
  const double oldest_s = rangings_.empty() ? out.time_s : rangings_.front();
  listener_->drop_before(std::min(oldest_s, out.time_s - config_.capture_period_s) - 1.0);
}

void Localiser::fuse_liu_fix(double ranging_s, double arrival_s, const fuse::StationRange& range) {
  // The station asks for a burst after each hit of its laser: a ranging
  // belongs to the last alpha before it, if that came soon enough.
  const auto after = std::ranges::upper_bound(alphas_, ranging_s, {}, &Alpha::time_s);
  if (!liu_ || after == alphas_.begin())
    return;
  const Alpha alpha = *std::prev(after);
  alphas_.erase(alphas_.begin(), after);
  if (ranging_s - alpha.time_s > config_.station->ranging_after_alpha_s)
    return;
  const double planar_m = std::sqrt(
      std::max(0.0, range.distance_m * range.distance_m - range.height_m * range.height_m));
  const fuse::Vector2 fix =
      fuse::LiuFilter::absolute_position(range.station_m, alpha.bearing_rad, planar_m);
  liu_->fuse_fix(fix, fuse::increment_between(odometry_at(arrival_s), track_.back().pose));
}

void Localiser::fuse_station(StationUpdate update, LocaliserStep& out) {
  if (ekf_.estimate().initialised)
    update.fused = ekf_.update(update.time_s, update.measurement);
  out.station.push_back(std::move(update));
}

}  // namespace odoloc::sw
