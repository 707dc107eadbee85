#include "odoloc/sw/beacon_cycle.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "odoloc/sw/detail/config_checks.hpp"

namespace odoloc::sw::tof {
namespace {

using detail::finite_non_negative;
using detail::finite_positive;
void require(bool ok, const std::string& message) {
  detail::require(ok, "KleemanConfig", message);
}
std::string num(double v) {
  return std::to_string(v);
}

int popcount(std::uint32_t bits) {
  return std::popcount(bits);
}

}  // namespace

// ------------------------------------------------------------ configuration

double KleemanConfig::lock_tolerance_s() const {
  const double cycle = schedule.cycle_s();
  return max_speed_mps * cycle / speed_of_sound_mps + clock_tolerance_ppm * 1e-6 * cycle +
         double_tolerance_s;
}

void KleemanConfig::validate() const {
  const BeaconSchedule& s = schedule;
  require(s.beacons >= 2 && s.beacons <= 64,
          "schedule.beacons must be 2..64, got " + std::to_string(s.beacons));
  require(s.reserved_slots >= 0 && s.reserved_slots <= 8,
          "schedule.reserved_slots must be 0..8, got " + std::to_string(s.reserved_slots));
  require(finite_positive(s.fire_period_s), "schedule.fire_period_s must be finite and positive");
  require(finite_positive(s.pulse_s), "schedule.pulse_s must be finite and positive");
  require(finite_positive(s.double_spacing_s),
          "schedule.double_spacing_s must be finite and positive");
  require(s.double_spacing_s > s.pulse_s,
          "schedule.double_spacing_s (start to start) must exceed pulse_s, or the double "
          "pulse's bursts overlap");
  array.validate();
  envelope.validate("KleemanConfig.envelope");
  timebase.validate();
  require(std::isfinite(speed_of_sound_mps) && speed_of_sound_mps > 200 && speed_of_sound_mps < 500,
          "speed_of_sound_mps must be in (200, 500) m/s, got " + num(speed_of_sound_mps));
  require(finite_positive(max_range_m), "max_range_m must be finite and positive");
  require(finite_non_negative(geometry_tolerance_m),
          "geometry_tolerance_m must be finite and >= 0");
  require(finite_non_negative(early_guard_s), "early_guard_s must be finite and >= 0");
  require(finite_non_negative(max_speed_mps), "max_speed_mps must be finite and >= 0");
  require(finite_non_negative(clock_tolerance_ppm) && clock_tolerance_ppm < 1e4,
          "clock_tolerance_ppm must be in [0, 10000)");
  require(finite_non_negative(timing_sd_s), "timing_sd_s must be finite and >= 0");
  require(finite_non_negative(group_margin_s), "group_margin_s must be finite and >= 0");
  require(finite_positive(double_tolerance_s), "double_tolerance_s must be finite and positive");
  require(finite_positive(double_bearing_tolerance_rad),
          "double_bearing_tolerance_rad must be finite and positive");
  require(std::isfinite(double_amplitude_tolerance) && double_amplitude_tolerance >= 1,
          "double_amplitude_tolerance must be finite and >= 1");
  require(finite_non_negative(min_width_s), "min_width_s must be finite and >= 0");
  require(std::isfinite(stuck_width_s) && stuck_width_s > envelope.max_width_s(),
          "stuck_width_s must be finite and longer than the longest single burst (" +
              num(envelope.max_width_s()) + " s)");
  require(std::isfinite(weak_ratio) && weak_ratio >= 1, "weak_ratio must be finite and >= 1");
  require(std::isfinite(occlusion_contrast) && occlusion_contrast >= 1,
          "occlusion_contrast must be finite and >= 1");
  require(finite_positive(expect_half_angle_rad) && expect_half_angle_rad < std::numbers::pi,
          "expect_half_angle_rad must be in (0, pi)");
  require(finite_positive(strong_ratio), "strong_ratio must be finite and positive");
  require(min_receivers >= 1 && static_cast<std::size_t>(min_receivers) <= array.receivers.size(),
          "min_receivers must be 1..receivers");
  require(max_coast_cycles >= 0 && max_coast_cycles <= 100, "max_coast_cycles must be 0..100");
  require(confirm_cycles >= 0 && confirm_cycles <= 10, "confirm_cycles must be 0..10");
  require(occlusion_memory_cycles >= 0 && occlusion_memory_cycles <= 10000,
          "occlusion_memory_cycles must be 0..10000");
  const double c = speed_of_sound_mps;
  require(s.fire_period_s > 2 * max_range_m / c + early_guard_s + s.double_spacing_s + s.pulse_s,
          "schedule.fire_period_s " + num(s.fire_period_s) +
              " s is too short for max_range_m (2 max_range/c + early_guard + double_spacing "
              "+ pulse = " +
              num(2 * max_range_m / c + early_guard_s + s.double_spacing_s + s.pulse_s) + " s)");
  require((max_coast_cycles + 1) * lock_tolerance_s() < s.fire_period_s / 2,
          "the double pulse's search window (max_speed_mps, clock_tolerance_ppm, "
          "max_coast_cycles) exceeds half a slot");
  if (!beacon_positions.empty()) {
    require(beacon_positions.size() == static_cast<std::size_t>(s.beacons),
            "beacon_positions must be empty or hold one position per beacon (" +
                std::to_string(s.beacons) + "), got " + std::to_string(beacon_positions.size()));
    for (std::size_t i = 0; i < beacon_positions.size(); ++i)
      require(std::isfinite(beacon_positions[i].x) && std::isfinite(beacon_positions[i].y),
              "beacon_positions[" + std::to_string(i) + "] is not finite");
  }
}

// ------------------------------------------------------------------ decoder

BeaconCycleDecoder::BeaconCycleDecoder(KleemanConfig config)
    : config_(std::move(config)), c_(config_.speed_of_sound_mps) {
  config_.validate();
  // Half the smallest angle between two receivers' axes (22.5 degrees on
  // the octagon), within [5, 90] degrees.
  double spacing = std::numbers::pi;
  for (const Receiver& a : config_.array.receivers)
    for (const Receiver& b : config_.array.receivers) {
      const double d = std::abs(angle_difference(a.axis_rad, b.axis_rad));
      if (d > 1e-6)
        spacing = std::min(spacing, d);
    }
  single_half_angle_ = std::clamp(spacing / 2, std::numbers::pi / 36, std::numbers::pi / 2);
  reset();
}

void BeaconCycleDecoder::set_fire_period(double seconds) {
  KleemanConfig changed = config_;
  changed.schedule.fire_period_s = seconds;
  changed.validate();
  if (state_ == State::kLocked)  // the next cycle is predicted with the new period
    anchor_pred_ += changed.schedule.cycle_s() - config_.schedule.cycle_s();
  config_ = std::move(changed);
}

void BeaconCycleDecoder::reset() {
  state_ = State::kSearching;
  have_origin_ = false;
  origin_ = 0;
  last_read_ = 0;
  horizon_s_ = -INFINITY;
  consumed_s_ = -INFINITY;
  dropped_before_s_ = -INFINITY;
  pulses_.clear();
  spans_.clear();
  last_rise_.assign(config_.array.receivers.size(), 0);
  noise_.clear();
  saturated_.clear();
  dropped_pending_ = 0;
  anchor_pred_ = 0;
  last_measured_anchor_ = NAN;
  coast_ = 0;
  resync_pending_ = false;
  sequence_ = 0;
  epoch_ = 0;
  track_.assign(static_cast<std::size_t>(config_.schedule.beacons), Track{});
}

double BeaconCycleDecoder::tick_time(Tick t) const {
  return config_.timebase.edge_time_s(t, origin_);
}

double BeaconCycleDecoder::cycle_s() const {
  return config_.schedule.cycle_s();
}

double BeaconCycleDecoder::cycle_end(double anchor) const {
  return anchor + cycle_s() - config_.max_range_m / c_ - config_.early_guard_s;
}

void BeaconCycleDecoder::ingest(const CaptureBatch& batch) {
  if (!(batch.timebase == config_.timebase))
    throw std::invalid_argument(
        "BeaconCycleDecoder: the batch's timebase (prescale " +
        std::to_string(batch.timebase.prescale) + ", latency " +
        std::to_string(batch.timebase.input_latency_clocks) +
        " clocks) differs from the configured one; a new timebase needs a new decoder");
  if (batch.channels.size() > config_.array.receivers.size())
    throw std::invalid_argument(
        "BeaconCycleDecoder: the batch has " + std::to_string(batch.channels.size()) +
        " channels, the receiver array " + std::to_string(config_.array.receivers.size()));
  if (!have_origin_) {
    have_origin_ = true;
    origin_ = batch.read_tick;
    last_read_ = batch.read_tick;
  }
  const double tick = config_.timebase.tick_s();
  for (const Incident& in : batch.incidents) {
    const Tick lo = std::min(in.from, in.until), hi = std::max(in.from, in.until);
    spans_.push_back({in.kind, in.channel, tick_time(lo), tick_time(hi) + tick});
  }
  const auto ambiguous = [&](int ch, double t) {
    for (const Span& s : spans_)
      if (s.kind == IncidentKind::kUnwrapAmbiguous && s.channel == ch && t >= s.from_s &&
          t < s.until_s)
        return true;
    return false;
  };
  // The FIFOs are drained in the bursts right after the timestamp is read:
  // nothing can be stamped a second later.
  const Tick future = batch.read_tick + static_cast<Tick>(std::ceil(1.0 / tick));
  for (std::size_t ch = 0; ch < batch.channels.size(); ++ch) {
    const ChannelEvents& events = batch.channels[ch];
    const int channel = static_cast<int>(ch);
    if (events.mode != ChannelMode::kEnvelope) {
      if (!events.carrier.empty())
        throw std::invalid_argument("BeaconCycleDecoder: channel " + std::to_string(ch) +
                                    " is in carrier mode; beacon cycles need envelope mode");
      continue;
    }
    for (const EnvelopeEvent& e : events.envelope) {
      // Behind the channel's last event, or stamped after the read (a bad
      // unwrap): not trusted, and not allowed to block the channel.
      if (e.rise < last_rise_[ch] || e.rise > future) {
        ++dropped_pending_;
        continue;
      }
      last_rise_[ch] = e.rise;
      const double rise = tick_time(e.rise);
      if (ambiguous(channel, rise)) {
        ++dropped_pending_;
        continue;
      }
      const double width = e.width * tick;
      if (e.saturated() || width >= config_.stuck_width_s) {
        const double until =
            e.saturated() ? std::max(rise + width, tick_time(batch.read_tick)) : rise + width;
        spans_.push_back({IncidentKind::kStuckHigh, channel, rise, until});
        if (e.saturated())
          saturated_.push_back({channel, rise});
        continue;
      }
      if (width < config_.min_width_s) {
        noise_.push_back({channel, rise});
        continue;
      }
      const CompensatedPulse p =
          compensate_pulse(config_.envelope, rise, width, tick, config_.timing_sd_s);
      if (p.time_s < dropped_before_s_) {  // for time already decoded
        ++dropped_pending_;
        continue;
      }
      pulses_.push_back({channel, e.rise, e.width, p.time_s, p.sd_s, p.compensation});
    }
  }
  std::stable_sort(pulses_.begin(), pulses_.end(),
                   [](const Pulse& a, const Pulse& b) { return a.time_s < b.time_s; });
  if (batch.read_tick > last_read_)
    last_read_ = batch.read_tick;
  // A pulse still high at the read rose at most stuck_width ago (else it is
  // stuck) and its compensated time is at most one burst before its rise.
  horizon_s_ = std::max(horizon_s_,
                        tick_time(last_read_) - config_.stuck_width_s - config_.envelope.burst_s);
}

// Groups the pulses of one wavefront: seeded by the widest (strongest) pulse
// within one array delay of the earliest unassigned one, then every pulse of
// another channel within |r_i - r_j|/c + margin of all members, strongest
// first. A noise pulse ahead of a wavefront is left to itself.
std::vector<BeaconCycleDecoder::Group> BeaconCycleDecoder::build_groups(double from_s,
                                                                        double until_s) const {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < pulses_.size(); ++i)
    if (pulses_[i].time_s >= from_s && pulses_[i].time_s < until_s)
      idx.push_back(i);
  const auto& rx = config_.array.receivers;
  const double window = config_.array.aperture_m() / c_ + config_.group_margin_s;
  const auto compatible = [&](std::size_t a, std::size_t b) {
    const Vec2 ra = rx[static_cast<std::size_t>(pulses_[a].channel)].position_m;
    const Vec2 rb = rx[static_cast<std::size_t>(pulses_[b].channel)].position_m;
    return std::abs(pulses_[a].time_s - pulses_[b].time_s) <=
           std::hypot(ra.x - rb.x, ra.y - rb.y) / c_ + config_.group_margin_s;
  };
  std::vector<bool> taken(idx.size(), false);
  std::vector<Group> groups;
  for (std::size_t pos = 0; pos < idx.size(); ++pos) {
    while (!taken[pos]) {
      const double first = pulses_[idx[pos]].time_s;
      std::size_t seed = pos;
      for (std::size_t q = pos + 1; q < idx.size() && pulses_[idx[q]].time_s <= first + window; ++q)
        if (!taken[q] && pulses_[idx[q]].width > pulses_[idx[seed]].width)
          seed = q;
      taken[seed] = true;
      const double ts = pulses_[idx[seed]].time_s;
      std::vector<std::size_t> members{idx[seed]};
      std::uint32_t channels = 1U << pulses_[idx[seed]].channel;
      std::vector<std::size_t> near;
      for (std::size_t q = pos; q < idx.size() && pulses_[idx[q]].time_s <= ts + window; ++q)
        if (!taken[q] && pulses_[idx[q]].time_s >= ts - window)
          near.push_back(q);
      std::stable_sort(near.begin(), near.end(), [&](std::size_t a, std::size_t b) {
        return pulses_[idx[a]].width > pulses_[idx[b]].width;
      });
      for (const std::size_t q : near) {
        const Pulse& p = pulses_[idx[q]];
        if ((channels & (1U << p.channel)) != 0)
          continue;
        if (!std::all_of(members.begin(), members.end(),
                         [&](std::size_t m) { return compatible(m, idx[q]); }))
          continue;
        members.push_back(idx[q]);
        channels |= 1U << p.channel;
        taken[q] = true;
      }
      Group g;
      g.pulses = members;
      g.arrival = make_arrival(members, g.t0_s);
      groups.push_back(std::move(g));
    }
  }
  std::stable_sort(groups.begin(), groups.end(),
                   [](const Group& a, const Group& b) { return a.t0_s < b.t0_s; });
  return groups;
}

