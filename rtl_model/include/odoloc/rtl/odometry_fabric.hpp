// The odometry fabric: four EPPMs, one shared sequential CORDIC, the rear and
// front computation units, min-select, the pose integrator and the report of
// the last update on one clock.
//
// Ports (odoloc/ports.hpp, generated from regmap/odoloc.yaml): the
// configuration is ports::Config (eppm.* and odometry.* rw registers), the
// one-clock strobes are the eppm.*.status and odometry.status clears and the
// odometry.command pulses, and status() is what the register file reads.
#pragma once

#include <algorithm>
#include <array>
#include <utility>

#include "odoloc/rtl/cordic.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
#include "odoloc/rtl/odometry.hpp"

namespace odoloc::rtl {

struct OdometryFabricInputs {
  std::array<UInt<2>, kEncoderCount> pins{};        // A/B per encoder, A in bit 1
  std::array<EppmFlagClear, kEncoderCount> eppm{};  // eppm.*.status clears
  OdometryPulses odometry;  // odometry.status clears; command.set_pose, command.clear_flags
  UInt<1> reset;
  ODOLOC_FIELDS(pins, eppm, odometry, reset)
};

class OdometryFabric {
 public:
  using In = OdometryFabricInputs;
  using Config = ports::Config;  // its top block is the SPI interface's, not read here

  // The wires into every child but the EPPMs, from the current registers only.
  struct UnitWires {
    OdometrySequencer::In sequencer;
    SequentialCordic::In cordic;
    RearOdometryUnit::In rear;
    FrontOdometryUnit::In front;
    MinSelect::In select;
    PoseIntegrator::In integrator;
    OdometryReport::In report;
  };
  // The wires into every child.
  struct Wires {
    EncoderFabric::In encoders;
    UnitWires units;
  };
  [[nodiscard]] Wires wires(const In& in, const Config& cfg) const {
    return {.encoders = eppm_inputs(in, phase_is(OdometryPhase::kLatch)),
            .units = unit_wires(in, cfg)};
  }
  [[nodiscard]] UnitWires unit_wires(const In& in, const Config& cfg) const {
    const OdometryConfig& oc = cfg.odometry;
    const UInt<1> clear_all = in.odometry.command.clear_flags;
    const UInt<1> phi_load = phase_is(OdometryPhase::kPhiLoad);
    const UInt<1> theta_load = phase_is(OdometryPhase::kThetaLoad);
    const UInt<1> gather = phase_is(OdometryPhase::kGather);
    const UInt<1> integrate = phase_is(OdometryPhase::kThetaWait) & cordic_.regs().ready;
    const auto latched = [&](Encoder w) { return encoders_.eppm(w).counter().latched; };
    const cordic::SinCos sincos = cordic_.regs().result;
    const RearOdometryUnit::Regs& rear = rear_.regs();
    const FrontOdometryUnit::Regs& front = front_.regs();
    const MinSelect::Regs& select = select_.regs();
    return {
        .sequencer = sequencer_in(in, cfg),
        .cordic = {.load = phi_load | theta_load,
                   .angle =
                       phi_load ? front_.cordic_angle() : integrator_.cordic_angle(select.dtheta),
                   .clear_flags = in.odometry.status.overrun | clear_all,
                   .reset = in.reset},
        .rear = {.start = gather,
                 .n_left = latched(Encoder::kLeftRear),
                 .n_right = latched(Encoder::kRightRear),
                 .ds_scale = oc.rear_ds_scale.value,
                 .dtheta_scale = oc.rear_dtheta_scale.value,
                 .reset = in.reset},
        .front = {.start = gather,
                  .finish = phase_is(OdometryPhase::kFront),
                  .n_front = latched(Encoder::kFrontDrive),
                  .n_steer = latched(Encoder::kSteering),
                  .steer_sincos = sincos,
                  .ds_scale = oc.front_ds_scale.value,
                  .dtheta_scale = oc.front_dtheta_scale.value,
                  .steer_scale = oc.steer_scale.value,
                  .steer_limit = oc.steer_limit.value,
                  .clear_clamp = in.odometry.status.steer_clamped | clear_all,
                  .reset = in.reset},
        .select = {.select = phase_is(OdometryPhase::kSelect),
                   .rear = rear,
                   .front_ds = front.ds,
                   .front_dtheta = front.dtheta,
                   .policy = oc.cfg.policy,
                   .shift = oc.cfg.select_shift,
                   .ds_threshold = oc.select_ds_threshold.value,
                   .dtheta_threshold = oc.select_dtheta_threshold.value,
                   .reset = in.reset},
        .integrator = {.integrate = integrate,
                       .ds = select.ds,
                       .dtheta = select.dtheta,
                       .heading_sincos = sincos,
                       .set_pose = in.odometry.command.set_pose,
                       .new_pose = {.x = oc.set_x.bits,
                                    .y = oc.set_y.bits,
                                    .theta = oc.set_theta.bits},
                       .reset = in.reset},
        .report = {.publish = integrate,
                   .rear = rear,
                   .front_ds = front.ds,
                   .front_dtheta = front.dtheta,
                   .steer_phi = front.phi,
                   .steer_position = front.steer_position,
                   .ds = select.ds,
                   .dtheta = select.dtheta,
                   .ds_from_front = select.ds_from_front,
                   .dtheta_from_front = select.dtheta_from_front,
                   .reset = in.reset},
    };
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Config& cfg, const Order& order = {}) {
    // Between updates (the common case) only the EPPMs and the period
    // counter move: the CORDIC and every unit are idle.
    if (G == Gating::kOn && between_updates(in)) {
      const EncoderFabric::In encoders_in = eppm_inputs(in, UInt<1>{});
      const OdometrySequencer::In sequencer_in_ = sequencer_in(in, cfg);
      order([&] { encoders_.step<G>(encoders_in, cfg.eppm, order); },
            [&] { clock_block<G>(sequencer_, sequencer_in_); });
      return;
    }
    step_all<G>(in, cfg, order);
  }
  // Fast-forward (clocked.hpp), until the period end. The EPPMs see the
  // update only in its LATCH clock (a latch-and-clear), and the units read
  // only the latched counts, which nothing else changes: outside LATCH the
  // EPPMs advance on their own, and the rest of an update runs clock by
  // clock in its own units.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& in, const Config& cfg) const {
    if (!in.reset.is_zero() || any_set(in.odometry) || sequencer_.in(OdometryPhase::kLatch))
      return 0;
    return sequencer_.clocks_to_period_end(cfg.odometry.cfg.update_clocks);
  }
  void skip(std::uint64_t n, const In& in, const Config& cfg) {
    skip(n, in, cfg, [&in](std::size_t w, std::uint64_t clocks) {
      return PinRun{in.pins[w], clocks};
    });
  }
  // The same with each encoder's pins following its own runs
  // (EncoderFabric::advance; the EPPMs share no signal, so each steps
  // through its own events alone); returns the pins of the last clock.
  template <class Runs>
  std::array<UInt<2>, kEncoderCount> skip(std::uint64_t n, const In& in, const Config& cfg,
                                          Runs&& runs) {
    const auto last = encoders_.advance(n, eppm_inputs(in, UInt<1>{}), cfg.eppm, runs);
    skip_units(n, in, cfg);
    return last;
  }
  [[nodiscard]] bool idle(const In& in, const Config& cfg) const {
    const Wires w = wires(in, cfg);
    const UnitWires& u = w.units;
    return encoders_.idle(w.encoders, cfg.eppm) && sequencer_.idle(u.sequencer) &&
           cordic_.idle(u.cordic) && rear_.idle(u.rear) && front_.idle(u.front) &&
           select_.idle(u.select) && integrator_.idle(u.integrator) && report_.idle(u.report);
  }

