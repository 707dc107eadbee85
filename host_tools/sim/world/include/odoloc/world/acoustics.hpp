// The acoustic world: a double-precision, seeded model of airborne
// ultrasound in a room that turns the robot's pose over time into the
// comparator waveforms of every ultrasonic receiver channel, and a sync pin.
// It is ground truth beside the tricycle: it emits physical signals only
// (comparator levels per fabric clock) and knows nothing of the chip.
// Model, formulas, sources and defaults: docs/acoustic-world.md. The three
// papers' set-ups (Kleeman's beacons and octagon, Thamma's RF-triggered base
// stations, the binaural pair) are in acoustic_systems.hpp.
//
// Conventions: planar geometry in the world frame (metres; angles in radians,
// counter-clockwise from +x), receivers in the robot's body frame (the
// tricycle's Pose: x forward), time in seconds from the start of the run.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "odoloc/world/tricycle.hpp"

namespace odoloc::world {

inline constexpr double kSpeedOfLightMps = 299'792'458.0;

// A point or vector in the plane, metres.
struct Vec2 {
  double x_m = 0;
  double y_m = 0;
};

// A body-frame point of a body at `pose`, in the world frame.
Vec2 to_world(const Pose& pose, Vec2 body);

// The robot's pose (its body frame) at any time in seconds.
using Trajectory = std::function<Pose(double time_s)>;
// A robot that never moves.
Trajectory stationary(Pose pose);
// Linear interpolation of x, y and the (unwrapped) heading between the
// tricycle's recorded samples, sorted by time; the first and last sample hold
// before and after them. With samples every 1 ms at 1 m/s the chord error is
// below v^2 dt^2 / (8 R) = 0.13 um on a 1 m radius turn (0.4 ns of flight).
// Throws std::invalid_argument for no samples or unsorted times.
Trajectory interpolate(std::vector<TrajectorySample> samples);

// Still air. Defaults: 20 degC, 50 % relative humidity, sea-level pressure.
struct Air {
  double temperature_c = 20;
  double relative_humidity = 0.5;  // 0..1
  double pressure_kpa = 101.325;

