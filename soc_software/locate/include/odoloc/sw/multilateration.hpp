// The all-beacon estimator: multilateration from times of flight with an
// unknown common offset (docs/beacon-solvers.md#all-beacon-estimator).
//
// Model, per usable beacon i (distances as the capture chain reports them):
//     d_i = k r_i(P) + o + noise_i,     r_i(P) = sqrt(|P - b_i|^2 + h_i^2),
// o the cycle's common offset (metres; GNSS's clock bias), k = c_used/c_true
// the ratio of the speed of sound the distances were computed with to the
// true one (1 when c is known; an unknown when calibrating, Kleeman 5.1),
// noise_i ~ N(0, sd_i^2) independent. State (x, y, o) or (x, y, o, k).
//
// Pipeline: the triangle-inequality check (kleeman_solver.hpp) ->
// closed-form hypotheses from beacon triples (the hyperbola
// intersection in closed form: linear in P for a given o, quadratic in o;
// both roots) -> consensus over every usable beacon, trying a beacon's later
// candidates (echoes) where its primary is suspect or disagrees (RANSAC,
// exhaustive over triples when there are few) -> weighted Gauss-Newton with
// Levenberg-Marquardt damping on the consensus -> studentised residual test,
// dropping the worst while redundancy remains -> covariance (J^T W J)^-1.
// Cost: about 7 us for 6 beacons (odoloc_bench BM_Fix_Multilateration).
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <optional>
#include <span>

#include "odoloc/sw/beacon_fix.hpp"
#include "odoloc/sw/kleeman_solver.hpp"

namespace odoloc::sw::locate {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The air temperatures the solvers accept (MultilaterationOptions, the host
// tool's --temperature), degrees Celsius, inclusive.
inline constexpr double kMinTemperatureC = -100;
inline constexpr double kMaxTemperatureC = 100;

// c = 331.3 sqrt(1 + T/273.15) m/s, dry air, T in degrees Celsius
// (reference/localisation.md; Cramer, JASA 93(5), 1993 for humidity's
// few tenths of a percent, not modelled). NaN below -273.15.
double speed_of_sound_mps(double temperature_c);
// dc/dT at T (m/s per kelvin): 0.606 near 0 C.
double speed_of_sound_slope(double temperature_c);

struct MultilaterationOptions {
  // The speed of sound assumed: from `temperature_c` when set (prior sd from
  // temperature_sd_c), else the range set's own c (taken as exact).
  std::optional<double> temperature_c;
  double temperature_sd_c = 2.0;
  // Kleeman's self-calibration: c is uncertain, with a Gaussian prior (from
  // the temperature and its sd when set, else the range set's c with a
  // relative sd of speed_of_sound_tolerance / 2), and k = c_used/c_true
  // becomes a state when at least min_beacons_to_calibrate beacons are used.
  // With fewer, c stays at the prior's mean and its uncertainty widens the
  // covariance (consider covariance). The consensus, solved at the prior's
  // c, tolerates range-difference errors of 4 prior sd x the layout's extent.
  bool calibrate_speed_of_sound = false;
  int min_beacons_to_calibrate = 5;
  double speed_of_sound_tolerance = 0.03;  // 3 %: about 10 K

  // Fewest beacons a valid fix rests on. Three fit exactly whatever their
  // errors (an echo taken for a direct pulse moves the fix unnoticed); four
  // give the one redundant measurement that can expose it. 3 accepts the
  // unchecked fixes (chi2 and dof say so).
  int min_beacons = 4;
  double min_sd_m = 1e-4;  // floor on a candidate's sd (sd 0 would claim infinite weight)
  int max_iterations = 20;
  double step_tolerance_m = 1e-7;  // stop when the position step is below this
  // How far outside the beacons' convex hull a fix may lie. Beacons stand
  // around the room's edge, so the hull is the room: near a wall lined with
  // collinear beacons, the robot's mirror image across that line explains a
  // wall echo as a direct path exactly (docs/beacon-solvers.md); only the
  // hull tells them apart.
  double max_outside_hull_m = 0.25;

  // The physical check before the consensus (Kleeman eqs. 5, 6): of a pair
  // whose distance difference exceeds their baseline, the longer primary is
  // rejected (a measurement can only be too long). Suspect primaries take no
  // part: an early spurious pulse would make the others look long. When
  // calibrating, the baseline fraction widens to 4 prior sd of c.
  bool check_triangle = true;
  TriangleOptions triangle;

  // Consensus: a candidate agrees with a hypothesis when its residual is
  // within inlier_sigmas x sd + inlier_floor_m (the floor covers the error of
  // the triple's own solution, which its geometry can magnify).
  bool robust = true;
  double inlier_sigmas = 5.0;
  double inlier_floor_m = 0.02;
  // Final test: drop the largest studentised residual beyond this while more
  // than the unknowns + 1 measurements remain.
  double residual_gate_sigmas = 4.0;
  // Triples tried: all of them when C(n,3) <= this, else this many drawn
  // with a generator seeded by `seed` (same input, same fix).
  int max_hypotheses = 64;
  std::uint64_t seed = 1;
  // With three beacons both intersections fit exactly: the one nearer to
  // this point wins when the other is at least mirror_margin_m further away
  // (else kMirrorAmbiguous); without it, a mirror inside the allowed hull
  // is ambiguous.
  std::optional<Vec2> prior_position_m;
  double mirror_margin_m = 0.5;

  // Throws std::invalid_argument naming the first bad field.
  void validate() const;
};

// Every usable beacon (and echo alternative), one fix: Solver::kGaussNewton.
// Never throws for data; throws std::invalid_argument for a bad layout or
// options.
Fix multilaterate(const BeaconLayout& layout, const RangeSet& ranges,
                  const MultilaterationOptions& options = {});

// The hyperbola intersection of three beacons in closed form, for a known
// k: zero, one or two (P, o) that reproduce the three distances exactly.
struct TripleSolution {
  Vec2 position_m;
  double offset_m = 0;
};
struct TripleSolutions {
  std::array<TripleSolution, 2> solutions;
  int count = 0;  // 0: collinear beacons or no real solution with ranges >= heights
};
TripleSolutions solve_triple_closed_form(const BeaconLayout& layout,
                                         std::span<const Observation, 3> observations,
                                         double k = 1.0);

// The Cramer-Rao bound of the model above at position P for the given
// beacons with independent Gaussian noise of sd_m each: the inverse Fisher
// information of (x, y, o) or, with_speed, (x, y, o, k) (at k = 1), k with a
// Gaussian prior of sd speed_ratio_prior_sd when finite (the Bayesian bound).
struct CramerRaoBound {
  bool valid = false;  // false: the information matrix is singular (too few or degenerate)
  Eigen::Matrix2d position_covariance_m2 = Eigen::Matrix2d::Constant(kNaN);
  double rms_m = kNaN;           // sqrt(trace of the position block)
  double hdop = kNaN;            // the same with unit sd
  double offset_sd_m = kNaN;     // sqrt of the offset's variance
  double speed_ratio_sd = kNaN;  // sd of k (relative sd of c) when with_speed
};
CramerRaoBound cramer_rao_bound(const BeaconLayout& layout, Vec2 position_m,
                                std::span<const int> beacons, std::span<const double> sd_m,
                                bool with_speed = false, double speed_ratio_prior_sd = kInfinity);

}  // namespace odoloc::sw::locate
