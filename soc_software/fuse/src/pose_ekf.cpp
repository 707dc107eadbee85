// The pose EKF (pose_ekf.hpp, docs/fusion.md).
#include "odoloc/sw/pose_ekf.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace odoloc::sw::fuse {

namespace {

constexpr double kPi = std::numbers::pi;

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
// Clang 14 (the fuzz preset) deduces no aggregate's template arguments.
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

Eigen::Matrix2d rotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

bool positive(double sd) {
  return std::isfinite(sd) && sd > 0;
}

bool positive_definite(const Matrix2& c) {
  return c.allFinite() && c(0, 0) > 0 && c.determinant() > 0 &&
         std::abs(c(0, 1) - c(1, 0)) <= 1e-9 * (std::abs(c(0, 0)) + std::abs(c(1, 1)));
}

// Every value finite and every deviation or covariance positive.
bool well_formed(const Measurement& m) {
  return std::visit(
      Overloaded{
          [](const PositionFix& f) {
            return f.position_m.allFinite() && positive_definite(f.covariance_m2);
          },
          [](const BodyPointFix& f) {
            return f.body_point_m.allFinite() && f.position_m.allFinite() &&
                   positive_definite(f.covariance_m2);
          },
          [](const RangeSet& set) {
            return positive(set.offset_sd_m) &&
                   std::all_of(set.ranges.begin(), set.ranges.end(), [](const BeaconRange& r) {
                     return r.beacon_m.allFinite() && std::isfinite(r.height_m) &&
                            std::isfinite(r.distance_m) && positive(r.sd_m);
                   });
          },
          [](const HeadingFix& h) { return std::isfinite(h.heading_rad) && positive(h.sd_rad); },
          [](const StationBearing& b) {
            return b.station_m.allFinite() && std::isfinite(b.bearing_rad) && positive(b.sd_rad);
          },
          [](const StationRange& r) {
            return r.station_m.allFinite() && std::isfinite(r.height_m) &&
                   std::isfinite(r.distance_m) && positive(r.sd_m);
          },
          [](const RobotBearing& b) {
            return b.station_m.allFinite() && std::isfinite(b.bearing_rad) && positive(b.sd_rad);
          },
      },
      m);
}

// Below this (m, or m^2 for squared distances) a range or bearing has no
// direction: the robot stands on the station.
constexpr double kMinDistanceM = 1e-6;

bool is_absolute(Outcome o) {
  return o == Outcome::kAccepted || o == Outcome::kReopened;
}

}  // namespace

double wrap_angle(double rad) {
  if (!std::isfinite(rad))
    return rad;
  double w = std::remainder(rad, 2 * kPi);  // [-pi, pi]
  if (w <= -kPi)
    w += 2 * kPi;
  return w;
}

Vector3 increment_between(const Pose& from, const Pose& to) {
  const Vector2 d = rotation(from.heading()).transpose() * (to.position() - from.position());
  return {d.x(), d.y(), wrap_angle(to.heading() - from.heading())};
}

Pose compose(const Pose& pose, const Vector3& increment) {
  Pose out;
  out.x.head<2>() = pose.position() + rotation(pose.heading()) * increment.head<2>();
  out.x(2) = wrap_angle(pose.heading() + increment(2));
  return out;
}

double arc_length(const Vector3& increment) {
  const double chord = std::hypot(increment(0), increment(1));
  const double half_turn = increment(2) / 2;
  // sin(h)/h is 1 - h^2/6 to double precision below 1e-4 rad.
  const double chord_per_arc =
      std::abs(half_turn) < 1e-4 ? 1 - half_turn * half_turn / 6 : std::sin(half_turn) / half_turn;
  return std::copysign(chord / chord_per_arc, increment(0));
}

std::string_view name(MeasurementType type) {
  switch (type) {
    case MeasurementType::kPositionFix:
      return "position_fix";
    case MeasurementType::kBodyPointFix:
      return "body_point_fix";
    case MeasurementType::kBeaconRange:
      return "beacon_range";
    case MeasurementType::kHeading:
      return "heading";
    case MeasurementType::kStationBearing:
      return "station_bearing";
    case MeasurementType::kStationRange:
      return "station_range";
    case MeasurementType::kRobotBearing:
      return "robot_bearing";
  }
  return "?";
}

