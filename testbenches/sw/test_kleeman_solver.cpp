// Kleeman's beacon solvers (soc_software kleeman_solver) against independent
// references: the trigonometric form of the derived eq. 4 written out here
// from docs/kleeman-solvers.md, distances computed in long double from known
// points, hyperbola intersections found by a grid search, the unit-weight
// Jacobian with the offset column, finite differences of the solvers' own
// outputs for their covariances, and hand-worked triangle-inequality cases.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "beacon_geometry.hpp"
#include "odoloc/sw/kleeman_solver.hpp"

namespace {

using namespace odoloc::sw::locate;  // NOLINT(google-build-using-namespace)
using odoloc::tb::exact_range;
using odoloc::tb::exact_range_set;
using odoloc::tb::kleeman_layout;
using LD = long double;

// Kleeman's room: 10 m square, corners and mid-walls, 0.3 m from the walls.
BeaconLayout room(double height_m = 0) {
  return kleeman_layout(10, 10, 0.3, height_m);
}

double distance(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

Vec2 random_point(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  const double x = u(rng);
  return {x, u(rng)};
}

Vec2 jitter(std::mt19937_64& rng, Vec2 p, double radius) {
  const Vec2 d = random_point(rng, -radius, radius);
  return {p.x + d.x, p.y + d.y};
}

std::array<Observation, 3> exact_triple(const BeaconLayout& layout, const Triple& t, Vec2 p,
                                        LD offset, std::array<double, 3> sd = {1e-3, 1e-3, 1e-3}) {
  std::array<Observation, 3> obs;
  for (std::size_t k = 0; k < 3; ++k)
    obs[k] = {t[k], 0,
              static_cast<double>(exact_range(layout, static_cast<std::size_t>(t[k]), p) + offset),
              sd[k], false};
  return obs;
}

std::vector<Triple> all_triples(int n) {
  std::vector<Triple> out;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c = b + 1; c < n; ++c)
        out.push_back({a, b, c});
  return out;
}

bool collinear_in_room(const Triple& t) {
  return t == Triple{0, 1, 2} || t == Triple{3, 4, 5};
}

// ---------------------------------------------- eq. 4 in trigonometric form

// psi_i: bearing of beacon i from P (Kleeman Fig. 8).
std::array<double, 3> bearings(const BeaconLayout& layout, const Triple& t, Vec2 p) {
  std::array<double, 3> psi{};
  for (std::size_t i = 0; i < 3; ++i) {
    const Vec2 b = layout.beacons[static_cast<std::size_t>(t[i])].position_m;
    psi[i] = std::atan2(b.y - p.y, b.x - p.x);
  }
  return psi;
}

// The derived eq. 4 and its delta-y (docs/kleeman-solvers.md), c10 = d(d1 - d0),
// c21 = d(d2 - d1).
Vec2 derived_trig_step(const BeaconLayout& layout, const Triple& t, Vec2 p, double c10,
                       double c21) {
  const auto [p0, p1, p2] = bearings(layout, t, p);
  const double s12 = (p1 + p2) / 2;
  const double s01 = (p0 + p1) / 2;
  const double a = c10 / (2 * std::sin((p0 - p1) / 2) * std::sin((p2 - p0) / 2));
  const double b = c21 / (2 * std::sin((p1 - p2) / 2) * std::sin((p2 - p0) / 2));
  return {a * std::cos(s12) - b * std::cos(s01), a * std::sin(s12) - b * std::sin(s01)};
}

// Eq. 4 as printed, and its delta-y "similar" (sin for cos): the deviation.
Vec2 printed_step(const BeaconLayout& layout, const Triple& t, Vec2 p, double c10, double c21) {
  const auto [p0, p1, p2] = bearings(layout, t, p);
  const double a = -(-c21) / (2 * std::sin((p0 - p2) / 2) * std::sin((p1 - p2) / 2));
  const double b = -(-c10) / (2 * std::sin((p2 - p0) / 2) * std::sin((p1 - p0) / 2));
  return {a * std::cos((p0 + p1) / 2) + b * std::cos((p2 + p1) / 2),
          a * std::sin((p0 + p1) / 2) + b * std::sin((p2 + p1) / 2)};
}

// The change of (d1 - d0, d2 - d1) between two points, in long double.
std::array<double, 2> difference_change(const BeaconLayout& layout, const Triple& t, Vec2 from,
                                        Vec2 to) {
  const auto diff = [&](std::size_t i, std::size_t j, Vec2 p) {
    return exact_range(layout, static_cast<std::size_t>(t[j]), p) -
           exact_range(layout, static_cast<std::size_t>(t[i]), p);
  };
  return {static_cast<double>(diff(0, 1, to) - diff(0, 1, from)),
          static_cast<double>(diff(1, 2, to) - diff(1, 2, from))};
}

TEST(KleemanStep, CramerEqualsTheTrigonometricFormAtHeightZero) {
  const BeaconLayout layout = room();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> change(-1e-2, 1e-2);
  const std::vector<Triple> triples = all_triples(6);
  int compared = 0;
  for (int n = 0; n < 2000; ++n) {
    const Vec2 p = random_point(rng, 0.5, 9.5);
    const Triple& t = triples[static_cast<std::size_t>(n) % triples.size()];
    const std::array<double, 2> c{change(rng), change(rng)};
    const std::optional<Vec2> step = kleeman_step(layout, t, p, c);
    if (collinear_in_room(t) && !step)
      continue;  // the room's collinear triples can be singular on their line's extension only
    ASSERT_TRUE(step.has_value()) << n;
    const Vec2 trig = derived_trig_step(layout, t, p, c[0], c[1]);
    const double scale = 1 + std::hypot(trig.x, trig.y);
    EXPECT_NEAR(step->x, trig.x, 1e-12 * scale) << n;
    EXPECT_NEAR(step->y, trig.y, 1e-12 * scale) << n;
    ++compared;
  }
  EXPECT_GT(compared, 1900);
}

TEST(KleemanStep, RecoversSmallKnownMovesWithAndWithoutHeights) {
  std::mt19937_64 rng(12);
  for (const double height : {0.0, 1.5}) {
    const BeaconLayout layout = room(height);
    for (int n = 0; n < 1000; ++n) {
      const Vec2 p = random_point(rng, 0.5, 9.5);
      const Triple t{0, 2, 4};
      const Vec2 move = random_point(rng, -1e-5, 1e-5);
      const Vec2 q{p.x + move.x, p.y + move.y};
      const std::optional<Vec2> step =
          kleeman_step(layout, t, p, difference_change(layout, t, p, q));
      ASSERT_TRUE(step.has_value());
      // First order: the error is second order in the move.
      EXPECT_LT(distance(*step, move), 1e-3 * std::hypot(move.x, move.y)) << n;
    }
  }
}

// The design note's numeric check: beacons (0,0), (10,0), (5,9), robot at
// (4,3), true move (1e-4, -2e-4).
TEST(KleemanStep, PrintedEquation4HasTheWrongSignDocumentedDeviation) {
  BeaconLayout layout;
  layout.beacons = {{{0, 0}, 0}, {{10, 0}, 0}, {{5, 9}, 0}};
  const Triple t{0, 1, 2};
  const Vec2 p{4, 3};
  const std::array<double, 2> c = difference_change(layout, t, p, {4 + 1e-4, 3 - 2e-4});
  const std::optional<Vec2> step = kleeman_step(layout, t, p, c);
  ASSERT_TRUE(step.has_value());
  EXPECT_NEAR(step->x, 1e-4, 1e-8);
  EXPECT_NEAR(step->y, -2e-4, 1e-8);
  const Vec2 printed = printed_step(layout, t, p, c[0], c[1]);
  EXPECT_NEAR(printed.x, -5.7e-5, 0.1e-5);  // the wrong sign of the second term
}

// ------------------------------------------------------ three-beacon solver

TEST(SolveTriple, ExactRangesGiveThePointToANanometre) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> offset(-2, 2);
  int solved = 0;
  int max_iterations = 0;
  double worst = 0;
  for (const double height : {0.0, 1.5}) {
    const BeaconLayout layout = room(height);
    for (int n = 0; n < 200; ++n) {
      const Vec2 p = random_point(rng, 0.5, 9.5);
      const LD o = offset(rng);
      for (const Triple& t : all_triples(6)) {
        const Fix fix = solve_triple(layout, exact_triple(layout, t, p, o), jitter(rng, p, 0.1));
        if (collinear_in_room(t)) {
          EXPECT_EQ(fix.reason, NoFixReason::kDegenerateGeometry);
          continue;
        }
        ASSERT_TRUE(fix.valid) << name(fix.reason) << " at " << p.x << ", " << p.y;
        EXPECT_EQ(fix.solver, Solver::kKleemanTriple);
        EXPECT_LT(distance(fix.position_m, p), 1e-9);
        EXPECT_NEAR(fix.offset_m, static_cast<double>(o), 1e-9);
        for (const BeaconUse& u : fix.beacons) {
          EXPECT_EQ(u.status, BeaconStatus::kUsed);
          EXPECT_NEAR(u.residual_m, 0, 1e-9);
        }
        EXPECT_EQ(fix.dof, 0);
        worst = std::max(worst, distance(fix.position_m, p));
        max_iterations = std::max(max_iterations, fix.iterations);
        ++solved;
      }
    }
  }
  EXPECT_EQ(solved, 2 * 200 * 18);
  EXPECT_LE(max_iterations, 6);
  std::printf("exact triples: %d fixes, worst error %.2g m, at most %d iterations\n", solved, worst,
              max_iterations);
}

