// Relative pose of two robots from binaural ultrasonic ranging
// (docs/heading-and-relative-pose.md#binaural-relative-pose).
//
// Source: the binaural relative-pose paper (Shoval and Borenstein), sec. 3,
// eqs. 3-9, derived anew (the printed eq. 5 and eqs. 7-9 are wrong or
// ambiguous as printed; the doc lists each deviation). Each robot carries a
// transmitter at its origin and a receiver pair at (-b/2, 0) (left) and
// (+b/2, 0) (right) of its frame, both looking along +y. A chirp from
// robot 1, timed by the RF sync, gives robot 2 (tof::measure_binaural) the
// absolute ranges r_left, r_right from its receivers to robot 1's
// transmitter (coarse TOF x c) and their difference r_left - r_right from
// the carrier phase; robot 2's chirp gives robot 1 the same.
//
// Per pair (locate_transmitter): with s = r_left + r_right and
// D = r_left - r_right the transmitter is at
//     x = s D / (2b),   y = sqrt((s^2 - b^2)(b^2 - D^2)) / (2b)   (in front: y > 0),
// the paper's circle intersection (eqs. 3-6) in the ellipse-hyperbola
// coordinates the pair measures: s from the coarse ranges, D from the
// carrier phase (about a thousand times finer than the ranges' difference;
// tof::measure_binaural already took its whole cycles from the coarse time).
// Both pairs (relative_pose): paper eqs. 7-9 with atan2,
//     a1 = atan2(X'_1, Y'_1),  a2 = atan2(Y'_2, X'_2),  q = pi/2 - a1 - a2,
// q = 0 when the pairs face each other squarely.
//
// Pure functions; data never throws (NaN, missing or impossible ranges give
// a result with valid == false and the reason); bad options throw
// std::invalid_argument.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string_view>

#include "odoloc/sw/beacon_fix.hpp"
#include "odoloc/sw/tof_sync_modes.hpp"

namespace odoloc::sw::locate {

struct BinauralOptions {
  double baseline_m = 0.35;           // b, both robots (paper sec. 4: 350 mm)
  double speed_of_sound_mps = 343.2;  // the c of tof::BinauralConfig (range = c TOF)
  // sd of one coarse range (first carrier edge after the sync, x c): edge
  // jitter plus the threshold crossing's uncertainty of a carrier cycle.
  double range_sd_m = 3e-3;
  // Floor on the phase's sd (0 would claim infinite weight).
  double min_path_difference_sd_m = 1e-6;
  // Gate, in standard deviations: front/back (y against its sd), the
  // tangent tolerance, the two robots' distances.
  double gate_sigmas = 3.0;
  // Paper sec. 4.3: relative orientation measured accurately within +-25 deg.
  double max_relative_orientation_rad = 0.436332312998582;
  // Longest range a chirp can come from (the paper's robots work within a
  // few metres); beyond, or negative, the TOF is not a measurement.
  double max_range_m = 50.0;

  void validate() const;  // std::invalid_argument naming the field
};

// Why a binaural result is not valid (kNone when it is).
enum class BinauralReason : std::uint8_t {
  kNone,
  kMissingData,     // a receiver heard nothing (tof flag kMissing)
  kNonFiniteInput,  // NaN or infinite TOF
  kOutOfRange,      // a range (c TOF) negative or beyond max_range_m: no chirp of this pair
  kNoIntersection,  // s < b or |D| > b beyond the noise: the circles do not meet (an echo)
  kOnBaselineAxis,  // the transmitter on the line through the receivers (tangent circles):
                    // front and back, and the lateral position, are not resolved
  kInconsistent,    // the two robots' distances disagree (relative_pose)
};
std::string_view name(BinauralReason reason);

// The other robot's transmitter in this robot's frame: the paper's (X'_i, Y'_i).
struct TransmitterFix {
  bool valid = false;
  BinauralReason reason = BinauralReason::kMissingData;
  Vec2 position_m{kNaN, kNaN};  // y > 0 (in front of the receivers)
  Eigen::Matrix2d covariance_m2 = Eigen::Matrix2d::Constant(kNaN);  // of position_m
  // s = r_left + r_right (coarse ranges) and D = r_left - r_right (phase),
  // independent, with their sd.
  double range_sum_m = kNaN, range_sum_sd_m = kNaN;
  double path_difference_m = kNaN, path_difference_sd_m = kNaN;
  // false: D from the coarse difference (tof flagged the phase's whole
  // cycles kAmbiguous, or no common carrier edge), sd sqrt(2) range_sd_m.
  bool phase_used = false;
  tof::Flags flags;  // the pair's measurement flags (kCycleUnverified, kAmbiguous, ...)
};

// One pair's measurement: r = c TOF per receiver, D from the phase.
TransmitterFix locate_transmitter(const tof::BinauralPairResult& pair,
                                  const BinauralOptions& options = {});

// Robot 1's pose in robot 2's frame.
struct RelativePose {
  bool valid = false;
  // The first failing pair's reason (robot 2's first), or kInconsistent.
  BinauralReason reason = BinauralReason::kMissingData;
  TransmitterFix robot1_in_robot2;  // (X'_1, Y'_1): robot 2's pair hearing robot 1
  TransmitterFix robot2_in_robot1;  // (X'_2, Y'_2): robot 1's pair hearing robot 2
  // Paper eqs. 7, 8: robot 1's bearing from robot 2's forward axis (+ toward
  // robot 2's right) and robot 2's bearing from robot 1's baseline axis.
  double a1_rad = kNaN, a2_rad = kNaN;
  // Paper eq. 9, wrapped to (-pi, pi]: 0 when the pairs face each other
  // squarely; robot 1's x axis points at q + pi in robot 2's frame.
  double relative_orientation_rad = kNaN;
  double relative_orientation_sd_rad = kNaN;
  // (X'_1, Y'_1, q): from both pairs' covariances (independent measurements).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Constant(kNaN);
  // |(X'_1, Y'_1)| - |(X'_2, Y'_2)|: both are the transmitters' separation.
  double distance_mismatch_m = kNaN, distance_mismatch_sd_m = kNaN;
  // |q| beyond BinauralOptions::max_relative_orientation_rad (paper sec. 4.3:
  // outside it the receivers' beams make the measurement unreliable). The
  // result stays valid: a flag for the consumer.
  bool beyond_orientation_limit = false;

  // Robot 1's heading in robot 2's frame: q + pi wrapped to (-pi, pi].
  [[nodiscard]] double heading_rad() const;
};

// Both robots' measurements of each other's chirps.
RelativePose relative_pose(const tof::BinauralPairResult& robot2_hears_robot1,
                           const tof::BinauralPairResult& robot1_hears_robot2,
                           const BinauralOptions& options = {});

}  // namespace odoloc::sw::locate