Arrival BeaconCycleDecoder::make_arrival(const std::vector<std::size_t>& members,
                                         double& t0) const {
  std::vector<TimedHit> hits;
  for (const std::size_t m : members)
    hits.push_back({pulses_[m].channel, pulses_[m].time_s, pulses_[m].sd_s});
  // Alone, a receiver heard the pulse better than its neighbours: the
  // source is within half the axis spacing of its axis.
  const PlaneWaveOptions options{c_, single_half_angle_, true};
  const PlaneWaveFit fit = fit_plane_wave(config_.array, hits, options);
  Arrival a;
  const double tick = config_.timebase.tick_s();
  bool merged = false;
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Pulse& p = pulses_[members[i]];
    a.hits.push_back({p.channel, p.rise, p.width, p.comp.delay_s, p.comp.ratio,
                      fit.hits[i].residual_s, fit.hits[i].used});
    a.width_s = std::max(a.width_s, p.width * tick);
    a.amplitude_ratio = std::max(a.amplitude_ratio, p.comp.ratio);
    a.receivers |= 1U << p.channel;
    merged = merged || p.comp.clamped_high;
  }
  std::sort(a.hits.begin(), a.hits.end(),
            [](const ReceiverHit& x, const ReceiverHit& y) { return x.channel < y.channel; });
  t0 = fit.t0_s;
  a.time_s = fit.t0_s;
  a.sd_m = c_ * fit.t0_sd_s;
  a.doa = fit.doa;
  if (members.size() == 1)
    a.flags.set(Flag::kSingleReceiver);
  if (fit.inconsistent)
    a.flags.set(Flag::kDoaInconsistent);
  if (merged)
    a.flags.set(Flag::kMergedPulse);
  if (a.amplitude_ratio < config_.weak_ratio)
    a.flags.set(Flag::kWeak);
  return a;
}

