// The odometry fabric: four EPPMs, one shared sequential CORDIC, the rear and
// front computation units, min-select and the pose integrator on one clock.
#pragma once

#include <array>

#include "odoloc/rtl/cordic.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
#include "odoloc/rtl/odometry.hpp"

namespace odoloc::rtl {

// One clear strobe per sticky odometry flag (register odometry.status, w1c).
struct OdometryFlagClear {
  UInt<1> overrun;        // the sequencer's, and the CORDIC's load_ignored
  UInt<1> steer_clamped;  // the front unit's clamp flag
  static constexpr OdometryFlagClear all(UInt<1> clear) { return {clear, clear}; }
  [[nodiscard]] constexpr UInt<1> any() const { return overrun | steer_clamped; }
  bool operator==(const OdometryFlagClear&) const = default;
};

struct OdometryFabricConfig {
  EncoderFabric::Configs eppm{};
  OdometryConfig odometry{};
};

class OdometryFabric {
 public:
  struct Inputs {
    std::array<UInt<2>, kWheelCount> pins{};  // A/B per encoder, A in bit 1
    UInt<1> set_pose;                         // load `pose` into the integrator
    PoseIntegrator::Regs pose;
    std::array<EppmFlagClear, kWheelCount> eppm_clear{};
    OdometryFlagClear odometry_clear;
    UInt<1> reset;
    // Every sticky flag of the fabric (odometry.command.clear_flags).
    void clear_all(UInt<1> clear) {
      eppm_clear.fill(EppmFlagClear::all(clear));
      odometry_clear = OdometryFlagClear::all(clear);
    }
  };

  template <Gating G = Gating::kOn>
  [[gnu::flatten]] void step(const Inputs& in, const OdometryFabricConfig& cfg) {
    const OdometryConfig& oc = cfg.odometry;
    const OdometrySequencer::In sequencer_in{oc.update_clocks, cordic_.regs().ready,
                                             in.odometry_clear.overrun, in.reset};
    // Between updates (the common case) only the EPPMs and the period
    // counter move: the CORDIC and every unit are idle.
    if (G == Gating::kOn && sequencer_.in(OdometryPhase::kIdle) &&
        (in.set_pose | in.odometry_clear.any() | in.reset).is_zero()) {
      encoders_.step<G>(eppm_inputs(in, UInt<1>{}), cfg.eppm);
      sequencer_.commit(sequencer_.eval(sequencer_in));
      return;
    }
    // Wires from the current registers.
    const UInt<1> phi_load = bit(sequencer_.in(OdometryPhase::kPhiLoad));
    const UInt<1> theta_load = bit(sequencer_.in(OdometryPhase::kThetaLoad));
    const UInt<1> gather = bit(sequencer_.in(OdometryPhase::kGather));
    const auto latched = [&](Wheel w) { return encoders_.eppm(w).counter().latched; };
    const cordic::SinCos sincos = cordic_.regs().result;
    const cordic::Angle cordic_angle =
        phi_load ? front_.cordic_angle() : integrator_.cordic_angle(select_.regs().dtheta);

    encoders_.step<G>(eppm_inputs(in, bit(sequencer_.in(OdometryPhase::kLatch))), cfg.eppm);
    clock_block<G>(sequencer_, sequencer_in);
    clock_block<G>(cordic_,
                   {phi_load | theta_load, cordic_angle, in.odometry_clear.overrun, in.reset});
    clock_block<G>(rear_, {gather, latched(Wheel::kLeftRear), latched(Wheel::kRightRear),
                           oc.rear_ds_scale, oc.rear_dtheta_scale, in.reset});
    clock_block<G>(front_,
                   {gather, bit(sequencer_.in(OdometryPhase::kFront)), latched(Wheel::kFrontDrive),
                    latched(Wheel::kSteering), sincos, oc.front_ds_scale, oc.front_dtheta_scale,
                    oc.steer_scale, oc.steer_limit, in.odometry_clear.steer_clamped, in.reset});
    clock_block<G>(select_, {bit(sequencer_.in(OdometryPhase::kSelect)), rear_.regs(),
                             front_.regs().ds, front_.regs().dtheta, oc.policy, oc.select_shift,
                             oc.select_ds_threshold, oc.select_dtheta_threshold, in.reset});
    clock_block<G>(integrator_, {bit(sequencer_.in(OdometryPhase::kIntegrate)), select_.regs().ds,
                                 select_.regs().dtheta, sincos, in.set_pose, in.pose, in.reset});
  }

  void reset_now() {
    encoders_.reset_now();
    sequencer_.reset_now();
    cordic_.reset_now();
    rear_.reset_now();
    front_.reset_now();
    select_.reset_now();
    integrator_.reset_now();
  }

  [[nodiscard]] const EncoderFabric& encoders() const { return encoders_; }
  [[nodiscard]] const OdometrySequencer::Regs& sequencer() const { return sequencer_.regs(); }
  [[nodiscard]] OdometryPhase phase() const { return sequencer_.phase(); }
  [[nodiscard]] const SequentialCordic::Regs& cordic() const { return cordic_.regs(); }
  [[nodiscard]] const RearOdometryUnit::Regs& rear() const { return rear_.regs(); }
  [[nodiscard]] const FrontOdometryUnit::Regs& front() const { return front_.regs(); }
  [[nodiscard]] const MinSelect::Regs& select() const { return select_.regs(); }
  [[nodiscard]] const PoseIntegrator::Regs& pose() const { return integrator_.regs(); }

  template <class V>
  void trace(V& v) const {
    trace_scope(v, "encoders", encoders_);
    trace_scope(v, "sequencer", sequencer_);
    trace_scope(v, "cordic", cordic_);
    trace_scope(v, "rear", rear_);
    trace_scope(v, "front", front_);
    trace_scope(v, "select", select_);
    trace_scope(v, "pose", integrator_);
  }

 private:
  static UInt<1> bit(bool b) { return UInt<1>::truncate(b); }
  static EncoderFabric::Inputs eppm_inputs(const Inputs& in, UInt<1> latch) {
    EncoderFabric::Inputs e;
    for (std::size_t w = 0; w < kWheelCount; ++w) {
      e[w] = {in.pins[w].bit<1>(), in.pins[w].bit<0>(), latch, in.eppm_clear[w], in.reset};
    }
    return e;
  }
  EncoderFabric encoders_;
  OdometrySequencer sequencer_;
  SequentialCordic cordic_;
  RearOdometryUnit rear_;
  FrontOdometryUnit front_;
  MinSelect select_;
  PoseIntegrator integrator_;
};

}  // namespace odoloc::rtl
