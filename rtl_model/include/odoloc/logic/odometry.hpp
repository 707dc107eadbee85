// The odometry datapath's logic, written once (docs/odometry.md; docs/hls.md,
// "One source per block"): the cycle model (rtl/odometry.hpp) runs it with
// the model's types, the HLS kernel (hls/odometry_kernel.hpp) with the
// vendor's, and `odoloc export-hls` exports this file. Paper: Kurian &
// Pillai, sections 3-4, with the corrected front-wheel kinematics
// (docs/odometry.md).
//
//   EPPM latched counts -> rear unit ---------+-> min-select -> pose integrator
//                       -> front unit (CORDIC: sin/cos phi) -+   (CORDIC: sin/cos theta)
//   sequencer: one update per control period, one shared CORDIC; the report
//   holds the last update's increments, published on the pose's edge.
//
// Fixed-point formats (rtl/odometry_constants.hpp has the widths):
//   counts            sint 20   latched EPPM increments (x4 edges)
//   scale registers   uint 32   metres or turns per count, units 2^-40
//   ds                sint 48   distance of the rear-axle midpoint, 2^-32 m
//   dtheta            sint 56   heading increment, 2^-40 turn
//   x, y              64 bits   2^-46 m (exact sums of ds * cos, ds * sin),
//                               as Words (two 32-bit words, int_family.hpp)
//   theta             uint 40   binary angle, 2^40 = one turn
//   phi (steering)    sint 40   2^-40 turn, clamped to +-steer_limit
// Each leaf is Regs, In and a next() that returns the registers after one
// clock's edge; the datapath (Datapath) computes every leaf's In from the
// current registers, so the leaves can be clocked in any order. The
// configuration and strobes are the register map's port structs
// (odoloc/ports.hpp in the model, odoloc/logic/ports.hpp in the kernel),
// taken as template parameters. C++14, no heap, no containers.
#pragma once

#include "odoloc/logic/cordic.hpp"
#include "odoloc/logic/int_family.hpp"
#include "odoloc/rtl/odometry_constants.hpp"

namespace odoloc {
namespace logic {
namespace odometry {

namespace constants = rtl::odometry;

template <class F>
using Count = sint<F, constants::kCountBits>;
template <class F>
using Scale = uint<F, constants::kScaleBits>;
template <class F>
using Distance = sint<F, constants::kDistanceBits>;  // 2^-32 m
template <class F>
using Heading = sint<F, constants::kHeadingBits>;  // 2^-40 turn
template <class F>
using Steer = sint<F, constants::kSteerBits>;  // 2^-40 turn
template <class F>
using SteerPosition = sint<F, constants::kSteerPositionBits>;
template <class F>
using Drive = sint<F, constants::kDriveBits>;
template <class F>
using Accumulator = sint<F, constants::kAccumulatorBits>;
template <class F>
using Theta = uint<F, constants::kThetaBits>;
template <class F>
using Phase = uint<F, constants::kPhaseBits>;
template <class F>
using Period = uint<F, constants::kPeriodBits>;
template <class F>
using Updates = uint<F, constants::kUpdatesBits>;
// A scale register read as a signed factor.
template <class F>
using SignedScale = sint<F, constants::kScaleBits + 1>;

// A 2^-40-turn angle (any signed width) to the CORDIC's 16-bit binary
// angle, rounded to nearest; only its low 40 bits matter.
template <class F, class T>
inline uint<F, rtl::cordic::kAngleBits> to_cordic_angle(const T& turns_40) {
  return wrap<uint<F, rtl::cordic::kAngleBits> >(
      round_shr<constants::kThetaBits - rtl::cordic::kAngleBits>(turns_40));
}

// ---- sequencer ----------------------------------------------------------------
// One update per control period with one shared CORDIC:
//   LATCH           latch-and-clear all four EPPMs
//   GATHER          rear unit computes; front unit takes counts and steering
//   PHI_LOAD/WAIT   CORDIC: sin/cos of the mid-period steering angle
//   FRONT           front unit finishes
//   SELECT          min-select
//   THETA_LOAD/WAIT CORDIC: sin/cos of the mid-step heading; in the clock the
//                   result is ready the pose integrates, the report
//                   publishes and `updates` counts, all on one edge
// Each phase's work commits on the edge that leaves the phase.
template <class F>
struct SequencerRegs {
  Phase<F> phase{0};
  Period<F> period_count{0};
  Updates<F> updates{0};  // completed pose updates
  uint<F, 1> overrun{0};  // sticky: a period ended before the update finished
};
template <class F>
struct SequencerIn {
  Period<F> update_clocks{0};  // 0 stops updates
  uint<F, 1> cordic_ready{0};
  uint<F, 1> clear_overrun{0};
  uint<F, 1> reset{0};
};

template <class F>
struct Sequencer {
  using R = SequencerRegs<F>;
  // LATCH edge -> GATHER, PHI_LOAD, 16 iterations, ready seen, FRONT, SELECT,
  // THETA_LOAD, 16 iterations, ready seen (the pose, report and count edge).
  static constexpr unsigned kUpdateLatencyClocks = 5 + 2 * (rtl::cordic::kIterations + 1);