MeasurementType type_of(const Measurement& m) {
  static_assert(std::variant_size_v<Measurement> == kMeasurementTypes);
  return static_cast<MeasurementType>(m.index());
}

std::string_view name(Outcome outcome) {
  switch (outcome) {
    case Outcome::kAccepted:
      return "accepted";
    case Outcome::kReopened:
      return "reopened";
    case Outcome::kGated:
      return "gated";
    case Outcome::kNonFinite:
      return "non_finite";
    case Outcome::kTooLate:
      return "too_late";
    case Outcome::kNotInitialised:
      return "not_initialised";
    case Outcome::kDegenerate:
      return "degenerate";
    case Outcome::kAmbiguous:
      return "ambiguous";
  }
  return "?";
}

double chi_square_cdf(double x, int k) {
  if (k < 1)
    throw std::invalid_argument("chi_square_cdf: k must be >= 1");
  if (!(x > 0))
    return 0;
  // The upper tail Q(k) from Q(1) = erfc(sqrt(x/2)) or Q(2) = exp(-x/2) by
  // Q(j + 2) = Q(j) + (x/2)^(j/2) exp(-x/2) / Gamma(j/2 + 1).
  const double h = x / 2;
  int j = k % 2 == 1 ? 1 : 2;
  double q = j == 1 ? std::erfc(std::sqrt(h)) : std::exp(-h);
  for (; j < k; j += 2)
    q += std::exp(j / 2.0 * std::log(h) - h - std::lgamma(j / 2.0 + 1));
  return std::clamp(1 - q, 0.0, 1.0);
}

