#include "odoloc/sw/thamma_pose.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "odoloc/sw/detail/config_checks.hpp"
#include "odoloc/sw/tof_doa.hpp"

namespace odoloc::sw::locate {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Used stations within this of one line are collinear: the reflection
// across it fits every range equally (BeaconLayout keeps beacons 1 mm apart).
constexpr double kCollinearTolerance = 1e-3;  // metres

Eigen::Vector2d vec(Vec2 p) {
  return {p.x, p.y};
}
Vec2 point(const Eigen::Vector2d& v) {
  return {v.x(), v.y()};
}
Eigen::Vector2d station(const BeaconLayout& stations, int beacon) {
  return vec(stations.beacons[static_cast<std::size_t>(beacon)].position_m);
}

// Two circles' intersections (the triangle of Thamma's steps 1-5 and 9 in
// vector form): with e the unit vector c1 -> c2 at distance a, the vertex is
// at c1 + xi e +- eta n, xi = (a^2 + r1^2 - r2^2) / (2a) (law of cosines),
// eta = sqrt(r1^2 - xi^2) (the height, 2 Area / a by Heron), n = e turned
// +90 degrees: left of c1 -> c2 (Thamma's vertex after his rotation).
struct CircleIntersection {
  bool intersect = false;
  Eigen::Vector2d left, right;
  double gap_m = 0;  // no intersection: how far the circles miss each other
};
CircleIntersection intersect_circles(const Eigen::Vector2d& c1, double r1,
                                     const Eigen::Vector2d& c2, double r2) {
  CircleIntersection out;
  const Eigen::Vector2d e = (c2 - c1).normalized();
  const double a = (c2 - c1).norm();
  const double xi = (a * a + (r1 - r2) * (r1 + r2)) / (2 * a);
  const double eta2 = (r1 - xi) * (r1 + xi);
  if (eta2 < 0) {
    out.gap_m = std::max(a - r1 - r2, std::abs(r1 - r2) - a);
    return out;
  }
  const Eigen::Vector2d n(-e.y(), e.x());
  const double eta = std::sqrt(eta2);
  out.intersect = true;
  out.left = c1 + xi * e + eta * n;
  out.right = c1 + xi * e - eta * n;
  return out;
}

// Range model d(P) = sqrt(|P - b|^2 + h^2) and its gradient in P.
double model_range(const BeaconLayout& stations, int beacon, const Eigen::Vector2d& p,
                   Eigen::Vector2d* gradient = nullptr) {
  const double h = stations.beacons[static_cast<std::size_t>(beacon)].height_m;
  const Eigen::Vector2d delta = p - station(stations, beacon);
  const double d = std::sqrt(delta.squaredNorm() + h * h);
  if (gradient != nullptr)
    *gradient = d > 0 ? Eigen::Vector2d(delta / d) : Eigen::Vector2d::Zero();
  return d;
}

// J^T W J, J^T W r and chi^2 of the observations at p.
struct Normal {
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d unit_information = Eigen::Matrix2d::Zero();  // W = I (HDOP)
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  double chi2 = 0;
};
Normal normal_equations(const BeaconLayout& stations, std::span<const Observation> obs,
                        const Eigen::Vector2d& p) {
  Normal n;
  for (const Observation& o : obs) {
    Eigen::Vector2d g;
    const double r = o.distance_m - model_range(stations, o.beacon, p, &g);
    const double w = 1 / (o.sd_m * o.sd_m);
    n.information += w * g * g.transpose();
    n.unit_information += g * g.transpose();
    n.gradient += w * r * g;
    n.chi2 += w * r * r;
  }
  return n;
}

// The inverse of a 2x2 information matrix, or nothing when it is singular
// (relative to its size: the ranges do not constrain one direction).
std::optional<Eigen::Matrix2d> invert(const Eigen::Matrix2d& information) {
  const double scale = information.trace();
  if (!(scale > 0) || !(information.determinant() > 1e-12 * scale * scale))
    return std::nullopt;
  return information.inverse();
}

double chi2_of(const BeaconLayout& stations, std::span<const Observation> obs,
               const Eigen::Vector2d& p) {
  return normal_equations(stations, obs, p).chi2;
}

// Which of two candidate positions: the one whose chi^2 is lower by more
// than one unit, else the one nearer the stations' hull (inside: 0); as near
// as each other within kHullTieTolerance (both inside, or a hull too thin to
// tell): ambiguous, the mirror kept.
constexpr double kHullTieTolerance = 1e-3;  // metres
struct Side {
  Eigen::Vector2d position;
  std::optional<Eigen::Vector2d> mirror;  // set when ambiguous
};
Side choose_side(const BeaconLayout& stations, const Eigen::Vector2d& a, double chi2_a,
                 const Eigen::Vector2d& b, double chi2_b) {
  if (std::abs(chi2_a - chi2_b) > 1)
    return {chi2_a < chi2_b ? a : b, std::nullopt};
  const double out_a = stations.distance_outside_hull_m(point(a));
  const double out_b = stations.distance_outside_hull_m(point(b));
  if (std::abs(out_a - out_b) > kHullTieTolerance)
    return {out_a < out_b ? a : b, std::nullopt};
  return {a, b};
}

// The line through the used stations when they are collinear: a point on
// it and its unit direction.
struct Line {
  Eigen::Vector2d origin, direction;
};
std::optional<Line> collinear(const BeaconLayout& stations, std::span<const Observation> obs) {
  const Eigen::Vector2d a = station(stations, obs.front().beacon);
  Eigen::Vector2d far = a;
  for (const Observation& o : obs)
    if ((station(stations, o.beacon) - a).norm() > (far - a).norm())
      far = station(stations, o.beacon);
  const Eigen::Vector2d u = (far - a).normalized();
  for (const Observation& o : obs) {
    const Eigen::Vector2d d = station(stations, o.beacon) - a;
    if (std::abs(u.x() * d.y() - u.y() * d.x()) > kCollinearTolerance)
      return std::nullopt;
  }
  return Line{a, u};
}

Eigen::Vector2d reflect(const Line& line, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = p - line.origin;
  return line.origin + 2 * d.dot(line.direction) * line.direction - d;
}

// Shared preparation: the fix's bookkeeping and the usable ranges.
Fix begin(const BeaconLayout& stations, const RangeSet& ranges, const ThammaOptions& options,
          Solver solver, Prepared& prepared) {
  stations.validate();
  options.validate();
  Fix fix;
  fix.solver = solver;
  fix.offset_m = 0;  // RF-synchronised: no common offset
  fix.offset_sd_m = 0;
  fix.speed_of_sound_mps = ranges.speed_of_sound_mps;
  prepared = prepare(stations, ranges, options.min_sd_m);
  fix.beacons = prepared.uses;
  if (prepared.primaries.size() < 2)
    fix.reason = prepared.any_non_finite && prepared.primaries.empty()
                     ? NoFixReason::kNonFiniteInput
                     : NoFixReason::kTooFewBeacons;
  return fix;
}

// Fills the fix at p from the `used` observations (the others of `all` are
// kUnused): covariance, HDOP, residuals, chi^2, and the verdict.
void finish(Fix& fix, const BeaconLayout& stations, std::span<const Observation> all,
            std::span<const Observation> used, const Side& side, const ThammaOptions& options) {
  const Eigen::Vector2d p = side.position;
  fix.position_m = point(p);
  if (side.mirror)
    fix.mirror_m = point(*side.mirror);
  const Normal n = normal_equations(stations, used, p);
  const std::optional<Eigen::Matrix2d> covariance = invert(n.information);
  const std::optional<Eigen::Matrix2d> unit = invert(n.unit_information);
  for (const Observation& o : all) {
    BeaconUse& use = fix.beacons[static_cast<std::size_t>(o.beacon)];
    use.residual_m = o.distance_m - model_range(stations, o.beacon, p);
    const bool in_fit = std::any_of(used.begin(), used.end(),
                                    [&](const Observation& u) { return u.beacon == o.beacon; });
    use.status = in_fit ? BeaconStatus::kUsed : BeaconStatus::kUnused;
  }
  fix.chi2 = n.chi2;
  fix.dof = static_cast<int>(used.size()) - 2;
  if (!covariance || !unit) {
    fix.reason = NoFixReason::kDegenerateGeometry;
    return;
  }
  fix.covariance_m2 = *covariance;
  fix.hdop = std::sqrt(unit->trace());
  const double k = options.gate_sigmas;
  // On (or within the noise of) the line through collinear stations the
  // two mirror solutions merge: no side, no lateral position.
  if (const std::optional<Line> line = collinear(stations, used)) {
    const Eigen::Vector2d normal(-line->direction.y(), line->direction.x());
    const double distance = std::abs(normal.dot(p - line->origin));
    if (distance <= k * std::sqrt(normal.dot(*covariance * normal))) {
      fix.reason = NoFixReason::kDegenerateGeometry;
      return;
    }
  }
  if (side.mirror) {
    fix.reason = NoFixReason::kMirrorAmbiguous;
    return;
  }
  // Studentised residuals: r_i / sqrt(sd_i^2 - g_i^T Cov g_i).
  if (fix.dof >= 1) {
    for (const Observation& o : used) {
      Eigen::Vector2d g;
      const double r = o.distance_m - model_range(stations, o.beacon, p, &g);
      const double var = o.sd_m * o.sd_m - g.dot(*covariance * g);
      if (var > 0 && std::abs(r) > k * std::sqrt(var)) {
        fix.reason = NoFixReason::kInconsistent;
        return;
      }
    }
  }
  if (stations.distance_outside_hull_m(fix.position_m) > options.max_outside_hull_m) {
    fix.reason = NoFixReason::kOutsideHull;
    return;
  }
  fix.valid = true;
  fix.reason = NoFixReason::kNone;
}

// The first repeat's receiver among those in the box's mean; -1: none.
int first_channel(const tof::ThammaBoxResult& box) {
  for (const tof::ThammaRepeat& r : box.repeats)
    if (std::isfinite(r.tof_s) && !r.flags.has(tof::Flag::kOutlier) && r.channel >= 0)
      return r.channel;
  return -1;
}

Eigen::Matrix2d rotation(double theta) {
  return Eigen::Rotation2Dd(theta).toRotationMatrix();
}

using detail::require;

}  // namespace

