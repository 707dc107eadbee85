#include "odoloc/sw/beacon_heading.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "odoloc/sw/detail/config_checks.hpp"
#include "odoloc/sw/tof_doa.hpp"

namespace odoloc::sw::locate {
namespace {

void require(bool ok, const char* what) {
  detail::require(ok, "HeadingOptions", what);
}

bool position_known(const Fix& fix) {
  return fix.valid && std::isfinite(fix.position_m.x) && std::isfinite(fix.position_m.y) &&
         fix.covariance_m2.allFinite();
}

// One usable beacon: its heading, the DOA's variance, and d psi / dP.
struct Bearing {
  std::size_t use = 0;  // index into Heading::beacons
  double heading_rad = 0;
  double doa_var = 0;
  Eigen::Vector2d gradient;
};

// GLS mean of the active bearings on the circle, about the weighted
// circular mean; returns the heading and its variance, fills residuals.
struct Mean {
  double heading_rad = 0;
  double variance = 0;
  Eigen::VectorXd residual;     // per active bearing, wrapped
  Eigen::VectorXd studentised;  // residual / sqrt(C_ii - variance); 0 when undefined
  double chi2 = 0;
  double resultant = 1;  // weighted mean resultant length R
};
Mean gls_mean(const std::vector<Bearing>& active, const Eigen::Matrix2d& position_covariance) {
  const auto n = static_cast<Eigen::Index>(active.size());
  Eigen::MatrixXd g(n, 2);
  Eigen::VectorXd doa_var(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    g.row(i) = active[static_cast<std::size_t>(i)].gradient.transpose();
    doa_var(i) = active[static_cast<std::size_t>(i)].doa_var;
  }
  const Eigen::MatrixXd c =
      Eigen::MatrixXd(doa_var.asDiagonal()) + g * position_covariance * g.transpose();
  // Reference: circular mean with weights 1/C_ii (keeps the deviations small
  // and away from the +-pi cut).
  double sum_w = 0, sum_s = 0, sum_c = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double w = 1 / c(i, i);
    const double h = active[static_cast<std::size_t>(i)].heading_rad;
    sum_w += w, sum_s += w * std::sin(h), sum_c += w * std::cos(h);
  }
  const double reference = std::atan2(sum_s, sum_c);
  Eigen::VectorXd delta(n);
  for (Eigen::Index i = 0; i < n; ++i)
    delta(i) = tof::angle_difference(active[static_cast<std::size_t>(i)].heading_rad, reference);
  const Eigen::LDLT<Eigen::MatrixXd> solver(c);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
  const Eigen::VectorXd c_inv_ones = solver.solve(ones);
  Mean mean;
  mean.variance = 1 / ones.dot(c_inv_ones);
  const double shift = mean.variance * c_inv_ones.dot(delta);
  mean.heading_rad = tof::angle_difference(reference + shift, 0);
  mean.residual = delta.array() - shift;
  mean.chi2 = mean.residual.dot(solver.solve(mean.residual));
  mean.studentised = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double var = c(i, i) - mean.variance;
    if (var > 0)
      mean.studentised(i) = mean.residual(i) / std::sqrt(var);
  }
  mean.resultant = std::min(1.0, std::hypot(sum_s, sum_c) / sum_w);
  return mean;
}

}  // namespace

void HeadingOptions::validate() const {
  require(std::isfinite(outlier_sigmas) && outlier_sigmas > 0,
          "outlier_sigmas must be finite and positive");
  require(std::isfinite(min_doa_sd_rad) && min_doa_sd_rad > 0,
          "min_doa_sd_rad must be finite and positive");
  require(std::isfinite(min_range_m) && min_range_m >= 0,
          "min_range_m must be finite and not negative");
}

std::string_view name(DoaStatus status) {
  switch (status) {
    case DoaStatus::kUsed:
      return "used";
    case DoaStatus::kNotInLayout:
      return "not_in_layout";
    case DoaStatus::kNoDoa:
      return "no_doa";
    case DoaStatus::kNonFinite:
      return "non_finite";
    case DoaStatus::kAtBeacon:
      return "at_beacon";
    case DoaStatus::kOutlier:
      return "outlier";
  }
  return "?";
}

std::string_view name(HeadingReason reason) {
  switch (reason) {
    case HeadingReason::kNone:
      return "none";
    case HeadingReason::kNoPosition:
      return "no_position";
    case HeadingReason::kNoValidDoa:
      return "no_valid_doa";
    case HeadingReason::kInconsistent:
      return "inconsistent";
  }
  return "?";
}

int Heading::used() const {
  return static_cast<int>(std::count_if(beacons.begin(), beacons.end(), [](const DoaUse& u) {
    return u.status == DoaStatus::kUsed;
  }));
}