double chi_square_quantile(double probability, int k) {
  if (!(probability > 0 && probability < 1))
    throw std::invalid_argument("chi_square_quantile: probability must be in (0, 1)");
  double lo = 0, hi = 1;
  while (chi_square_cdf(hi, k) < probability)
    hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = (lo + hi) / 2;
    (chi_square_cdf(mid, k) < probability ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

void EkfOptions::validate() const {
  const auto require = [](bool ok, const char* field) {
    if (!ok)
      throw std::invalid_argument(std::string("EkfOptions: ") + field + " out of range");
  };
  const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0; };
  require(non_negative(odometry.along_sd_per_sqrt_m), "odometry.along_sd_per_sqrt_m");
  require(non_negative(odometry.across_sd_per_sqrt_m), "odometry.across_sd_per_sqrt_m");
  require(non_negative(odometry.heading_sd_per_sqrt_m), "odometry.heading_sd_per_sqrt_m");
  require(non_negative(odometry.heading_sd_per_sqrt_rad), "odometry.heading_sd_per_sqrt_rad");
  require(positive(odometry.floor_sd), "odometry.floor_sd (> 0)");
  require(gate.probability > 0 && gate.probability < 1, "gate.probability (0 < p < 1)");
  require(gate.reopen_after >= 1, "gate.reopen_after (>= 1)");
  require(non_negative(gate.reopen_after_s), "gate.reopen_after_s");
  require(non_negative(history_s), "history_s");
  require(positive(timeout_s), "timeout_s (> 0)");
  require(positive(min_variance), "min_variance (> 0)");
}

PoseEkf::PoseEkf(const EkfOptions& options) : options_(options) {
  options_.validate();
  for (int d = 1; d < static_cast<int>(gates_.size()); ++d)
    gates_[static_cast<std::size_t>(d)] = chi_square_quantile(options_.gate.probability, d);
}

double PoseEkf::gate(int dimension) const {
  if (dimension < 1 || dimension >= static_cast<int>(gates_.size()))
    throw std::invalid_argument("PoseEkf::gate: dimension must be 1 to 4");
  return gates_[static_cast<std::size_t>(dimension)];
}

void PoseEkf::initialise(double time_s, const Pose& pose, const Matrix3& covariance) {
  if (!std::isfinite(time_s) || !pose.x.allFinite())
    throw std::invalid_argument("PoseEkf::initialise: time and pose must be finite");
  const Eigen::LLT<Matrix3> llt(covariance);
  if (!covariance.allFinite() || !covariance.isApprox(covariance.transpose(), 1e-9) ||
      llt.info() != Eigen::Success) {
    throw std::invalid_argument(
        "PoseEkf::initialise: covariance must be symmetric positive definite");
  }
  state_.x = pose.x;
  state_.x(2) = wrap_angle(state_.x(2));
  state_.P = covariance;
  condition(state_.P);
  time_s_ = time_s;
  last_absolute_s_ = time_s;
  history_.clear();
  for (TypeStats& s : stats_)
    s.rejected_in_row = 0;
  initialised_ = true;
}

Outcome PoseEkf::predict(double time_s, const Increment& increment) {
  if (!std::isfinite(time_s) || !increment.d.allFinite())
    return Outcome::kNonFinite;
  if (!initialised_)
    return Outcome::kNotInitialised;
  return insert(time_s, increment);
}

Outcome PoseEkf::update(double time_s, const Measurement& measurement) {
  const MeasurementType type = type_of(measurement);
  Outcome refused = Outcome::kAccepted;
  if (!std::isfinite(time_s) || !well_formed(measurement))
    refused = Outcome::kNonFinite;
  else if (!initialised_)
    refused = Outcome::kNotInitialised;
  if (refused != Outcome::kAccepted) {
    ++stats_[static_cast<std::size_t>(type)].refused;
    return refused;
  }
  return insert(time_s, measurement);
}

Outcome PoseEkf::insert(double time_s, const Input& input) {
  if (time_s < time_s_ - options_.history_s) {
    if (const auto* m = std::get_if<Measurement>(&input))
      ++stats_[static_cast<std::size_t>(type_of(*m))].refused;
    return Outcome::kTooLate;
  }
  // After every input of the same or an earlier time.
  const auto at = std::upper_bound(history_.begin(), history_.end(), time_s,
                                   [](double t, const Step& s) { return t < s.time_s; });
  State s = at == history_.end() ? state_ : at->before;
  const State before = s;
  const Outcome outcome = apply(s, time_s, input, nullptr);
  auto next = history_.insert(at, Step{time_s, input, before, outcome});
  for (++next; next != history_.end(); ++next) {  // the inputs after it, again
    next->before = s;
    apply(s, next->time_s, next->input, &next->first);
  }
  state_ = s;
  time_s_ = std::max(time_s_, time_s);
  while (!history_.empty() && history_.front().time_s < time_s_ - options_.history_s)
    history_.pop_front();
  return outcome;
}

Outcome PoseEkf::apply(State& s, double time_s, const Input& input, const Outcome* replaying) {
  last_time_s_ = time_s;
  if (const auto* m = std::get_if<Measurement>(&input))
    return fuse(s, *m, replaying);
  const Vector3& d = std::get<Increment>(input).d;
  const OdometryNoise& n = options_.odometry;
  const double theta = s.x(2);
  const double c = std::cos(theta), sn = std::sin(theta);
  Matrix3 F = Matrix3::Identity();
  F(0, 2) = -sn * d.x() - c * d.y();
  F(1, 2) = c * d.x() - sn * d.y();
  Matrix3 G = Matrix3::Identity();
  G.topLeftCorner<2, 2>() = rotation(theta);
  const double distance = std::hypot(d.x(), d.y());
  const double floor = n.floor_sd * n.floor_sd;
  const Vector3 q{n.along_sd_per_sqrt_m * n.along_sd_per_sqrt_m * distance + floor,
                  n.across_sd_per_sqrt_m * n.across_sd_per_sqrt_m * distance + floor,
                  n.heading_sd_per_sqrt_m * n.heading_sd_per_sqrt_m * distance +
                      n.heading_sd_per_sqrt_rad * n.heading_sd_per_sqrt_rad * std::abs(d.z()) +
                      floor};
  s.x = compose(Pose{s.x}, d).x;
  s.P = F * s.P * F.transpose() + G * q.asDiagonal() * G.transpose();
  condition(s.P);
  return Outcome::kAccepted;
}

Outcome PoseEkf::fuse(State& s, const Measurement& m, const Outcome* replaying) {
  using V1 = Eigen::Matrix<double, 1, 1>;
  using H1 = Eigen::Matrix<double, 1, 3>;
  const Vector2 p = s.x.head<2>();
  const double theta = s.x(2);
  const auto scalar = [&](MeasurementType type, double nu, const H1& H, double sd) {
    return correct<3, 1>(s.x, s.P, type, V1(nu), H, V1(sd * sd), replaying);
  };
  return std::visit(
      Overloaded{
          [&](const PositionFix& f) {
            Eigen::Matrix<double, 2, 3> H = Eigen::Matrix<double, 2, 3>::Zero();
            H.leftCols<2>().setIdentity();
            return correct<3, 2>(s.x, s.P, MeasurementType::kPositionFix, Vector2(f.position_m - p),
                                 H, f.covariance_m2, replaying);
          },
          [&](const BodyPointFix& f) {
            const Vector2 predicted = p + rotation(theta) * f.body_point_m;
            Eigen::Matrix<double, 2, 3> H = Eigen::Matrix<double, 2, 3>::Zero();
            H.leftCols<2>().setIdentity();
            // d/dtheta of R(theta) o: R(theta + pi/2) o.
            H.col(2) = rotation(theta + kPi / 2) * f.body_point_m;
            return correct<3, 2>(s.x, s.P, MeasurementType::kBodyPointFix,
                                 Vector2(f.position_m - predicted), H, f.covariance_m2, replaying);
          },
          [&](const RangeSet& set) { return fuse_range_set(s, set, replaying); },
          [&](const HeadingFix& h) {
            return scalar(MeasurementType::kHeading, wrap_angle(h.heading_rad - theta), H1(0, 0, 1),
                          h.sd_rad);
          },
          [&](const StationBearing& b) {
            const Vector2 e = p - b.station_m;
            const double r2 = e.squaredNorm();
            if (r2 < kMinDistanceM * kMinDistanceM) {
              record(MeasurementType::kStationBearing, Outcome::kDegenerate, 0, replaying);
              return Outcome::kDegenerate;
            }
            const double predicted = std::atan2(e.y(), e.x());
            return scalar(MeasurementType::kStationBearing, wrap_angle(b.bearing_rad - predicted),
                          H1(-e.y() / r2, e.x() / r2, 0), b.sd_rad);
          },
          [&](const StationRange& r) {
            const Vector2 e = p - r.station_m;
            const double rho = std::sqrt(e.squaredNorm() + r.height_m * r.height_m);
            if (rho < kMinDistanceM) {
              record(MeasurementType::kStationRange, Outcome::kDegenerate, 0, replaying);
              return Outcome::kDegenerate;
            }
            return scalar(MeasurementType::kStationRange, r.distance_m - rho,
                          H1(e.x() / rho, e.y() / rho, 0), r.sd_m);
          },
          [&](const RobotBearing& b) {
            const Vector2 e = b.station_m - p;
            const double r2 = e.squaredNorm();
            if (r2 < kMinDistanceM * kMinDistanceM) {
              record(MeasurementType::kRobotBearing, Outcome::kDegenerate, 0, replaying);
              return Outcome::kDegenerate;
            }
            const double predicted = std::atan2(e.y(), e.x()) - theta;
            return scalar(MeasurementType::kRobotBearing, wrap_angle(b.bearing_rad - predicted),
                          H1(e.y() / r2, -e.x() / r2, -1), b.sd_rad);
          },
      },
      m);
}

Outcome PoseEkf::fuse_range_set(State& s, const RangeSet& set, const Outcome* replaying) {
  constexpr auto kType = static_cast<std::size_t>(MeasurementType::kBeaconRange);
  const State prior = s;
  const Outcome outcome = fuse_ranges(s, set, replaying);
  // This set's rejection is already counted in the run (fuse_ranges).
  const bool reopen = replaying != nullptr
                          ? *replaying == Outcome::kReopened
                          : outcome == Outcome::kGated && run_ends(MeasurementType::kBeaconRange,
                                                                   stats_[kType].rejected_in_row);
  if (!reopen)
    return outcome;
  // Back in after a run of rejected sets: the position's prior is
  // discredited. Its variance grows by offset_sd_m^2 and its correlation
  // with the heading is dropped (ranges do not see the heading), and the
  // set is fused again from its own result until the position settles: an
  // iterated EKF from a wide prior, the data used once per pass.
  Matrix3 wide = prior.P;
  wide.topLeftCorner<2, 2>() += Matrix2::Identity() * set.offset_sd_m * set.offset_sd_m;
  wide.block<2, 1>(0, 2).setZero();
  wide.block<1, 2>(2, 0).setZero();
  static constexpr Outcome kQuiet = Outcome::kAccepted;  // gated, not counted
  s = prior;
  for (int pass = 0; pass < 10; ++pass) {
    State again{s.x, wide};
    fuse_ranges(again, set, &kQuiet);
    const double moved = (again.x.head<2>() - s.x.head<2>()).norm();
    s = again;
    if (moved < 1e-4)
      break;
  }
  record(MeasurementType::kBeaconRange, Outcome::kReopened, 0, replaying);
  if (replaying == nullptr)
    stats_[kType].rejected_in_row = 0;
  return Outcome::kReopened;
}

Outcome PoseEkf::fuse_ranges(State& s, const RangeSet& set, const Outcome* replaying) {
  constexpr MeasurementType kType = MeasurementType::kBeaconRange;
  if (set.ranges.empty()) {
    record(kType, Outcome::kDegenerate, 0, replaying);
    return Outcome::kDegenerate;
  }
  using Vector4 = Eigen::Vector4d;
  using Matrix4 = Eigen::Matrix4d;
  // The robot origin at the range's capture time, minus the beacon.
  const auto beacon_to_robot = [](const Vector4& x, const BeaconRange& r) -> Vector2 {
    return x.head<2>() + rotation(x(2)) * r.motion_m - r.beacon_m;
  };
  const auto predicted_range = [&](const Vector4& x, const BeaconRange& r) {
    return std::sqrt(beacon_to_robot(x, r).squaredNorm() + r.height_m * r.height_m);
  };
  Vector4 x;
  x << s.x, 0;
  // The offset's prior: each beacon's measured minus predicted range, with
  // its variance from the position's uncertainty and the range's noise. The
  // direct paths agree on one offset, and an echo only ever adds its detour:
  // the prior is the smallest offset another one agrees with within 3 sigma
  // (the earliest consistent pair; without a pair, the smallest), and its
  // range the reference. Echoes off one wall may agree with each other, but
  // they come later than the direct paths.
  const std::size_t n = set.ranges.size();
  std::vector<double> offsets(n), variances(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BeaconRange& r = set.ranges[i];
    const double rho = predicted_range(x, r);
    const Vector2 g = rho < kMinDistanceM ? Vector2::Zero() : Vector2(beacon_to_robot(x, r) / rho);
    offsets[i] = r.distance_m - rho;
    variances[i] = g.dot(s.P.topLeftCorner<2, 2>() * g) + r.sd_m * r.sd_m;
  }
  std::size_t prior = 0;
  bool paired = false;
  for (std::size_t i = 0; i < n; ++i) {
    bool agrees = false;
    for (std::size_t j = 0; j < n; ++j)
      agrees |=
          j != i && std::abs(offsets[i] - offsets[j]) <= 3 * std::sqrt(variances[i] + variances[j]);
    if ((agrees && !paired) || (agrees == paired && offsets[i] < offsets[prior])) {
      paired = agrees;
      prior = i;
    }
  }
  x(3) = offsets[prior];
  Matrix4 P = Matrix4::Zero();
  P.topLeftCorner<3, 3>() = s.P;
  P(3, 3) = set.offset_sd_m * set.offset_sd_m;
  // One range's residual and Jacobian at the running estimate (false: the
  // robot stands on the beacon, no direction).
  const auto linearise = [&](const BeaconRange& r, double& nu, Eigen::Matrix<double, 1, 4>& H) {
    const double rho = predicted_range(x, r);
    if (rho < kMinDistanceM)
      return false;
    const Vector2 e = beacon_to_robot(x, r);
    // d(R(theta) m)/dtheta = R(theta + pi/2) m.
    const Vector2 turn = rotation(x(2) + kPi / 2) * r.motion_m;
    H << e.x() / rho, e.y() / rho, e.dot(turn) / rho, 1;
    nu = r.distance_m - rho - x(3);
    return true;
  };
  // The reference first; then, each time, the range that fits best (the
  // smallest NIS at the running estimate), so the direct paths settle the
  // pose before any echo is looked at.
  std::vector<std::size_t> left;
  for (std::size_t i = 0; i < n; ++i)
    if (i != prior)
      left.push_back(i);
  int fused = 0;  // ranges fused, the reference included
  int passed = 0, gated = 0;
  for (std::size_t next = prior;;) {
    const BeaconRange& r = set.ranges[next];
    double nu = 0;
    Eigen::Matrix<double, 1, 4> H;
    if (linearise(r, nu, H)) {
      // The first range fused pins the offset: with the offset's prior so
      // wide it says next to nothing about the pose (it is the reference of
      // the differences, a TDoA filter's anchor), so it is neither gated nor
      // counted. n ranges are n - 1 measurements.
      const bool pins_offset = fused++ == 0;
      const Outcome o =
          correct<4, 1>(x, P, kType, Eigen::Matrix<double, 1, 1>(nu), H,
                        Eigen::Matrix<double, 1, 1>(r.sd_m * r.sd_m), replaying, pins_offset);
      if (!pins_offset)
        (o == Outcome::kGated ? gated : passed) += 1;
    }
    if (left.empty())
      break;
    auto best = left.begin();
    double best_nis = std::numeric_limits<double>::infinity();
    for (auto it = left.begin(); it != left.end(); ++it) {
      double nu_i = 0;
      Eigen::Matrix<double, 1, 4> H_i;
      if (!linearise(set.ranges[*it], nu_i, H_i)) {
        best = it;  // no direction: dropped next, whatever the others
        break;
      }
      const double S =
          (H_i * P * H_i.transpose())(0, 0) + set.ranges[*it].sd_m * set.ranges[*it].sd_m;
      if (nu_i * nu_i / S < best_nis) {
        best_nis = nu_i * nu_i / S;
        best = it;
      }
    }
    next = *best;
    left.erase(best);
  }
  // The set is a rejection when more of its ranges were gated than fused.
  if (replaying == nullptr && fused >= 2) {
    if (gated > passed)
      count_rejection(kType);
    else
      stats_[static_cast<std::size_t>(kType)].rejected_in_row = 0;
  }
  if (fused < 2) {  // no range, or the reference alone: nothing about the pose
    record(kType, Outcome::kDegenerate, 0, replaying);
    return Outcome::kDegenerate;
  }
  s.x = x.head<3>();
  s.P = P.topLeftCorner<3, 3>();
  condition(s.P);
  return gated > passed ? Outcome::kGated : Outcome::kAccepted;
}

template <int N, int Rows>
Outcome PoseEkf::correct(Eigen::Matrix<double, N, 1>& x, Eigen::Matrix<double, N, N>& P,
                         MeasurementType type, const Eigen::Matrix<double, Rows, 1>& nu,
                         const Eigen::Matrix<double, Rows, N>& H,
                         const Eigen::Matrix<double, Rows, Rows>& R, const Outcome* replaying,
                         bool ungated) {
  using MatrixR = Eigen::Matrix<double, Rows, Rows>;
  const auto nis_of = [&](const Eigen::Matrix<double, N, N>& P_, MatrixR& S) {
    S = H * P_ * H.transpose() + R;
    return nu.dot(S.ldlt().solve(nu));
  };
  MatrixR S;
  double nis = nis_of(P, S);
  if (!std::isfinite(nis)) {
    record(type, Outcome::kDegenerate, 0, replaying);
    return Outcome::kDegenerate;
  }
  Outcome outcome = Outcome::kAccepted;
  const double limit = gates_[Rows];
  if (options_.gate.enabled && !ungated && nis > limit) {
    // A range set reopens as a whole (fuse_range_set), not range by range.
    const bool reopen =
        type != MeasurementType::kBeaconRange &&
        (replaying != nullptr
             ? *replaying == Outcome::kReopened
             : run_ends(type, stats_[static_cast<std::size_t>(type)].rejected_in_row + 1));
    if (!reopen) {
      record(type, Outcome::kGated, nis, replaying);
      return Outcome::kGated;
    }
    // Back in: the variances of the states this measurement sees (the
    // columns of H it uses) grow, their correlations kept, until it is one
    // sigma from the prediction (NIS <= its dimension: the discredited prior
    // no longer holds it back); the others stay (a range does not unsettle
    // the heading). The run ends here, so the rest of a range set meets the
    // gate again.
    Eigen::Matrix<double, N, 1> grow = Eigen::Matrix<double, N, 1>::Ones();
    for (int j = 0; j < N; ++j)
      if (H.col(j).cwiseAbs().maxCoeff() > 0)
        grow(j) = std::sqrt(2.0);
    for (int i = 0; i < 200 && nis > Rows; ++i) {
      P = grow.asDiagonal() * P * grow.asDiagonal();
      nis = nis_of(P, S);
    }
    outcome = Outcome::kReopened;
    if (replaying == nullptr)
      stats_[static_cast<std::size_t>(type)].rejected_in_row = 0;
  }
  const Eigen::Matrix<double, N, Rows> K = P * H.transpose() * S.inverse();
  x += K * nu;
  x(2) = wrap_angle(x(2));
  const Eigen::Matrix<double, N, N> IKH = Eigen::Matrix<double, N, N>::Identity() - K * H;
  P = IKH * P * IKH.transpose() + K * R * K.transpose();  // Joseph form: stays symmetric PSD
  condition(P);
  if (!ungated)
    record(type, outcome, nis, replaying);
  return outcome;
}

template <int N>
void PoseEkf::condition(Eigen::Matrix<double, N, N>& P) const {
  P = (0.5 * (P + P.transpose())).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(P);
  if (eig.info() == Eigen::Success && eig.eigenvalues().minCoeff() >= options_.min_variance)
    return;
  const Eigen::Matrix<double, N, 1> floored = eig.eigenvalues().cwiseMax(options_.min_variance);
  P = eig.eigenvectors() * floored.asDiagonal() * eig.eigenvectors().transpose();
}

void PoseEkf::record(MeasurementType type, Outcome outcome, double nis, const Outcome* replaying) {
  if (is_absolute(outcome))
    last_absolute_s_ = std::max(last_absolute_s_, last_time_s_);
  if (replaying != nullptr)
    return;
  const auto i = static_cast<std::size_t>(type);
  TypeStats& st = stats_[i];
  // A range set's run of rejections is counted per set (fuse_ranges): a
  // pair of beacons whose difference a wrong pose happens to fit would
  // otherwise end every run.
  const bool per_set = type == MeasurementType::kBeaconRange;
  switch (outcome) {
    case Outcome::kAccepted:
    case Outcome::kReopened:
      ++(outcome == Outcome::kAccepted ? st.accepted : st.reopened);
      if (!per_set)
        st.rejected_in_row = 0;
      st.last_nis = nis;
      break;
    case Outcome::kGated:
      if (!per_set)
        count_rejection(type);
      ++st.gated;
      st.last_nis = nis;
      break;
    default:
      ++st.refused;
      break;
  }
}

bool PoseEkf::run_ends(MeasurementType type, int rejections) const {
  return rejections > options_.gate.reopen_after &&
         last_time_s_ - rejected_since_[static_cast<std::size_t>(type)] >=
             options_.gate.reopen_after_s;
}

void PoseEkf::count_rejection(MeasurementType type) {
  const auto i = static_cast<std::size_t>(type);
  if (stats_[i].rejected_in_row++ == 0)
    rejected_since_[i] = last_time_s_;
}

Estimate PoseEkf::estimate() const {
  Estimate e;
  e.time_s = time_s_;
  e.pose.x = state_.x;
  e.covariance = state_.P;
  e.initialised = initialised_;
  e.last_absolute_s = last_absolute_s_;
  e.odometry_only =
      !initialised_ || last_absolute_s_ < 0 || time_s_ - last_absolute_s_ > options_.timeout_s;
  return e;
}

}  // namespace odoloc::sw::fuse