void ThammaOptions::validate() const {
  require(std::isfinite(min_sd_m) && min_sd_m > 0, "ThammaOptions",
          "min_sd_m must be finite and positive");
  require(max_iterations >= 1, "ThammaOptions", "max_iterations must be at least 1");
  require(std::isfinite(step_tolerance_m) && step_tolerance_m > 0, "ThammaOptions",
          "step_tolerance_m must be finite and positive");
  require(max_outside_hull_m >= 0, "ThammaOptions", "max_outside_hull_m must not be negative");
  require(std::isfinite(gate_sigmas) && gate_sigmas > 0, "ThammaOptions",
          "gate_sigmas must be finite and positive");
}

void ThammaBody::validate() const {
  require(std::isfinite(head_m.x) && std::isfinite(head_m.y) && std::isfinite(tail_m.x) &&
              std::isfinite(tail_m.y),
          "ThammaBody", "head_m and tail_m must be finite");
  require(std::hypot(head_m.x - tail_m.x, head_m.y - tail_m.y) >= 1e-3, "ThammaBody",
          "head_m and tail_m must be at least 1 mm apart");
  require(head_box >= 0 && tail_box >= 0 && head_box != tail_box, "ThammaBody",
          "head_box and tail_box must be two different box indices");
  if (!receivers.receivers.empty())
    receivers.validate();
}