// Iterating the printed eq. 4 with the same starts, stopping rule and
// iteration limit: it converges nowhere.
TEST(SolveTriple, PrintedEquation4DoesNotConvergeDocumentedDeviation) {
  const BeaconLayout layout = room();
  std::mt19937_64 rng(14);
  const Triple t{0, 2, 4};
  int printed_converged = 0;
  for (int n = 0; n < 300; ++n) {
    const Vec2 p = random_point(rng, 0.5, 9.5);
    const Vec2 start = jitter(rng, p, 0.1);
    Vec2 q = start;
    for (int i = 0; i < TripleOptions{}.max_iterations; ++i) {
      const std::array<double, 2> c = difference_change(layout, t, q, p);
      const Vec2 s = printed_step(layout, t, q, c[0], c[1]);
      q = {q.x + s.x, q.y + s.y};
    }
    printed_converged += distance(q, p) < 1e-9 ? 1 : 0;
    const Fix fix = solve_triple(layout, exact_triple(layout, t, p, 0.5L), start);
    ASSERT_TRUE(fix.valid);
    EXPECT_LT(distance(fix.position_m, p), 1e-9);
  }
  EXPECT_EQ(printed_converged, 0);
}

// The triple's covariance against finite differences of its own position
// (the true dP/dd), and its HDOP against the unit-weight Jacobian H = [g_i 1]
// of the offset model: sqrt(trace of the position block of (H^T H)^-1).
TEST(SolveTriple, CovarianceHdopAndOffsetAreTheLinearisedPropagation) {
  std::mt19937_64 rng(15);
  const std::array<double, 3> sd{1e-3, 2e-3, 0.5e-3};
  for (const double height : {0.0, 1.5}) {
    const BeaconLayout layout = room(height);
    for (int n = 0; n < 50; ++n) {
      const Vec2 p = random_point(rng, 0.5, 9.5);
      const Triple t{1, 3, 5};
      const std::array<Observation, 3> obs = exact_triple(layout, t, p, 0.7L, sd);
      const Fix fix = solve_triple(layout, obs, p);
      ASSERT_TRUE(fix.valid);
      Eigen::Matrix<double, 3, 3> jacobian;  // rows x, y, offset; columns d0, d1, d2
      const double h = 1e-6;
      for (std::size_t k = 0; k < 3; ++k) {
        std::array<Observation, 3> up = obs, down = obs;
        up[k].distance_m += h;
        down[k].distance_m -= h;
        const Fix a = solve_triple(layout, up, p);
        const Fix b = solve_triple(layout, down, p);
        jacobian.col(static_cast<Eigen::Index>(k)) << (a.position_m.x - b.position_m.x) / (2 * h),
            (a.position_m.y - b.position_m.y) / (2 * h), (a.offset_m - b.offset_m) / (2 * h);
      }
      const Eigen::Matrix3d sigma =
          Eigen::Vector3d(sd[0] * sd[0], sd[1] * sd[1], sd[2] * sd[2]).asDiagonal();
      const Eigen::Matrix3d cov = jacobian * sigma * jacobian.transpose();
      const double scale = cov.topLeftCorner<2, 2>().norm();
      EXPECT_LT((fix.covariance_m2 - cov.topLeftCorner<2, 2>()).norm(), 1e-5 * scale) << n;
      EXPECT_NEAR(fix.offset_sd_m, std::sqrt(cov(2, 2)), 1e-5 * std::sqrt(cov(2, 2)));

      Eigen::Matrix3d hm;
      for (std::size_t i = 0; i < 3; ++i) {
        const Vec2 b = layout.beacons[static_cast<std::size_t>(t[i])].position_m;
        const double r =
            static_cast<double>(exact_range(layout, static_cast<std::size_t>(t[i]), p));
        hm.row(static_cast<Eigen::Index>(i)) << (p.x - b.x) / r, (p.y - b.y) / r, 1;
      }
      const Eigen::Matrix3d unit = (hm.transpose() * hm).inverse();
      EXPECT_NEAR(fix.hdop, std::sqrt(unit(0, 0) + unit(1, 1)), 1e-9 * fix.hdop) << n;
    }
  }
}

