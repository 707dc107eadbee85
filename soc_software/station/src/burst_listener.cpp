// Liu's ranging burst as the robot hears it (burst_listener.hpp).
#include "odoloc/sw/burst_listener.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

#include "odoloc/sw/detail/config_checks.hpp"

namespace odoloc::sw::station {

void BurstListenerConfig::validate() const {
  constexpr std::string_view kOwner = "BurstListenerConfig";
  array.validate();
  envelope.validate(std::string(kOwner) + ".envelope");
  detail::require(detail::finite_positive(speed_of_sound_mps), kOwner,
                  "speed_of_sound_mps must be finite and > 0");
  detail::require(detail::finite_positive(max_range_m), kOwner,
                  "max_range_m must be finite and > 0");
  detail::require(detail::finite_non_negative(min_width_s), kOwner,
                  "min_width_s must be finite and >= 0");
  detail::require(detail::finite_non_negative(timing_sd_s), kOwner,
                  "timing_sd_s must be finite and >= 0");
  detail::require(detail::finite_non_negative(group_margin_s), kOwner,
                  "group_margin_s must be finite and >= 0");
  detail::require(min_receivers >= 1 && min_receivers <= static_cast<int>(array.receivers.size()),
                  kOwner, "min_receivers must be in [1, receivers]");
}

BurstListener::BurstListener(BurstListenerConfig config)
    : config_((config.validate(), std::move(config))),
      aperture_s_(config_.array.aperture_m() / config_.speed_of_sound_mps +
                  config_.group_margin_s) {}

void BurstListener::push(const tof::CaptureBatch& batch) {
  const double tick = batch.timebase.tick_s();
  const auto time_of = [&](tof::Tick t) { return batch.timebase.edge_time_s(t, 0); };
  // Events lost or mistimed spoil a window; a comparator stuck high only
  // takes its own channel out (the others still hear the wavefront).
  for (const tof::Incident& in : batch.incidents)
    if (in.channel != tof::kSyncChannel && in.kind != tof::IncidentKind::kStuckHigh)
      incidents_.push_back(
          {time_of(std::min(in.from, in.until)), time_of(std::max(in.from, in.until)) + tick});
  const std::size_t channels = std::min(batch.channels.size(), config_.array.receivers.size());
  for (std::size_t ch = 0; ch < channels; ++ch) {
    const tof::ChannelEvents& events = batch.channels[ch];
    if (events.mode != tof::ChannelMode::kEnvelope)
      continue;
    for (const tof::EnvelopeEvent& e : events.envelope) {
      const double width = e.width * tick;
      if (e.saturated() || width < config_.min_width_s)
        continue;
      const tof::CompensatedPulse p = tof::compensate_pulse(config_.envelope, time_of(e.rise),
                                                            width, tick, config_.timing_sd_s);
      pulses_.push_back({static_cast<int>(ch), p.time_s, p.sd_s});
    }
  }
  std::ranges::stable_sort(pulses_, {}, &Pulse::time_s);
  // An envelope entry exists from its fall on: a pulse still high at the
  // read is at most the longest single burst wide, and its compensated
  // arrival at most one burst before its rise.
  complete_s_ = std::max(complete_s_, time_of(batch.read_tick) - config_.envelope.max_width_s() -
                                          config_.envelope.burst_s);
}

BurstResult BurstListener::listen(double sent_s) const {
  const double until_s = sent_s + config_.max_range_m / config_.speed_of_sound_mps;
  if (complete_s_ < until_s + aperture_s_)
    return {};
  for (const Span& s : incidents_)
    if (s.from_s < until_s + aperture_s_ && s.until_s > sent_s)
      return {.status = BurstStatus::kLost, .burst = {}};
  const auto first = std::ranges::upper_bound(pulses_, sent_s, {}, &Pulse::time_s);
  for (auto it = first; it != pulses_.end() && it->time_s <= until_s; ++it) {
    // The first pulse of each channel within the aperture of this one.
    std::vector<tof::TimedHit> hits;
    std::uint32_t receivers = 0;
    for (auto m = it; m != pulses_.end() && m->time_s <= it->time_s + aperture_s_; ++m) {
      const std::uint32_t bit = 1U << static_cast<unsigned>(m->channel);
      if ((receivers & bit) != 0)
        continue;
      receivers |= bit;
      hits.push_back({m->channel, m->time_s, m->sd_s});
    }
    if (std::popcount(receivers) < config_.min_receivers)
      continue;
    const tof::PlaneWaveFit fit = tof::fit_plane_wave(
        config_.array, hits, {.speed_of_sound_mps = config_.speed_of_sound_mps});
    return {.status = BurstStatus::kHeard,
            .burst = {.arrival_s = fit.t0_s, .sd_s = fit.t0_sd_s, .receivers = receivers}};
  }
  return {.status = BurstStatus::kNotHeard, .burst = {}};
}

void BurstListener::drop_before(double t_s) {
  std::erase_if(pulses_, [&](const Pulse& p) { return p.time_s < t_s; });
  std::erase_if(incidents_, [&](const Span& s) { return s.until_s < t_s; });
}

}  // namespace odoloc::sw::station