  void reset_now() {
    encoders_.reset_now();
    sequencer_.reset_now();
    cordic_.reset_now();
    rear_.reset_now();
    front_.reset_now();
    select_.reset_now();
    integrator_.reset_now();
    report_.reset_now();
  }

  // What the register file reads: every eppm.* and odometry.* status field
  // (the top block's belong to the SPI interface and stay 0 here).
  [[nodiscard]] ports::Status status(const Config& cfg) const {
    ports::Status s;
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      s.eppm[w] = encoders_.eppm(static_cast<Encoder>(w)).status(cfg.eppm[w]);
    const OdometryReport::Regs& r = report_.regs();
    OdometryStatus& o = s.odometry;
    o.status.overrun = sequencer_.regs().overrun;
    o.status.steer_clamped = front_.regs().clamp_flag;
    o.status.ds_from_front = r.ds_from_front;
    o.status.dtheta_from_front = r.dtheta_from_front;
    o.status.phase = sequencer_.regs().phase;
    o.updates.count = sequencer_.regs().updates;
    o.pose_x.bits = integrator_.regs().x;
    o.pose_y.bits = integrator_.regs().y;
    o.pose_theta.bits = integrator_.regs().theta;
    o.rear_ds.bits = r.rear_ds;
    o.rear_dtheta.bits = r.rear_dtheta;
    o.front_ds.bits = r.front_ds;
    o.front_dtheta.bits = r.front_dtheta;
    o.ds.bits = r.ds;
    o.dtheta.bits = r.dtheta;
    o.steer_phi.bits = r.steer_phi;
    o.steer_position.counts = r.steer_position;
    return s;
  }

