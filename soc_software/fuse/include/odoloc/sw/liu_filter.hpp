// Liu et al.'s own fusion of dead reckoning with the scanning-laser and
// ultrasonic base station (sec. 14.3.3, eqs. 14.9-14.19; paper:
// ../shared/papers/liu-scanning-laser-ultrasonic-ekf.txt), with the
// paper's settings as defaults, so that one run can put it beside the pose
// EKF (pose_ekf.hpp). docs/fusion.md, "Liu's own filter", derives each
// step and lists the deviations from the printed equations.
//
// State: the position X = (x, y) in metres (world frame) with its 2 x 2
// covariance P (m^2), and the heading theta (rad, (-pi, pi]) without one
// (Liu fuses it with fixed variances, eq. 14.19).
//   - predict: dead reckoning, X_d = X (+) d for each odometry increment d
//     (the fabric's integration, eqs. 14.4-14.7); P does not change;
//   - fix X_a (eqs. 14.9, 14.10: x_a = x_s + d cos(alpha), y_a = y_s +
//     d sin(alpha)): one step k of the filter with F = C = I,
//       P(k|k-1) = P(k-1|k-1) + Q                          (14.12)
//       K = P(k|k-1) [P(k|k-1) + R]^-1                     (14.13, the
//           printed equation has lost its inverse)
//       X = X_d + K (X_a - X_d),  P = (I - K) P(k|k-1)     (14.14, 14.15)
//     fused only when |X_a - X_d| < fix_gate_m (Liu's "selected
//     threshold"); a gated fix still counts as a step k (P grows by Q);
//   - heading from the robot's laser angle beta of the station:
//     alpha = atan2(y - y_s, x - x_s) from the estimate (14.17),
//     theta_l = pi - (beta - alpha) (14.18), fused when within
//     heading_gate_rad of theta_d as
//       theta = (theta_d sigma_l^2 + theta_l sigma_d^2) / (sigma_l^2 + sigma_d^2)
//     (14.19, whose printed denominator reads sigma_a^2 for sigma_d^2).
// Inputs that are not finite are refused and change nothing.
#pragma once

#include <cstdint>
#include <numbers>

#include "odoloc/sw/pose_ekf.hpp"

namespace odoloc::sw::fuse {

struct LiuFilterOptions {
  // Liu's Q, R and P(0|0): diag(1000, 1000) mm^2 each, 1e-3 m^2 per axis.
  double process_var_m2 = 1e-3;  // Q, per step k (per fix offered)
  double fix_var_m2 = 1e-3;      // R
  double initial_var_m2 = 1e-3;  // P(0|0)
  // Liu gives no value; he calls "absolute error larger than 15 cm" the
  // occasional wrong measurement that the fusion filters out.
  double fix_gate_m = 0.15;
  double heading_gate_rad = 3 * std::numbers::pi / 180;  // "for example 3 degrees"
  // sigma_d^2 (dead-reckoned heading) and sigma_l^2 (laser heading): 2 deg^2.
  double odometry_heading_var_rad2 = 2 * (std::numbers::pi / 180) * (std::numbers::pi / 180);
  double laser_heading_var_rad2 = 2 * (std::numbers::pi / 180) * (std::numbers::pi / 180);

  // Throws std::invalid_argument naming the first field that is not finite
  // and positive.
  void validate() const;
};

struct LiuEstimate {
  double time_s = 0;
  Pose pose;
  Matrix2 covariance_m2 = Matrix2::Zero();  // of the position
  bool initialised = false;
};

struct LiuStats {
  std::uint64_t fixes = 0, fixes_gated = 0;
  std::uint64_t headings = 0, headings_gated = 0;
  std::uint64_t refused = 0;  // not finite, or before initialise()
};

class LiuFilter {
 public:
  explicit LiuFilter(const LiuFilterOptions& options = {});

  // X(0|0) = the pose's position with P(0|0) = initial_var_m2 I, theta_d =
  // its heading. Throws std::invalid_argument for a pose that is not finite.
  void initialise(double time_s, const Pose& pose);
  // Dead reckoning with an odometry increment (robot frame at the previous
  // pose) ending at time_s. Dropped before initialise().
  Outcome predict(double time_s, const Vector3& increment);
  // One filter step with the absolute position X_a (m, world frame)
  // measured `since` ago: the robot's motion from the fix's time to the
  // newest prediction, robot frame at the fix's time (increment_between of
  // the odometry; zero: a fix at the newest time). The innovation is taken
  // against the dead-reckoned position at the fix's time and moves the
  // whole track (F = I: the same as fusing it then and predicting since).
  // kAccepted, kGated (beyond fix_gate_m: P still grows by Q), kNonFinite,
  // kNotInitialised.
  Outcome fuse_fix(const Vector2& absolute_m, const Vector3& since = Vector3::Zero());
  // Eqs. 14.17-14.19 with beta (rad, robot frame, from the robot to the
  // station at station_m): kAccepted, kGated (beyond heading_gate_rad),
  // kNonFinite, kNotInitialised, kDegenerate (the estimate at the station).
  Outcome fuse_heading(double robot_bearing_rad, const Vector2& station_m);

  [[nodiscard]] const LiuEstimate& estimate() const { return estimate_; }
  [[nodiscard]] const LiuStats& stats() const { return stats_; }
  [[nodiscard]] const LiuFilterOptions& options() const { return options_; }

  // Eqs. 14.9 and 14.10 about a station at station_m: the point at
  // horizontal distance distance_m along the station laser's angle alpha
  // (rad, world frame).
  [[nodiscard]] static Vector2 absolute_position(const Vector2& station_m, double alpha_rad,
                                                 double distance_m);

 private:
  LiuFilterOptions options_;
  LiuEstimate estimate_;
  LiuStats stats_;
};

}  // namespace odoloc::sw::fuse
