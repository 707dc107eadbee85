#include "odoloc/sw/multilateration.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

#include "odoloc/sw/detail/config_checks.hpp"

namespace odoloc::sw::locate {

double speed_of_sound_mps(double temperature_c) {
  constexpr double kC0 = 331.3;
  constexpr double kZeroCelsius = 273.15;
  return temperature_c < -kZeroCelsius ? kNaN : kC0 * std::sqrt(1.0 + temperature_c / kZeroCelsius);
}

double speed_of_sound_slope(double temperature_c) {
  constexpr double kZeroCelsius = 273.15;
  return speed_of_sound_mps(temperature_c) / (2.0 * (kZeroCelsius + temperature_c));
}

void MultilaterationOptions::validate() const {
  const auto fail = [](std::string_view what) {
    detail::require(false, "MultilaterationOptions", what);
  };
  if (temperature_c && !(*temperature_c >= kMinTemperatureC && *temperature_c <= kMaxTemperatureC))
    fail("temperature_c must be within -100..100 C");
  if (!(std::isfinite(temperature_sd_c) && temperature_sd_c > 0))
    fail("temperature_sd_c must be finite and positive");
  if (!(std::isfinite(speed_of_sound_tolerance) && speed_of_sound_tolerance >= 0 &&
        speed_of_sound_tolerance < 0.5))
    fail("speed_of_sound_tolerance must be within 0..0.5");
  if (min_beacons < 3)
    fail("min_beacons must be at least 3");
  if (min_beacons_to_calibrate < 5)
    fail("min_beacons_to_calibrate must be at least 5 (four unknowns and one redundancy)");
  if (!(std::isfinite(min_sd_m) && min_sd_m > 0))
    fail("min_sd_m must be finite and positive");
  if (max_iterations < 1 || max_iterations > 1000)
    fail("max_iterations must be 1..1000");
  if (!(std::isfinite(step_tolerance_m) && step_tolerance_m > 0))
    fail("step_tolerance_m must be finite and positive");
  if (!(max_outside_hull_m >= 0))
    fail("max_outside_hull_m must be non-negative");
  if (!(std::isfinite(inlier_sigmas) && inlier_sigmas > 0 && std::isfinite(inlier_floor_m) &&
        inlier_floor_m >= 0))
    fail("inlier_sigmas must be positive and inlier_floor_m non-negative");
  if (!(std::isfinite(residual_gate_sigmas) && residual_gate_sigmas > 0))
    fail("residual_gate_sigmas must be finite and positive");
  if (max_hypotheses < 1)
    fail("max_hypotheses must be at least 1");
  if (prior_position_m &&
      !(std::isfinite(prior_position_m->x) && std::isfinite(prior_position_m->y)))
    fail("prior_position_m must be finite");
  if (!(std::isfinite(mirror_margin_m) && mirror_margin_m >= 0))
    fail("mirror_margin_m must be finite and non-negative");
}

namespace {

constexpr int kMaxState = 4;  // x, y, o, k
using StateVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxState, 1>;
using StateMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxState, kMaxState>;
using Row = Eigen::Matrix<double, kMaxState, 1>;

double distance(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

// The diagonal of the beacons' bounding box.
double extent_m(const BeaconLayout& layout) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Beacon& b : layout.beacons) {
    x0 = std::min(x0, b.position_m.x);
    x1 = std::max(x1, b.position_m.x);
    y0 = std::min(y0, b.position_m.y);
    y1 = std::max(y1, b.position_m.y);
  }
  return layout.beacons.empty() ? 0.0 : std::hypot(x1 - x0, y1 - y0);
}

// r_i(P) and its gradient with respect to P.
struct RangeGradient {
  double range;
  double gx, gy;
};
RangeGradient range_gradient(const Beacon& b, Vec2 p) {
  const double dx = p.x - b.position_m.x;
  const double dy = p.y - b.position_m.y;
  const double r = std::sqrt(dx * dx + dy * dy + b.height_m * b.height_m);
  return r > 0 ? RangeGradient{r, dx / r, dy / r} : RangeGradient{0, 0, 0};
}

// The Jacobian row of d_i = k r_i + o over (x, y, o[, k]).
Row jacobian_row(const RangeGradient& g, double k) {
  Row row;
  row << k * g.gx, k * g.gy, 1.0, g.range;
  return row;
}

struct State {
  Vec2 p;
  double o = 0;
  double k = 1;
};

// Everything the fit knows besides the observations.
struct Model {
  const BeaconLayout* layout;
  const ConvexHull* hull;
  bool calibrate = false;  // k is a state
  double k_prior = 1;      // k when fixed; the prior's mean when calibrating
  double k_prior_sd = 0;   // > 0: k is uncertain (a pseudo-measurement when it is a state)
  // Range error the consensus tolerates besides the noise: a relative error
  // of k shifts d_i - d_j by up to that fraction of the layout's extent (the
  // triples are solved at k_prior). Nonzero only when calibrating.
  double consensus_slack_m = 0;
  [[nodiscard]] int dimension() const { return calibrate ? 4 : 3; }
};

double residual(const Model& model, const Observation& obs, const State& s) {
  const Beacon& b = model.layout->beacons[static_cast<std::size_t>(obs.beacon)];
  return obs.distance_m - (s.k * range_gradient(b, s.p).range + s.o);
}

// sum of squared normalised residuals, the k prior included.
double cost(const Model& model, std::span<const Observation> obs, const State& s) {
  double c = 0;
  for (const Observation& o : obs) {
    const double e = residual(model, o, s) / o.sd_m;
    c += e * e;
  }
  if (model.calibrate && model.k_prior_sd > 0) {
    const double e = (s.k - model.k_prior) / model.k_prior_sd;
    c += e * e;
  }
  return c;
}

// Normal equations N = J^T W J and g = J^T W e at s (weights 1/sd^2, or 1
// with unit_weights for the dilution of precision).
void normal_equations(const Model& model, std::span<const Observation> obs, const State& s,
                      bool unit_weights, StateMatrix& n, StateVector& g) {
  const int dim = model.dimension();
  n.setZero(dim, dim);
  g.setZero(dim);
  for (const Observation& o : obs) {
    const RangeGradient rg =
        range_gradient(model.layout->beacons[static_cast<std::size_t>(o.beacon)], s.p);
    const Row j = jacobian_row(rg, s.k);
    const double w = unit_weights ? 1.0 : 1.0 / (o.sd_m * o.sd_m);
    const auto jd = j.head(dim);
    n.noalias() += w * jd * jd.transpose();
    g.noalias() += w * (o.distance_m - (s.k * rg.range + s.o)) * jd;
  }
  if (model.calibrate && model.k_prior_sd > 0 && !unit_weights) {
    const double w = 1.0 / (model.k_prior_sd * model.k_prior_sd);
    n(3, 3) += w;
    g(3) += w * (model.k_prior - s.k);
  }
}

// The inverse of a symmetric positive definite matrix, or nothing when it is
// not numerically positive definite (Cholesky pivots spanning more than 13
// decades: a direction the measurements do not constrain).
std::optional<StateMatrix> spd_inverse(const StateMatrix& n) {
  const Eigen::LLT<StateMatrix> llt(n);
  if (llt.info() != Eigen::Success)
    return std::nullopt;
  const auto pivots = llt.matrixLLT().diagonal().cwiseAbs2();
  if (!(pivots.minCoeff() > pivots.maxCoeff() * 1e-13))
    return std::nullopt;
  StateMatrix inverse = llt.solve(StateMatrix::Identity(n.rows(), n.cols()));
  if (!inverse.allFinite())
    return std::nullopt;
  return inverse;
}

// The covariance of the fitted state: (J^T W J)^-1 of the fit's model. When
// k is uncertain but held at its prior (too few beacons to estimate it), the
// consider covariance: its spread enters through the cross information,
// P + (P N_xk) sd_k^2 (P N_xk)^T with P the position-and-offset block's
// inverse, and the result is 4 x 4 with k's prior variance.
std::optional<StateMatrix> state_covariance(const Model& model, std::span<const Observation> obs,
                                            const State& s) {
  StateMatrix n;
  StateVector g;
  if (model.calibrate || model.k_prior_sd <= 0) {
    normal_equations(model, obs, s, false, n, g);
    return spd_inverse(n);
  }
  Model with_k = model;
  with_k.calibrate = true;
  with_k.k_prior_sd = 0;  // the data's information alone
  normal_equations(with_k, obs, s, false, n, g);
  const std::optional<StateMatrix> p = spd_inverse(n.topLeftCorner(3, 3));
  if (!p)
    return std::nullopt;
  const StateVector gain = *p * n.topRightCorner(3, 1);
  const double var_k = model.k_prior_sd * model.k_prior_sd;
  StateMatrix cov = StateMatrix::Zero(4, 4);
  cov.topLeftCorner(3, 3) = *p + gain * var_k * gain.transpose();
  cov.topRightCorner(3, 1) = -gain * var_k;
  cov.bottomLeftCorner(1, 3) = -var_k * gain.transpose();
  cov(3, 3) = var_k;
  return cov;
}

struct FitResult {
  State state;
  int iterations = 0;
  bool converged = false;
  bool singular = false;
};

// Weighted Gauss-Newton with Levenberg-Marquardt damping from `start`.
FitResult gauss_newton(const Model& model, std::span<const Observation> obs, State start,
                       const MultilaterationOptions& options) {
  FitResult fit{start};
  const int dim = model.dimension();
  double current = cost(model, obs, fit.state);
  double lambda = 1e-6;
  StateMatrix n;
  StateVector g;
  for (int it = 0; it < options.max_iterations; ++it) {
    fit.iterations = it + 1;
    normal_equations(model, obs, fit.state, false, n, g);
    bool accepted = false;
    double step_m = 0;
    while (lambda < 1e12) {
      StateMatrix damped = n;
      damped.diagonal() *= 1.0 + lambda;
      const Eigen::LDLT<StateMatrix> ldlt(damped);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
        fit.singular = true;
        return fit;
      }
      const StateVector delta = ldlt.solve(g);
      if (!delta.allFinite()) {
        fit.singular = true;
        return fit;
      }
      State next = fit.state;
      next.p.x += delta(0);
      next.p.y += delta(1);
      next.o += delta(2);
      if (dim == 4)
        next.k += delta(3);
      step_m = std::hypot(delta(0), delta(1));
      const double next_cost = cost(model, obs, next);
      if (next_cost <= current) {
        fit.state = next;
        current = next_cost;
        lambda = std::max(lambda / 10, 1e-9);
        accepted = true;
        break;
      }
      if (step_m < options.step_tolerance_m) {  // at the minimum to rounding
        fit.converged = true;
        return fit;
      }
      lambda *= 10;
    }
    if (!accepted)
      return fit;
    if (step_m < options.step_tolerance_m) {
      fit.converged = true;
      return fit;
    }
  }
  return fit;
}

