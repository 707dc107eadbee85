// Ultrasonic time of flight, SoC side: the data that crosses between the
// capture driver (which reads the fabric's FIFOs over sw::RegisterBus), the
// decoders (beacon_cycle.hpp: Kleeman's beacon schedule; tof_sync_modes.hpp:
// RF-synchronised and binaural ranging) and the solvers.
//
// Input: the capture unit's events (docs/tof-capture.md) after the
// driver has unwrapped the 32-bit timestamps into 64-bit tick counts, plus
// what went wrong while reading them (Incident). Output: measurement sets
// with validity flags. Pure data: no bus access, no fabric model.
// docs/tof-measurements.md documents every type and flag.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/regs.hpp"

namespace odoloc::sw::tof {

// ---------------------------------------------------------------- time base

// A timestamp in capture ticks, unwrapped by the driver: the fabric's 32-bit
// counter extended to 64 bits ("each new timestamp is within 2^31 ticks after
// the last one seen"). Tick 0 is wherever the driver's count started.
using Tick = std::uint64_t;

// Envelope-mode widths saturate here (the FIFO entry's 24-bit width field).
inline constexpr std::uint32_t kWidthSaturated = (1U << 24) - 1U;

// How ticks map to seconds on the robot's clock. The decoders, not the
// driver, subtract the input latency: events arrive exactly as the fabric
// stamped them.
struct Timebase {
  // tof.cfg.prescale: one tick every prescale+1 fabric clocks (0: 20 ns,
  // 124: Kleeman's 2.5 us).
  std::uint32_t prescale = 0;
  // Fabric clocks between an edge at the pin and the clock its timestamp is
  // taken in: N + 2, N = max(tof.cfg.filter_clocks, 1) (docs/tof-capture.md,
  // "Latency"; the default assumes the reset N = 3). The same for every
  // channel and the sync input, so it cancels in sync-referenced and
  // differential times; it matters only for absolute edge times
  // (edge_time_s).
  std::uint32_t input_latency_clocks = 5;
  double fabric_clock_hz = regs::kFabricClockHz;

  [[nodiscard]] double tick_s() const { return (prescale + 1.0) / fabric_clock_hz; }
  [[nodiscard]] double latency_s() const { return input_latency_clocks / fabric_clock_hz; }

  // Best estimate, in seconds after tick `origin`'s start, of when an edge
  // stamped `tick` happened at the pin: the middle of the tick's interval of
  // fabric clocks, minus the latency, minus half a clock (the pin changed at
  // some time in the clock period before the sampling edge). `tick` may be
  // before `origin`.
  [[nodiscard]] double edge_time_s(Tick tick, Tick origin) const {
    const auto ticks = static_cast<double>(static_cast<std::int64_t>(tick - origin));
    return ((ticks + 0.5) * (prescale + 1.0) - 0.5 - input_latency_clocks) / fabric_clock_hz;
  }
  // Quantisation noise of one timestamp (uniform over a tick): tick/sqrt(12).
  [[nodiscard]] double quantisation_sd_s() const { return tick_s() / std::sqrt(12.0); }

