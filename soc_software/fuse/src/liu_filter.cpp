// Liu et al.'s filter (liu_filter.hpp).
#include "odoloc/sw/liu_filter.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <numbers>

#include "odoloc/sw/detail/config_checks.hpp"

namespace odoloc::sw::fuse {

void LiuFilterOptions::validate() const {
  constexpr std::string_view kOwner = "LiuFilterOptions";
  const auto positive = [&](double v, std::string_view field) {
    detail::require(detail::finite_positive(v), kOwner,
                    std::string(field) + " must be finite and > 0");
  };
  positive(process_var_m2, "process_var_m2");
  positive(fix_var_m2, "fix_var_m2");
  positive(initial_var_m2, "initial_var_m2");
  positive(fix_gate_m, "fix_gate_m");
  positive(heading_gate_rad, "heading_gate_rad");
  positive(odometry_heading_var_rad2, "odometry_heading_var_rad2");
  positive(laser_heading_var_rad2, "laser_heading_var_rad2");
}

LiuFilter::LiuFilter(const LiuFilterOptions& options) : options_((options.validate(), options)) {}

void LiuFilter::initialise(double time_s, const Pose& pose) {
  detail::require(std::isfinite(time_s) && pose.x.allFinite(), "LiuFilter",
                  "the initial pose must be finite");
  estimate_.time_s = time_s;
  estimate_.pose = pose;
  estimate_.pose.x(2) = wrap_angle(pose.heading());
  estimate_.covariance_m2 = options_.initial_var_m2 * Matrix2::Identity();
  estimate_.initialised = true;
}

Outcome LiuFilter::predict(double time_s, const Vector3& increment) {
  if (!estimate_.initialised)
    return Outcome::kNotInitialised;
  if (!std::isfinite(time_s) || !increment.allFinite()) {
    ++stats_.refused;
    return Outcome::kNonFinite;
  }
  estimate_.pose = compose(estimate_.pose, increment);
  estimate_.time_s = time_s;
  return Outcome::kAccepted;
}

Outcome LiuFilter::fuse_fix(const Vector2& absolute_m, const Vector3& since) {
  if (!estimate_.initialised || !absolute_m.allFinite() || !since.allFinite()) {
    ++stats_.refused;
    return estimate_.initialised ? Outcome::kNonFinite : Outcome::kNotInitialised;
  }
  const Matrix2 predicted = estimate_.covariance_m2 + options_.process_var_m2 * Matrix2::Identity();
  const double heading_then = estimate_.pose.heading() - since(2);
  const Vector2 then = estimate_.pose.position() -
                       Eigen::Rotation2Dd(heading_then).toRotationMatrix() * since.head<2>();
  const Vector2 innovation = absolute_m - then;
  if (innovation.norm() >= options_.fix_gate_m) {
    estimate_.covariance_m2 = predicted;
    ++stats_.fixes_gated;
    return Outcome::kGated;
  }
  const Matrix2 gain =
      predicted * (predicted + options_.fix_var_m2 * Matrix2::Identity()).inverse();
  estimate_.pose.x.head<2>() += gain * innovation;
  estimate_.covariance_m2 = (Matrix2::Identity() - gain) * predicted;
  ++stats_.fixes;
  return Outcome::kAccepted;
}

Outcome LiuFilter::fuse_heading(double robot_bearing_rad, const Vector2& station_m) {
  if (!estimate_.initialised || !std::isfinite(robot_bearing_rad) || !station_m.allFinite()) {
    ++stats_.refused;
    return estimate_.initialised ? Outcome::kNonFinite : Outcome::kNotInitialised;
  }
  const Vector2 from_station = estimate_.pose.position() - station_m;
  if (from_station.norm() == 0) {
    ++stats_.refused;
    return Outcome::kDegenerate;
  }
  const double alpha = std::atan2(from_station.y(), from_station.x());              // eq. 14.17
  const double laser = wrap_angle(std::numbers::pi - (robot_bearing_rad - alpha));  // 14.18
  const double odometry = estimate_.pose.heading();
  const double difference = wrap_angle(laser - odometry);
  if (std::abs(difference) >= options_.heading_gate_rad) {
    ++stats_.headings_gated;
    return Outcome::kGated;
  }
  // Eq. 14.19 as a step from theta_d, so that it holds across +-pi.
  const double sd2 = options_.odometry_heading_var_rad2;
  const double sl2 = options_.laser_heading_var_rad2;
  estimate_.pose.x(2) = wrap_angle(odometry + difference * sd2 / (sl2 + sd2));
  ++stats_.headings;
  return Outcome::kAccepted;
}

Vector2 LiuFilter::absolute_position(const Vector2& station_m, double alpha_rad,
                                     double distance_m) {
  return station_m + distance_m * Vector2{std::cos(alpha_rad), std::sin(alpha_rad)};
}

}  // namespace odoloc::sw::fuse
