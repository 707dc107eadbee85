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

#include <array>
#include <cstddef>
#include <cstdint>

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"

namespace odoloc::rtl {

// ---- configuration (block-level registers written by the host) --------------
enum class DecodeMode : std::uint8_t { kX4 = 0, kX2 = 1, kX1 = 2 };  // 3 behaves as x4
enum class SpeedModeSelect : std::uint8_t { kAuto = 0, kPulse = 1, kPeriod = 2 };  // 3: auto
enum class SpeedMode : std::uint8_t { kPeriod = 0, kPulse = 1 };

struct EppmConfig {
  UInt<8> filter_clocks{3};  // a level must be stable this many clocks; 0 and 1: filter off
  UInt<2> decode_mode{static_cast<std::uint8_t>(DecodeMode::kX4)};
  UInt<2> speed_mode_select{static_cast<std::uint8_t>(SpeedModeSelect::kAuto)};
  UInt<23> window_clocks{50'000};  // pulse-mode window T in fabric clocks; 0 behaves as 1
  UInt<16> prescale{49};           // one reference tick every prescale+1 clocks (1 MHz)
  UInt<23> to_period_below{25};    // auto: pulse -> period when |edges per window| < this
  UInt<23> to_pulse_at{40};        // auto: period -> pulse when |edges per window| >= this
  UInt<23> stall_ticks{50'000};    // stalled after this many ticks without an edge; 0: never
};

// One clear strobe per sticky flag, so a write-1-to-clear status register
// clears exactly the flags written; an event in the clearing clock wins.
struct EppmFlagClear {
  UInt<1> phase_error;  // and the error counter
  UInt<1> carry, borrow, period_overflow;
  static constexpr EppmFlagClear all(UInt<1> clear) { return {clear, clear, clear, clear}; }
  [[nodiscard]] constexpr UInt<1> any() const {
    return phase_error | carry | borrow | period_overflow;
  }
  bool operator==(const EppmFlagClear&) const = default;
};

struct EppmInputs {
  UInt<1> a, b;         // encoder pins, asynchronous to the fabric clock
  UInt<1> latch_clear;  // read increment: latch the count and restart it from 0
  EppmFlagClear clear;  // sticky flags to clear
  UInt<1> reset;        // synchronous reset of every register
};

// ---- input conditioning -------------------------------------------------------
// Per channel: two synchroniser flops, then a level filter. A/B travel packed
// as a 2-bit value, A in bit 1.
struct InputConditionerRegs {
  UInt<2> sync1, sync2, filtered;
  UInt<8> stable_a, stable_b;  // consecutive samples the level has differed from `filtered`
  bool operator==(const InputConditionerRegs&) const = default;
};

class InputConditioner : public Registers<InputConditionerRegs> {
 public:
  struct In {
    UInt<2> pins;
    UInt<8> filter_clocks;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    const Channel a =
        filter(r_.sync2.bit<1>(), r_.filtered.bit<1>(), r_.stable_a, in.filter_clocks);
    const Channel b =
        filter(r_.sync2.bit<0>(), r_.filtered.bit<0>(), r_.stable_b, in.filter_clocks);
    return {in.pins, r_.sync1, cat(a.level, b.level), a.stable, b.stable};
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.pins == r_.sync1 && r_.sync1 == r_.sync2 && r_.sync2 == r_.filtered &&
           (r_.stable_a | r_.stable_b | in.reset).is_zero();
  }

  template <class V>
  void trace(V& v) const {
    v.signal("sync1", r_.sync1);
    v.signal("sync2", r_.sync2);
    v.signal("filtered", r_.filtered);
    v.signal("stable_a", r_.stable_a);
    v.signal("stable_b", r_.stable_b);
  }

 private:
  struct Channel {
    UInt<1> level;
    UInt<8> stable;
  };
  // Takes the new level on the N-th consecutive differing sample (N <= 1: the first).
  static Channel filter(UInt<1> in, UInt<1> level, UInt<8> stable, UInt<8> n) {
    if (in == level)
      return {level, UInt<8>{}};
    const UInt<9> seen = stable + UInt<1>{1};
    if (seen >= n)
      return {in, UInt<8>{}};
    return {level, seen.wrap<8>()};  // seen < n <= 255
  }
};

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

  template <class V>
  void trace(V& v) const {
    v.signal("prev", r_.prev);
    v.signal("direction", r_.direction);
    v.signal("phase_error", r_.phase_error);
    v.signal("error_count", r_.error_count);
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

  template <class V>
  void trace(V& v) const {
    v.signal("count", r_.count);
    v.signal("latched", r_.latched);
    v.signal("carry", r_.carry);
    v.signal("borrow", r_.borrow);
  }
};

// ---- speed measurement ------------------------------------------------------
// Window timer for pulse mode and the prescaler that makes period mode's
// reference clock. Free-running from reset.
struct SpeedTimebaseRegs {
  UInt<23> window_count;    // clocks elapsed in the current window
  UInt<16> prescale_count;  // clocks since the last reference tick
  bool operator==(const SpeedTimebaseRegs&) const = default;
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

  template <class V>
  void trace(V& v) const {
    v.signal("window_count", r_.window_count);
    v.signal("prescale_count", r_.prescale_count);
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

  template <class V>
  void trace(V& v) const {
    v.signal("acc", r_.acc);
    v.signal("last", r_.last);
    v.signal("mode", r_.mode);
    v.signal("sampled", r_.sampled);
  }

 private:
  // The mode changes only at window ends, so a reading never mixes modes
  // within a window. The automatic switch keeps the current mode inside the
  // hysteresis band [to_period_below, to_pulse_at).
  [[nodiscard]] UInt<1> next_mode(const In& in, SInt<24> window_edges) const {
    constexpr UInt<1> kPulse{static_cast<std::uint8_t>(SpeedMode::kPulse)};
    constexpr UInt<1> kPeriod{static_cast<std::uint8_t>(SpeedMode::kPeriod)};
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

  template <class V>
  void trace(V& v) const {
    v.signal("count", r_.count);
    v.signal("last", r_.last);
    v.signal("valid", r_.valid);
    v.signal("armed", r_.armed);
    v.signal("last_dir", r_.last_dir);
    v.signal("overflow", r_.overflow);
    v.signal("sampled", r_.sampled);
  }
};

// The speed word the host reads: the mode bit selects which measurement it is.
struct EppmSpeed {
  SInt<24> value;   // pulse: edges per window; period: +/- ticks per edge; 0 when stalled
  UInt<1> mode;     // SpeedMode: 1 pulse, 0 period
  UInt<1> valid;    // 0: the period sample spans a reversal or starts a measurement
  UInt<1> stalled;  // no edge for stall_ticks reference ticks
  bool operator==(const EppmSpeed&) const = default;
};

// ---- the module ---------------------------------------------------------------
class Eppm {
 public:
  template <Gating G = Gating::kOn>
  void step(const EppmInputs& in, const EppmConfig& cfg) {
    // Wires between the children, all from the current registers.
    const UInt<2> filtered = conditioner_.regs().filtered;
    const bool window_end = timebase_.window_end(cfg.window_clocks);
    const bool tick = timebase_.tick(cfg.prescale);
    const SpeedTimebase::In timebase_in{cfg.window_clocks, cfg.prescale, in.reset};

    // Fast path: a settled pipeline with unchanged pins and no control makes
    // no step, so only the timebase moves, plus the period meter on a tick.
    // Window ends take the full path: they set a strobe that unsettles.
    if (G == Gating::kOn && settled_ && !window_end && cat(in.a, in.b) == filtered &&
        (in.latch_clear | in.clear.any() | in.reset).is_zero()) {
      timebase_.commit(timebase_.eval(timebase_in));
      clock_block<G>(period_, {SInt<2>{}, tick, cfg.stall_ticks, UInt<1>{}, in.reset});
      return;
    }
    const SInt<2> step = decoder_.step(filtered, cfg.decode_mode);
    ports_ = in;
    clock_block<G>(conditioner_, {cat(in.a, in.b), cfg.filter_clocks, in.reset});
    clock_block<G>(decoder_, {filtered, in.clear.phase_error, in.reset});
    clock_block<G>(counter_, {step, in.latch_clear, in.clear.carry, in.clear.borrow, in.reset});
    clock_block<G>(timebase_, timebase_in);
    clock_block<G>(pulse_, {step, window_end, cfg.speed_mode_select, cfg.to_period_below,
                            cfg.to_pulse_at, in.reset});
    clock_block<G>(period_, {step, tick, cfg.stall_ticks, in.clear.period_overflow, in.reset});
    settled_ = settled();
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

  [[nodiscard]] EppmSpeed speed(const EppmConfig& cfg) const {
    const auto& p = period_.regs();
    EppmSpeed s;
    s.mode = pulse_.regs().mode;
    s.stalled = UInt<1>::truncate(period_.stalled(cfg.stall_ticks));
    if (s.stalled) {
      s.valid = UInt<1>{1};
    } else if (s.mode.value() == static_cast<std::uint8_t>(SpeedMode::kPulse)) {
      s.value = pulse_.regs().last;
      s.valid = UInt<1>{1};
    } else if (p.valid) {
      const SInt<24> ticks = p.last.to_sint();
      s.value = p.last_dir ? ticks : (-ticks).wrap<24>();  // |ticks| < 2^23: exact
      s.valid = UInt<1>{1};
    }
    return s;
  }

  [[nodiscard]] const InputConditioner::Regs& conditioner() const { return conditioner_.regs(); }
  [[nodiscard]] const QuadratureDecoder::Regs& decoder() const { return decoder_.regs(); }
  [[nodiscard]] const PositionCounter::Regs& counter() const { return counter_.regs(); }
  [[nodiscard]] const SpeedTimebase::Regs& timebase() const { return timebase_.regs(); }
  [[nodiscard]] const PulseMeter::Regs& pulse() const { return pulse_.regs(); }
  [[nodiscard]] const PeriodMeter::Regs& period() const { return period_.regs(); }
  [[nodiscard]] PositionCounter::Count count() const { return counter_.regs().count; }

  template <class V>
  void trace(V& v) const {
    v.signal("a", ports_.a);
    v.signal("b", ports_.b);
    v.signal("latch_clear", ports_.latch_clear);
    v.signal("clear_phase_error", ports_.clear.phase_error);
    v.signal("clear_carry", ports_.clear.carry);
    v.signal("clear_borrow", ports_.clear.borrow);
    v.signal("clear_period_overflow", ports_.clear.period_overflow);
    v.signal("reset", ports_.reset);
    trace_scope(v, "conditioner", conditioner_);
    trace_scope(v, "decoder", decoder_);
    trace_scope(v, "counter", counter_);
    trace_scope(v, "timebase", timebase_);
    trace_scope(v, "pulse", pulse_);
    trace_scope(v, "period", period_);
  }

 private:
  // Every stage holds the same A/B with no filter count, no strobe is pending
  // and the last clock carried no control: nothing but the timebase can move
  // until the pins change, a control arrives, a window ends or a tick comes.
  [[nodiscard]] bool settled() const {
    const auto& c = conditioner_.regs();
    return c.sync1 == c.sync2 && c.sync2 == c.filtered && c.filtered == decoder_.regs().prev &&
           (c.stable_a | c.stable_b).is_zero() &&
           (pulse_.regs().sampled | period_.regs().sampled | ports_.latch_clear |
            ports_.clear.any() | ports_.reset)
               .is_zero();
  }

  EppmInputs ports_;      // the inputs of the last clock, for waveforms
  bool settled_ = false;  // simulator bookkeeping, not a register: settled() after the last clock
  InputConditioner conditioner_;
  QuadratureDecoder decoder_;
  PositionCounter counter_;
  SpeedTimebase timebase_;
  PulseMeter pulse_;
  PeriodMeter period_;
};

}  // namespace odoloc::rtl
