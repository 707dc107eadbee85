// The sequential rotation-mode CORDIC's logic, written once (docs/cordic.md):
// the cycle model (rtl/cordic.hpp) runs it with the model's types, the HLS
// top function (hls/src/cordic_top.cpp) with the vendor's, and
// `odoloc export-hls` exports this file. Parameters and tables:
// rtl/cordic_constants.hpp.
//
// Formats:
//   angle in:  16-bit unsigned binary angle, 65536 = one turn
//   x, y:      22-bit signed, 20 fractional bits (14 output + 6 guard)
//   z:         21-bit signed, units of 2^-22 turn (16 input + 6 guard bits)
//   sin, cos:  16-bit signed, 14 fractional bits (1.0 = 16384), round to nearest
// The quadrant pre-rotation folds every angle into [-45, +45) degrees, so the
// 45-degree micro-rotation (shift 0) is never needed: the 16 iterations use
// shifts 1..16, which halves the final residual angle (atan 2^-16) compared
// with shifts 0..15 and is what makes faithful rounding possible.
//
// Timing (next()): a LOAD while idle loads, then 16 clocks rotate, the last
// also rounds into the result: RESULT_READY 16 clocks after the LOAD. A LOAD
// while busy is ignored and sets the sticky load_ignored.
// C++14, no heap, no containers, static loop bounds (int_family.hpp).
#pragma once

#include "odoloc/logic/int_family.hpp"
#include "odoloc/rtl/cordic_constants.hpp"

namespace odoloc {
namespace logic {
namespace cordic {

namespace constants = rtl::cordic;

template <class F>
struct State {
  sint<F, constants::kXyFractionBits + 2> x{0}, y{0};  // sign, one integer bit
  sint<F, constants::kZUnitsBits - 1> z{0};            // |z| <= 1/8 turn + atan(2^-1) < 2^20 units
  uint<F, 2> quadrant{0};  // multiples of 90 degrees taken out by the pre-rotation
};

template <class F>
struct SinCos {
  sint<F, constants::kOutputFractionBits + 2> sin{0}, cos{0};
};

template <class F>
struct Regs {
  State<F> state;
  uint<F, 4> iteration{0};  // index of the next micro-rotation
  uint<F, 1> busy{0};
  uint<F, 1> ready{0};         // RESULT_READY
  uint<F, 1> load_ignored{0};  // sticky: LOAD arrived while busy
  SinCos<F> result;
};

template <class F>
struct In {
  uint<F, 1> load{0};
  uint<F, constants::kAngleBits> angle{0};
  uint<F, 1> clear_flags{0};  // clears load_ignored
  uint<F, 1> reset{0};        // synchronous
};

// The kernel's output ports: registers after the clock's edge.
template <class F>
struct Out {
  uint<F, 1> busy{0}, ready{0}, load_ignored{0};
  sint<F, constants::kOutputFractionBits + 2> sin{0}, cos{0};
};

// The ports by name, in the golden vectors' column order.
template <class F, class Visit>
void visit_fields(In<F>& s, Visit&& v) {
  v("load", s.load);
  v("angle", s.angle);
  v("clear_flags", s.clear_flags);
  v("reset", s.reset);
}
template <class F, class Visit>
void visit_fields(Out<F>& s, Visit&& v) {
  v("busy", s.busy);
  v("ready", s.ready);
  v("load_ignored", s.load_ignored);
  v("sin", s.sin);
  v("cos", s.cos);
}

template <class F>
struct Cordic {
  using Angle = uint<F, constants::kAngleBits>;
  using Xy = sint<F, constants::kXyFractionBits + 2>;
  using Z = sint<F, constants::kZUnitsBits - 1>;
  using Output = sint<F, constants::kOutputFractionBits + 2>;
  using Iteration = uint<F, 4>;

  // Quadrant pre-rotation: angle = quadrant * 90 deg + residual, residual in [-45, 45).
  static State<F> load(Angle angle) {
    using Residual = sint<F, constants::kAngleBits>;
    const Angle shifted = wrap<Angle>(angle + uint<F, constants::kAngleBits - 2>(kEighthTurn));
    const Residual low = wrap<Residual>(bits<constants::kAngleBits - 3, 0>(shifted));
    const Residual residual = wrap<Residual>(low - sint<F, constants::kAngleBits - 1>(kEighthTurn));
    State<F> s;
    s.x = Xy(constants::kX0Units);
    s.y = Xy(0);
    s.z = wrap<Z>(shl<constants::kAngleGuardBits>(residual));
    s.quadrant = bits<constants::kAngleBits - 1, constants::kAngleBits - 2>(shifted);
    return s;
  }

