// Fusion of the fabric's odometry with the absolute sources: an extended
// Kalman filter on the planar pose (docs/fusion.md).
//
// State x = (x, y, theta): the robot origin in the world frame, metres, and
// the heading of its x axis counter-clockwise from world x, radians, kept in
// (-pi, pi]. Covariance P (3 x 3), m^2, m rad, rad^2.
//
// Predict: an odometry increment d = (dx, dy, dtheta) in the robot frame
// at the start of the step (increment_between: two poses the fabric
// integrated), x' = x (+) d:
//     p' = p + R(theta) (dx, dy),  theta' = theta + dtheta,
//     P' = F P F^T + G Q(d) G^T,   F = dx'/dx, G = dx'/dd = blockdiag(R(theta), 1),
// with Q(d) diagonal in the robot frame, growing with the distance driven
// and the turning (OdometryNoise; Liu eq. 14.12 adds a constant Q per step
// instead, which does not scale with how far the wheels went).
//
// Updates (each at its capture time, see "Late measurements" below), every
// one through the same gate and Joseph-form update:
//   - PositionFix: z = p (a beacon fix, Liu's eqs. 14.9/14.10 as x_a, y_a);
//   - BodyPointFix: z = p + R(theta) o, a known point o of the body
//     (Thamma's head and tail boxes);
//   - RangeSet: tightly coupled beacon ranges with a common unknown offset
//     (Kleeman's cycle): z_i = sqrt(|p + R(theta) m_i - b_i|^2 + h_i^2) + c,
//     m_i the robot's motion from the set's time to the range's, one scalar
//     update per beacon with the offset c as a temporary fourth state (the
//     Crazyflie's TDoA filter fuses one scalar per anchor pair: the same
//     information once c is eliminated). The first range pins c (the
//     earliest pair of agreeing offsets: echoes only add their detour) and
//     is not gated; then the best-fitting range each time, so an echo comes
//     last and is gated;
//   - HeadingFix: z = theta (directions of arrival, sw::locate::beacon_heading);
//   - StationBearing: z = atan2(y - y_s, x - x_s), the station's laser angle
//     of the robot (Liu alpha);
//   - StationRange: z = sqrt(|p - s|^2 + h^2), the station's ultrasonic
//     range after the RF trigger, t0 already removed (Liu eq. 14.8);
//   - RobotBearing: z = atan2(y_s - y, x_s - x) - theta, the robot's laser
//     angle of the station (Liu beta; eq. 14.18 solved for it).
// Angle innovations are wrapped to (-pi, pi].
//
// Gate: the normalised innovation squared NIS = nu^T S^-1 nu against the
// chi-square quantile of the measurement's dimension at GateOptions::
// probability, per measurement type. A type rejected `reopen_after`
// times in a row over at least `reopen_after_s` is let back in, so the
// filter is never locked out for good (Liu gates on a fixed distance; a
// robot that slipped further than it never recovers): the variances of the
// states the measurement sees grow until it is one sigma away, then it is
// fused; a beacon cycle (one rejection when most of its ranges are gated)
// is fused again from a position prior widened by offset_sd_m until it
// settles (docs/fusion.md, "The gate, and the way back in").
//
// Late measurements: the filter keeps the last `history_s` seconds of
// inputs with the state before each. A measurement older than the newest
// input is inserted at its capture time and everything after it replayed.
// Older than the history: refused (Outcome::kTooLate).
//
// Time-out: without an accepted absolute update for `timeout_s` the
// estimate is odometry alone, and Estimate::odometry_only says so.
//
// Covariance: symmetrised after every step; eigenvalues below
// `min_variance` are raised to it, so P is never zero, negative or NaN.
// Inputs that are not finite are refused (Outcome::kNonFinite) and change
// nothing. Bad options or an initial covariance that is not positive
// definite throw std::invalid_argument.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <deque>
#include <string_view>
#include <variant>
#include <vector>

