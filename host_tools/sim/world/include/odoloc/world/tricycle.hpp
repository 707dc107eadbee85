// Ground-truth tricycle: a double-precision kinematic simulator of the robot
// (two fixed rear idler wheels on one axle, one front driving-and-steering
// wheel) that drives a path and produces the four encoders' A/B waveforms
// clock by clock on the 50 MHz fabric clock. It is the truth the odometry
// fabric is tested against; model, derivation and error budget in
// docs/tricycle-simulator.md.
//
// Conventions: the reference point P is the rear-axle midpoint; theta is the
// heading of the body x axis (forward), counter-clockwise positive and not
// wrapped; a positive steering angle phi turns left; distances are metres.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include "odoloc/world/quadrature_source.hpp"

namespace odoloc::world {

// The robot's four incremental encoders. Arrays of per-encoder values
// (tick(), true_edges(), TrajectorySample::edges) are indexed by
// index(Encoder).
enum class Encoder : std::uint8_t { kLeftRear, kRightRear, kFrontDrive, kSteering };
inline constexpr std::size_t kEncoderCount = 4;
inline constexpr std::array<Encoder, kEncoderCount> kEncoders = {
    Encoder::kLeftRear, Encoder::kRightRear, Encoder::kFrontDrive, Encoder::kSteering};

// The three rolling wheels, the only places a bump or slip can act: the
// steering encoder is not a wheel. Each wheel's encoder is encoder(Wheel).
enum class Wheel : std::uint8_t { kLeftRear, kRightRear, kFront };
inline constexpr std::size_t kWheelCount = 3;

constexpr std::size_t index(Encoder e) {
  return static_cast<std::size_t>(e);
}
constexpr std::size_t index(Wheel w) {
  return static_cast<std::size_t>(w);
}
constexpr Encoder encoder(Wheel w) {
  constexpr std::array<Encoder, kWheelCount> kEncoderOfWheel = {
      Encoder::kLeftRear, Encoder::kRightRear, Encoder::kFrontDrive};
  return kEncoderOfWheel[index(w)];
}

// A rolling wheel and its incremental encoder. The odometry only knows the
// nominal radius; the ground truth rolls on the true one (radius error).
struct WheelEncoder {
  double nominal_radius_m = 0.05;
  double true_radius_m = 0.05;
  std::uint32_t lines = 1000;  // N: encoder lines per encoder revolution
  double gear = 1;             // G: encoder turns per wheel turn

  [[nodiscard]] double edges_per_rev() const { return 4.0 * lines * gear; }  // x4 decoding
  [[nodiscard]] double true_edges_per_metre() const {
    return edges_per_rev() / (2 * std::numbers::pi * true_radius_m);
  }
  [[nodiscard]] double nominal_edges_per_metre() const {
    return edges_per_rev() / (2 * std::numbers::pi * nominal_radius_m);
  }
};

struct SteeringEncoder {
  std::uint32_t lines = 500;                       // N_s
  double gear = 100;                               // encoder turns per steering turn
  double limit_rad = 40 * std::numbers::pi / 180;  // |phi| limit (paper: 40 degrees)

  [[nodiscard]] double edges_per_rad() const { return 4.0 * lines * gear / (2 * std::numbers::pi); }
};

struct Geometry {
  double track_m = 0.40;      // D: distance between the rear wheels
  double wheelbase_m = 0.50;  // L: rear axle to the front wheel's steering axis
  WheelEncoder left_rear;
  WheelEncoder right_rear;
  WheelEncoder front{.nominal_radius_m = 0.075, .true_radius_m = 0.075, .lines = 500, .gear = 30};
  SteeringEncoder steering;

  // The rolling wheel's encoder; throws std::invalid_argument for a value
  // that names no wheel.
  [[nodiscard]] const WheelEncoder& wheel(Wheel w) const;
};

struct Pose {
  double x_m = 0;
  double y_m = 0;
  double theta_rad = 0;
};

// One piece of a path: the rear-midpoint speed is held for the whole segment
// (speed changes are steps); the steering moves toward its target at
// Path::steer_rate_radps and carries over into the next segment.
struct Segment {
  enum class End : std::uint8_t {
    kDistance,  // after `amount` metres of rear-midpoint travel (unsigned)
    kDuration,  // after `amount` seconds
    kSteered,   // when the steering reaches its target (`amount` unused)
  };
  double speed_mps = 0;  // signed: negative drives in reverse
  double steer_rad = 0;  // target steering angle
  End end = End::kDuration;
  double amount = 0;

