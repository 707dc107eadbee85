// The project's own fixed-width integers with the ap_int/ac_int semantics the
// HLS kernels rely on, for builds without a vendor header (types.hpp picks).
//
//   own::uint<W>  unsigned, 1..63 bits     own::sint<W>  two's complement, 2..63 bits
//
// - Construction and assignment from any integer or fixed-width integer wrap
//   to W bits (two's complement for sint), as ap_uint/ap_int and ac_int do.
// - In arithmetic a value reads as a 64-bit signed integer (every W <= 63
//   fits), so +, -, *, /, %, &, |, ^, ~, <<, >> and comparisons act on the
//   values, as the vendors' widened results do, provided every intermediate
//   fits in 63 bits: the kernels keep to that (docs/hls.md), and
//   test_hls_types compares the three families on the same expressions.
// Header-only, constexpr, no containers, no heap; C++14, as the HLS tools'
// front ends accept (docs/hls.md).
#pragma once

#include <cstdint>
#include <type_traits>

namespace odoloc {
namespace hls {
namespace own {

template <int W, bool Signed>
class fixed_int {
  static_assert(W >= (Signed ? 2 : 1) && W <= 63, "own::uint is 1..63 bits, own::sint 2..63");

 public:
  static constexpr int width = W;
  static constexpr bool is_signed = Signed;

  constexpr fixed_int() = default;
  template <typename T, typename = typename std::enable_if<std::is_integral<T>::value>::type>
  constexpr fixed_int(T value)  // NOLINT(google-explicit-constructor): wraps, as ap_int does
      : value_(wrap(static_cast<std::int64_t>(value))) {}
  template <int W2, bool S2>
  constexpr fixed_int(fixed_int<W2, S2> other)  // NOLINT(google-explicit-constructor)
      : value_(wrap(other)) {}

  // The value as a 64-bit signed integer: what arithmetic sees.
  constexpr operator std::int64_t() const { return value_; }  // NOLINT(google-explicit-constructor)

  template <typename T>
  constexpr fixed_int& operator+=(T other) {
    return *this = value_ + static_cast<std::int64_t>(other);
  }
  template <typename T>
  constexpr fixed_int& operator-=(T other) {
    return *this = value_ - static_cast<std::int64_t>(other);
  }
  constexpr fixed_int& operator++() { return *this += 1; }
  constexpr fixed_int& operator--() { return *this -= 1; }

 private:
  static constexpr std::int64_t wrap(std::int64_t v) {
    const std::uint64_t bits = static_cast<std::uint64_t>(v) & ((std::uint64_t{1} << W) - 1);
    const std::uint64_t sign = Signed ? std::uint64_t{1} << (W - 1) : 0;
    return static_cast<std::int64_t>(bits ^ sign) - static_cast<std::int64_t>(sign);
  }
  std::int64_t value_ = 0;
};

template <int W>
using uint = fixed_int<W, false>;
template <int W>
using sint = fixed_int<W, true>;

// Bits Hi..Lo of x as an unsigned value (ap_int's x.range(Hi, Lo), ac_int's
// x.slc<Hi-Lo+1>(Lo)).
template <int Hi, int Lo, int W, bool S>
constexpr uint<Hi - Lo + 1> bits(fixed_int<W, S> x) {
  static_assert(Lo >= 0 && Hi >= Lo && Hi < W, "bits<Hi, Lo> outside the word");
  return uint<Hi - Lo + 1>(
      static_cast<std::int64_t>(static_cast<std::uint64_t>(static_cast<std::int64_t>(x)) >> Lo));
}

// Bit i of x.
template <int W, bool S>
constexpr bool bit(fixed_int<W, S> x, int i) {
  return ((static_cast<std::uint64_t>(static_cast<std::int64_t>(x)) >> i) & 1U) != 0;
}

// The value as a host integer.
template <int W, bool S>
constexpr long long to_s64(fixed_int<W, S> x) {
  return static_cast<std::int64_t>(x);
}

}  // namespace own
}  // namespace hls
}  // namespace odoloc
