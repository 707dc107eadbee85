// Fixed-width hardware integers: the width is part of the type.
//
//   UInt<W>  unsigned, 1..64 bits        SInt<W>  two's complement, 2..64 bits
//
// Rules (after firrtl-sig's uint.h):
// - Arithmetic grows the width so it never overflows: a+b is max(Wa,Wb)+1 bits,
//   a*b is Wa+Wb bits. UInt - UInt wraps modulo 2^(max+1) (firrtl "sub"); for an
//   exact signed difference convert first with to_sint().
// - Narrowing never happens silently: it does not compile. Say what you want:
//   wrap<N>() keeps the low N bits (two's complement wrap), sat<N>() clamps.
// - Widening to a wider type of the same signedness is implicit.
// - Construction from a plain integer is explicit and range-checked (a compile
//   error in constant evaluation, std::out_of_range at run time); use
//   UInt<W>::truncate() where wrapping a host integer is intended.
// Storage is the narrowest machine word that holds W bits, so register structs
// stay small and the simulator's clock loop stays in cache.
#pragma once

#include <bit>
#include <concepts>
#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace odoloc::rtl {

namespace detail {
template <int W>
using storage_t = std::conditional_t<
    (W <= 8), std::uint8_t,
    std::conditional_t<(W <= 16), std::uint16_t,
                       std::conditional_t<(W <= 32), std::uint32_t, std::uint64_t>>>;
template <int W>
using signed_storage_t = std::make_signed_t<storage_t<W>>;

constexpr std::uint64_t low_mask(int width) {
  return width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
}
constexpr std::int64_t sign_extend(std::uint64_t bits, int width) {
  const int shift = 64 - width;
  return static_cast<std::int64_t>(bits << shift) >> shift;
}
constexpr int max_width(int a, int b) {
  return a > b ? a : b;
}
}  // namespace detail

template <int W>
class SInt;

template <int W>
class UInt {
  static_assert(W >= 1 && W <= 64, "UInt width must be 1..64");

 public:
  static constexpr int width = W;
  static constexpr std::uint64_t mask = detail::low_mask(W);
  static constexpr std::uint64_t max_value = mask;

  constexpr UInt() = default;

  template <std::integral T>
  constexpr explicit UInt(T value) : bits_(static_cast<Storage>(value)) {
    if (std::cmp_less(+value, 0) || std::cmp_greater(+value, mask)) {  // +: bool, char promote
      throw std::out_of_range("UInt: value does not fit the width");
    }
  }

  template <int V>
  requires(V <= W) constexpr UInt(UInt<V> narrower)
      : bits_(static_cast<Storage>(narrower.value())) {}  // NOLINT

  // Keeps the low W bits of a host integer: the explicit way to wrap.
  static constexpr UInt truncate(std::uint64_t value) {
    UInt r;
    r.bits_ = static_cast<Storage>(value & mask);
    return r;
  }
  // A value that fits W bits by construction (the growing operators' exact
  // results): no mask to compute.
  static constexpr UInt exact(std::uint64_t value) {
    UInt r;
    r.bits_ = static_cast<Storage>(value);
    return r;
  }

  // The range promise lets the optimiser drop masks that cannot change a value.
  [[nodiscard]] constexpr std::uint64_t value() const {
    if (bits_ > mask)
      __builtin_unreachable();
    return bits_;
  }
  [[nodiscard]] constexpr bool is_zero() const { return bits_ == 0; }
  explicit constexpr operator bool() const { return bits_ != 0; }

  template <int N>
  [[nodiscard]] constexpr UInt<N> wrap() const {
    return UInt<N>::truncate(bits_);
  }
  template <int N>
  [[nodiscard]] constexpr UInt<N> sat() const {
    return UInt<N>::truncate(bits_ > UInt<N>::mask ? UInt<N>::mask : bits_);
  }
  // Reinterprets the same bits as two's complement.
  [[nodiscard]] constexpr SInt<W> as_sint() const;
  // Zero-extends by one bit into a signed value: exact.
  [[nodiscard]] constexpr SInt<W + 1> to_sint() const;

  template <int I>
  [[nodiscard]] constexpr UInt<1> bit() const {
    static_assert(I >= 0 && I < W);
    return UInt<1>::truncate(bits_ >> I);
  }
  template <int Hi, int Lo>
  [[nodiscard]] constexpr UInt<Hi - Lo + 1> bits() const {
    static_assert(Lo >= 0 && Hi >= Lo && Hi < W);
    return UInt<Hi - Lo + 1>::truncate(bits_ >> Lo);
  }
  template <int N>
  [[nodiscard]] constexpr UInt<W + N> shl() const {
    return UInt<W + N>::truncate(std::uint64_t{bits_} << N);
  }
  template <int N>
  [[nodiscard]] constexpr UInt<(W - N > 0 ? W - N : 1)> shr() const {
    return UInt<(W - N > 0 ? W - N : 1)>::exact(N >= 64 ? 0 : std::uint64_t{bits_} >> N);
  }