bool BeaconCycleDecoder::is_double(const Group& first, const Group& second) const {
  const double dt = second.t0_s - first.t0_s;
  if (std::abs(dt - config_.schedule.double_spacing_s) > config_.double_tolerance_s)
    return false;
  const std::uint32_t shared = first.arrival.receivers & second.arrival.receivers;
  if (shared == 0)
    return false;
  if (first.arrival.doa.valid && second.arrival.doa.valid &&
      std::abs(angle_difference(first.arrival.doa.bearing_rad, second.arrival.doa.bearing_rad)) >
          config_.double_bearing_tolerance_rad)
    return false;
  // Same burst amplitude: compare on the receiver of `first` that heard it
  // best among those both heard.
  const ReceiverHit* a = nullptr;
  for (const ReceiverHit& h : first.arrival.hits)
    if ((shared & (1U << h.channel)) != 0 &&
        (a == nullptr || h.amplitude_ratio > a->amplitude_ratio))
      a = &h;
  for (const ReceiverHit& h : second.arrival.hits) {
    if (h.channel != a->channel)
      continue;
    const double r = h.amplitude_ratio / a->amplitude_ratio;
    return std::max(r, 1 / r) <= config_.double_amplitude_tolerance;
  }
  return false;
}

const BeaconCycleDecoder::Group* BeaconCycleDecoder::find_double(const std::vector<Group>& groups,
                                                                 double from_s,
                                                                 double until_s) const {
  const double reach = config_.schedule.double_spacing_s + config_.double_tolerance_s;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    if (groups[i].t0_s < from_s)
      continue;
    if (groups[i].t0_s >= until_s)
      break;
    for (std::size_t j = i + 1; j < groups.size() && groups[j].t0_s <= groups[i].t0_s + reach; ++j)
      if (is_double(groups[i], groups[j]))
        return &groups[i];
  }
  return nullptr;
}

