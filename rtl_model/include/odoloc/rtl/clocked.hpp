// The clocked-model conventions every fabric block follows.
//
// A leaf block is one class with
//   - its registers as a `Regs` struct (current state), readable via regs(),
//   - `Next eval(const In&) const`: combinational logic only. It reads the
//     current registers and the input wires `In`, returns the next state and
//     never writes a register,
//   - `bool idle(const In&) const`: a cheap, sufficient condition for
//     eval(in) == regs(). Composites skip idle blocks (activity gating, as in
//     ESSENT); test_eppm_gating proves gated and ungated runs identical,
//   - `void commit(const Next&)`: the clock edge, the only place registers change,
//   - synchronous reset as an input wire, plus reset_now() for testbench set-up,
//   - `template <class V> void trace(V&) const`: names its registers for
//     waveform dumps (see TraceVisitor).
// A composite first computes every wire that crosses its children from the
// current registers, then clocks each child with clock_block(). Because no
// child's eval reads another child's registers directly, commit order does not
// matter and the composite's step is exactly one clock edge. No heap, no
// virtual calls: blocks compose by value.
#pragma once

#include <concepts>
#include <string_view>

#include "odoloc/rtl/bits.hpp"

namespace odoloc::rtl {

// What a block's trace() may call. Scopes nest; signal names are local to the
// innermost scope.
template <class V>
concept TraceVisitor = requires(V v, std::string_view name, UInt<1> u1, UInt<64> u64, SInt<2> s2,
                                SInt<64> s64) {
  v.enter(name);
  v.leave();
  v.signal(name, u1);
  v.signal(name, u64);
  v.signal(name, s2);
  v.signal(name, s64);
};

template <class B>
concept ClockedBlock = requires(B b, const B cb, const typename B::In& in,
                                const typename B::Regs& next) {
  { cb.eval(in) } -> std::same_as<typename B::Regs>;
  { cb.idle(in) } -> std::same_as<bool>;
  b.commit(next);
  b.reset_now();
  { cb.regs() } -> std::same_as<const typename B::Regs&>;
};

// The register half every leaf block shares: its Regs, the clock edge, the
// testbench reset and read access. The block adds In, eval, idle and trace.
template <class R>
class Registers {
 public:
  using Regs = R;
  void commit(const Regs& next) { r_ = next; }
  void reset_now() { r_ = Regs{}; }
  [[nodiscard]] const Regs& regs() const { return r_; }

 protected:
  Regs r_;
};

// Names a child's registers inside a scope of the waveform.
template <class V, class Child>
void trace_scope(V& v, std::string_view name, const Child& child) {
  v.enter(name);
  child.trace(v);
  v.leave();
}

enum class Gating : bool { kOff = false, kOn = true };

// One clock edge of a leaf block.
template <Gating G = Gating::kOn, ClockedBlock B>
inline void clock_block(B& block, const typename B::In& in) {
  if (G == Gating::kOn && block.idle(in))
    return;
  block.commit(block.eval(in));
}

// Fabric clock: every block of the odometry fabric runs on it.
inline constexpr double kFabricClockHz = 50.0e6;
inline constexpr unsigned kFabricClockPeriodNs = 20;

}  // namespace odoloc::rtl