  static bool in_phase(const R& r, int phase) { return to_s64(r.phase) == phase; }
  // The period ends in this clock.
  static bool period_end(const R& r, Period<F> update_clocks) {
    return !is_zero(update_clocks) && r.period_count + uint<F, 1>(1) >= update_clocks;
  }

  static R next(const R& r, const SequencerIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    if (!is_zero(in.clear_overrun))
      n.overrun = uint<F, 1>(0);
    const bool end = period_end(r, in.update_clocks);
    n.period_count = end ? Period<F>(0) : wrap<Period<F> >(r.period_count + uint<F, 1>(1));
    const long long phase = to_s64(r.phase);
    if (end && phase != constants::kPhaseIdle)
      n.overrun = uint<F, 1>(1);
    switch (phase) {
      case constants::kPhaseIdle:
        if (end)
          n.phase = Phase<F>(constants::kPhaseLatch);
        break;
      case constants::kPhasePhiWait:
        if (!is_zero(in.cordic_ready))
          n.phase = Phase<F>(constants::kPhaseFront);
        break;
      case constants::kPhaseThetaWait:
        if (!is_zero(in.cordic_ready)) {
          n.phase = Phase<F>(constants::kPhaseIdle);
          n.updates = wrap<Updates<F> >(r.updates + uint<F, 1>(1));
        }
        break;
      default:
        n.phase = wrap<Phase<F> >(r.phase + uint<F, 1>(1));
        break;
    }
    return n;
  }
};

// ---- rear unit ----------------------------------------------------------------
// ds = kappa (nL + nR) / 2, dtheta = kappa (nR - nL) / D (paper eqs. 1-3),
// the halving and the track folded into the scale registers.
template <class F>
struct RearRegs {
  Distance<F> ds{0};
  Heading<F> dtheta{0};
};
template <class F>
struct RearIn {
  uint<F, 1> start{0};
  Count<F> n_left{0}, n_right{0};
  Scale<F> ds_scale{0}, dtheta_scale{0};
  uint<F, 1> reset{0};
};

template <class F>
struct RearUnit {
  using R = RearRegs<F>;
  static R next(const R& r, const RearIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    if (is_zero(in.start))
      return r;
    // |products| < 2^53 at 2^-40; the 2^-32 m rounding is the only loss.
    using Product = sint<F, constants::kCountBits + 1 + constants::kScaleBits + 1>;
    const Product ds_units =
        wrap<Product>((in.n_left + in.n_right) * wrap<SignedScale<F> >(in.ds_scale));
    const Product dtheta_units =
        wrap<Product>((in.n_right - in.n_left) * wrap<SignedScale<F> >(in.dtheta_scale));
    R n;
    n.ds = wrap<Distance<F> >(round_shr<constants::kScaleShift>(ds_units));
    n.dtheta = wrap<Heading<F> >(dtheta_units);
    return n;
  }
};

// ---- front unit ---------------------------------------------------------------
// The drive wheel rolls dF along its own heading theta + phi; the rear-axle
// midpoint then moves ds = dF cos(phi) along theta and the body turns
// dtheta = dF sin(phi) / L. (The paper's eq. 5 prints cos(theta) sin(phi)
// for the y increment; see docs/odometry.md.) Two steps: `start` latches
// the counts, steering and dF; `finish` applies the CORDIC's sin/cos of the
// mid-period steering angle.
template <class F>
struct FrontRegs {
  SteerPosition<F> steer_position{0};  // steering counts since reset (wheel straight at reset)
  Steer<F> phi{0}, phi_prev{0};        // clamped steering angle, this and the last period
  uint<F, 1> clamped{0};               // phi was limited in this period
  uint<F, 1> clamp_flag{0};            // sticky
  Drive<F> drive{0};                   // dF: wheel roll, 2^-32 m (|nF| < 2^19 counts)
  Drive<F> turn_per_sin{0};            // dF / L in 2^-32 turn: dtheta before sin(phi)
  Distance<F> ds{0};
  Heading<F> dtheta{0};
};
template <class F>
struct FrontIn {
  uint<F, 1> start{0}, finish{0};
  Count<F> n_front{0}, n_steer{0};
  cordic::SinCos<F> steer_sincos;
  Scale<F> ds_scale{0}, dtheta_scale{0}, steer_scale{0};
  Scale<F> steer_limit{0};  // 2^-32 turn
  uint<F, 1> clear_clamp{0};
  uint<F, 1> reset{0};
};

template <class F>
struct FrontUnit {
  using R = FrontRegs<F>;
  static R next(const R& r, const FrontIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    if (!is_zero(in.clear_clamp))
      n.clamp_flag = uint<F, 1>(0);
    if (!is_zero(in.start)) {
      n.steer_position = saturate<SteerPosition<F> >(r.steer_position + in.n_steer);
      using Raw = sint<F, constants::kSteerPositionBits + constants::kScaleBits + 2>;
      using Limit = sint<F, constants::kScaleBits + constants::kScaleShift + 1>;
      const Raw raw = wrap<Raw>(n.steer_position * wrap<SignedScale<F> >(in.steer_scale));
      const Limit limit = wrap<Limit>(shl<constants::kScaleShift>(in.steer_limit));  // <= 2^38
      const bool above = raw > limit;
      const bool below = raw < -limit;
      n.clamped = wrap<uint<F, 1> >(above || below);
      if (above || below)
        n.clamp_flag = uint<F, 1>(1);
      n.phi_prev = r.phi;
      n.phi = above   ? wrap<Steer<F> >(limit)
              : below ? wrap<Steer<F> >(-limit)
                      : wrap<Steer<F> >(raw);
      using Roll = sint<F, constants::kCountBits + constants::kScaleBits + 1>;
      n.drive = round_shr<constants::kScaleShift>(
          wrap<Roll>(in.n_front * wrap<SignedScale<F> >(in.ds_scale)));
      n.turn_per_sin = round_shr<constants::kScaleShift>(
          wrap<Roll>(in.n_front * wrap<SignedScale<F> >(in.dtheta_scale)));
    }
    if (!is_zero(in.finish)) {
      // |dF cos| <= |dF| and |dF/L sin| <= |dF/L|: the narrowing wraps nothing.
      using Product = sint<F, constants::kDriveBits + rtl::cordic::kOutputFractionBits + 2>;
      n.ds = wrap<Distance<F> >(round_shr<rtl::cordic::kOutputFractionBits>(
          wrap<Product>(r.drive * in.steer_sincos.cos)));
      n.dtheta =
          wrap<Heading<F> >(round_shr<rtl::cordic::kOutputFractionBits - constants::kScaleShift>(
              wrap<Product>(r.turn_per_sin * in.steer_sincos.sin)));
    }
    return n;
  }
  // Mid-period steering angle, the CORDIC input of the `finish` step.
  static uint<F, rtl::cordic::kAngleBits> cordic_angle(const R& r) {
    return to_cordic_angle<F>(
        shr<1>(wrap<sint<F, constants::kSteerBits + 1> >(r.phi + r.phi_prev)));
  }
};

// ---- min-select ---------------------------------------------------------------
// The paper's error reduction: slip and bumps only ever add counts, so the
// source that claims less motion is the better one. Comparing single 100 us
// increments is biased, though: each is quantised by up to one edge, and the
// minimum of two noisy readings under-reads (docs/odometry.md). So each
// source's increments go into a leaky sum A <- A - A/2^shift + inc, which
// telescopes (quantisation stays bounded), and the comparison D = |A_rear| -
// |A_front| has hysteresis: the front takes a component over when D >
// threshold and gives it back when D <= -threshold, so noise around one
// threshold cannot flip the choice every update. shift = 0, threshold = 0 is
// exactly the paper's memoryless minimum (ties: rear). The policies:
// per_component (the paper: the smaller |ds| and the smaller |dtheta|,
// independently), whole_set (both increments of the source that travelled
// less), rear_only, front_only.
template <class F>
struct SelectRegs {
  Distance<F> ds{0};
  Heading<F> dtheta{0};
  uint<F, 1> ds_from_front{0};      // status: which source won the distance
  uint<F, 1> dtheta_from_front{0};  // status: which source won the heading
  Accumulator<F> rear_ds_sum{0}, front_ds_sum{0}, rear_dtheta_sum{0}, front_dtheta_sum{0};
};
template <class F>
struct SelectIn {
  uint<F, 1> select{0};
  RearRegs<F> rear;
  Distance<F> front_ds{0};
  Heading<F> front_dtheta{0};
  uint<F, constants::kPolicyBits> policy{0};
  uint<F, constants::kShiftBits> shift{0};
  Scale<F> ds_threshold{0};      // 2^-32 m
  Scale<F> dtheta_threshold{0};  // 2^-40 turn
  uint<F, 1> reset{0};
};

template <class F>
struct MinSelect {
  using R = SelectRegs<F>;
  using A = Accumulator<F>;
  static R next(const R& r, const SelectIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    if (is_zero(in.select))
      return r;
    R n;
    n.rear_ds_sum = leak(r.rear_ds_sum, in.rear.ds, in.shift);
    n.front_ds_sum = leak(r.front_ds_sum, in.front_ds, in.shift);
    n.rear_dtheta_sum = leak(r.rear_dtheta_sum, in.rear.dtheta, in.shift);
    n.front_dtheta_sum = leak(r.front_dtheta_sum, in.front_dtheta, in.shift);
    const bool front_ds =
        front_wins(r.ds_from_front, n.rear_ds_sum, n.front_ds_sum, in.ds_threshold);
    const bool front_dtheta =
        front_wins(r.dtheta_from_front, n.rear_dtheta_sum, n.front_dtheta_sum, in.dtheta_threshold);
    bool ds_front = false;
    bool dtheta_front = false;
    switch (to_s64(in.policy)) {
      case constants::kPolicyPerComponent:
        ds_front = front_ds;
        dtheta_front = front_dtheta;
        break;
      case constants::kPolicyWholeSet:
        ds_front = front_ds;
        dtheta_front = front_ds;
        break;
      case constants::kPolicyRearOnly:
        break;
      default:  // kPolicyFrontOnly: the 2-bit field's last value
        ds_front = true;
        dtheta_front = true;
        break;
    }
    n.ds = ds_front ? in.front_ds : in.rear.ds;
    n.dtheta = dtheta_front ? in.front_dtheta : in.rear.dtheta;
    n.ds_from_front = wrap<uint<F, 1> >(ds_front);
    n.dtheta_from_front = wrap<uint<F, 1> >(dtheta_front);
    return n;
  }

