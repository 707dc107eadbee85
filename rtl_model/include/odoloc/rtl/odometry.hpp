// Odometry computation: rear unit (idler wheels), front unit (drive + steer
// wheel), min-select comparators, pose integrator and the sequencer that
// runs them once per control period. Paper: Kurian & Pillai, sections 3-4,
// with the corrected front-wheel kinematics (docs/odometry.md).
//
// Fixed-point formats (all documented in docs/odometry.md):
//   counts            SInt<20>  latched EPPM increments (x4 edges)
//   scale registers   UInt<32>  metres or turns per count, units 2^-40
//   ds                SInt<48>  distance of the rear-axle midpoint, 2^-32 m
//   dtheta            SInt<56>  heading increment, 2^-40 turn
//   x, y              SInt<64>  2^-46 m (exact sums of ds * cos, ds * sin)
//   theta             UInt<40>  binary angle, 2^40 = one turn
//   phi (steering)    SInt<40>  2^-40 turn, clamped to +-steer_limit
#pragma once

#include <cstdint>

#include "odoloc/ports.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/cordic_core.hpp"

namespace odoloc::rtl {

// Configuration, clear strobes and commands, and status: the odometry.*
// registers (odoloc/ports.hpp, generated from regmap/odoloc.yaml).
using OdometryConfig = ports::odometry::Config;
using OdometryPulses = ports::odometry::Pulses;
using OdometryStatus = ports::odometry::Status;
// per_component (the paper: the smaller |ds| and the smaller |dtheta|,
// independently), whole_set (both increments of the source that travelled
// less), rear_only, front_only.
using MinSelectPolicy = regs::odometry::cfg::Policy;

using Distance = SInt<48>;  // 2^-32 m
using Heading = SInt<56>;   // 2^-40 turn
using Steer = SInt<40>;     // 2^-40 turn

// 40-bit binary angle (2^-40 turn) to the CORDIC's 16 bits, rounded to nearest.
template <int W>
constexpr cordic::Angle to_cordic_angle(SInt<W> turns_40) {
  return round_shr<24>(turns_40).template wrap<cordic::kAngleBits>().as_uint();
}

// Rear unit: ds = kappa (nL + nR) / 2, dtheta = kappa (nR - nL) / D (paper eqs. 1-3).
struct RearOdometryUnitRegs {
  Distance ds;
  Heading dtheta;
  bool operator==(const RearOdometryUnitRegs&) const = default;
  ODOLOC_FIELDS(ds, dtheta)
};

class RearOdometryUnit : public Registers<RearOdometryUnitRegs> {
 public:
  struct In {
    UInt<1> start;
    SInt<20> n_left, n_right;
    UInt<32> ds_scale, dtheta_scale;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    if (!in.start)
      return r_;
    // |products| < 2^53 at 2^-40; the 2^-32 m rounding is the only loss.
    return {round_shr<8>((in.n_left + in.n_right) * in.ds_scale.to_sint()).wrap<Distance::width>(),
            ((in.n_right - in.n_left) * in.dtheta_scale.to_sint()).wrap<Heading::width>()};
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.start | in.reset).is_zero(); }
};

// Front unit. The drive wheel rolls dF along its own heading theta + phi; the
// rear-axle midpoint then moves ds = dF cos(phi) along theta and the body
// turns dtheta = dF sin(phi) / L. (The paper's eq. 5 prints cos(theta)
// sin(phi) for the y increment; see docs/odometry.md.) Two steps: `start`
// latches the counts, steering and dF; `finish` applies the CORDIC's
// sin/cos of the mid-period steering angle.
struct FrontOdometryUnitRegs {
  SInt<24> steer_position;  // steering counts since reset (wheel straight at reset)
  Steer phi, phi_prev;      // clamped steering angle, this and the last period
  UInt<1> clamped;          // phi was limited in this period
  UInt<1> clamp_flag;       // sticky
  SInt<46> drive;           // dF: wheel roll, 2^-32 m (|nF| < 2^19 counts)
  SInt<46> turn_per_sin;    // dF / L in 2^-32 turn: dtheta before sin(phi)
  Distance ds;
  Heading dtheta;
  bool operator==(const FrontOdometryUnitRegs&) const = default;
  ODOLOC_FIELDS(steer_position, phi, phi_prev, clamped, clamp_flag, drive, turn_per_sin, ds, dtheta)
};

