#include "odoloc/sw/binaural_pose.hpp"

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "odoloc/sw/detail/config_checks.hpp"
#include "odoloc/sw/tof_doa.hpp"

namespace odoloc::sw::locate {
namespace {

using tof::Flag;

double wrap(double a) {
  return tof::angle_difference(a, 0);
}

void require(bool ok, const char* field) {
  detail::require(ok, "BinauralOptions", field);
}

}  // namespace

void BinauralOptions::validate() const {
  require(std::isfinite(baseline_m) && baseline_m > 0, "baseline_m must be finite and positive");
  require(std::isfinite(speed_of_sound_mps) && speed_of_sound_mps > 0,
          "speed_of_sound_mps must be finite and positive");
  require(std::isfinite(range_sd_m) && range_sd_m > 0, "range_sd_m must be finite and positive");
  require(std::isfinite(min_path_difference_sd_m) && min_path_difference_sd_m > 0,
          "min_path_difference_sd_m must be finite and positive");
  require(std::isfinite(gate_sigmas) && gate_sigmas > 0, "gate_sigmas must be finite and positive");
  require(max_relative_orientation_rad > 0 && max_relative_orientation_rad <= std::numbers::pi,
          "max_relative_orientation_rad must be in (0, pi]");
  require(std::isfinite(max_range_m) && max_range_m > baseline_m,
          "max_range_m must be finite and longer than the baseline");
}

std::string_view name(BinauralReason reason) {
  switch (reason) {
    case BinauralReason::kNone:
      return "none";
    case BinauralReason::kMissingData:
      return "missing_data";
    case BinauralReason::kNonFiniteInput:
      return "non_finite_input";
    case BinauralReason::kOutOfRange:
      return "out_of_range";
    case BinauralReason::kNoIntersection:
      return "no_intersection";
    case BinauralReason::kOnBaselineAxis:
      return "on_baseline_axis";
    case BinauralReason::kInconsistent:
      return "inconsistent";
  }
  return "?";
}

TransmitterFix locate_transmitter(const tof::BinauralPairResult& pair,
                                  const BinauralOptions& options) {
  options.validate();
  TransmitterFix fix;
  fix.flags = pair.flags;
  if (pair.flags.has(Flag::kMissing)) {
    fix.reason = BinauralReason::kMissingData;
    return fix;
  }
  const double c = options.speed_of_sound_mps;
  const double b = options.baseline_m;
  const double r_left = c * pair.tof_left_s;
  const double r_right = c * pair.tof_right_s;
  if (!std::isfinite(r_left) || !std::isfinite(r_right)) {
    fix.reason = BinauralReason::kNonFiniteInput;
    return fix;
  }
  const auto physical = [&](double r) { return r >= 0 && r <= options.max_range_m; };
  if (!physical(r_left) || !physical(r_right)) {
    fix.reason = BinauralReason::kOutOfRange;
    return fix;
  }
  // s from the coarse ranges; D from the phase unless tof could not decide
  // its whole cycles (kAmbiguous) or had no common edge, then the coarse
  // difference (the envelopes' when wired).
  const double s = r_left + r_right;
  const double var_s = 2 * options.range_sd_m * options.range_sd_m;
  const double phase_sd = c * pair.difference_sd_s;
  // A phase whose deviation exceeds the baseline says nothing about D.
  fix.phase_used = std::isfinite(pair.path_difference_m) && std::isfinite(phase_sd) &&
                   phase_sd <= b && !pair.flags.has(Flag::kAmbiguous);
  double d = 0;
  double var_d = 0;
  if (fix.phase_used) {
    d = pair.path_difference_m;
    var_d = std::pow(std::max(phase_sd, options.min_path_difference_sd_m), 2);
  } else {
    d = std::isfinite(pair.coarse_difference_s) ? c * pair.coarse_difference_s : r_left - r_right;
    var_d = var_s;
  }
  fix.range_sum_m = s;
  fix.range_sum_sd_m = std::sqrt(var_s);
  fix.path_difference_m = d;
  fix.path_difference_sd_m = std::sqrt(var_d);

  // Ellipse (s) and hyperbola (D) with foci at the receivers:
  //   x = s D / (2b),  y^2 = (s^2 - b^2)(b^2 - D^2) / (4 b^2).
  const double b2 = b * b;
  const double es = (s - b) * (s + b);  // s^2 - b^2: < 0 when the ranges cannot reach
  const double hd = (b - d) * (b + d);  // b^2 - D^2: < 0 beyond the baseline's ends
  const double x = s * d / (2 * b);
  const double y2 = es * hd / (4 * b2);
  // sd of y^2 (linearised): 2 Q. y >= k sd(y) <=> y^2 >= k Q, defined at y = 0.
  const double q = std::sqrt(s * s * hd * hd * var_s + d * d * es * es * var_d) / (4 * b2);
  const double k = options.gate_sigmas;
  if (y2 < -2 * k * q) {
    fix.reason = BinauralReason::kNoIntersection;
    return fix;
  }
  if (y2 <= k * q) {
    fix.reason = BinauralReason::kOnBaselineAxis;
    return fix;
  }
  const double y = std::sqrt(y2);
  fix.position_m = {x, y};
  Eigen::Matrix2d jacobian;  // d(x, y)/d(s, D)
  jacobian << d / (2 * b), s / (2 * b), s * hd / (4 * b2 * y), -d * es / (4 * b2 * y);
  fix.covariance_m2 = jacobian * Eigen::Vector2d(var_s, var_d).asDiagonal() * jacobian.transpose();
  if (!fix.covariance_m2.allFinite()) {
    fix.reason = BinauralReason::kNonFiniteInput;
    return fix;
  }
  fix.valid = true;
  fix.reason = BinauralReason::kNone;
  return fix;
}

double RelativePose::heading_rad() const {
  return wrap(relative_orientation_rad + std::numbers::pi);
}

RelativePose relative_pose(const tof::BinauralPairResult& robot2_hears_robot1,
                           const tof::BinauralPairResult& robot1_hears_robot2,
                           const BinauralOptions& options) {
  RelativePose pose;
  pose.robot1_in_robot2 = locate_transmitter(robot2_hears_robot1, options);
  pose.robot2_in_robot1 = locate_transmitter(robot1_hears_robot2, options);
  const TransmitterFix& f1 = pose.robot1_in_robot2;
  const TransmitterFix& f2 = pose.robot2_in_robot1;
  if (!f1.valid || !f2.valid) {
    pose.reason = !f1.valid ? f1.reason : f2.reason;
    return pose;
  }
  const Eigen::Vector2d p1(f1.position_m.x, f1.position_m.y);
  const Eigen::Vector2d p2(f2.position_m.x, f2.position_m.y);
  // Eqs. 7-9 with atan2 (the printed tan^-1 loses the quadrant of a2).
  pose.a1_rad = std::atan2(p1.x(), p1.y());
  pose.a2_rad = std::atan2(p2.y(), p2.x());
  pose.relative_orientation_rad = wrap(std::numbers::pi / 2 - pose.a1_rad - pose.a2_rad);
  // d(X'_1, Y'_1, q)/d(X'_1, Y'_1, X'_2, Y'_2); da1 = (Y, -X)/rho^2 dP1,
  // da2 = (-Y, X)/rho^2 dP2, dq = -da1 - da2.
  Eigen::Matrix<double, 3, 4> jacobian = Eigen::Matrix<double, 3, 4>::Zero();
  jacobian(0, 0) = 1;
  jacobian(1, 1) = 1;
  jacobian(2, 0) = -p1.y() / p1.squaredNorm();
  jacobian(2, 1) = p1.x() / p1.squaredNorm();
  jacobian(2, 2) = p2.y() / p2.squaredNorm();
  jacobian(2, 3) = -p2.x() / p2.squaredNorm();
  Eigen::Matrix4d inputs = Eigen::Matrix4d::Zero();
  inputs.topLeftCorner<2, 2>() = f1.covariance_m2;
  inputs.bottomRightCorner<2, 2>() = f2.covariance_m2;
  pose.covariance = jacobian * inputs * jacobian.transpose();
  pose.relative_orientation_sd_rad = std::sqrt(pose.covariance(2, 2));
  pose.beyond_orientation_limit =
      std::abs(pose.relative_orientation_rad) > options.max_relative_orientation_rad;
  // Both pairs measured the distance between the two transmitters.
  const Eigen::Vector2d u1 = p1.normalized();
  const Eigen::Vector2d u2 = p2.normalized();
  pose.distance_mismatch_m = p1.norm() - p2.norm();
  pose.distance_mismatch_sd_m =
      std::sqrt(u1.dot(f1.covariance_m2 * u1) + u2.dot(f2.covariance_m2 * u2));
  if (!pose.covariance.allFinite()) {
    pose.reason = BinauralReason::kNonFiniteInput;
    return pose;
  }
  if (std::abs(pose.distance_mismatch_m) > options.gate_sigmas * pose.distance_mismatch_sd_m) {
    pose.reason = BinauralReason::kInconsistent;
    return pose;
  }
  pose.valid = true;
  pose.reason = BinauralReason::kNone;
  return pose;
}

}  // namespace odoloc::sw::locate