// Unknowns (x, y, o/k) from the n-1 differences to the first observation,
// linear least squares (Chan's first stage, unweighted): the start point
// with four or more observations.
std::optional<State> linear_start(const BeaconLayout& layout, std::span<const Observation> obs,
                                  double k) {
  const int rows = static_cast<int>(obs.size()) - 1;
  if (rows < 3)
    return std::nullopt;
  Eigen::MatrixX3d a(rows, 3);
  Eigen::VectorXd rhs(rows);
  const Beacon& b0 = layout.beacons[static_cast<std::size_t>(obs[0].beacon)];
  const double d0 = obs[0].distance_m / k;
  const double e0 = b0.position_m.x * b0.position_m.x + b0.position_m.y * b0.position_m.y +
                    b0.height_m * b0.height_m;
  for (int i = 0; i < rows; ++i) {
    const Observation& o = obs[static_cast<std::size_t>(i) + 1];
    const Beacon& b = layout.beacons[static_cast<std::size_t>(o.beacon)];
    const double d = o.distance_m / k;
    const double e =
        b.position_m.x * b.position_m.x + b.position_m.y * b.position_m.y + b.height_m * b.height_m;
    a.row(i) << 2 * (b.position_m.x - b0.position_m.x), 2 * (b.position_m.y - b0.position_m.y),
        -2 * (d - d0);
    rhs(i) = e - e0 - d * d + d0 * d0;
  }
  const Eigen::Vector3d x = a.colPivHouseholderQr().solve(rhs);
  if (!x.allFinite() || a.colPivHouseholderQr().rank() < 3)
    return std::nullopt;
  return State{{x(0), x(1)}, x(2) * k, k};
}