void ThammaPoseOptions::validate() const {
  fix.validate();
  require(max_passes >= 1, "ThammaPoseOptions", "max_passes must be at least 1");
  require(std::isfinite(heading_tolerance_rad) && heading_tolerance_rad > 0, "ThammaPoseOptions",
          "heading_tolerance_rad must be finite and positive");
  require(std::isfinite(separation_sigmas) && separation_sigmas > 0, "ThammaPoseOptions",
          "separation_sigmas must be finite and positive");
  require(min_repeats >= 1, "ThammaPoseOptions", "min_repeats must be at least 1");
}

std::string_view name(ThammaPoseReason reason) {
  switch (reason) {
    case ThammaPoseReason::kNone:
      return "none";
    case ThammaPoseReason::kNoHeadFix:
      return "no_head_fix";
    case ThammaPoseReason::kNoTailFix:
      return "no_tail_fix";
    case ThammaPoseReason::kSeparationMismatch:
      return "separation_mismatch";
  }
  return "?";
}

Fix thamma_trilateration(const BeaconLayout& stations, const RangeSet& ranges,
                         const ThammaOptions& options) {
  Prepared prepared;
  Fix fix = begin(stations, ranges, options, Solver::kThammaTrilateration, prepared);
  const std::vector<Observation>& obs = prepared.primaries;
  if (obs.size() < 2)
    return fix;
  // The base: of the pairs whose circles cross, the one with the smallest
  // two-range covariance (the most square crossing).
  struct Base {
    std::size_t i = 0, j = 0;
    CircleIntersection crossing;
    double trace = kInf;
  };
  std::optional<Base> base;
  double least_gap_sigmas = kInf;
  for (std::size_t i = 0; i < obs.size(); ++i)
    for (std::size_t j = i + 1; j < obs.size(); ++j) {
      const auto planar = [&](const Observation& o) {
        const double h = stations.beacons[static_cast<std::size_t>(o.beacon)].height_m;
        return std::sqrt(std::max(0.0, (o.distance_m - h) * (o.distance_m + h)));
      };
      const CircleIntersection c =
          intersect_circles(station(stations, obs[i].beacon), planar(obs[i]),
                            station(stations, obs[j].beacon), planar(obs[j]));
      if (!c.intersect) {
        least_gap_sigmas =
            std::min(least_gap_sigmas, c.gap_m / std::hypot(obs[i].sd_m, obs[j].sd_m));
        continue;
      }
      const std::array<Observation, 2> pair{obs[i], obs[j]};
      const std::optional<Eigen::Matrix2d> cov =
          invert(normal_equations(stations, pair, c.left).information);
      const double trace = cov ? cov->trace() : kInf;
      if (!base || trace < base->trace)
        base = Base{i, j, c, trace};
    }
  if (!base) {
    // Tangent within the noise: the robot on the stations' line.
    fix.reason = least_gap_sigmas <= options.gate_sigmas ? NoFixReason::kDegenerateGeometry
                                                         : NoFixReason::kInconsistent;
    return fix;
  }
  const std::array<Observation, 2> pair{obs[base->i], obs[base->j]};
  std::vector<Observation> others;
  for (std::size_t k = 0; k < obs.size(); ++k)
    if (k != base->i && k != base->j)
      others.push_back(obs[k]);
  const Side side =
      choose_side(stations, base->crossing.left, chi2_of(stations, others, base->crossing.left),
                  base->crossing.right, chi2_of(stations, others, base->crossing.right));
  finish(fix, stations, obs, pair, side, options);
  return fix;
}

