#include "odoloc/sw/kleeman_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>

#include "odoloc/sw/detail/config_checks.hpp"
#include "odoloc/sw/multilateration.hpp"

namespace odoloc::sw::locate {
namespace {

using Vec2d = Eigen::Vector2d;
using Sensitivity = Eigen::Matrix<double, 2, Eigen::Dynamic>;

constexpr double kInf = std::numeric_limits<double>::infinity();
// Three beacons this close to one line (sine of the angle at b0) have
// mirror-symmetric hyperbolas: no unique fix anywhere.
constexpr double kCollinearSine = 1e-6;

Vec2d eigen(Vec2 p) {
  return {p.x, p.y};
}
Vec2 vec2(const Vec2d& p) {
  return {p(0), p(1)};
}

using detail::finite_non_negative;
using detail::finite_positive;
using detail::require;

// The difference operator D: (d1 - d0, d2 - d1) = D (d0, d1, d2).
TripleSensitivity difference_operator() {
  TripleSensitivity d;
  d << -1, 1, 0, 0, -1, 1;
  return d;
}

struct TripleGeometry {
  std::array<Vec2d, 3> b;
  std::array<double, 3> h2;  // squared heights above the receivers' plane
};

TripleGeometry geometry(const BeaconLayout& layout, const Triple& beacons) {
  TripleGeometry geo;
  for (std::size_t i = 0; i < 3; ++i) {
    const int n = beacons[i];
    if (n < 0 || static_cast<std::size_t>(n) >= layout.beacons.size())
      throw std::invalid_argument("kleeman: beacon " + std::to_string(n) + " is not in the layout");
    for (std::size_t j = 0; j < i; ++j)
      if (beacons[j] == n)
        throw std::invalid_argument("kleeman: beacon " + std::to_string(n) +
                                    " appears twice in the triple");
    const Beacon& b = layout.beacons[static_cast<std::size_t>(n)];
    geo.b[i] = eigen(b.position_m);
    geo.h2[i] = b.height_m * b.height_m;
  }
  return geo;
}

bool collinear(const TripleGeometry& geo) {
  const Vec2d a1 = geo.b[1] - geo.b[0];
  const Vec2d a2 = geo.b[2] - geo.b[0];
  const double cross = a1(0) * a2(1) - a1(1) * a2(0);
  return std::abs(cross) < kCollinearSine * a1.norm() * a2.norm();
}

// The ranges r_i(P) and the Jacobian J of (r1 - r0, r2 - r1): rows g1 - g0,
// g2 - g1 with g_i = (P - b_i)/r_i.
struct Linearisation {
  std::array<double, 3> r;
  Eigen::Matrix2d j;
};

Linearisation linearise(const TripleGeometry& geo, const Vec2d& p) {
  Linearisation l;
  std::array<Vec2d, 3> g;
  for (std::size_t i = 0; i < 3; ++i) {
    const Vec2d d = p - geo.b[i];
    l.r[i] = std::sqrt(d.squaredNorm() + geo.h2[i]);
    g[i] = d / l.r[i];
  }
  l.j.row(0) = (g[1] - g[0]).transpose();
  l.j.row(1) = (g[2] - g[1]).transpose();
  return l;
}

// Cramer's rule for J x = rhs (the derived eq. 4); nullopt when |det J| is
// below min_determinant or not a number, never a division by ~0.
std::optional<Vec2d> cramer(const Eigen::Matrix2d& j, const Vec2d& rhs, double min_determinant) {
  const double det = j(0, 0) * j(1, 1) - j(0, 1) * j(1, 0);
  if (!(std::abs(det) >= min_determinant))
    return std::nullopt;
  return Vec2d((rhs(0) * j(1, 1) - j(0, 1) * rhs(1)) / det,
               (j(0, 0) * rhs(1) - j(1, 0) * rhs(0)) / det);
}

std::optional<TripleSensitivity> sensitivity_at(const TripleGeometry& geo, const Vec2d& p,
                                                double min_determinant) {
  const Linearisation l = linearise(geo, p);
  const TripleSensitivity d = difference_operator();
  TripleSensitivity s;
  for (int k = 0; k < 3; ++k) {
    const std::optional<Vec2d> column = cramer(l.j, d.col(k), min_determinant);
    if (!column)
      return std::nullopt;
    s.col(k) = *column;
  }
  return s;
}

// One run of the eq. 4 iteration towards the measured differences m.
struct Run {
  Vec2d p;
  int iterations = 0;  // steps taken
  NoFixReason reason = NoFixReason::kNotConverged;
};

Run iterate(const TripleGeometry& geo, const Vec2d& m, const Vec2d& start,
            const TripleOptions& options) {
  Run run{start};
  while (run.iterations < options.max_iterations) {
    const Linearisation l = linearise(geo, run.p);
    const Vec2d residual(m(0) - (l.r[1] - l.r[0]), m(1) - (l.r[2] - l.r[1]));
    const std::optional<Vec2d> step = cramer(l.j, residual, options.min_determinant);
    if (!step || !step->allFinite()) {
      run.reason = NoFixReason::kDegenerateGeometry;
      return run;
    }
    run.p += *step;
    ++run.iterations;
    if (step->norm() < options.tolerance_m) {
      run.reason = NoFixReason::kNone;
      return run;
    }
  }
  return run;
}

// Position, covariance, hdop, offset and chi^2 of a fix at p that is the
// linear function m (2 x obs, metres per metre) of the distances of obs; the
// offset and chi^2 are taken over the used observations. Returns every
// observation's residual d - o - r(p).
std::vector<double> fill_statistics(const BeaconLayout& layout, std::span<const Observation> obs,
                                    const std::vector<bool>& used, const Sensitivity& m,
                                    const Vec2d& p, Fix& fix) {
  const auto n = static_cast<Eigen::Index>(obs.size());
  Eigen::VectorXd variance(n);
  Eigen::VectorXd range(n);
  Eigen::RowVectorXd used_row = Eigen::RowVectorXd::Zero(n);
  Vec2d sum_g = Vec2d::Zero();  // sum of dr_i/dP over the used observations
  double sum_d_minus_r = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Observation& o = obs[static_cast<std::size_t>(j)];
    const Beacon& b = layout.beacons[static_cast<std::size_t>(o.beacon)];
    variance(j) = o.sd_m * o.sd_m;
    range(j) = layout.range_m(static_cast<std::size_t>(o.beacon), vec2(p));
    if (used[static_cast<std::size_t>(j)]) {
      used_row(j) = 1;
      sum_g += (p - eigen(b.position_m)) / range(j);
      sum_d_minus_r += o.distance_m - range(j);
    }
  }
  const double n_used = used_row.sum();
  fix.position_m = vec2(p);
  fix.covariance_m2 = m * variance.asDiagonal() * m.transpose();
  fix.hdop = std::sqrt((m * m.transpose()).trace());
  fix.offset_m = sum_d_minus_r / n_used;
  // o = mean over the used of (d_i - r_i(P(d))): do/dd = (1_used - sum_g^T M)/n_used.
  const Eigen::RowVectorXd offset_gradient = (used_row - sum_g.transpose() * m) / n_used;
  fix.offset_sd_m = std::sqrt(offset_gradient.cwiseAbs2().dot(variance));
  std::vector<double> residuals(obs.size());
  fix.chi2 = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Observation& o = obs[static_cast<std::size_t>(j)];
    const double r = o.distance_m - fix.offset_m - range(j);
    residuals[static_cast<std::size_t>(j)] = r;
    if (used[static_cast<std::size_t>(j)])
      fix.chi2 += r * r / variance(j);
  }
  fix.dof = static_cast<int>(n_used) - 3;
  return residuals;
}