class FrontOdometryUnit : public Registers<FrontOdometryUnitRegs> {
 public:
  struct In {
    UInt<1> start, finish;
    SInt<20> n_front, n_steer;
    cordic::SinCos steer_sincos;
    UInt<32> ds_scale, dtheta_scale, steer_scale, steer_limit;
    UInt<1> clear_clamp, reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    if (in.clear_clamp)
      n.clamp_flag = UInt<1>{};
    if (in.start) {
      n.steer_position = (r_.steer_position + in.n_steer).sat<24>();
      const SInt<58> raw = n.steer_position * in.steer_scale.to_sint();
      const SInt<41> limit = in.steer_limit.shl<8>().to_sint();  // <= 2^38 (1/4 turn)
      const bool above = raw > limit, below = raw < -limit;
      n.clamped = UInt<1>::truncate(above || below);
      if (n.clamped)
        n.clamp_flag = UInt<1>{1};
      n.phi_prev = r_.phi;
      n.phi = (above ? SInt<58>{limit} : below ? SInt<58>{-limit} : raw).wrap<Steer::width>();
      n.drive = round_shr<8>(in.n_front * in.ds_scale.to_sint());
      n.turn_per_sin = round_shr<8>(in.n_front * in.dtheta_scale.to_sint());
    }
    if (in.finish) {
      // |dF cos| <= |dF| and |dF/L sin| <= |dF/L|: the narrowing wraps nothing.
      n.ds = round_shr<cordic::kOutputFractionBits>(r_.drive * in.steer_sincos.cos)
                 .wrap<Distance::width>();
      n.dtheta = round_shr<cordic::kOutputFractionBits - 8>(r_.turn_per_sin * in.steer_sincos.sin)
                     .wrap<Heading::width>();
    }
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return (in.start | in.finish | in.clear_clamp | in.reset).is_zero();
  }
  // Mid-period steering angle, the CORDIC input of the `finish` step.
  [[nodiscard]] cordic::Angle cordic_angle() const {
    return to_cordic_angle((r_.phi + r_.phi_prev).shr<1>());
  }
};

// The paper's error reduction: slip and bumps only ever add counts, so the
// source that claims less motion is the better one. Comparing single 100 us
// increments is biased, though: each is quantised by up to one edge, and the
// minimum of two noisy readings under-reads (docs/odometry.md). So each
// source's increments go into a leaky sum A <- A - A/2^shift + inc, which
// telescopes (quantisation stays bounded), and the comparison D = |A_rear| -
// |A_front| has hysteresis: the front takes a component over when D >
// threshold and gives it back when D <= -threshold, so noise around one
// threshold cannot flip the choice every update. shift = 0, threshold = 0 is
// exactly the paper's memoryless minimum (ties: rear).
struct MinSelectRegs {
  Distance ds;
  Heading dtheta;
  UInt<1> ds_from_front;      // status: which source won the distance
  UInt<1> dtheta_from_front;  // status: which source won the heading
  SInt<62> rear_ds_sum, front_ds_sum, rear_dtheta_sum, front_dtheta_sum;  // leaky sums
  bool operator==(const MinSelectRegs&) const = default;
  ODOLOC_FIELDS(ds, dtheta, ds_from_front, dtheta_from_front, rear_ds_sum, front_ds_sum,
                rear_dtheta_sum, front_dtheta_sum)
};

