// Beacon fixes: the data every ultrasonic solver shares (docs/beacon-solvers.md).
//
// Input: a beacon layout (world frame, metres) and one cycle's range set:
// per beacon the candidate distances (direct pulse and echoes, earliest
// first) that the capture chain measured, all carrying one unknown common
// offset (Kleeman: the beacons and the robot share no clock):
//     candidate distance = c_used / c_true * |P - b_i|_3D + offset.
// Output: a Fix with position, covariance, HDOP, the beacons used and
// rejected with the reason, the solver, its iterations and a verdict.
//
// Pure functions over plain data: no bus, no fabric, no exceptions for data
// a real room produces (NaN, missing beacons, degenerate geometry all give a
// fix with valid == false and the reason). Only a malformed layout, which is
// configuration, throws std::invalid_argument.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "odoloc/sw/tof_measurement.hpp"

namespace odoloc::sw::locate {

using tof::Flag;
using tof::Flags;
using tof::Vec2;

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ------------------------------------------------------------------ layout

struct Beacon {
  Vec2 position_m;      // world frame
  double height_m = 0;  // above the receivers' plane: range = sqrt(planar^2 + height^2)
};

struct BeaconLayout {
  std::vector<Beacon> beacons;  // index = beacon number (Kleeman: beacon 0 sends the double pulse)

  // Throws std::invalid_argument naming the beacon: non-finite coordinates,
  // two beacons within 1 mm of each other, more than 64 beacons.
  void validate() const;
  // |P - b_i| in 3D (the beacon's height above the receivers' plane).
  [[nodiscard]] double range_m(std::size_t beacon, Vec2 p) const;
  // Distance from p to the convex hull of the beacons' positions (0 inside
  // or on it; with fewer than 3 non-collinear beacons, to their segment or
  // point; infinite without beacons). Builds the hull: for many points, use
  // ConvexHull.
  [[nodiscard]] double distance_outside_hull_m(Vec2 p) const;
};

// The convex hull of a layout's beacons, built once.
class ConvexHull {
 public:
  explicit ConvexHull(const BeaconLayout& layout);
  // As BeaconLayout::distance_outside_hull_m.
  [[nodiscard]] double distance_outside_m(Vec2 p) const;