  // c = 331.3 sqrt(1 + T/273.15) m/s (dry air; humidity's few tenths of a
  // percent are not modelled). 343.2 m/s at 20 degC.
  [[nodiscard]] double speed_of_sound_mps() const;
  // Pure-tone atmospheric absorption, ISO 9613-1 (dB per metre of path):
  // 1.32 dB/m at 40 kHz and 1.04 dB/m at 32.5 kHz at the defaults.
  [[nodiscard]] double absorption_db_per_m(double frequency_hz) const;
};

// The four walls of a rectangular room [0, width] x [0, depth].
enum class Wall : std::uint8_t { kXMin, kXMax, kYMin, kYMax };
inline constexpr std::size_t kWallCount = 4;
constexpr std::size_t index(Wall w) {
  return static_cast<std::size_t>(w);
}

// Walls reflect first-order echoes (image sources, Allen & Berkley 1979);
// floor and ceiling do not. A wall with reflection 0 gives no echo.
struct Room {
  double width_m = 10;  // x from 0 to width_m
  double depth_m = 10;  // y from 0 to depth_m
  // Pressure reflection coefficient of each wall, indexed by index(Wall).
  std::array<double, kWallCount> reflection{0.9, 0.9, 0.9, 0.9};
};

// An occluding obstacle: the segment a-b thickened by radius_m (a capsule:
// a == b gives a disc, radius 0 a thin screen). It blocks every ray that comes
// within radius_m of the segment; it neither reflects nor diffracts.
struct Obstacle {
  Vec2 a;
  Vec2 b;
  double radius_m = 0;
};

// An ultrasonic transmitter: one or more transducers at one point, driven in
// phase (their baffled-piston patterns add). Its position and axes are in the
// world frame, or in the body frame of `mount` when it is set (a transmitter
// on another robot, evaluated at the emission time of each wavefront).
struct Beacon {
  Vec2 position;
  std::vector<double> axes_rad{0.0};
  double carrier_hz = 40e3;
  // Envelope peak at a receiver 1 m away on both axes, at the receiver's
  // resonance (volts at its comparator input; Kleeman: 12.5 V at 1 m).
  double amplitude_1m_v = 12.5;
  double piston_radius_m = 5e-3;  // directivity 2 J1(ka sin t)/(ka sin t)
  // First-order envelope time constant: 10-90 % rise tau ln 9 = 1.1 ms at
  // 0.5 ms (Kleeman: "about 1 msec").
  double envelope_tau_s = 0.5e-3;
  // Trigger to sound: the fixed electronics delay (Thamma's t).
  double electronics_delay_s = 0;
  Trajectory mount;  // empty: fixed in the world
};

// An ultrasonic receiver channel on the robot, with its comparator.
struct Receiver {
  Vec2 position;  // robot body frame
  double axis_rad = 0;
  double resonance_hz = 40e3;
  // Q of the receiver's resonance: a carrier f is received with
  // 1 / sqrt(1 + Q^2 (f/f0 - f0/f)^2) of its amplitude (-12.7 dB for
  // 32.5 kHz at a 40 kHz receiver with Q = 10).
  double quality = 10;
  double piston_radius_m = 5e-3;
  double threshold_v = 0.2;  // envelope comparator threshold (Kleeman: 200 mV)
};

// Random disturbances; all zero (the ideal world) by default. Drawn from
// std::mt19937_64 with portable transforms: a seed gives the same run on every
// standard library.
struct AcousticNoise {
  // Turbulence: a Gaussian delay per emission and path, common to every
  // receiver of the array (its paths share the air), plus one per receiver.
  double path_jitter_sd_s = 0;
  double receiver_jitter_sd_s = 0;
  // Relative Gaussian amplitude fluctuation per arrival (clamped at 0).
  double amplitude_sd = 0;
  // Spurious pulses per channel: Poisson rate, widths uniform in
  // [min, max], ringing at the receiver's resonance with a uniform phase.
  double noise_rate_hz = 0;
  double noise_min_width_s = 0.1e-3;
  double noise_max_width_s = 2e-3;
};

struct AcousticWorld {
  Air air;
  std::optional<Room> room;  // empty: free field, no echoes
  std::vector<Obstacle> obstacles;
  std::vector<Beacon> beacons;
  std::vector<Receiver> receivers;  // channel i is receivers[i], on the robot
  // Height of the transmitters above the receivers' plane (constant): every
  // path length is sqrt(planar^2 + h^2); axes stay horizontal.
  double height_m = 0;
  AcousticNoise noise;
};

// A burst: beacon `beacon` is triggered at trigger_s; its sound leaves the
// transducer electronics_delay_s later and is driven for duration_s.
struct Emission {
  std::size_t beacon = 0;
  double trigger_s = 0;
  double duration_s = 0;
};
// An RF pulse sent from beacon `beacon`'s position at start_s; it reaches the
// robot's reference point at the speed of light and drives the sync pin.
struct SyncPulse {
  std::size_t beacon = 0;
  double start_s = 0;
  double duration_s = 0;
};
struct Schedule {
  std::vector<Emission> emissions;
  std::vector<SyncPulse> sync;
};

// A comparator output pulse: high on [rise_s, fall_s).
struct Pulse {
  double rise_s = 0;
  double fall_s = 0;

  friend bool operator==(const Pulse&, const Pulse&) = default;
};

// The two comparator outputs of a channel: high while the envelope exceeds
// the threshold, or the comparator on the carrier itself (high on the
// carrier's positive half-cycles that begin while the envelope exceeds the
// threshold).
enum class ComparatorKind : std::uint8_t { kEnvelope, kCarrier };

// One path of one emission to one receiver (ground truth). Times are those
// of the wavefront that left the transducer at the emission time (the
// burst's start); the robot moves during the flight.
struct Arrival {
  std::optional<Wall> wall;  // the reflecting wall of an echo; empty: direct path
  Vec2 source;               // the transmitter, or its image in the wall, at the emission time
  double path_m = 0;         // source to receiver at the arrival (3-D)
  double true_time_s = 0;    // arrival without turbulence
  double time_s = 0;         // with turbulence jitter: the carrier's phase reference
  double amplitude_v = 0;    // envelope peak A (the fluctuation included)
  bool inverted = false;     // carrier polarity reversed (a directivity side lobe)
  bool occluded = false;     // an obstacle blocks the path: no pulse
  // Where the envelope exceeds the receiver's threshold: the rise comes
  // tau ln(A / (A - V_th)) after the arrival. Empty when occluded or when the
  // envelope never exceeds the threshold.
  std::optional<Pulse> above_threshold;
};

struct Reception {
  Arrival direct;  // computed even when occluded, for comparison
  std::vector<Arrival> echoes;
  // Noise pulses on this channel rising in this emission's slot: from its
  // emission time to the next emission's (to the end of the run for the last).
  std::size_t noise_pulses = 0;
};

struct EmissionRecord {
  Emission emission;
  double emission_s = 0;             // trigger_s + the beacon's electronics delay
  std::vector<Reception> receivers;  // by channel
};

struct NoisePulse {
  Pulse pulse;
  double phase_rad = 0;  // carrier phase at the rise
};

struct ChannelWaveforms {
  std::vector<Pulse> envelope;  // sorted, disjoint
  std::vector<Pulse> carrier;

