// The Encoder Pulse Processing Module as an HLS kernel: one call = one 50 MHz
// fabric clock of rtl::Eppm (rtl_model/include/odoloc/rtl/eppm.hpp,
// docs/eppm.md), one kernel per wheel encoder, in odoloc::hls integer types
// (types.hpp: ap_int.h, ac_int.h or the project's own). C++14. Inside: the
// input conditioner (2-flop synchroniser and level filter per line,
// logic/input_conditioner.hpp), the quadrature decoder (x4/x2/x1, phase errors),
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
// The logic is the model's own (logic/eppm.hpp, which the cycle model
// rtl::Eppm runs): this file maps the kernel's flat ports onto the register
// map's port structs (odoloc/logic/ports.hpp) and back, nothing else.
// test_hls_eppm_* checks every output and register against the model per
// type family. No heap, no containers, no floating point, static loop bounds.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/logic/eppm.hpp"

namespace odoloc {
namespace hls {
namespace eppm {

namespace ec = rtl::eppm;

using Filter = uint<ec::kFilterBits>;
using ErrorCount = uint<ec::kErrorCountBits>;
using Count = sint<ec::kCountBits>;
using WindowClocks = uint<ec::kWindowBits>;
using Prescale = uint<ec::kPrescaleBits>;
using Edges = sint<ec::kPulseBits>;
using Ticks = uint<ec::kPeriodBits>;
using ModeField = uint<ec::kModeBits>;

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

using Logic = logic::eppm::Eppm<Family>;
using Registers = logic::eppm::Regs<Family>;  // the model's blocks, register for register

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

// The flat ports as the register map's port structs.
inline logic::eppm::In<Family> module_in(const Inputs& in) {
  logic::eppm::In<Family> m;
  m.a = in.a;
  m.b = in.b;
  m.latch_clear = in.latch_clear;
  m.clear.status.phase_error = in.clear_phase_error;
  m.clear.status.carry = in.clear_carry;
  m.clear.status.borrow = in.clear_borrow;
  m.clear.status.period_overflow = in.clear_period_overflow;
  m.reset = in.reset;
  return m;
}
inline logic::ports::eppm::Config<Family> config(const Inputs& in) {
  logic::ports::eppm::Config<Family> c;
  c.cfg.filter_clocks = in.filter_clocks;
  c.cfg.decode_mode = in.decode_mode;
  c.cfg.speed_mode_select = in.speed_mode_select;
  c.cfg.reverse = in.reverse;
  c.window.clocks = in.window_clocks;
  c.prescale.divider = in.prescale_divider;
  c.to_period_below.edges = in.to_period_below;
  c.to_pulse_at.edges = in.to_pulse_at;
  c.stall_ticks.ticks = in.stall_ticks;
  return c;
}
inline void drive(Outputs& out, const logic::ports::eppm::Status<Family>& s) {
  out.count = s.count.value;
  out.latched = s.latched.value;
  out.speed_value = s.speed.value;
  out.speed_mode = s.speed.mode;
  out.speed_valid = s.speed.valid;
  out.speed_stalled = s.speed.stalled;
  out.speed_bound = s.speed.bound;
  out.pulse_last = s.pulse_last.edges;
  out.period_last_ticks = s.period_last.ticks;
  out.period_last_valid = s.period_last.valid;
  out.period_last_forward = s.period_last.forward;
  out.phase_error = s.status.phase_error;
  out.carry = s.status.carry;
  out.borrow = s.status.borrow;
  out.period_overflow = s.status.period_overflow;
  out.forward = s.status.forward;
  out.error_count = s.error_count.count;
}

// One fabric clock: the registers after this clock's edge (`regs` is the
// register bank), then the status of those registers with this call's
// configuration.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  const logic::ports::eppm::Config<Family> cfg = config(in);
  regs = Logic::next(regs, module_in(in), cfg);
  drive(out, Logic::status<logic::ports::eppm::Status<Family> >(regs, cfg));
}

}  // namespace eppm
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/eppm_top.cpp): one call = one clock, the
// registers held in the function's static state.
void odoloc_eppm(const odoloc::hls::eppm::Inputs& in, odoloc::hls::eppm::Outputs& out);