void BeaconCycleDecoder::drop_before(double t_s) {
  if (!(t_s > dropped_before_s_))
    return;
  dropped_before_s_ = t_s;
  std::erase_if(pulses_, [&](const Pulse& p) { return p.time_s < t_s; });
  std::erase_if(noise_, [&](const Mark& m) { return m.time_s < t_s; });
  std::erase_if(saturated_, [&](const Mark& m) { return m.time_s < t_s; });
  std::erase_if(spans_, [&](const Span& s) { return s.until_s < t_s; });
}

Flags BeaconCycleDecoder::incident_flags(double from_s, double until_s, int channel) const {
  Flags f;
  for (const Span& s : spans_) {
    if (!(s.from_s < until_s && s.until_s > from_s))
      continue;
    if (s.channel != channel)
      continue;
    f.set(incident_flag(s.kind));
  }
  return f;
}

bool BeaconCycleDecoder::try_lock() {
  if (!std::isfinite(horizon_s_))
    return false;
  const double window = config_.array.aperture_m() / c_ + config_.group_margin_s;
  const double need = config_.schedule.double_spacing_s + config_.double_tolerance_s + window;
  const double keep_back = config_.max_range_m / c_ + config_.early_guard_s + window;
  const double tol = config_.lock_tolerance_s();
  const std::vector<Group> groups = build_groups(consumed_s_ - keep_back, horizon_s_);
  double from = consumed_s_;
  for (;;) {
    const Group* first = find_double(groups, from, horizon_s_ - need);
    if (first == nullptr) {
      consumed_s_ = std::max(consumed_s_, horizon_s_ - need);
      drop_before(consumed_s_ - keep_back);
      return false;
    }
    const double a = first->t0_s;
    bool confirmed = true;
    for (int m = 1; m <= config_.confirm_cycles && confirmed; ++m) {
      const double centre = a + m * cycle_s();
      const double w = m * tol;
      if (horizon_s_ < centre + w + need) {  // wait for the confirming cycle
        consumed_s_ = std::max(consumed_s_, a);
        drop_before(consumed_s_ - keep_back);
        return false;
      }
      confirmed = find_double(groups, centre - w, centre + w) != nullptr;
    }
    if (!confirmed) {
      from = std::nextafter(a, INFINITY);
      continue;
    }
    state_ = State::kLocked;
    anchor_pred_ = a;
    coast_ = 0;
    resync_pending_ = true;
    ++epoch_;
    consumed_s_ = a - config_.max_range_m / c_ - config_.early_guard_s;
    last_measured_anchor_ = NAN;
    for (Track& t : track_)
      t = Track{};
    return true;
  }
}