int Heading::rejected() const {
  return static_cast<int>(std::count_if(beacons.begin(), beacons.end(), [](const DoaUse& u) {
    return u.status == DoaStatus::kOutlier;
  }));
}

Heading beacon_heading(const Fix& fix, const BeaconLayout& layout, std::span<const tof::Doa> doas,
                       const HeadingOptions& options) {
  layout.validate();
  options.validate();
  Heading out;
  if (!position_known(fix)) {
    out.reason = HeadingReason::kNoPosition;
    return out;
  }
  const Eigen::Vector2d p(fix.position_m.x, fix.position_m.y);
  std::vector<Bearing> active;
  for (std::size_t i = 0; i < doas.size(); ++i) {
    const tof::Doa& doa = doas[i];
    DoaUse& use = out.beacons.emplace_back();
    use.beacon = static_cast<int>(i);
    if (i >= layout.beacons.size()) {
      use.status = DoaStatus::kNotInLayout;
      continue;
    }
    if (!doa.valid) {
      use.status = DoaStatus::kNoDoa;
      continue;
    }
    // A deviation beyond pi (or negative) says no direction at all.
    if (!std::isfinite(doa.bearing_rad) || !(doa.sd_rad >= 0 && doa.sd_rad <= std::numbers::pi)) {
      use.status = DoaStatus::kNonFinite;
      continue;
    }
    const Eigen::Vector2d d =
        Eigen::Vector2d(layout.beacons[i].position_m.x, layout.beacons[i].position_m.y) - p;
    const double rho = d.norm();
    if (!(rho > options.min_range_m)) {
      use.status = DoaStatus::kAtBeacon;
      continue;
    }
    const double psi = std::atan2(d.y(), d.x());
    const double sd = std::max(doa.sd_rad, options.min_doa_sd_rad);
    use.status = DoaStatus::kUsed;
    use.heading_rad = tof::angle_difference(psi, doa.bearing_rad);
    // d psi / dP = (sin psi, -cos psi) / rho = (d_y, -d_x) / rho^2.
    const Eigen::Vector2d gradient = Eigen::Vector2d(d.y(), -d.x()) / (rho * rho);
    use.sd_rad = std::sqrt(sd * sd + gradient.dot(fix.covariance_m2 * gradient));
    active.push_back({out.beacons.size() - 1, use.heading_rad, sd * sd, gradient});
  }
  if (active.empty()) {
    out.reason = HeadingReason::kNoValidDoa;
    return out;
  }
  Mean mean = gls_mean(active, fix.covariance_m2);
  // Drop the worst beyond k while three or more remain: with two, either
  // could be the outlier.
  Eigen::Index worst = 0;
  while (mean.studentised.cwiseAbs().maxCoeff(&worst) > options.outlier_sigmas &&
         active.size() >= 3) {
    out.beacons[active[static_cast<std::size_t>(worst)].use].status = DoaStatus::kOutlier;
    active.erase(active.begin() + worst);
    mean = gls_mean(active, fix.covariance_m2);
  }
  out.heading_rad = mean.heading_rad;
  out.sd_rad = std::sqrt(mean.variance);
  out.chi2 = mean.chi2;
  out.dof = static_cast<int>(active.size()) - 1;
  out.circular_variance = 1 - mean.resultant;
  out.circular_sd_rad = std::sqrt(-2 * std::log(mean.resultant));
  if (!std::isfinite(out.heading_rad) || !(out.sd_rad > 0 && std::isfinite(out.sd_rad))) {
    out.reason = HeadingReason::kNoValidDoa;  // the fix's covariance made the mean meaningless
    return out;
  }
  for (DoaUse& use : out.beacons)
    if (std::isfinite(use.heading_rad))
      use.residual_rad = tof::angle_difference(use.heading_rad, out.heading_rad);
  if (mean.studentised.cwiseAbs().maxCoeff() > options.outlier_sigmas) {
    out.reason = HeadingReason::kInconsistent;
    return out;
  }
  out.valid = true;
  out.reason = HeadingReason::kNone;
  return out;
}

std::vector<tof::Doa> used_directions(const tof::CycleMeasurement& cycle, const Fix& fix) {
  std::vector<tof::Doa> out(cycle.beacons.size());
  for (std::size_t i = 0; i < cycle.beacons.size() && i < fix.beacons.size(); ++i) {
    const BeaconUse& use = fix.beacons[i];
    const std::vector<tof::Arrival>& candidates = cycle.beacons[i].candidates;
    if (use.status == BeaconStatus::kUsed && use.candidate >= 0 &&
        static_cast<std::size_t>(use.candidate) < candidates.size())
      out[i] = candidates[static_cast<std::size_t>(use.candidate)].doa;
  }
  return out;
}

}  // namespace odoloc::sw::locate