  // Throws std::invalid_argument naming the bad field.
  void validate() const {
    if (!(std::isfinite(fabric_clock_hz) && fabric_clock_hz > 0))
      throw std::invalid_argument("tof::Timebase: fabric_clock_hz must be finite and positive");
    if (prescale > 0xFFFFU)
      throw std::invalid_argument("tof::Timebase: prescale " + std::to_string(prescale) +
                                  " does not fit tof.cfg.prescale (16 bits)");
    if (input_latency_clocks > 1000)
      throw std::invalid_argument("tof::Timebase: input_latency_clocks " +
                                  std::to_string(input_latency_clocks) +
                                  " is not a synchroniser and filter delay");
  }
  bool operator==(const Timebase&) const = default;
};

// ------------------------------------------------------------------- input

enum class ChannelMode : std::uint8_t { kEnvelope, kCarrier };

// Envelope mode: one comparator pulse (tof_channel.entry ticks and width).
struct EnvelopeEvent {
  Tick rise = 0;            // rising-edge timestamp, unwrapped
  std::uint32_t width = 0;  // ticks the comparator stayed high (fall - rise)
  [[nodiscard]] bool saturated() const { return width >= kWidthSaturated; }
};

// Carrier mode: one rising edge of the carrier (tof_channel.entry ticks and
// edge). `edge` counts the rising edges recorded since arming before this
// one (the fabric saturates it at 127): the first entry after arming has 0,
// a gap in the sequence means edges were dropped or fell outside the window.
struct CarrierEvent {
  Tick rise = 0;
  std::uint32_t edge = 0;
};

// One receiver channel's events in one batch, oldest first. Only the vector
// of the channel's mode is read.
struct ChannelEvents {
  ChannelMode mode = ChannelMode::kEnvelope;
  std::vector<EnvelopeEvent> envelope;
  std::vector<CarrierEvent> carrier;
};

// What went wrong while the driver read the capture unit. An incident covers
// the tick interval [from, until) in which events of `channel` may be missing
// or wrong; the decoders flag every measurement whose listening interval
// overlaps it.
enum class IncidentKind : std::uint8_t {
  // The FIFO was full and the fabric dropped `count` events (status.overflow,
  // events.dropped). The fabric keeps the oldest entries, so the dropped ones
  // came after the last event read from that FIFO: from = that event's rise
  // (or the previous read), until = this read.
  kOverflow,
  // A bus read failed (sw::BusError) and `count` entries (0: unknown) were
  // lost: from = the previous good read, until = this read.
  kLostEvents,
  // The comparator has been high (status.in_progress) for longer than any
  // valid pulse: from = when the driver first saw it high (or the last event
  // before), until = the read at which it was still high. The driver extends
  // it read after read.
  kStuckHigh,
  // The driver could not unwrap these timestamps unambiguously (it read the
  // FIFO too late, or a timestamp went backwards): the decoders drop the
  // channel's events in [from, until).
  kUnwrapAmbiguous,
};

inline constexpr int kSyncChannel = -1;  // Incident::channel of the sync input

struct Incident {
  IncidentKind kind = IncidentKind::kOverflow;
  int channel = 0;  // receiver channel, or kSyncChannel
  Tick from = 0;
  Tick until = 0;           // exclusive
  std::uint32_t count = 0;  // events dropped or lost; 0 when unknown or not a count
};

// One read of the capture unit by the driver.
struct CaptureBatch {
  Timebase timebase;
  // The timestamp counter (tof.timestamp, unwrapped) in the read frame that
  // drained the FIFOs: every event whose FIFO entry existed by then is in
  // this batch or an earlier one, except where an incident says otherwise.
  // An envelope entry exists from its falling edge on, so a pulse still high
  // at the read comes in a later batch.
  Tick read_tick = 0;
  std::vector<ChannelEvents> channels;  // index = receiver channel (tof_channel rx0, rx1, ...)
  std::vector<Tick> sync;               // rising edges of the sync input, oldest first
  std::vector<Incident> incidents;
};

// ---------------------------------------------------------------- geometry

struct Vec2 {
  double x = 0, y = 0;
  bool operator==(const Vec2&) const = default;
};

// The receivers in the robot frame: receiver i is capture channel i.
struct Receiver {
  Vec2 position_m;
  double axis_rad = 0;  // direction the receiver faces (robot frame, counter-clockwise from x)
};

struct ReceiverArray {
  std::vector<Receiver> receivers;

  // Kleeman's array: n receivers on the faces of a regular n-gon of side
  // `side_m`, centred on the robot origin, each facing outward; receiver 0
  // faces `first_axis_rad`, the others follow counter-clockwise. The
  // receivers sit at the face centres, side/(2 tan(pi/n)) from the centre
  // (60.4 mm for 8 faces of 50 mm).
  static ReceiverArray polygon(int n = 8, double side_m = 0.05, double first_axis_rad = 0);

