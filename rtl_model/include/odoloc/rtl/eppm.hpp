// Encoder Pulse Processing Module (EPPM): one per wheel encoder.
//
//   pins A,B -> InputConditioner -> QuadratureDecoder --step--> PositionCounter
//               (2-flop sync,       (x4/x2/x1, phase        +-> PulseMeter  (window count, mode)
//                glitch filter)      error counting)        +-> PeriodMeter (ticks per edge, stall)
//                                        SpeedTimebase (window timer, reference prescaler)
//
// Paper: Kurian & Pillai, section 2 (Fig. 1). Formats, latencies and every
// register are documented in docs/eppm.md and asserted by testbenches/rtl/.
// The logic: logic/eppm.hpp (the one source, also the HLS kernel's). Here:
// what only a simulator needs around it (field lists, the waveform's ports,
// the quiet fast path and activity gating, the fast-forward).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "odoloc/logic/eppm.hpp"
#include "odoloc/ports.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/eppm_constants.hpp"
#include "odoloc/rtl/family.hpp"
#include "odoloc/rtl/input_conditioner.hpp"

namespace odoloc::rtl {

// ---- ports (generated from regmap/odoloc.yaml: odoloc/ports.hpp) -------------
// Configuration (the eppm.* rw registers, resets from the YAML), the sticky
// flags' clear strobes (eppm.*.status, w1c) and the status the register file
// reads. The enums are the register map's.
using DecodeMode = regs::eppm::cfg::DecodeMode;            // 3 behaves as x4
using SpeedModeSelect = regs::eppm::cfg::SpeedModeSelect;  // 3: auto
using SpeedMode = regs::eppm::speed::Mode;
using EppmConfig = ports::eppm::Config;
using EppmFlagClear = ports::eppm::Pulses;  // status.<flag>: clear it this clock; an event wins
using EppmStatus = ports::eppm::Status;

struct EppmInputs {
  UInt<1> a, b;         // encoder pins, asynchronous to the fabric clock
  UInt<1> latch_clear;  // read increment: latch the count and restart it from 0
  EppmFlagClear clear;  // sticky flags to clear
  UInt<1> reset;        // synchronous reset of every register
  ODOLOC_FIELDS(a, b, latch_clear, clear, reset)
};

// ---- the leaves (logic/eppm.hpp) ------------------------------------------------
// A/B travel packed as a 2-bit value, A in bit 1 (input_conditioner.hpp).
using QuadratureConditioner = InputConditioner<eppm::kLines>;

ODOLOC_LOGIC_FIELDS(logic::eppm::DecoderRegs, prev, direction, phase_error, error_count)
ODOLOC_LOGIC_FIELDS(logic::eppm::CounterRegs, count, latched, carry, borrow)
ODOLOC_LOGIC_FIELDS(logic::eppm::TimebaseRegs, window_count, prescale_count)
ODOLOC_LOGIC_FIELDS(logic::eppm::PulseRegs, acc, last, mode, sampled)
ODOLOC_LOGIC_FIELDS(logic::eppm::PeriodRegs, count, last, valid, armed, last_dir, overflow, sampled)
using QuadratureDecoderRegs = logic::eppm::DecoderRegs<Family>;
using PositionCounterRegs = logic::eppm::CounterRegs<Family>;
using SpeedTimebaseRegs = logic::eppm::TimebaseRegs<Family>;
using PulseMeterRegs = logic::eppm::PulseRegs<Family>;
using PeriodMeterRegs = logic::eppm::PeriodRegs<Family>;
using PositionCount = logic::eppm::Count<Family>;
using PeriodTicks = logic::eppm::Ticks<Family>;

class QuadratureDecoder : public Registers<QuadratureDecoderRegs> {
  using Logic = logic::eppm::QuadratureDecoder<Family>;

