// The odometry datapath's register widths and port encodings, in one place
// for its logic (logic/odometry.hpp), the cycle model (odometry.hpp, which
// static_asserts the register map's enumerations against them) and the HLS
// kernel (hls/odometry_kernel.hpp). Formats: docs/odometry.md. Plain C++14
// with integer results only, because HLS front ends accept C++14.
#pragma once

namespace odoloc {
namespace rtl {
namespace odometry {

constexpr int kCountBits = 20;          // the EPPMs' latched counts (x4 edges)
constexpr int kScaleBits = 32;          // scale, limit and threshold registers
constexpr int kDistanceBits = 48;       // ds: 2^-32 m
constexpr int kHeadingBits = 56;        // dtheta: 2^-40 turn
constexpr int kSteerBits = 40;          // phi: 2^-40 turn
constexpr int kSteerPositionBits = 24;  // steering counts since reset, saturating
constexpr int kDriveBits = 46;          // dF and dF / L before the CORDIC: 2^-32 m, 2^-32 turn
constexpr int kAccumulatorBits = 62;    // min-select's leaky sums
constexpr int kThetaBits = 40;          // binary angle, 2^40 = one turn
constexpr int kPhaseBits = 4;           // the sequencer's phase
constexpr int kPeriodBits = 16;         // update_clocks and the period counter
constexpr int kUpdatesBits = 32;        // completed updates, wrapping
constexpr int kPolicyBits = 2;          // odometry.cfg.policy
constexpr int kShiftBits = 4;           // odometry.cfg.select_shift
// Scales are 2^-40 per count, ds and dF 2^-32: the products drop 8 bits.
constexpr int kScaleShift = 8;

// odometry.status.phase.
constexpr int kPhaseIdle = 0;
constexpr int kPhaseLatch = 1;
constexpr int kPhaseGather = 2;
constexpr int kPhasePhiLoad = 3;
constexpr int kPhasePhiWait = 4;
constexpr int kPhaseFront = 5;
constexpr int kPhaseSelect = 6;
constexpr int kPhaseThetaLoad = 7;
constexpr int kPhaseThetaWait = 8;
// odometry.cfg.policy.
constexpr int kPolicyPerComponent = 0;
constexpr int kPolicyWholeSet = 1;
constexpr int kPolicyRearOnly = 2;
constexpr int kPolicyFrontOnly = 3;

}  // namespace odometry
}  // namespace rtl
}  // namespace odoloc