Fix thamma_least_squares(const BeaconLayout& stations, const RangeSet& ranges,
                         const ThammaOptions& options) {
  Prepared prepared;
  Fix fix = begin(stations, ranges, options, Solver::kThammaLeastSquares, prepared);
  const std::vector<Observation>& obs = prepared.primaries;
  if (obs.size() < 2)
    return fix;
  const Fix start = thamma_trilateration(stations, ranges, options);
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  if (std::isfinite(start.position_m.x) && std::isfinite(start.position_m.y)) {
    p = vec(start.position_m);
  } else {
    for (const Beacon& b : stations.beacons)
      p += vec(b.position_m);
    p /= static_cast<double>(stations.beacons.size());
  }
  bool converged = false;
  for (int it = 0; it < options.max_iterations && !converged; ++it) {
    const Normal n = normal_equations(stations, obs, p);
    const std::optional<Eigen::Matrix2d> cov = invert(n.information);
    if (!cov)
      break;
    // Gauss-Newton step, halved while it raises chi^2.
    Eigen::Vector2d step = *cov * n.gradient;
    for (int halving = 0; halving < 30 && chi2_of(stations, obs, p + step) > n.chi2; ++halving)
      step /= 2;
    p += step;
    fix.iterations = it + 1;
    converged = step.norm() < options.step_tolerance_m;
  }
  if (!converged) {
    fix.reason = invert(normal_equations(stations, obs, p).information)
                     ? NoFixReason::kNotConverged
                     : NoFixReason::kDegenerateGeometry;
    fix.position_m = point(p);
    return fix;
  }
  const double chi2 = chi2_of(stations, obs, p);
  const std::optional<Line> line = collinear(stations, obs);
  const Side side =
      line ? choose_side(stations, p, chi2, reflect(*line, p), chi2) : Side{p, std::nullopt};
  finish(fix, stations, obs, obs, side, options);
  return fix;
}

RangeSet box_ranges(std::span<const tof::ThammaMeasurement> per_station, int box,
                    double speed_of_sound_mps) {
  RangeSet set;
  set.speed_of_sound_mps = speed_of_sound_mps;
  for (const tof::ThammaMeasurement& m : per_station) {
    BeaconRange range;
    range.flags = m.flags;
    if (box >= 0 && static_cast<std::size_t>(box) < m.boxes.size()) {
      const tof::ThammaBoxResult& b = m.boxes[static_cast<std::size_t>(box)];
      range.candidates.push_back({b.distance_m, b.distance_sd_m, b.flags});
      range.primary = 0;
    } else {
      range.flags.set(tof::Flag::kMissing);
    }
    set.beacons.push_back(std::move(range));
  }
  return set;
}

