// Thamma's head and tail: position and heading of a vehicle from absolute
// ranges (docs/heading-and-relative-pose.md#thammas-head-and-tail).
//
// Source: Thamma, "Estimating position and orientation of an unmanned
// guided vehicle with ultrasound and radio frequency sensing", sec. V
// (triangle steps 1-10) and VI (orientation), derived anew; the doc lists
// where the printed steps mislead. An RF sync times every burst, so a
// range has no unknown offset: d_i = |P - b_i|_3D + noise_i. Each receiver
// box (head, tail) gives one fix of its reference point; the vector from
// the tail to the head gives the heading, the known head-tail separation a
// consistency check.
//
// Input: one tof::ThammaMeasurement per base station (measure_thamma of that
// station's burst; index = station in the layout), or a RangeSet per box.
// Output: locate::Fix per box (Solver::kThammaTrilateration: the paper's
// triangle on two stations; Solver::kThammaLeastSquares: weighted
// Gauss-Newton over every range) and the pose (x, y, heading) with its
// covariance. Data never throws; a malformed layout, body or options throws
// std::invalid_argument.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string_view>

#include "odoloc/sw/beacon_fix.hpp"
#include "odoloc/sw/tof_sync_modes.hpp"

namespace odoloc::sw::locate {

struct ThammaOptions {
  double min_sd_m = 1e-4;  // floor on a range's sd (0 would claim infinite weight)
  int max_iterations = 20;
  double step_tolerance_m = 1e-9;   // Gauss-Newton stops below this step
  double max_outside_hull_m = 0.5;  // a fix further outside the stations' hull: kOutsideHull
  // Gate, in standard deviations: a studentised range residual beyond it is
  // kInconsistent (4: a false alarm in ~1 of 16 000 ranges); two circles
  // missing each other by less are tangent (kDegenerateGeometry), by more
  // kInconsistent; a fix closer than this to the line through collinear
  // stations is kDegenerateGeometry.
  double gate_sigmas = 4.0;

  void validate() const;  // std::invalid_argument naming the field
};

// Thamma's triangle (sec. V, steps 1-10): the two usable stations whose
// circles cross most squarely form the base; the vertex is on the side
// where the other ranges fit better by more than one unit of chi^2, else
// the side nearer the stations' hull (inside it: distance 0);
// kMirrorAmbiguous when both are as near (both inside, or a two-station
// hull). Covariance of the two-range solution; the other stations are
// kUnused with their residuals.
Fix thamma_trilateration(const BeaconLayout& stations, const RangeSet& ranges,
                         const ThammaOptions& options = {});

// Weighted Gauss-Newton over every usable range from the triangle's
// solution (the stations' centroid when there is none): covariance
// (J^T W J)^-1, chi^2 with n - 2 degrees of freedom, the worst studentised
// residual gated.
Fix thamma_least_squares(const BeaconLayout& stations, const RangeSet& ranges,
                         const ThammaOptions& options = {});

// Box `box`'s ranges from one measurement per station (index = station):
// the box's distance and sd as the primary candidate, its flags; a box that
// heard nothing is kMissing.
RangeSet box_ranges(std::span<const tof::ThammaMeasurement> per_station, int box,
                    double speed_of_sound_mps = 343.2);

// The vehicle (body frame: x forward, metres).
struct ThammaBody {
  Vec2 head_m{0.6, 0};  // the head box's reference point (its centre)
  Vec2 tail_m{-0.2, 0};
  int head_box = 0;  // index into ThammaMeasurement::boxes (ThammaConfig::boxes)
  int tail_box = 1;
  // Receiver i = capture channel i. A range ends at the receiver that heard
  // first (facing the station), up to half a box from the reference point:
  // with the receivers given, the pose corrects for it (see thamma_pose).
  // Empty: every range is taken to end at its box's reference point.
  tof::ReceiverArray receivers;

  void validate() const;  // head and tail apart, finite, boxes valid indices
};

struct ThammaPoseOptions {
  ThammaOptions fix;
  bool least_squares = true;  // false: the paper's triangle per box
  // Receiver offsets: fixes, heading, offsets rotated by the heading, fixes
  // again (secant steps from the third pass), until the heading moves less
  // than heading_tolerance_rad or after max_passes.
  int max_passes = 10;
  double heading_tolerance_rad = 1e-10;
  // |head - tail| further than this many sd from the body's separation: kSeparationMismatch.
  double separation_sigmas = 3.0;
  // A box's range from fewer of the burst's repeats is not used (missing):
  // one pulse of four that agrees with nothing is likelier noise than the
  // burst.
  int min_repeats = 1;

  void validate() const;  // std::invalid_argument naming the field (fix included)
};

enum class ThammaPoseReason : std::uint8_t {
  kNone,
  kNoHeadFix,           // the head box's fix is invalid (ThammaPose::head.reason)
  kNoTailFix,           // the tail box's fix is invalid
  kSeparationMismatch,  // |head - tail| disagrees with the body: one fix is wrong
};
std::string_view name(ThammaPoseReason reason);

struct ThammaPose {
  bool valid = false;
  ThammaPoseReason reason = ThammaPoseReason::kNoHeadFix;
  Fix head;  // world position of ThammaBody::head_m
  Fix tail;
  // The body origin in the world and the heading (x axis, counter-clockwise
  // from world x, (-pi, pi]); filled when both fixes are valid (also when
  // the separation check fails).
  Vec2 position_m{kNaN, kNaN};
  double heading_rad = kNaN;
  double heading_sd_rad = kNaN;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Constant(kNaN);  // (x, y, heading)
  double separation_m = kNaN;                                    // |head - tail| measured
  double separation_sd_m = kNaN;                                 // from both fixes' covariances
  double separation_error_m = kNaN;                              // measured minus the body's
  int passes = 0;  // fix-heading passes (receiver offsets)
};

// A moving vehicle: the stations fire one after the other (Thamma: 0.4 s
// apart), so each range is from another place. Per station (index =
// station), where each box's reference point was at that station's time
// relative to where it is at the pose's time, in the body frame at the
// pose's time (from the odometry). Empty: the vehicle stood.
struct ThammaMotion {
  std::vector<Vec2> head, tail;
};

// Both boxes' fixes, the heading from the tail to the head, the body origin,
// at the pose's time. With receivers in the body, each range is corrected
// for the receiver that heard it first (ThammaRepeat::channel of the first
// used repeat), and with `motion` for where the box was: the station's
// circle is moved by -R(heading) (receiver - box reference + motion), and
// the fixes are repeated with the new heading. The first pass, which does
// not know the heading, takes the largest of those offsets as each range's
// uncertainty. Throws std::invalid_argument for a motion of the wrong size.
ThammaPose thamma_pose(const BeaconLayout& stations,
                       std::span<const tof::ThammaMeasurement> per_station, const ThammaBody& body,
                       const ThammaPoseOptions& options = {}, const ThammaMotion& motion = {});

}  // namespace odoloc::sw::locate