 public:
  using In = logic::eppm::DecoderIn<Family>;
  // The count pulse of this clock: -1, 0 or +1 after x4/x2/x1 gating.
  [[nodiscard]] SInt<2> step(UInt<2> filtered, UInt<2> decode_mode) const {
    return Logic::step(r_, filtered, decode_mode);
  }
  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  [[nodiscard]] bool idle(const In& in) const {
    return in.filtered == r_.prev && (in.clear_phase_error | in.reset).is_zero();
  }
};

class PositionCounter : public Registers<PositionCounterRegs> {
 public:
  using Count = PositionCount;
  static constexpr int kWidth = Count::width;
  using In = logic::eppm::CounterIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::eppm::PositionCounter<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.step.is_zero() &&
           (in.latch_clear | in.clear_carry | in.clear_borrow | in.reset).is_zero();
  }
};

class SpeedTimebase : public Registers<SpeedTimebaseRegs> {
  using Logic = logic::eppm::SpeedTimebase<Family>;

 public:
  using In = logic::eppm::TimebaseIn<Family>;
  [[nodiscard]] bool window_end(UInt<23> window_clocks) const {
    return Logic::window_end(r_, window_clocks);
  }
  [[nodiscard]] bool tick(UInt<16> prescale) const { return Logic::tick(r_, prescale); }
  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  [[nodiscard]] bool idle(const In&) const { return false; }  // counts every clock

  // Fast-forward (clocked.hpp). Both counters restart after their terminal
  // clock: the window's is window_end (window_count + 1 >= window_clocks, so
  // 0 behaves as 1), the prescaler's is tick.
  [[nodiscard]] std::uint64_t clocks_to_window_end(UInt<23> window_clocks) const {
    return clocks_to_fire(r_.window_count.value(), window_last(window_clocks));
  }
  // n clocks in which no window ends; returns the reference ticks among them.
  std::uint64_t skip(std::uint64_t n, const In& in) {
    const RestartingCount window =
        run_restarting(r_.window_count.value(), window_last(in.window_clocks), n);
    const RestartingCount prescale =
        run_restarting(r_.prescale_count.value(), in.prescale.value(), n);
    commit({UInt<23>::truncate(window.count), UInt<16>::truncate(prescale.count)});
    return prescale.fires;
  }

 private:
  static std::uint64_t window_last(UInt<23> window_clocks) {
    return window_clocks.is_zero() ? 0 : window_clocks.value() - 1;
  }
};

class PulseMeter : public Registers<PulseMeterRegs> {
 public:
  using In = logic::eppm::PulseIn<Family>;
  [[nodiscard]] Regs eval(const In& in) const {
    return logic::eppm::PulseMeter<Family>::next(r_, in);
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.step.is_zero() && !in.window_end && (r_.sampled | in.reset).is_zero();
  }
};

class PeriodMeter : public Registers<PeriodMeterRegs> {
  using Logic = logic::eppm::PeriodMeter<Family>;

 public:
  using Ticks = PeriodTicks;
  static constexpr int kWidth = Ticks::width;
  using In = logic::eppm::PeriodIn<Family>;
  [[nodiscard]] bool stalled(UInt<23> stall_ticks) const { return Logic::stalled(r_, stall_ticks); }
  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  [[nodiscard]] bool idle(const In& in) const {
    return in.step.is_zero() && !in.tick && (r_.sampled | in.clear_overflow | in.reset).is_zero();
  }

  // Fast-forward: clocks >= 1 with no edge or control, `ticks` reference
  // ticks among them. The last edge's strobe, if set, clears in the first.
  // Per tick the count saturates and a tick at the maximum sets overflow, so
  // overflow is set iff count + ticks exceeds the maximum.
  // Only those registers are written: a copy of the whole 13-byte next
  // state, assembled from narrow stores, stalled on store forwarding.
  void skip_ticks(std::uint64_t ticks) {
    const std::uint64_t total = r_.count.value() + ticks;
    if (total > Ticks::max_value)
      r_.overflow = UInt<1>{1};
    r_.count = Ticks::truncate(std::min<std::uint64_t>(total, Ticks::max_value));
    r_.sampled = UInt<1>{};
  }
};

