// Encoder Pulse Processing Module (EPPM): one per wheel encoder.
//
//   pins A,B -> InputConditioner -> QuadratureDecoder --step--> PositionCounter
//               (2-flop sync,       (x4/x2/x1, phase        +-> PulseMeter  (window count, mode)
//                glitch filter)      error counting)        +-> PeriodMeter (ticks per edge, stall)
//                                        SpeedTimebase (window timer, reference prescaler)
//
// Paper: Kurian & Pillai, section 2 (Fig. 1). Formats, latencies and every
// register are documented in docs/eppm.md and asserted by testbenches/rtl/.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "odoloc/ports.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/eppm_constants.hpp"
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

// ---- input conditioning -------------------------------------------------------
// A/B travel packed as a 2-bit value, A in bit 1 (input_conditioner.hpp).
using QuadratureConditioner = InputConditioner<2>;

// ---- quadrature decoder -----------------------------------------------------
// One entry per (previous, current) A/B pair, index prev*4 + curr, generated
// from the Gray code rather than typed in. count[decode_mode]: x4, x2, x1, x4.
struct QuadTransition {
  std::array<std::int8_t, 4> count;
  bool illegal;
};
constexpr std::array<QuadTransition, 16> make_quadrature_table() {
  // Forward (A leads B): AB = 00 -> 10 -> 11 -> 01 -> 00, with A in bit 1.
  constexpr std::array<int, 4> phase_of_ab = {0, 3, 1, 2};
  std::array<QuadTransition, 16> table{};
  for (std::size_t prev = 0; prev < 4; ++prev) {
    for (std::size_t curr = 0; curr < 4; ++curr) {
      const int delta = (phase_of_ab[curr] - phase_of_ab[prev] + 4) % 4;
      const int dir = delta == 1 ? 1 : delta == 3 ? -1 : 0;
      const bool a_changed = ((prev ^ curr) & 2U) != 0;
      // x1 counts only the edge between phases 0 and 1 (A toggling while B is
      // low), in both directions, so back-and-forth over it nets to zero.
      const bool x1_edge = a_changed && (prev & 1U) == 0 && (curr & 1U) == 0;
      const auto x4 = static_cast<std::int8_t>(dir);
      const auto x2 = static_cast<std::int8_t>(a_changed ? dir : 0);
      const auto x1 = static_cast<std::int8_t>(x1_edge ? dir : 0);
      table[prev * 4 + curr] = {{x4, x2, x1, x4}, delta == 2};
    }
  }
  return table;
}

struct QuadratureDecoderRegs {
  UInt<2> prev;          // filtered A/B one clock earlier
  UInt<1> direction;     // direction of the last legal step: 1 forward (A leads B)
  UInt<1> phase_error;   // sticky: A and B changed in the same sample
  UInt<16> error_count;  // illegal transitions, saturating
  bool operator==(const QuadratureDecoderRegs&) const = default;
  ODOLOC_FIELDS(prev, direction, phase_error, error_count)
};

class QuadratureDecoder : public Registers<QuadratureDecoderRegs> {
 public:
  static constexpr std::array<QuadTransition, 16> kTable = make_quadrature_table();
  struct In {
    UInt<2> filtered;
    UInt<1> clear_phase_error;
    UInt<1> reset;
  };

  // The count pulse of this clock: -1, 0 or +1 after x4/x2/x1 gating.
  [[nodiscard]] SInt<2> step(UInt<2> filtered, UInt<2> decode_mode) const {
    return SInt<2>::truncate(transition(filtered).count[decode_mode.value()]);
  }

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    const QuadTransition t = transition(in.filtered);
    Regs n = r_;
    n.prev = in.filtered;
    if (t.count[0] != 0)
      n.direction = UInt<1>::truncate(t.count[0] > 0);
    if (in.clear_phase_error) {
      n.phase_error = UInt<1>{};
      n.error_count = UInt<16>{};
    }
    if (t.illegal) {
      n.phase_error = UInt<1>{1};
      n.error_count = (n.error_count + UInt<1>{1}).sat<16>();
    }
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.filtered == r_.prev && (in.clear_phase_error | in.reset).is_zero();
  }

 private:
  [[nodiscard]] const QuadTransition& transition(UInt<2> curr) const {
    return kTable[static_cast<std::size_t>(cat(r_.prev, curr).value())];
  }
};