  // Micro-rotation k (shift kFirstShift + k), towards z = 0. |x|, |y| stay
  // below 1 + 2^-19 and |z| below 2^19 units: no wrap happens.
  static State<F> iterate(const State<F>& s, Iteration k) {
    const uint<F, 5> shift = wrap<uint<F, 5>>(k + uint<F, 1>(constants::kFirstShift));
    const Xy dx = shr_by(s.y, shift);
    const Xy dy = shr_by(s.x, shift);
    const Z angle = wrap<Z>(constants::kAtan.units[to_s64(k)]);
    // Built whole (not a copy patched field by field), so the state stays in
    // registers across the fast-forward's loop of rotations.
    if (s.z < Z(0))
      return State<F>{wrap<Xy>(s.x + dx), wrap<Xy>(s.y - dy), wrap<Z>(s.z + angle), s.quadrant};
    return State<F>{wrap<Xy>(s.x - dx), wrap<Xy>(s.y + dy), wrap<Z>(s.z - angle), s.quadrant};
  }

  // Round to nearest (half up) into 14 fractional bits, then undo the pre-rotation.
  static SinCos<F> finish(const State<F>& s) {
    using Sum = sint<F, constants::kXyFractionBits + 3>;
    const sint<F, constants::kGuardBits + 1> half(1 << (constants::kGuardBits - 1));
    const Output c = wrap<Output>(shr<constants::kGuardBits>(wrap<Sum>(s.x + half)));
    const Output v = wrap<Output>(shr<constants::kGuardBits>(wrap<Sum>(s.y + half)));
    SinCos<F> r;
    switch (to_s64(s.quadrant)) {
      case 1:
        r.sin = c;
        r.cos = wrap<Output>(-v);
        break;
      case 2:
        r.sin = wrap<Output>(-v);
        r.cos = wrap<Output>(-c);
        break;
      case 3:
        r.sin = wrap<Output>(-c);
        r.cos = v;
        break;
      default:
        r.sin = v;
        r.cos = c;
        break;
    }
    return r;
  }

  // One fabric clock: the registers after this clock's edge.
  static Regs<F> next(const Regs<F>& r, const In<F>& in) {
    if (!is_zero(in.reset))
      return Regs<F>();
    Regs<F> n = r;
    if (!is_zero(in.clear_flags))
      n.load_ignored = uint<F, 1>(0);
    if (!is_zero(r.busy)) {
      if (!is_zero(in.load))
        n.load_ignored = uint<F, 1>(1);
      n.state = iterate(r.state, r.iteration);
      n.iteration = wrap<Iteration>(r.iteration + uint<F, 1>(1));
      if (to_s64(r.iteration) == constants::kIterations - 1) {
        n.busy = uint<F, 1>(0);
        n.ready = uint<F, 1>(1);
        n.result = finish(n.state);
      }
    } else if (!is_zero(in.load)) {
      n.state = load(in.angle);
      n.iteration = Iteration(0);
      n.busy = uint<F, 1>(1);
      n.ready = uint<F, 1>(0);
    }
    return n;
  }

  static Out<F> outputs(const Regs<F>& r) {
    Out<F> out;
    out.busy = r.busy;
    out.ready = r.ready;
    out.load_ignored = r.load_ignored;
    out.sin = r.result.sin;
    out.cos = r.result.cos;
    return out;
  }

  // The whole computation, untimed: what the sequential unit produces.
  static SinCos<F> sincos(Angle angle) {
    State<F> s = load(angle);
    for (int k = 0; k < constants::kIterations; ++k)
      s = iterate(s, wrap<Iteration>(k));
    return finish(s);
  }

 private:
  static constexpr int kEighthTurn = 1 << (constants::kAngleBits - 3);
};

}  // namespace cordic
}  // namespace logic
}  // namespace odoloc
