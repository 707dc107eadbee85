// UInt<W>/SInt<W> against plain host integers: exhaustive over small widths,
// edge cases at 64 bits, and the compile-time rules (result widths, no silent
// narrowing) as static_asserts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "odoloc/rtl/bits.hpp"

namespace {

using namespace odoloc::rtl;  // NOLINT(google-build-using-namespace): UInt, SInt, cat, mux, ...
using namespace odoloc::rtl::literals;

constexpr std::int64_t kI64Min = std::numeric_limits<std::int64_t>::min();
constexpr std::int64_t kI64Max = std::numeric_limits<std::int64_t>::max();
constexpr std::uint64_t kU64Max = std::numeric_limits<std::uint64_t>::max();

// Two's complement wrap of v into n bits, computed without bit tricks.
std::int64_t wrap_signed(std::int64_t v, int n) {
  const std::int64_t modulus = std::int64_t{1} << n;
  const std::int64_t r = ((v % modulus) + modulus) % modulus;
  return r >= modulus / 2 ? r - modulus : r;
}
// v / 2^n rounded toward minus infinity.
std::int64_t floor_div_pow2(std::int64_t v, int n) {
  const std::int64_t d = std::int64_t{1} << n;
  return v >= 0 ? v / d : -((-v + d - 1) / d);
}

// Calls f.template operator()<N>() for each N.
template <int... N, class F>
void for_each_width(F&& f) {
  (f.template operator()<N>(), ...);
}

// ---- compile-time rules -------------------------------------------------------

// Result widths.
static_assert(std::is_same_v<decltype(UInt<4>{} + UInt<5>{}), UInt<6>>);
static_assert(std::is_same_v<decltype(UInt<4>{} - UInt<5>{}), UInt<6>>);
static_assert(std::is_same_v<decltype(UInt<4>{} * UInt<5>{}), UInt<9>>);
static_assert(std::is_same_v<decltype(UInt<4>{} & UInt<5>{}), UInt<5>>);
static_assert(std::is_same_v<decltype(UInt<4>{} | UInt<5>{}), UInt<5>>);
static_assert(std::is_same_v<decltype(UInt<4>{} ^ UInt<5>{}), UInt<5>>);
static_assert(std::is_same_v<decltype(~UInt<4>{}), UInt<4>>);
static_assert(std::is_same_v<decltype(SInt<4>{} + SInt<5>{}), SInt<6>>);
static_assert(std::is_same_v<decltype(SInt<4>{} - SInt<5>{}), SInt<6>>);
static_assert(std::is_same_v<decltype(SInt<4>{} * SInt<5>{}), SInt<9>>);
static_assert(std::is_same_v<decltype(-SInt<4>{}), SInt<5>>);
static_assert(std::is_same_v<decltype(UInt<6>{}.shl<3>()), UInt<9>>);
static_assert(std::is_same_v<decltype(UInt<6>{}.shr<2>()), UInt<4>>);
static_assert(std::is_same_v<decltype(UInt<6>{}.shr<8>()), UInt<1>>);
static_assert(std::is_same_v<decltype(SInt<6>{}.shl<3>()), SInt<9>>);
static_assert(std::is_same_v<decltype(SInt<6>{}.shr<2>()), SInt<4>>);
static_assert(std::is_same_v<decltype(SInt<6>{}.shr<8>()), SInt<2>>);
static_assert(std::is_same_v<decltype(UInt<8>{}.bit<3>()), UInt<1>>);
static_assert(std::is_same_v<decltype(UInt<8>{}.bits<5, 2>()), UInt<4>>);
static_assert(std::is_same_v<decltype(cat(UInt<3>{}, UInt<5>{})), UInt<8>>);
static_assert(std::is_same_v<decltype(SInt<5>{}.abs()), UInt<5>>);
static_assert(std::is_same_v<decltype(UInt<5>{}.as_sint()), SInt<5>>);
static_assert(std::is_same_v<decltype(UInt<5>{}.to_sint()), SInt<6>>);
static_assert(std::is_same_v<decltype(SInt<5>{}.as_uint()), UInt<5>>);

// Narrowing does not compile; widening of the same signedness is implicit.
static_assert(!std::is_convertible_v<UInt<9>, UInt<8>>);
static_assert(!std::is_constructible_v<UInt<8>, UInt<9>>);
static_assert(!std::is_assignable_v<UInt<8>&, UInt<9>>);
static_assert(!std::is_convertible_v<SInt<9>, SInt<8>>);
static_assert(!std::is_constructible_v<SInt<8>, SInt<9>>);
static_assert(!std::is_assignable_v<SInt<8>&, SInt<9>>);
static_assert(std::is_convertible_v<UInt<8>, UInt<9>>);
static_assert(std::is_convertible_v<UInt<1>, UInt<64>>);
static_assert(std::is_convertible_v<SInt<8>, SInt<9>>);
static_assert(std::is_convertible_v<SInt<2>, SInt<64>>);
// No implicit change of signedness.
static_assert(!std::is_convertible_v<UInt<8>, SInt<9>>);
static_assert(!std::is_convertible_v<SInt<8>, UInt<8>>);
static_assert(!std::is_constructible_v<UInt<8>, SInt<8>>);
// Host integers only explicitly; a value is not implicitly a bool.
static_assert(!std::is_convertible_v<int, UInt<8>>);
static_assert(std::is_constructible_v<UInt<8>, int>);
static_assert(!std::is_convertible_v<int, SInt<8>>);
static_assert(std::is_constructible_v<SInt<8>, int>);
static_assert(!std::is_convertible_v<UInt<8>, bool>);
static_assert(!std::is_convertible_v<UInt<8>, std::uint64_t>);

// Mixed signedness has no operators.
template <class A, class B>
concept Addable = requires(A a, B b) {
  a + b;
};
template <class A, class B>
concept Comparable = requires(A a, B b) {
  a < b;
};
static_assert(Addable<UInt<4>, UInt<4>> && Addable<SInt<4>, SInt<4>>);
static_assert(!Addable<UInt<4>, SInt<4>> && !Addable<UInt<4>, int>);
static_assert(!Comparable<UInt<4>, SInt<4>> && !Comparable<SInt<4>, int>);

// Storage is the narrowest machine word.
static_assert(sizeof(UInt<1>) == 1 && sizeof(UInt<8>) == 1 && sizeof(UInt<9>) == 2);
static_assert(sizeof(UInt<17>) == 4 && sizeof(UInt<33>) == 8 && sizeof(UInt<64>) == 8);
static_assert(sizeof(SInt<8>) == 1 && sizeof(SInt<16>) == 2 && sizeof(SInt<64>) == 8);

// Everything is usable in constant expressions.
static_assert((UInt<4>{15} + UInt<4>{1}).value() == 16);
static_assert((SInt<4>{-8} * SInt<4>{-8}).value() == 64);
static_assert(SInt<64>::min_value == kI64Min && SInt<64>::max_value == kI64Max);
static_assert(SInt<64>{kI64Min}.abs().value() == std::uint64_t{1} << 63);

// ---- exhaustive small widths ----------------------------------------------------

TEST(Bits, UIntBinaryOperatorsExhaustive) {
  for (std::int64_t a = 0; a < 16; ++a) {
    for (std::int64_t b = 0; b < 32; ++b) {
      const UInt<4> x{a};
      const UInt<5> y{b};
      SCOPED_TRACE(testing::Message() << a << ", " << b);
      EXPECT_EQ((x + y).value(), static_cast<std::uint64_t>(a + b));
      EXPECT_EQ((x - y).value(), static_cast<std::uint64_t>((a - b + 64) % 64));
      EXPECT_EQ((x * y).value(), static_cast<std::uint64_t>(a * b));
      EXPECT_EQ((x & y).value(), static_cast<std::uint64_t>(a & b));
      EXPECT_EQ((x | y).value(), static_cast<std::uint64_t>(a | b));
      EXPECT_EQ((x ^ y).value(), static_cast<std::uint64_t>(a ^ b));
      EXPECT_EQ(x == y, a == b);
      EXPECT_EQ(x != y, a != b);
      EXPECT_EQ(x < y, a < b);
      EXPECT_EQ(x <= y, a <= b);
      EXPECT_EQ(x > y, a > b);
      EXPECT_EQ(x >= y, a >= b);
      EXPECT_EQ(y < x, b < a);
      EXPECT_EQ(x <=> y, a <=> b);
    }
  }
}

TEST(Bits, SIntBinaryOperatorsExhaustive) {
  for (std::int64_t a = -8; a < 8; ++a) {
    for (std::int64_t b = -16; b < 16; ++b) {
      const SInt<4> x{a};
      const SInt<5> y{b};
      SCOPED_TRACE(testing::Message() << a << ", " << b);
      EXPECT_EQ((x + y).value(), a + b);
      EXPECT_EQ((x - y).value(), a - b);
      EXPECT_EQ((y - x).value(), b - a);
      EXPECT_EQ((x * y).value(), a * b);
      EXPECT_EQ(x == y, a == b);
      EXPECT_EQ(x != y, a != b);
      EXPECT_EQ(x < y, a < b);
      EXPECT_EQ(x <= y, a <= b);
      EXPECT_EQ(x > y, a > b);
      EXPECT_EQ(x >= y, a >= b);
      EXPECT_EQ(x <=> y, a <=> b);
    }
  }
}

TEST(Bits, UnaryOperatorsExhaustive) {
  for (std::int64_t a = 0; a < 16; ++a) {
    EXPECT_EQ((~UInt<4>{a}).value(), static_cast<std::uint64_t>(15 - a));
    EXPECT_EQ(UInt<4>{a}.is_zero(), a == 0);
    EXPECT_EQ(static_cast<bool>(UInt<4>{a}), a != 0);
  }
  for (std::int64_t a = -8; a < 8; ++a) {
    EXPECT_EQ((-SInt<4>{a}).value(), -a);  // -(-8) = 8 needs the fifth bit
    EXPECT_EQ(SInt<4>{a}.is_negative(), a < 0);
    EXPECT_EQ(SInt<4>{a}.is_zero(), a == 0);
  }
}

TEST(Bits, UIntWrapAndSatExhaustive) {
  for (std::int64_t v = 0; v < 1024; ++v) {
    const UInt<10> x{v};
    for_each_width<1, 2, 3, 5, 8, 9, 10, 12, 64>([&]<int N>() {
      const std::uint64_t limit = N >= 64 ? kU64Max : (std::uint64_t{1} << N) - 1;
      const auto u = static_cast<std::uint64_t>(v);
      SCOPED_TRACE(testing::Message() << v << " to " << N << " bits");
      static_assert(std::is_same_v<decltype(x.wrap<N>()), UInt<N>>);
      static_assert(std::is_same_v<decltype(x.sat<N>()), UInt<N>>);
      EXPECT_EQ(x.wrap<N>().value(), u & limit);
      EXPECT_EQ(x.sat<N>().value(), std::min(u, limit));
    });
  }
}

TEST(Bits, SIntWrapAndSatExhaustive) {
  for (std::int64_t v = -256; v < 256; ++v) {
    const SInt<9> x{v};
    for_each_width<2, 3, 5, 8, 9, 12, 64>([&]<int N>() {
      const std::int64_t lo = SInt<N>::min_value;
      const std::int64_t hi = SInt<N>::max_value;
      SCOPED_TRACE(testing::Message() << v << " to " << N << " bits");
      static_assert(std::is_same_v<decltype(x.wrap<N>()), SInt<N>>);
      static_assert(std::is_same_v<decltype(x.sat<N>()), SInt<N>>);
      EXPECT_EQ(x.wrap<N>().value(), N >= 64 ? v : wrap_signed(v, N));
      EXPECT_EQ(x.sat<N>().value(), std::clamp(v, lo, hi));
    });
  }
}

TEST(Bits, ShiftsExhaustive) {
  for (std::int64_t v = 0; v < 64; ++v) {
    const UInt<6> x{v};
    for_each_width<0, 1, 3, 5, 6, 8, 64>([&]<int N>() {
      SCOPED_TRACE(testing::Message() << v << " by " << N);
      if constexpr (6 + N <= 64) {
        EXPECT_EQ(x.shl<N>().value(), static_cast<std::uint64_t>(v) << N);
      }
      EXPECT_EQ(x.shr<N>().value(), N >= 6 ? 0U : static_cast<std::uint64_t>(v) >> N);
    });
  }
  for (std::int64_t v = -32; v < 32; ++v) {
    const SInt<6> x{v};
    for_each_width<0, 1, 3, 5, 6, 8, 64>([&]<int N>() {
      SCOPED_TRACE(testing::Message() << v << " by " << N);
      if constexpr (6 + N <= 64) {
        EXPECT_EQ(x.shl<N>().value(), v * (std::int64_t{1} << N));
      }
      // Arithmetic: rounds toward minus infinity, so -1 stays -1.
      EXPECT_EQ(x.shr<N>().value(), N >= 6 ? (v < 0 ? -1 : 0) : floor_div_pow2(v, N));
    });
  }
  EXPECT_EQ(SInt<6>{-5}.shr<1>().value(), -3);
  EXPECT_EQ(SInt<6>{-1}.shr<3>().value(), -1);
}

TEST(Bits, BitSelectAndConcatenateExhaustive) {
  for (std::int64_t v = 0; v < 256; ++v) {
    const UInt<8> x{v};
    const auto u = static_cast<std::uint64_t>(v);
    for_each_width<0, 1, 2, 3, 4, 5, 6, 7>(
        [&]<int I>() { EXPECT_EQ(x.bit<I>().value(), (u >> I) & 1U) << v << " bit " << I; });
    EXPECT_EQ((x.bits<5, 2>().value()), (u >> 2) & 0xFU);
    EXPECT_EQ((x.bits<7, 0>().value()), u);
    EXPECT_EQ((x.bits<7, 7>().value()), u >> 7);
  }
  for (std::int64_t h = 0; h < 8; ++h) {
    for (std::int64_t l = 0; l < 32; ++l) {
      EXPECT_EQ(cat(UInt<3>{h}, UInt<5>{l}).value(), static_cast<std::uint64_t>(h * 32 + l));
    }
  }
  EXPECT_EQ(mux(UInt<1>{1}, UInt<4>{3}, UInt<4>{9}).value(), 3U);
  EXPECT_EQ(mux(UInt<1>{0}, UInt<4>{3}, UInt<4>{9}).value(), 9U);
}

TEST(Bits, SignConversionsExhaustive) {
  for (std::int64_t v = 0; v < 32; ++v) {
    const UInt<5> x{v};
    EXPECT_EQ(x.as_sint().value(), v >= 16 ? v - 32 : v) << v;
    EXPECT_EQ(x.to_sint().value(), v) << v;
    EXPECT_EQ(x.as_sint().as_uint(), x) << v;
  }
  for (std::int64_t v = -16; v < 16; ++v) {
    const SInt<5> x{v};
    const auto pattern = static_cast<std::uint64_t>(v < 0 ? v + 32 : v);
    EXPECT_EQ(x.as_uint().value(), pattern) << v;
    EXPECT_EQ(x.raw_bits(), pattern) << v;
    EXPECT_EQ(x.as_uint().as_sint(), x) << v;
    EXPECT_EQ(x.abs().value(), static_cast<std::uint64_t>(v < 0 ? -v : v)) << v;  // |-16| = 16
  }
}

TEST(Bits, Truncate) {
  for (std::int64_t v = -1000; v < 1000; ++v) {
    EXPECT_EQ(UInt<5>::truncate(static_cast<std::uint64_t>(v)).value(),
              static_cast<std::uint64_t>(v) & 31U)
        << v;
    EXPECT_EQ(SInt<5>::truncate(v).value(), wrap_signed(v, 5)) << v;
  }
  EXPECT_EQ(UInt<64>::truncate(kU64Max).value(), kU64Max);
  EXPECT_EQ(UInt<1>::truncate(kU64Max).value(), 1U);
  EXPECT_EQ(SInt<64>::truncate(kI64Min).value(), kI64Min);
  EXPECT_EQ(SInt<2>::truncate(kI64Max).value(), -1);
}

// ---- 64 bits ---------------------------------------------------------------------

TEST(Bits, SixtyFourBitEdges) {
  const UInt<64> umax{kU64Max};
  const UInt<63> u63max = UInt<63>::truncate(kU64Max);
  EXPECT_EQ(umax.value(), kU64Max);
  EXPECT_EQ((u63max + u63max).value(), kU64Max - 1);
  EXPECT_EQ((UInt<63>{} - UInt<63>{1}).value(), kU64Max);  // wraps modulo 2^64
  EXPECT_EQ((UInt<32>::truncate(kU64Max) * UInt<32>::truncate(kU64Max)).value(),
            0xFFFFFFFE00000001U);
  EXPECT_EQ((~umax).value(), 0U);
  EXPECT_EQ(umax.bit<63>().value(), 1U);
  EXPECT_EQ((umax.bits<63, 60>().value()), 0xFU);
  EXPECT_EQ(umax.shr<63>().value(), 1U);
  EXPECT_EQ(umax.shr<64>().value(), 0U);
  EXPECT_EQ(umax.sat<32>().value(), 0xFFFFFFFFU);
  EXPECT_EQ(UInt<1>{1}.shl<63>().value(), std::uint64_t{1} << 63);
  EXPECT_EQ(cat(UInt<32>::truncate(kU64Max), UInt<32>{}).value(), 0xFFFFFFFF00000000U);

  const SInt<64> smin{kI64Min};
  const SInt<64> smax{kI64Max};
  EXPECT_EQ(smin.value(), kI64Min);
  EXPECT_EQ(smax.value(), kI64Max);
  EXPECT_EQ(smin.raw_bits(), std::uint64_t{1} << 63);
  EXPECT_EQ(SInt<64>{-1}.raw_bits(), kU64Max);
  EXPECT_EQ(smin.abs().value(), std::uint64_t{1} << 63);
  EXPECT_EQ(smax.abs().value(), static_cast<std::uint64_t>(kI64Max));
  EXPECT_EQ(smin.as_uint().value(), std::uint64_t{1} << 63);
  EXPECT_EQ(smin.shr<63>().value(), -1);
  EXPECT_EQ(smin.shr<64>().value(), -1);
  EXPECT_EQ(smax.shr<64>().value(), 0);
  EXPECT_EQ(smin.sat<8>().value(), -128);
  EXPECT_EQ(smax.sat<8>().value(), 127);
  EXPECT_EQ(smin.wrap<2>().value(), 0);
  EXPECT_EQ(smax.wrap<2>().value(), -1);
  const SInt<63> s63min{SInt<63>::min_value};
  const SInt<63> s63max{SInt<63>::max_value};
  EXPECT_EQ((s63min - s63max).value(), SInt<63>::min_value - SInt<63>::max_value);
  EXPECT_EQ((s63min + s63min).value(), kI64Min);
  EXPECT_EQ((SInt<32>{SInt<32>::min_value} * SInt<32>{SInt<32>::min_value}).value(),
            std::int64_t{1} << 62);
  EXPECT_EQ(umax.sat<64>(), umax);
  EXPECT_EQ(UInt<63>::truncate(kU64Max).to_sint().value(), kI64Max);
}

// ---- construction ---------------------------------------------------------------

TEST(Bits, ConstructorsCheckTheRange) {
  EXPECT_THROW(UInt<4>{16}, std::out_of_range);
  EXPECT_THROW(UInt<4>{-1}, std::out_of_range);
  EXPECT_THROW(UInt<1>{2U}, std::out_of_range);
  EXPECT_THROW(UInt<63>{kU64Max}, std::out_of_range);
  EXPECT_THROW(UInt<64>{kI64Min}, std::out_of_range);
  EXPECT_THROW(SInt<4>{8}, std::out_of_range);
  EXPECT_THROW(SInt<4>{-9}, std::out_of_range);
  EXPECT_THROW(SInt<5>{16U}, std::out_of_range);
  EXPECT_THROW(SInt<64>{kU64Max}, std::out_of_range);
  EXPECT_THROW(SInt<64>{static_cast<std::uint64_t>(kI64Max) + 1}, std::out_of_range);
  EXPECT_EQ(UInt<4>{15}.value(), 15U);
  EXPECT_EQ(UInt<4>{std::uint8_t{0}}.value(), 0U);
  EXPECT_EQ(UInt<64>{kU64Max}.value(), kU64Max);
  EXPECT_EQ(SInt<4>{-8}.value(), -8);
  EXPECT_EQ(SInt<4>{7U}.value(), 7);
  EXPECT_EQ(SInt<64>{static_cast<std::uint64_t>(kI64Max)}.value(), kI64Max);
  EXPECT_EQ(UInt<1>{true}.value(), 1U);  // a condition is a 1-bit value
  EXPECT_EQ(UInt<1>{false}.value(), 0U);
  EXPECT_EQ(UInt<8>{}.value(), 0U);
  EXPECT_EQ(SInt<8>{}.value(), 0);
}

TEST(Bits, WideningKeepsTheValue) {
  const UInt<16> u = UInt<4>{9};
  const SInt<16> s = SInt<4>{-7};
  EXPECT_EQ(u.value(), 9U);
  EXPECT_EQ(s.value(), -7);
  EXPECT_EQ(s.raw_bits(), 0xFFF9U);
}

TEST(Bits, LiteralsHaveJustEnoughWidth) {
  static_assert(std::is_same_v<decltype(0_u), UInt<1>>);
  static_assert(std::is_same_v<decltype(1_u), UInt<1>>);
  static_assert(std::is_same_v<decltype(2_u), UInt<2>>);
  static_assert(std::is_same_v<decltype(5_u), UInt<3>>);
  static_assert(std::is_same_v<decltype(255_u), UInt<8>>);
  static_assert(std::is_same_v<decltype(256_u), UInt<9>>);
  static_assert(std::is_same_v<decltype(18446744073709551615_u), UInt<64>>);
  static_assert((5_u).value() == 5 && (255_u).value() == 255);
  EXPECT_EQ((18446744073709551615_u).value(), kU64Max);
  EXPECT_EQ((0_u + 255_u).value(), 255U);
}

}  // namespace