CycleMeasurement BeaconCycleDecoder::empty_record(double anchor, Flags flags) {
  CycleMeasurement rec;
  rec.sequence = sequence_++;
  rec.lock_epoch = epoch_;
  rec.anchor_s = anchor + static_cast<double>(origin_) * config_.timebase.tick_s();
  rec.fire_period_s = config_.schedule.fire_period_s;
  rec.speed_of_sound_mps = c_;
  rec.channels.resize(config_.array.receivers.size());
  if (dropped_pending_ > 0) {
    flags.set(Flag::kOutOfOrder);
    rec.dropped_events = dropped_pending_;
    dropped_pending_ = 0;
  }
  rec.flags = flags;
  return rec;
}

bool BeaconCycleDecoder::try_cycle(std::vector<CycleMeasurement>& out) {
  const double tol = config_.lock_tolerance_s() * (1 + coast_);
  const double window = config_.array.aperture_m() / c_ + config_.group_margin_s;
  const double need = config_.schedule.double_spacing_s + config_.double_tolerance_s + window;
  const double pred = anchor_pred_;
  const double end_max = cycle_end(pred + tol);
  if (horizon_s_ < std::max(end_max + window, pred + tol + need))
    return false;
  std::vector<Group> groups = build_groups(consumed_s_, end_max + window);
  Flags flags;
  double anchor = pred;
  bool measured = false;
  if (const Group* g = find_double(groups, pred - tol, pred + tol)) {
    anchor = g->t0_s;
    measured = true;
    coast_ = 0;
  } else {
    flags.set(Flag::kDoublePulseMissing);
    const bool elsewhere = find_double(groups, consumed_s_, cycle_end(pred)) != nullptr;
    if (elsewhere || coast_ >= config_.max_coast_cycles) {
      if (elsewhere)
        flags.set(Flag::kDoublePulseMisplaced);
      out.push_back(empty_record(pred, flags.set(Flag::kLockLost)));
      state_ = State::kSearching;
      coast_ = 0;
      // Misplaced: the search starts here and finds it; missing: after this cycle.
      if (!elsewhere)
        consumed_s_ = cycle_end(pred);
      return true;
    }
    ++coast_;
    flags.set(Flag::kCoasted);
  }
  if (resync_pending_) {
    flags.set(Flag::kResynchronised);
    resync_pending_ = false;
  }
  const double end = cycle_end(anchor);
  std::erase_if(groups, [&](const Group& g) { return g.t0_s >= end; });
  CycleMeasurement rec = decode_cycle(groups, anchor, flags, measured);
  if (measured && std::isfinite(last_measured_anchor_))
    rec.cycle_period_s = anchor - last_measured_anchor_;
  last_measured_anchor_ = measured ? anchor : NAN;
  out.push_back(std::move(rec));
  consumed_s_ = end;
  drop_before(end);
  anchor_pred_ = anchor + cycle_s();
  return true;
}

