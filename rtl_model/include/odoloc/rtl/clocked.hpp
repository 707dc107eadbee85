// The clocked-model conventions every fabric block follows.
//
// A leaf block is one class with
//   - its registers as a `Regs` struct with one field list (ODOLOC_FIELDS,
//     fields.hpp), readable via regs(); trace() is derived from that list,
//   - `Next eval(const In&) const`: combinational logic only. It reads the
//     current registers and the input wires `In` (values, never references),
//     returns the next state and never writes a register,
//   - `bool idle(const In&) const`: a cheap, sufficient condition for
//     eval(in) == regs(). Composites skip idle blocks (activity gating, as in
//     ESSENT); the gating tests prove gated and ungated runs identical,
//   - `void commit(const Next&)`: the clock edge, the only place registers change,
//   - synchronous reset as an input wire, plus reset_now() for testbench set-up.
// A composite is two-phase by construction: step() first computes, from the
// current registers only, every wire that crosses its children (each child's
// In, filled by value), and only then clocks the children. Nothing is read
// after the first child is clocked, so the order the children are clocked in
// cannot matter: step() takes that order as a parameter, and the commit-order
// tests clock every composite's children in a random permutation every clock
// against declaration order. A composite's idle(in) is the conjunction of its
// children's, so gating works the same way at every level. No heap, no
// virtual calls: blocks compose by value.
#pragma once

#include <algorithm>
#include <concepts>
#include <cstdint>
#include <string_view>

#include "odoloc/regs.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/fields.hpp"

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
// testbench reset, read access and the waveform of every register. The block
// adds In, eval and idle.
template <HasFields R>
class Registers {
 public:
  using Regs = R;
  void commit(const Regs& next) { r_ = next; }
  void reset_now() { r_ = Regs{}; }
  [[nodiscard]] const Regs& regs() const { return r_; }
  template <class V>
  void trace(V& v) const {
    trace_fields(v, r_);
  }

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

// A register-map enumerator's value, to compare with a field's bits.
template <class E>
constexpr auto encoding(E e) {
  return static_cast<std::uint32_t>(e);
}

enum class Gating : bool { kOff = false, kOn = true };

// One clock edge of a leaf block. Flattened: eval's next state goes straight
// into the registers instead of through a returned struct in memory.
template <Gating G = Gating::kOn, ClockedBlock B>
[[gnu::flatten]] inline void clock_block(B& block, const typename B::In& in) {
  if (G == Gating::kOn && block.idle(in))
    return;
  block.commit(block.eval(in));
}

// ---- fast-forward ------------------------------------------------------------
// Between input events most of the fabric only counts. A block that can jump
// ahead offers
//   - `std::uint64_t clocks_until_event(const In&[, cfg]) const`: how many of
//     the next clocks, with `in` held, it can skip (0: step this clock);
//     kNoEvent when nothing happens on its own,
//   - `void skip(std::uint64_t n, const In&[, cfg])`: exactly n steps with
//     `in` held, for n <= clocks_until_event(in); bit-identical to stepping
//     (testbenches/rtl/test_fast_forward.cpp, with a mutant of every rule),
//   - `advance(n, in[, cfg])`: fast_forward() below, any n.
inline constexpr std::uint64_t kNoEvent = ~std::uint64_t{0};

// A counter that restarts after its terminal clock: in a clock with
// count >= last it fires and restarts at 0, otherwise it counts up (the
// EPPM's window timer and reference prescaler, the TOF timestamp prescaler,
// the odometry period counter; last = its period - 1).
struct RestartingCount {
  std::uint64_t fires;  // terminal clocks among the n
  std::uint64_t count;  // the count after them
};
// Clocks before the next terminal clock (0: this clock fires).
constexpr std::uint64_t clocks_to_fire(std::uint64_t count, std::uint64_t last) {
  return count >= last ? 0 : last - count;
}
// The count after n clocks: the first fire at clock clocks_to_fire, then one
// every last + 1 clocks.
constexpr RestartingCount run_restarting(std::uint64_t count, std::uint64_t last, std::uint64_t n) {
  const std::uint64_t first = clocks_to_fire(count, last);
  if (n <= first)
    return {0, count + n};
  const std::uint64_t after = n - 1 - first;  // clocks after the first fire
  return {1 + after / (last + 1), after % (last + 1)};
}
// The clock (from now) of the k-th fire, k >= 1.
constexpr std::uint64_t clock_of_fire(std::uint64_t count, std::uint64_t last, std::uint64_t k) {
  return clocks_to_fire(count, last) + (k - 1) * (last + 1);
}

// The contract as a concept: what fast_forward() and the board's drivers
// call on a block, a composite and the chip alike.
template <class B, class... Config>
concept FastForwardBlock = requires(B b, const B cb, const typename B::In& in, std::uint64_t n,
                                    const Config&... config) {
  { cb.clocks_until_event(in, config...) } -> std::same_as<std::uint64_t>;
  b.skip(n, in, config...);
  b.step(in, config...);
};

// The horizon of a composite whose children interact: the nearest of their
// horizons (each a callable, asked in order until one is 0). Children that
// share no signal while the others skip advance on their own through their
// events instead (fast_forward), and bound nothing.
template <class... Horizon>
[[gnu::always_inline]] inline std::uint64_t nearest_event(const Horizon&... horizon) {
  std::uint64_t nearest = kNoEvent;
  static_cast<void>((((nearest = std::min(nearest, horizon())) != 0) && ...));
  return nearest;
}

// n clocks with `in` held: skipped up to each event, stepped through it.
// Bit-identical to n calls of block.step(in, config...). Returns how many of
// the n were skipped.
template <class Block, class... Config>
std::uint64_t fast_forward(Block& block, std::uint64_t n, const typename Block::In& in,
                           const Config&... config) {
  static_assert(FastForwardBlock<Block, Config...>, "fast_forward needs the fast-forward contract");
  std::uint64_t skipped = 0;
  while (n != 0) {
    // One clock: a step costs no more than a skip and needs no horizon.
    const std::uint64_t quiet = n == 1 ? 0 : block.clocks_until_event(in, config...);
    if (quiet == 0) {
      block.step(in, config...);
      --n;
    } else {
      const std::uint64_t clocks = quiet < n ? quiet : n;
      block.skip(clocks, in, config...);
      n -= clocks;
      skipped += clocks;
    }
  }
  return skipped;
}

// The order a composite clocks its children in, given one callable per
// child. Production code uses declaration order; the commit-order tests pass
// an order that permutes the calls.
struct DeclarationOrder {
  template <class... Clock>
  void operator()(Clock&&... clock) const {
    (clock(), ...);
  }
};

// Fabric clock: every block of the fabric runs on it (regmap/odoloc.yaml).
inline constexpr double kFabricClockHz = regs::kFabricClockHz;
inline constexpr unsigned kFabricClockPeriodNs = regs::kFabricClockPeriodNs;

}  // namespace odoloc::rtl