// ------------------------------------------------------------------ mirrors

// Every intersection of the two hyperbolas of (t, p) in [lo, hi]^2: grid
// points where F = (dr10 - k10)^2 + (dr21 - k21)^2 is a local minimum below
// the grid's reach, refined by Newton's method with a finite-difference
// Jacobian, all in long double.
std::vector<Vec2> grid_intersections(const BeaconLayout& layout, const Triple& t, Vec2 p, double lo,
                                     double hi, double step) {
  const auto range = [&](std::size_t i, LD x, LD y) {
    const Beacon& b = layout.beacons[static_cast<std::size_t>(t[i])];
    const LD dx = x - b.position_m.x, dy = y - b.position_m.y, dh = b.height_m;
    return std::sqrt(dx * dx + dy * dy + dh * dh);
  };
  const LD k10 = range(1, p.x, p.y) - range(0, p.x, p.y);
  const LD k21 = range(2, p.x, p.y) - range(1, p.x, p.y);
  const auto residual = [&](LD x, LD y) {
    return std::array<LD, 2>{range(1, x, y) - range(0, x, y) - k10,
                             range(2, x, y) - range(1, x, y) - k21};
  };
  const auto f = [&](LD x, LD y) {
    const auto [a, b] = residual(x, y);
    return a * a + b * b;
  };
  std::vector<Vec2> found;
  const int n = static_cast<int>((hi - lo) / step);
  for (int i = 1; i < n; ++i)
    for (int j = 1; j < n; ++j) {
      LD x = lo + i * step, y = lo + j * step;
      const LD v = f(x, y);
      if (v > 8 * step * step)
        continue;
      bool minimum = true;
      for (int di = -1; di <= 1 && minimum; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          if ((di != 0 || dj != 0) && f(x + di * step, y + dj * step) < v)
            minimum = false;
      if (!minimum)
        continue;
      for (int newton = 0; newton < 30; ++newton) {
        const LD h = 1e-9L;
        const auto [r0, r1] = residual(x, y);
        const auto [ax, bx] = residual(x + h, y);
        const auto [ay, by] = residual(x, y + h);
        const LD j00 = (ax - r0) / h, j01 = (ay - r0) / h, j10 = (bx - r1) / h, j11 = (by - r1) / h;
        const LD det = j00 * j11 - j01 * j10;
        x -= (r0 * j11 - j01 * r1) / det;
        y -= (j00 * r1 - j10 * r0) / det;
      }
      const Vec2 q{static_cast<double>(x), static_cast<double>(y)};
      const bool known = std::any_of(found.begin(), found.end(),
                                     [&](Vec2 other) { return distance(other, q) < 1e-6; });
      if (f(x, y) < 1e-24L && !known)
        found.push_back(q);
    }
  return found;
}

// Near the top wall, beacons 2, 4, 5: the hyperbolas cross again 0.59 m
// outside the beacons' hull, within a 2 m allowance.
TEST(SolveTriple, FindsTheMirrorAndLetsTheStartDecide) {
  TripleOptions wide;
  wide.max_outside_hull_m = 2.0;
  const BeaconLayout layout = room();
  const Triple t{2, 4, 5};
  const Vec2 p{7.391, 9.223};
  const std::vector<Vec2> ref = grid_intersections(layout, t, p, -5, 15, 0.01);
  ASSERT_EQ(ref.size(), 2u);
  const Vec2 mirror = distance(ref[0], p) > 1e-6 ? ref[0] : ref[1];
  EXPECT_LT(std::min(distance(ref[0], p), distance(ref[1], p)), 1e-9);
  EXPECT_GT(distance(mirror, p), 0.5);
  EXPECT_GT(layout.distance_outside_hull_m(mirror), 0.5);
  const std::array<Observation, 3> obs = exact_triple(layout, t, p, 0.25L);

  const Fix near_truth = solve_triple(layout, obs, {7.3, 9.0}, wide);
  ASSERT_TRUE(near_truth.valid);
  EXPECT_LT(distance(near_truth.position_m, p), 1e-9);
  ASSERT_TRUE(near_truth.mirror_m.has_value());
  EXPECT_LT(distance(*near_truth.mirror_m, mirror), 1e-9);

  // The data fit the mirror as well: from next to it, it is the fix.
  const Fix near_mirror = solve_triple(layout, obs, {mirror.x - 0.05, mirror.y}, wide);
  ASSERT_TRUE(near_mirror.valid);
  EXPECT_LT(distance(near_mirror.position_m, mirror), 1e-9);
  EXPECT_LT(distance(*near_mirror.mirror_m, p), 1e-9);

  // From the room's centre neither is markedly nearer: ambiguous, both given.
  const Fix centre = solve_triple(layout, obs, {5, 5}, wide);
  EXPECT_FALSE(centre.valid);
  EXPECT_EQ(centre.reason, NoFixReason::kMirrorAmbiguous);
  ASSERT_TRUE(centre.mirror_m.has_value());
  EXPECT_LT(distance(centre.position_m, p), 1e-9);  // the nearer one
  EXPECT_LT(distance(*centre.mirror_m, mirror), 1e-9);

  // The default allowance (0.25 m) makes the mirror implausible.
  const Fix inside = solve_triple(layout, obs, {5, 5});
  ASSERT_TRUE(inside.valid);
  EXPECT_LT(distance(inside.position_m, p), 1e-9);
  EXPECT_LT(distance(*inside.mirror_m, mirror), 1e-9);
}

TEST(SolveTriple, NoMirrorWhereTheOtherRootNeedsANegativeRange) {
  const BeaconLayout layout = room();
  const Triple t{0, 2, 4};
  const Vec2 p{5.2, 4.1};
  EXPECT_EQ(grid_intersections(layout, t, p, -15, 25, 0.02).size(), 1u);
  const Fix fix = solve_triple(layout, exact_triple(layout, t, p, 0.0L), {5, 5});
  ASSERT_TRUE(fix.valid);
  EXPECT_LT(distance(fix.position_m, p), 1e-9);
  EXPECT_FALSE(fix.mirror_m.has_value());
}

// ----------------------------------------------------- degenerate and invalid

TEST(SolveTriple, DegenerateGeometryAndInvalidInputsGiveNoFix) {
  const BeaconLayout layout = room();
  const Vec2 p{4, 6};
  // Collinear beacons (the bottom wall).
  EXPECT_EQ(solve_triple(layout, exact_triple(layout, {0, 1, 2}, p, 0), p).reason,
            NoFixReason::kDegenerateGeometry);
  // b0 and b1 in the same direction from the robot: the hyperbola d1 - d0 is
  // the ray behind b1, tangent to everything.
  BeaconLayout inner;
  inner.beacons = {{{0, 0}, 0}, {{3, 3}, 0}, {{10, 0}, 0}, {{0, 10}, 0}};
  const Fix ray = solve_triple(inner, exact_triple(inner, {0, 1, 2}, {4, 4}, 0), {4.2, 3.9});
  EXPECT_FALSE(ray.valid);
  EXPECT_EQ(ray.reason, NoFixReason::kDegenerateGeometry);
  // NaN.
  std::array<Observation, 3> obs = exact_triple(layout, {0, 2, 4}, p, 0);
  obs[1].distance_m = std::nan("");
  EXPECT_EQ(solve_triple(layout, obs, p).reason, NoFixReason::kNonFiniteInput);
  // Far outside the hull: the fix is there, but not allowed.
  const Vec2 outside{15, 5};
  const Fix far = solve_triple(layout, exact_triple(layout, {0, 2, 4}, outside, 0), outside);
  EXPECT_EQ(far.reason, NoFixReason::kOutsideHull);
  EXPECT_LT(distance(far.position_m, outside), 1e-9);
  // A start where J is singular (beacons 0 and 1 in the same direction):
  // restarted from the closed-form intersections.
  const Fix singular_start = solve_triple(layout, exact_triple(layout, {0, 1, 3}, p, 0), {7, 0.3});
  ASSERT_TRUE(singular_start.valid) << name(singular_start.reason);
  EXPECT_LT(distance(singular_start.position_m, p), 1e-9);
  // One iteration is not enough from afar.
  TripleOptions once;
  once.max_iterations = 1;
  EXPECT_EQ(solve_triple(layout, exact_triple(layout, {0, 2, 4}, p, 0), {5, 5}, once).reason,
            NoFixReason::kNotConverged);
  // Configuration errors throw.
  EXPECT_THROW(solve_triple(layout, exact_triple(layout, {0, 2, 2}, p, 0), p),
               std::invalid_argument);
  obs = exact_triple(layout, {0, 2, 4}, p, 0);
  obs[2].beacon = 6;
  EXPECT_THROW(solve_triple(layout, obs, p), std::invalid_argument);
  BeaconLayout broken = layout;
  broken.beacons[3].height_m = std::nan("");
  EXPECT_THROW(solve_triple(broken, exact_triple(layout, {0, 2, 4}, p, 0), p),
               std::invalid_argument);
  TripleOptions bad;
  bad.mirror_decision_ratio = 1;
  EXPECT_THROW(solve_triple(layout, exact_triple(layout, {0, 2, 4}, p, 0), p, bad),
               std::invalid_argument);
}

TEST(SolveTriple, RangeSetOverloadMarksEveryBeacon) {
  const BeaconLayout layout = room();
  const Vec2 p{6.5, 3.2};
  RangeSet ranges = exact_range_set(layout, p, 1.5);
  const Fix fix = solve_triple(layout, ranges, {1, 3, 5}, {6, 3});
  ASSERT_TRUE(fix.valid);
  EXPECT_LT(distance(fix.position_m, p), 1e-9);
  ASSERT_EQ(fix.beacons.size(), 6u);
  for (const BeaconUse& u : fix.beacons)
    EXPECT_EQ(u.status, u.beacon % 2 == 1 ? BeaconStatus::kUsed : BeaconStatus::kUnused);
  EXPECT_EQ(fix.used(), 3);

  ranges.beacons[3].primary = -1;  // missing
  EXPECT_EQ(solve_triple(layout, ranges, {1, 3, 5}, p).reason, NoFixReason::kTooFewBeacons);
  ranges = exact_range_set(layout, p, 1.5);
  ranges.beacons[5].candidates[0].distance_m = INFINITY;
  const Fix nan = solve_triple(layout, ranges, {1, 3, 5}, p);
  EXPECT_EQ(nan.reason, NoFixReason::kNonFiniteInput);
  EXPECT_EQ(nan.beacons[5].status, BeaconStatus::kNonFinite);
}

// An echo among the three moves the fix; the beacons left out then show it
// in their residuals, and one much shorter than the fix predicts refutes it
// (a measurement can only be too long). At least one does at every point
// tried here; without it the fix would be valid and metres off.
TEST(SolveTriple, ABeaconLeftOutRefutesAFixWithAnEcho) {
  const BeaconLayout layout = room();
  std::mt19937_64 rng(31);
  int refuted = 0, points = 0;
  for (int n = 0; n < 200; ++n) {
    const Vec2 p = random_point(rng, 1, 9);
    RangeSet ranges = exact_range_set(layout, p, 1.5);
    const Fix clean = solve_triple(layout, ranges, {0, 2, 4}, p);
    ASSERT_TRUE(clean.valid);
    for (const int b : {1, 3, 5})  // exact: the left-out residuals vanish
      EXPECT_NEAR(clean.beacons[static_cast<std::size_t>(b)].residual_m, 0, 1e-9);
    ranges.beacons[2].candidates[0].distance_m += 0.5;
    const Fix echo = solve_triple(layout, ranges, {0, 2, 4}, p);
    if (!std::isfinite(echo.position_m.x) || distance(echo.position_m, p) < 0.05)
      continue;  // no solution, or the echo barely moves it
    ++points;
    if (!echo.valid) {  // refuted, or already outside the room
      EXPECT_TRUE(echo.reason == NoFixReason::kInconsistent ||
                  echo.reason == NoFixReason::kOutsideHull)
          << name(echo.reason);
      refuted += echo.reason == NoFixReason::kInconsistent ? 1 : 0;
    }
    EXPECT_FALSE(echo.valid) << p.x << ", " << p.y;
  }
  EXPECT_GT(points, 100);
  EXPECT_GT(refuted, points / 2);
}

// ------------------------------------------------- triangle inequality

// A (0,0), B (4,0), C (0,3): |AB| = 4, |AC| = 3, |BC| = 5.
BeaconLayout right_triangle(double c_height = 0) {
  BeaconLayout layout;
  layout.beacons = {{{0, 0}, 0}, {{4, 0}, 0}, {{0, 3}, c_height}};
  return layout;
}

RangeSet distances(std::array<double, 3> d, double sd = 1e-3) {
  RangeSet set;
  for (const double x : d)
    set.beacons.push_back({{{x, sd, {}}}, 0, {}});
  return set;
}

// The default tolerance of a pair with 1 mm each: 3 sqrt(2) mm + 0.25 % of the
// baseline + 1 cm.
double tolerance(double baseline) {
  return 3 * std::sqrt(2.0) * 1e-3 + 0.0025 * baseline + 0.01;
}

std::vector<BeaconUse> triangle(const BeaconLayout& layout, const RangeSet& set) {
  return check_triangle_inequality(layout, prepare(layout, set));
}

TEST(TriangleInequality, TheLongerOfAViolatingPairIsRejected) {
  const BeaconLayout layout = right_triangle();
  // Consistent: the robot at (1, 1), offset 7 m.
  const double a = std::hypot(1.0, 1.0) + 7, b = std::hypot(3.0, 1.0) + 7,
               c = std::hypot(1.0, 2.0) + 7;
  for (const BeaconUse& u : triangle(layout, distances({a, b, c})))
    EXPECT_EQ(u.status, BeaconStatus::kUsed);
  // A late by enough that d_A - d_C exceeds |AC| + tolerance: A goes, C (the
  // shorter) stays; just within the tolerance both stay.
  const double limit = c + 3 + tolerance(3);
  std::vector<BeaconUse> uses = triangle(layout, distances({limit + 1e-4, b, c}));
  EXPECT_EQ(uses[0].status, BeaconStatus::kTriangleInequality);
  EXPECT_EQ(uses[0].rejected_by, 2);
  EXPECT_EQ(uses[0].candidate, -1);
  EXPECT_EQ(uses[1].status, BeaconStatus::kUsed);
  EXPECT_EQ(uses[2].status, BeaconStatus::kUsed);
  uses = triangle(layout, distances({limit - 1e-4, b, c}));
  EXPECT_EQ(uses[0].status, BeaconStatus::kUsed);
  // With C 4 m above the plane |AC| is 5 m in 3-D: the same distances pass.
  uses = triangle(right_triangle(4), distances({limit + 1e-4, b, c}));
  EXPECT_EQ(uses[0].status, BeaconStatus::kUsed);
}

// Two echoes: A late (rejected by C) and B later still. B is checked against
// A as well, although A is rejected (the paper's rule), and the check against
// C rejects it: any beacon rejecting A rejects a B that A rejects, because
// the tolerance is subadditive, so rejected_by always names a beacon that
// passed (docs/kleeman-solvers.md#triangle-inequality-eqs-5-6).
TEST(TriangleInequality, RejectedMeasurementsStillTakePart) {
  const BeaconLayout layout = right_triangle();
  const double c = std::hypot(1.0, 2.0) + 7;
  const double a = c + 3.5;  // A - C = 3.5 > 3 + tol
  const double b = a + 4.3;  // B - A = 4.3 > 4 + tol; B - C = 7.8 > 5 + tol
  const std::vector<BeaconUse> uses = triangle(layout, distances({a, b, c}));
  EXPECT_EQ(uses[0].status, BeaconStatus::kTriangleInequality);
  EXPECT_EQ(uses[0].rejected_by, 2);
  EXPECT_EQ(uses[1].status, BeaconStatus::kTriangleInequality);
  EXPECT_EQ(uses[1].rejected_by, 2);
  EXPECT_EQ(uses[2].status, BeaconStatus::kUsed);

  // Random sets with several echoes against the literal rule written out:
  // every pair, rejected or not, rejects its longer member.
  const BeaconLayout six = room();
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<double> echo(0, 8);
  for (int n = 0; n < 500; ++n) {
    RangeSet set = exact_range_set(six, random_point(rng, 0.3, 9.7), 0.3);
    for (std::size_t i = 0; i < 6; ++i)
      if (rng() % 3 == 0)
        set.beacons[i].candidates[0].distance_m += echo(rng);
    const std::vector<BeaconUse> got = triangle(six, set);
    for (std::size_t i = 0; i < 6; ++i) {
      bool rejected = false;
      for (std::size_t j = 0; j < 6; ++j) {
        const Vec2 bi = six.beacons[i].position_m, bj = six.beacons[j].position_m;
        const double base = distance(bi, bj);
        rejected = rejected || set.beacons[i].candidates[0].distance_m -
                                       set.beacons[j].candidates[0].distance_m >
                                   base + tolerance(base);
      }
      EXPECT_EQ(got[i].status == BeaconStatus::kTriangleInequality, rejected) << n << " " << i;
      if (rejected) {
        EXPECT_EQ(got[static_cast<std::size_t>(got[i].rejected_by)].status, BeaconStatus::kUsed);
      }
    }
  }
}

// -------------------------------------------------------------- longsolve

int uses_of(const std::vector<Triple>& triples, int beacon) {
  int n = 0;
  for (const Triple& t : triples)
    n += static_cast<int>(std::count(t.begin(), t.end(), beacon));
  return n;
}

TEST(Longsolve, ExactRangesGiveThePointToANanometre) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> offset(-2, 2);
  for (const double height : {0.0, 1.5}) {
    const BeaconLayout layout = room(height);
    Longsolve solver;
    for (int n = 0; n < 200; ++n) {
      const Vec2 p = random_point(rng, 0.5, 9.5);
      const double o = offset(rng);
      const Fix fix = solver.solve(layout, exact_range_set(layout, p, o));
      ASSERT_TRUE(fix.valid) << name(fix.reason);
      EXPECT_EQ(fix.solver, Solver::kLongsolve);
      EXPECT_LT(distance(fix.position_m, p), 1e-9);
      EXPECT_NEAR(fix.offset_m, o, 1e-9);
      EXPECT_LT(fix.chi2, 1e-6);
      const std::vector<Triple>& avg = solver.averaged();
      EXPECT_EQ(avg.size(), 7u);
      for (int b = 0; b < 6; ++b) {
        EXPECT_LE(uses_of(avg, b), 5);
        const BeaconStatus s = fix.beacons[static_cast<std::size_t>(b)].status;
        EXPECT_EQ(s, uses_of(avg, b) > 0 ? BeaconStatus::kUsed : BeaconStatus::kUnused);
      }
      EXPECT_EQ(solver.best_triple(), avg.front());
    }
  }
  // A tighter limit on the uses is honoured.
  LongsolveOptions three;
  three.max_uses_per_beacon = 3;
  Longsolve limited(three);
  const BeaconLayout layout = room();
  for (int n = 0; n < 50; ++n) {
    const Vec2 p = random_point(rng, 0.5, 9.5);
    const Fix fix = limited.solve(layout, exact_range_set(layout, p, 0.1));
    ASSERT_TRUE(fix.valid);
    EXPECT_LT(distance(fix.position_m, p), 1e-9);
    for (int b = 0; b < 6; ++b)
      EXPECT_LE(uses_of(limited.averaged(), b), 3);
  }
}