 private:
  std::vector<Vec2> vertices_;  // counter-clockwise, collinear points dropped
};

// -------------------------------------------------------------- range set

// One candidate distance to a beacon: the direct pulse or an echo, with the
// cycle's common offset (tof::Arrival::distance_m).
struct RangeCandidate {
  double distance_m = kNaN;
  double sd_m = 0;  // timing noise only (the offset is common to the cycle)
  Flags flags;
};

struct BeaconRange {
  std::vector<RangeCandidate> candidates;  // earliest first
  int primary = -1;                        // the capture chain's pick for the direct path; -1: none
  Flags flags;                             // slot level (kMissing, kEchoSuspect, ...)
};

// One cycle of measurements; index = beacon number in the layout.
struct RangeSet {
  std::vector<BeaconRange> beacons;
  double speed_of_sound_mps = 343.2;  // the c the distances were computed with
};

// A Kleeman cycle (beacon_cycle.hpp) as a range set: candidates = the slot's
// candidates, primary = the decoder's pick, slot flags plus the cycle's.
RangeSet range_set(const tof::CycleMeasurement& cycle);

// A primary candidate with one of these flags is not a measurement at all.
inline constexpr Flags kUnusableFlags = Flags(Flag::kInvalid) | Flag::kMissing |
                                        Flag::kUnwrapAmbiguous | Flag::kLostEvents |
                                        Flag::kOverflow | Flag::kStuckChannel;
// ... with one of these it may be an echo or noise: the robust estimator
// tries the later candidates as alternatives.
inline constexpr Flags kSuspectFlags = Flags(Flag::kEchoSuspect) | Flag::kOccludedSuspect |
                                       Flag::kReferenceSuspect | Flag::kBeforeBound | Flag::kWeak |
                                       Flag::kMergedPulse | Flag::kOutOfRange;

// --------------------------------------------------------------------- fix

enum class Solver : std::uint8_t {
  kKleemanTriple,        // Kleeman eq. 4 iterated on three beacons
  kLongsolve,            // Kleeman 5.2: weighted average of the best triples
  kGaussNewton,          // all beacons, weighted Gauss-Newton with the offset as a state
  kThammaTrilateration,  // Thamma: closed form from three absolute ranges
  kThammaLeastSquares,   // Thamma's problem as least squares over all ranges
};

// Why a fix is not valid (kNone when it is).
enum class NoFixReason : std::uint8_t {
  kNone,
  kNonFiniteInput,      // NaN or infinite distance or deviation on every candidate left
  kTooFewBeacons,       // fewer usable beacons than the solver needs
  kDegenerateGeometry,  // collinear beacons, or the robot on a beacon baseline: no unique fix
  kOutsideHull,         // the solution is further outside the beacons' hull than allowed
  kNotConverged,        // iteration limit reached, or the iteration diverged
  kMirrorAmbiguous,     // two solutions fit the data equally well (fix.mirror_m holds the other)
  kInconsistent,        // no subset of the measurements agrees within the noise
  // Two different sets of beacons each explain the cycle at two different
  // places (echoes that agree with one another as well as the direct paths
  // do): choosing one would be a guess with a confident covariance.
  // fix.position_m holds the chosen set's fix, fix.mirror_m the rival's.
  kAmbiguousBeaconSets,
};

// What a solver did with each beacon of the range set.
enum class BeaconStatus : std::uint8_t {
  kUsed,
  kNotInLayout,         // the range set has more beacons than the layout
  kMissing,             // no candidate, or the primary is flagged unusable (kUnusableFlags)
  kNonFinite,           // the distance or its deviation is NaN or infinite (or the deviation < 0)
  kTriangleInequality,  // Kleeman eqs. 5/6: longer than another beacon's distance plus the baseline
  kTripleDeviation,     // longsolve: every triple using it deviated from the weighted average
  kOutlier,             // the robust estimator: outside the consensus (RANSAC) or residual test
  kUnused,              // valid but not needed (the 3-beacon solver's other beacons)
};

struct BeaconUse {
  int beacon = 0;
  BeaconStatus status = BeaconStatus::kMissing;
  int candidate = -1;        // index into BeaconRange::candidates used (kUsed); -1 otherwise
  double residual_m = kNaN;  // measured minus predicted distance at the fix (offset removed)
  int rejected_by = -1;      // kTriangleInequality: the other beacon of the failing pair
};

struct Fix {
  bool valid = false;
  NoFixReason reason = NoFixReason::kTooFewBeacons;
  Solver solver = Solver::kGaussNewton;
  Vec2 position_m{kNaN, kNaN};
  // Position covariance, m^2 (x, y); NaN when invalid.
  Eigen::Matrix2d covariance_m2 = Eigen::Matrix2d::Constant(kNaN);
  // Horizontal dilution of precision: sqrt(trace of the position block of
  // (H^T H)^-1), H the unit-weight Jacobian of the solver's model (with the
  // offset column).
  double hdop = kNaN;
  double offset_m = kNaN;  // the common offset, metres (distance units of the input)
  double offset_sd_m = kNaN;
  double speed_of_sound_mps = kNaN;       // c the fix assumes (estimated when calibrating)
  double speed_of_sound_sd_mps = 0;       // 0 when c was taken as exact
  bool speed_of_sound_estimated = false;  // c from the data (else the prior's, sd the prior's)
  int iterations = 0;
  double chi2 = kNaN;              // sum of squared normalised residuals of the used beacons
  int dof = 0;                     // used measurements minus unknowns
  std::optional<Vec2> mirror_m;    // the other intersection, when one fits too
  std::vector<BeaconUse> beacons;  // one per beacon of the range set, in order

  [[nodiscard]] int used() const;
};

std::string_view name(Solver solver);
std::string_view name(NoFixReason reason);
std::string_view name(BeaconStatus status);

// ------------------------------------------------------- shared preparation

// A usable distance: one candidate of one beacon.
struct Observation {
  int beacon = 0;
  int candidate = 0;
  double distance_m = 0;
  double sd_m = 0;
  bool suspect = false;  // the candidate or its slot carries a kSuspectFlags flag
};

// The first step of every solver: one BeaconUse per beacon of the range set
// (kMissing, kNotInLayout, kNonFinite marked; kUsed for the rest, to be
// refined by the solver), and the primaries of the usable ones. A candidate
// with sd_m <= 0 gets min_sd_m (a deviation of zero would claim infinite
// weight).
struct Prepared {
  std::vector<BeaconUse> uses;
  std::vector<Observation> primaries;  // ordered by beacon
  bool any_non_finite = false;
};
Prepared prepare(const BeaconLayout& layout, const RangeSet& ranges, double min_sd_m = 1e-4);

// The last step of every solver: a fix that never reached a position used
// no beacon, so every kUsed becomes kUnused (the usable beacons stay
// distinguishable from the rejected ones).
void settle_unused(Fix& fix);

// The later candidates of a beacon (alternatives to its primary), as
// observations; non-finite or unusable ones are skipped.
std::vector<Observation> alternatives(const RangeSet& ranges, int beacon, double min_sd_m = 1e-4);

}  // namespace odoloc::sw::locate