ThammaPose thamma_pose(const BeaconLayout& stations,
                       std::span<const tof::ThammaMeasurement> per_station, const ThammaBody& body,
                       const ThammaPoseOptions& options, const ThammaMotion& motion) {
  stations.validate();
  body.validate();
  options.validate();
  for (const std::vector<Vec2>* m : {&motion.head, &motion.tail})
    if (!m->empty() && m->size() != per_station.size())
      throw std::invalid_argument("thamma_pose: a motion per station, or none");
  const auto heard = [&](int box) {
    RangeSet set = box_ranges(per_station, box);
    for (std::size_t s = 0; s < per_station.size(); ++s)
      if (per_station[s].boxes[static_cast<std::size_t>(box)].used < options.min_repeats)
        set.beacons[s].flags.set(tof::Flag::kMissing);
    return set;
  };
  const RangeSet head_ranges = heard(body.head_box);
  const RangeSet tail_ranges = heard(body.tail_box);
  const auto solve = options.least_squares ? thamma_least_squares : thamma_trilateration;
  // The receiver that heard station s, relative to the box's reference
  // point (body frame; zero when unknown), plus where the box was then.
  const auto offsets = [&](int box, Vec2 reference, const std::vector<Vec2>& moved_by) {
    std::vector<Eigen::Vector2d> out(per_station.size(), Eigen::Vector2d::Zero());
    for (std::size_t s = 0; s < per_station.size(); ++s) {
      if (!moved_by.empty())
        out[s] = vec(moved_by[s]);
      if (static_cast<std::size_t>(box) >= per_station[s].boxes.size())
        continue;
      const int ch = first_channel(per_station[s].boxes[static_cast<std::size_t>(box)]);
      if (ch >= 0 && static_cast<std::size_t>(ch) < body.receivers.receivers.size())
        out[s] +=
            vec(body.receivers.receivers[static_cast<std::size_t>(ch)].position_m) - vec(reference);
    }
    return out;
  };
  const std::vector<Eigen::Vector2d> head_offsets =
      offsets(body.head_box, body.head_m, motion.head);
  const std::vector<Eigen::Vector2d> tail_offsets =
      offsets(body.tail_box, body.tail_m, motion.tail);
  const bool any_offset = std::any_of(head_offsets.begin(), head_offsets.end(),
                                      [](const Eigen::Vector2d& o) { return !o.isZero(); }) ||
                          std::any_of(tail_offsets.begin(), tail_offsets.end(),
                                      [](const Eigen::Vector2d& o) { return !o.isZero(); });
  // |P + R(theta) o - b| = d  <=>  |P - (b - R(theta) o)| = d.
  const auto moved = [&](const std::vector<Eigen::Vector2d>& o, double theta) {
    BeaconLayout out = stations;
    const Eigen::Matrix2d r = rotation(theta);
    for (std::size_t s = 0; s < out.beacons.size() && s < o.size(); ++s)
      out.beacons[s].position_m = point(vec(out.beacons[s].position_m) - r * o[s]);
    return out;
  };

  ThammaPose pose;
  const Eigen::Vector2d body_head = vec(body.head_m);
  const Eigen::Vector2d body_tail = vec(body.tail_m);
  const Eigen::Vector2d body_axis = body_head - body_tail;
  const double body_angle = std::atan2(body_axis.y(), body_axis.x());
  const auto heading_of = [&](const Fix& head, const Fix& tail) {
    const Eigen::Vector2d v = vec(head.position_m) - vec(tail.position_m);
    return tof::angle_difference(std::atan2(v.y(), v.x()), body_angle);
  };
  // The heading is a fixed point theta = F(theta) (F: fixes with the
  // offsets turned by theta, then their heading), contracting by about the
  // offsets over the separation per pass; secant steps after the second
  // pass make it superlinear. Pass 0 ignores the offsets.
  // Pass 0 does not know where on its box each range ends: up to the
  // farthest receiver from the box's reference point, which it takes as
  // each range's uncertainty (a fix a few centimetres off, to start from).
  const auto unplaced = [](RangeSet ranges, const std::vector<Eigen::Vector2d>& o) {
    double reach = 0;
    for (const Eigen::Vector2d& v : o)
      reach = std::max(reach, v.norm());
    for (BeaconRange& b : ranges.beacons)
      for (RangeCandidate& c : b.candidates)
        c.sd_m = std::hypot(c.sd_m, reach);
    return ranges;
  };
  const RangeSet head_unplaced = unplaced(head_ranges, head_offsets);
  const RangeSet tail_unplaced = unplaced(tail_ranges, tail_offsets);
  double theta = 0, previous_theta = 0, previous_f = kNaN;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    const bool shift = pass > 0;
    pose.head = shift ? solve(moved(head_offsets, theta), head_ranges, options.fix)
                      : solve(stations, head_unplaced, options.fix);
    pose.tail = shift ? solve(moved(tail_offsets, theta), tail_ranges, options.fix)
                      : solve(stations, tail_unplaced, options.fix);
    pose.passes = pass + 1;
    if (!any_offset || !std::isfinite(pose.head.position_m.x) ||
        !std::isfinite(pose.tail.position_m.x))
      break;
    const double heading = heading_of(pose.head, pose.tail);
    if (!shift) {
      theta = heading;
      continue;
    }
    const double f = tof::angle_difference(heading, theta);
    if (std::abs(f) < options.heading_tolerance_rad)
      break;
    double next = heading;
    if (std::isfinite(previous_f) && f != previous_f)
      next = theta - f * tof::angle_difference(theta, previous_theta) / (f - previous_f);
    previous_theta = theta, previous_f = f;
    theta = tof::angle_difference(next, 0);
  }
  if (!pose.head.valid || !pose.tail.valid) {
    pose.reason = !pose.head.valid ? ThammaPoseReason::kNoHeadFix : ThammaPoseReason::kNoTailFix;
    return pose;
  }

  // theta = atan2(h - t) - atan2(body axis); dtheta = g^T d(h - t),
  // g = (-v_y, v_x)/|v|^2. Origin P = (h + t)/2 - R(theta) m, m the body
  // midpoint: dP = (dh + dt)/2 - R'(theta) m dtheta.
  const Eigen::Vector2d h = vec(pose.head.position_m);
  const Eigen::Vector2d t = vec(pose.tail.position_m);
  const Eigen::Vector2d v = h - t;
  pose.separation_m = v.norm();
  pose.separation_error_m = pose.separation_m - body_axis.norm();
  if (!(pose.separation_m > 0)) {  // both fixes at one point: no direction at all
    pose.reason = ThammaPoseReason::kSeparationMismatch;
    return pose;
  }
  const Eigen::Vector2d g = Eigen::Vector2d(-v.y(), v.x()) / v.squaredNorm();
  const Eigen::Vector2d m = (body_head + body_tail) / 2;
  pose.heading_rad = heading_of(pose.head, pose.tail);
  const Eigen::Vector2d rm = rotation(pose.heading_rad) * m;
  const Eigen::Vector2d drm(-rm.y(), rm.x());  // dR(theta)m/dtheta
  pose.position_m = point((h + t) / 2 - rm);
  Eigen::Matrix<double, 3, 4> jacobian;
  jacobian.topLeftCorner<2, 2>() = Eigen::Matrix2d::Identity() / 2 - drm * g.transpose();
  jacobian.topRightCorner<2, 2>() = Eigen::Matrix2d::Identity() / 2 + drm * g.transpose();
  jacobian.bottomLeftCorner<1, 2>() = g.transpose();
  jacobian.bottomRightCorner<1, 2>() = -g.transpose();
  Eigen::Matrix4d inputs = Eigen::Matrix4d::Zero();
  inputs.topLeftCorner<2, 2>() = pose.head.covariance_m2;
  inputs.bottomRightCorner<2, 2>() = pose.tail.covariance_m2;
  pose.covariance = jacobian * inputs * jacobian.transpose();
  pose.heading_sd_rad = std::sqrt(pose.covariance(2, 2));
  // The separation: |v| against the body's, sd along v.
  const Eigen::Vector2d u = v.normalized();
  pose.separation_sd_m = std::sqrt(u.dot((pose.head.covariance_m2 + pose.tail.covariance_m2) * u));
  if (std::abs(pose.separation_error_m) > options.separation_sigmas * pose.separation_sd_m) {
    pose.reason = ThammaPoseReason::kSeparationMismatch;
    return pose;
  }
  pose.valid = true;
  pose.reason = ThammaPoseReason::kNone;
  return pose;
}

}  // namespace odoloc::sw::locate