namespace odoloc::sw::fuse {

using Vector2 = Eigen::Vector2d;
using Vector3 = Eigen::Vector3d;
using Matrix2 = Eigen::Matrix2d;
using Matrix3 = Eigen::Matrix3d;

// x = (x m, y m, theta rad).
struct Pose {
  Vector3 x = Vector3::Zero();
  [[nodiscard]] Vector2 position() const { return x.head<2>(); }
  [[nodiscard]] double heading() const { return x(2); }
};

// Wraps an angle to (-pi, pi].
double wrap_angle(double rad);

// The motion from `from` to `to` in the robot frame at `from`:
// (R(-theta_from) (p_to - p_from), wrap(theta_to - theta_from)). The
// fabric's pose registers read twice give the increment between the reads.
Vector3 increment_between(const Pose& from, const Pose& to);
// `pose` moved by `increment` (the inverse of increment_between).
Pose compose(const Pose& pose, const Vector3& increment);
// The signed distance driven along `increment` (m; negative when reversing):
// the length of the circular arc from the origin, heading 0, to (dx, dy)
// with the turn dtheta, chord * (dtheta/2) / sin(dtheta/2). Exact for a
// straight drive and for a constant turning radius; the fabric's midpoint
// integration over a 10 ms read interval makes that arc to second order.
// NaN for a non-finite increment.
double arc_length(const Vector3& increment);

// ---------------------------------------------------------------- inputs

// An odometry increment (robot frame at the start of the step).
struct Increment {
  Vector3 d = Vector3::Zero();  // dx m, dy m, dtheta rad
};
struct PositionFix {
  Vector2 position_m = Vector2::Zero();
  Matrix2 covariance_m2 = Matrix2::Identity();
};
struct BodyPointFix {
  Vector2 body_point_m = Vector2::Zero();  // the point in the robot frame
  Vector2 position_m = Vector2::Zero();    // where it was measured, world frame
  Matrix2 covariance_m2 = Matrix2::Identity();
};
struct BeaconRange {
  Vector2 beacon_m = Vector2::Zero();
  double height_m = 0;    // the beacon above the receivers' plane
  double distance_m = 0;  // measured, with the cycle's common offset
  double sd_m = 0.01;
  // Where the robot origin was when this range was captured, in the robot
  // frame at the set's time (from odometry: a moving robot hears a cycle's
  // beacons one after the other); zero: at the set's time.
  Vector2 motion_m = Vector2::Zero();
};
struct RangeSet {
  std::vector<BeaconRange> ranges;
  double offset_sd_m = 10;  // prior on the common offset about the one most ranges share
};
struct HeadingFix {
  double heading_rad = 0;
  double sd_rad = 0.01;
};
struct StationBearing {
  Vector2 station_m = Vector2::Zero();
  double bearing_rad = 0;  // world frame, from the station to the robot
  double sd_rad = 0.001;
};
struct StationRange {
  Vector2 station_m = Vector2::Zero();
  double height_m = 0;
  double distance_m = 0;
  double sd_m = 0.01;
};
struct RobotBearing {
  Vector2 station_m = Vector2::Zero();
  double bearing_rad = 0;  // robot frame, from the robot to the station
  double sd_rad = 0.001;
};

using Measurement = std::variant<PositionFix, BodyPointFix, RangeSet, HeadingFix, StationBearing,
                                 StationRange, RobotBearing>;

// One entry per Measurement alternative, in the same order.
enum class MeasurementType : std::uint8_t {
  kPositionFix,
  kBodyPointFix,
  kBeaconRange,  // one per range of a RangeSet
  kHeading,
  kStationBearing,
  kStationRange,
  kRobotBearing,
};
inline constexpr std::size_t kMeasurementTypes = 7;
std::string_view name(MeasurementType type);
MeasurementType type_of(const Measurement& m);

// What the filter did with an input.
enum class Outcome : std::uint8_t {
  kAccepted,
  kReopened,        // accepted after a run of rejections, P inflated
  kGated,           // NIS beyond the gate
  kNonFinite,       // a NaN or infinite value, or a deviation <= 0
  kTooLate,         // older than the history
  kNotInitialised,  // before the first pose
  kDegenerate,      // the geometry gives no information (at the station, no ranges)
  // Not offered to the filter: the beacon cycle's solver found two sets of
  // beacons explaining it at two places (locate::NoFixReason::
  // kAmbiguousBeaconSets), so its ranges hold echoes that fit as well as the
  // direct paths (the localiser's decision; the filter never returns it).
  kAmbiguous,
};
std::string_view name(Outcome outcome);

// ---------------------------------------------------------------- options

// Odometry noise per step, robot frame (standard deviations grow with the
// square root of the distance |d| driven and the angle |dtheta| turned, as
// independent errors per unit of travel add up).
struct OdometryNoise {
  double along_sd_per_sqrt_m = 0.01;      // wheel radius and slip along the track
  double across_sd_per_sqrt_m = 0.005;    // side slip
  double heading_sd_per_sqrt_m = 0.005;   // rad per sqrt(m): bumps, track width
  double heading_sd_per_sqrt_rad = 0.02;  // rad per sqrt(rad turned)
  double floor_sd = 1e-5;                 // per step (m and rad), so Q is never zero
};

struct GateOptions {
  double probability = 0.999;   // chi-square quantile per measurement dimension
  int reopen_after = 5;         // rejections in a row of one type ...
  double reopen_after_s = 1.0;  // ... spanning at least this long
  bool enabled = true;
};

struct EkfOptions {
  OdometryNoise odometry;
  GateOptions gate;
  double history_s = 1.0;       // late measurements up to this old are replayed
  double timeout_s = 2.0;       // no absolute update for this long: odometry only
  double min_variance = 1e-12;  // floor on P's eigenvalues (m^2 and rad^2)

