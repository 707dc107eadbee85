// The Encoder Pulse Processing Module as an HLS kernel: one call = one 50 MHz
// fabric clock of rtl::Eppm (rtl_model/include/odoloc/rtl/eppm.hpp,
// docs/eppm.md), one kernel per wheel encoder, in odoloc::hls integer types
// (types.hpp: ap_int.h, ac_int.h or the project's own). C++14. Inside: the
// input conditioner (2-flop synchroniser and level filter per line,
// rtl::InputConditioner<2>), the quadrature decoder (x4/x2/x1, phase errors),
// the 20-bit position counter (latch-and-clear, carry/borrow), the speed
// timebase (window timer, reference prescaler), the pulse meter (edges per
// window, automatic mode switch with hysteresis) and the period meter (ticks
// per edge, stall, overflow).
//
// Inputs, per call:
//   a, b [1 each]          encoder pins, asynchronous to the fabric clock
//   latch_clear [1]        read increment: latched <- count including this
//                          clock's edge, count <- 0
//   clear_phase_error, clear_carry, clear_borrow, clear_period_overflow [1 each]
//                          the w1c strobes of eppm.status (phase_error also
//                          clears error_count); an event in the same clock wins
//   reset [1]              synchronous reset of every register
//   filter_clocks [8], decode_mode [2] (0 x4, 1 x2, 2 x1, 3 x4),
//   speed_mode_select [2] (0 auto, 1 pulse, 2 period, 3 auto), reverse [1]
//                          eppm.cfg
//   window_clocks [23]     eppm.window: pulse-mode window, 0 behaves as 1
//   prescale_divider [16]  eppm.prescale: one reference tick every divider+1 clocks
//   to_period_below [23], to_pulse_at [23]   the automatic switch's thresholds
//   stall_ticks [23]       eppm.stall_ticks: 0 disables the stall
// The configuration ports are the register file's stored words (wires); the
// strobes last one call.
//
// Outputs, the status wires the register file reads (ports::eppm::Status):
//   count [s20], latched [s20]                 eppm.count, eppm.latched
//   speed_value [s24], speed_mode [1] (1 pulse, 0 period), speed_valid [1],
//   speed_stalled [1], speed_bound [1]         eppm.speed
//   pulse_last [s24]                           eppm.pulse_last: edges in the last window
//   period_last_ticks [23], period_last_valid [1], period_last_forward [1]
//                                              eppm.period_last
//   phase_error, carry, borrow, period_overflow [1 each] (sticky), forward [1]
//                                              eppm.status
//   error_count [16]                           eppm.error_count, saturating
// Each is Eppm::status(cfg) of the registers after this call's clock edge.
// status() is combinational in one configuration port, stall_ticks (the
// stall compare and so the speed word): the outputs take this call's
// stall_ticks, as the model's status(cfg) after step(in, cfg) does. That is
// the wire the register file samples in the next clock whenever stall_ticks
// is not rewritten at this edge (it changes only by an SPI write).
//
// Latency: a pin change first applied in call t (held >= N calls, N =
// max(filter_clocks, 1)) reaches the count, the direction and both speed
// meters in the outputs of call t + N + 2 (docs/eppm.md: N + 3 clocks
// counting the sampling clock); a glitch shorter than N calls never reaches
// the decoder. Reset: the `reset` port, and the registers' initial values
// (all 0, the model's reset values).
//
// The widths and encodings are the model's own (rtl/eppm_constants.hpp,
// which the model static_asserts against its register types and the
// register map), so the kernel cannot drift from them; test_hls_eppm_* proves
// every output equal to the model's on every call, and every register equal,
// per type family. No heap, no containers, no floating point, static loop
// bounds.
#pragma once

#include "odoloc/hls/input_conditioner.hpp"
#include "odoloc/hls/types.hpp"
#include "odoloc/rtl/eppm_constants.hpp"