 private:
  // A - A/2^shift + inc, saturating; shift 0 keeps only inc.
  template <class Increment>
  static A leak(const A& a, const Increment& inc, uint<F, constants::kShiftBits> shift) {
    const sint<F, constants::kAccumulatorBits + 1> kept =
        wrap<sint<F, constants::kAccumulatorBits + 1> >(a - shr_by(a, shift));
    return saturate<A>(kept + inc);
  }
  // The front's claim must fall below the rear's by more than the threshold
  // to take over, and rise above it by as much to hand back.
  static bool front_wins(uint<F, 1> front_now, const A& rear, const A& front, Scale<F> threshold) {
    using Magnitude = sint<F, constants::kAccumulatorBits + 1>;  // |A| <= 2^61
    const Magnitude rear_magnitude = rear < A(0) ? wrap<Magnitude>(-rear) : wrap<Magnitude>(rear);
    const Magnitude front_magnitude =
        front < A(0) ? wrap<Magnitude>(-front) : wrap<Magnitude>(front);
    const Magnitude d = wrap<Magnitude>(rear_magnitude - front_magnitude);  // |d| <= 2^61
    const SignedScale<F> t = wrap<SignedScale<F> >(threshold);
    return !is_zero(front_now) ? d > -t : d > t;
  }
};

// ---- pose integrator ----------------------------------------------------------
// x += ds cos(theta_mid), y += ds sin(theta_mid), theta += dtheta, with
// theta_mid = theta + dtheta/2 (midpoint rule: exact for a straight line,
// second order on arcs). x and y wrap modulo 2^64, theta at one turn.
template <class F>
struct PoseRegs {
  Words<F> x, y;  // 2^-46 m
  Theta<F> theta{0};
};
template <class F>
struct PoseIn {
  uint<F, 1> integrate{0};
  Distance<F> ds{0};
  Heading<F> dtheta{0};
  cordic::SinCos<F> heading_sincos;
  uint<F, 1> set_pose{0};  // host initialisation; wins over an update in the same clock
  PoseRegs<F> new_pose;
  uint<F, 1> reset{0};
};

template <class F>
struct PoseIntegrator {
  using R = PoseRegs<F>;
  using Output = typename cordic::Cordic<F>::Output;
  static R next(const R& r, const PoseIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    if (!is_zero(in.set_pose))
      return in.new_pose;
    if (is_zero(in.integrate))
      return r;
    R n;
    n.x = accumulate(r.x, in.ds, in.heading_sincos.cos);
    n.y = accumulate(r.y, in.ds, in.heading_sincos.sin);
    n.theta = wrap<Theta<F> >(wrap<sint<F, constants::kThetaBits + 1> >(r.theta) + in.dtheta);
    return n;
  }
  // The mid-step heading theta + dtheta / 2, the CORDIC input of the update.
  static uint<F, rtl::cordic::kAngleBits> cordic_angle(const R& r, const Heading<F>& dtheta) {
    using Mid = sint<F, constants::kHeadingBits + 1>;
    return to_cordic_angle<F>(
        wrap<Mid>(wrap<sint<F, constants::kThetaBits + 1> >(r.theta) + shr<1>(dtheta)));
  }

