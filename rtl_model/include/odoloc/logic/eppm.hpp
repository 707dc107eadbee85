// The Encoder Pulse Processing Module's logic, written once (docs/eppm.md;
// docs/hls.md, "One source per block"): the cycle model (rtl/eppm.hpp) runs
// it with the model's types, the HLS kernel (hls/eppm_kernel.hpp) with the
// vendor's, and `odoloc export-hls` exports this file.
//
//   pins A,B -> input conditioner -> quadrature decoder --step--> position counter
//                                    (x4/x2/x1, phase     +-> pulse meter (window count, mode)
//                                     error counting)     +-> period meter (ticks per edge, stall)
//               speed timebase (window timer, reference prescaler)
//
// Paper: Kurian & Pillai, section 2 (Fig. 1). Widths and encodings:
// rtl/eppm_constants.hpp (the model static_asserts them against the register
// map). Each leaf is Regs, In and a next() that returns the registers after
// one clock's edge from the current ones and the input wires; the module
// (Eppm) computes every wire that crosses the leaves from the current
// registers, then each leaf's In, so the leaves can be clocked in any order.
// The module's configuration, clear strobes and status are the register
// map's port structs (odoloc/ports.hpp in the model, odoloc/logic/ports.hpp
// in the kernel): the functions take them as template parameters.
// C++14, no heap, no containers, static loop bounds (int_family.hpp).
#pragma once

#include "odoloc/logic/input_conditioner.hpp"
#include "odoloc/logic/int_family.hpp"
#include "odoloc/logic/ports.hpp"
#include "odoloc/rtl/eppm_constants.hpp"

namespace odoloc {
namespace logic {
namespace eppm {

namespace constants = rtl::eppm;

template <class F>
using Lines = uint<F, constants::kLines>;  // A in bit 1, B in bit 0
template <class F>
using Step = sint<F, 2>;  // the decoder's count pulse: -1, 0 or +1
template <class F>
using Count = sint<F, constants::kCountBits>;
template <class F>
using Edges = sint<F, constants::kPulseBits>;
template <class F>
using Ticks = uint<F, constants::kPeriodBits>;
template <class F>
using Mode = uint<F, constants::kModeBits>;

// ---- quadrature decoder -----------------------------------------------------
// The decoder's truth table, computed at compile time (a 16-entry ROM in
// hardware, a load in the model): entry prev * 4 + curr of the (previous,
// current) A/B pair, A in bit 1. The position in the forward cycle AB = 00
// -> 10 -> 11 -> 01 is the Gray code (B, A^B) read as binary; one step up is
// forward, one down backward, two is illegal (both lines changed). x4 counts
// every step, x2 the steps of A, x1 only A's edge with B low (in both
// directions, so back and forth over it nets zero); decode mode 3 behaves as
// x4.
struct DecodeTable {
  signed char count[16][4];  // per decode mode: -1, 0 or +1
  bool illegal[16];
};
constexpr int gray_position(int ab) {
  return ((ab & 1) << 1) | ((ab >> 1 & 1) ^ (ab & 1));
}
constexpr DecodeTable make_decode_table() {
  DecodeTable t = {};
  for (int prev = 0; prev < 4; ++prev) {
    for (int curr = 0; curr < 4; ++curr) {
      const int delta = (gray_position(curr) - gray_position(prev) + 4) % 4;
      const int dir = delta == 1 ? 1 : delta == 3 ? -1 : 0;
      const bool a_changed = ((prev ^ curr) & 2) != 0;
      const bool b_low = (prev & 1) == 0 && (curr & 1) == 0;
      const int at = prev * 4 + curr;
      t.count[at][constants::kDecodeX4] = static_cast<signed char>(dir);
      t.count[at][constants::kDecodeX2] = static_cast<signed char>(a_changed ? dir : 0);
      t.count[at][constants::kDecodeX1] = static_cast<signed char>(a_changed && b_low ? dir : 0);
      t.count[at][3] = static_cast<signed char>(dir);
      t.illegal[at] = delta == 2;
    }
  }
  return t;
}
constexpr DecodeTable kDecodeTable = make_decode_table();

template <class F>
struct DecoderRegs {
  Lines<F> prev{0};           // filtered A/B one clock earlier
  uint<F, 1> direction{0};    // direction of the last legal step: 1 forward (A leads B)
  uint<F, 1> phase_error{0};  // sticky: A and B changed in the same sample
  uint<F, constants::kErrorCountBits> error_count{0};  // illegal transitions, saturating
};
template <class F>
struct DecoderIn {
  Lines<F> filtered{0};
  uint<F, 1> clear_phase_error{0};  // also clears error_count
  uint<F, 1> reset{0};
};

template <class F>
struct QuadratureDecoder {
  using R = DecoderRegs<F>;
  // One (previous, current) A/B pair.
  struct Transition {
    Step<F> step;  // after x4/x2/x1 gating
    bool moved;    // a legal x4 step, either way
    bool forward;  // that step was forward (A leads B)
    bool illegal;  // both lines changed
  };