// ---- position counter ---------------------------------------------------------
using PositionCount = SInt<20>;
struct PositionCounterRegs {
  PositionCount count;    // edges since the last latch-and-clear, two's complement wrap
  PositionCount latched;  // captured by the last latch-and-clear
  UInt<1> carry;          // sticky: counted up past +2^19-1
  UInt<1> borrow;         // sticky: counted down past -2^19
  bool operator==(const PositionCounterRegs&) const = default;
  ODOLOC_FIELDS(count, latched, carry, borrow)
};

class PositionCounter : public Registers<PositionCounterRegs> {
 public:
  using Count = PositionCount;
  static constexpr int kWidth = Count::width;
  struct In {
    SInt<2> step;
    UInt<1> latch_clear;
    UInt<1> clear_carry, clear_borrow;
    UInt<1> reset;
  };

  // The clearing clock's own edge goes into the latched value and the count
  // restarts at 0, so no edge is lost or counted twice.
  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    const Count sum = (r_.count + in.step).wrap<kWidth>();
    if (in.clear_carry)
      n.carry = UInt<1>{};
    if (in.clear_borrow)
      n.borrow = UInt<1>{};
    if (in.step.value() > 0 && r_.count.value() == Count::max_value)
      n.carry = UInt<1>{1};
    if (in.step.value() < 0 && r_.count.value() == Count::min_value)
      n.borrow = UInt<1>{1};
    n.count = in.latch_clear ? Count{} : sum;
    if (in.latch_clear)
      n.latched = sum;
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.step.is_zero() &&
           (in.latch_clear | in.clear_carry | in.clear_borrow | in.reset).is_zero();
  }
};

// ---- speed measurement ------------------------------------------------------
// Window timer for pulse mode and the prescaler that makes period mode's
// reference clock. Free-running from reset.
struct SpeedTimebaseRegs {
  UInt<23> window_count;    // clocks elapsed in the current window
  UInt<16> prescale_count;  // clocks since the last reference tick
  bool operator==(const SpeedTimebaseRegs&) const = default;
  ODOLOC_FIELDS(window_count, prescale_count)
};

class SpeedTimebase : public Registers<SpeedTimebaseRegs> {
 public:
  struct In {
    UInt<23> window_clocks;
    UInt<16> prescale;
    UInt<1> reset;
  };

  // Combinational outputs of this clock.
  [[nodiscard]] bool window_end(UInt<23> window_clocks) const {
    return r_.window_count + UInt<1>{1} >= window_clocks;
  }
  [[nodiscard]] bool tick(UInt<16> prescale) const { return r_.prescale_count >= prescale; }

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    return {window_end(in.window_clocks) ? UInt<23>{} : (r_.window_count + UInt<1>{1}).wrap<23>(),
            tick(in.prescale) ? UInt<16>{} : (r_.prescale_count + UInt<1>{1}).wrap<16>()};
  }
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

// Pulse (M) method: signed edges per window of T clocks. Owns the mode bit,
// because the automatic switch decides on each completed window.
struct PulseMeterRegs {
  SInt<24> acc;     // signed edges in the current window; |acc| <= T < 2^23
  SInt<24> last;    // edges in the last complete window
  UInt<1> mode;     // SpeedMode
  UInt<1> sampled;  // strobe: `last` was updated at this edge
  bool operator==(const PulseMeterRegs&) const = default;
  ODOLOC_FIELDS(acc, last, mode, sampled)
};