// The cycle's parts: part[k] .. part[k + 1] belongs to beacon k's slot (the
// first part from where decoding stopped), part[n] .. the cycle's end to the
// reserved slots; a slot starts one separation (the farthest echo's flight
// plus the early guard) before its fire time.
std::vector<double> BeaconCycleDecoder::slot_bounds(double anchor) const {
  const BeaconSchedule& sch = config_.schedule;
  const auto n = static_cast<std::size_t>(sch.beacons);
  const double separation = config_.max_range_m / c_ + config_.early_guard_s;
  std::vector<double> part(n + 1);
  part[0] = std::min(consumed_s_, anchor - separation);
  for (std::size_t k = 1; k < n; ++k)
    part[k] = anchor + static_cast<double>(k) * sch.fire_period_s - separation;
  part[n] = sch.reserved_slots > 0 ? reserved_start(anchor) - separation : cycle_end(anchor);
  return part;
}

double BeaconCycleDecoder::reserved_start(double anchor) const {
  const BeaconSchedule& sch = config_.schedule;
  return anchor + static_cast<double>(sch.beacons) * sch.fire_period_s;
}

// How much earlier than its fire time beacon k's wavefront can arrive: its
// distance from beacon 0 (the anchor) and the tolerance, or the range limit
// without a layout.
std::vector<double> BeaconCycleDecoder::beacon_reach() const {
  const auto n = static_cast<std::size_t>(config_.schedule.beacons);
  const auto& pos = config_.beacon_positions;
  std::vector<double> reach;
  for (std::size_t k = 0; k < n; ++k)
    reach.push_back(k == 0        ? 0.0
                    : pos.empty() ? config_.max_range_m
                                  : std::hypot(pos[k].x - pos[0].x, pos[k].y - pos[0].y) +
                                        config_.geometry_tolerance_m);
  return reach;
}

// Each wavefront into its beacon's slot, as a candidate or (before the
// slot's acceptance bound) rejected; beacon 0's second pulse of the double
// is not an arrival; the rest into the reserved slots.
void BeaconCycleDecoder::assign_to_slots(std::vector<Group>& groups, double anchor,
                                         const std::vector<double>& part,
                                         const std::vector<double>& reach,
                                         CycleMeasurement& rec) const {
  const BeaconSchedule& sch = config_.schedule;
  const std::size_t n = rec.beacons.size();
  for (std::size_t k = 0; k < n; ++k) {
    BeaconMeasurement& b = rec.beacons[k];
    b.beacon = static_cast<int>(k);
    const double start = anchor + static_cast<double>(k) * sch.fire_period_s;
    const double accept_from = start - reach[k] / c_ - (k == 0 ? config_.double_tolerance_s : 0.0);
    std::vector<double> accepted_t0;
    std::vector<std::uint32_t> accepted_rx;
    for (Group& g : groups) {
      if (g.t0_s >= part[k + 1] || (k > 0 && g.t0_s < part[k]))
        continue;
      if (k == 0) {
        bool second = false;
        for (std::size_t i = 0; i < accepted_t0.size() && !second; ++i)
          second = std::abs(g.t0_s - accepted_t0[i] - sch.double_spacing_s) <=
                       config_.double_tolerance_s &&
                   (accepted_rx[i] & g.arrival.receivers) != 0;
        if (second)
          continue;
      }
      Arrival a = std::move(g.arrival);
      a.time_s = g.t0_s - start;
      a.distance_m = c_ * a.time_s;
      if (g.t0_s < accept_from) {
        a.flags.set(Flag::kEarlyRejected);
        b.rejected.push_back(std::move(a));
      } else {
        accepted_t0.push_back(g.t0_s);
        accepted_rx.push_back(a.receivers);
        b.candidates.push_back(std::move(a));
      }
    }
  }
  const double end = cycle_end(anchor);
  for (Group& g : groups) {
    if (g.t0_s < part[n] || g.t0_s >= end)
      continue;
    Arrival& a = rec.reserved.emplace_back(std::move(g.arrival));
    a.time_s = g.t0_s - reserved_start(anchor);
    a.distance_m = c_ * a.time_s;
  }
}

