// The odometry fabric: four EPPMs and the odometry datapath (odometry.hpp:
// one shared sequential CORDIC, the rear and front computation units,
// min-select, the pose integrator and the report of the last update) on one
// clock.
//
// Ports (odoloc/ports.hpp, generated from regmap/odoloc.yaml): the
// configuration is ports::Config (eppm.* and odometry.* rw registers), the
// one-clock strobes are the eppm.*.status and odometry.status clears and the
// odometry.command pulses, and status() is what the register file reads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

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

  // The wires into both children, from the current registers only.
  struct Wires {
    EncoderFabric::In encoders;
    OdometryDatapath::Wires datapath;
  };
  [[nodiscard]] Wires wires(const In& in, const Config& cfg) const {
    return {.encoders = eppm_inputs(in, datapath_.latch()),
            .datapath = datapath_.wires(datapath_in(in), cfg.odometry)};
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Config& cfg, const Order& order = {}) {
    // Between updates (the common case) only the EPPMs and the period
    // counter move: the CORDIC and every unit are idle.
    if (G == Gating::kOn && datapath_.between_updates(in.odometry, in.reset)) {
      const EncoderFabric::In encoders_in = eppm_inputs(in, UInt<1>{});
      order([&] { encoders_.step<G>(encoders_in, cfg.eppm, order); },
            [&] { datapath_.count_period<G>(cfg.odometry); });
      return;
    }
    step_all<G>(in, cfg, order);
  }
  // Fast-forward (clocked.hpp), until the period end. The EPPMs see the
  // update only in its LATCH clock (a latch-and-clear), and the datapath
  // reads only the latched counts, which nothing else changes: outside LATCH
  // the EPPMs advance on their own, and the rest of an update runs clock by
  // clock in the datapath.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& in, const Config& cfg) const {
    return datapath_.clocks_until_event(datapath_in(in), cfg.odometry);
  }
  void skip(std::uint64_t n, const In& in, const Config& cfg) {
    skip(n, in, cfg, held_runs(in.pins));
  }
  // The same with each encoder's pins following its own runs
  // (EncoderFabric::advance; the EPPMs share no signal, so each steps
  // through its own events alone); returns the pins of the last clock.
  template <class Runs>
  std::array<UInt<2>, kEncoderCount> skip(std::uint64_t n, const In& in, const Config& cfg,
                                          Runs&& runs) {
    const auto last = encoders_.advance(n, eppm_inputs(in, UInt<1>{}), cfg.eppm, runs);
    datapath_.skip(n, datapath_in(in), cfg.odometry);
    return last;
  }
  [[nodiscard]] bool idle(const In& in, const Config& cfg) const {
    const Wires w = wires(in, cfg);
    return encoders_.idle(w.encoders, cfg.eppm) && datapath_.idle(datapath_in(in), cfg.odometry);
  }

  void reset_now() {
    encoders_.reset_now();
    datapath_.reset_now();
  }

  // What the register file reads: every eppm.* and odometry.* status field
  // (the top block's belong to the SPI interface and stay 0 here).
  [[nodiscard]] ports::Status status(const Config& cfg) const {
    ports::Status s;
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      s.eppm[w] = encoders_.eppm(static_cast<Encoder>(w)).status(cfg.eppm[w]);
    s.odometry = datapath_.status();
    return s;
  }

  [[nodiscard]] const EncoderFabric& encoders() const { return encoders_; }
  [[nodiscard]] const OdometryDatapath& datapath() const { return datapath_; }
  [[nodiscard]] const OdometrySequencer::Regs& sequencer() const { return datapath_.sequencer(); }
  [[nodiscard]] OdometryPhase phase() const { return datapath_.phase(); }
  [[nodiscard]] const SequentialCordic::Regs& cordic() const { return datapath_.cordic(); }
  [[nodiscard]] const RearOdometryUnit::Regs& rear() const { return datapath_.rear(); }
  [[nodiscard]] const FrontOdometryUnit::Regs& front() const { return datapath_.front(); }
  [[nodiscard]] const MinSelect::Regs& select() const { return datapath_.select(); }
  [[nodiscard]] const PoseIntegrator::Regs& pose() const { return datapath_.pose(); }
  [[nodiscard]] const OdometryReport::Regs& report() const { return datapath_.report(); }

  // The datapath's registers appear beside the encoders', unscoped.
  template <class V>
  void trace(V& v) const {
    trace_scope(v, "encoders", encoders_);
    datapath_.trace(v);
  }

 private:
  // Both children, from the wires of the current registers. Kept out of
  // line: it runs about 40 clocks per update, and inlined it slows the
  // common path.
  template <Gating G, class Order>
  [[gnu::noinline]] void step_all(const In& in, const Config& cfg, const Order& order) {
    const Wires w = wires(in, cfg);
    order([&] { encoders_.step<G>(w.encoders, cfg.eppm, order); },
          [&] { datapath_.clock<G>(w.datapath, order); });
  }

  // The datapath's inputs: the EPPMs' latched counts and this clock's strobes.
  [[nodiscard]] OdometryDatapath::In datapath_in(const In& in) const {
    const auto latched = [&](Encoder w) { return encoders_.eppm(w).counter().latched; };
    return {.latched = {latched(Encoder::kLeftRear), latched(Encoder::kRightRear),
                        latched(Encoder::kFrontDrive), latched(Encoder::kSteering)},
            .odometry = in.odometry,
            .reset = in.reset};
  }
  // The EPPMs' inputs: pins, latch-and-clear, and each flag's clear (its own
  // strobe or command.clear_flags).
  [[gnu::always_inline]] static EncoderFabric::In eppm_inputs(const In& in, UInt<1> latch) {
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
  OdometryDatapath datapath_;
};

}  // namespace odoloc::rtl