 private:
  // a + ds * factor modulo 2^64, word by word: the low words' carry goes into
  // the high words. |ds| < 2^47 and |factor| <= 2^14 + a few LSB, so the
  // product fits 63 bits.
  static Words<F> accumulate(const Words<F>& a, const Distance<F>& ds, const Output& factor) {
    using Product = sint<F, constants::kDistanceBits + rtl::cordic::kOutputFractionBits + 1>;
    const Product p = wrap<Product>(ds * factor);
    const uint<F, 33> lo = wrap<uint<F, 33> >(a.lo + bits<31, 0>(p));
    const sint<F, 32> p_high = wrap<sint<F, 32> >(shr<32>(p));
    Words<F> s;
    s.hi = wrap<sint<F, 32> >(a.hi + p_high + wrap<sint<F, 2> >(bit<32>(lo)));
    s.lo = wrap<uint<F, 32> >(lo);
    return s;
  }
};

// ---- report -------------------------------------------------------------------
// The results of the last update, as the register file shows them. Every
// one of them, the pose and the update count change on the same clock edge
// (the `publish` strobe is the pose's `integrate`), so an SPI snapshot can
// never pair the pose of one update with the increments or count of another.
template <class F>
struct ReportRegs {
  Distance<F> rear_ds{0}, front_ds{0}, ds{0};
  Heading<F> rear_dtheta{0}, front_dtheta{0}, dtheta{0};
  Steer<F> steer_phi{0};
  SteerPosition<F> steer_position{0};
  uint<F, 1> ds_from_front{0}, dtheta_from_front{0};
};
template <class F>
struct ReportIn {
  uint<F, 1> publish{0};
  RearRegs<F> rear;
  Distance<F> front_ds{0};
  Heading<F> front_dtheta{0};
  Steer<F> steer_phi{0};
  SteerPosition<F> steer_position{0};
  Distance<F> ds{0};
  Heading<F> dtheta{0};
  uint<F, 1> ds_from_front{0}, dtheta_from_front{0};
  uint<F, 1> reset{0};
};

template <class F>
struct Report {
  using R = ReportRegs<F>;
  static R next(const R& r, const ReportIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    if (is_zero(in.publish))
      return r;
    R n;
    n.rear_ds = in.rear.ds;
    n.front_ds = in.front_ds;
    n.ds = in.ds;
    n.rear_dtheta = in.rear.dtheta;
    n.front_dtheta = in.front_dtheta;
    n.dtheta = in.dtheta;
    n.steer_phi = in.steer_phi;
    n.steer_position = in.steer_position;
    n.ds_from_front = in.ds_from_front;
    n.dtheta_from_front = in.dtheta_from_front;
    return n;
  }
};

// ---- the datapath ---------------------------------------------------------------
// What crosses from the four EPPMs: the count each latched at the last
// latch-and-clear.
template <class F>
struct LatchedCounts {
  Count<F> left_rear{0}, right_rear{0}, front_drive{0}, steering{0};
};

// The datapath's register bank: the leaves' registers.
template <class F>
struct Regs {
  SequencerRegs<F> sequencer;
  cordic::Regs<F> cordic;
  RearRegs<F> rear;
  FrontRegs<F> front;
  SelectRegs<F> select;
  PoseRegs<F> pose;
  ReportRegs<F> report;
};

// Every leaf's inputs.
template <class F>
struct UnitIns {
  SequencerIn<F> sequencer;
  cordic::In<F> cordic;
  RearIn<F> rear;
  FrontIn<F> front;
  SelectIn<F> select;
  PoseIn<F> pose;
  ReportIn<F> report;
};

// Config: the odometry Config ports (cfg, the scales, limit, thresholds,
// set_x/set_y/set_theta); Pulses: the odometry Pulses ports (status.overrun
// and status.steer_clamped clears, command.set_pose, command.clear_flags).
template <class F>
struct Datapath {
  using Cordic = cordic::Cordic<F>;
  using Seq = Sequencer<F>;