class PulseMeter : public Registers<PulseMeterRegs> {
 public:
  struct In {
    SInt<2> step;
    bool window_end;
    UInt<2> select;  // SpeedModeSelect
    UInt<23> to_period_below;
    UInt<23> to_pulse_at;
    UInt<1> reset;
  };

  // An edge in the window's last clock still belongs to the closing window.
  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    const SInt<24> acc = (r_.acc + in.step).wrap<24>();
    if (!in.window_end)
      return {acc, r_.last, next_mode(in, acc), UInt<1>{}};
    return {SInt<24>{}, acc, next_mode(in, acc), UInt<1>{1}};
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.step.is_zero() && !in.window_end && (r_.sampled | in.reset).is_zero();
  }

 private:
  // The mode changes only at window ends, so a reading never mixes modes
  // within a window. The automatic switch keeps the current mode inside the
  // hysteresis band [to_period_below, to_pulse_at).
  [[nodiscard]] UInt<1> next_mode(const In& in, SInt<24> window_edges) const {
    constexpr UInt<1> kPulse{encoding(SpeedMode::kPulse)};
    constexpr UInt<1> kPeriod{encoding(SpeedMode::kPeriod)};
    if (!in.window_end)
      return r_.mode;
    switch (static_cast<SpeedModeSelect>(in.select.value())) {
      case SpeedModeSelect::kPulse:
        return kPulse;
      case SpeedModeSelect::kPeriod:
        return kPeriod;
      default:
        break;
    }
    const UInt<24> magnitude = window_edges.abs();
    if (r_.mode == kPulse && magnitude < in.to_period_below)
      return kPeriod;
    if (r_.mode == kPeriod && magnitude >= in.to_pulse_at)
      return kPulse;
    return r_.mode;
  }
};

// Period (T) method: reference ticks between two successive edges. The tick of
// an edge's own clock starts the next measurement, so no tick is lost.
using PeriodTicks = UInt<23>;
struct PeriodMeterRegs {
  PeriodTicks count;  // ticks since the last edge, saturating
  PeriodTicks last;   // ticks between the last two edges
  UInt<1> valid;      // `last` spans two same-direction edges, not stalled, not saturated
  UInt<1> armed;      // an edge has started the running measurement
  UInt<1> last_dir;   // direction of the last edge: 1 forward
  UInt<1> overflow;   // sticky: `count` saturated
  UInt<1> sampled;    // strobe: `last` was updated at this edge
  bool operator==(const PeriodMeterRegs&) const = default;
  ODOLOC_FIELDS(count, last, valid, armed, last_dir, overflow, sampled)
};

class PeriodMeter : public Registers<PeriodMeterRegs> {
 public:
  using Ticks = PeriodTicks;
  static constexpr int kWidth = Ticks::width;
  struct In {
    SInt<2> step;
    bool tick;
    UInt<23> stall_ticks;
    UInt<1> clear_overflow;
    UInt<1> reset;
  };

  [[nodiscard]] bool stalled(UInt<23> stall_ticks) const {
    return !stall_ticks.is_zero() && r_.count >= stall_ticks;
  }

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    n.sampled = UInt<1>::truncate(!in.step.is_zero());
    if (in.clear_overflow)
      n.overflow = UInt<1>{};
    const UInt<1> tick = UInt<1>::truncate(in.tick);
    if (in.step.is_zero()) {
      const UInt<24> ticks = r_.count + tick;
      if (ticks.bit<kWidth>())
        n.overflow = UInt<1>{1};
      n.count = ticks.sat<kWidth>();
      return n;
    }
    const UInt<1> dir = UInt<1>::truncate(in.step.value() > 0);
    n.valid = UInt<1>::truncate(r_.armed && dir == r_.last_dir && !stalled(in.stall_ticks) &&
                                r_.count.value() != Ticks::max_value);
    n.last = r_.count;
    n.armed = UInt<1>{1};
    n.last_dir = dir;
    n.count = tick;
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.step.is_zero() && !in.tick && (r_.sampled | in.clear_overflow | in.reset).is_zero();
  }

  // Fast-forward: `ticks` reference ticks with no edge, strobe or control.
  // Per tick the count saturates and a tick at the maximum sets overflow, so
  // overflow is set iff count + ticks exceeds the maximum.
  // Only those two registers are written: a copy of the whole 13-byte next
  // state, assembled from narrow stores, stalled on store forwarding.
  void skip_ticks(std::uint64_t ticks) {
    const std::uint64_t total = r_.count.value() + ticks;
    if (total > Ticks::max_value)
      r_.overflow = UInt<1>{1};
    r_.count = Ticks::truncate(std::min<std::uint64_t>(total, Ticks::max_value));
  }
};

