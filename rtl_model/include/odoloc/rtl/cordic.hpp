// Sequential rotation-mode CORDIC: one micro-rotation per clock, 16 clocks.
//
//   clock k      LOAD=1, not busy: quadrant pre-rotation into x, y, z; BUSY=1,
//                RESULT_READY=0
//   k+1 .. k+16  one micro-rotation each; the last also rounds into SIN/COS
//   after k+16   RESULT_READY=1, BUSY=0 (kLatencyClocks = 16 edges after LOAD)
//
// A LOAD while busy is ignored and sets the sticky LOAD_IGNORED flag; the
// running computation completes undisturbed. RESULT_READY stays high until
// the next accepted LOAD. The logic: logic/cordic.hpp (the one source, also
// the HLS kernel's); formats: docs/cordic.md. Here: what only a simulator
// needs around it (field lists, idle, the fast-forward).
#pragma once

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/cordic_core.hpp"

namespace odoloc::rtl {

ODOLOC_LOGIC_FIELDS(logic::cordic::Regs, state, iteration, busy, ready, load_ignored, result)
using SequentialCordicRegs = logic::cordic::Regs<Family>;

class SequentialCordic : public Registers<SequentialCordicRegs> {
 public:
  static constexpr unsigned kLatencyClocks = cordic::kIterations;
  using In = logic::cordic::In<Family>;

  [[nodiscard]] Regs eval(const In& in) const { return cordic::Logic::next(r_, in); }
  [[nodiscard]] bool idle(const In& in) const {
    return (r_.busy | in.load | in.clear_flags | in.reset).is_zero();
  }

  // Fast-forward (clocked.hpp): with no input (no LOAD, clear or reset) a
  // busy CORDIC only rotates; skip(n), n <= rotations_left(), runs those n
  // clocks in one go, the state kept in locals: the clocks before the last
  // rotation only rotate and count (what next() does with no input), the
  // last one, if among the n, goes through next() for the result.
  [[nodiscard]] std::uint64_t rotations_left() const {
    return r_.busy ? cordic::kIterations - r_.iteration.value() : 0;
  }
  void skip(std::uint64_t n) {
    const std::uint64_t first = r_.iteration.value();
    const bool finishes = first + n == cordic::kIterations;
    const std::uint64_t rotations = finishes ? n - 1 : n;
    cordic::State state = r_.state;  // a local: kept in registers
    for (std::uint64_t k = 0; k < rotations; ++k)
      state = cordic::iterate(state, UInt<4>::truncate(first + k));
    // Only the rotated registers are written (a copy of the whole next
    // state costs more than the rotations).
    r_.state = state;
    r_.iteration = UInt<4>::truncate(first + rotations);
    if (finishes)
      commit(cordic::Logic::next(r_, In{}));
  }
};

}  // namespace odoloc::rtl