  static Transition decode(Lines<F> prev, Lines<F> curr, Mode<F> decode_mode) {
    const long long at = to_s64(cat(prev, curr));
    const signed char x4 = kDecodeTable.count[at][constants::kDecodeX4];
    Transition t;
    t.step = wrap<Step<F> >(kDecodeTable.count[at][to_s64(decode_mode)]);
    t.moved = x4 != 0;
    t.forward = x4 > 0;
    t.illegal = kDecodeTable.illegal[at];
    return t;
  }
  // The count pulse of this clock.
  static Step<F> step(const R& r, Lines<F> filtered, Mode<F> decode_mode) {
    return decode(r.prev, filtered, decode_mode).step;
  }

  static R next(const R& r, const DecoderIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    const Transition t = decode(r.prev, in.filtered, Mode<F>(constants::kDecodeX4));
    R n = r;
    n.prev = in.filtered;
    if (t.moved)
      n.direction = wrap<uint<F, 1> >(t.forward);
    if (!is_zero(in.clear_phase_error)) {
      n.phase_error = uint<F, 1>(0);
      n.error_count = uint<F, constants::kErrorCountBits>(0);
    }
    if (t.illegal) {
      n.phase_error = uint<F, 1>(1);
      if (to_s64(n.error_count) != kErrorCountMax)
        n.error_count = wrap<uint<F, constants::kErrorCountBits> >(n.error_count + uint<F, 1>(1));
    }
    return n;
  }

 private:
  static constexpr long long kErrorCountMax = (1LL << constants::kErrorCountBits) - 1;
};

// ---- position counter ---------------------------------------------------------
template <class F>
struct CounterRegs {
  Count<F> count{0};     // edges since the last latch-and-clear, two's complement wrap
  Count<F> latched{0};   // captured by the last latch-and-clear
  uint<F, 1> carry{0};   // sticky: counted up past +2^19-1
  uint<F, 1> borrow{0};  // sticky: counted down past -2^19
};
template <class F>
struct CounterIn {
  Step<F> step{0};
  uint<F, 1> latch_clear{0};
  uint<F, 1> clear_carry{0}, clear_borrow{0};
  uint<F, 1> reset{0};
};

template <class F>
struct PositionCounter {
  using R = CounterRegs<F>;
  // The clearing clock's own edge goes into the latched value and the count
  // restarts at 0, so no edge is lost or counted twice.
  static R next(const R& r, const CounterIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    const Count<F> sum = wrap<Count<F> >(r.count + in.step);
    if (!is_zero(in.clear_carry))
      n.carry = uint<F, 1>(0);
    if (!is_zero(in.clear_borrow))
      n.borrow = uint<F, 1>(0);
    if (in.step > Step<F>(0) && to_s64(r.count) == kMax)
      n.carry = uint<F, 1>(1);
    if (in.step < Step<F>(0) && to_s64(r.count) == kMin)
      n.borrow = uint<F, 1>(1);
    if (!is_zero(in.latch_clear)) {
      n.count = Count<F>(0);
      n.latched = sum;
    } else {
      n.count = sum;
    }
    return n;
  }

 private:
  static constexpr long long kMax = (1LL << (constants::kCountBits - 1)) - 1;
  static constexpr long long kMin = -(1LL << (constants::kCountBits - 1));
};

// ---- speed timebase -----------------------------------------------------------
// Window timer for pulse mode and the prescaler that makes period mode's
// reference clock. Free-running from reset.
template <class F>
struct TimebaseRegs {
  uint<F, constants::kWindowBits> window_count{0};      // clocks elapsed in the current window
  uint<F, constants::kPrescaleBits> prescale_count{0};  // clocks since the last reference tick
};
template <class F>
struct TimebaseIn {
  uint<F, constants::kWindowBits> window_clocks{0};  // 0 behaves as 1
  uint<F, constants::kPrescaleBits> prescale{0};     // a tick every prescale + 1 clocks
  uint<F, 1> reset{0};
};

template <class F>
struct SpeedTimebase {
  using R = TimebaseRegs<F>;
  using Window = uint<F, constants::kWindowBits>;
  using Prescale = uint<F, constants::kPrescaleBits>;
  // Combinational outputs of this clock.
  static bool window_end(const R& r, Window window_clocks) {
    return r.window_count + uint<F, 1>(1) >= window_clocks;
  }
  static bool tick(const R& r, Prescale prescale) { return r.prescale_count >= prescale; }

