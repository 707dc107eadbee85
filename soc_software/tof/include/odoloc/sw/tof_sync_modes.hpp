// Sync-referenced time of flight (docs/tof-measurements.md#rf-synchronised-ranging-thamma
// and #binaural-pair-carrier-phase): the emission time is known on the robot
// clock from the sync input's rising edge (an RF trigger, or the robot's own
// command to the transmitter), so the time of flight is absolute.
//
// Thamma et al.: TOF = (ultrasound rise - sync rise) - t, t the fixed delay
// of the electronics, averaged over four repeats (their eq. 2 and 4); here
// per receiver box (one carrier frequency each), with the spread of the
// repeats and an outlier rule.
//
// Binaural pair: per receiver pair the coarse TOF of each receiver (first
// carrier edge after the reference) and the carrier phase difference from
// the first K rising edges of both: the circular mean of
// 2 pi f (t_left,k - t_right,k) modulo 2 pi, with its circular spread. The
// coarse difference picks the whole number of carrier periods.
#pragma once

#include <limits>
#include <span>
#include <vector>

#include "odoloc/sw/tof_envelope.hpp"
#include "odoloc/sw/tof_measurement.hpp"

namespace odoloc::sw::tof {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ------------------------------------------------------------------ Thamma

struct ThammaConfig {
  // Receiver boxes: the channels of one box, all tuned to one carrier
  // (Thamma: head box 4 x 40 kHz, tail box 4 x 32.5 kHz, on the four sides).
  struct Box {
    std::vector<int> channels;
    double carrier_hz = 40e3;
  };
  std::vector<Box> boxes{{{0, 1, 2, 3}, 40e3}, {{4, 5, 6, 7}, 32.5e3}};
  // t: from the sync edge at the pin to the ultrasound leaving the
  // transmitter, plus the receiver chain's delay (Thamma's "time elapse
  // across the electronic circuit"); calibrated at a known distance.
  double fixed_delay_s = 0;
  // Arrivals are looked for in [sync + t + min_tof, sync + t + max_tof),
  // and before the next sync edge.
  double min_tof_s = 0;
  double max_tof_s = 0.04;
  std::size_t repeats = 4;
  // With three or more repeats, one further than this from their median is
  // left out of the mean (kOutlier).
  double outlier_tolerance_s = 100e-6;
  // Envelope-mode channels: subtract the crossing delay from the width
  // (tof_envelope.hpp). Carrier-mode channels (first edge) are not
  // compensated: their threshold delay belongs in fixed_delay_s.
  bool compensate_rise = true;
  EnvelopeModel envelope;
  double min_width_s = 0.25e-3;  // envelope pulses narrower are noise
  double speed_of_sound_mps = 343.2;
  double timing_sd_s = 1e-6;  // per arrival, besides quantisation

  void validate() const;  // std::invalid_argument naming the field
};

struct ThammaRepeat {
  double tof_s = kNaN;  // earliest compensated arrival in the box minus sync minus t
  int channel = -1;     // the receiver that heard it first
  Flags flags;          // kMissing, kNoise, kOverflow, kLostEvents, kStuckChannel, ...
};

struct ThammaBoxResult {
  int box = 0;
  double carrier_hz = 0;
  std::vector<ThammaRepeat> repeats;  // one per sync edge
  int used = 0;                       // repeats in the mean
  double tof_s = kNaN;                // mean of the used repeats
  double spread_s = kNaN;             // their sample standard deviation (0 for one)
  double sd_s = kNaN;                 // of the mean: max(spread, timing model)/sqrt(used)
  double distance_m = kNaN;           // c tof_s
  double distance_sd_m = kNaN;
  Flags flags;  // kMissing when no repeat was heard; union of the repeats' incident flags
};

struct ThammaMeasurement {
  std::vector<ThammaBoxResult> boxes;  // index = ThammaConfig::boxes
  Flags flags;                         // kSyncMissing, kExtraSync, kInvalid (no sync edge)
};

// One ranging burst: `sync` holds its sync edges (the caller groups them per
// base station), `channels` the receiver events around them (index =
// channel), `incidents` the driver's incidents.
ThammaMeasurement measure_thamma(const ThammaConfig& config, const Timebase& timebase,
                                 std::span<const Tick> sync,
                                 std::span<const ChannelEvents> channels,
                                 std::span<const Incident> incidents = {});

// --------------------------------------------------------------- binaural

struct BinauralPair {
  int left = 0, right = 1;
  double baseline_m = 0.35;  // the paper's receivers are 350 mm apart
  double carrier_hz = 40e3;
  // The same two receivers' envelope comparators on two more channels
  // (envelope mode), or -1. With them the whole carrier periods come from
  // the rise-time-compensated envelope arrivals (a few microseconds, well
  // inside half a period); without them from the carriers' first edges,
  // which an amplitude difference between the receivers shifts by whole
  // periods: such results carry kCycleUnverified.
  int left_envelope = -1, right_envelope = -1;
};

struct BinauralConfig {
  std::vector<BinauralPair> pairs{BinauralPair{}};
  // From the reference edge to the chirp leaving the transmitter, plus the
  // receivers' delay to their first recorded edge (calibrated).
  double fixed_delay_s = 0;
  std::size_t edges = 8;  // K: tof_channel.cfg.edges
  double max_tof_s = 0.04;
  // Edges must lie on a grid of whole carrier periods from the first one,
  // within this fraction of a period; the others are left out (kCarrierIrregular).
  double period_tolerance = 0.2;
  // |coarse - resolved| beyond this many periods: kAmbiguous (0.5 is a coin toss).
  double ambiguity_limit = 0.3;
  double speed_of_sound_mps = 343.2;
  EnvelopeModel envelope;  // of the envelope channels (burst_s: the chirp's length)

  void validate() const;
};

struct BinauralPairResult {
  int left = 0, right = 1;
  // Coarse: first edge after the reference (moved back by its edge index
  // when earlier edges were dropped), minus the fixed delay.
  double tof_left_s = kNaN, tof_right_s = kNaN;
  double coarse_difference_s = kNaN;  // tof_left - tof_right
  // Fine: circular mean of 2 pi f (t_left,k - t_right,k) over the edges k
  // both receivers recorded, in (-pi, pi], and its circular standard
  // deviation sqrt(-2 ln R).
  double phase_rad = kNaN;
  double phase_sd_rad = kNaN;
  int edges_used = 0;
  int cycles = 0;                   // whole periods: difference = phase/(2 pi f) + cycles/f
  double difference_s = kNaN;       // left arrival minus right arrival
  double difference_sd_s = kNaN;    // phase_sd / (2 pi f sqrt(edges_used))
  double path_difference_m = kNaN;  // c difference_s: |left - source| - |right - source|
  double ambiguity = kNaN;          // |coarse - difference| in periods
  Flags flags;
};

struct BinauralMeasurement {
  std::vector<BinauralPairResult> pairs;  // index = BinauralConfig::pairs
  Flags flags;
};

// One chirp: `reference` is the sync (or arming) edge the chirp is timed
// from; the channels must be in carrier mode.
BinauralMeasurement measure_binaural(const BinauralConfig& config, const Timebase& timebase,
                                     Tick reference, std::span<const ChannelEvents> channels,
                                     std::span<const Incident> incidents = {});

}  // namespace odoloc::sw::tof