struct Consensus {
  State state;
  std::vector<Observation> inliers;
  double score = -1;  // inliers minus the truncated normalised cost share
};

}  // namespace

TripleSolutions solve_triple_closed_form(const BeaconLayout& layout,
                                         std::span<const Observation, 3> obs, double k) {
  TripleSolutions out;
  if (!(std::isfinite(k) && k > 0))
    return out;
  // D_i = d_i/k = r_i + q with q = o/k. Differences to beacon 0 are linear
  // in P for a given q: 2 (b_i - b_0) . P = 2 q (D_i - D_0) + K_i, so
  // P = p0 + q v; then (D_0 - q)^2 = |P - b_0|^2 + h_0^2 is quadratic in q.
  std::array<const Beacon*, 3> b{};
  std::array<double, 3> d{};
  for (std::size_t i = 0; i < 3; ++i) {
    b[i] = &layout.beacons.at(static_cast<std::size_t>(obs[i].beacon));
    d[i] = obs[i].distance_m / k;
  }
  const auto energy = [](const Beacon& x) {
    return x.position_m.x * x.position_m.x + x.position_m.y * x.position_m.y +
           x.height_m * x.height_m;
  };
  Eigen::Matrix2d a;
  Eigen::Vector2d kv;
  Eigen::Vector2d dv;
  for (int i = 0; i < 2; ++i) {
    const Beacon& bi = *b[static_cast<std::size_t>(i) + 1];
    const double di = d[static_cast<std::size_t>(i) + 1];
    a.row(i) << 2 * (bi.position_m.x - b[0]->position_m.x),
        2 * (bi.position_m.y - b[0]->position_m.y);
    kv(i) = energy(bi) - energy(*b[0]) - di * di + d[0] * d[0];
    dv(i) = 2 * (di - d[0]);
  }
  const double det = a.determinant();
  const double scale = a.cwiseAbs().maxCoeff();
  if (!(std::abs(det) > 1e-9 * scale * scale))
    return out;  // collinear beacons
  const Eigen::Matrix2d inv = a.inverse();
  const Eigen::Vector2d p0 = inv * kv;
  const Eigen::Vector2d v = inv * dv;
  const Eigen::Vector2d w = p0 - Eigen::Vector2d(b[0]->position_m.x, b[0]->position_m.y);
  const double qa = v.squaredNorm() - 1.0;
  const double qb = 2.0 * (w.dot(v) + d[0]);
  const double qc = w.squaredNorm() + b[0]->height_m * b[0]->height_m - d[0] * d[0];
  std::array<double, 2> roots{};
  int root_count = 0;
  if (std::abs(qa) < 1e-12) {
    if (std::abs(qb) > 0)
      roots[root_count++] = -qc / qb;
  } else {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      // The numerically stable pair of roots.
      const double t = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      roots[root_count++] = t / qa;
      if (t != 0 && disc > 0)
        roots[root_count++] = qc / t;
    }
  }
  for (int r = 0; r < root_count; ++r) {
    const double q = roots[static_cast<std::size_t>(r)];
    if (!std::isfinite(q))
      continue;
    bool physical = true;  // every range r_i = D_i - q at least the beacon's height
    for (std::size_t i = 0; i < 3; ++i)
      physical = physical && d[i] - q >= b[i]->height_m - 1e-9 * (1 + std::abs(d[i]));
    if (!physical)
      continue;
    const Eigen::Vector2d p = p0 + q * v;
    out.solutions[static_cast<std::size_t>(out.count++)] = {{p(0), p(1)}, q * k};
  }
  return out;
}

