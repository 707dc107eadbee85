#include "odoloc/sw/tof_sync_modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

namespace odoloc::sw::tof {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

void require(bool ok, const char* owner, const std::string& message) {
  if (!ok)
    throw std::invalid_argument(std::string(owner) + ": " + message);
}
bool finite_positive(double v) {
  return std::isfinite(v) && v > 0;
}
bool finite_non_negative(double v) {
  return std::isfinite(v) && v >= 0;
}

// Incident flags for `channel` overlapping the ticks [from, until).
Flags incident_flags(std::span<const Incident> incidents, int channel, Tick from, Tick until) {
  Flags f;
  for (const Incident& in : incidents) {
    if (in.channel != channel)
      continue;
    const Tick lo = std::min(in.from, in.until), hi = std::max(in.from, in.until);
    if (!(lo < until && hi >= from))
      continue;
    f.set(incident_flag(in.kind));
  }
  return f;
}

bool unwrap_ambiguous(std::span<const Incident> incidents, int channel, Tick t) {
  for (const Incident& in : incidents)
    if (in.kind == IncidentKind::kUnwrapAmbiguous && in.channel == channel &&
        t >= std::min(in.from, in.until) && t < std::max(in.from, in.until))
      return true;
  return false;
}

Tick ticks_after(Tick base, double seconds, double tick_s) {
  const double n = std::ceil(seconds / tick_s);
  if (n <= 0)
    return base;
  return base + static_cast<Tick>(n);
}

void check_channels(const char* owner, int channel, std::span<const ChannelEvents> channels) {
  require(channel >= 0 && static_cast<std::size_t>(channel) < channels.size(), owner,
          "channel " + std::to_string(channel) + " is not among the " +
              std::to_string(channels.size()) + " channels given");
}

}  // namespace

// ------------------------------------------------------------------ Thamma

void ThammaConfig::validate() const {
  const char* o = "ThammaConfig";
  require(!boxes.empty(), o, "at least one receiver box");
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    require(!boxes[b].channels.empty(), o, "box " + std::to_string(b) + " has no channel");
    for (const int ch : boxes[b].channels)
      require(ch >= 0 && ch < 32, o, "box " + std::to_string(b) + ": channel out of 0..31");
    require(finite_positive(boxes[b].carrier_hz), o,
            "box " + std::to_string(b) + ": carrier_hz must be finite and positive");
  }
  require(std::isfinite(fixed_delay_s), o, "fixed_delay_s must be finite");
  require(finite_non_negative(min_tof_s), o, "min_tof_s must be finite and >= 0");
  require(std::isfinite(max_tof_s) && max_tof_s > min_tof_s, o,
          "max_tof_s must be finite and above min_tof_s");
  require(repeats >= 1 && repeats <= 64, o, "repeats must be 1..64");
  require(finite_positive(outlier_tolerance_s), o,
          "outlier_tolerance_s must be finite and positive");
  envelope.validate("ThammaConfig.envelope");
  require(finite_non_negative(min_width_s), o, "min_width_s must be finite and >= 0");
  require(std::isfinite(speed_of_sound_mps) && speed_of_sound_mps > 200 && speed_of_sound_mps < 500,
          o, "speed_of_sound_mps must be in (200, 500)");
  require(finite_non_negative(timing_sd_s), o, "timing_sd_s must be finite and >= 0");
}