Vec2 centroid(const BeaconLayout& layout) {
  Vec2d sum = Vec2d::Zero();
  for (const Beacon& b : layout.beacons)
    sum += eigen(b.position_m);
  return vec2(sum / static_cast<double>(layout.beacons.size()));
}

bool same_beacons(const std::vector<Beacon>& a, const std::vector<Beacon>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const Beacon& x, const Beacon& y) {
    return x.position_m == y.position_m && x.height_m == y.height_m;
  });
}

}  // namespace

// ------------------------------------------------------ three-beacon solver

void TripleOptions::validate() const {
  constexpr const char* kOwner = "TripleOptions";
  require(finite_positive(tolerance_m), kOwner, "tolerance_m must be finite and positive");
  require(max_iterations >= 1 && max_iterations <= 1000, kOwner, "max_iterations must be 1..1000");
  require(finite_positive(min_determinant), kOwner, "min_determinant must be finite and positive");
  require(max_outside_hull_m >= 0, kOwner, "max_outside_hull_m must be at least 0");
  require(finite_positive(mirror_separation_m), kOwner,
          "mirror_separation_m must be finite and positive");
  require(mirror_decision_ratio > 0 && mirror_decision_ratio < 1, kOwner,
          "mirror_decision_ratio must be within (0, 1)");
  require(finite_positive(min_sd_m), kOwner, "min_sd_m must be finite and positive");
}