// One beacon's distance made 0.5 m long (an echo), at random points: the
// triples with it deviate from the average and go (or the triangle check
// takes it first), and the fix is the clean triples' one.
TEST(Longsolve, RejectsAnEcho) {
  const BeaconLayout layout = room();
  std::mt19937_64 rng(18);
  for (const double sd : {0.0, 1e-3}) {
    Longsolve solver;
    double worst = 0, sum2 = 0, worst_normalised = 0;
    int by_deviation = 0, by_triangle = 0;
    const int points = 300;
    for (int n = 0; n < points; ++n) {
      const Vec2 p = random_point(rng, 0.5, 9.5);
      RangeSet set = exact_range_set(layout, p, 0.8, std::max(sd, 1e-3), sd > 0 ? &rng : nullptr);
      const auto echo = static_cast<std::size_t>(rng() % 6);
      set.beacons[echo].candidates[0].distance_m += 0.5;
      const Fix fix = solver.solve(layout, set);
      ASSERT_TRUE(fix.valid) << name(fix.reason) << " at " << p.x << ", " << p.y;
      const BeaconStatus s = fix.beacons[echo].status;
      ASSERT_TRUE(s == BeaconStatus::kTripleDeviation || s == BeaconStatus::kTriangleInequality)
          << name(s) << " at " << p.x << ", " << p.y;
      (s == BeaconStatus::kTripleDeviation ? by_deviation : by_triangle) += 1;
      EXPECT_LT(uses_of(solver.averaged(), static_cast<int>(echo)), 1);
      const double e = distance(fix.position_m, p);
      worst = std::max(worst, e);
      sum2 += e * e;
      worst_normalised = std::max(worst_normalised, e / std::sqrt(fix.covariance_m2.trace()));
    }
    if (sd == 0) {
      EXPECT_LT(worst, 1e-9);
    } else {  // the clean beacons' noise only: within its covariance
      EXPECT_LT(std::sqrt(sum2 / points), 2e-3);
      EXPECT_LT(worst_normalised, 4);
    }
    std::printf(
        "echo +0.5 m, sd %.0f mm: %d by deviation, %d by triangle, error rms %.2g m, "
        "worst %.2g m (%.2g x its DRMS)\n",
        sd * 1e3, by_deviation, by_triangle, std::sqrt(sum2 / points), worst, worst_normalised);
  }
  // Next to beacon 1 on its wall, beacon 2's echo breaks the triangle with 1.
  RangeSet set = exact_range_set(layout, {4, 0.5}, 0.8);
  set.beacons[2].candidates[0].distance_m += 0.5;
  Longsolve solver;
  const Fix fix = solver.solve(layout, set);
  ASSERT_TRUE(fix.valid);
  EXPECT_EQ(fix.beacons[2].status, BeaconStatus::kTriangleInequality);
  EXPECT_EQ(fix.beacons[2].rejected_by, 1);
  EXPECT_NEAR(fix.beacons[2].residual_m, 0.5, 1e-6);
  EXPECT_LT(distance(fix.position_m, {4, 0.5}), 1e-9);
}