  [[nodiscard]] const std::vector<Pulse>& operator()(ComparatorKind kind) const {
    return kind == ComparatorKind::kEnvelope ? envelope : carrier;
  }
};

struct AcousticRun {
  std::vector<EmissionRecord> emissions;       // sorted by emission time
  std::vector<std::vector<NoisePulse>> noise;  // per channel, sorted
  std::vector<ChannelWaveforms> channels;      // per channel
  std::vector<Pulse> sync;                     // the sync pin, sorted, disjoint
};

// Simulates the span [0, end_s): every emission triggered before end_s, with
// all its arrivals (also those after end_s), and noise pulses over the span.
// Comparator rule for overlapping arrivals on one channel: the envelope
// output is the union of the arrivals' above-threshold intervals; the carrier
// output belongs at each instant to the arrival that crossed the threshold
// first among those still above it, and is the union of the half-cycles each
// arrival begins while it owns the comparator. Throws std::invalid_argument
// for an inconsistent world or schedule, std::runtime_error if an arrival
// cannot be solved (a receiver moving at the speed of sound).
AcousticRun simulate(const AcousticWorld& world, const Schedule& schedule, const Trajectory& robot,
                     double end_s, std::uint64_t seed);

// One comparator output pin sampled on the fabric clock: clock n covers
// [n/f, (n+1)/f) and shows the level at n/f, so a pulse [rise, fall) is high
// on clocks ceil(rise f) .. ceil(fall f) - 1 (pulses merge or vanish
// accordingly). Per clock it costs a compare against the next transition.
class PinSource {
 public:
  static constexpr std::uint64_t kNever = std::numeric_limits<std::uint64_t>::max();

  PinSource() = default;
  PinSource(const std::vector<Pulse>& waveform, double clock_hz);

  // The level of clock clock(); then moves to the next clock.
  bool tick() {
    if (next_ < transitions_.size() && transitions_[next_] == clock_)
      ++next_;
    ++clock_;
    return (next_ & 1U) != 0;
  }
  // The clock the next tick() samples.
  [[nodiscard]] std::uint64_t clock() const { return clock_; }
  // The level of clock clock() - 1 (low before clock 0).
  [[nodiscard]] bool level() const { return (next_ & 1U) != 0; }
  // The first clock >= clock() whose level differs from the clock before it,
  // or kNever: every clock in between has level().
  [[nodiscard]] std::uint64_t next_transition_clock() const {
    return next_ < transitions_.size() ? transitions_[next_] : kNever;
  }
  // Fast-forward (or rewind): the next tick() samples `clock`.
  void skip_to(std::uint64_t clock);
  // Rising and falling clocks, alternating, strictly increasing.
  [[nodiscard]] const std::vector<std::uint64_t>& transitions() const { return transitions_; }

 private:
  std::vector<std::uint64_t> transitions_;
  std::size_t next_ = 0;  // transitions before clock_ that have been passed
  std::uint64_t clock_ = 0;
};

// Every channel's pin (bit i of `channels`) and the sync pin of one clock.
struct PinLevels {
  std::uint32_t channels = 0;
  bool sync = false;

  friend bool operator==(const PinLevels&, const PinLevels&) = default;
};

// All pins of a run on the fabric clock (at most 32 channels). tick() costs a
// compare per clock between transitions.
class AcousticPins {
 public:
  AcousticPins(const AcousticRun& run, ComparatorKind kind, double clock_hz = 50e6);
  // One kind per channel.
  AcousticPins(const AcousticRun& run, const std::vector<ComparatorKind>& kinds,
               double clock_hz = 50e6);

  // The levels of clock clock(); then moves to the next clock.
  PinLevels tick();
  [[nodiscard]] std::uint64_t clock() const { return clock_; }
  // The first clock >= clock() at which any pin changes, or PinSource::kNever:
  // every clock in between repeats the last levels (a fast-forward may jump).
  [[nodiscard]] std::uint64_t next_transition_clock() const { return next_change_; }
  void skip_to(std::uint64_t clock);
  [[nodiscard]] const PinSource& channel(std::size_t i) const { return channels_.at(i); }
  [[nodiscard]] const PinSource& sync() const { return sync_; }

 private:
  std::vector<PinSource> channels_;
  PinSource sync_;
  std::uint64_t clock_ = 0;
  std::uint64_t next_change_ = 0;  // the first clock >= clock_ at which a pin changes
  PinLevels levels_;               // the levels of clock clock_ - 1
};

}  // namespace odoloc::world