namespace {

// The candidates of each usable beacon: primary first, then its echoes.
struct BeaconCandidates {
  std::vector<Observation> options;
};

constexpr double kRefuted = 1e300;  // the score of a hypothesis a short measurement refutes

// Best consensus over triples of primaries (exhaustive or seeded sample).
// `rivals` receives every other hypothesis with at least `needed` inliers,
// one per distinct inlier set: the explanations the best must be the only
// one of (rival_explains).
Consensus find_consensus(const Model& model, const std::vector<BeaconCandidates>& beacons,
                         const MultilaterationOptions& options, std::size_t needed,
                         std::vector<Consensus>& rivals, bool& any_geometry, bool& any_inside) {
  Consensus best;
  std::set<std::vector<std::pair<int, int>>> seen;
  const auto keep_rival = [&](const Consensus& c) {
    if (c.inliers.size() < needed)
      return;
    std::vector<std::pair<int, int>> members;
    for (const Observation& o : c.inliers)
      members.emplace_back(o.beacon, o.candidate);
    std::ranges::sort(members);
    if (seen.insert(std::move(members)).second)
      rivals.push_back(c);
  };
  const std::size_t n = beacons.size();
  const auto score_hypothesis = [&](const State& s) {
    Consensus c{s, {}, 0};
    double truncated = 0;
    for (const BeaconCandidates& bc : beacons) {
      const Observation* chosen = nullptr;
      double chosen_norm = 0;
      for (std::size_t k = 0; k < bc.options.size(); ++k) {
        const Observation& o = bc.options[k];
        // A primary that agrees and is not suspect stands; alternatives are
        // tried when it is suspect or disagrees.
        const double range =
            range_gradient(model.layout->beacons[static_cast<std::size_t>(o.beacon)], s.p).range;
        const double signed_e = o.distance_m - (s.k * range + s.o);
        const double e = std::abs(signed_e);
        const double threshold =
            options.inlier_sigmas * o.sd_m + options.inlier_floor_m + model.consensus_slack_m;
        // A measurement can only be too long (Kleeman 4.3): a trusted primary
        // much shorter than the hypothesis predicts refutes the hypothesis.
        if (k == 0 && !o.suspect && signed_e < -threshold)
          return Consensus{s, {}, -kRefuted};
        if (e <= threshold && (chosen == nullptr || e / threshold < chosen_norm)) {
          chosen = &o;
          chosen_norm = e / threshold;
        }
        if (k == 0 && chosen != nullptr && !o.suspect)
          break;
      }
      if (chosen != nullptr) {
        c.inliers.push_back(*chosen);
        truncated += chosen_norm * chosen_norm;
      } else {
        truncated += 1.0;
      }
    }
    c.score = static_cast<double>(c.inliers.size()) - truncated / static_cast<double>(n + 1);
    return c;
  };
  const auto try_triple = [&](std::size_t i, std::size_t j, std::size_t l) {
    const std::array<Observation, 3> triple{beacons[i].options[0], beacons[j].options[0],
                                            beacons[l].options[0]};
    const TripleSolutions sol = solve_triple_closed_form(
        *model.layout, std::span<const Observation, 3>(triple), model.k_prior);
    for (int s = 0; s < sol.count; ++s) {
      any_geometry = true;
      const TripleSolution& t = sol.solutions[static_cast<std::size_t>(s)];
      // A solution too far outside the beacons cannot become a fix: its
      // mirror (or another triple) must.
      if (model.hull->distance_outside_m(t.position_m) > options.max_outside_hull_m)
        continue;
      any_inside = true;
      Consensus c = score_hypothesis({t.position_m, t.offset_m, model.k_prior});
      keep_rival(c);
      // Equal scores (the two roots of a lone triple): the one nearer the prior.
      const bool nearer =
          options.prior_position_m && distance(c.state.p, *options.prior_position_m) <
                                          distance(best.state.p, *options.prior_position_m);
      if (c.score > best.score + 1e-9 || (c.score > best.score - 1e-9 && nearer))
        best = std::move(c);
    }
  };
  const double triples =
      static_cast<double>(n) * static_cast<double>(n - 1) * static_cast<double>(n - 2) / 6.0;
  if (triples <= options.max_hypotheses) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        for (std::size_t l = j + 1; l < n; ++l)
          try_triple(i, j, l);
  } else {
    // Raw 64-bit draws reduced modulo n: the same sequence on every standard
    // library (std::uniform_int_distribution is implementation-defined).
    std::mt19937_64 rng(options.seed);
    for (int h = 0; h < options.max_hypotheses; ++h) {
      const std::size_t i = rng() % n;
      const std::size_t j = (i + 1 + rng() % (n - 1)) % n;
      std::size_t l = rng() % n;
      while (l == i || l == j)
        l = (l + 1) % n;
      try_triple(i, j, l);
    }
  }
  return best;
}