  void validate() const;  // std::invalid_argument naming the field
};

// The estimate at the newest input.
struct Estimate {
  double time_s = 0;
  Pose pose;
  Matrix3 covariance = Matrix3::Zero();
  bool initialised = false;
  bool odometry_only = true;    // no accepted absolute update within timeout_s
  double last_absolute_s = -1;  // time of the last accepted absolute update; -1: none
};

// What one measurement type has seen (first processing only, not replays).
struct TypeStats {
  std::uint64_t accepted = 0;
  std::uint64_t reopened = 0;
  std::uint64_t gated = 0;
  std::uint64_t refused = 0;  // non-finite, too late, not initialised, degenerate
  double last_nis = 0;        // of the last gated or accepted update
  int rejected_in_row = 0;
};

// ---------------------------------------------------------------- filter

class PoseEkf {
 public:
  explicit PoseEkf(const EkfOptions& options = {});

  // Sets the pose at time_s (also the set-pose path): the history is
  // dropped. Throws std::invalid_argument if the pose is not finite or the
  // covariance is not symmetric positive definite.
  void initialise(double time_s, const Pose& pose, const Matrix3& covariance);
  // Predicts with an odometry increment ending at time_s. Before
  // initialise() the increment is dropped (there is no pose to move).
  Outcome predict(double time_s, const Increment& increment);
  // Fuses a measurement captured at time_s (<= newest input: replayed).
  Outcome update(double time_s, const Measurement& measurement);

  [[nodiscard]] Estimate estimate() const;
  [[nodiscard]] const TypeStats& stats(MeasurementType type) const {
    return stats_[static_cast<std::size_t>(type)];
  }
  [[nodiscard]] const EkfOptions& options() const { return options_; }
  // Inputs kept for late measurements (those within history_s of the newest).
  [[nodiscard]] std::size_t history_length() const { return history_.size(); }
  // The chi-square gate of a measurement of `dimension` (the quantile).
  [[nodiscard]] double gate(int dimension) const;

 private:
  struct State {
    Vector3 x = Vector3::Zero();
    Matrix3 P = Matrix3::Identity();
  };
  using Input = std::variant<Increment, Measurement>;
  struct Step {
    double time_s;
    Input input;
    State before;   // the state this input was applied to
    Outcome first;  // what the first pass did (a replay keeps a reopening)
  };

  Outcome apply(State& s, double time_s, const Input& input, const Outcome* replaying);
  Outcome fuse(State& s, const Measurement& m, const Outcome* replaying);
  // A range set; reopened, fused again until it settles (fuse_ranges: one pass).
  Outcome fuse_range_set(State& s, const RangeSet& set, const Outcome* replaying);
  Outcome fuse_ranges(State& s, const RangeSet& set, const Outcome* replaying);
  // The gate and the Joseph update of one linearised measurement on an
  // N-dimensional state (the pose, or the pose and a range offset):
  // residual nu (angles already wrapped), Jacobian H, noise R. `ungated`:
  // applied without the gate and not counted (a range set's reference).
  template <int N, int Rows>
  Outcome correct(Eigen::Matrix<double, N, 1>& x, Eigen::Matrix<double, N, N>& P,
                  MeasurementType type, const Eigen::Matrix<double, Rows, 1>& nu,
                  const Eigen::Matrix<double, Rows, N>& H,
                  const Eigen::Matrix<double, Rows, Rows>& R, const Outcome* replaying,
                  bool ungated = false);
  template <int N>
  void condition(Eigen::Matrix<double, N, N>& P) const;
  void record(MeasurementType type, Outcome outcome, double nis, const Outcome* replaying);
  // One more rejection in the type's run (its start time kept).
  void count_rejection(MeasurementType type);
  // Whether `rejections` in a row of `type`, this one included, let it back
  // in: more than gate.reopen_after, over at least gate.reopen_after_s.
  [[nodiscard]] bool run_ends(MeasurementType type, int rejections) const;
  Outcome insert(double time_s, const Input& input);

  EkfOptions options_;
  std::array<double, 5> gates_{};  // chi-square quantile by dimension 1..4 (index 0 unused)
  bool initialised_ = false;
  double time_s_ = 0;  // the newest input's
  State state_;
  double last_absolute_s_ = -1;
  double last_time_s_ = 0;  // the time of the input being applied
  std::deque<Step> history_;
  std::array<TypeStats, kMeasurementTypes> stats_{};
  std::array<double, kMeasurementTypes> rejected_since_{};  // start of the run of rejections
};

// Chi-square distribution function of integer degrees of freedom k >= 1,
// and its quantile (bisection), for the gates and the consistency tests.
double chi_square_cdf(double x, int k);
double chi_square_quantile(double probability, int k);

}  // namespace odoloc::sw::fuse
