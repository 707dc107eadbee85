// The odometry datapath as an HLS kernel: one call = one fabric clock of
// rtl::OdometryFabric without its four EPPMs (rtl/odometry_fabric.hpp,
// docs/odometry.md), in odoloc::hls integer types. C++14.
//
// Boundary. The fabric is four EPPMs plus this datapath: the sequencer, the
// shared sequential CORDIC, the rear unit, the front unit, min-select, the pose
// integrator and the report of the last update. The EPPMs are a kernel of
// their own (one per encoder), and what crosses from them into the datapath is
// one register per encoder, the count latched by the last latch-and-clear; what
// goes back is the latch-and-clear strobe. So the latched counts are input
// ports, `latch` is an output port, and the odometry.* configuration registers
// (wires from the register file) are input ports. The outputs are the
// odometry.* status the register file reads, i.e. everything this block drives
// to the rest of the fabric. The CORDIC is the cordic kernel's step()
// (cordic_kernel.hpp), clocked inside this call exactly as the fabric clocks
// its rtl::SequentialCordic: one CORDIC, two runs per update.
//
// Inputs (per call; all read in this clock):
//   n_left, n_right, n_front, n_steer   SInt<20>  the four EPPMs' latched counts
//                      (x4 edges; eppm[left_rear, right_rear, front_drive,
//                      steering].latched). Read only in the GATHER clock.
//   update_clocks      UInt<16>  control period in clocks, 0 stops updates
//   policy             UInt<2>   min-select: 0 per component, 1 whole set,
//                                2 rear only, 3 front only
//   select_shift       UInt<4>   min-select memory, 2^shift updates
//   rear_ds_scale, rear_dtheta_scale, front_ds_scale, front_dtheta_scale,
//   steer_scale        UInt<32>  2^-40 m or 2^-40 turn per count
//   steer_limit        UInt<32>  |phi| limit, 2^-32 turn
//   select_ds_threshold UInt<32> 2^-32 m;  select_dtheta_threshold UInt<32> 2^-40 turn
//   set_x_hi, set_y_hi SInt<32>, set_x_lo, set_y_lo UInt<32>: set_x, set_y
//                      (SInt<64>, 2^-46 m) as their high and low words
//   set_theta          UInt<40>  2^-40 turn
//   clear_overrun      UInt<1>   odometry.status.overrun write-1-to-clear
//   clear_steer_clamped UInt<1>  odometry.status.steer_clamped write-1-to-clear
//   set_pose           UInt<1>   command.set_pose: pose <- set_*; wins over an
//                                update on the same edge
//   clear_flags        UInt<1>   command.clear_flags: clears every sticky flag
//   reset              UInt<1>   synchronous reset of the whole datapath
// Outputs (the registers after this clock's edge):
//   latch              UInt<1>   the EPPMs latch-and-clear on the next edge
//                                (phase = LATCH): the EPPMs' latch_clear wire
//   phase              UInt<4>   sequencer phase (0 idle, 1 latch, 2 gather,
//                                3 phi_load, 4 phi_wait, 5 front, 6 select,
//                                7 theta_load, 8 theta_wait)
//   overrun, steer_clamped UInt<1> sticky flags
//   ds_from_front, dtheta_from_front UInt<1> min-select's choice, last update
//   updates            UInt<32>  completed pose updates (wraps)
//   pose_x_hi, pose_y_hi SInt<32>, pose_x_lo, pose_y_lo UInt<32>: x, y
//                      (SInt<64>, 2^-46 m, wrap) as their high and low words
//   pose_theta         UInt<40>  2^-40 turn (wraps at one turn)
//   rear_ds, front_ds, ds   SInt<48>  2^-32 m, the last update's increments
//   rear_dtheta, front_dtheta, dtheta  SInt<56>  2^-40 turn
//   steer_phi          SInt<40>  clamped steering angle of the last update
//   steer_position     SInt<24>  steering counts since reset (saturating)
//
// Latency: `latch` = 1 after call k means call k+1 is the LATCH clock, whose
// edge latches the EPPMs; the pose, the update count and every increment
// output then change together on the edge of call k+1+39
// (rtl::OdometrySequencer::kUpdateLatencyClocks). An update holds the
// sequencer for 40 calls, so with update_clocks <= 40 a period ends before
// its update finished: `overrun` is set and that period is skipped.
// Reset: every register to 0 (the model's reset values), CORDIC included.
//
// x and y are 64 bits: they are kept and added as two 32-bit words, so that
// every intermediate fits in 63 bits (docs/hls.md) and the ports are the
// register map's own _hi/_lo words. test_hls_odometry_* proves every output
// of every call equal to the model, and every register equal to the real
// rtl::OdometryFabric's, per type family.
#pragma once