  [[nodiscard]] const EncoderFabric& encoders() const { return encoders_; }
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
    trace_scope(v, "encoders", encoders_);
    trace_scope(v, "sequencer", sequencer_);
    trace_scope(v, "cordic", cordic_);
    trace_scope(v, "rear", rear_);
    trace_scope(v, "front", front_);
    trace_scope(v, "select", select_);
    trace_scope(v, "pose", integrator_);
    trace_scope(v, "report", report_);
  }

 private:
  // Every child, from the wires of the current registers. Kept out of line:
  // it runs about 40 clocks per update, and inlined it slows the common path.
  template <Gating G, class Order>
  [[gnu::noinline]] void step_all(const In& in, const Config& cfg, const Order& order) {
    const Wires w = wires(in, cfg);
    clock_units<G>(w.units, order, [&] { encoders_.step<G>(w.encoders, cfg.eppm, order); });
  }
  // Every child but the EPPMs, plus `more` children, in `order`.
  template <Gating G, class Order, class... More>
  void clock_units(const UnitWires& w, const Order& order, More&&... more) {
    order(
        std::forward<More>(more)..., [&] { clock_block<G>(sequencer_, w.sequencer); },
        [&] { clock_block<G>(cordic_, w.cordic); }, [&] { clock_block<G>(rear_, w.rear); },
        [&] { clock_block<G>(front_, w.front); }, [&] { clock_block<G>(select_, w.select); },
        [&] { clock_block<G>(integrator_, w.integrator); },
        [&] { clock_block<G>(report_, w.report); });
  }

  // The clocks of skip() outside the EPPMs: an update in progress runs in
  // the units clock by clock, the CORDIC waits as bare micro-rotations, and
  // the period counter counts.
  void skip_units(std::uint64_t n, const In& in, const Config& cfg) {
    while (n != 0 && !sequencer_.in(OdometryPhase::kIdle)) {
      const std::uint64_t iterations = cordic_wait();
      if (iterations == 0) {
        // The EPPMs' inputs are not needed: they advance on their own.
        clock_units<Gating::kOn>(unit_wires(in, cfg), DeclarationOrder{});
        --n;
        continue;
      }
      // Only the CORDIC iterates and the period counter counts: every unit
      // waits for RESULT_READY.
      const std::uint64_t clocks = std::min(n, iterations);
      cordic_.skip(clocks);
      sequencer_.skip(clocks, sequencer_in(in, cfg));
      n -= clocks;
    }
    sequencer_.skip(n, sequencer_in(in, cfg));
  }
  // In a CORDIC wait with the CORDIC busy: the micro-rotations left.
  [[nodiscard]] std::uint64_t cordic_wait() const {
    const bool waiting =
        sequencer_.in(OdometryPhase::kPhiWait) || sequencer_.in(OdometryPhase::kThetaWait);
    return waiting ? cordic_.rotations_left() : 0;
  }
  // Idle phase, no reset and no odometry strobe: the CORDIC and every unit
  // are idle, the EPPMs see no latch.
  [[nodiscard]] bool between_updates(const In& in) const {
    return sequencer_.in(OdometryPhase::kIdle) && in.reset.is_zero() && !any_set(in.odometry);
  }
  [[nodiscard]] UInt<1> phase_is(OdometryPhase p) const {
    return UInt<1>::truncate(sequencer_.in(p));
  }
  [[nodiscard]] OdometrySequencer::In sequencer_in(const In& in, const Config& cfg) const {
    return {.update_clocks = cfg.odometry.cfg.update_clocks,
            .cordic_ready = cordic_.regs().ready,
            .clear_overrun = in.odometry.status.overrun | in.odometry.command.clear_flags,
            .reset = in.reset};
  }
  // The EPPMs' inputs: pins, latch-and-clear, and each flag's clear (its own
  // strobe or command.clear_flags).
  static EncoderFabric::In eppm_inputs(const In& in, UInt<1> latch) {
    const UInt<1> clear_all = in.odometry.command.clear_flags;
    EncoderFabric::In e;
    for (std::size_t w = 0; w < kEncoderCount; ++w) {
      const auto& c = in.eppm[w].status;
      e[w] = {.a = in.pins[w].bit<1>(),
              .b = in.pins[w].bit<0>(),
              .latch_clear = latch,
              .clear = {.status = {.phase_error = c.phase_error | clear_all,
                                   .carry = c.carry | clear_all,
                                   .borrow = c.borrow | clear_all,
                                   .period_overflow = c.period_overflow | clear_all}},
              .reset = in.reset};
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
  OdometryReport report_;
};

}  // namespace odoloc::rtl