namespace odoloc {
namespace hls {
namespace eppm {

namespace ec = rtl::eppm;

// Loop labels name the loops in the HLS tools' reports; no C++ jumps to them.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-label"
#endif

using Lines = uint<ec::kLines>;  // A in bit 1, B in bit 0
using Filter = uint<ec::kFilterBits>;
using ErrorCount = uint<ec::kErrorCountBits>;
using Count = sint<ec::kCountBits>;
using WindowClocks = uint<ec::kWindowBits>;
using Prescale = uint<ec::kPrescaleBits>;
using Edges = sint<ec::kPulseBits>;
using Ticks = uint<ec::kPeriodBits>;
using ModeField = uint<ec::kModeBits>;
using Step = sint<2>;  // the decoder's count pulse: -1, 0 or +1

constexpr long long kCountMax = (1LL << (ec::kCountBits - 1)) - 1;
constexpr long long kCountMin = -(1LL << (ec::kCountBits - 1));
constexpr long long kErrorCountMax = (1LL << ec::kErrorCountBits) - 1;
constexpr long long kTicksMax = (1LL << ec::kPeriodBits) - 1;

// Every field starts at 0: ap_int's default constructor leaves the value
// undefined, so a port struct without initialisers differs between families.
struct Inputs {
  uint<1> a = 0, b = 0;
  uint<1> latch_clear = 0;
  uint<1> clear_phase_error = 0, clear_carry = 0, clear_borrow = 0, clear_period_overflow = 0;
  uint<1> reset = 0;
  Filter filter_clocks = 0;
  ModeField decode_mode = 0;
  ModeField speed_mode_select = 0;
  uint<1> reverse = 0;
  WindowClocks window_clocks = 0;
  Prescale prescale_divider = 0;
  Ticks to_period_below = 0, to_pulse_at = 0;
  Ticks stall_ticks = 0;
};

struct Outputs {
  Count count = 0, latched = 0;
  Edges speed_value = 0;
  uint<1> speed_mode = 0, speed_valid = 0, speed_stalled = 0, speed_bound = 0;
  Edges pulse_last = 0;
  Ticks period_last_ticks = 0;
  uint<1> period_last_valid = 0, period_last_forward = 0;
  uint<1> phase_error = 0, carry = 0, borrow = 0, period_overflow = 0, forward = 0;
  ErrorCount error_count = 0;
};

// The model's blocks, register for register (rtl::<Block>Regs).
using Conditioner = InputConditioner<ec::kLines, ec::kFilterBits>;  // rtl::InputConditionerRegs<2>
struct Decoder {                                                    // rtl::QuadratureDecoderRegs
  Lines prev = 0;
  uint<1> direction = 0, phase_error = 0;
  ErrorCount error_count = 0;
};
struct Counter {  // rtl::PositionCounterRegs
  Count count = 0, latched = 0;
  uint<1> carry = 0, borrow = 0;
};
struct Timebase {  // rtl::SpeedTimebaseRegs
  WindowClocks window_count = 0;
  Prescale prescale_count = 0;
};
struct PulseMeter {  // rtl::PulseMeterRegs
  Edges acc = 0, last = 0;
  uint<1> mode = 0, sampled = 0;
};
struct PeriodMeter {  // rtl::PeriodMeterRegs
  Ticks count = 0, last = 0;
  uint<1> valid = 0, armed = 0, last_dir = 0, overflow = 0, sampled = 0;
};

struct Registers {
  Conditioner conditioner;
  Decoder decoder;
  Counter counter;
  Timebase timebase;
  PulseMeter pulse;
  PeriodMeter period;
};

// The ports by name, in the golden vectors' column order (testbenches only).
template <class Visit>
void visit_fields(Inputs& s, Visit&& v) {
  v("a", s.a);
  v("b", s.b);
  v("latch_clear", s.latch_clear);
  v("clear_phase_error", s.clear_phase_error);
  v("clear_carry", s.clear_carry);
  v("clear_borrow", s.clear_borrow);
  v("clear_period_overflow", s.clear_period_overflow);
  v("reset", s.reset);
  v("filter_clocks", s.filter_clocks);
  v("decode_mode", s.decode_mode);
  v("speed_mode_select", s.speed_mode_select);
  v("reverse", s.reverse);
  v("window_clocks", s.window_clocks);
  v("prescale_divider", s.prescale_divider);
  v("to_period_below", s.to_period_below);
  v("to_pulse_at", s.to_pulse_at);
  v("stall_ticks", s.stall_ticks);
}
template <class Visit>
void visit_fields(Outputs& s, Visit&& v) {
  v("count", s.count);
  v("latched", s.latched);
  v("speed_value", s.speed_value);
  v("speed_mode", s.speed_mode);
  v("speed_valid", s.speed_valid);
  v("speed_stalled", s.speed_stalled);
  v("speed_bound", s.speed_bound);
  v("pulse_last", s.pulse_last);
  v("period_last_ticks", s.period_last_ticks);
  v("period_last_valid", s.period_last_valid);
  v("period_last_forward", s.period_last_forward);
  v("phase_error", s.phase_error);
  v("carry", s.carry);
  v("borrow", s.borrow);
  v("period_overflow", s.period_overflow);
  v("forward", s.forward);
  v("error_count", s.error_count);
}

// One (previous, current) A/B pair through the decoder.
struct Transition {
  Step step;     // after x4/x2/x1 gating
  bool moved;    // a legal x4 step, either way: updates the direction
  bool forward;  // that step was forward (A leads B)
  bool illegal;  // both lines changed
};

// The wires that cross the blocks in one clock, from the current registers
// only (rtl::Eppm::Wires).
struct Wires {
  Transition decoded;  // prev -> filtered; its step feeds the counter and both meters
  bool window_end;     // timebase -> pulse meter
  bool tick;           // timebase -> period meter
};

// Position in the forward cycle AB = 00 -> 10 -> 11 -> 01: the Gray code
// (B, A^B) read as binary.
inline uint<2> phase_of(Lines ab) {
  const bool a = bit(ab, ec::kLineA);
  const bool b = bit(ab, ec::kLineB);
  const uint<2> high = b ? 1 : 0;  // widened before the shift
  return (high << 1) | ((a != b) ? 1 : 0);
}

// x4 counts every step, x2 the steps of A, x1 only A's edge with B low (in
// both directions, so back and forth over it nets zero).
inline Transition decode(Lines prev, Lines curr, ModeField decode_mode) {
  const uint<2> delta = phase_of(curr) - phase_of(prev);  // mod 4
  Transition t;
  t.forward = delta == 1;
  t.moved = delta == 1 || delta == 3;
  t.illegal = delta == 2;
  const bool a_changed = bit(prev, ec::kLineA) != bit(curr, ec::kLineA);
  bool counts = true;
  if (decode_mode == ec::kDecodeX2)
    counts = a_changed;
  else if (decode_mode == ec::kDecodeX1)
    counts = a_changed && !bit(prev, ec::kLineB) && !bit(curr, ec::kLineB);
  t.step = 0;
  if (counts && t.moved)
    t.step = t.forward ? 1 : -1;
  return t;
}

// A/B as the decoder sees them: exchanged when `reverse`, so a mirrored wheel
// counts forward.
inline Lines pins(const Inputs& in) {
  const Lines a = in.a;  // widened before the shift
  const Lines b = in.b;
  if (in.reverse == 1)
    return (b << ec::kLineA) | a;
  return (a << ec::kLineA) | b;
}

inline bool stalled(const PeriodMeter& p, Ticks stall_ticks) {
  return stall_ticks != 0 && p.count >= stall_ticks;
}

inline Wires wires(const Registers& r, const Inputs& in) {
  const uint<ec::kWindowBits + 1> next_window = r.timebase.window_count + 1;
  Wires w;
  w.decoded = decode(r.decoder.prev, r.conditioner.filtered, in.decode_mode);
  w.window_end = next_window >= in.window_clocks;
  w.tick = r.timebase.prescale_count >= in.prescale_divider;
  return w;
}

// The decoder compares the filtered level with its value one clock earlier.
inline void clock_decoder(Decoder& n, Lines filtered, const Transition& t, const Inputs& in) {
  n.prev = filtered;
  if (t.moved)
    n.direction = t.forward ? 1 : 0;
  if (in.clear_phase_error == 1) {
    n.phase_error = 0;
    n.error_count = 0;
  }
  if (t.illegal) {
    n.phase_error = 1;
    if (n.error_count != kErrorCountMax)
      n.error_count = n.error_count + 1;
  }
}

// The clearing clock's own edge goes into the latched value and the count
// restarts at 0, so no edge is lost or counted twice.
inline void clock_counter(Counter& n, const Counter& r, Step step, const Inputs& in) {
  const Count sum = r.count + step;  // wraps
  if (in.clear_carry == 1)
    n.carry = 0;
  if (in.clear_borrow == 1)
    n.borrow = 0;
  if (step > 0 && r.count == kCountMax)
    n.carry = 1;
  if (step < 0 && r.count == kCountMin)
    n.borrow = 1;
  if (in.latch_clear == 1) {
    n.count = 0;
    n.latched = sum;
  } else {
    n.count = sum;
  }
}

inline void clock_timebase(Timebase& n, const Timebase& r, const Wires& w) {
  if (w.window_end)
    n.window_count = 0;
  else
    n.window_count = r.window_count + 1;
  if (w.tick)
    n.prescale_count = 0;
  else
    n.prescale_count = r.prescale_count + 1;
}

// At a window end: forced modes, or the automatic switch, which keeps the
// current mode inside the hysteresis band [to_period_below, to_pulse_at).
inline uint<1> next_mode(const PulseMeter& r, Edges window_edges, const Inputs& in) {
  if (in.speed_mode_select == ec::kSelectPulse)
    return ec::kModePulse;
  if (in.speed_mode_select == ec::kSelectPeriod)
    return ec::kModePeriod;
  const sint<ec::kPulseBits + 1> wide = window_edges;
  uint<ec::kPulseBits> magnitude = wide;  // exact, including -2^23
  if (wide < 0)
    magnitude = -wide;
  if (r.mode == ec::kModePulse && magnitude < in.to_period_below)
    return ec::kModePeriod;
  if (r.mode == ec::kModePeriod && magnitude >= in.to_pulse_at)
    return ec::kModePulse;
  return r.mode;
}

// An edge in the window's last clock still belongs to the closing window.
inline void clock_pulse(PulseMeter& n, const PulseMeter& r, const Wires& w, const Inputs& in) {
  const Edges acc = r.acc + w.decoded.step;  // wraps; |acc| <= T < 2^23
  if (w.window_end) {
    n.acc = 0;
    n.last = acc;
    n.mode = next_mode(r, acc, in);
    n.sampled = 1;
  } else {
    n.acc = acc;
    n.sampled = 0;
  }
}

// The tick of an edge's own clock starts the next measurement, so no tick is
// lost; the count saturates and sets the sticky overflow.
inline void clock_period(PeriodMeter& n, const PeriodMeter& r, const Wires& w, const Inputs& in) {
  const Step step = w.decoded.step;
  n.sampled = step != 0 ? 1 : 0;
  if (in.clear_period_overflow == 1)
    n.overflow = 0;
  const uint<1> tick = w.tick ? 1 : 0;
  if (step == 0) {
    const uint<ec::kPeriodBits + 1> ticks = r.count + tick;
    if (bit(ticks, ec::kPeriodBits)) {
      n.overflow = 1;
      n.count = kTicksMax;
    } else {
      n.count = ticks;
    }
    return;
  }
  const uint<1> dir = step > 0 ? 1 : 0;
  n.valid =
      (r.armed == 1 && dir == r.last_dir && !stalled(r, in.stall_ticks) && r.count != kTicksMax)
          ? 1
          : 0;
  n.last = r.count;
  n.armed = 1;
  n.last_dir = dir;
  n.count = tick;
}

// The status wires (rtl::Eppm::status): the speed word is the pulse count or
// the period per the mode bit, 0 when stalled. In period mode it reads
// max(last period, ticks since the last edge, 1) with the last edge's sign,
// and `bound` when that is not the last period.
inline void drive(Outputs& out, const Registers& r, const Inputs& in) {
  const PeriodMeter& p = r.period;
  out.count = r.counter.count;
  out.latched = r.counter.latched;
  out.speed_mode = r.pulse.mode;
  const bool stall = stalled(p, in.stall_ticks);
  out.speed_stalled = stall ? 1 : 0;
  out.speed_value = 0;
  out.speed_valid = 0;
  out.speed_bound = 0;
  if (stall) {
    out.speed_valid = 1;
  } else if (r.pulse.mode == ec::kModePulse) {
    out.speed_value = r.pulse.last;
    out.speed_valid = 1;
  } else if (p.valid == 1) {
    Ticks ticks = p.last;
    if (p.count > p.last)
      ticks = p.count;
    if (ticks == 0)
      ticks = 1;
    out.speed_bound = ticks != p.last ? 1 : 0;
    const Edges magnitude = ticks;  // exact: < 2^23
    if (p.last_dir == 1)
      out.speed_value = magnitude;
    else
      out.speed_value = -magnitude;
    out.speed_valid = 1;
  }
  out.pulse_last = r.pulse.last;
  out.period_last_ticks = p.last;
  out.period_last_valid = p.valid;
  out.period_last_forward = p.last_dir;
  out.phase_error = r.decoder.phase_error;
  out.carry = r.counter.carry;
  out.borrow = r.counter.borrow;
  out.period_overflow = p.overflow;
  out.forward = r.decoder.direction;
  out.error_count = r.decoder.error_count;
}

// One fabric clock: the next registers from the current ones and the inputs,
// then the commit (`regs` is the register bank) and the outputs.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  const Registers r = regs;
  Registers n = r;
#pragma HLS array_partition variable = n.conditioner.line complete
  if (in.reset == 1) {
    n = Registers();
  } else {
    const Wires w = wires(r, in);
    condition(n.conditioner, r.conditioner, pins(in), in.filter_clocks);
    clock_decoder(n.decoder, r.conditioner.filtered, w.decoded, in);
    clock_counter(n.counter, r.counter, w.decoded.step, in);
    clock_timebase(n.timebase, r.timebase, w);
    clock_pulse(n.pulse, r.pulse, w, in);
    clock_period(n.period, r.period, w, in);
  }
  regs = n;
  drive(out, n, in);
}

#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

}  // namespace eppm
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/eppm_top.cpp): one call = one clock, the
// registers held in the function's static state.
void odoloc_eppm(const odoloc::hls::eppm::Inputs& in, odoloc::hls::eppm::Outputs& out);