// Kleeman 4.3: arrivals can only be late. When several beacons have
// wavefronts before their bound, beacon 0's arrival (the anchor) is the late
// one: keep them as candidates, flagged. Two beacons, or half of those
// heard: a genuine tail of the previous slot is rare (t_fire is chosen so
// that echoes die out), a late reference moves every slot.
void BeaconCycleDecoder::check_reference(CycleMeasurement& rec, Flags& cycle_flags) const {
  const auto heard_by_enough = [&](const Arrival& a) {
    return popcount(a.receivers) >= config_.min_receivers;
  };
  int early = 0, seen = 0;
  for (std::size_t k = 1; k < rec.beacons.size(); ++k) {
    const BeaconMeasurement& b = rec.beacons[k];
    if (!b.candidates.empty() || !b.rejected.empty())
      ++seen;
    if (std::ranges::any_of(b.rejected, heard_by_enough))
      ++early;
  }
  if (!(early >= 2 || (early >= 1 && 2 * early >= seen)))
    return;
  cycle_flags.set(Flag::kReferenceSuspect);
  rec.beacons[0].flags.set(Flag::kEchoSuspect);
  for (BeaconMeasurement& b : rec.beacons) {  // beacon 0's direct pulse may be among them too
    for (Arrival& a : b.rejected) {
      a.flags.clear(Flag::kEarlyRejected).set(Flag::kBeforeBound);
      b.candidates.push_back(std::move(a));
    }
    b.rejected.clear();
    std::stable_sort(b.candidates.begin(), b.candidates.end(),
                     [](const Arrival& x, const Arrival& y) { return x.time_s < y.time_s; });
  }
}

// Beacon k's flags from the cycle, its slot's incidents and its arrivals,
// and its primary: the first candidate heard by min_receivers (else the
// first).
void BeaconCycleDecoder::classify_beacon(BeaconMeasurement& b, std::size_t k, double from_s,
                                         double until_s, double reach_m, Flags cycle_flags,
                                         double anchor, bool measured) {
  const Flags propagated_mask = Flags(Flag::kResynchronised) | Flag::kCoasted |
                                Flag::kDoublePulseMissing | Flag::kReferenceSuspect |
                                Flag::kOutOfOrder;
  Flags& f = b.flags;
  f |= Flags(cycle_flags.bits() & propagated_mask.bits());
  for (std::size_t ch = 0; ch < config_.array.receivers.size(); ++ch)
    f |= incident_flags(from_s, until_s, static_cast<int>(ch));
  for (const Mark& m : noise_)
    if (m.time_s >= from_s && m.time_s < until_s)
      f.set(Flag::kNoise);
  for (const Mark& m : saturated_)
    if (m.time_s >= from_s && m.time_s < until_s)
      f.set(Flag::kSaturated).set(Flag::kStuckChannel);
  if (!b.rejected.empty())
    f.set(Flag::kEarlyRejected);
  // A rejected wavefront heard by several receivers may have been the
  // direct pulse after all, if the anchor was late: the rest is suspect.
  if (std::ranges::any_of(b.rejected, [&](const Arrival& a) {
        return popcount(a.receivers) >= config_.min_receivers;
      }))
    f.set(Flag::kEchoSuspect);
  if (b.candidates.empty()) {
    f.set(Flag::kMissing);
    return;
  }
  if (b.candidates.size() > 1)
    f.set(Flag::kEchoes);
  for (std::size_t i = 0; i < b.candidates.size() && b.primary < 0; ++i)
    if (popcount(b.candidates[i].receivers) >= config_.min_receivers)
      b.primary = static_cast<int>(i);
  if (b.primary < 0)
    b.primary = 0;
  Arrival& p = b.candidates[static_cast<std::size_t>(b.primary)];
  for (const Flag carried :
       {Flag::kSingleReceiver, Flag::kDoaInconsistent, Flag::kWeak, Flag::kMergedPulse})
    if (p.flags.has(carried))
      f.set(carried);
  if (p.flags.has(Flag::kMergedPulse))
    f.set(Flag::kEchoSuspect);
  if (k > 0 && p.distance_m > reach_m + 3 * p.sd_m) {
    p.flags.set(Flag::kOutOfRange);
    f.set(Flag::kEchoSuspect);
  }
  for (std::size_t i = static_cast<std::size_t>(b.primary) + 1; i < b.candidates.size(); ++i)
    if (p.amplitude_ratio < config_.weak_ratio &&
        b.candidates[i].amplitude_ratio >= config_.occlusion_contrast * p.amplitude_ratio)
      f.set(Flag::kOccludedSuspect);
  if (measured)
    track_occlusion(k, p, f, anchor);
}