std::optional<Vec2> kleeman_step(const BeaconLayout& layout, const Triple& beacons, Vec2 p_m,
                                 const std::array<double, 2>& difference_change_m,
                                 double min_determinant) {
  const Linearisation l = linearise(geometry(layout, beacons), eigen(p_m));
  const std::optional<Vec2d> step =
      cramer(l.j, Vec2d(difference_change_m[0], difference_change_m[1]), min_determinant);
  return step ? std::optional<Vec2>(vec2(*step)) : std::nullopt;
}

std::optional<TripleSensitivity> triple_sensitivity(const BeaconLayout& layout,
                                                    const Triple& beacons, Vec2 p_m,
                                                    double min_determinant) {
  return sensitivity_at(geometry(layout, beacons), eigen(p_m), min_determinant);
}

Fix solve_triple(const BeaconLayout& layout, const std::array<Observation, 3>& observations,
                 Vec2 start_m, const TripleOptions& options) {
  layout.validate();
  options.validate();
  const Triple beacons{observations[0].beacon, observations[1].beacon, observations[2].beacon};
  const TripleGeometry geo = geometry(layout, beacons);

  Fix fix;
  fix.solver = Solver::kKleemanTriple;
  std::array<Observation, 3> obs = observations;
  bool finite = std::isfinite(start_m.x) && std::isfinite(start_m.y);
  for (Observation& o : obs) {
    fix.beacons.push_back({o.beacon, BeaconStatus::kUsed, o.candidate});
    finite = finite && std::isfinite(o.distance_m) && std::isfinite(o.sd_m);
    o.sd_m = std::max(o.sd_m, options.min_sd_m);
  }
  const auto fail = [&fix](NoFixReason reason) {
    fix.reason = reason;
    return fix;
  };
  if (!finite)
    return fail(NoFixReason::kNonFiniteInput);
  if (collinear(geo))
    return fail(NoFixReason::kDegenerateGeometry);

  const Vec2d m(obs[1].distance_m - obs[0].distance_m, obs[2].distance_m - obs[1].distance_m);
  const Vec2d start = eigen(start_m);
  // Both intersections in closed form (all ranges valid), nearest to start first.
  const TripleSolutions closed =
      solve_triple_closed_form(layout, std::span<const Observation, 3>(obs));
  std::vector<Vec2d> roots;
  for (int k = 0; k < closed.count; ++k)
    roots.push_back(eigen(closed.solutions[static_cast<std::size_t>(k)].position_m));
  std::sort(roots.begin(), roots.end(), [&](const Vec2d& a, const Vec2d& b) {
    return (a - start).norm() < (b - start).norm();
  });

  Run run = iterate(geo, m, start, options);
  // J singular on the way (a start on a beacon baseline's extension): restart
  // from the intersections, so that only a singular solution ends here.
  for (std::size_t k = 0; run.reason == NoFixReason::kDegenerateGeometry && k < roots.size(); ++k)
    run = iterate(geo, m, roots[k], options);
  if (run.reason != NoFixReason::kNone)
    return fail(run.reason);

  // The other intersection: the root furthest from the solution, polished.
  std::optional<Run> mirror;
  const auto furthest = std::max_element(
      roots.begin(), roots.end(),
      [&](const Vec2d& a, const Vec2d& b) { return (a - run.p).norm() < (b - run.p).norm(); });
  if (furthest != roots.end() && (*furthest - run.p).norm() > options.mirror_separation_m) {
    Run polished = iterate(geo, m, *furthest, options);
    if (polished.reason != NoFixReason::kNone)
      polished = {*furthest, 0, NoFixReason::kNone};
    if ((polished.p - run.p).norm() > options.mirror_separation_m)
      mirror = polished;
  }

  const auto within_hull = [&](const Vec2d& p) {
    return layout.distance_outside_hull_m(vec2(p)) <= options.max_outside_hull_m;
  };
  if (mirror) {
    const bool run_ok = within_hull(run.p);
    const bool mirror_ok = within_hull(mirror->p);
    const double to_run = (run.p - start).norm();
    const double to_mirror = (mirror->p - start).norm();
    if (mirror_ok && (!run_ok || to_mirror < to_run))
      std::swap(run, *mirror);
    fix.mirror_m = vec2(mirror->p);
    fix.iterations = run.iterations;
    if (run_ok && mirror_ok &&
        std::min(to_run, to_mirror) > options.mirror_decision_ratio * std::max(to_run, to_mirror)) {
      fix.position_m = vec2(run.p);
      return fail(NoFixReason::kMirrorAmbiguous);
    }
  }
  fix.iterations = run.iterations;  // of the iteration that gave position_m
  if (!within_hull(run.p)) {
    fix.position_m = vec2(run.p);
    return fail(NoFixReason::kOutsideHull);
  }
  const std::optional<TripleSensitivity> s = sensitivity_at(geo, run.p, options.min_determinant);
  if (!s)
    return fail(NoFixReason::kDegenerateGeometry);

  const std::vector<double> residuals =
      fill_statistics(layout, obs, std::vector<bool>(3, true), *s, run.p, fix);
  for (std::size_t i = 0; i < 3; ++i)
    fix.beacons[i].residual_m = residuals[i];
  fix.valid = true;
  fix.reason = NoFixReason::kNone;
  return fix;
}

