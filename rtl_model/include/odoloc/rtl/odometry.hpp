// Odometry computation: the datapath of the odometry fabric, from the four
// EPPMs' latched counts to the pose: the sequencer, one shared sequential
// CORDIC, the rear unit (idler wheels), the front unit (drive + steer
// wheel), min-select, the pose integrator and the report of the last
// update. Paper: Kurian & Pillai, sections 3-4, with the corrected
// front-wheel kinematics (docs/odometry.md, which has every format).
//
// The logic: logic/odometry.hpp (the one source, also the HLS kernel's).
// Here: what only a simulator needs around it (field lists, the waveform's
// names, activity gating, the between-updates path and the fast-forward).
#pragma once

#include <algorithm>
#include <cstdint>

#include "odoloc/logic/odometry.hpp"
#include "odoloc/ports.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/cordic.hpp"
#include "odoloc/rtl/family.hpp"
#include "odoloc/rtl/odometry_constants.hpp"

namespace odoloc::rtl {

// Configuration, clear strobes and commands, and status: the odometry.*
// registers (odoloc/ports.hpp, generated from regmap/odoloc.yaml).
using OdometryConfig = ports::odometry::Config;
using OdometryPulses = ports::odometry::Pulses;
using OdometryStatus = ports::odometry::Status;
using MinSelectPolicy = regs::odometry::cfg::Policy;
using OdometryPhase = regs::odometry::status::Phase;

static_assert(odometry::kPhaseIdle == encoding(OdometryPhase::kIdle) &&
              odometry::kPhaseLatch == encoding(OdometryPhase::kLatch) &&
              odometry::kPhaseGather == encoding(OdometryPhase::kGather) &&
              odometry::kPhasePhiLoad == encoding(OdometryPhase::kPhiLoad) &&
              odometry::kPhasePhiWait == encoding(OdometryPhase::kPhiWait) &&
              odometry::kPhaseFront == encoding(OdometryPhase::kFront) &&
              odometry::kPhaseSelect == encoding(OdometryPhase::kSelect) &&
              odometry::kPhaseThetaLoad == encoding(OdometryPhase::kThetaLoad) &&
              odometry::kPhaseThetaWait == encoding(OdometryPhase::kThetaWait));
static_assert(odometry::kPolicyPerComponent == encoding(MinSelectPolicy::kPerComponent) &&
              odometry::kPolicyWholeSet == encoding(MinSelectPolicy::kWholeSet) &&
              odometry::kPolicyRearOnly == encoding(MinSelectPolicy::kRearOnly) &&
              odometry::kPolicyFrontOnly == encoding(MinSelectPolicy::kFrontOnly));

using Distance = logic::odometry::Distance<Family>;  // 2^-32 m
using Heading = logic::odometry::Heading<Family>;    // 2^-40 turn
using Steer = logic::odometry::Steer<Family>;        // 2^-40 turn
using LatchedCounts = logic::odometry::LatchedCounts<Family>;

ODOLOC_LOGIC_FIELDS(logic::odometry::SequencerRegs, phase, period_count, updates, overrun)
ODOLOC_LOGIC_FIELDS(logic::odometry::RearRegs, ds, dtheta)
ODOLOC_LOGIC_FIELDS(logic::odometry::FrontRegs, steer_position, phi, phi_prev, clamped, clamp_flag,
                    drive, turn_per_sin, ds, dtheta)
ODOLOC_LOGIC_FIELDS(logic::odometry::SelectRegs, ds, dtheta, ds_from_front, dtheta_from_front,
                    rear_ds_sum, front_ds_sum, rear_dtheta_sum, front_dtheta_sum)
ODOLOC_LOGIC_FIELDS(logic::odometry::PoseRegs, x, y, theta)
ODOLOC_LOGIC_FIELDS(logic::odometry::ReportRegs, rear_ds, front_ds, ds, rear_dtheta, front_dtheta,
                    dtheta, steer_phi, steer_position, ds_from_front, dtheta_from_front)
ODOLOC_LOGIC_FIELDS(logic::odometry::LatchedCounts, left_rear, right_rear, front_drive, steering)
using OdometrySequencerRegs = logic::odometry::SequencerRegs<Family>;
using RearOdometryUnitRegs = logic::odometry::RearRegs<Family>;
using FrontOdometryUnitRegs = logic::odometry::FrontRegs<Family>;
using MinSelectRegs = logic::odometry::SelectRegs<Family>;
using PoseIntegratorRegs = logic::odometry::PoseRegs<Family>;
using OdometryReportRegs = logic::odometry::ReportRegs<Family>;

// x or y of the pose as one 64-bit value (2^-46 m).
inline SInt<64> pose_coordinate(const logic::Words<Family>& w) {
  SInt<64> v;
  logic::from_words(v, w);
  return v;
}

class RearOdometryUnit : public Registers<RearOdometryUnitRegs> {
 public:
  using In = logic::odometry::RearIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::odometry::RearUnit<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.start | in.reset).is_zero(); }
};