// Two echoes (+0.5 m, +0.3 m) on random beacons: rejected, or the fix is
// refused. The exception: four beacons, two of them late, that agree on
// another point while the two clean ones look late from there; one cycle
// cannot tell (docs/kleeman-solvers.md#limits).
TEST(Longsolve, TwoEchoesAreRejectedOrTheFixIsRefused) {
  const BeaconLayout layout = room();
  std::mt19937_64 rng(20);
  int correct = 0, refused = 0, wrong = 0;
  double worst_wrong = 0;
  const int points = 600;
  for (int n = 0; n < points; ++n) {
    const Vec2 p = random_point(rng, 0.5, 9.5);
    RangeSet set = exact_range_set(layout, p, 0.3);
    const auto a = static_cast<std::size_t>(rng() % 6);
    const auto b = (a + 1 + static_cast<std::size_t>(rng() % 5)) % 6;
    set.beacons[a].candidates[0].distance_m += 0.5;
    set.beacons[b].candidates[0].distance_m += 0.3;
    const Fix fix = Longsolve().solve(layout, set);
    if (!fix.valid) {
      EXPECT_EQ(fix.reason, NoFixReason::kInconsistent);
      ++refused;
    } else if (distance(fix.position_m, p) < 1e-9) {
      EXPECT_NE(fix.beacons[a].status, BeaconStatus::kUsed);
      EXPECT_NE(fix.beacons[b].status, BeaconStatus::kUsed);
      ++correct;
    } else {
      ++wrong;
      worst_wrong = std::max(worst_wrong, distance(fix.position_m, p));
    }
  }
  EXPECT_GT(correct, points * 85 / 100);
  EXPECT_LE(wrong, points / 200);
  std::printf("two echoes: %d correct, %d refused (inconsistent), %d wrong (up to %.2f m) of %d\n",
              correct, refused, wrong, worst_wrong, points);
}