ThammaMeasurement measure_thamma(const ThammaConfig& config, const Timebase& timebase,
                                 std::span<const Tick> sync,
                                 std::span<const ChannelEvents> channels,
                                 std::span<const Incident> incidents) {
  config.validate();
  timebase.validate();
  for (const auto& box : config.boxes)
    for (const int ch : box.channels)
      check_channels("measure_thamma", ch, channels);
  ThammaMeasurement out;
  if (sync.empty())
    out.flags.set(Flag::kInvalid).set(Flag::kSyncMissing);
  if (!sync.empty() && sync.size() < config.repeats)
    out.flags.set(Flag::kSyncMissing);
  if (sync.size() > config.repeats)
    out.flags.set(Flag::kExtraSync);
  const double tick = timebase.tick_s();
  const double c = config.speed_of_sound_mps;
  const double q = timebase.quantisation_sd_s();
  // Sync and receivers pass the same input conditioner: the latency cancels,
  // edge_time_s subtracts it from both anyway.
  for (std::size_t b = 0; b < config.boxes.size(); ++b) {
    const ThammaConfig::Box& box = config.boxes[b];
    ThammaBoxResult r;
    r.box = static_cast<int>(b);
    r.carrier_hz = box.carrier_hz;
    std::vector<double> tofs;
    std::vector<std::size_t> which;
    for (std::size_t k = 0; k < sync.size(); ++k) {
      ThammaRepeat rep;
      const Tick s = sync[k];
      const Tick lo = ticks_after(s, config.fixed_delay_s + config.min_tof_s - tick, tick);
      Tick hi = ticks_after(s, config.fixed_delay_s + config.max_tof_s + tick, tick);
      if (k + 1 < sync.size())
        hi = std::min(hi, sync[k + 1]);
      rep.flags |= incident_flags(incidents, kSyncChannel, s, s + 1);
      for (const int ch : box.channels) {
        const ChannelEvents& ev = channels[static_cast<std::size_t>(ch)];
        rep.flags |= incident_flags(incidents, ch, lo, hi);
        const auto consider = [&](Tick rise, double delay) {
          if (rise < lo || rise >= hi)
            return;
          if (unwrap_ambiguous(incidents, ch, rise)) {
            rep.flags.set(Flag::kUnwrapAmbiguous);
            return;
          }
          const double t = timebase.edge_time_s(rise, s) - timebase.edge_time_s(s, s) - delay -
                           config.fixed_delay_s;
          if (t < config.min_tof_s || t >= config.max_tof_s)
            return;
          if (std::isnan(rep.tof_s) || t < rep.tof_s)
            rep.tof_s = t, rep.channel = ch;
        };
        if (ev.mode == ChannelMode::kEnvelope) {
          for (const EnvelopeEvent& e : ev.envelope) {
            if (e.rise < lo || e.rise >= hi)
              continue;
            if (e.saturated()) {
              rep.flags.set(Flag::kSaturated).set(Flag::kStuckChannel);
              continue;
            }
            const double w = e.width * tick;
            if (w < config.min_width_s) {
              rep.flags.set(Flag::kNoise);
              continue;
            }
            const EnvelopeModel::Inverse inv = config.envelope.invert_width(w);
            if (inv.clamped_high)
              rep.flags.set(Flag::kMergedPulse);
            consider(e.rise, config.compensate_rise ? inv.delay_s : 0.0);
          }
        } else {
          for (const CarrierEvent& e : ev.carrier)
            consider(e.rise, 0.0);
        }
      }
      if (std::isnan(rep.tof_s)) {
        rep.flags.set(Flag::kMissing);
      } else {
        tofs.push_back(rep.tof_s);
        which.push_back(k);
      }
      r.flags |= Flags(rep.flags.bits() & ~Flags(Flag::kMissing).bits());
      r.repeats.push_back(rep);
    }
    // Outliers: with three or more, drop what is far from the median.
    std::vector<double> kept = tofs;
    if (tofs.size() >= 3) {
      std::vector<double> sorted = tofs;
      std::sort(sorted.begin(), sorted.end());
      const std::size_t m = sorted.size() / 2;
      const double median = sorted.size() % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
      kept.clear();
      for (std::size_t i = 0; i < tofs.size(); ++i) {
        if (std::abs(tofs[i] - median) > config.outlier_tolerance_s) {
          r.repeats[which[i]].flags.set(Flag::kOutlier);
          r.flags.set(Flag::kOutlier);
        } else {
          kept.push_back(tofs[i]);
        }
      }
    } else if (tofs.size() == 2 && std::abs(tofs[0] - tofs[1]) > 2 * config.outlier_tolerance_s) {
      r.flags.set(Flag::kOutlier);  // two that disagree: kept, flagged
    }
    r.used = static_cast<int>(kept.size());
    if (kept.empty()) {
      r.flags.set(Flag::kMissing);
    } else {
      double mean = 0;
      for (const double t : kept)
        mean += t;
      mean /= static_cast<double>(kept.size());
      double ss = 0;
      for (const double t : kept)
        ss += (t - mean) * (t - mean);
      r.tof_s = mean;
      r.spread_s = kept.size() > 1 ? std::sqrt(ss / static_cast<double>(kept.size() - 1)) : 0.0;
      const double model = std::sqrt(2 * q * q + config.timing_sd_s * config.timing_sd_s);
      r.sd_s = std::max(r.spread_s, model) / std::sqrt(static_cast<double>(kept.size()));
      r.distance_m = c * r.tof_s;
      r.distance_sd_m = c * r.sd_s;
    }
    r.flags |= out.flags;  // sync problems concern every box
    out.boxes.push_back(std::move(r));
  }
  return out;
}

// --------------------------------------------------------------- binaural

