// Thamma's ranging cycle on the SoC (thamma_cycle.hpp).
#include "odoloc/sw/thamma_cycle.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace odoloc::sw::tof {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok)
    throw std::invalid_argument("ThammaSchedule: " + what);
}

}  // namespace

void ThammaSchedule::validate() const {
  require(stations >= 1 && stations <= 64, "stations must be in [1, 64]");
  require(repeats >= 1 && repeats <= 64, "repeats must be in [1, 64]");
  require(std::isfinite(period_s) && period_s > 0, "period_s must be finite and > 0");
  require(std::isfinite(place_tolerance_s) && place_tolerance_s > 0 &&
              place_tolerance_s < period_s / 4,
          "place_tolerance_s must be in (0, period_s / 4)");
  // A gap shorter than half a period could not be told from a late edge.
  require(std::isfinite(cycle_gap_s) && cycle_gap_s >= period_s / 2,
          "cycle_gap_s must be finite and >= period_s / 2 (the cycles are framed on it)");
}

ThammaCycleDecoder::ThammaCycleDecoder(ThammaConfig measure, ThammaSchedule schedule)
    : measure_((measure.validate(), std::move(measure))),
      schedule_((schedule.validate(), schedule)) {
  if (measure_.repeats != static_cast<std::size_t>(schedule_.repeats))
    throw std::invalid_argument("ThammaCycleDecoder: measure.repeats must equal schedule.repeats");
  if (measure_.max_tof_s + measure_.fixed_delay_s >= schedule_.period_s)
    throw std::invalid_argument(
        "ThammaCycleDecoder: a burst's listening window (fixed_delay_s + max_tof_s) must end "
        "before the next trigger");
}

void ThammaCycleDecoder::keep(const CaptureBatch& batch) {
  if (!timebase_) {
    timebase_ = batch.timebase;
    // The silence since the driver started counts as a gap.
    last_edge_s_ = batch.timebase.edge_time_s(batch.read_tick, 0);
  } else if (batch.timebase.prescale != timebase_->prescale ||
             batch.timebase.input_latency_clocks != timebase_->input_latency_clocks) {
    throw std::invalid_argument("ThammaCycleDecoder: the batches' timebase changed");
  }
  sync_.insert(sync_.end(), batch.sync.begin(), batch.sync.end());
  if (channels_.size() < batch.channels.size())
    channels_.resize(batch.channels.size());
  for (std::size_t c = 0; c < batch.channels.size(); ++c) {
    const ChannelEvents& in = batch.channels[c];
    ChannelEvents& kept = channels_[c];
    kept.mode = in.mode;
    kept.envelope.insert(kept.envelope.end(), in.envelope.begin(), in.envelope.end());
    kept.carrier.insert(kept.carrier.end(), in.carrier.begin(), in.carrier.end());
  }
  incidents_.insert(incidents_.end(), batch.incidents.begin(), batch.incidents.end());
}

std::vector<ThammaCycle> ThammaCycleDecoder::push(const CaptureBatch& batch) {
  keep(batch);
  const Timebase& tb = *timebase_;
  const double period = schedule_.period_s;
  std::vector<ThammaCycle> out;
  // Framing: the first edge after a silence longer than a period and half
  // the gap starts a cycle.
  while (!start_s_ && !sync_.empty()) {
    const double t = tb.edge_time_s(sync_.front(), 0);
    if (t - last_edge_s_ > period + schedule_.cycle_gap_s / 2)
      start_s_ = t;
    else
      sync_.pop_front();
    last_edge_s_ = t;
  }
  if (!start_s_)
    return out;
  // A cycle is measured once its last listening window has been read (an
  // envelope entry exists from its fall on: one longest pulse more).
  const double places = schedule_.stations * schedule_.repeats;
  const double listen_s = measure_.fixed_delay_s + measure_.max_tof_s +
                          measure_.envelope.max_width_s() + measure_.envelope.burst_s;
  const double read_s = tb.edge_time_s(batch.read_tick, 0);
  while (*start_s_ + (places - 1) * period + listen_s <= read_s) {
    ThammaCycle cycle = measure(*start_s_);
    // The next cycle is where the schedule puts it, from this cycle's first
    // edge when it came (the two clocks drift apart slowly).
    double next = *start_s_ + schedule_.cycle_s();
    for (const Tick s : sync_) {
      const double t = tb.edge_time_s(s, 0);
      if (std::abs(t - next) <= schedule_.place_tolerance_s) {
        next = t;
        break;
      }
    }
    out.push_back(std::move(cycle));
    start_s_ = next;
    const double keep_from = next - schedule_.place_tolerance_s;
    const auto tick = static_cast<Tick>(std::max(
        0.0, std::floor((keep_from * tb.fabric_clock_hz + tb.input_latency_clocks) /
                        (tb.prescale + 1.0))));
    drop_before(tick);
  }
  return out;
}

ThammaCycle ThammaCycleDecoder::measure(double start_s) const {
  const Timebase& tb = *timebase_;
  const int repeats = schedule_.repeats;
  ThammaCycle cycle;
  cycle.time_s = start_s;
  for (int station = 0; station < schedule_.stations; ++station) {
    std::vector<Tick> ticks;
    for (int r = 0; r < repeats; ++r) {
      const double place = start_s + (station * repeats + r) * schedule_.period_s;
      for (const Tick s : sync_)
        if (std::abs(tb.edge_time_s(s, 0) - place) <= schedule_.place_tolerance_s) {
          ticks.push_back(s);
          break;
        }
    }
    // The station's time: the middle of its repeats.
    cycle.station_time_s.push_back(start_s +
                                   (station * repeats + (repeats - 1) / 2.0) * schedule_.period_s);
    cycle.per_station.push_back(measure_thamma(measure_, tb, ticks, channels_, incidents_));
  }
  return cycle;
}

void ThammaCycleDecoder::drop_before(Tick tick) {
  while (!sync_.empty() && sync_.front() < tick)
    sync_.pop_front();
  for (ChannelEvents& c : channels_) {
    std::erase_if(c.envelope, [&](const EnvelopeEvent& e) { return e.rise < tick; });
    std::erase_if(c.carrier, [&](const CarrierEvent& e) { return e.rise < tick; });
  }
  std::erase_if(incidents_, [&](const Incident& i) { return std::max(i.from, i.until) < tick; });
}

}  // namespace odoloc::sw::tof
