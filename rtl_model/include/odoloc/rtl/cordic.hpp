// Sequential rotation-mode CORDIC: one micro-rotation per clock, 16 clocks.
//
//   clock k      LOAD=1, not busy: quadrant pre-rotation into x, y, z; BUSY=1,
//                RESULT_READY=0
//   k+1 .. k+16  one micro-rotation each; the last also rounds into SIN/COS
//   after k+16   RESULT_READY=1, BUSY=0 (kLatencyClocks = 16 edges after LOAD)
//
// A LOAD while busy is ignored and sets the sticky LOAD_IGNORED flag; the
// running computation completes undisturbed. RESULT_READY stays high until
// the next accepted LOAD. Arithmetic: cordic_core.hpp; formats: docs/cordic.md.
#pragma once

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/cordic_core.hpp"

namespace odoloc::rtl {

namespace cordic {
// Field lists of the shared core's structs (fields.hpp), kept out of the
// HLS-shared header.
template <class F>
constexpr void for_each_field(const State& s, F&& f) {
  [[maybe_unused]] const auto& [s_x, s_y, s_z, s_quadrant] = s;  // every member, in order
  f("x", s.x);
  f("y", s.y);
  f("z", s.z);
  f("quadrant", s.quadrant);
}
template <class F>
constexpr void for_each_field(const SinCos& s, F&& f) {
  [[maybe_unused]] const auto& [s_sin, s_cos] = s;
  f("sin", s.sin);
  f("cos", s.cos);
}
}  // namespace cordic

struct SequentialCordicRegs {
  cordic::State state;
  UInt<4> iteration;  // index of the next micro-rotation
  UInt<1> busy;
  UInt<1> ready;         // RESULT_READY
  UInt<1> load_ignored;  // sticky: LOAD arrived while busy
  cordic::SinCos result;
  bool operator==(const SequentialCordicRegs&) const = default;
  ODOLOC_FIELDS(state, iteration, busy, ready, load_ignored, result)
};

class SequentialCordic : public Registers<SequentialCordicRegs> {
 public:
  static constexpr unsigned kLatencyClocks = cordic::kIterations;
  struct In {
    UInt<1> load;
    cordic::Angle angle;
    UInt<1> clear_flags;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    if (in.clear_flags)
      n.load_ignored = UInt<1>{};
    if (r_.busy) {
      if (in.load)
        n.load_ignored = UInt<1>{1};
      n.state = cordic::iterate(r_.state, r_.iteration);
      n.iteration = (r_.iteration + UInt<1>{1}).wrap<4>();
      if (r_.iteration.value() == cordic::kIterations - 1) {
        n.busy = UInt<1>{};
        n.ready = UInt<1>{1};
        n.result = cordic::finish(n.state);
      }
    } else if (in.load) {
      n.state = cordic::load(in.angle);
      n.iteration = UInt<4>{};
      n.busy = UInt<1>{1};
      n.ready = UInt<1>{};
    }
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return (r_.busy | in.load | in.clear_flags | in.reset).is_zero();
  }

  // Fast-forward (clocked.hpp): with no input (no LOAD, clear or reset) a
  // busy CORDIC only rotates; skip(n), n <= rotations_left(), runs n
  // micro-rotations in one go, the state kept in locals (eval per clock
  // goes through the registers in memory every time).
  [[nodiscard]] std::uint64_t rotations_left() const {
    return r_.busy ? cordic::kIterations - r_.iteration.value() : 0;
  }
  void skip(std::uint64_t n) {
    Regs next = r_;
    std::uint64_t k = r_.iteration.value();
    for (const std::uint64_t end = k + n; k < end; ++k)
      next.state = cordic::iterate(next.state, UInt<4>::truncate(k));
    next.iteration = UInt<4>::truncate(k);  // wraps to 0 after the last
    if (k == cordic::kIterations) {
      next.busy = UInt<1>{};
      next.ready = UInt<1>{1};
      next.result = cordic::finish(next.state);
    }
    commit(next);
  }
};

}  // namespace odoloc::rtl