// A measurement can only be too long: one shorter than every other beacon
// says is refused, not averaged away.
TEST(Longsolve, AShortMeasurementIsInconsistent) {
  const BeaconLayout layout = room();
  RangeSet set = exact_range_set(layout, {6.2, 4.4}, 0.3);
  set.beacons[3].candidates[0].distance_m -= 0.3;
  const Fix fix = Longsolve().solve(layout, set);
  EXPECT_FALSE(fix.valid);
  EXPECT_EQ(fix.reason, NoFixReason::kInconsistent);
  EXPECT_NEAR(fix.beacons[3].residual_m, -0.3, 1e-6);
  EXPECT_LT(distance(fix.position_m, {6.2, 4.4}), 1e-9);
}

TEST(Longsolve, ReestimatesTheErrorsOnlyAfterMovingAMetre) {
  const BeaconLayout layout = room();
  Longsolve solver;
  const auto at = [&](Vec2 p) {
    const Fix fix = solver.solve(layout, exact_range_set(layout, p, 0.2));
    EXPECT_TRUE(fix.valid);
    return solver.error_estimations();
  };
  // First call: estimated at the centre, then at the fix 2.8 m away.
  const int first = at({3, 3});
  EXPECT_EQ(first, 2);
  EXPECT_LT(distance(*solver.errors_estimated_at(), {3, 3}), 1e-9);
  EXPECT_EQ(at({3.6, 3}), first);       // 0.6 m
  EXPECT_EQ(at({3.9, 3.3}), first);     // 0.95 m from (3, 3)
  EXPECT_EQ(at({4.05, 3}), first + 1);  // 1.05 m
  EXPECT_LT(distance(*solver.errors_estimated_at(), {4.05, 3}), 1e-9);
  EXPECT_EQ(at({4.05, 3.95}), first + 1);  // 0.95 m from there
  // Another layout: a fresh start.
  BeaconLayout moved = layout;
  moved.beacons[0].position_m.x += 0.01;
  EXPECT_TRUE(solver.solve(moved, exact_range_set(moved, {5.2, 5.1}, 0.2)).valid);
  EXPECT_EQ(solver.error_estimations(), 1);  // the centre is within a metre
}