namespace {
// Kleeman 4.3 against a fix: a measurement can only be too long, so one
// shorter than the fix predicts by more than the triangle check's tolerance
// (its timing and survey terms, with the fix's own scatter) refutes the fix.
bool too_short(double residual_m, double sd_m, double position_sd_m,
               const TriangleOptions& tolerance) {
  return residual_m <
         -(tolerance.sigma_factor * std::hypot(sd_m, position_sd_m) + tolerance.margin_m);
}
}  // namespace

Fix solve_triple(const BeaconLayout& layout, const RangeSet& ranges, const Triple& beacons,
                 Vec2 start_m, const TripleOptions& options) {
  layout.validate();
  options.validate();
  geometry(layout, beacons);  // throws on a bad triple
  const Prepared prepared = prepare(layout, ranges, options.min_sd_m);
  std::vector<BeaconUse> uses = prepared.uses;
  for (BeaconUse& u : uses)
    if (u.status == BeaconStatus::kUsed) {
      u.status = BeaconStatus::kUnused;
      u.candidate = -1;
    }

  std::array<Observation, 3> obs;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto it = std::find_if(prepared.primaries.begin(), prepared.primaries.end(),
                                 [&](const Observation& o) { return o.beacon == beacons[k]; });
    if (it != prepared.primaries.end()) {
      obs[k] = *it;
      continue;
    }
    Fix fix;
    fix.solver = Solver::kKleemanTriple;
    fix.speed_of_sound_mps = ranges.speed_of_sound_mps;
    const auto b = static_cast<std::size_t>(beacons[k]);
    fix.reason = b < uses.size() && uses[b].status == BeaconStatus::kNonFinite
                     ? NoFixReason::kNonFiniteInput
                     : NoFixReason::kTooFewBeacons;
    fix.beacons = std::move(uses);
    return fix;
  }
  Fix fix = solve_triple(layout, obs, start_m, options);
  for (const BeaconUse& u : fix.beacons)
    uses[static_cast<std::size_t>(u.beacon)] = u;
  // The beacons left out, measured against the fix: three beacons check
  // nothing, so their residuals are the only sign of a wrong one, and one
  // that is too short refutes the fix (an echo is among the three).
  if (std::isfinite(fix.position_m.x) && std::isfinite(fix.position_m.y)) {
    const double position_sd = fix.valid ? std::sqrt(fix.covariance_m2.trace()) : 0.0;
    for (const Observation& o : prepared.primaries) {
      BeaconUse& u = uses[static_cast<std::size_t>(o.beacon)];
      if (u.status != BeaconStatus::kUnused)
        continue;
      u.residual_m = o.distance_m -
                     layout.range_m(static_cast<std::size_t>(o.beacon), fix.position_m) -
                     fix.offset_m;
      if (fix.valid && !o.suspect && too_short(u.residual_m, o.sd_m, position_sd, {})) {
        fix.valid = false;
        fix.reason = NoFixReason::kInconsistent;
      }
    }
  }
  fix.beacons = std::move(uses);
  fix.speed_of_sound_mps = ranges.speed_of_sound_mps;
  return fix;
}

// ------------------------------------------------- triangle inequality

void TriangleOptions::validate() const {
  constexpr const char* kOwner = "TriangleOptions";
  require(finite_non_negative(sigma_factor), kOwner, "sigma_factor must be finite and >= 0");
  require(finite_non_negative(baseline_fraction), kOwner,
          "baseline_fraction must be finite and >= 0");
  require(finite_non_negative(margin_m), kOwner, "margin_m must be finite and >= 0");
}

