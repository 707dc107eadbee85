// The CORDIC's parameters and constants, generated at compile time from one
// place: the arctangent table, the gain and x0. Plain C++14 with integer
// results only (no UInt), because the HLS kernel (hls/cordic_kernel.hpp)
// includes this header too and HLS front ends accept C++14; cordic_core.hpp
// wraps the results in the model's types. The long double arithmetic runs in
// the compiler only: every constant below is folded to an integer.
#pragma once

#include <cstdint>

namespace odoloc {
namespace rtl {
namespace cordic {

constexpr int kIterations = 16;
constexpr int kFirstShift = 1;
constexpr int kAngleBits = 16;
constexpr int kAngleGuardBits = 6;
constexpr int kOutputFractionBits = 14;
constexpr int kGuardBits = 6;
constexpr int kXyFractionBits = kOutputFractionBits + kGuardBits;
constexpr int kZUnitsBits = kAngleBits + kAngleGuardBits;  // 2^22 units per turn

// atan(x) by its Taylor series; |x| <= 1/2 converges to long double
// precision in under 40 terms.
constexpr long double atan_series(long double x) {
  const long double x2 = x * x;
  long double term = x, sum = 0.0L;
  for (int n = 0; n < 40; ++n) {
    sum += ((n % 2 == 0) ? term : -term) / (2 * n + 1);
    term *= x2;
  }
  return sum;
}

// Machin's formula, pi = 16 atan(1/5) - 4 atan(1/239): pi from the same series.
constexpr long double kPi = 16 * atan_series(1.0L / 5) - 4 * atan_series(1.0L / 239);

// atan(2^-i).
constexpr long double atan_pow2(int i) {
  if (i == 0)
    return kPi / 4;
  long double x = 1.0L;
  for (int k = 0; k < i; ++k)
    x /= 2;
  return atan_series(x);
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
constexpr long double kPaperInverseGain = 1.0L / gain(0, kIterations);
// Ours: shifts 1..16; equals sqrt(2) * kPaperInverseGain up to the last term.
constexpr long double kInverseGain = 1.0L / gain(kFirstShift, kIterations);
// x0 = 1/A quantised to the x/y format (round to nearest), in units of 2^-20.
constexpr std::int64_t kX0Units = round_to_int(kInverseGain * (1LL << kXyFractionBits));

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
constexpr AtanTable kAtan = make_atan_table();

}  // namespace cordic
}  // namespace rtl
}  // namespace odoloc
