// Odometry register values from physical vehicle parameters, and pose
// registers back to SI units. Formats: docs/odometry.md.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>

#include "odoloc/sw/eppm_units.hpp"

namespace odoloc::sw {

struct SteeringEncoder {
  double lines_per_rev = 500;
  double gear_ratio = 20;  // encoder turns per steering turn
  double edges_per_line = 4;
  [[nodiscard]] double turns_per_edge() const {
    return 1.0 / (edges_per_line * lines_per_rev * gear_ratio);
  }
};

struct VehicleGeometry {
  double rear_track_m = 0.40;  // D: distance between the rear wheels
  double wheelbase_m = 0.50;   // L: rear axle to the front wheel axis
  EncoderGeometry rear{0.075, 500, 20, 4};
  EncoderGeometry front{0.10, 500, 30, 4};
  SteeringEncoder steering{};
  double steer_limit_rad = 40.0 * std::numbers::pi / 180.0;
};

// The scale registers of OdometryConfig (units 2^-40 m or turn per count;
// the steering limit in 2^-32 turn).
struct OdometryScales {
  std::uint32_t rear_ds, rear_dtheta, front_ds, front_dtheta, steer, steer_limit;
};

namespace detail {
inline std::uint32_t to_register(double value, int fraction_bits, const char* name) {
  const double scaled = std::ldexp(value, fraction_bits);
  if (!std::isfinite(scaled) || scaled < 1.0 || scaled > 4294967295.0) {
    throw std::domain_error(std::string("odometry scale '") + name +
                            "' does not fit 32 bits: " + std::to_string(value));
  }
  return static_cast<std::uint32_t>(std::llround(scaled));
}
}  // namespace detail

inline OdometryScales odometry_scales(const VehicleGeometry& g) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  if (!(g.rear_track_m > 0) || !(g.wheelbase_m > 0)) {
    throw std::domain_error("odometry: track and wheelbase must be positive");
  }
  if (!(g.steer_limit_rad > 0) || g.steer_limit_rad > std::numbers::pi / 2) {
    throw std::domain_error("odometry: steering limit must be in (0, 90] degrees");
  }
  const double kappa_rear = g.rear.metres_per_edge();
  const double kappa_front = g.front.metres_per_edge();
  return {
      detail::to_register(kappa_rear / 2, 40, "rear_ds"),
      detail::to_register(kappa_rear / (kTwoPi * g.rear_track_m), 40, "rear_dtheta"),
      detail::to_register(kappa_front, 40, "front_ds"),
      detail::to_register(kappa_front / (kTwoPi * g.wheelbase_m), 40, "front_dtheta"),
      detail::to_register(g.steering.turns_per_edge(), 40, "steer"),
      detail::to_register(g.steer_limit_rad / kTwoPi, 32, "steer_limit"),
  };
}

// Min-select tuning. Leaky sums of quantised increments telescope: two honest
// sources differ by at most about one reading's quantisation, one edge per
// wheel: kappa_rear + kappa_front in distance, 2 kappa_rear / D + kappa_front
// / L in heading. The threshold is `margin` times that, so noise neither
// takes a component over nor hands it back; shift sets the memory (2^shift
// updates: 4096 = 0.41 s at 100 us, long enough to integrate a bump's
// over-count). shift = 0 with zero thresholds is the paper's rule.
struct MinSelectSetup {
  std::uint8_t shift;
  std::uint32_t ds_threshold;      // 2^-32 m
  std::uint32_t dtheta_threshold;  // 2^-40 turn
};
inline MinSelectSetup min_select_setup(const VehicleGeometry& g, std::uint8_t shift = 12,
                                       double margin = 3.0) {
  const double kappa_rear = g.rear.metres_per_edge();
  const double kappa_front = g.front.metres_per_edge();
  const double heading_rad = 2 * kappa_rear / g.rear_track_m + kappa_front / g.wheelbase_m;
  return {
      shift, detail::to_register(margin * (kappa_rear + kappa_front), 32, "ds_threshold"),
      detail::to_register(margin * heading_rad / (2.0 * std::numbers::pi), 40, "dtheta_threshold")};
}

// Pose registers to SI: x, y in 2^-46 m; theta a 40-bit binary angle.
inline double pose_metres(std::int64_t raw) {
  return std::ldexp(static_cast<double>(raw), -46);
}
inline double heading_radians(std::uint64_t theta40) {
  const double turns = std::ldexp(static_cast<double>(theta40 & ((1ULL << 40) - 1)), -40);
  return 2.0 * std::numbers::pi * (turns >= 0.5 ? turns - 1.0 : turns);
}
inline std::int64_t metres_to_pose(double metres) {
  return std::llround(std::ldexp(metres, 46));
}
inline std::uint64_t radians_to_heading(double rad) {
  const double turns = rad / (2.0 * std::numbers::pi);
  const double wrapped = turns - std::floor(turns);
  return static_cast<std::uint64_t>(std::llround(std::ldexp(wrapped, 40))) & ((1ULL << 40) - 1);
}

}  // namespace odoloc::sw