std::vector<BeaconUse> check_triangle_inequality(const BeaconLayout& layout,
                                                 const Prepared& prepared,
                                                 const TriangleOptions& options) {
  layout.validate();
  options.validate();
  std::vector<BeaconUse> uses = prepared.uses;
  std::vector<double> worst(uses.size(), 0.0);  // largest violation so far, per beacon
  const std::vector<Observation>& obs = prepared.primaries;
  for (std::size_t i = 0; i < obs.size(); ++i)
    for (std::size_t j = i + 1; j < obs.size(); ++j) {
      const bool i_longer = obs[i].distance_m > obs[j].distance_m;
      const Observation& longer = i_longer ? obs[i] : obs[j];
      const Observation& shorter = i_longer ? obs[j] : obs[i];
      const Beacon& a = layout.beacons[static_cast<std::size_t>(longer.beacon)];
      const Beacon& b = layout.beacons[static_cast<std::size_t>(shorter.beacon)];
      const double baseline = std::hypot(a.position_m.x - b.position_m.x,
                                         a.position_m.y - b.position_m.y, a.height_m - b.height_m);
      const double tolerance = options.sigma_factor * std::hypot(longer.sd_m, shorter.sd_m) +
                               options.baseline_fraction * baseline + options.margin_m;
      const double excess = longer.distance_m - shorter.distance_m - baseline - tolerance;
      const auto n = static_cast<std::size_t>(longer.beacon);
      if (excess > worst[n]) {
        worst[n] = excess;
        uses[n].status = BeaconStatus::kTriangleInequality;
        uses[n].rejected_by = shorter.beacon;
        uses[n].candidate = -1;
      }
    }
  return uses;
}

// ------------------------------------------------------------- longsolve

void LongsolveOptions::validate() const {
  constexpr const char* kOwner = "LongsolveOptions";
  triple.validate();
  triangle.validate();
  require(averaged_triples >= 1, kOwner, "averaged_triples must be at least 1");
  require(max_uses_per_beacon >= 1, kOwner, "max_uses_per_beacon must be at least 1");
  require(finite_non_negative(reestimate_distance_m), kOwner,
          "reestimate_distance_m must be finite and >= 0");
  require(min_triples >= 1, kOwner, "min_triples must be at least 1");
  require(min_beacons >= 3, kOwner, "min_beacons must be at least 3");
  require(finite_positive(deviation_factor), kOwner,
          "deviation_factor must be finite and positive");
}

Longsolve::Longsolve(const LongsolveOptions& options) : options_(options) {
  options_.validate();
}

void Longsolve::reset() {
  layout_.clear();
  last_fix_.reset();
  best_.reset();
  estimated_at_.reset();
  estimations_ = 0;
  sensitivities_.clear();
  averaged_.clear();
}

void Longsolve::estimate_at(Vec2 p) {
  estimated_at_ = p;
  ++estimations_;
  sensitivities_.clear();
}

const std::optional<TripleSensitivity>& Longsolve::sensitivity(const BeaconLayout& layout,
                                                               const Triple& triple) {
  auto it = sensitivities_.find(triple);
  if (it == sensitivities_.end())
    it = sensitivities_
             .emplace(triple, triple_sensitivity(layout, triple, *estimated_at_,
                                                 options_.triple.min_determinant))
             .first;
  return it->second;
}