void fill_uses(Fix& fix, const Model& model, std::span<const Observation> used,
               const std::vector<BeaconCandidates>& candidates, const State& s) {
  for (BeaconUse& u : fix.beacons) {
    if (u.status != BeaconStatus::kUsed)
      continue;
    const auto it = std::find_if(used.begin(), used.end(),
                                 [&](const Observation& o) { return o.beacon == u.beacon; });
    if (it != used.end()) {
      u.candidate = it->candidate;
      u.residual_m = residual(model, *it, s);
      continue;
    }
    u.status = BeaconStatus::kOutlier;
    for (const BeaconCandidates& bc : candidates)
      if (bc.options.front().beacon == u.beacon)
        u.residual_m = residual(model, bc.options.front(), s);
    u.candidate = -1;
  }
}

// The triangle-inequality check over the non-suspect primaries: the
// rejected ones leave `prepared` and are marked in `uses`.
void reject_too_long(const BeaconLayout& layout, const MultilaterationOptions& options,
                     const Model& model, Prepared& prepared, std::vector<BeaconUse>& uses) {
  Prepared checked = prepared;
  checked.uses = uses;
  std::erase_if(checked.primaries, [](const Observation& o) { return o.suspect; });
  TriangleOptions triangle = options.triangle;
  if (model.k_prior_sd > 0)
    triangle.baseline_fraction =
        std::max(triangle.baseline_fraction, 4 * model.k_prior_sd / model.k_prior);
  for (const BeaconUse& u : check_triangle_inequality(layout, checked, triangle)) {
    if (u.status != BeaconStatus::kTriangleInequality)
      continue;
    uses[static_cast<std::size_t>(u.beacon)] = u;
    std::erase_if(prepared.primaries, [&](const Observation& o) { return o.beacon == u.beacon; });
  }
}

// The chi-square value a sum of `dof` squared standard normals exceeds with
// the one-sided normal tail probability of z (Wilson-Hilferty: within a few
// percent from one degree of freedom up).
double chi2_quantile(int dof, double z) {
  const double k = dof;
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

// The final check of a fit: its chi-square within the gate's quantile (the
// studentised test cannot drop the last redundant measurement), and no
// trusted primary it rejected much shorter than it predicts (a measurement
// can only be too long: a short one means the fix is the wrong one).
bool consistent(const Fix& fix, const Model& model, std::span<const Observation> used,
                const std::vector<BeaconCandidates>& candidates,
                const MultilaterationOptions& options) {
  if (fix.dof >= 1 && fix.chi2 > chi2_quantile(fix.dof, options.residual_gate_sigmas))
    return false;
  for (const BeaconCandidates& bc : candidates) {
    const Observation& primary = bc.options.front();
    const bool is_used = std::any_of(
        used.begin(), used.end(), [&](const Observation& o) { return o.beacon == primary.beacon; });
    if (is_used || primary.suspect)
      continue;
    const double e = fix.beacons[static_cast<std::size_t>(primary.beacon)].residual_m;
    if (e <
        -(options.inlier_sigmas * primary.sd_m + options.inlier_floor_m + model.consensus_slack_m))
      return false;
  }
  return true;
}

// The place of a rival explanation of the cycle, if there is one: another
// consensus whose own members, fitted alone, pass the same tests as the
// fix's (converged, chi-square within the residual gate, no trusted primary
// refuting it by being short, inside the hull) at a place the two
// covariances cannot reconcile (squared Mahalanobis distance of the
// difference beyond the 2-dof quantile of the residual gate). Different
// triples of one set refit to the same place and are no rivals.
std::optional<Vec2> rival_explains(const Fix& fix, const Model& model,
                                   const std::vector<Consensus>& rivals,
                                   const std::vector<BeaconCandidates>& candidates,
                                   const MultilaterationOptions& options) {
  const double apart = chi2_quantile(2, options.residual_gate_sigmas);
  for (const Consensus& rival : rivals) {
    const FitResult fit = gauss_newton(model, rival.inliers, rival.state, options);
    if (fit.singular || !fit.converged)
      continue;
    const std::optional<StateMatrix> covariance = state_covariance(model, rival.inliers, fit.state);
    if (!covariance)
      continue;
    const int dof = static_cast<int>(rival.inliers.size()) - model.dimension();
    if (dof >= 1 &&
        cost(model, rival.inliers, fit.state) > chi2_quantile(dof, options.residual_gate_sigmas))
      continue;
    if (model.hull->distance_outside_m(fit.state.p) > options.max_outside_hull_m)
      continue;
    const bool refuted = std::ranges::any_of(candidates, [&](const BeaconCandidates& bc) {
      const Observation& primary = bc.options.front();
      const double threshold =
          options.inlier_sigmas * primary.sd_m + options.inlier_floor_m + model.consensus_slack_m;
      return !primary.suspect && residual(model, primary, fit.state) < -threshold;
    });
    if (refuted)
      continue;
    const Eigen::Vector2d difference(fit.state.p.x - fix.position_m.x,
                                     fit.state.p.y - fix.position_m.y);
    const Eigen::Matrix2d joint = fix.covariance_m2 + covariance->topLeftCorner<2, 2>();
    if (difference.dot(joint.ldlt().solve(difference)) > apart)
      return fit.state.p;
  }
  return std::nullopt;
}

}  // namespace