// Kleeman: arrivals can only be late. d_k - d_0 changes by at most
// 2 max_speed per second; a primary later than that is an echo of a hidden
// direct path, and stays suspect until it jumps back.
void BeaconCycleDecoder::track_occlusion(std::size_t k, const Arrival& p, Flags& f, double anchor) {
  Track& t = track_[k];
  const double slack = config_.geometry_tolerance_m + 3 * p.sd_m;
  const double speed = 2 * config_.max_speed_mps;
  if (t.occluded) {
    const bool back = p.distance_m < t.last_m - speed * (anchor - t.last_anchor_s) - slack;
    if (back || ++t.occluded_cycles > config_.occlusion_memory_cycles) {
      t.occluded = false;
    } else {
      f.set(Flag::kOccludedSuspect);
      t.last_m = p.distance_m, t.last_anchor_s = anchor;
    }
  } else if (t.valid && p.distance_m > t.distance_m + speed * (anchor - t.anchor_s) + slack) {
    f.set(Flag::kOccludedSuspect);
    t.occluded = true;
    t.occluded_cycles = 1;
    t.last_m = p.distance_m, t.last_anchor_s = anchor;
  }
  if (!f.has(Flag::kOccludedSuspect) && !f.has(Flag::kEchoSuspect) &&
      !f.has(Flag::kSingleReceiver)) {
    t.valid = true;
    t.distance_m = p.distance_m, t.anchor_s = anchor;
  }
}

// Channels: use, noise, stuck; silent where a strong direct arrival came
// from within its receiver's expected angle and it heard nothing.
void BeaconCycleDecoder::channel_status(CycleMeasurement& rec, double from_s, double end) const {
  const std::size_t channels = config_.array.receivers.size();
  for (std::size_t ch = 0; ch < channels; ++ch) {
    ChannelStatus& s = rec.channels[ch];
    s.flags = incident_flags(from_s, end, static_cast<int>(ch));
    s.stuck = s.flags.has(Flag::kStuckChannel);
    for (const Mark& m : saturated_)
      if (m.channel == static_cast<int>(ch) && m.time_s < end)
        s.stuck = true;
    for (const Mark& m : noise_)
      if (m.channel == static_cast<int>(ch) && m.time_s < end)
        ++s.noise;
    rec.noise_pulses += s.noise;
    std::vector<const std::vector<Arrival>*> lists{&rec.reserved};
    for (const BeaconMeasurement& b : rec.beacons)
      lists.insert(lists.end(), {&b.candidates, &b.rejected});
    for (const auto* list : lists)
      for (const Arrival& a : *list)
        if ((a.receivers & (1U << ch)) != 0)
          ++s.pulses;
  }
  for (std::size_t ch = 0; ch < channels; ++ch) {
    ChannelStatus& s = rec.channels[ch];
    if (s.pulses > 0 || s.noise > 0 || s.stuck)
      continue;
    const double axis = config_.array.receivers[ch].axis_rad;
    for (BeaconMeasurement& b : rec.beacons) {
      const Arrival* p = b.direct();
      if (p == nullptr || !p->doa.valid || p->amplitude_ratio < config_.strong_ratio)
        continue;
      if (std::abs(angle_difference(p->doa.bearing_rad, axis)) > config_.expect_half_angle_rad)
        continue;
      s.silent = true;
      b.flags.set(Flag::kDeadChannel);
    }
  }
}

CycleMeasurement BeaconCycleDecoder::decode_cycle(std::vector<Group>& groups, double anchor,
                                                  Flags cycle_flags, bool measured) {
  const auto n = static_cast<std::size_t>(config_.schedule.beacons);
  const std::vector<double> part = slot_bounds(anchor);
  const std::vector<double> reach = beacon_reach();
  CycleMeasurement rec = empty_record(anchor, cycle_flags);
  cycle_flags = rec.flags;  // with kOutOfOrder
  rec.beacons.resize(n);
  assign_to_slots(groups, anchor, part, reach, rec);
  if (measured)
    check_reference(rec, cycle_flags);
  rec.flags = cycle_flags;
  for (std::size_t k = 0; k < n; ++k)
    classify_beacon(rec.beacons[k], k, part[k], part[k + 1], reach[k], cycle_flags, anchor,
                    measured);
  channel_status(rec, part[0], cycle_end(anchor));
  return rec;
}

std::vector<CycleMeasurement> BeaconCycleDecoder::push(const CaptureBatch& batch) {
  ingest(batch);
  std::vector<CycleMeasurement> out;
  for (;;) {
    if (state_ == State::kSearching) {
      if (!try_lock())
        break;
    } else if (!try_cycle(out)) {
      break;
    }
  }
  return out;
}

}  // namespace odoloc::sw::tof
