// Kleeman's beacon solvers (docs/kleeman-solvers.md; L. Kleeman, "Ultrasonic
// autonomous robot localisation system", sections 4.1, 4.3 and 5.2).
//
// Model, per beacon i: d_i = r_i(P) + o, r_i(P) = sqrt(|P - b_i|^2 + h_i^2),
// o the cycle's unknown common offset (metres). Differences of distances
// cancel o; two differences of three beacons fix P at an intersection of two
// hyperbolas.
//
// - solve_triple: Kleeman's eq. 4 iterated on three beacons, in the derived
//   form (the printed one has a sign error:
//   docs/kleeman-solvers.md#the-printed-eq-4-is-wrong), with the other
//   intersection (mirror) found in closed form.
// - check_triangle_inequality: eqs. 5 and 6, |d_i - d_j| <= |b_i b_j|.
// - Longsolve: section 5.2, the weighted average of the best triples.
//
// Data never throws (NaN, missing beacons, degenerate geometry give a fix with
// valid == false and the reason); a malformed layout or options throw
// std::invalid_argument.
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <optional>
#include <vector>

#include "odoloc/sw/beacon_fix.hpp"

namespace odoloc::sw::locate {

using Triple = std::array<int, 3>;  // beacon numbers b0, b1, b2

// dP/dd of a three-beacon fix: 2 x 3, metres per metre, columns d0, d1, d2.
using TripleSensitivity = Eigen::Matrix<double, 2, 3>;

// ------------------------------------------------------ three-beacon solver

struct TripleOptions {
  double tolerance_m = 1e-6;  // stop when the step |dP| is below this (Kleeman: "converges")
  int max_iterations = 20;    // then kNotConverged
  // |det J| below this is singular (kDegenerateGeometry): J's rows are
  // differences of unit vectors, so det ~ 1 in a well-spread layout and
  // 1e-6 would turn a 1 um residual into a metre.
  double min_determinant = 1e-6;
  // Further outside the layout's hull: kOutsideHull (0.25 m, as multilateration:
  // docs/beacon-solvers.md, "The mirror across a wall").
  double max_outside_hull_m = 0.25;
  // Two intersections closer than this are one (tangent hyperbolas).
  double mirror_separation_m = 1e-3;
  // Both intersections fit and lie within the allowed hull: the start point
  // decides when it is at most this fraction as far from one as from the
  // other; otherwise kMirrorAmbiguous.
  double mirror_decision_ratio = 0.5;
  double min_sd_m = 1e-4;  // floor on a distance's sd (prepare())

  // Throws std::invalid_argument naming the first bad field.
  void validate() const;
};

// One step of the derived eq. 4 at P: the move dP (metres) that changes the
// differences (d1 - d0, d2 - d1) by difference_change_m to first order.
// Cramer's rule on the rows g_i = dr_i/dP = (P - b_i)/r_i:
//     (g1 - g0) . dP = change[0],   (g2 - g1) . dP = change[1].
// With heights 0 this is Kleeman's trigonometric form exactly. nullopt when
// |det| < min_determinant. Throws std::invalid_argument for a bad triple.
std::optional<Vec2> kleeman_step(const BeaconLayout& layout, const Triple& beacons, Vec2 p_m,
                                 const std::array<double, 2>& difference_change_m,
                                 double min_determinant = TripleOptions{}.min_determinant);

// dP/dd at P (J^-1 D, D the 2 x 3 difference operator); nullopt when
// |det J| < min_determinant. Its columns sum to zero (the offset cancels).
std::optional<TripleSensitivity> triple_sensitivity(
    const BeaconLayout& layout, const Triple& beacons, Vec2 p_m,
    double min_determinant = TripleOptions{}.min_determinant);

// Kleeman's three-beacon fix, Solver::kKleemanTriple. Iterates eq. 4 from
// start_m until |dP| < tolerance_m (kNotConverged after max_iterations).
// Where J is singular on the way the iteration restarts from the closed-form
// intersections, so kDegenerateGeometry means collinear beacons or a singular
// solution (two beacons in the same direction). The other intersection, when its
// ranges are all valid, is fix.mirror_m; when both lie within the allowed
// hull and start_m does not decide (mirror_decision_ratio), the fix is
// kMirrorAmbiguous with position_m the one nearer to start_m.
// Covariance J^-1 (D Sigma D^T) J^-T, Sigma = diag(sd_i^2); hdop the same
// with unit sd; offset = mean(d_i - r_i(P)). position_m is also set on
// kMirrorAmbiguous and kOutsideHull (the rejected candidate).
// fix.beacons: the three observations in order. Throws std::invalid_argument
// for a bad layout or options, a beacon outside the layout or a repeated one.
Fix solve_triple(const BeaconLayout& layout, const std::array<Observation, 3>& observations,
                 Vec2 start_m, const TripleOptions& options = {});

// The same on a range set's primaries; fix.beacons has one entry per beacon
// of the range set (the other usable ones kUnused). A requested beacon that is
// missing gives kTooFewBeacons, one that is NaN kNonFiniteInput.
Fix solve_triple(const BeaconLayout& layout, const RangeSet& ranges, const Triple& beacons,
                 Vec2 start_m, const TripleOptions& options = {});

// ------------------------------------------------- triangle inequality

// Kleeman eqs. 5, 6: for every pair of usable primaries |d_i - d_j| <=
// |b_i b_j|_3D + tolerance_ij, with
//     tolerance_ij = sigma_factor sqrt(sd_i^2 + sd_j^2)
//                    + baseline_fraction |b_i b_j|_3D + margin_m.
struct TriangleOptions {
  double sigma_factor = 3.0;  // the timing noise of the two distances
  // A speed of sound off by this fraction scales a difference by it
  // (Kleeman resolves c to 0.25 %).
  double baseline_fraction = 0.0025;
  double margin_m = 0.01;  // beacon survey error