class FrontOdometryUnit : public Registers<FrontOdometryUnitRegs> {
 public:
  using In = logic::odometry::FrontIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::odometry::FrontUnit<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const {
    return (in.start | in.finish | in.clear_clamp | in.reset).is_zero();
  }
  // Mid-period steering angle, the CORDIC input of the `finish` step.
  [[nodiscard]] cordic::Angle cordic_angle() const {
    return logic::odometry::FrontUnit<Family>::cordic_angle(r_);
  }
};

class MinSelect : public Registers<MinSelectRegs> {
 public:
  using Accumulator = logic::odometry::Accumulator<Family>;
  using In = logic::odometry::SelectIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::odometry::MinSelect<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.select | in.reset).is_zero(); }
};

class PoseIntegrator : public Registers<PoseIntegratorRegs> {
 public:
  using In = logic::odometry::PoseIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::odometry::PoseIntegrator<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const {
    return (in.integrate | in.set_pose | in.reset).is_zero();
  }
};

class OdometryReport : public Registers<OdometryReportRegs> {
 public:
  using In = logic::odometry::ReportIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::odometry::Report<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.publish | in.reset).is_zero(); }
};

class OdometrySequencer : public Registers<OdometrySequencerRegs> {
  using Logic = logic::odometry::Sequencer<Family>;

 public:
  static constexpr unsigned kUpdateLatencyClocks = Logic::kUpdateLatencyClocks;
  using In = logic::odometry::SequencerIn<Family>;

  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
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
};

// The datapath's inputs besides its configuration.
struct OdometryDatapathInputs {
  LatchedCounts latched;    // the four EPPMs' counter().latched
  OdometryPulses odometry;  // odometry.status clears; command.set_pose, command.clear_flags
  UInt<1> reset;
  ODOLOC_FIELDS(latched, odometry, reset)
};

// The datapath as one block of the fabric (and the odometry HLS kernel's
// boundary): its children's wires from the current registers
// (logic::odometry::Datapath::unit_inputs), then its children.
class OdometryDatapath {
  using Logic = logic::odometry::Datapath<Family>;

 public:
  using In = OdometryDatapathInputs;
  using Config = OdometryConfig;
  using Wires = logic::odometry::UnitIns<Family>;