namespace {

// One triple of longsolve.
struct Candidate {
  Triple beacons;                  // ascending
  std::array<std::size_t, 3> obs;  // indices into the primaries
  double error_m = kInf;           // DRMS at the estimation point
  std::optional<Fix> fix{};        // its solution, once one was found
  bool failed = false;             // tried and no fix (outside the hull, mirror, ...)
};

// Steps 3 and 4 over the candidates in `order` (least error first), without
// the triples of beacon observation `excluded`.
enum class Role : std::uint8_t { kOut, kAveraged, kDropped };
struct Average {
  std::vector<std::size_t> used;  // candidates averaged, least error first
  std::vector<Role> roles;        // per candidate
  Vec2d point = Vec2d::Zero();
  bool consistent = false;  // no averaged triple deviates
};

template <typename Solve>
Average average_triples(std::vector<Candidate>& candidates, const std::vector<std::size_t>& order,
                        std::size_t observations, std::optional<std::size_t> excluded,
                        const LongsolveOptions& options, Solve&& solve) {
  Average out;
  out.roles.assign(candidates.size(), Role::kOut);
  std::vector<int> uses(observations, 0);
  if (excluded)
    uses[*excluded] = options.max_uses_per_beacon;
  const auto point = [&](std::size_t c) { return eigen(candidates[c].fix->position_m); };
  for (;;) {
    // Step 3: fill up with the next best triples that keep every beacon
    // within its uses, and average them with weights 1/error.
    for (const std::size_t c : order) {
      if (out.used.size() >= static_cast<std::size_t>(options.averaged_triples))
        break;
      Candidate& t = candidates[c];
      const bool fits = std::all_of(t.obs.begin(), t.obs.end(), [&](std::size_t o) {
        return uses[o] < options.max_uses_per_beacon;
      });
      if (out.roles[c] != Role::kOut || !fits || !solve(t))
        continue;
      out.roles[c] = Role::kAveraged;
      out.used.push_back(c);
      for (const std::size_t o : t.obs)
        ++uses[o];
    }
    if (out.used.empty())
      return out;
    out.point.setZero();
    double weights = 0;
    for (const std::size_t c : out.used) {
      out.point += point(c) / candidates[c].error_m;
      weights += 1 / candidates[c].error_m;
    }
    out.point /= weights;
    // Step 4: of the triples further from the average than their expected
    // error allows, drop the furthest, until none or min_triples are left.
    std::optional<std::size_t> worst;
    double worst_deviation = 0;
    for (std::size_t u = 0; u < out.used.size(); ++u) {
      const double deviation = (point(out.used[u]) - out.point).norm();
      if (deviation > options.deviation_factor * candidates[out.used[u]].error_m &&
          deviation > worst_deviation) {
        worst = u;
        worst_deviation = deviation;
      }
    }
    out.consistent = !worst;
    if (out.consistent || out.used.size() <= static_cast<std::size_t>(options.min_triples))
      break;
    const std::size_t c = out.used[*worst];
    out.roles[c] = Role::kDropped;
    for (const std::size_t o : candidates[c].obs)
      --uses[o];
    out.used.erase(out.used.begin() + static_cast<std::ptrdiff_t>(*worst));
  }
  std::stable_sort(out.used.begin(), out.used.end(), [&](std::size_t a, std::size_t b) {
    return candidates[a].error_m < candidates[b].error_m;
  });
  return out;
}

double total_weight(const std::vector<Candidate>& candidates, const Average& a) {
  double w = 0;
  for (const std::size_t c : a.used)
    w += 1 / candidates[c].error_m;
  return w;
}

// The primaries that passed the triangle check.
std::vector<std::size_t> usable_primaries(const std::vector<Observation>& obs,
                                          const std::vector<BeaconUse>& uses) {
  std::vector<std::size_t> valid;
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (uses[static_cast<std::size_t>(obs[i].beacon)].status == BeaconStatus::kUsed)
      valid.push_back(i);
  return valid;
}

// Why fewer than `needed` primaries are usable.
NoFixReason too_few_reason(std::size_t primaries, const std::vector<BeaconUse>& uses,
                           std::size_t needed) {
  const auto non_finite = static_cast<std::size_t>(std::ranges::count_if(
      uses, [](const BeaconUse& u) { return u.status == BeaconStatus::kNonFinite; }));
  return primaries >= needed                ? NoFixReason::kInconsistent
         : primaries + non_finite >= needed ? NoFixReason::kNonFiniteInput
                                            : NoFixReason::kTooFewBeacons;
}

// Every triple of the usable primaries.
std::vector<Candidate> all_triples(const std::vector<Observation>& obs,
                                   const std::vector<std::size_t>& valid) {
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < valid.size(); ++i)
    for (std::size_t j = i + 1; j < valid.size(); ++j)
      for (std::size_t k = j + 1; k < valid.size(); ++k) {
        Candidate t;
        t.beacons = {obs[valid[i]].beacon, obs[valid[j]].beacon, obs[valid[k]].beacon};
        t.obs = {valid[i], valid[j], valid[k]};
        candidates.push_back(std::move(t));
      }
  return candidates;
}

// Each candidate's DRMS error from its sensitivity (sensitivity_of(triple):
// nullopt where singular); the candidates with a finite error, least first.
template <class SensitivityOf>
std::vector<std::size_t> rank(std::vector<Candidate>& candidates,
                              const std::vector<Observation>& obs, SensitivityOf&& sensitivity_of) {
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    Candidate& t = candidates[c];
    const std::optional<TripleSensitivity>& s = sensitivity_of(t.beacons);
    double variance = kInf;
    if (s) {
      variance = 0;
      for (int k = 0; k < 3; ++k) {
        const double sd = obs[t.obs[static_cast<std::size_t>(k)]].sd_m;
        variance += sd * sd * s->col(k).squaredNorm();
      }
    }
    t.error_m = std::sqrt(variance);
    if (std::isfinite(t.error_m))
      order.push_back(c);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return candidates[a].error_m < candidates[b].error_m;
  });
  return order;
}