  static R next(const R& r, const TimebaseIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    return R{
        window_end(r, in.window_clocks) ? Window(0) : wrap<Window>(r.window_count + uint<F, 1>(1)),
        tick(r, in.prescale) ? Prescale(0) : wrap<Prescale>(r.prescale_count + uint<F, 1>(1))};
  }
};

// ---- pulse (M) meter ----------------------------------------------------------
// Signed edges per window of T clocks. Owns the mode bit, because the
// automatic switch decides on each completed window.
template <class F>
struct PulseRegs {
  Edges<F> acc{0};        // signed edges in the current window; |acc| <= T < 2^23
  Edges<F> last{0};       // edges in the last complete window
  uint<F, 1> mode{0};     // eppm.speed.mode: 1 pulse, 0 period
  uint<F, 1> sampled{0};  // strobe: `last` was updated at this edge
};
template <class F>
struct PulseIn {
  Step<F> step{0};
  bool window_end = false;
  Mode<F> select{0};  // eppm.cfg.speed_mode_select
  Ticks<F> to_period_below{0};
  Ticks<F> to_pulse_at{0};
  uint<F, 1> reset{0};
};

template <class F>
struct PulseMeter {
  using R = PulseRegs<F>;
  // An edge in the window's last clock still belongs to the closing window.
  static R next(const R& r, const PulseIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    const Edges<F> acc = wrap<Edges<F> >(r.acc + in.step);
    if (!in.window_end)
      return R{acc, r.last, r.mode, uint<F, 1>(0)};
    return R{Edges<F>(0), acc, next_mode(r, in, acc), uint<F, 1>(1)};
  }

 private:
  // At a window end, so a reading never mixes modes within a window: the
  // forced modes, or the automatic switch, which keeps the current mode
  // inside the hysteresis band [to_period_below, to_pulse_at).
  static uint<F, 1> next_mode(const R& r, const PulseIn<F>& in, Edges<F> window_edges) {
    const uint<F, 1> pulse(constants::kModePulse);
    const uint<F, 1> period(constants::kModePeriod);
    const long long select = to_s64(in.select);
    if (select == constants::kSelectPulse)
      return pulse;
    if (select == constants::kSelectPeriod)
      return period;
    using Magnitude = uint<F, constants::kPulseBits>;
    const Magnitude magnitude =
        window_edges < Edges<F>(0) ? wrap<Magnitude>(-window_edges) : wrap<Magnitude>(window_edges);
    if (r.mode == pulse && magnitude < in.to_period_below)
      return period;
    if (r.mode == period && magnitude >= in.to_pulse_at)
      return pulse;
    return r.mode;
  }
};

// ---- period (T) meter ---------------------------------------------------------
// Reference ticks between two successive edges. The tick of an edge's own
// clock starts the next measurement, so no tick is lost.
template <class F>
struct PeriodRegs {
  Ticks<F> count{0};       // ticks since the last edge, saturating
  Ticks<F> last{0};        // ticks between the last two edges
  uint<F, 1> valid{0};     // `last` spans two same-direction edges, not stalled, not saturated
  uint<F, 1> armed{0};     // an edge has started the running measurement
  uint<F, 1> last_dir{0};  // direction of the last edge: 1 forward
  uint<F, 1> overflow{0};  // sticky: `count` saturated
  uint<F, 1> sampled{0};   // strobe: `last` was updated at this edge
};
template <class F>
struct PeriodIn {
  Step<F> step{0};
  bool tick = false;
  Ticks<F> stall_ticks{0};  // 0: no stall
  uint<F, 1> clear_overflow{0};
  uint<F, 1> reset{0};
};

template <class F>
struct PeriodMeter {
  using R = PeriodRegs<F>;
  static constexpr long long kTicksMax = (1LL << constants::kPeriodBits) - 1;

  static bool stalled(const R& r, Ticks<F> stall_ticks) {
    return !is_zero(stall_ticks) && r.count >= stall_ticks;
  }