  [[nodiscard]] Wires wires(const In& in, const Config& cfg) const {
    return Logic::unit_inputs(sequencer_.regs(), cordic_.regs(), rear_.regs(), front_.regs(),
                              select_.regs(), integrator_.regs(), in.latched, cfg, in.odometry,
                              in.reset);
  }
  // The children, from wires computed before any of them is clocked.
  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void clock(const Wires& w, const Order& order = {}) {
    order([&] { clock_block<G>(sequencer_, w.sequencer); },
          [&] { clock_block<G>(cordic_, w.cordic); }, [&] { clock_block<G>(rear_, w.rear); },
          [&] { clock_block<G>(front_, w.front); }, [&] { clock_block<G>(select_, w.select); },
          [&] { clock_block<G>(integrator_, w.pose); }, [&] { clock_block<G>(report_, w.report); });
  }
  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Config& cfg, const Order& order = {}) {
    if (G == Gating::kOn && between_updates(in.odometry, in.reset)) {
      count_period<G>(cfg);
      return;
    }
    clock<G>(wires(in, cfg), order);
  }

  // Idle phase, no reset and no strobe: the CORDIC and every unit are idle,
  // the EPPMs see no latch; only the period counter moves (count_period).
  [[nodiscard]] bool between_updates(const OdometryPulses& pulses, UInt<1> reset) const {
    return sequencer_.in(OdometryPhase::kIdle) && reset.is_zero() && !any_set(pulses);
  }
  template <Gating G = Gating::kOn>
  void count_period(const Config& cfg) {
    clock_block<G>(sequencer_, sequencer_in(cfg, OdometryPulses{}, UInt<1>{}));
  }

  // Fast-forward (clocked.hpp), until the period end: the rest of an update
  // runs clock by clock, the CORDIC's waits as bare micro-rotations.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& in, const Config& cfg) const {
    if (!in.reset.is_zero() || any_set(in.odometry) || sequencer_.in(OdometryPhase::kLatch))
      return 0;
    return sequencer_.clocks_to_period_end(cfg.cfg.update_clocks);
  }
  [[gnu::flatten]] void skip(std::uint64_t n, const In& in, const Config& cfg) {
    while (n != 0 && !sequencer_.in(OdometryPhase::kIdle)) {
      const std::uint64_t iterations = cordic_wait();
      if (iterations == 0) {
        clock<Gating::kOn>(wires(in, cfg));
        --n;
        continue;
      }
      // Only the CORDIC iterates and the period counter counts: every unit
      // waits for RESULT_READY.
      const std::uint64_t clocks = std::min(n, iterations);
      cordic_.skip(clocks);
      sequencer_.skip(clocks, sequencer_in(cfg, in.odometry, in.reset));
      n -= clocks;
    }
    sequencer_.skip(n, sequencer_in(cfg, in.odometry, in.reset));
  }
  [[nodiscard]] bool idle(const In& in, const Config& cfg) const {
    const Wires w = wires(in, cfg);
    return sequencer_.idle(w.sequencer) && cordic_.idle(w.cordic) && rear_.idle(w.rear) &&
           front_.idle(w.front) && select_.idle(w.select) && integrator_.idle(w.pose) &&
           report_.idle(w.report);
  }
  void reset_now() {
    sequencer_.reset_now();
    cordic_.reset_now();
    rear_.reset_now();
    front_.reset_now();
    select_.reset_now();
    integrator_.reset_now();
    report_.reset_now();
  }

  // The EPPMs' latch-and-clear wire.
  [[nodiscard]] UInt<1> latch() const { return Logic::latch(sequencer_.regs()); }
  // Every odometry.* status field the register file reads.
  [[nodiscard]] OdometryStatus status() const {
    return Logic::status<OdometryStatus>(sequencer_.regs(), front_.regs(), integrator_.regs(),
                                         report_.regs());
  }

  [[nodiscard]] const OdometrySequencer::Regs& sequencer() const { return sequencer_.regs(); }
  [[nodiscard]] OdometryPhase phase() const { return sequencer_.phase(); }
  [[nodiscard]] const SequentialCordic::Regs& cordic() const { return cordic_.regs(); }
  [[nodiscard]] const RearOdometryUnit::Regs& rear() const { return rear_.regs(); }
  [[nodiscard]] const FrontOdometryUnit::Regs& front() const { return front_.regs(); }
  [[nodiscard]] const MinSelect::Regs& select() const { return select_.regs(); }
  [[nodiscard]] const PoseIntegrator::Regs& pose() const { return integrator_.regs(); }
  [[nodiscard]] const OdometryReport::Regs& report() const { return report_.regs(); }

  template <class V>
  void trace(V& v) const {
    trace_scope(v, "sequencer", sequencer_);
    trace_scope(v, "cordic", cordic_);
    trace_scope(v, "rear", rear_);
    trace_scope(v, "front", front_);
    trace_scope(v, "select", select_);
    trace_scope(v, "pose", integrator_);
    trace_scope(v, "report", report_);
  }

 private:
  // In a CORDIC wait with the CORDIC busy: the micro-rotations left.
  [[nodiscard]] std::uint64_t cordic_wait() const {
    const bool waiting =
        sequencer_.in(OdometryPhase::kPhiWait) || sequencer_.in(OdometryPhase::kThetaWait);
    return waiting ? cordic_.rotations_left() : 0;
  }
  [[nodiscard]] OdometrySequencer::In sequencer_in(const Config& cfg, const OdometryPulses& pulses,
                                                   UInt<1> reset) const {
    return Logic::sequencer_in(cordic_.regs(), cfg, pulses, reset);
  }

  OdometrySequencer sequencer_;
  SequentialCordic cordic_;
  RearOdometryUnit rear_;
  FrontOdometryUnit front_;
  MinSelect select_;
  PoseIntegrator integrator_;
  OdometryReport report_;
};

}  // namespace odoloc::rtl