  // The EPPMs' latch-and-clear wire: the LATCH phase.
  static uint<F, 1> latch(const SequencerRegs<F>& s) {
    return wrap<uint<F, 1> >(Seq::in_phase(s, constants::kPhaseLatch));
  }

  template <class Config, class Pulses>
  static SequencerIn<F> sequencer_in(const cordic::Regs<F>& c, const Config& cfg,
                                     const Pulses& pulses, uint<F, 1> reset) {
    SequencerIn<F> in;
    in.update_clocks = cfg.cfg.update_clocks;
    in.cordic_ready = c.ready;
    in.clear_overrun = pulses.status.overrun | pulses.command.clear_flags;
    in.reset = reset;
    return in;
  }

  static bool integrating(const SequencerRegs<F>& s, const cordic::Regs<F>& c) {
    return Seq::in_phase(s, constants::kPhaseThetaWait) && !is_zero(c.ready);
  }
  // Each leaf's inputs from the current registers, the EPPMs' latched
  // counts, the configuration and this clock's strobes.
  template <class Pulses>
  static cordic::In<F> cordic_in(const SequencerRegs<F>& s, const FrontRegs<F>& front,
                                 const SelectRegs<F>& select, const PoseRegs<F>& pose,
                                 const Pulses& pulses, uint<F, 1> reset) {
    const bool phi_load = Seq::in_phase(s, constants::kPhasePhiLoad);
    cordic::In<F> in;
    in.load = wrap<uint<F, 1> >(phi_load || Seq::in_phase(s, constants::kPhaseThetaLoad));
    in.angle = phi_load ? FrontUnit<F>::cordic_angle(front)
                        : PoseIntegrator<F>::cordic_angle(pose, select.dtheta);
    in.clear_flags = pulses.status.overrun | pulses.command.clear_flags;
    in.reset = reset;
    return in;
  }
  template <class Config>
  static RearIn<F> rear_in(const SequencerRegs<F>& s, const LatchedCounts<F>& latched,
                           const Config& cfg, uint<F, 1> reset) {
    RearIn<F> in;
    in.start = wrap<uint<F, 1> >(Seq::in_phase(s, constants::kPhaseGather));
    in.n_left = latched.left_rear;
    in.n_right = latched.right_rear;
    in.ds_scale = cfg.rear_ds_scale.value;
    in.dtheta_scale = cfg.rear_dtheta_scale.value;
    in.reset = reset;
    return in;
  }
  template <class Config, class Pulses>
  static FrontIn<F> front_in(const SequencerRegs<F>& s, const cordic::Regs<F>& c,
                             const LatchedCounts<F>& latched, const Config& cfg,
                             const Pulses& pulses, uint<F, 1> reset) {
    FrontIn<F> in;
    in.start = wrap<uint<F, 1> >(Seq::in_phase(s, constants::kPhaseGather));
    in.finish = wrap<uint<F, 1> >(Seq::in_phase(s, constants::kPhaseFront));
    in.n_front = latched.front_drive;
    in.n_steer = latched.steering;
    in.steer_sincos = c.result;
    in.ds_scale = cfg.front_ds_scale.value;
    in.dtheta_scale = cfg.front_dtheta_scale.value;
    in.steer_scale = cfg.steer_scale.value;
    in.steer_limit = cfg.steer_limit.value;
    in.clear_clamp = pulses.status.steer_clamped | pulses.command.clear_flags;
    in.reset = reset;
    return in;
  }
  template <class Config>
  static SelectIn<F> select_in(const SequencerRegs<F>& s, const RearRegs<F>& rear,
                               const FrontRegs<F>& front, const Config& cfg, uint<F, 1> reset) {
    SelectIn<F> in;
    in.select = wrap<uint<F, 1> >(Seq::in_phase(s, constants::kPhaseSelect));
    in.rear = rear;
    in.front_ds = front.ds;
    in.front_dtheta = front.dtheta;
    in.policy = cfg.cfg.policy;
    in.shift = cfg.cfg.select_shift;
    in.ds_threshold = cfg.select_ds_threshold.value;
    in.dtheta_threshold = cfg.select_dtheta_threshold.value;
    in.reset = reset;
    return in;
  }
  template <class Config, class Pulses>
  static PoseIn<F> pose_in(const SequencerRegs<F>& s, const cordic::Regs<F>& c,
                           const SelectRegs<F>& select, const Config& cfg, const Pulses& pulses,
                           uint<F, 1> reset) {
    PoseIn<F> in;
    in.integrate = wrap<uint<F, 1> >(integrating(s, c));
    in.ds = select.ds;
    in.dtheta = select.dtheta;
    in.heading_sincos = c.result;
    in.set_pose = pulses.command.set_pose;
    in.new_pose.x = to_words(cfg.set_x.bits);
    in.new_pose.y = to_words(cfg.set_y.bits);
    in.new_pose.theta = cfg.set_theta.bits;
    in.reset = reset;
    return in;
  }
  static ReportIn<F> report_in(const SequencerRegs<F>& s, const cordic::Regs<F>& c,
                               const RearRegs<F>& rear, const FrontRegs<F>& front,
                               const SelectRegs<F>& select, uint<F, 1> reset) {
    ReportIn<F> in;
    in.publish = wrap<uint<F, 1> >(integrating(s, c));  // on the pose's edge
    in.rear = rear;
    in.front_ds = front.ds;
    in.front_dtheta = front.dtheta;
    in.steer_phi = front.phi;
    in.steer_position = front.steer_position;
    in.ds = select.ds;
    in.dtheta = select.dtheta;
    in.ds_from_front = select.ds_from_front;
    in.dtheta_from_front = select.dtheta_from_front;
    in.reset = reset;
    return in;
  }
  // Every leaf's inputs.
  template <class Config, class Pulses>
  static UnitIns<F> unit_inputs(const SequencerRegs<F>& s, const cordic::Regs<F>& c,
                                const RearRegs<F>& rear, const FrontRegs<F>& front,
                                const SelectRegs<F>& select, const PoseRegs<F>& pose,
                                const LatchedCounts<F>& latched, const Config& cfg,
                                const Pulses& pulses, uint<F, 1> reset) {
    const UnitIns<F> u = {sequencer_in(c, cfg, pulses, reset),
                          cordic_in(s, front, select, pose, pulses, reset),
                          rear_in(s, latched, cfg, reset),
                          front_in(s, c, latched, cfg, pulses, reset),
                          select_in(s, rear, front, cfg, reset),
                          pose_in(s, c, select, cfg, pulses, reset),
                          report_in(s, c, rear, front, select, reset)};
    return u;
  }