namespace {

// The range model: the speed of sound the ranges assumed against the one
// this fix assumes (k_prior) and, when calibrating, how uncertain k is.
Model range_model(const BeaconLayout& layout, const ConvexHull& hull, const RangeSet& ranges,
                  const MultilaterationOptions& options) {
  Model model{&layout, &hull};
  double c_assumed = ranges.speed_of_sound_mps;
  if (options.temperature_c)
    c_assumed = speed_of_sound_mps(*options.temperature_c);
  model.k_prior = ranges.speed_of_sound_mps / c_assumed;
  if (options.calibrate_speed_of_sound) {
    // k is uncertain: from the temperature's sd, else half the tolerance.
    const double relative_sd =
        options.temperature_c
            ? speed_of_sound_slope(*options.temperature_c) * options.temperature_sd_c / c_assumed
            : options.speed_of_sound_tolerance / 2;
    model.k_prior_sd = model.k_prior * relative_sd;
    model.consensus_slack_m = 4 * relative_sd * extent_m(layout);
  }
  return model;
}

// Each usable beacon's primary reading and, robust, its other candidates.
std::vector<BeaconCandidates> beacon_candidates(const RangeSet& ranges, const Prepared& prepared,
                                                const MultilaterationOptions& options) {
  std::vector<BeaconCandidates> candidates;
  candidates.reserve(prepared.primaries.size());
  for (const Observation& p : prepared.primaries) {
    BeaconCandidates bc{{p}};
    if (options.robust)
      for (const Observation& alt : alternatives(ranges, p.beacon, options.min_sd_m))
        bc.options.push_back(alt);
    candidates.push_back(std::move(bc));
  }
  return candidates;
}

// The measurements to fit and where the fit starts: a consensus of the
// candidates (robust, or a lone triple), else every primary from the linear
// solution. `failure` says why there is none.
struct Start {
  std::vector<Observation> used;
  std::vector<Consensus> rivals;  // other consistent beacon sets (robust)
  State state;
  NoFixReason failure = NoFixReason::kNone;
};
Start choose_start(const BeaconLayout& layout, const Model& model, const Prepared& prepared,
                   const std::vector<BeaconCandidates>& candidates,
                   const MultilaterationOptions& options) {
  Start start;
  if (options.robust || prepared.primaries.size() == 3) {
    // A lone triple always agrees with itself: with more beacons usable, a
    // consensus needs one that checks it.
    const std::size_t needed = prepared.primaries.size() > 3 ? 4 : 3;
    bool any_geometry = false;
    bool any_inside = false;
    Consensus consensus =
        find_consensus(model, candidates, options, needed, start.rivals, any_geometry, any_inside);
    if (!any_geometry || !any_inside)
      start.failure = any_geometry ? NoFixReason::kOutsideHull : NoFixReason::kDegenerateGeometry;
    else if (consensus.inliers.size() < needed)
      start.failure = NoFixReason::kInconsistent;
    start.used = std::move(consensus.inliers);
    start.state = consensus.state;
    return start;
  }
  start.used = prepared.primaries;
  const std::optional<State> linear = linear_start(layout, start.used, model.k_prior);
  if (!linear)
    start.failure = NoFixReason::kDegenerateGeometry;
  else
    start.state = *linear;
  return start;
}

// The measurement whose studentised residual is the largest beyond the gate,
// or used.size(): none (a measurement without redundancy says nothing).
std::size_t worst_residual(const BeaconLayout& layout, const Model& model,
                           std::span<const Observation> used, const State& state,
                           const StateMatrix& covariance, double gate_sigmas) {
  std::size_t worst = used.size();
  double worst_t = gate_sigmas;
  for (std::size_t i = 0; i < used.size(); ++i) {
    const Observation& o = used[i];
    const Row j = jacobian_row(
        range_gradient(layout.beacons[static_cast<std::size_t>(o.beacon)], state.p), state.k);
    const auto jd = j.head(covariance.rows());
    const double leverage = (jd.transpose() * covariance * jd)(0, 0) / (o.sd_m * o.sd_m);
    if (leverage > 1 - 1e-6)
      continue;
    const double t = std::abs(residual(model, o, state)) / (o.sd_m * std::sqrt(1 - leverage));
    if (t > worst_t) {
      worst_t = t;
      worst = i;
    }
  }
  return worst;
}

// Gauss-Newton from the start (position and offset at the assumed c first
// when calibrating: from a triple solved at the wrong c, the four-state
// problem can slide off toward the far field), then, robust, the
// studentised residual test drops the worst while redundancy remains.
struct Fitted {
  FitResult fit;
  std::optional<StateMatrix> covariance;
  int iterations = 0;
};
Fitted fit_dropping_outliers(const BeaconLayout& layout, Model& model,
                             std::vector<Observation>& used, State start,
                             const MultilaterationOptions& options) {
  model.calibrate = options.calibrate_speed_of_sound &&
                    static_cast<int>(used.size()) >= options.min_beacons_to_calibrate;
  start.k = model.k_prior;
  Fitted f;
  if (model.calibrate) {
    Model fixed_c = model;
    fixed_c.calibrate = false;
    const FitResult first = gauss_newton(fixed_c, used, start, options);
    f.iterations += first.iterations;
    if (!first.singular)
      start = first.state;
  }
  f.fit = gauss_newton(model, used, start, options);
  f.iterations += f.fit.iterations;
  while (!f.fit.singular) {
    f.covariance = state_covariance(model, used, f.fit.state);
    if (!f.covariance || !options.robust || static_cast<int>(used.size()) <= model.dimension() + 1)
      break;
    const std::size_t worst = worst_residual(layout, model, used, f.fit.state, *f.covariance,
                                             options.residual_gate_sigmas);
    if (worst == used.size())
      break;
    used.erase(used.begin() + static_cast<std::ptrdiff_t>(worst));
    model.calibrate =
        model.calibrate && static_cast<int>(used.size()) >= options.min_beacons_to_calibrate;
    f.fit = gauss_newton(model, used, f.fit.state, options);
    f.iterations += f.fit.iterations;
  }
  return f;
}

// The fix's uncertainty and fit statistics from a converged fit.
void fill_statistics(Fix& fix, const Model& model, std::span<const Observation> used,
                     const State& state, const StateMatrix& covariance, double c_ranges_mps) {
  fix.covariance_m2 = covariance.topLeftCorner<2, 2>();
  fix.offset_sd_m = std::sqrt(covariance(2, 2));
  fix.speed_of_sound_estimated = model.calibrate;
  if (covariance.rows() == 4)
    fix.speed_of_sound_sd_mps = c_ranges_mps / (state.k * state.k) * std::sqrt(covariance(3, 3));
  fix.chi2 = cost(model, used, state);
  fix.dof = static_cast<int>(used.size()) - model.dimension();
  StateMatrix n;
  StateVector g;
  normal_equations(model, used, state, true, n, g);
  if (const std::optional<StateMatrix> unit = spd_inverse(n))
    fix.hdop = std::sqrt((*unit)(0, 0) + (*unit)(1, 1));
}

// Three measurements and three unknowns: the other intersection fits too.
// Sets fix.mirror_m to it; true when it is inside the hull and no prior
// position decides between the two.
bool mirror_ambiguous(Fix& fix, const BeaconLayout& layout, const ConvexHull& hull,
                      std::span<const Observation> used, const State& state,
                      const MultilaterationOptions& options) {
  const std::array<Observation, 3> triple{used[0], used[1], used[2]};
  const TripleSolutions sol =
      solve_triple_closed_form(layout, std::span<const Observation, 3>(triple), state.k);
  for (int s = 0; s < sol.count; ++s) {
    const Vec2 q = sol.solutions[static_cast<std::size_t>(s)].position_m;
    if (distance(q, fix.position_m) > 1e-3)
      fix.mirror_m = q;
  }
  if (!fix.mirror_m || hull.distance_outside_m(*fix.mirror_m) > options.max_outside_hull_m)
    return false;
  const bool decided =
      options.prior_position_m &&
      distance(*fix.mirror_m, *options.prior_position_m) >=
          distance(fix.position_m, *options.prior_position_m) + options.mirror_margin_m;
  return !decided;
}

Fix multilaterate_unsettled(const BeaconLayout& layout, const RangeSet& ranges,
                            const MultilaterationOptions& options) {
  layout.validate();
  options.validate();
  options.triangle.validate();
  Fix fix;
  fix.solver = Solver::kGaussNewton;
  Prepared prepared = prepare(layout, ranges, options.min_sd_m);
  fix.beacons = std::move(prepared.uses);
  const auto no_fix = [&fix](NoFixReason reason) {
    fix.reason = reason;
    return fix;
  };

  if (!std::isfinite(ranges.speed_of_sound_mps) || ranges.speed_of_sound_mps <= 0)
    return no_fix(NoFixReason::kNonFiniteInput);
  const ConvexHull hull(layout);
  Model model = range_model(layout, hull, ranges, options);
  if (options.check_triangle)
    reject_too_long(layout, options, model, prepared, fix.beacons);
  if (prepared.primaries.size() < 3)
    return no_fix(prepared.any_non_finite ? NoFixReason::kNonFiniteInput
                                          : NoFixReason::kTooFewBeacons);

  const std::vector<BeaconCandidates> candidates = beacon_candidates(ranges, prepared, options);
  Start start = choose_start(layout, model, prepared, candidates, options);
  if (start.failure != NoFixReason::kNone)
    return no_fix(start.failure);
  std::vector<Observation>& used = start.used;
  const Fitted fitted = fit_dropping_outliers(layout, model, used, start.state, options);
  const State& state = fitted.fit.state;

  fix.iterations = fitted.iterations;
  fill_uses(fix, model, used, candidates, state);
  fix.position_m = state.p;
  fix.offset_m = state.o;
  fix.speed_of_sound_mps = ranges.speed_of_sound_mps / state.k;
  if (fitted.fit.singular || !fitted.covariance)
    return no_fix(NoFixReason::kDegenerateGeometry);
  if (!fitted.fit.converged)
    return no_fix(NoFixReason::kNotConverged);
  fill_statistics(fix, model, used, state, *fitted.covariance, ranges.speed_of_sound_mps);

  if (!std::isfinite(fix.position_m.x) || !std::isfinite(fix.position_m.y))
    return no_fix(NoFixReason::kNotConverged);
  if (!consistent(fix, model, used, candidates, options))
    return no_fix(NoFixReason::kInconsistent);
  if (static_cast<int>(used.size()) < options.min_beacons)
    return no_fix(NoFixReason::kTooFewBeacons);
  if (hull.distance_outside_m(fix.position_m) > options.max_outside_hull_m)
    return no_fix(NoFixReason::kOutsideHull);
  if (used.size() == 3 && !model.calibrate &&
      mirror_ambiguous(fix, layout, hull, used, state, options))
    return no_fix(NoFixReason::kMirrorAmbiguous);
  if (used.size() > 3) {
    if (const std::optional<Vec2> rival =
            rival_explains(fix, model, start.rivals, candidates, options)) {
      fix.mirror_m = rival;
      return no_fix(NoFixReason::kAmbiguousBeaconSets);
    }
  }
  fix.valid = true;
  fix.reason = NoFixReason::kNone;
  return fix;
}

}  // namespace

