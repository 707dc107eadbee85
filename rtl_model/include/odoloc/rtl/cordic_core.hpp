// Rotation-mode CORDIC arithmetic for sin/cos: parameters, the arctangent
// table, the gain constant and the per-stage datapath, all in one place.
// Header-only, constexpr, no containers, no heap: the sequential RTL model
// (cordic.hpp) and the HLS sources use exactly these functions.
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
#include <numbers>

#include "odoloc/rtl/bits.hpp"

namespace odoloc::rtl::cordic {

inline constexpr int kIterations = 16;
inline constexpr int kFirstShift = 1;
inline constexpr int kAngleBits = 16;
inline constexpr int kAngleGuardBits = 6;
inline constexpr int kOutputFractionBits = 14;
inline constexpr int kGuardBits = 6;
inline constexpr int kXyFractionBits = kOutputFractionBits + kGuardBits;
inline constexpr int kZUnitsBits = kAngleBits + kAngleGuardBits;  // 2^22 units per turn

using Angle = UInt<kAngleBits>;
using Xy = SInt<kXyFractionBits + 2>;  // |x|, |y| <= 1 + rounding: sign, one integer bit
using Z = SInt<kZUnitsBits - 1>;       // |z| <= 1/8 turn + atan(2^-1) < 2^20 units
using Output = SInt<kOutputFractionBits + 2>;

// ---- compile-time math (long double), so tables are generated, not typed ----
constexpr long double kPi = std::numbers::pi_v<long double>;

// atan(2^-i) by its Taylor series; 2^-i <= 1/2 converges to long double
// precision in under 40 terms.
constexpr long double atan_pow2(int i) {
  if (i == 0)
    return kPi / 4;
  long double x = 1.0L;
  for (int k = 0; k < i; ++k)
    x /= 2;
  const long double x2 = x * x;
  long double term = x, sum = 0.0L;
  for (int n = 0; n < 40; ++n) {
    sum += ((n % 2 == 0) ? term : -term) / (2 * n + 1);
    term *= x2;
  }
  return sum;
}

constexpr long double sqrt_newton(long double v) {
  long double y = v > 1 ? v : 1.0L;
  for (int k = 0; k < 60; ++k)
    y = (y + v / y) / 2;
  return y;
}

// Gain of micro-rotations with shifts first..first+count-1: prod sqrt(1 + 2^-2i).
constexpr long double gain(int first, int count) {
  long double product = 1.0L;
  for (int i = first; i < first + count; ++i) {
    long double t = 1.0L;
    for (int k = 0; k < 2 * i; ++k)
      t /= 2;
    product *= 1.0L + t;
  }
  return sqrt_newton(product);
}

constexpr std::int64_t round_to_int(long double v) {
  return static_cast<std::int64_t>(v < 0 ? v - 0.5L : v + 0.5L);
}

// The paper's constant: 1/A16 for shifts 0..15.
inline constexpr long double kPaperInverseGain = 1.0L / gain(0, kIterations);
// Ours: shifts 1..16; equals sqrt(2) * kPaperInverseGain up to the last term.
inline constexpr long double kInverseGain = 1.0L / gain(kFirstShift, kIterations);
// x0 = 1/A quantised to the x/y format (round to nearest).
inline constexpr Xy kX0 = Xy::truncate(round_to_int(kInverseGain * (1LL << kXyFractionBits)));

struct AtanTable {
  std::int32_t units[kIterations];  // atan(2^-(kFirstShift + k)) in 2^-22 turns
};
constexpr AtanTable make_atan_table() {
  AtanTable t{};
  for (int k = 0; k < kIterations; ++k) {
    const long double turns = atan_pow2(kFirstShift + k) / (2 * kPi);
    t.units[k] = static_cast<std::int32_t>(round_to_int(turns * (1LL << kZUnitsBits)));
  }
  return t;
}
inline constexpr AtanTable kAtan = make_atan_table();

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