#include "odoloc/hls/cordic_kernel.hpp"
#include "odoloc/hls/types.hpp"

namespace odoloc {
namespace hls {
namespace odometry {

// Widths, named after the model's (rtl/odometry.hpp); test_hls_odometry
// asserts that each equals the model's type.
constexpr int kCountBits = 20;          // rtl::PositionCount, the latched counts
constexpr int kScaleBits = 32;          // scale, limit and threshold registers
constexpr int kDistanceBits = 48;       // rtl::Distance, 2^-32 m
constexpr int kHeadingBits = 56;        // rtl::Heading, 2^-40 turn
constexpr int kSteerBits = 40;          // rtl::Steer, 2^-40 turn
constexpr int kSteerPositionBits = 24;  // FrontOdometryUnitRegs::steer_position
constexpr int kDriveBits = 46;          // FrontOdometryUnitRegs::drive, turn_per_sin
constexpr int kAccumulatorBits = 62;    // rtl::MinSelect::Accumulator
constexpr int kThetaBits = 40;          // PoseIntegratorRegs::theta, 2^-40 turn
constexpr int kWordBits = 32;           // x, y (SInt<64>) are two words
constexpr int kPhaseBits = 4;           // OdometrySequencerRegs::phase
constexpr int kPeriodBits = 16;         // period_count, update_clocks
constexpr int kUpdatesBits = 32;        // updates
constexpr int kPolicyBits = 2;
constexpr int kShiftBits = 4;
// Scales are 2^-40 per count, ds and drive 2^-32: the products drop 8 bits.
constexpr int kScaleShift = 8;
// 2^-40-turn angles to the CORDIC's 2^-16 turn.
constexpr int kCordicAngleShift = kThetaBits - rtl::cordic::kAngleBits;
constexpr int kSinCosShift = rtl::cordic::kOutputFractionBits;  // sin, cos are 2^-14

// Sequencer phases (regmap odometry.status.phase) and min-select policies
// (odometry.cfg.policy).
constexpr int kPhaseIdle = 0;
constexpr int kPhaseLatch = 1;
constexpr int kPhaseGather = 2;
constexpr int kPhasePhiLoad = 3;
constexpr int kPhasePhiWait = 4;
constexpr int kPhaseFront = 5;
constexpr int kPhaseSelect = 6;
constexpr int kPhaseThetaLoad = 7;
constexpr int kPhaseThetaWait = 8;
constexpr int kPolicyPerComponent = 0;
constexpr int kPolicyWholeSet = 1;
constexpr int kPolicyRearOnly = 2;
constexpr int kPolicyFrontOnly = 3;

using Count = sint<kCountBits>;
using Scale = uint<kScaleBits>;
using Distance = sint<kDistanceBits>;
using Heading = sint<kHeadingBits>;
using Steer = sint<kSteerBits>;
using SteerPosition = sint<kSteerPositionBits>;
using Drive = sint<kDriveBits>;
using Accumulator = sint<kAccumulatorBits>;
using Theta = uint<kThetaBits>;
using HiWord = sint<kWordBits>;
using LoWord = uint<kWordBits>;

// Every field starts at 0: ap_int's default constructor leaves the value
// undefined (docs/hls.md).
struct Inputs {
  Count n_left = 0, n_right = 0, n_front = 0, n_steer = 0;
  uint<kPeriodBits> update_clocks = 0;
  uint<kPolicyBits> policy = 0;
  uint<kShiftBits> select_shift = 0;
  Scale rear_ds_scale = 0, rear_dtheta_scale = 0, front_ds_scale = 0, front_dtheta_scale = 0;
  Scale steer_scale = 0, steer_limit = 0, select_ds_threshold = 0, select_dtheta_threshold = 0;
  HiWord set_x_hi = 0;
  LoWord set_x_lo = 0;
  HiWord set_y_hi = 0;
  LoWord set_y_lo = 0;
  Theta set_theta = 0;
  uint<1> clear_overrun = 0, clear_steer_clamped = 0, set_pose = 0, clear_flags = 0, reset = 0;
};

struct Outputs {
  uint<1> latch = 0;
  uint<kPhaseBits> phase = 0;
  uint<1> overrun = 0, steer_clamped = 0, ds_from_front = 0, dtheta_from_front = 0;
  uint<kUpdatesBits> updates = 0;
  HiWord pose_x_hi = 0;
  LoWord pose_x_lo = 0;
  HiWord pose_y_hi = 0;
  LoWord pose_y_lo = 0;
  Theta pose_theta = 0;
  Distance rear_ds = 0;
  Heading rear_dtheta = 0;
  Distance front_ds = 0;
  Heading front_dtheta = 0;
  Distance ds = 0;
  Heading dtheta = 0;
  Steer steer_phi = 0;
  SteerPosition steer_position = 0;
};

// A 64-bit two's complement value as two words: hi signed, lo unsigned.
struct Wide {
  HiWord hi = 0;
  LoWord lo = 0;
};

// One struct per model block, the model's register names
// (rtl::OdometrySequencerRegs, RearOdometryUnitRegs, ...).
struct SequencerRegs {
  uint<kPhaseBits> phase = 0;
  uint<kPeriodBits> period_count = 0;
  uint<kUpdatesBits> updates = 0;
  uint<1> overrun = 0;
};
struct RearRegs {
  Distance ds = 0;
  Heading dtheta = 0;
};
struct FrontRegs {
  SteerPosition steer_position = 0;
  Steer phi = 0, phi_prev = 0;
  uint<1> clamped = 0, clamp_flag = 0;
  Drive drive = 0, turn_per_sin = 0;
  Distance ds = 0;
  Heading dtheta = 0;
};
struct SelectRegs {
  Distance ds = 0;
  Heading dtheta = 0;
  uint<1> ds_from_front = 0, dtheta_from_front = 0;
  Accumulator rear_ds_sum = 0, front_ds_sum = 0, rear_dtheta_sum = 0, front_dtheta_sum = 0;
};
struct PoseRegs {
  Wide x, y;
  Theta theta = 0;
};
struct ReportRegs {
  Distance rear_ds = 0, front_ds = 0, ds = 0;
  Heading rear_dtheta = 0, front_dtheta = 0, dtheta = 0;
  Steer steer_phi = 0;
  SteerPosition steer_position = 0;
  uint<1> ds_from_front = 0, dtheta_from_front = 0;
};

struct Registers {
  SequencerRegs sequencer;
  cordic::Registers cordic;
  RearRegs rear;
  FrontRegs front;
  SelectRegs select;
  PoseRegs pose;
  ReportRegs report;
};

// The ports by name, in the golden vectors' column order (testbenches only).
template <class Visit>
void visit_fields(Inputs& s, Visit&& v) {
  v("n_left", s.n_left);
  v("n_right", s.n_right);
  v("n_front", s.n_front);
  v("n_steer", s.n_steer);
  v("update_clocks", s.update_clocks);
  v("policy", s.policy);
  v("select_shift", s.select_shift);
  v("rear_ds_scale", s.rear_ds_scale);
  v("rear_dtheta_scale", s.rear_dtheta_scale);
  v("front_ds_scale", s.front_ds_scale);
  v("front_dtheta_scale", s.front_dtheta_scale);
  v("steer_scale", s.steer_scale);
  v("steer_limit", s.steer_limit);
  v("select_ds_threshold", s.select_ds_threshold);
  v("select_dtheta_threshold", s.select_dtheta_threshold);
  v("set_x_hi", s.set_x_hi);
  v("set_x_lo", s.set_x_lo);
  v("set_y_hi", s.set_y_hi);
  v("set_y_lo", s.set_y_lo);
  v("set_theta", s.set_theta);
  v("clear_overrun", s.clear_overrun);
  v("clear_steer_clamped", s.clear_steer_clamped);
  v("set_pose", s.set_pose);
  v("clear_flags", s.clear_flags);
  v("reset", s.reset);
}
template <class Visit>
void visit_fields(Outputs& s, Visit&& v) {
  v("latch", s.latch);
  v("phase", s.phase);
  v("overrun", s.overrun);
  v("steer_clamped", s.steer_clamped);
  v("ds_from_front", s.ds_from_front);
  v("dtheta_from_front", s.dtheta_from_front);
  v("updates", s.updates);
  v("pose_x_hi", s.pose_x_hi);
  v("pose_x_lo", s.pose_x_lo);
  v("pose_y_hi", s.pose_y_hi);
  v("pose_y_lo", s.pose_y_lo);
  v("pose_theta", s.pose_theta);
  v("rear_ds", s.rear_ds);
  v("rear_dtheta", s.rear_dtheta);
  v("front_ds", s.front_ds);
  v("front_dtheta", s.front_dtheta);
  v("ds", s.ds);
  v("dtheta", s.dtheta);
  v("steer_phi", s.steer_phi);
  v("steer_position", s.steer_position);
}

// ---- arithmetic helpers (the model's bits.hpp operations) ------------------

// (v + 2^(N-1)) >> N: round half up, as the model's round_shr.
template <int N, int W>
inline sint<W + 1 - N> round_shr(const sint<W>& v) {
#pragma HLS inline
  const sint<N + 1> half = 1LL << (N - 1);
  const sint<W + 1> biased = v + half;
  return biased >> N;
}

// Clamp to the N-bit two's complement range, as the model's sat<N>().
template <int N, int W>
inline sint<N> saturate(const sint<W>& v) {
#pragma HLS inline
  const sint<W> most = (1LL << (N - 1)) - 1;
  const sint<W> least = -(1LL << (N - 1));
  sint<N> r = v;
  if (v > most)
    r = most;
  else if (v < least)
    r = least;
  return r;
}

// A 2^-40-turn angle to the CORDIC's 16-bit binary angle, rounded to nearest
// (the model's to_cordic_angle). Only the low 40 bits of the angle matter.
inline cordic::Logic::Angle to_cordic_angle(const sint<kHeadingBits + 2>& turns) {
#pragma HLS inline
  const sint<kHeadingBits + 3 - kCordicAngleShift> rounded = round_shr<kCordicAngleShift>(turns);
  return bits<rtl::cordic::kAngleBits - 1, 0>(rounded);
}

// ---- the blocks, each one clock of its model block --------------------------

// rtl::OdometrySequencer: the period counter and the phase of the update.
inline void sequence(SequencerRegs& n, const SequencerRegs& r, const Inputs& in,
                     const uint<1>& cordic_ready) {
#pragma HLS inline
  if (in.clear_overrun == 1 || in.clear_flags == 1)
    n.overrun = 0;
  const uint<kPeriodBits + 1> next_count = r.period_count + 1;
  const bool period_end = in.update_clocks != 0 && next_count >= in.update_clocks;
  if (period_end)
    n.period_count = 0;
  else
    n.period_count = next_count;  // wraps, as update_clocks = 0 lets it
  if (period_end && r.phase != kPhaseIdle)
    n.overrun = 1;
  switch (to_s64(r.phase)) {
    case kPhaseIdle:
      if (period_end)
        n.phase = kPhaseLatch;
      break;
    case kPhasePhiWait:
      if (cordic_ready == 1)
        n.phase = kPhaseFront;
      break;
    case kPhaseThetaWait:
      if (cordic_ready == 1) {
        n.phase = kPhaseIdle;
        n.updates = r.updates + 1;
      }
      break;
    default:
      n.phase = r.phase + 1;
      break;
  }
}

// rtl::RearOdometryUnit, start: ds = kappa (nL + nR) / 2, dtheta = kappa (nR - nL) / D.
inline void rear_start(RearRegs& n, const Inputs& in) {
#pragma HLS inline
  const sint<kCountBits + 1> sum = in.n_left + in.n_right;
  const sint<kCountBits + 1> difference = in.n_right - in.n_left;
  const sint<kScaleBits + 1> ds_scale = in.rear_ds_scale;
  const sint<kScaleBits + 1> dtheta_scale = in.rear_dtheta_scale;
  const sint<kCountBits + kScaleBits + 2> ds_units = sum * ds_scale;  // < 2^53 at 2^-40
  n.ds = round_shr<kScaleShift>(ds_units);
  n.dtheta = difference * dtheta_scale;  // exact: |product| < 2^53
}

// rtl::FrontOdometryUnit, start: steering position, clamped phi, dF and dF/L.
inline void front_start(FrontRegs& n, const FrontRegs& r, const Inputs& in) {
#pragma HLS inline
  const sint<kSteerPositionBits + 1> position = r.steer_position + in.n_steer;
  n.steer_position = saturate<kSteerPositionBits>(position);
  const sint<kScaleBits + 1> steer_scale = in.steer_scale;
  const sint<kSteerPositionBits + kScaleBits + 2> raw = n.steer_position * steer_scale;
  const sint<kScaleBits + kScaleShift + 1> limit_units = in.steer_limit;
  const sint<kScaleBits + kScaleShift + 1> limit = limit_units << kScaleShift;  // 2^-40 turn
  const sint<kScaleBits + kScaleShift + 2> minus_limit = -limit;
  const bool above = raw > limit;
  const bool below = raw < minus_limit;
  if (above || below) {
    n.clamped = 1;
    n.clamp_flag = 1;
  } else {
    n.clamped = 0;
  }
  n.phi_prev = r.phi;
  // Each assignment wraps to 40 bits, as the model's wrap<40>().
  if (above)
    n.phi = limit;
  else if (below)
    n.phi = minus_limit;
  else
    n.phi = raw;
  const sint<kScaleBits + 1> ds_scale = in.front_ds_scale;
  const sint<kScaleBits + 1> dtheta_scale = in.front_dtheta_scale;
  const sint<kCountBits + kScaleBits + 1> drive_units = in.n_front * ds_scale;
  const sint<kCountBits + kScaleBits + 1> turn_units = in.n_front * dtheta_scale;
  n.drive = round_shr<kScaleShift>(drive_units);
  n.turn_per_sin = round_shr<kScaleShift>(turn_units);
}

// rtl::FrontOdometryUnit, finish: ds = dF cos(phi), dtheta = (dF / L) sin(phi),
// from the registers of the start step and the CORDIC's result.
inline void front_finish(FrontRegs& n, const FrontRegs& r, const cordic::Registers& c) {
#pragma HLS inline
  const sint<kDriveBits + rtl::cordic::kOutputFractionBits + 2> ds_units = r.drive * c.result.cos;
  const sint<kDriveBits + rtl::cordic::kOutputFractionBits + 2> dtheta_units =
      r.turn_per_sin * c.result.sin;
  n.ds = round_shr<kSinCosShift>(ds_units);
  n.dtheta = round_shr<kSinCosShift - kScaleShift>(dtheta_units);
}

// The CORDIC's angle for the front unit: the mid-period steering angle.
inline cordic::Logic::Angle steer_angle(const FrontRegs& r) {
#pragma HLS inline
  const sint<kSteerBits + 1> sum = r.phi + r.phi_prev;
  const sint<kSteerBits + 1> mid = sum >> 1;
  return to_cordic_angle(mid);
}

// The CORDIC's angle for the pose: the mid-step heading theta + dtheta / 2.
inline cordic::Logic::Angle heading_angle(const PoseRegs& r, const Heading& dtheta) {
#pragma HLS inline
  const Heading half = dtheta >> 1;
  const sint<kHeadingBits + 2> mid = r.theta + half;
  return to_cordic_angle(mid);
}

// A - A / 2^shift + inc, saturating (rtl::MinSelect::leak); shift 0 keeps only inc.
inline Accumulator leak(const Accumulator& a, const Heading& inc, const uint<kShiftBits>& shift) {
#pragma HLS inline
  const Accumulator kept = a - (a >> shift);  // between a and 0: fits
  const sint<kAccumulatorBits + 1> sum = kept + inc;
  return saturate<kAccumulatorBits>(sum);
}

// The front takes a component over when |A_rear| - |A_front| > threshold and
// hands it back when it is <= -threshold (rtl::MinSelect::front_wins).
inline bool front_wins(const uint<1>& front_now, const Accumulator& rear, const Accumulator& front,
                       const Scale& threshold) {
#pragma HLS inline
  sint<kAccumulatorBits + 1> rear_magnitude = rear;
  if (rear < 0)
    rear_magnitude = -rear;
  sint<kAccumulatorBits + 1> front_magnitude = front;
  if (front < 0)
    front_magnitude = -front;
  const sint<kAccumulatorBits + 1> d = rear_magnitude - front_magnitude;  // |d| <= 2^61
  const sint<kScaleBits + 1> t = threshold;
  if (front_now == 1)
    return d > -t;
  return d > t;
}

// rtl::MinSelect, select: the leaky sums, the hysteresis and the policy.
inline void min_select(SelectRegs& n, const SelectRegs& r, const RearRegs& rear,
                       const FrontRegs& front, const Inputs& in) {
#pragma HLS inline
  n.rear_ds_sum = leak(r.rear_ds_sum, rear.ds, in.select_shift);
  n.front_ds_sum = leak(r.front_ds_sum, front.ds, in.select_shift);
  n.rear_dtheta_sum = leak(r.rear_dtheta_sum, rear.dtheta, in.select_shift);
  n.front_dtheta_sum = leak(r.front_dtheta_sum, front.dtheta, in.select_shift);
  const bool front_ds =
      front_wins(r.ds_from_front, n.rear_ds_sum, n.front_ds_sum, in.select_ds_threshold);
  const bool front_dtheta = front_wins(r.dtheta_from_front, n.rear_dtheta_sum, n.front_dtheta_sum,
                                       in.select_dtheta_threshold);
  bool ds_front = false;
  bool dtheta_front = false;
  switch (to_s64(in.policy)) {
    case kPolicyPerComponent:
      ds_front = front_ds;
      dtheta_front = front_dtheta;
      break;
    case kPolicyWholeSet:
      ds_front = front_ds;
      dtheta_front = front_ds;
      break;
    case kPolicyRearOnly:
      break;
    default:  // kPolicyFrontOnly
      ds_front = true;
      dtheta_front = true;
      break;
  }
  if (ds_front)
    n.ds = front.ds;
  else
    n.ds = rear.ds;
  if (dtheta_front)
    n.dtheta = front.dtheta;
  else
    n.dtheta = rear.dtheta;
  n.ds_from_front = ds_front ? 1 : 0;
  n.dtheta_from_front = dtheta_front ? 1 : 0;
}

// a + ds * factor, modulo 2^64, word by word (the model's add_wrap on SInt<64>).
inline Wide accumulate(const Wide& a, const Distance& ds, const cordic::Logic::Output& factor) {
#pragma HLS inline
  // |ds| < 2^47 and |factor| <= 2^14 + a few LSB, so |p| < 2^62.
  const sint<kDistanceBits + rtl::cordic::kOutputFractionBits + 1> p = ds * factor;
  const uint<kWordBits + 1> lo = a.lo + bits<kWordBits - 1, 0>(p);
  const sint<kDistanceBits + rtl::cordic::kOutputFractionBits + 1> p_high = p >> kWordBits;
  Wide s;
  s.hi = a.hi + p_high + bits<kWordBits, kWordBits>(lo);  // wraps to 32 bits
  s.lo = lo;                                              // the carry leaves
  return s;
}

// rtl::PoseIntegrator, integrate: x += ds cos, y += ds sin, theta += dtheta.
inline void integrate(PoseRegs& n, const PoseRegs& r, const SelectRegs& s,
                      const cordic::Registers& c) {
#pragma HLS inline
  n.x = accumulate(r.x, s.ds, c.result.cos);
  n.y = accumulate(r.y, s.ds, c.result.sin);
  n.theta = r.theta + s.dtheta;  // wraps at one turn
}

// rtl::OdometryReport, publish: the increments of the update the pose takes.
inline void publish(ReportRegs& n, const RearRegs& rear, const FrontRegs& front,
                    const SelectRegs& s) {
#pragma HLS inline
  n.rear_ds = rear.ds;
  n.front_ds = front.ds;
  n.ds = s.ds;
  n.rear_dtheta = rear.dtheta;
  n.front_dtheta = front.dtheta;
  n.dtheta = s.dtheta;
  n.steer_phi = front.phi;
  n.steer_position = front.steer_position;
  n.ds_from_front = s.ds_from_front;
  n.dtheta_from_front = s.dtheta_from_front;
}

// One fabric clock: every block's next registers from the current ones (the
// wires of rtl::OdometryFabric::wires), then the commit and the outputs.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  const Registers r = regs;
  Registers n = r;
  if (in.reset == 1) {
    n = Registers();
  } else {
    const bool gather = r.sequencer.phase == kPhaseGather;
    const bool phi_load = r.sequencer.phase == kPhasePhiLoad;
    const bool theta_load = r.sequencer.phase == kPhaseThetaLoad;
    const bool integrating = r.sequencer.phase == kPhaseThetaWait && r.cordic.ready == 1;

    sequence(n.sequencer, r.sequencer, in, r.cordic.ready);

    // The shared CORDIC: the steering angle in PHI_LOAD, the heading in THETA_LOAD.
    cordic::Inputs cordic_in;
    cordic_in.load = (phi_load || theta_load) ? 1 : 0;
    if (phi_load)
      cordic_in.angle = steer_angle(r.front);
    else
      cordic_in.angle = heading_angle(r.pose, r.select.dtheta);
    cordic_in.clear_flags = (in.clear_overrun == 1 || in.clear_flags == 1) ? 1 : 0;
    cordic::Outputs cordic_out;  // its outputs are its registers, read from r
    cordic::step(n.cordic, cordic_in, cordic_out);

    if (gather)
      rear_start(n.rear, in);

    if (in.clear_steer_clamped == 1 || in.clear_flags == 1)
      n.front.clamp_flag = 0;
    if (gather)
      front_start(n.front, r.front, in);
    if (r.sequencer.phase == kPhaseFront)
      front_finish(n.front, r.front, r.cordic);

    if (r.sequencer.phase == kPhaseSelect)
      min_select(n.select, r.select, r.rear, r.front, in);

    if (in.set_pose == 1) {
      n.pose.x.hi = in.set_x_hi;
      n.pose.x.lo = in.set_x_lo;
      n.pose.y.hi = in.set_y_hi;
      n.pose.y.lo = in.set_y_lo;
      n.pose.theta = in.set_theta;
    } else if (integrating) {
      integrate(n.pose, r.pose, r.select, r.cordic);
    }

    if (integrating)
      publish(n.report, r.rear, r.front, r.select);
  }
  regs = n;
  out.latch = (n.sequencer.phase == kPhaseLatch) ? 1 : 0;
  out.phase = n.sequencer.phase;
  out.overrun = n.sequencer.overrun;
  out.steer_clamped = n.front.clamp_flag;
  out.ds_from_front = n.report.ds_from_front;
  out.dtheta_from_front = n.report.dtheta_from_front;
  out.updates = n.sequencer.updates;
  out.pose_x_hi = n.pose.x.hi;
  out.pose_x_lo = n.pose.x.lo;
  out.pose_y_hi = n.pose.y.hi;
  out.pose_y_lo = n.pose.y.lo;
  out.pose_theta = n.pose.theta;
  out.rear_ds = n.report.rear_ds;
  out.rear_dtheta = n.report.rear_dtheta;
  out.front_ds = n.report.front_ds;
  out.front_dtheta = n.report.front_dtheta;
  out.ds = n.report.ds;
  out.dtheta = n.report.dtheta;
  out.steer_phi = n.report.steer_phi;
  out.steer_position = n.report.steer_position;
}

}  // namespace odometry
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/odometry_top.cpp): one call = one clock, the
// registers held in the function's static state.
void odoloc_odometry(const odoloc::hls::odometry::Inputs& in, odoloc::hls::odometry::Outputs& out);