// The average is linear in the distances: its covariance against finite
// differences of the fix, with unequal deviations, and its HDOP against the
// least-squares bound over the beacons it used (never below it).
TEST(Longsolve, CovarianceIsTheLinearPropagationOfTheAverage) {
  std::mt19937_64 rng(19);
  const std::array<double, 6> sd{1e-3, 2e-3, 1.5e-3, 0.5e-3, 1e-3, 3e-3};
  double worst_ratio = INFINITY;
  for (const double height : {0.0, 1.5}) {
    const BeaconLayout layout = room(height);
    for (int n = 0; n < 20; ++n) {
      const Vec2 p = random_point(rng, 0.5, 9.5);
      RangeSet set = exact_range_set(layout, p, 0.4);
      for (std::size_t i = 0; i < 6; ++i)
        set.beacons[i].candidates[0].sd_m = sd[i];
      const Fix fix = Longsolve().solve(layout, set);
      ASSERT_TRUE(fix.valid);
      Eigen::Matrix<double, 2, 6> m;
      const double h = 1e-6;
      for (std::size_t k = 0; k < 6; ++k) {
        RangeSet up = set, down = set;
        up.beacons[k].candidates[0].distance_m += h;
        down.beacons[k].candidates[0].distance_m -= h;
        const Vec2 a = Longsolve().solve(layout, up).position_m;
        const Vec2 b = Longsolve().solve(layout, down).position_m;
        m.col(static_cast<Eigen::Index>(k)) << (a.x - b.x) / (2 * h), (a.y - b.y) / (2 * h);
      }
      Eigen::Matrix<double, 6, 1> var;
      for (std::size_t i = 0; i < 6; ++i)
        var(static_cast<Eigen::Index>(i)) = sd[i] * sd[i];
      const Eigen::Matrix2d cov = m * var.asDiagonal() * m.transpose();
      EXPECT_LT((fix.covariance_m2 - cov).norm(), 1e-5 * cov.norm()) << n;
      EXPECT_NEAR(fix.hdop, std::sqrt((m * m.transpose()).trace()), 1e-5 * fix.hdop);

      Eigen::MatrixXd hm(6, 3);
      int rows = 0;
      for (const BeaconUse& u : fix.beacons)
        if (u.status == BeaconStatus::kUsed) {
          const auto b = static_cast<std::size_t>(u.beacon);
          const Vec2 q = layout.beacons[b].position_m;
          const double r = static_cast<double>(exact_range(layout, b, p));
          hm.row(rows++) << (p.x - q.x) / r, (p.y - q.y) / r, 1;
        }
      const Eigen::Matrix3d unit = (hm.topRows(rows).transpose() * hm.topRows(rows)).inverse();
      const double least_squares = std::sqrt(unit(0, 0) + unit(1, 1));
      EXPECT_GE(fix.hdop, least_squares * (1 - 1e-9));
      worst_ratio = std::min(worst_ratio, least_squares / fix.hdop);
    }
  }
  std::printf("longsolve hdop vs least squares over the same beacons: ratio >= %.3f\n",
              worst_ratio);
}