void BinauralConfig::validate() const {
  const char* o = "BinauralConfig";
  require(!pairs.empty(), o, "at least one receiver pair");
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const BinauralPair& p = pairs[i];
    const std::string at = "pair " + std::to_string(i) + ": ";
    require(p.left >= 0 && p.left < 32 && p.right >= 0 && p.right < 32 && p.left != p.right, o,
            at + "channels must be two different ones in 0..31");
    require(finite_positive(p.baseline_m), o, at + "baseline_m must be finite and positive");
    require(finite_positive(p.carrier_hz), o, at + "carrier_hz must be finite and positive");
    require(p.left_envelope >= -1 && p.left_envelope < 32 && p.right_envelope >= -1 &&
                p.right_envelope < 32,
            o, at + "envelope channels must be -1 (none) or 0..31");
  }
  envelope.validate("BinauralConfig.envelope");
  require(std::isfinite(fixed_delay_s), o, "fixed_delay_s must be finite");
  require(edges >= 1 && edges <= 127, o, "edges (K) must be 1..127");
  require(finite_positive(max_tof_s), o, "max_tof_s must be finite and positive");
  require(std::isfinite(period_tolerance) && period_tolerance > 0 && period_tolerance < 0.5, o,
          "period_tolerance must be in (0, 0.5)");
  require(std::isfinite(ambiguity_limit) && ambiguity_limit > 0 && ambiguity_limit <= 0.5, o,
          "ambiguity_limit must be in (0, 0.5]");
  require(std::isfinite(speed_of_sound_mps) && speed_of_sound_mps > 200 && speed_of_sound_mps < 500,
          o, "speed_of_sound_mps must be in (200, 500)");
}

namespace {

struct EdgeTrain {
  std::vector<double> t;         // seconds after the reference
  std::vector<std::uint32_t> k;  // edge index since arming, less the irregular edges before it
  Flags flags;
};

// The first K edges of one channel after the reference. Edges off the
// carrier's grid (its phase: the circular mean over all edges) by more than
// period_tolerance are noise: left out, and the fabric's index of every
// later edge, which counted them, is corrected.
EdgeTrain edge_train(const BinauralConfig& config, const Timebase& timebase, Tick reference,
                     const ChannelEvents& ev, int channel, double f,
                     std::span<const Incident> incidents) {
  EdgeTrain train;
  const double tick = timebase.tick_s();
  const Tick until = ticks_after(
      reference,
      config.fixed_delay_s + config.max_tof_s + (static_cast<double>(config.edges) + 1.0) / f,
      tick);
  train.flags |= incident_flags(incidents, channel, reference, until);
  if (ev.mode != ChannelMode::kCarrier) {
    train.flags.set(Flag::kInvalid);
    return train;
  }
  std::vector<double> t;
  std::vector<std::uint32_t> k;
  for (const CarrierEvent& e : ev.carrier) {
    if (e.rise < reference || e.rise >= until || e.edge >= config.edges)
      continue;
    if (unwrap_ambiguous(incidents, channel, e.rise)) {
      train.flags.set(Flag::kUnwrapAmbiguous);
      continue;
    }
    const double te =
        timebase.edge_time_s(e.rise, reference) - timebase.edge_time_s(reference, reference);
    if (!t.empty() && (e.edge <= k.back() || te <= t.back())) {  // out of order or repeated
      train.flags.set(Flag::kCarrierIrregular);
      continue;
    }
    t.push_back(te);
    k.push_back(e.edge);
  }
  std::complex<double> sum = 0;
  for (const double te : t)
    sum += std::polar(1.0, kTwoPi * f * te);
  const double grid = std::arg(sum) / kTwoPi;  // in periods
  std::uint32_t irregular = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double off = std::remainder(f * t[i] - grid, 1.0);
    if (std::abs(off) > config.period_tolerance) {
      train.flags.set(Flag::kCarrierIrregular);
      ++irregular;
      continue;
    }
    train.t.push_back(t[i]);
    train.k.push_back(k[i] - irregular);
  }
  if (train.t.empty()) {
    train.flags.set(Flag::kMissing);
  } else if (train.k.front() != 0 || train.k.back() + 1 != train.k.size() + train.k.front()) {
    train.flags.set(Flag::kEdgesMissing);
  }
  return train;
}

}  // namespace