// ---- the module ---------------------------------------------------------------
class Eppm {
  using Logic = logic::eppm::Eppm<Family>;

 public:
  using In = EppmInputs;
  using Config = EppmConfig;

  using Wires = logic::eppm::Wires<Family>;
  // The wires that cross the children, from the current registers only.
  [[nodiscard]] Wires wires(const Config& cfg) const {
    return Logic::wires(conditioner_.regs(), decoder_.regs(), timebase_.regs(), cfg);
  }
  // Each child's inputs (logic/eppm.hpp): the wires, this module's inputs and
  // configuration.
  static UInt<2> pins(const In& in, const Config& cfg) { return Logic::pins(in, cfg); }
  static QuadratureConditioner::In conditioner_in(const In& in, const Config& cfg) {
    return Logic::conditioner_in(in, cfg);
  }
  static QuadratureDecoder::In decoder_in(const Wires& w, const In& in) {
    return Logic::decoder_in(w, in);
  }
  static PositionCounter::In counter_in(const Wires& w, const In& in) {
    return Logic::counter_in(w, in);
  }
  static SpeedTimebase::In timebase_in(const In& in, const Config& cfg) {
    return Logic::timebase_in(in, cfg);
  }
  static PulseMeter::In pulse_in(const Wires& w, const In& in, const Config& cfg) {
    return Logic::pulse_in(w, in, cfg);
  }
  static PeriodMeter::In period_in(const Wires& w, const In& in, const Config& cfg) {
    return Logic::period_in(w, in, cfg);
  }