  // Largest distance between two receivers.
  [[nodiscard]] double aperture_m() const;
  // Throws std::invalid_argument: empty, non-finite, or two receivers at one place.
  void validate() const;
};

// ------------------------------------------------------------------ output

// Validity and provenance flags. One set of bits for cycles, beacons and
// arrivals; docs/tof-measurements.md says where each one appears.
enum class Flag : std::uint64_t {
  kMissing = 1ULL << 0,          // no arrival at all where one was due
  kEarlyRejected = 1ULL << 1,    // arrivals earlier than the beacon could produce were dropped
  kEchoSuspect = 1ULL << 2,      // the first arrival may itself be an echo (late, overlong)
  kEchoes = 1ULL << 3,           // more arrivals after the first one (echoes, usually)
  kOccludedSuspect = 1ULL << 4,  // first arrival weak before a much stronger one, or late
  kOverflow = 1ULL << 5,         // a FIFO overflow may have dropped events here
  kLostEvents = 1ULL << 6,       // a failed bus read may have lost events here
  kStuckChannel = 1ULL << 7,     // a comparator stuck high (or saturated width) here
  kUnwrapAmbiguous = 1ULL << 8,  // events dropped: the driver could not unwrap them
  kOutOfOrder = 1ULL << 9,       // events out of time order, or for time already decoded, dropped
  kDeadChannel = 1ULL << 10,     // a receiver that should have heard the pulse was silent all cycle
  kNoise = 1ULL << 11,           // pulses too short to be a beacon were dropped here
  kSingleReceiver = 1ULL << 12,  // heard by one receiver: no direction, range via its axis
  kDoaInconsistent = 1ULL << 13,  // the plane-wave fit's residuals exceed the timing noise
  kResynchronised = 1ULL << 14,   // first cycle after (re)locking to the double pulse
  kCoasted = 1ULL << 15,          // anchor predicted from the previous cycle (double pulse absent)
  kDoublePulseMissing = 1ULL << 16,    // beacon 0's double pulse not where the lock expects it
  kDoublePulseMisplaced = 1ULL << 17,  // a double pulse elsewhere in the cycle: lock dropped
  kLockLost = 1ULL << 18,              // the decoder dropped the lock and searches again
  kReferenceSuspect = 1ULL << 19,  // beacon 0's arrival (the anchor) looks late: offsets shifted
  kSaturated = 1ULL << 20,         // a width read 2^24-1
  kMergedPulse = 1ULL << 21,       // a width longer than one burst at the model's largest amplitude
  kBeforeBound =
      1ULL << 22,  // kept although earlier than the geometric bound (see kReferenceSuspect)
  kSyncMissing = 1ULL << 23,       // fewer sync edges than repeats expected
  kExtraSync = 1ULL << 24,         // more sync edges than repeats expected
  kOutlier = 1ULL << 25,           // a repeat far from the others' median was excluded
  kAmbiguous = 1ULL << 26,         // the coarse time does not decide the carrier cycle
  kCarrierIrregular = 1ULL << 27,  // carrier edges not spaced by whole periods
  kEdgesMissing = 1ULL << 28,      // carrier edge indices skip (dropped or windowed edges)
  kWeak = 1ULL << 29,              // amplitude barely over threshold: compensation least certain
  kOutOfRange = 1ULL << 30,        // arrival outside the physically possible interval
  kInvalid = 1ULL << 31,           // no usable value (see the other flags)
  // Binaural: the whole carrier periods rest on the two carriers' first
  // edges alone (no envelope channels), which unequal amplitudes at the two
  // receivers can shift by whole periods.
  kCycleUnverified = 1ULL << 32,
};

class Flags {
 public:
  constexpr Flags() = default;
  constexpr Flags(Flag f) : bits_(static_cast<std::uint64_t>(f)) {}  // NOLINT: implicit on purpose
  constexpr explicit Flags(std::uint64_t bits) : bits_(bits) {}
  [[nodiscard]] constexpr bool has(Flag f) const {
    return (bits_ & static_cast<std::uint64_t>(f)) != 0;
  }
  [[nodiscard]] constexpr bool any() const { return bits_ != 0; }
  [[nodiscard]] constexpr std::uint64_t bits() const { return bits_; }
  constexpr Flags& set(Flag f) {
    bits_ |= static_cast<std::uint64_t>(f);
    return *this;
  }
  constexpr Flags& clear(Flag f) {
    bits_ &= ~static_cast<std::uint64_t>(f);
    return *this;
  }
  constexpr Flags& operator|=(Flags o) {
    bits_ |= o.bits_;
    return *this;
  }
  friend constexpr Flags operator|(Flags a, Flags b) { return a |= b; }
  constexpr bool operator==(const Flags&) const = default;