class MinSelect : public Registers<MinSelectRegs> {
 public:
  using Accumulator = SInt<62>;
  struct In {
    UInt<1> select;
    RearOdometryUnit::Regs rear;
    Distance front_ds;
    Heading front_dtheta;
    UInt<2> policy;
    UInt<4> shift;
    UInt<32> ds_threshold;      // 2^-32 m
    UInt<32> dtheta_threshold;  // 2^-40 turn
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    if (!in.select)
      return r_;
    Regs n = r_;
    n.rear_ds_sum = leak(r_.rear_ds_sum, in.rear.ds, in.shift);
    n.front_ds_sum = leak(r_.front_ds_sum, in.front_ds, in.shift);
    n.rear_dtheta_sum = leak(r_.rear_dtheta_sum, in.rear.dtheta, in.shift);
    n.front_dtheta_sum = leak(r_.front_dtheta_sum, in.front_dtheta, in.shift);
    const bool front_ds =
        front_wins(r_.ds_from_front, n.rear_ds_sum, n.front_ds_sum, in.ds_threshold);
    const bool front_dtheta = front_wins(r_.dtheta_from_front, n.rear_dtheta_sum,
                                         n.front_dtheta_sum, in.dtheta_threshold);
    bool ds_front = false, dtheta_front = false;
    switch (static_cast<MinSelectPolicy>(in.policy.value())) {
      case MinSelectPolicy::kPerComponent:
        ds_front = front_ds;
        dtheta_front = front_dtheta;
        break;
      case MinSelectPolicy::kWholeSet:
        ds_front = dtheta_front = front_ds;
        break;
      case MinSelectPolicy::kRearOnly:
        break;
      case MinSelectPolicy::kFrontOnly:
        ds_front = dtheta_front = true;
        break;
    }
    n.ds = ds_front ? in.front_ds : in.rear.ds;
    n.dtheta = dtheta_front ? in.front_dtheta : in.rear.dtheta;
    n.ds_from_front = UInt<1>::truncate(ds_front);
    n.dtheta_from_front = UInt<1>::truncate(dtheta_front);
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.select | in.reset).is_zero(); }

 private:
  // A - A/2^shift + inc, saturating; shift 0 keeps only inc.
  template <int W>
  static Accumulator leak(Accumulator a, SInt<W> inc, UInt<4> shift) {
    return ((a - a.dshr(shift)) + inc).template sat<Accumulator::width>();
  }
  // The front's claim must fall below the rear's by more than the threshold
  // to take over, and rise above it by as much to hand back.
  static bool front_wins(UInt<1> front_now, Accumulator rear, Accumulator front,
                         UInt<32> threshold) {
    const SInt<64> d = (rear.abs().to_sint() - front.abs().to_sint()).wrap<64>();  // |d| < 2^62
    return front_now ? d > -threshold.to_sint() : d > threshold.to_sint();
  }
};

// Pose: x += ds cos(theta_mid), y += ds sin(theta_mid), theta += dtheta, with
// theta_mid = theta + dtheta/2 (midpoint rule: exact for a straight line,
// second order on arcs).
struct PoseIntegratorRegs {
  SInt<64> x, y;   // 2^-46 m
  UInt<40> theta;  // 2^-40 turn
  bool operator==(const PoseIntegratorRegs&) const = default;
  ODOLOC_FIELDS(x, y, theta)
};

class PoseIntegrator : public Registers<PoseIntegratorRegs> {
 public:
  struct In {
    UInt<1> integrate;
    Distance ds;
    Heading dtheta;
    cordic::SinCos heading_sincos;
    UInt<1> set_pose;  // host initialisation; wins over an update in the same clock
    Regs new_pose;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    if (in.set_pose)
      return in.new_pose;
    if (!in.integrate)
      return r_;
    return {add_wrap(r_.x, in.ds * in.heading_sincos.cos),
            add_wrap(r_.y, in.ds * in.heading_sincos.sin),
            (r_.theta.to_sint() + in.dtheta).wrap<40>().as_uint()};
  }
  [[nodiscard]] bool idle(const In& in) const {
    return (in.integrate | in.set_pose | in.reset).is_zero();
  }
  [[nodiscard]] cordic::Angle cordic_angle(Heading dtheta) const {
    return to_cordic_angle(r_.theta.to_sint() + dtheta.shr<1>());
  }
};

// The results of the last update, as the register file shows them. Every
// one of them, the pose and the update count change on the same clock edge
// (the `publish` strobe is the pose's `integrate`), so an SPI snapshot can
// never pair the pose of one update with the increments or count of another.
struct OdometryReportRegs {
  Distance rear_ds, front_ds, ds;
  Heading rear_dtheta, front_dtheta, dtheta;
  Steer steer_phi;
  SInt<24> steer_position;
  UInt<1> ds_from_front, dtheta_from_front;
  bool operator==(const OdometryReportRegs&) const = default;
  ODOLOC_FIELDS(rear_ds, front_ds, ds, rear_dtheta, front_dtheta, dtheta, steer_phi, steer_position,
                ds_from_front, dtheta_from_front)
};

class OdometryReport : public Registers<OdometryReportRegs> {
 public:
  struct In {
    UInt<1> publish;
    RearOdometryUnit::Regs rear;
    Distance front_ds;
    Heading front_dtheta;
    Steer steer_phi;
    SInt<24> steer_position;
    Distance ds;
    Heading dtheta;
    UInt<1> ds_from_front, dtheta_from_front;
    UInt<1> reset;
  };
  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    if (!in.publish)
      return r_;
    return {.rear_ds = in.rear.ds,
            .front_ds = in.front_ds,
            .ds = in.ds,
            .rear_dtheta = in.rear.dtheta,
            .front_dtheta = in.front_dtheta,
            .dtheta = in.dtheta,
            .steer_phi = in.steer_phi,
            .steer_position = in.steer_position,
            .ds_from_front = in.ds_from_front,
            .dtheta_from_front = in.dtheta_from_front};
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.publish | in.reset).is_zero(); }
};