// ---- the module ---------------------------------------------------------------
class Eppm {
 public:
  using In = EppmInputs;
  using Config = EppmConfig;

  // The wires that cross the children, from the current registers only.
  struct Wires {
    UInt<2> filtered;  // conditioner -> decoder
    SInt<2> step;      // decoder -> counter, pulse and period meters
    bool window_end;   // timebase -> pulse meter
    bool tick;         // timebase -> period meter
  };
  [[nodiscard]] Wires wires(const Config& cfg) const {
    const UInt<2> filtered = conditioner_.regs().filtered;
    return {.filtered = filtered,
            .step = decoder_.step(filtered, cfg.cfg.decode_mode),
            .window_end = timebase_.window_end(cfg.window.clocks),
            .tick = timebase_.tick(cfg.prescale.divider)};
  }
  // Each child's inputs: the wires, this module's inputs and configuration.
  // A/B as the decoder sees them: swapped when cfg.reverse (a mirrored wheel
  // then counts forward), so counts, speeds and direction bits all follow.
  static UInt<2> pins(const In& in, const Config& cfg) {
    return cfg.cfg.reverse ? cat(in.b, in.a) : cat(in.a, in.b);
  }
  static QuadratureConditioner::In conditioner_in(const In& in, const Config& cfg) {
    return {.pins = pins(in, cfg), .filter_clocks = cfg.cfg.filter_clocks, .reset = in.reset};
  }
  static QuadratureDecoder::In decoder_in(const Wires& w, const In& in) {
    return {.filtered = w.filtered,
            .clear_phase_error = in.clear.status.phase_error,
            .reset = in.reset};
  }
  static PositionCounter::In counter_in(const Wires& w, const In& in) {
    return {.step = w.step,
            .latch_clear = in.latch_clear,
            .clear_carry = in.clear.status.carry,
            .clear_borrow = in.clear.status.borrow,
            .reset = in.reset};
  }
  static SpeedTimebase::In timebase_in(const In& in, const Config& cfg) {
    return {
        .window_clocks = cfg.window.clocks, .prescale = cfg.prescale.divider, .reset = in.reset};
  }
  static PulseMeter::In pulse_in(const Wires& w, const In& in, const Config& cfg) {
    return {.step = w.step,
            .window_end = w.window_end,
            .select = cfg.cfg.speed_mode_select,
            .to_period_below = cfg.to_period_below.edges,
            .to_pulse_at = cfg.to_pulse_at.edges,
            .reset = in.reset};
  }
  static PeriodMeter::In period_in(const Wires& w, const In& in, const Config& cfg) {
    return {.step = w.step,
            .tick = w.tick,
            .stall_ticks = cfg.stall_ticks.ticks,
            .clear_overflow = in.clear.status.period_overflow,
            .reset = in.reset};
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Config& cfg, const Order& order = {}) {
    // Fast path: a quiet EPPM makes no step, so only the timebase moves, plus
    // the period meter on a tick. Window ends take the full path: they set a
    // strobe that unsettles. (Each block's own eval, never a skip rule: the
    // cycle step is the reference fast-forward is checked against.)
    if (G == Gating::kOn && quiet(in, cfg) && !timebase_.window_end(cfg.window.clocks)) {
      const Wires settled{.filtered = conditioner_.regs().filtered,
                          .step = SInt<2>{},
                          .window_end = false,
                          .tick = timebase_.tick(cfg.prescale.divider)};
      order([&] { clock_block<G>(timebase_, timebase_in(in, cfg)); },
            [&] { clock_block<G>(period_, period_in(settled, in, cfg)); });
      return;
    }
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
  // Fast-forward (clocked.hpp): while quiet, only the timebase and the
  // period meter's count move, until the window ends. A pin change reaching
  // a settled EPPM is skipped too, up to the clock before the decoder sees it
  // (InputConditioner::held_from_settled): until then the conditioner alone
  // differs from a quiet clock. Unless the window ends in those clocks: then
  // every clock is stepped.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& in, const Config& cfg) const {
    const std::uint64_t window = timebase_.clocks_to_window_end(cfg.window.clocks);
    if (quiet(in, cfg))
      return window;
    if (!taking(in, cfg))
      return 0;
    const std::uint64_t take = QuadratureConditioner::clocks_to_take(cfg.cfg.filter_clocks);
    return window >= take ? take : 0;
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

  // What the register file reads (eppm.* status registers). The speed word:
  // the mode bit selects which measurement the value is; a stall reads 0.
  [[nodiscard]] EppmStatus status(const Config& cfg) const {
    const auto& p = period_.regs();
    const auto& d = decoder_.regs();
    const auto& c = counter_.regs();
    EppmStatus s;
    s.count.value = c.count;
    s.latched.value = c.latched;
    s.speed.mode = pulse_.regs().mode;
    s.speed.stalled = UInt<1>::truncate(period_.stalled(cfg.stall_ticks.ticks));
    if (s.speed.stalled) {
      s.speed.valid = UInt<1>{1};
    } else if (s.speed.mode.value() == encoding(SpeedMode::kPulse)) {
      s.speed.value = pulse_.regs().last;
      s.speed.valid = UInt<1>{1};
    } else if (p.valid) {
      // The last period, unless the time since the last edge already exceeds
      // it (the wheel is slower now: at most one edge per elapsed time, so the
      // reading decays toward zero instead of holding until the stall), and
      // never below one tick (two edges within one tick are faster than the
      // meter resolves; 0 would read as standing still).
      const PeriodTicks open = p.count;
      const PeriodTicks longest = p.last >= open ? p.last : open;
      const PeriodTicks ticks = longest.is_zero() ? PeriodTicks{1} : longest;
      s.speed.bound = UInt<1>::truncate(ticks != p.last);
      const SInt<24> signed_ticks = ticks.to_sint();
      s.speed.value = p.last_dir ? signed_ticks : (-signed_ticks).wrap<24>();  // exact: < 2^23
      s.speed.valid = UInt<1>{1};
    }
    s.pulse_last.edges = pulse_.regs().last;
    s.period_last.ticks = p.last;
    s.period_last.valid = p.valid;
    s.period_last.forward = p.last_dir;
    s.status.phase_error = d.phase_error;
    s.status.carry = c.carry;
    s.status.borrow = c.borrow;
    s.status.period_overflow = p.overflow;
    s.status.forward = d.direction;
    s.error_count.count = d.error_count;
    return s;
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
  // Every stage holds the same A/B with no filter count, no strobe is pending
  // and the last clock carried no control: nothing but the timebase can move
  // until the pins change, a control arrives, a window ends or a tick comes.
  [[nodiscard]] bool settled() const {
    return conditioner_.settled() && conditioner_.regs().filtered == decoder_.regs().prev &&
           (pulse_.regs().sampled | period_.regs().sampled | ports_.latch_clear | ports_.reset)
               .is_zero() &&
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
              decltype(QuadratureConditioner::Regs{}.stable)::value_type::width ==
                  eppm::kFilterBits &&
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