TEST(Longsolve, InvalidInputsGiveNoFix) {
  const BeaconLayout layout = room();
  const Vec2 p{4, 6};
  Longsolve solver;
  RangeSet set = exact_range_set(layout, p, 0);
  for (const std::size_t i : {0u, 2u, 3u, 5u})
    set.beacons[i].candidates[0].distance_m = std::nan("");
  EXPECT_EQ(solver.solve(layout, set).reason, NoFixReason::kNonFiniteInput);
  set = exact_range_set(layout, p, 0);
  for (const std::size_t i : {0u, 2u, 3u, 5u})
    set.beacons[i].primary = -1;
  EXPECT_EQ(solver.solve(layout, set).reason, NoFixReason::kTooFewBeacons);
  // Six beacons on one line.
  BeaconLayout line;
  for (int i = 0; i < 6; ++i)
    line.beacons.push_back({{2.0 * i, 0}, 0});
  EXPECT_EQ(solver.solve(line, exact_range_set(line, {5, 4}, 0)).reason,
            NoFixReason::kDegenerateGeometry);
  // Far outside the room.
  EXPECT_EQ(Longsolve().solve(layout, exact_range_set(layout, {16, 5}, 0)).reason,
            NoFixReason::kOutsideHull);
  // Four beacons, one echo: every drop leaves a deviant, down to three triples.
  BeaconLayout four;
  four.beacons = {{{0.3, 0.3}, 0}, {{9.7, 0.3}, 0}, {{9.7, 9.7}, 0}, {{0.3, 9.7}, 0}};
  set = exact_range_set(four, {4.5, 5.5}, 0);
  set.beacons[1].candidates[0].distance_m += 0.5;
  const Fix inconsistent = Longsolve().solve(four, set);
  EXPECT_FALSE(inconsistent.valid);
  EXPECT_EQ(inconsistent.reason, NoFixReason::kInconsistent);
  // Three beacons: unchecked, so no fix by default; allowed, one rejected
  // by the triangle check leaves too few.
  set = exact_range_set(right_triangle(), {1, 1}, 0);
  EXPECT_EQ(Longsolve().solve(right_triangle(), set).reason, NoFixReason::kTooFewBeacons);
  LongsolveOptions three;
  three.min_beacons = 3;
  EXPECT_TRUE(Longsolve(three).solve(right_triangle(), set).valid);
  set.beacons[0].candidates[0].distance_m += 4;
  EXPECT_EQ(Longsolve(three).solve(right_triangle(), set).reason, NoFixReason::kInconsistent);
  // Configuration errors throw.
  BeaconLayout broken = layout;
  broken.beacons[1].position_m = broken.beacons[0].position_m;
  EXPECT_THROW(solver.solve(broken, exact_range_set(layout, p, 0)), std::invalid_argument);
  LongsolveOptions bad;
  bad.averaged_triples = 0;
  EXPECT_THROW(Longsolve{bad}, std::invalid_argument);
  bad = {};
  bad.triangle.margin_m = -1;
  EXPECT_THROW(Longsolve{bad}, std::invalid_argument);
}

}  // namespace