 private:
  std::uint64_t bits_ = 0;
};

// The flag a measurement gets when its interval overlaps an incident of
// this kind (overflow, lost events, stuck channel, unwrap ambiguous).
Flag incident_flag(IncidentKind kind);

// "kMissing", ... (without the k in to_string: "missing|echoes").
std::string_view flag_name(Flag f);
std::string to_string(Flags flags);

// A direction of arrival from the plane-wave fit over the receivers that
// heard one wavefront. bearing_rad points from the robot toward the source,
// robot frame, in (-pi, pi].
struct Doa {
  bool valid = false;
  double bearing_rad = 0;
  double sd_rad = std::numeric_limits<double>::infinity();
  double rms_residual_s = 0;  // of the arrival times about the fitted plane wave
  int receivers = 0;          // used in the fit
};

// One receiver's pulse within an arrival.
struct ReceiverHit {
  int channel = 0;
  Tick rise = 0;                // as stamped (unwrapped)
  std::uint32_t width = 0;      // ticks (carrier mode: 0)
  double crossing_delay_s = 0;  // rise-time compensation subtracted from the rise
  double amplitude_ratio = 0;   // A/V, envelope amplitude over comparator threshold, from the width
  double residual_s = 0;        // arrival time minus the plane wave's prediction
  bool used = true;             // in the direction fit (false: rejected as an outlier)
};

// One wavefront (the direct pulse or an echo), heard by one or more receivers.
struct Arrival {
  // At the robot origin (the plane wave's time there), seconds after the
  // slot start (beacon_cycle.hpp: anchor + k t_fire); distance_m = c time_s.
  double time_s = 0;
  double distance_m = 0;
  double sd_m = 0;              // standard deviation from timing noise only (not the common offset)
  double width_s = 0;           // the widest receiver's pulse width
  double amplitude_ratio = 0;   // the strongest receiver's A/V
  std::uint32_t receivers = 0;  // bit i: channel i heard it
  std::vector<ReceiverHit> hits;  // ordered by channel
  Doa doa;
  Flags flags;
};

// ----------------------------------------------- Kleeman beacon cycle output

// One beacon's slot in one cycle (beacon_cycle.hpp). Distances carry the
// cycle's common offset (CycleMeasurement::anchor_s, docs/tof-measurements.md):
//     candidates[i].distance_m = true path length + offset_m(cycle).
struct BeaconMeasurement {
  int beacon = 0;
  // Every accepted wavefront in the slot, ordered by arrival: the direct
  // pulse and its echoes (beacon 0: the double pulse's second pulse and its
  // echoes are left out).
  std::vector<Arrival> candidates;
  // Wavefronts dropped from the slot, with the reason in their flags
  // (kEarlyRejected: earlier than the beacon could have produced them).
  std::vector<Arrival> rejected;
  // The decoder's pick for the direct path: the first candidate heard by at
  // least KleemanConfig::min_receivers receivers, else the first; -1: none.
  int primary = -1;
  // Slot-level flags, plus the cycle's flags (resynchronised, coasted, ...).
  Flags flags;

  [[nodiscard]] const Arrival* direct() const {
    return primary >= 0 ? &candidates[static_cast<std::size_t>(primary)] : nullptr;
  }
};

// One receiver channel over one cycle.
struct ChannelStatus {
  int pulses = 0;  // pulses used (in arrivals)
  int noise = 0;   // pulses dropped as too short
  bool silent =
      false;           // no pulse at all although a strong arrival came from the direction it faces
  bool stuck = false;  // stuck high (driver incident, saturated or overlong width)
  Flags flags;         // incidents on this channel during the cycle
};

// One beacon cycle: N slots of t_fire, slot 0 starting at the anchor.
struct CycleMeasurement {
  std::uint64_t sequence = 0;  // record number since the decoder started or was reset
  std::uint64_t lock_epoch =
      0;        // incremented at every (re)lock; the offset is continuous within one
  Flags flags;  // cycle level
  // The cycle's reference on the robot clock, seconds after tick 0 of the
  // driver's count (Timebase::edge_time_s(tick, 0)): the compensated arrival
  // of beacon 0's first pulse at the robot origin; when kCoasted the previous
  // anchor plus the cycle ((N + reserved slots) t_fire). Slot k starts at
  // anchor_s + k fire_period_s.
  double anchor_s = 0;
  double fire_period_s = 0;       // t_fire used
  double speed_of_sound_mps = 0;  // c used (distance_m = c time_s)
  // anchor_s minus the previous record's, when both anchors were measured
  // in consecutive cycles; NaN otherwise. The cycle x (beacon clock / robot
  // clock) + (change of the range to beacon 0)/c.
  double cycle_period_s = std::numeric_limits<double>::quiet_NaN();
  std::vector<BeaconMeasurement> beacons;  // index = beacon; empty when kLockLost
  // Every wavefront in the reserved slots (BeaconSchedule::reserved_slots),
  // ordered by arrival; time_s counts from the first reserved slot's start,
  // anchor_s + N fire_period_s (no beacon: distance_m is c time_s, offset
  // by nothing in particular).
  std::vector<Arrival> reserved;
  std::vector<ChannelStatus> channels;  // index = receiver channel
  int noise_pulses = 0;                 // too short, dropped (all channels)
  int dropped_events = 0;               // out of order / too late / unwrap-ambiguous

  [[nodiscard]] bool locked() const { return !beacons.empty(); }
};

}  // namespace odoloc::sw::tof