// Solves a candidate's triple (eq. 4) once, from the first start asked;
// counts the iterations and remembers the first failure's reason.
class TripleSolves {
 public:
  TripleSolves(const BeaconLayout& layout, const std::vector<Observation>& obs,
               const TripleOptions& options, int& iterations)
      : layout_(layout), obs_(obs), options_(options), iterations_(iterations) {}
  bool operator()(Candidate& t, Vec2 from) {
    if (!t.fix) {
      const std::array<Observation, 3> three{obs_[t.obs[0]], obs_[t.obs[1]], obs_[t.obs[2]]};
      Fix f = solve_triple(layout_, three, from, options_);
      iterations_ += f.iterations;
      if (f.valid) {
        t.fix = std::move(f);
      } else {
        t.failed = true;
        if (!first_failure_)
          first_failure_ = f.reason;
      }
    }
    return t.fix.has_value();
  }
  [[nodiscard]] NoFixReason failure() const {
    return first_failure_.value_or(NoFixReason::kDegenerateGeometry);
  }

 private:
  const BeaconLayout& layout_;
  const std::vector<Observation>& obs_;
  const TripleOptions& options_;
  int& iterations_;
  std::optional<NoFixReason> first_failure_;
};

// Steps 3 and 4. When they end with deviants, the paper's loop has met a
// bad beacon whose triples outnumber the good ones among the best (it can be
// in max_uses_per_beacon of averaged_triples): repeat without each usable
// measurement in turn and keep the consistent average with the most triples
// (then the most weight), at least min_triples of them (fewer would not show
// it consistent). Returns the average and the measurement left out, if any.
template <class Solve>
std::pair<Average, std::optional<std::size_t>> best_average(std::vector<Candidate>& candidates,
                                                            const std::vector<std::size_t>& order,
                                                            std::size_t observations,
                                                            const std::vector<std::size_t>& valid,
                                                            const LongsolveOptions& options,
                                                            Solve&& solve) {
  Average average = average_triples(candidates, order, observations, {}, options, solve);
  std::optional<std::size_t> excluded;
  if (average.consistent)
    return {std::move(average), excluded};
  for (const std::size_t o : valid) {
    Average without = average_triples(candidates, order, observations, o, options, solve);
    const bool better = without.consistent &&
                        without.used.size() >= static_cast<std::size_t>(options.min_triples) &&
                        (!excluded || without.used.size() > average.used.size() ||
                         (without.used.size() == average.used.size() &&
                          total_weight(candidates, without) > total_weight(candidates, average)));
    if (better) {
      average = std::move(without);
      excluded = o;
    }
  }
  return {std::move(average), excluded};
}

// The usable measurements in no averaged triple: rejected (kTripleDeviation)
// when their triples were dropped as deviating or gave no fix at all (an
// echo's triples often land outside the room), else unused. Returns which
// measurements the average rests on.
std::vector<bool> mark_unaveraged(Fix& fix, const std::vector<Candidate>& candidates,
                                  const Average& average, std::optional<std::size_t> excluded,
                                  const std::vector<Observation>& obs,
                                  const std::vector<std::size_t>& valid) {
  std::vector<bool> in_average(obs.size(), false);
  std::vector<bool> in_dropped(obs.size(), false);
  if (excluded)
    in_dropped[*excluded] = true;
  for (std::size_t c = 0; c < candidates.size(); ++c)
    for (const std::size_t o : candidates[c].obs)
      in_dropped[o] = in_dropped[o] || average.roles[c] == Role::kDropped || candidates[c].failed;
  for (const std::size_t c : average.used)
    for (const std::size_t o : candidates[c].obs)
      in_average[o] = true;
  for (const std::size_t o : valid)
    if (!in_average[o]) {
      BeaconUse& u = fix.beacons[static_cast<std::size_t>(obs[o].beacon)];
      u.status = in_dropped[o] ? BeaconStatus::kTripleDeviation : BeaconStatus::kUnused;
      u.candidate = -1;
    }
  return in_average;
}

// The average as a linear function of the distances: M = sum(w S_t)/sum(w),
// S_t each triple's sensitivity at its own solution, w = 1 / its error.
Sensitivity average_sensitivity(const BeaconLayout& layout,
                                const std::vector<Candidate>& candidates, const Average& average,
                                std::size_t observations, double min_determinant) {
  Sensitivity m = Sensitivity::Zero(2, static_cast<Eigen::Index>(observations));
  for (const std::size_t c : average.used) {
    const Candidate& t = candidates[c];
    const TripleSensitivity s =
        *triple_sensitivity(layout, t.beacons, t.fix->position_m, min_determinant);
    for (std::size_t k = 0; k < 3; ++k)
      m.col(static_cast<Eigen::Index>(t.obs[k])) += s.col(static_cast<Eigen::Index>(k)) / t.error_m;
  }
  return m / total_weight(candidates, average);
}

}  // namespace