  // One fabric clock of the whole datapath: every leaf's inputs from the
  // current registers, then every leaf.
  template <class Config, class Pulses>
  static Regs<F> next(const Regs<F>& r, const LatchedCounts<F>& latched, const Config& cfg,
                      const Pulses& pulses, uint<F, 1> reset) {
    const UnitIns<F> u = unit_inputs(r.sequencer, r.cordic, r.rear, r.front, r.select, r.pose,
                                     latched, cfg, pulses, reset);
    Regs<F> n;
    n.sequencer = Seq::next(r.sequencer, u.sequencer);
    n.cordic = Cordic::next(r.cordic, u.cordic);
    n.rear = RearUnit<F>::next(r.rear, u.rear);
    n.front = FrontUnit<F>::next(r.front, u.front);
    n.select = MinSelect<F>::next(r.select, u.select);
    n.pose = PoseIntegrator<F>::next(r.pose, u.pose);
    n.report = Report<F>::next(r.report, u.report);
    return n;
  }

  // What the register file reads: every odometry.* status field.
  template <class Status>
  static Status status(const SequencerRegs<F>& s, const FrontRegs<F>& front,
                       const PoseRegs<F>& pose, const ReportRegs<F>& r) {
    Status o;
    o.status.overrun = s.overrun;
    o.status.steer_clamped = front.clamp_flag;
    o.status.ds_from_front = r.ds_from_front;
    o.status.dtheta_from_front = r.dtheta_from_front;
    o.status.phase = s.phase;
    o.updates.count = s.updates;
    from_words(o.pose_x.bits, pose.x);
    from_words(o.pose_y.bits, pose.y);
    o.pose_theta.bits = pose.theta;
    o.rear_ds.bits = r.rear_ds;
    o.rear_dtheta.bits = r.rear_dtheta;
    o.front_ds.bits = r.front_ds;
    o.front_dtheta.bits = r.front_dtheta;
    o.ds.bits = r.ds;
    o.dtheta.bits = r.dtheta;
    o.steer_phi.bits = r.steer_phi;
    o.steer_position.counts = r.steer_position;
    return o;
  }
  template <class Status>
  static Status status(const Regs<F>& r) {
    return status<Status>(r.sequencer, r.front, r.pose, r.report);
  }
};

}  // namespace odometry
}  // namespace logic
}  // namespace odoloc
