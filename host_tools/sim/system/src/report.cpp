#include "odoloc/sim/report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace odoloc::sim {

namespace {

double wrapped(double rad) {
  return std::remainder(rad, 2 * std::numbers::pi);
}
double distance(const world::Pose& a, const world::Pose& b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
}
constexpr double kDegPerRad = 180 / std::numbers::pi;

}  // namespace

std::string_view name(Source source) {
  switch (source) {
    case Source::kRearOdometry:
      return "rear-only odometry";
    case Source::kFrontOdometry:
      return "front-only odometry";
    case Source::kMinSelect:
      return "min-select odometry";
    case Source::kUltrasonic:
      return "ultrasonic fixes alone";
    case Source::kFused:
      return "fused (EKF)";
    case Source::kLiuFilter:
      return "Liu et al.'s filter";
  }
  return "?";
}

void ErrorReport::add(Source source, const world::Pose& truth, const world::Pose& estimate,
                      bool has_heading) {
  Sums& s = sums_[static_cast<std::size_t>(source)];
  const double e = distance(estimate, truth);
  const double h = has_heading ? wrapped(estimate.theta_rad - truth.theta_rad) : 0.0;
  ++s.n;
  s.position2 += e * e;
  s.heading2 += h * h;
  s.last = estimate;
  s.last_truth = truth;
  s.has_heading = has_heading;
}

void ErrorReport::mark_return() {
  for (Sums& s : sums_)
    if (s.n > 0)
      s.returns.push_back(distance(s.last, s.last_truth));
}

SourceErrors ErrorReport::errors(Source source) const {
  const Sums& s = sums_[static_cast<std::size_t>(source)];
  SourceErrors e;
  e.samples = s.n;
  e.has_heading = s.has_heading;
  e.returns_m = s.returns;
  if (s.n == 0)
    return e;
  const auto n = static_cast<double>(s.n);
  e.final_position_m = distance(s.last, s.last_truth);
  e.final_heading_rad = s.has_heading ? wrapped(s.last.theta_rad - s.last_truth.theta_rad) : 0.0;
  e.rms_position_m = std::sqrt(s.position2 / n);
  e.rms_heading_rad = std::sqrt(s.heading2 / n);
  e.return_to_start_m =
      returns_to_start_ ? distance(s.last, start_) : std::numeric_limits<double>::quiet_NaN();
  return e;
}

std::string ErrorReport::table() const {
  std::string out =
      fmt::format("{:<24} {:>8} {:>11} {:>11} {:>10} {:>10} {:>13}\n", "source", "samples",
                  "final (mm)", "final (deg)", "RMS (mm)", "RMS (deg)", "return (mm)");
  for (const Source source : sources()) {
    const SourceErrors e = errors(source);
    if (e.samples == 0) {
      out += fmt::format("{:<24} {:>8}\n", name(source), 0);
      continue;
    }
    const auto degrees = [&](double rad) {
      return e.has_heading ? fmt::format("{:.2f}", rad * kDegPerRad) : std::string("-");
    };
    const std::string returned = std::isnan(e.return_to_start_m)
                                     ? std::string("-")
                                     : fmt::format("{:.1f}", e.return_to_start_m * 1e3);
    out += fmt::format("{:<24} {:>8} {:>11.1f} {:>11} {:>10.1f} {:>10} {:>13}\n", name(source),
                       e.samples, e.final_position_m * 1e3, degrees(e.final_heading_rad),
                       e.rms_position_m * 1e3, degrees(e.rms_heading_rad), returned);
  }
  return out;
}

void DistanceStudy::add(double distance_m, double position_error_m, double heading_error_rad) {
  const auto bin = static_cast<std::size_t>(std::max(0.0, std::floor(distance_m / bin_m_)));
  if (bins_.size() <= bin)
    bins_.resize(bin + 1);
  Bin& b = bins_[bin];
  ++b.poses;
  b.position2 += position_error_m * position_error_m;
  b.heading2 += heading_error_rad * heading_error_rad;
  b.worst_m = std::max(b.worst_m, position_error_m);
}

std::size_t DistanceStudy::poses() const {
  std::size_t n = 0;
  for (const Bin& b : bins_)
    n += b.poses;
  return n;
}

std::string DistanceStudy::table() const {
  std::string out = fmt::format("{:<20} {:>6} {:>10} {:>11} {:>18}\n", "nearest station (m)",
                                "poses", "RMS (mm)", "worst (mm)", "heading RMS (deg)");
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    const Bin& b = bins_[i];
    if (b.poses == 0)
      continue;
    const auto n = static_cast<double>(b.poses);
    out += fmt::format("{:<20} {:>6} {:>10.1f} {:>11.1f} {:>18.2f}\n",
                       fmt::format("{:.0f} to {:.0f}", static_cast<double>(i) * bin_m_,
                                   static_cast<double>(i + 1) * bin_m_),
                       b.poses, std::sqrt(b.position2 / n) * 1e3, b.worst_m * 1e3,
                       std::sqrt(b.heading2 / n) * kDegPerRad);
  }
  return out;
}

std::string update_summary(const sw::fuse::PoseEkf& filter) {
  std::string out = fmt::format("{:<18} {:>9} {:>9} {:>7} {:>8}\n", "filter update", "accepted",
                                "reopened", "gated", "refused");
  for (std::size_t i = 0; i < sw::fuse::kMeasurementTypes; ++i) {
    const auto type = static_cast<sw::fuse::MeasurementType>(i);
    const sw::fuse::TypeStats& s = filter.stats(type);
    if (s.accepted + s.reopened + s.gated + s.refused == 0)
      continue;
    out += fmt::format("{:<18} {:>9} {:>9} {:>7} {:>8}\n", sw::fuse::name(type), s.accepted,
                       s.reopened, s.gated, s.refused);
  }
  return out;
}

}  // namespace odoloc::sim