Fix multilaterate(const BeaconLayout& layout, const RangeSet& ranges,
                  const MultilaterationOptions& options) {
  Fix fix = multilaterate_unsettled(layout, ranges, options);
  settle_unused(fix);
  return fix;
}

CramerRaoBound cramer_rao_bound(const BeaconLayout& layout, Vec2 position_m,
                                std::span<const int> beacons, std::span<const double> sd_m,
                                bool with_speed, double speed_ratio_prior_sd) {
  CramerRaoBound bound;
  if (beacons.size() != sd_m.size())
    throw std::invalid_argument("cramer_rao_bound: one sd per beacon");
  const ConvexHull hull(layout);
  Model model{&layout, &hull, with_speed, 1.0,
              std::isfinite(speed_ratio_prior_sd) ? speed_ratio_prior_sd : 0.0};
  std::vector<Observation> obs;
  for (std::size_t i = 0; i < beacons.size(); ++i) {
    if (!(std::isfinite(sd_m[i]) && sd_m[i] > 0))
      throw std::invalid_argument("cramer_rao_bound: sd must be finite and positive");
    obs.push_back({beacons[i], 0, 0.0, sd_m[i], false});
  }
  StateMatrix n;
  StateVector g;
  const State at{position_m, 0, 1};
  normal_equations(model, obs, at, false, n, g);
  const std::optional<StateMatrix> cov = spd_inverse(n);
  if (!cov)
    return bound;
  bound.valid = true;
  bound.position_covariance_m2 = cov->topLeftCorner<2, 2>();
  bound.rms_m = std::sqrt((*cov)(0, 0) + (*cov)(1, 1));
  bound.offset_sd_m = std::sqrt((*cov)(2, 2));
  if (with_speed)
    bound.speed_ratio_sd = std::sqrt((*cov)(3, 3));
  normal_equations(model, obs, at, true, n, g);
  if (const std::optional<StateMatrix> unit = spd_inverse(n))
    bound.hdop = std::sqrt((*unit)(0, 0) + (*unit)(1, 1));
  return bound;
}

}  // namespace odoloc::sw::locate