  static R next(const R& r, const PeriodIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    n.sampled = wrap<uint<F, 1> >(!is_zero(in.step));
    if (!is_zero(in.clear_overflow))
      n.overflow = uint<F, 1>(0);
    const uint<F, 1> tick = wrap<uint<F, 1> >(in.tick);
    if (is_zero(in.step)) {
      const uint<F, constants::kPeriodBits + 1> ticks = r.count + tick;
      if (!is_zero(bit<constants::kPeriodBits>(ticks))) {
        n.overflow = uint<F, 1>(1);
        n.count = Ticks<F>(kTicksMax);
      } else {
        n.count = wrap<Ticks<F> >(ticks);
      }
      return n;
    }
    const uint<F, 1> dir = wrap<uint<F, 1> >(in.step > Step<F>(0));
    n.valid = wrap<uint<F, 1> >(!is_zero(r.armed) && dir == r.last_dir &&
                                !stalled(r, in.stall_ticks) && to_s64(r.count) != kTicksMax);
    n.last = r.count;
    n.armed = uint<F, 1>(1);
    n.last_dir = dir;
    n.count = Ticks<F>(tick);
    return n;
  }
};

// ---- the module ---------------------------------------------------------------
// The module's inputs besides configuration: the pins, the read-increment
// strobe, the sticky flags' clears (eppm.*.status, w1c) and reset.
template <class F>
struct In {
  uint<F, 1> a{0}, b{0};         // encoder pins, asynchronous to the fabric clock
  uint<F, 1> latch_clear{0};     // read increment: latch the count and restart it from 0
  ports::eppm::Pulses<F> clear;  // status.<flag>: clear it this clock; an event wins
  uint<F, 1> reset{0};           // synchronous reset of every register
};

// The module's register bank: the leaves' registers.
template <class F>
struct Regs {
  conditioner::Regs<F, constants::kLines> conditioner;
  DecoderRegs<F> decoder;
  CounterRegs<F> counter;
  TimebaseRegs<F> timebase;
  PulseRegs<F> pulse;
  PeriodRegs<F> period;
};

// The wires that cross the leaves, from the current registers only.
template <class F>
struct Wires {
  Lines<F> filtered;  // conditioner -> decoder
  Step<F> step;       // decoder -> counter, pulse and period meters
  bool window_end;    // timebase -> pulse meter
  bool tick;          // timebase -> period meter
};

// Config: eppm Config ports (cfg, window, prescale, to_period_below,
// to_pulse_at, stall_ticks); ModuleIn: In<F> or the model's EppmInputs;
// Status: eppm Status ports.
template <class F>
struct Eppm {
  using Conditioner = conditioner::InputConditioner<F, constants::kLines>;
  using Decoder = QuadratureDecoder<F>;
  using Counter = PositionCounter<F>;
  using Timebase = SpeedTimebase<F>;
  using Pulse = PulseMeter<F>;
  using Period = PeriodMeter<F>;

  template <class Config>
  static Wires<F> wires(const conditioner::Regs<F, constants::kLines>& conditioner,
                        const DecoderRegs<F>& decoder, const TimebaseRegs<F>& timebase,
                        const Config& cfg) {
    Wires<F> w;
    w.filtered = conditioner.filtered;
    w.step = Decoder::step(decoder, conditioner.filtered, cfg.cfg.decode_mode);
    w.window_end = Timebase::window_end(timebase, cfg.window.clocks);
    w.tick = Timebase::tick(timebase, cfg.prescale.divider);
    return w;
  }