  static constexpr Segment distance(double speed_mps, double steer_rad, double metres) {
    return {speed_mps, steer_rad, End::kDistance, metres};
  }
  static constexpr Segment duration(double speed_mps, double steer_rad, double seconds) {
    return {speed_mps, steer_rad, End::kDuration, seconds};
  }
  // Stands still until the steering reaches steer_rad.
  static constexpr Segment steer_to(double steer_rad) { return {0, steer_rad, End::kSteered, 0}; }
};

struct Path {
  std::vector<Segment> segments;
  double steer_rate_radps = 1.0;  // steering rate limit
};

// Drives distance_m straight ahead (speed_mps < 0: backwards).
Path straight_path(double distance_m, double speed_mps);
// The rear midpoint traces a square of side side_m with corners rounded to
// the turn radius L/tan(steer_rad), turning left for steer_rad > 0. The robot
// stops to steer in and out of each corner, so every corner turns exactly
// 90 degrees and the path ends at its start pose, whatever that pose is.
Path square_path(const Geometry& geometry, double side_m, double speed_mps, double steer_rad);

// A hump of raised-cosine profile z(u) = h/2 (1 - cos(2 pi u / l)), u in
// [0, l] along the wheel's own track, met when the rear-midpoint odometer
// reaches start_m. The wheel rolls the profile's arc length, more than the
// horizontal distance: the encoder over-counts by bump_extra_length(h, l).
struct Bump {
  Wheel wheel = Wheel::kLeftRear;
  double start_m = 0;
  double height_m = 0.02;
  double length_m = 0.3;
};
// The wheel turns (1 + ratio) times as far as it travels over the ground
// while the rear-midpoint odometer is in [start_m, end_m).
struct Slip {
  Wheel wheel = Wheel::kFront;
  double start_m = 0;
  double end_m = 0;
  double ratio = 0;
};
struct Disturbances {
  std::vector<Bump> bumps;
  std::vector<Slip> slips;
};

// Arc length minus horizontal length of the whole raised-cosine profile.
double bump_extra_length(double height_m, double length_m);

// The paper's Fig. 4 cases: (a) both rear wheels over a hump, (b) one rear
// wheel over a hump, (c) the front wheel over a hump.
Disturbances bump_under_both_rear(double start_m, double height_m, double length_m);
Disturbances bump_under_one_rear(Wheel rear, double start_m, double height_m, double length_m);
Disturbances bump_under_front(double start_m, double height_m, double length_m);

struct Options {
  Pose start;                            // the steering starts straight (phi = 0)
  double clock_hz = 50e6;                // fabric clock
  std::uint32_t clocks_per_step = 500;   // integration step dt: 10 us at 50 MHz
  std::uint32_t record_every_steps = 0;  // trajectory decimation; 0 records nothing
};

struct TruePose {
  Pose pose;
  double steer_rad = 0;
  double distance_m = 0;  // rear-midpoint odometer: path length, unsigned
  double time_s = 0;
};

struct TrajectorySample {
  TruePose truth;
  std::array<double, kEncoderCount> edges{};  // exact (unquantised) encoder positions, x4 edges
};

class TricycleSimulator {
 public:
  // Throws std::invalid_argument for an inconsistent geometry, path or
  // disturbance (steering beyond the limit, a bump the wheel cannot follow...).
  explicit TricycleSimulator(Geometry geometry, Path path, Disturbances disturbances = {},
                             Options options = {});

  // The path is finished and the current integration step is complete.
  [[nodiscard]] bool done() const {
    return state_.segment == path_.segments.size() && clock_in_step_ == 0;
  }