// Runs one update per control period with one shared CORDIC:
//   LATCH           latch-and-clear all four EPPMs
//   GATHER          rear unit computes; front unit takes counts and steering
//   PHI_LOAD/WAIT   CORDIC: sin/cos of the mid-period steering angle
//   FRONT           front unit finishes
//   SELECT          min-select
//   THETA_LOAD/WAIT CORDIC: sin/cos of the mid-step heading; in the clock the
//                   result is ready the pose integrates, the report publishes
//                   and `updates` counts, all on one edge
// Each phase's work commits on the edge that leaves the phase.
// kUpdateLatencyClocks from the LATCH edge to the pose edge.
using OdometryPhase = regs::odometry::status::Phase;

struct OdometrySequencerRegs {
  UInt<4> phase;
  UInt<16> period_count;
  UInt<32> updates;  // completed pose updates
  UInt<1> overrun;   // sticky: a period ended before the update finished
  bool operator==(const OdometrySequencerRegs&) const = default;
  ODOLOC_FIELDS(phase, period_count, updates, overrun)
};

class OdometrySequencer : public Registers<OdometrySequencerRegs> {
 public:
  // LATCH edge -> GATHER, PHI_LOAD, 16 iterations, ready seen, FRONT, SELECT,
  // THETA_LOAD, 16 iterations, ready seen (the pose, report and count edge).
  static constexpr unsigned kUpdateLatencyClocks = 5 + 2 * (cordic::kIterations + 1);
  struct In {
    UInt<16> update_clocks;
    UInt<1> cordic_ready;
    UInt<1> clear_overrun, reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    if (in.clear_overrun)
      n.overrun = UInt<1>{};
    const bool period_end =
        !in.update_clocks.is_zero() && r_.period_count + UInt<1>{1} >= in.update_clocks;
    n.period_count = period_end ? UInt<16>{} : (r_.period_count + UInt<1>{1}).wrap<16>();
    if (period_end && phase() != OdometryPhase::kIdle)
      n.overrun = UInt<1>{1};
    switch (phase()) {
      case OdometryPhase::kIdle:
        if (period_end)
          n.phase = encode(OdometryPhase::kLatch);
        break;
      case OdometryPhase::kPhiWait:
        if (in.cordic_ready)
          n.phase = encode(OdometryPhase::kFront);
        break;
      case OdometryPhase::kThetaWait:
        if (in.cordic_ready) {
          n.phase = encode(OdometryPhase::kIdle);
          n.updates = (r_.updates + UInt<1>{1}).wrap<32>();
        }
        break;
      default:
        n.phase = (r_.phase + UInt<1>{1}).wrap<4>();
        break;
    }
    return n;
  }
  [[nodiscard]] bool idle(const In&) const { return false; }  // the period counter runs

  // Fast-forward (clocked.hpp), in a phase that waits (idle, or a CORDIC
  // wait before RESULT_READY) with no clear and no period end: the period
  // counter restarts after the clock with period_count + 1 >= update_clocks
  // (the period end, an event); with update_clocks 0 it wraps and never ends.
  [[nodiscard]] std::uint64_t clocks_to_period_end(UInt<16> update_clocks) const {
    return update_clocks.is_zero()
               ? kNoEvent
               : clocks_to_fire(r_.period_count.value(), period_last(update_clocks));
  }
  void skip(std::uint64_t n, const In& in) {
    Regs next = r_;
    next.period_count =
        in.update_clocks.is_zero()
            ? UInt<16>::truncate(r_.period_count.value() + n)
            : UInt<16>::truncate(
                  run_restarting(r_.period_count.value(), period_last(in.update_clocks), n).count);
    commit(next);
  }
  [[nodiscard]] OdometryPhase phase() const { return static_cast<OdometryPhase>(r_.phase.value()); }
  [[nodiscard]] bool in(OdometryPhase p) const { return phase() == p; }

 private:
  static std::uint64_t period_last(UInt<16> update_clocks) { return update_clocks.value() - 1; }
  static constexpr UInt<4> encode(OdometryPhase p) { return UInt<4>{static_cast<std::uint8_t>(p)}; }
};

}  // namespace odoloc::rtl