namespace {

// The rise-time-compensated arrival of the first envelope pulse on
// `channel` after `reference`, seconds after it; nullopt without one.
std::optional<double> envelope_arrival(const BinauralConfig& config, const Timebase& timebase,
                                       Tick reference, std::span<const ChannelEvents> channels,
                                       int channel) {
  if (channel < 0)
    return std::nullopt;
  check_channels("measure_binaural", channel, channels);
  const ChannelEvents& ev = channels[static_cast<std::size_t>(channel)];
  if (ev.mode != ChannelMode::kEnvelope)
    return std::nullopt;
  for (const EnvelopeEvent& e : ev.envelope) {
    if (e.rise < reference || e.saturated())
      continue;
    const double width_s = static_cast<double>(e.width) * timebase.tick_s();
    return timebase.edge_time_s(e.rise, reference) - timebase.edge_time_s(reference, reference) -
           config.envelope.invert_width(width_s).delay_s;
  }
  return std::nullopt;
}

}  // namespace

BinauralMeasurement measure_binaural(const BinauralConfig& config, const Timebase& timebase,
                                     Tick reference, std::span<const ChannelEvents> channels,
                                     std::span<const Incident> incidents) {
  config.validate();
  timebase.validate();
  BinauralMeasurement out;
  const double c = config.speed_of_sound_mps;
  for (const BinauralPair& pair : config.pairs) {
    check_channels("measure_binaural", pair.left, channels);
    check_channels("measure_binaural", pair.right, channels);
    const double f = pair.carrier_hz;
    BinauralPairResult r;
    r.left = pair.left;
    r.right = pair.right;
    const EdgeTrain l =
        edge_train(config, timebase, reference, channels[static_cast<std::size_t>(pair.left)],
                   pair.left, f, incidents);
    const EdgeTrain rt =
        edge_train(config, timebase, reference, channels[static_cast<std::size_t>(pair.right)],
                   pair.right, f, incidents);
    r.flags = l.flags | rt.flags;
    if (l.t.empty() || rt.t.empty()) {
      r.flags.set(Flag::kMissing).set(Flag::kInvalid);
      out.flags |= r.flags;
      out.pairs.push_back(r);
      continue;
    }
    // Coarse: the first edge moved back to edge index 0.
    r.tof_left_s = l.t.front() - l.k.front() / f - config.fixed_delay_s;
    r.tof_right_s = rt.t.front() - rt.k.front() / f - config.fixed_delay_s;
    r.coarse_difference_s = r.tof_left_s - r.tof_right_s;
    // The envelopes, when wired, decide the whole periods instead.
    const std::optional<double> envelope_left =
        envelope_arrival(config, timebase, reference, channels, pair.left_envelope);
    const std::optional<double> envelope_right =
        envelope_arrival(config, timebase, reference, channels, pair.right_envelope);
    if (envelope_left && envelope_right)
      r.coarse_difference_s = *envelope_left - *envelope_right;
    else
      r.flags.set(Flag::kCycleUnverified);
    // Fine: circular mean over the edge indices both recorded.
    std::complex<double> sum = 0;
    for (std::size_t i = 0, j = 0; i < l.t.size() && j < rt.t.size();) {
      if (l.k[i] < rt.k[j]) {
        ++i;
      } else if (rt.k[j] < l.k[i]) {
        ++j;
      } else {
        sum += std::polar(1.0, kTwoPi * f * (l.t[i] - rt.t[j]));
        ++r.edges_used;
        ++i, ++j;
      }
    }
    if (r.edges_used == 0) {
      r.flags.set(Flag::kInvalid);
      out.flags |= r.flags;
      out.pairs.push_back(r);
      continue;
    }
    const double resultant = std::min(1.0, std::abs(sum) / r.edges_used);
    r.phase_rad = std::arg(sum);
    r.phase_sd_rad = resultant > 0 ? std::sqrt(-2 * std::log(resultant)) : INFINITY;
    const double fine = r.phase_rad / (kTwoPi * f);
    r.cycles = static_cast<int>(std::lround((r.coarse_difference_s - fine) * f));
    r.difference_s = fine + r.cycles / f;
    // Quantisation alone when the edges agree exactly.
    const double floor_sd = std::sqrt(2.0) * timebase.quantisation_sd_s() * kTwoPi * f;
    r.difference_sd_s = std::max(r.phase_sd_rad, floor_sd) / (kTwoPi * f) /
                        std::sqrt(static_cast<double>(r.edges_used));
    r.path_difference_m = c * r.difference_s;
    r.ambiguity = std::abs(r.coarse_difference_s - r.difference_s) * f;
    if (r.ambiguity > config.ambiguity_limit)
      r.flags.set(Flag::kAmbiguous);
    if (std::abs(r.path_difference_m) > pair.baseline_m + c / f / 2)
      r.flags.set(Flag::kOutOfRange);
    out.flags |= r.flags;
    out.pairs.push_back(r);
  }
  return out;
}

}  // namespace odoloc::sw::tof