  void validate() const;
};

// prepared.uses with every violation marked: a measurement can only be too
// long (a late echo), so the longer of the pair is kTriangleInequality,
// rejected_by = the beacon of its largest violation, candidate = -1. A
// rejected measurement still takes part in checking the other pairs (the
// paper's rule). Shorter measurements are never rejected.
std::vector<BeaconUse> check_triangle_inequality(const BeaconLayout& layout,
                                                 const Prepared& prepared,
                                                 const TriangleOptions& options = {});

// ------------------------------------------------------------- longsolve

struct LongsolveOptions {
  TripleOptions triple;
  TriangleOptions triangle;
  int averaged_triples = 7;            // step 3: the least-error triples averaged
  int max_uses_per_beacon = 5;         // step 3: a beacon's measurement in at most this many
  double reestimate_distance_m = 1.0;  // step 2: re-estimate the errors after moving this far
  int min_triples = 3;                 // step 4: stop dropping at this many
  // Fewest valid beacons (after the triangle check) for a fix: three give
  // one triple, which fits whatever its errors (docs/beacon-solvers.md, "Why
  // four beacons"); 3 accepts such unchecked fixes.
  int min_beacons = 4;
  // Step 4: a triple deviates when its solution is further than
  // deviation_factor x its error estimate (DRMS) from the average.
  double deviation_factor = 3.0;

  void validate() const;
};

// Kleeman's longsolve (section 5.2), Solver::kLongsolve. One instance follows
// one robot: it keeps the last fix, the last least-error triple and the
// per-triple sensitivities at the position where it last estimated the errors.
// A call with a different layout starts afresh.
//
//   0. Triangle check; all C(n, 3) triples of the beacons that pass.
//   1. Quick solution: the last least-error triple, from the last fix (first
//      call: from the beacons' centroid, with the errors estimated there).
//   2. If the quick solution is more than reestimate_distance_m from where
//      the errors were estimated, re-estimate every triple's sensitivity
//      there. A triple's error is e = sqrt(trace(S diag(sd^2) S^T)), S its
//      sensitivity: the RMS radial error of its fix (DRMS).
//   3. Weighted average (weights 1/e) of the averaged_triples least-error
//      triples that solve, skipping a triple that would use a beacon more
//      than max_uses_per_beacon times.
//   4. While some triples lie further than deviation_factor e from the
//      average: drop the furthest of those and refill from the next best,
//      until none deviates or min_triples are left.
//   Ours: 5. If step 4 stopped with deviants, repeat 3-4 without each beacon
//      in turn; keep the consistent average of the most triples (at least
//      min_triples), else kInconsistent. 6. A measurement can only be too
//      long: one shorter than the fix predicts by more than the triangle
//      tolerance (sigma_factor sqrt(sd^2 + trace Cov) + margin_m) makes the
//      fix kInconsistent (two echoes agreeing on a wrong point).
//
// Beacons left out of the average because triples with them were dropped (or
// by step 5) are kTripleDeviation, other left-out ones kUnused. Covariance:
// the average is linear in the distances, P = M d with M = sum(w_t S_t) /
// sum(w_t) (S_t at each triple's solution), so Cov = M diag(sd^2) M^T, shared
// beacons included; hdop = sqrt(trace(M M^T)). iterations = eq. 4 steps of
// every triple tried. position_m is also set on kInconsistent and
// kOutsideHull.
class Longsolve {
 public:
  explicit Longsolve(const LongsolveOptions& options = {});

  Fix solve(const BeaconLayout& layout, const RangeSet& ranges);
  void reset();  // forget the robot: the next call is a first call

  [[nodiscard]] const LongsolveOptions& options() const { return options_; }
  // Where the errors were last estimated, and how many times so far (step 2).
  [[nodiscard]] std::optional<Vec2> errors_estimated_at() const { return estimated_at_; }
  [[nodiscard]] int error_estimations() const { return estimations_; }
  // The least-error triple of the last valid fix (step 1's next quick solution).
  [[nodiscard]] std::optional<Triple> best_triple() const { return best_; }
  // The triples of the last call's average, least error first.
  [[nodiscard]] const std::vector<Triple>& averaged() const { return averaged_; }

 private:
  Fix solve_unsettled(const BeaconLayout& layout, const RangeSet& ranges);
  // Sensitivity of a triple at estimated_at_ (nullopt: singular there),
  // computed on first use after each estimation.
  const std::optional<TripleSensitivity>& sensitivity(const BeaconLayout& layout,
                                                      const Triple& triple);
  void estimate_at(Vec2 p);

  LongsolveOptions options_;
  std::vector<Beacon> layout_;  // the layout the state below belongs to
  std::optional<Vec2> last_fix_;
  std::optional<Triple> best_;
  std::optional<Vec2> estimated_at_;
  int estimations_ = 0;
  std::map<Triple, std::optional<TripleSensitivity>> sensitivities_;
  std::vector<Triple> averaged_;
};

}  // namespace odoloc::sw::locate