  // The quiet clock inline, the full clock out of line (step_all_out_of_line).
  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Config& cfg, const Order& order = {}) {
    if (!step_quiet<G>(in, cfg, order))
      step_all_out_of_line<G>(in, cfg, order);
  }
  // Fast-forward (clocked.hpp): while quiet, only the timebase and the
  // period meter's count move, until the window ends. A pin change reaching
  // a settled EPPM is skipped too, up to the clock before the decoder sees it
  // (InputConditioner::held_from_settled): until then the conditioner alone
  // differs from a quiet clock. Unless the window ends in those clocks: then
  // every clock is stepped.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& in, const Config& cfg) const {
    // Mid-edge or a control, the common answer inside an edge, first.
    if (!calm(in))
      return 0;
    const std::uint64_t window = timebase_.clocks_to_window_end(cfg.window.clocks);
    if (quiet(in, cfg))
      return window;
    const std::uint64_t take = QuadratureConditioner::clocks_to_take(cfg.cfg.filter_clocks);
    return window >= take ? take : 0;  // taking
  }
  void skip(std::uint64_t n, const In& in, const Config& cfg) {
    if (taking(in, cfg)) {
      conditioner_.commit(conditioner_.held_from_settled(pins(in, cfg), cfg.cfg.filter_clocks, n));
      ports_ = in;
      settled_ = false;
    }
    period_.skip_ticks(timebase_.skip(n, timebase_in(in, cfg)));
  }
  // n clocks with `in` held: stepped through its events, skipped between.
  void advance(std::uint64_t n, const In& in, const Config& cfg) {
    fast_forward(*this, n, in, cfg);
  }

  [[nodiscard]] bool idle(const In& in, const Config& cfg) const {
    const Wires w = wires(cfg);
    return conditioner_.idle(conditioner_in(in, cfg)) && decoder_.idle(decoder_in(w, in)) &&
           counter_.idle(counter_in(w, in)) && timebase_.idle(timebase_in(in, cfg)) &&
           pulse_.idle(pulse_in(w, in, cfg)) && period_.idle(period_in(w, in, cfg));
  }
  void reset_now() {
    ports_ = {};
    settled_ = false;
    conditioner_.reset_now();
    decoder_.reset_now();
    counter_.reset_now();
    timebase_.reset_now();
    pulse_.reset_now();
    period_.reset_now();
  }

  // What the register file reads (eppm.* status registers; logic/eppm.hpp).
  [[nodiscard]] EppmStatus status(const Config& cfg) const {
    return Logic::status<EppmStatus>(decoder_.regs(), counter_.regs(), pulse_.regs(),
                                     period_.regs(), cfg);
  }

  [[nodiscard]] const QuadratureConditioner::Regs& conditioner() const {
    return conditioner_.regs();
  }
  [[nodiscard]] const QuadratureDecoder::Regs& decoder() const { return decoder_.regs(); }
  [[nodiscard]] const PositionCounter::Regs& counter() const { return counter_.regs(); }
  [[nodiscard]] const SpeedTimebase::Regs& timebase() const { return timebase_.regs(); }
  [[nodiscard]] const PulseMeter::Regs& pulse() const { return pulse_.regs(); }
  [[nodiscard]] const PeriodMeter::Regs& period() const { return period_.regs(); }
  [[nodiscard]] PositionCounter::Count count() const { return counter_.regs().count; }

  template <class V>
  void trace(V& v) const {
    trace_fields(v, ports_);
    trace_scope(v, "conditioner", conditioner_);
    trace_scope(v, "decoder", decoder_);
    trace_scope(v, "counter", counter_);
    trace_scope(v, "timebase", timebase_);
    trace_scope(v, "pulse", pulse_);
    trace_scope(v, "period", period_);
  }

 private:
  // Fast path: a quiet EPPM makes no step, so only the timebase moves, plus
  // the period meter on a tick or with its strobe set. Window ends take the full path: they set a
  // strobe that unsettles. (Each block's own eval, never a skip rule: the
  // cycle step is the reference fast-forward is checked against.) Returns
  // whether the clock was quiet (and done).
  template <Gating G, class Order>
  bool step_quiet(const In& in, const Config& cfg, const Order& order) {
    if (G == Gating::kOff || !quiet(in, cfg) || timebase_.window_end(cfg.window.clocks))
      return false;
    const Wires settled{.filtered = conditioner_.regs().filtered,
                        .step = SInt<2>{},
                        .window_end = false,
                        .tick = timebase_.tick(cfg.prescale.divider)};
    order([&] { clock_block<G>(timebase_, timebase_in(in, cfg)); },
          [&] { clock_block<G>(period_, period_in(settled, in, cfg)); });
    return true;
  }
  // Every child, from wires computed before any of them is clocked.
  template <Gating G, class Order>
  [[gnu::noinline, gnu::flatten]] void step_all_out_of_line(const In& in, const Config& cfg,
                                                            const Order& order) {
    step_all<G>(in, cfg, order);
  }
  template <Gating G, class Order>
  void step_all(const In& in, const Config& cfg, const Order& order) {
    const Wires w = wires(cfg);
    ports_ = in;
    order([&] { clock_block<G>(conditioner_, conditioner_in(in, cfg)); },
          [&] { clock_block<G>(decoder_, decoder_in(w, in)); },
          [&] { clock_block<G>(counter_, counter_in(w, in)); },
          [&] { clock_block<G>(timebase_, timebase_in(in, cfg)); },
          [&] { clock_block<G>(pulse_, pulse_in(w, in, cfg)); },
          [&] { clock_block<G>(period_, period_in(w, in, cfg)); });
    // Only the gated step reads the bookkeeping; ungated, the next gated
    // clock takes the full path and sets it.
    settled_ = G == Gating::kOn && settled();
  }

  // Settled after the last full clock, the pins unchanged and no control: the
  // decoder's prev equals the filtered level, so no step is made.
  [[nodiscard]] bool quiet(const In& in, const Config& cfg) const {
    return calm(in) && pins(in, cfg) == conditioner_.regs().filtered;
  }
  // Calm with new pins: the conditioner is about to take them.
  [[nodiscard]] bool taking(const In& in, const Config& cfg) const {
    return calm(in) && pins(in, cfg) != conditioner_.regs().filtered;
  }
  // Settled after the last clock, and no control in this one.
  [[nodiscard]] bool calm(const In& in) const {
    return settled_ && (in.latch_clear | in.reset).is_zero() && !any_set(in.clear);
  }
  // Every stage holds the same A/B with no filter count, the pulse meter's
  // strobe is clear and the last clock carried no control: nothing but the
  // timebase and the period meter can move until the pins change, a control
  // arrives, a window ends or a tick comes. The period meter's strobe may be
  // set (the clock after an edge): the quiet clock clocks that meter by its
  // own eval and a skip clears it (PeriodMeter::skip_ticks), so an edge
  // costs one full clock, not two.
  [[nodiscard]] bool settled() const {
    return conditioner_.settled() && conditioner_.regs().filtered == decoder_.regs().prev &&
           (pulse_.regs().sampled | ports_.latch_clear | ports_.reset).is_zero() &&
           !any_set(ports_.clear);
  }

  EppmInputs ports_;      // the inputs of the last clock, for waveforms
  bool settled_ = false;  // simulator bookkeeping, not a register: settled() after the last clock
  QuadratureConditioner conditioner_;
  QuadratureDecoder decoder_;
  PositionCounter counter_;
  SpeedTimebase timebase_;
  PulseMeter pulse_;
  PeriodMeter period_;
};