  // Shift right by a run-time amount (a barrel shifter): same width.
  template <int K>
  [[nodiscard]] constexpr UInt<W> dshr(UInt<K> amount) const {
    return exact(amount.value() >= 64 ? 0 : std::uint64_t{bits_} >> amount.value());
  }

  constexpr UInt<W> operator~() const { return truncate(~std::uint64_t{bits_}); }

 private:
  using Storage = detail::storage_t<W>;
  Storage bits_{0};
};

template <int W>
class SInt {
  static_assert(W >= 2 && W <= 64, "SInt width must be 2..64");

 public:
  static constexpr int width = W;
  static constexpr std::int64_t max_value = static_cast<std::int64_t>(detail::low_mask(W - 1));
  static constexpr std::int64_t min_value = -max_value - 1;  // -(1 << 63) would overflow

  constexpr SInt() = default;

  template <std::integral T>
  constexpr explicit SInt(T value) : value_(static_cast<Storage>(value)) {
    if (std::cmp_less(+value, min_value) || std::cmp_greater(+value, max_value)) {
      throw std::out_of_range("SInt: value does not fit the width");
    }
  }

  template <int V>
  requires(V <= W) constexpr SInt(SInt<V> narrower)
      : value_(static_cast<Storage>(narrower.value())) {}  // NOLINT

  // Two's complement wrap of a host integer into W bits.
  static constexpr SInt truncate(std::int64_t value) {
    SInt r;
    r.value_ = static_cast<Storage>(detail::sign_extend(static_cast<std::uint64_t>(value), W));
    return r;
  }
  // A value that fits W bits by construction (the growing operators' exact
  // results): no sign extension to compute.
  static constexpr SInt exact(std::int64_t value) {
    SInt r;
    r.value_ = static_cast<Storage>(value);
    return r;
  }

  [[nodiscard]] constexpr std::int64_t value() const {
    if (value_ < min_value || value_ > max_value)
      __builtin_unreachable();
    return value_;
  }
  // The W-bit two's complement pattern, zero-extended (what a waveform shows).
  [[nodiscard]] constexpr std::uint64_t raw_bits() const {
    return static_cast<std::uint64_t>(std::int64_t{value_}) & detail::low_mask(W);
  }
  [[nodiscard]] constexpr bool is_negative() const { return value_ < 0; }
  [[nodiscard]] constexpr bool is_zero() const { return value_ == 0; }

  template <int N>
  [[nodiscard]] constexpr SInt<N> wrap() const {
    return SInt<N>::truncate(value_);
  }
  template <int N>
  [[nodiscard]] constexpr SInt<N> sat() const {
    const std::int64_t v = value_;
    return SInt<N>::truncate(v > SInt<N>::max_value   ? SInt<N>::max_value
                             : v < SInt<N>::min_value ? SInt<N>::min_value
                                                      : v);
  }
  [[nodiscard]] constexpr UInt<W> as_uint() const { return UInt<W>::truncate(raw_bits()); }
  // |x| is exact in W bits for every value except the minimum, which W bits
  // of magnitude still hold.
  [[nodiscard]] constexpr UInt<W> abs() const {
    const auto bits = static_cast<std::uint64_t>(value_);
    return UInt<W>::truncate(value_ < 0 ? 0 - bits : bits);
  }

  template <int N>
  [[nodiscard]] constexpr SInt<W + N> shl() const {
    return SInt<W + N>::truncate(
        static_cast<std::int64_t>(static_cast<std::uint64_t>(value_) << N));
  }
  // Arithmetic shift right: rounds toward minus infinity, like the hardware.
  template <int N>
  [[nodiscard]] constexpr SInt<(W - N > 1 ? W - N : 2)> shr() const {
    return SInt<(W - N > 1 ? W - N : 2)>::exact(std::int64_t{value_} >> (N >= 64 ? 63 : N));
  }

  // Arithmetic shift right by a run-time amount (a barrel shifter): same width.
  template <int K>
  [[nodiscard]] constexpr SInt<W> dshr(UInt<K> amount) const {
    return exact(std::int64_t{value_} >> (amount.value() >= 63 ? 63 : amount.value()));
  }

  constexpr SInt<W + 1> operator-() const { return SInt<W + 1>::exact(-std::int64_t{value_}); }

 private:
  using Storage = detail::signed_storage_t<W>;
  Storage value_{0};
};

template <int W>
constexpr SInt<W> UInt<W>::as_sint() const {
  static_assert(W >= 2, "a 1-bit value has no signed reading");
  return SInt<W>::truncate(static_cast<std::int64_t>(bits_));
}
template <int W>
constexpr SInt<W + 1> UInt<W>::to_sint() const {
  return SInt<W + 1>::truncate(static_cast<std::int64_t>(bits_));
}