  // Each leaf's inputs: the wires, the module's inputs and configuration.
  // A/B as the decoder sees them: swapped when cfg.reverse (a mirrored wheel
  // then counts forward), so counts, speeds and direction bits all follow.
  template <class ModuleIn, class Config>
  static Lines<F> pins(const ModuleIn& in, const Config& cfg) {
    return !is_zero(cfg.cfg.reverse) ? cat(in.b, in.a) : cat(in.a, in.b);
  }
  template <class ModuleIn, class Config>
  static conditioner::In<F, constants::kLines> conditioner_in(const ModuleIn& in,
                                                              const Config& cfg) {
    conditioner::In<F, constants::kLines> c;
    c.pins = pins(in, cfg);
    c.filter_clocks = cfg.cfg.filter_clocks;
    c.reset = in.reset;
    return c;
  }
  template <class ModuleIn>
  static DecoderIn<F> decoder_in(const Wires<F>& w, const ModuleIn& in) {
    DecoderIn<F> d;
    d.filtered = w.filtered;
    d.clear_phase_error = in.clear.status.phase_error;
    d.reset = in.reset;
    return d;
  }
  template <class ModuleIn>
  static CounterIn<F> counter_in(const Wires<F>& w, const ModuleIn& in) {
    CounterIn<F> c;
    c.step = w.step;
    c.latch_clear = in.latch_clear;
    c.clear_carry = in.clear.status.carry;
    c.clear_borrow = in.clear.status.borrow;
    c.reset = in.reset;
    return c;
  }
  template <class ModuleIn, class Config>
  static TimebaseIn<F> timebase_in(const ModuleIn& in, const Config& cfg) {
    TimebaseIn<F> t;
    t.window_clocks = cfg.window.clocks;
    t.prescale = cfg.prescale.divider;
    t.reset = in.reset;
    return t;
  }
  template <class ModuleIn, class Config>
  static PulseIn<F> pulse_in(const Wires<F>& w, const ModuleIn& in, const Config& cfg) {
    PulseIn<F> p;
    p.step = w.step;
    p.window_end = w.window_end;
    p.select = cfg.cfg.speed_mode_select;
    p.to_period_below = cfg.to_period_below.edges;
    p.to_pulse_at = cfg.to_pulse_at.edges;
    p.reset = in.reset;
    return p;
  }
  template <class ModuleIn, class Config>
  static PeriodIn<F> period_in(const Wires<F>& w, const ModuleIn& in, const Config& cfg) {
    PeriodIn<F> p;
    p.step = w.step;
    p.tick = w.tick;
    p.stall_ticks = cfg.stall_ticks.ticks;
    p.clear_overflow = in.clear.status.period_overflow;
    p.reset = in.reset;
    return p;
  }

  // One fabric clock of the whole module: every wire from the current
  // registers, then every leaf.
  template <class ModuleIn, class Config>
  static Regs<F> next(const Regs<F>& r, const ModuleIn& in, const Config& cfg) {
    const Wires<F> w = wires(r.conditioner, r.decoder, r.timebase, cfg);
    Regs<F> n;
    n.conditioner = Conditioner::next(r.conditioner, conditioner_in(in, cfg));
    n.decoder = Decoder::next(r.decoder, decoder_in(w, in));
    n.counter = Counter::next(r.counter, counter_in(w, in));
    n.timebase = Timebase::next(r.timebase, timebase_in(in, cfg));
    n.pulse = Pulse::next(r.pulse, pulse_in(w, in, cfg));
    n.period = Period::next(r.period, period_in(w, in, cfg));
    return n;
  }

  // What the register file reads (eppm.* status registers). The speed word:
  // the mode bit selects which measurement the value is; a stall reads 0. In
  // period mode: max(last period, ticks since the last edge, 1) with the last
  // edge's sign, and `bound` when that is not the last period (the wheel is
  // slower now: at most one edge per elapsed time, so the reading decays
  // toward zero instead of holding until the stall; two edges within one
  // tick are faster than the meter resolves, and 0 would read as standing
  // still).
  template <class Status, class Config>
  static Status status(const DecoderRegs<F>& d, const CounterRegs<F>& c, const PulseRegs<F>& pulse,
                       const PeriodRegs<F>& p, const Config& cfg) {
    Status s;
    s.count.value = c.count;
    s.latched.value = c.latched;
    s.speed.mode = pulse.mode;
    const bool stall = Period::stalled(p, cfg.stall_ticks.ticks);
    s.speed.stalled = wrap<uint<F, 1> >(stall);
    if (stall) {
      s.speed.valid = uint<F, 1>(1);
    } else if (to_s64(pulse.mode) == constants::kModePulse) {
      s.speed.value = pulse.last;
      s.speed.valid = uint<F, 1>(1);
    } else if (!is_zero(p.valid)) {
      const Ticks<F> longest = p.last >= p.count ? p.last : p.count;
      const Ticks<F> ticks = is_zero(longest) ? Ticks<F>(1) : longest;
      s.speed.bound = wrap<uint<F, 1> >(ticks != p.last);
      const Edges<F> magnitude = wrap<Edges<F> >(ticks);  // exact: < 2^23
      s.speed.value = is_zero(p.last_dir) ? wrap<Edges<F> >(-magnitude) : magnitude;
      s.speed.valid = uint<F, 1>(1);
    }
    s.pulse_last.edges = pulse.last;
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
  template <class Status, class Config>
  static Status status(const Regs<F>& r, const Config& cfg) {
    return status<Status>(r.decoder, r.counter, r.pulse, r.period, cfg);
  }
};

}  // namespace eppm
}  // namespace logic
}  // namespace odoloc