// The constants the HLS kernel shares (eppm_constants.hpp) are the model's
// register widths and the register map's encodings.
static_assert(decltype(QuadratureConditioner::Regs{}.sync1)::width == eppm::kLines &&
              decltype(EppmConfig{}.cfg.filter_clocks)::width == eppm::kFilterBits &&
              logic::conditioner::kFilterBits == eppm::kFilterBits &&
              decltype(QuadratureDecoderRegs{}.error_count)::width == eppm::kErrorCountBits &&
              PositionCount::width == eppm::kCountBits &&
              decltype(EppmConfig{}.window.clocks)::width == eppm::kWindowBits &&
              decltype(SpeedTimebaseRegs{}.window_count)::width == eppm::kWindowBits &&
              decltype(EppmConfig{}.prescale.divider)::width == eppm::kPrescaleBits &&
              decltype(SpeedTimebaseRegs{}.prescale_count)::width == eppm::kPrescaleBits &&
              decltype(PulseMeterRegs{}.acc)::width == eppm::kPulseBits &&
              decltype(EppmStatus{}.speed.value)::width == eppm::kPulseBits &&
              PeriodTicks::width == eppm::kPeriodBits &&
              decltype(EppmConfig{}.stall_ticks.ticks)::width == eppm::kPeriodBits &&
              decltype(EppmConfig{}.to_period_below.edges)::width == eppm::kPeriodBits &&
              decltype(EppmConfig{}.to_pulse_at.edges)::width == eppm::kPeriodBits &&
              decltype(EppmConfig{}.cfg.decode_mode)::width == eppm::kModeBits &&
              decltype(EppmConfig{}.cfg.speed_mode_select)::width == eppm::kModeBits);
static_assert(eppm::kDecodeX4 == encoding(DecodeMode::kX4) &&
              eppm::kDecodeX2 == encoding(DecodeMode::kX2) &&
              eppm::kDecodeX1 == encoding(DecodeMode::kX1) &&
              eppm::kSelectPulse == encoding(SpeedModeSelect::kPulse) &&
              eppm::kSelectPeriod == encoding(SpeedModeSelect::kPeriod) &&
              eppm::kModePeriod == encoding(SpeedMode::kPeriod) &&
              eppm::kModePulse == encoding(SpeedMode::kPulse));

}  // namespace odoloc::rtl
