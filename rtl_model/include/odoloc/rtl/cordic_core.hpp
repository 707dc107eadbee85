// Rotation-mode CORDIC arithmetic for sin/cos: the per-stage datapath in the
// model's types, over the parameters and tables of cordic_constants.hpp.
// Header-only, constexpr, no containers, no heap. The sequential RTL model
// (cordic.hpp) runs these functions; the HLS kernel shares the constants and
// is proven bit-identical to them (test_hls_cordic_*).
//
// Formats (docs/cordic.md):
//   angle in:  UInt<16> binary angle, 65536 = one turn
//   x, y:      SInt<22>, 20 fractional bits (14 output + 6 guard)
//   z:         SInt<21>, units of 2^-22 turn (16 input + 6 guard bits)
//   sin, cos:  SInt<16>, 14 fractional bits (1.0 = 16384), round to nearest
//
// The quadrant pre-rotation folds every angle into [-45, +45) degrees, so the
// 45-degree micro-rotation (shift 0) is never needed: the 16 iterations use
// shifts 1..16, which halves the final residual angle (atan 2^-16) compared
// with shifts 0..15 and is what makes faithful rounding possible.
#pragma once

#include <cstdint>

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/cordic_constants.hpp"

namespace odoloc::rtl::cordic {

using Angle = UInt<kAngleBits>;
using Xy = SInt<kXyFractionBits + 2>;  // |x|, |y| <= 1 + rounding: sign, one integer bit
using Z = SInt<kZUnitsBits - 1>;       // |z| <= 1/8 turn + atan(2^-1) < 2^20 units
using Output = SInt<kOutputFractionBits + 2>;

inline constexpr Xy kX0 = Xy::truncate(kX0Units);

// ---- the datapath -------------------------------------------------------
struct State {
  Xy x, y;
  Z z;
  UInt<2> quadrant;  // multiples of 90 degrees taken out by the pre-rotation
  bool operator==(const State&) const = default;
};

struct SinCos {
  Output sin, cos;
  bool operator==(const SinCos&) const = default;
};

// Quadrant pre-rotation: angle = quadrant * 90 deg + residual, residual in [-45, 45).
constexpr State load(Angle angle) {
  constexpr UInt<16> kEighthTurn{1U << (kAngleBits - 3)};
  const UInt<16> shifted = (angle + kEighthTurn).wrap<kAngleBits>();
  const UInt<2> quadrant = shifted.bits<kAngleBits - 1, kAngleBits - 2>();
  const SInt<16> residual =
      (shifted.bits<kAngleBits - 3, 0>().to_sint() - kEighthTurn.to_sint()).wrap<16>();
  return {kX0, Xy{}, residual.shl<kAngleGuardBits>().wrap<Z::width>(), quadrant};
}

// Micro-rotation k (shift kFirstShift + k), towards z = 0.
constexpr State iterate(const State& s, UInt<4> k) {
  const UInt<5> shift = (k + UInt<1>{kFirstShift}).wrap<5>();
  const Xy dx = s.y.dshr(shift);
  const Xy dy = s.x.dshr(shift);
  const Z angle = Z::truncate(kAtan.units[k.value()]);
  // |x|, |y| stay below 1 + 2^-19 and |z| below 2^19 units: no wrap happens.
  if (s.z.is_negative()) {
    return {(s.x + dx).wrap<Xy::width>(), (s.y - dy).wrap<Xy::width>(),
            (s.z + angle).wrap<Z::width>(), s.quadrant};
  }
  return {(s.x - dx).wrap<Xy::width>(), (s.y + dy).wrap<Xy::width>(),
          (s.z - angle).wrap<Z::width>(), s.quadrant};
}

// Round to nearest (half up) into 14 fractional bits, then undo the pre-rotation.
constexpr SinCos finish(const State& s) {
  const Output c = round_shr<kGuardBits>(s.x).wrap<Output::width>();
  const Output v = round_shr<kGuardBits>(s.y).wrap<Output::width>();
  switch (s.quadrant.value()) {
    case 1:
      return {c, (-v).wrap<Output::width>()};
    case 2:
      return {(-v).wrap<Output::width>(), (-c).wrap<Output::width>()};
    case 3:
      return {(-c).wrap<Output::width>(), v};
    default:
      return {v, c};
  }
}

// The whole computation, untimed: what the sequential unit produces.
constexpr SinCos sincos(Angle angle) {
  State s = load(angle);
  for (int k = 0; k < kIterations; ++k)
    s = iterate(s, UInt<4>::truncate(static_cast<std::uint64_t>(k)));
  return finish(s);
}

}  // namespace odoloc::rtl::cordic
