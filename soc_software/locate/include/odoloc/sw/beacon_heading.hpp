// Heading from directions of arrival
// (docs/heading-and-relative-pose.md#heading-from-directions-of-arrival).
//
// Kleeman (sec. 1.2, 5.1): "the direction of arrival of each pulse is
// logged so that the robot orientation can be determined"; the paper gives
// no formula. With the robot's position P (a fix) and beacon i at b_i, the
// world bearing of the beacon is psi_i = atan2(b_i - P) and the array
// measured it at beta_i in the robot frame (tof::Doa), so each beacon gives
//     theta_i = psi_i - beta_i   (wrapped to (-pi, pi]).
// Their errors: the DOA's (sd_i, independent) plus the position's, common
// to all beacons: d psi_i = g_i^T dP, g_i = (sin psi_i, -cos psi_i) / rho_i
// (rho_i the planar distance), so Cov(theta) = diag(sd_i^2) + G Sigma_P G^T.
// The estimate is the generalised least-squares mean on the circle: the
// deviations from a reference (the weighted circular mean, weights
// 1/Cov_ii) wrapped to (-pi, pi], then
//     theta = ref + (1^T C^-1 delta) / (1^T C^-1 1),   var = 1 / (1^T C^-1 1).
// Outliers (an echo's direction): the largest studentised residual beyond
// k sd is dropped and the mean recomputed while three or more beacons
// remain; two that disagree are kInconsistent.
//
// Pure function; data never throws (NaN, invalid DOAs, an invalid fix give
// a result with valid == false and the reason); a malformed layout or
// options throw std::invalid_argument.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "odoloc/sw/beacon_fix.hpp"

namespace odoloc::sw::locate {

struct HeadingOptions {
  double outlier_sigmas = 3.0;   // k: studentised residual beyond k sd is an outlier
  double min_doa_sd_rad = 1e-4;  // floor on a DOA's sd (0 would claim infinite weight)
  // A beacon closer than this (planar) to the fix gives no bearing: the
  // position's uncertainty swamps it and atan2 is undefined at 0.
  double min_range_m = 0.05;

  void validate() const;  // std::invalid_argument naming the field
};

// What the heading did with each beacon's DOA.
enum class DoaStatus : std::uint8_t {
  kUsed,
  kNotInLayout,  // more DOAs than beacons in the layout
  kNoDoa,        // tof::Doa::valid is false
  kNonFinite,    // bearing NaN or infinite, sd NaN, negative or beyond pi
  kAtBeacon,     // the fix is within HeadingOptions::min_range_m of the beacon
  kOutlier,      // studentised residual beyond HeadingOptions::outlier_sigmas
};
std::string_view name(DoaStatus status);

enum class HeadingReason : std::uint8_t {
  kNone,
  kNoPosition,    // the fix is invalid, or its position or covariance not finite
  kNoValidDoa,    // no beacon left with a usable DOA
  kInconsistent,  // two beacons left that disagree beyond k sd
};
std::string_view name(HeadingReason reason);

struct DoaUse {
  int beacon = 0;
  DoaStatus status = DoaStatus::kNoDoa;
  double heading_rad = kNaN;   // theta_i = psi_i - beta_i, (-pi, pi]
  double sd_rad = kNaN;        // sqrt(Cov_ii): the DOA's sd and the position's share
  double residual_rad = kNaN;  // theta_i minus the heading, wrapped
};

struct Heading {
  bool valid = false;
  HeadingReason reason = HeadingReason::kNoValidDoa;
  double heading_rad = kNaN;  // robot x axis, counter-clockwise from world x, (-pi, pi]
  double sd_rad = kNaN;       // propagated: DOA sds and the fix's covariance
  // Spread of the used beacons' headings (weights 1/sd_i^2): R the mean
  // resultant length, circular variance 1 - R, circular sd sqrt(-2 ln R).
  double circular_variance = kNaN;
  double circular_sd_rad = kNaN;
  double chi2 = kNaN;           // r^T C^-1 r of the used beacons
  int dof = 0;                  // used - 1
  std::vector<DoaUse> beacons;  // one per DOA given, in order (empty when kNoPosition)

  [[nodiscard]] int used() const;
  [[nodiscard]] int rejected() const;  // kOutlier
};

// doas[i]: beacon i's direction of arrival in the robot frame (the array
// centred on the robot origin, which the fix locates).
Heading beacon_heading(const Fix& fix, const BeaconLayout& layout, std::span<const tof::Doa> doas,
                       const HeadingOptions& options = {});

// Kleeman's cycle: per beacon the DOA of the candidate the fix used
// (BeaconUse::candidate when kUsed), an invalid Doa otherwise (a beacon the
// fix rejected was likely heard by an echo, from the wrong direction).
std::vector<tof::Doa> used_directions(const tof::CycleMeasurement& cycle, const Fix& fix);

}  // namespace odoloc::sw::locate