  // Advances one fabric clock; returns each encoder's A/B levels, indexed by
  // index(Encoder). The physics runs once per step, at its first clock;
  // the other clocks only advance four phase accumulators. Throws
  // std::range_error if an encoder would need more than one edge per clock.
  std::array<QuadratureLevels, kEncoderCount> tick() {
    if (clock_in_step_ == 0)
      begin_step();
    if (++clock_in_step_ == options_.clocks_per_step)
      clock_in_step_ = 0;
    ++clock_;
    return {sources_[0].tick(), sources_[1].tick(), sources_[2].tick(), sources_[3].tick()};
  }

  // For fast-forward: how many of the next ticks return the levels of the
  // last one (0: the next one may change them or runs the physics), and
  // skipping n <= hold_ticks() of them at once.
  [[nodiscard]] std::uint64_t hold_ticks() const {
    std::uint64_t hold = ticks_to_step_end();
    for (const QuadratureSource& s : sources_)
      hold = std::min(hold, s.ticks_to_next_edge() - 1);
    return hold;
  }
  // For walking the encoders one by one over a stretch: how many of the
  // next ticks stay inside the current physics step (0 at a step boundary:
  // the next tick runs the physics), over which encoder e's levels are those
  // of a copy of source(e) ticked along.
  [[nodiscard]] std::uint64_t ticks_to_step_end() const {
    return clock_in_step_ == 0 ? 0 : options_.clocks_per_step - clock_in_step_;
  }
  [[nodiscard]] const QuadratureSource& source(Encoder e) const { return sources_[index(e)]; }
  void skip(std::uint64_t ticks) {
    clock_in_step_ += static_cast<std::uint32_t>(ticks);
    if (clock_in_step_ == options_.clocks_per_step)
      clock_in_step_ = 0;
    clock_ += ticks;
    for (QuadratureSource& s : sources_)
      s.skip(ticks);
  }

  // The truth at the current clock (exact, also between step boundaries).
  [[nodiscard]] TruePose pose() const;
  [[nodiscard]] double distance() const { return pose().distance_m; }
  // Signed x4 edges each encoder has produced so far, indexed by index(Encoder).
  [[nodiscard]] std::array<std::int64_t, kEncoderCount> true_edges() const {
    return {sources_[0].edges(), sources_[1].edges(), sources_[2].edges(), sources_[3].edges()};
  }
  [[nodiscard]] std::uint64_t clock() const { return clock_; }
  // The start, then every record_every_steps steps, and the end of the path.
  [[nodiscard]] const std::vector<TrajectorySample>& trajectory() const { return trajectory_; }
  [[nodiscard]] const Geometry& geometry() const { return geometry_; }

 private:
  struct State {
    Pose pose;
    double steer_rad = 0;
    double odometer_m = 0;
    std::size_t segment = 0;
    double segment_time_s = 0;
    double segment_distance_m = 0;
    std::size_t next_boundary = 0;  // index into boundaries_
  };
  // Signed ground distance of each rolling wheel's contact point, by index(Wheel).
  using Travel = std::array<double, kWheelCount>;
  struct BumpTrack {
    Bump bump;
    bool met = false;
    double direction = 0;   // +1 or -1: the wheel's travel direction when met
    double position_m = 0;  // u: along the bump, in that direction
  };

  void begin_step();
  template <class OnTravel>
  void drive(State& s, double seconds, OnTravel&& on_travel) const;
  Travel move(State& s, double speed_mps, double steer1_rad, double seconds) const;
  void roll(double odometer_m, const Travel& ground);
  void record();

  Geometry geometry_;
  Path path_;
  std::vector<BumpTrack> bumps_;
  std::vector<Slip> slips_;
  std::vector<double> boundaries_;  // sorted odometer readings where a disturbance starts or ends
  Options options_;
  double step_s_;
  std::array<double, kWheelCount> edges_per_metre_{};  // true radius

  State state_;       // at the end of the current step
  State step_start_;  // at its beginning
  std::uint32_t clock_in_step_ = 0;
  std::uint64_t clock_ = 0;
  std::uint64_t steps_ = 0;
  std::array<double, kEncoderCount> exact_edges_{};  // at the end of the current step
  std::array<std::int64_t, kEncoderCount> phase_{};  // the sources' phase accumulators
  std::array<QuadratureSource, kEncoderCount> sources_{};
  std::vector<TrajectorySample> trajectory_;
};

}  // namespace odoloc::world