// ---- UInt operators -------------------------------------------------------
template <int A, int B>
constexpr UInt<detail::max_width(A, B) + 1> operator+(UInt<A> a, UInt<B> b) {
  static_assert(detail::max_width(A, B) < 64, "sum would exceed 64 bits");
  return UInt<detail::max_width(A, B) + 1>::exact(a.value() + b.value());
}
template <int A, int B>
constexpr UInt<detail::max_width(A, B) + 1> operator-(UInt<A> a, UInt<B> b) {
  static_assert(detail::max_width(A, B) < 64, "difference would exceed 64 bits");
  return UInt<detail::max_width(A, B) + 1>::truncate(a.value() - b.value());
}
template <int A, int B>
constexpr UInt<A + B> operator*(UInt<A> a, UInt<B> b) {
  static_assert(A + B <= 64, "product would exceed 64 bits");
  return UInt<A + B>::exact(a.value() * b.value());
}
template <int A, int B>
constexpr UInt<detail::max_width(A, B)> operator&(UInt<A> a, UInt<B> b) {
  return UInt<detail::max_width(A, B)>::truncate(a.value() & b.value());
}
template <int A, int B>
constexpr UInt<detail::max_width(A, B)> operator|(UInt<A> a, UInt<B> b) {
  return UInt<detail::max_width(A, B)>::truncate(a.value() | b.value());
}
template <int A, int B>
constexpr UInt<detail::max_width(A, B)> operator^(UInt<A> a, UInt<B> b) {
  return UInt<detail::max_width(A, B)>::truncate(a.value() ^ b.value());
}
template <int A, int B>
constexpr bool operator==(UInt<A> a, UInt<B> b) {
  return a.value() == b.value();
}
template <int A, int B>
constexpr auto operator<=>(UInt<A> a, UInt<B> b) {
  return a.value() <=> b.value();
}

// ---- SInt operators -------------------------------------------------------
template <int A, int B>
constexpr SInt<detail::max_width(A, B) + 1> operator+(SInt<A> a, SInt<B> b) {
  static_assert(detail::max_width(A, B) < 64, "sum would exceed 64 bits");
  return SInt<detail::max_width(A, B) + 1>::exact(a.value() + b.value());
}
template <int A, int B>
constexpr SInt<detail::max_width(A, B) + 1> operator-(SInt<A> a, SInt<B> b) {
  static_assert(detail::max_width(A, B) < 64, "difference would exceed 64 bits");
  return SInt<detail::max_width(A, B) + 1>::exact(a.value() - b.value());
}
template <int A, int B>
constexpr SInt<A + B> operator*(SInt<A> a, SInt<B> b) {
  static_assert(A + B <= 64, "product would exceed 64 bits");
  return SInt<A + B>::exact(a.value() * b.value());
}
template <int A, int B>
constexpr bool operator==(SInt<A> a, SInt<B> b) {
  return a.value() == b.value();
}
template <int A, int B>
constexpr auto operator<=>(SInt<A> a, SInt<B> b) {
  return a.value() <=> b.value();
}

// ---- composition ----------------------------------------------------------
template <int A, int B>
constexpr UInt<A + B> cat(UInt<A> high, UInt<B> low) {
  static_assert(A + B <= 64);
  return UInt<A + B>::truncate((high.value() << B) | low.value());
}
template <class T>
constexpr T mux(UInt<1> select, T when_one, T when_zero) {
  return select ? when_one : when_zero;
}

// Modular addition at the wider operand's width: for accumulators that are
// meant to wrap (binary angles, 64-bit sums), where a + b would not fit.
template <int A, int B>
constexpr SInt<detail::max_width(A, B)> add_wrap(SInt<A> a, SInt<B> b) {
  return SInt<detail::max_width(A, B)>::truncate(static_cast<std::int64_t>(
      static_cast<std::uint64_t>(a.value()) + static_cast<std::uint64_t>(b.value())));
}

// Round-half-up shift right by N: (v + 2^(N-1)) >> N, the fixed-point
// "round to nearest" of the datapaths.
template <int N, int W>
constexpr SInt<W + 1 - N> round_shr(SInt<W> v) {
  static_assert(N >= 1 && N < W);
  return (v + SInt<N + 1>::truncate(std::int64_t{1} << (N - 1))).template shr<N>();
}

// A literal of just enough width: 5_u is UInt<3>, 0_u is UInt<1>.
namespace literals {
template <char... Digits>
consteval std::uint64_t parse_decimal() {
  std::uint64_t v = 0;
  for (char c : {Digits...}) {
    if (c < '0' || c > '9')
      throw std::invalid_argument("_u takes decimal digits");
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (v > (~std::uint64_t{0} - digit) / 10)
      throw std::out_of_range("_u literal exceeds 64 bits");
    v = v * 10 + digit;
  }
  return v;
}
template <char... Digits>
consteval auto operator""_u() {
  constexpr std::uint64_t v = parse_decimal<Digits...>();
  constexpr int w = v == 0 ? 1 : static_cast<int>(std::bit_width(v));
  return UInt<w>(v);
}
}  // namespace literals

}  // namespace odoloc::rtl