Fix Longsolve::solve(const BeaconLayout& layout, const RangeSet& ranges) {
  Fix fix = solve_unsettled(layout, ranges);
  settle_unused(fix);
  return fix;
}

Fix Longsolve::solve_unsettled(const BeaconLayout& layout, const RangeSet& ranges) {
  layout.validate();
  if (!same_beacons(layout.beacons, layout_)) {
    reset();
    layout_ = layout.beacons;
  }
  averaged_.clear();
  const Prepared prepared = prepare(layout, ranges, options_.triple.min_sd_m);
  const std::vector<Observation>& obs = prepared.primaries;
  Fix fix;
  fix.solver = Solver::kLongsolve;
  fix.speed_of_sound_mps = ranges.speed_of_sound_mps;
  fix.beacons = check_triangle_inequality(layout, prepared, options_.triangle);
  const auto no_fix = [&fix](NoFixReason reason) {
    fix.reason = reason;
    return fix;
  };

  const std::vector<std::size_t> valid = usable_primaries(obs, fix.beacons);
  const auto needed = static_cast<std::size_t>(options_.min_beacons);
  if (valid.size() < needed)
    return no_fix(too_few_reason(obs.size(), fix.beacons, needed));
  std::vector<Candidate> candidates = all_triples(obs, valid);
  const auto sensitivity_of = [&](const Triple& t) -> const std::optional<TripleSensitivity>& {
    return sensitivity(layout, t);
  };
  TripleSolves solve_from(layout, obs, options_.triple, fix.iterations);

  // Step 1: the quick solution, from the last least-error triple.
  const Vec2 start = last_fix_.value_or(centroid(layout));
  if (!estimated_at_)
    estimate_at(start);
  std::vector<std::size_t> order = rank(candidates, obs, sensitivity_of);
  std::optional<Vec2> quick;
  const auto try_quick = [&](Candidate& t) {
    if (!quick && solve_from(t, start))
      quick = t.fix->position_m;
  };
  for (Candidate& t : candidates)
    if (best_ && t.beacons == *best_)
      try_quick(t);
  for (const std::size_t c : order)
    try_quick(candidates[c]);
  if (!quick)
    return no_fix(solve_from.failure());
  // Step 2: re-estimate the errors where the robot is now.
  if (std::hypot(quick->x - estimated_at_->x, quick->y - estimated_at_->y) >
      options_.reestimate_distance_m) {
    estimate_at(*quick);
    order = rank(candidates, obs, sensitivity_of);
  }

  // Steps 3 and 4.
  const auto [average, excluded] =
      best_average(candidates, order, obs.size(), valid, options_,
                   [&](Candidate& t) { return solve_from(t, *quick); });
  if (average.used.empty())
    return no_fix(solve_from.failure());
  const std::vector<bool> in_average =
      mark_unaveraged(fix, candidates, average, excluded, obs, valid);
  for (const std::size_t c : average.used)
    averaged_.push_back(candidates[c].beacons);
  fix.position_m = vec2(average.point);
  // The average must rest on min_beacons measurements: one triple left
  // (three beacons) fits whatever its errors, so the others' disagreement
  // leaves nothing checked.
  if (!average.consistent || fix.used() < options_.min_beacons)
    return no_fix(NoFixReason::kInconsistent);
  if (layout.distance_outside_hull_m(fix.position_m) > options_.triple.max_outside_hull_m)
    return no_fix(NoFixReason::kOutsideHull);

  const Sensitivity m =
      average_sensitivity(layout, candidates, average, obs.size(), options_.triple.min_determinant);
  const std::vector<double> residuals =
      fill_statistics(layout, obs, in_average, m, average.point, fix);
  for (std::size_t i = 0; i < obs.size(); ++i)
    fix.beacons[static_cast<std::size_t>(obs[i].beacon)].residual_m = residuals[i];
  // A measurement can only be too long (Kleeman 4.3): one markedly shorter
  // than the fix predicts says that averaged ones are late (two echoes can
  // agree on a wrong point).
  const double position_sd = std::sqrt(fix.covariance_m2.trace());
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (too_short(residuals[i], obs[i].sd_m, position_sd, options_.triangle)) {
      fix.covariance_m2.setConstant(kNaN);
      fix.hdop = kNaN;
      return no_fix(NoFixReason::kInconsistent);
    }
  fix.valid = true;
  fix.reason = NoFixReason::kNone;
  last_fix_ = fix.position_m;
  best_ = averaged_.front();
  return fix;
}

}  // namespace odoloc::sw::locate
