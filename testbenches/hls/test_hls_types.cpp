// odoloc::hls::uint/sint against exact arithmetic: the same source compiled
// once per type family (ODOLOC_HLS_TYPES = 0 own, 1 ap_int.h, 2 ac_int.h),
// each build checking every expression the kernels may use against __int128
// arithmetic wrapped by hand, on seeded random operands of several widths.
// All three agreeing with the reference is what makes them interchangeable.
// The same for the functions the blocks' logic is written with
// (logic/int_family.hpp), in this build's family and in the cycle model's
// (rtl::Family), which runs the same logic.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <random>

#include "odoloc/hls/types.hpp"
#include "odoloc/logic/int_family.hpp"
#include "odoloc/rtl/family.hpp"

namespace {

// Exact reference arithmetic (a GCC/Clang extension, hence __extension__).
__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;
namespace hls = odoloc::hls;

// x wrapped to w bits, as an unsigned or two's-complement value.
std::int64_t wrapped(i128 x, int w, bool is_signed) {
  const auto u = static_cast<u128>(x) & ((static_cast<u128>(1) << w) - 1);
  if (is_signed && ((u >> (w - 1)) & 1U) != 0)
    return static_cast<std::int64_t>(static_cast<i128>(u) - (static_cast<i128>(1) << w));
  return static_cast<std::int64_t>(u);
}

int failures = 0;
void expect(bool ok, const char* what, int w, std::int64_t x, std::int64_t y) {
  if (!ok && ++failures <= 10)
    std::printf("FAIL %s: W=%d x=%lld y=%lld\n", what, w, static_cast<long long>(x),
                static_cast<long long>(y));
}

template <typename T>
std::int64_t value(const T& v) {
#if ODOLOC_HLS_TYPES == 2
  return v.to_int64();
#else
  return static_cast<std::int64_t>(v);
#endif
}

template <int W>
void suite(std::mt19937_64& rng) {
  for (int n = 0; n < 20000; ++n) {
    const auto x = static_cast<std::int64_t>(rng());
    const auto y = static_cast<std::int64_t>(rng() >> (rng() % 64));
    const hls::uint<W> a = x;  // construction wraps
    const hls::uint<W> b = y;
    const hls::sint<W> s = x;
    const hls::sint<W> t = y;
    const std::int64_t av = wrapped(x, W, false), bv = wrapped(y, W, false);
    const std::int64_t sv = wrapped(x, W, true), tv = wrapped(y, W, true);
    expect(value(a) == av && value(b) == bv, "uint wrap", W, x, y);
    expect(value(s) == sv && value(t) == tv, "sint wrap", W, x, y);
    const hls::uint<W> sum = a + b;
    expect(value(sum) == wrapped(i128{av} + bv, W, false), "uint sum wraps", W, x, y);
    const hls::sint<W + 1> diff = a - b;
    expect(value(diff) == av - bv, "exact difference", W, x, y);
    const hls::sint<2 * W> product = s * t;
    expect(value(product) == wrapped(i128{sv} * tv, 2 * W, true), "product", W, x, y);
    const hls::sint<W + 1> mixed = s + a;
    expect(value(mixed) == wrapped(i128{sv} + av, W + 1, true), "signed + unsigned", W, x, y);
    const hls::uint<W> left = a << 3;
    expect(value(left) == wrapped(i128{av} << 3, W, false), "shift left", W, x, y);
    // Widen first, then shift: exact in every family (types.hpp's rule).
    const hls::sint<W + 6> widened = s;
    const hls::sint<W + 6> scaled = widened << 6;
    expect(value(scaled) == sv * 64, "widened shift left", W, x, y);
    const hls::sint<W> right = s >> 2;
    expect(value(right) == (sv >> 2), "arithmetic shift right", W, x, y);
    expect((a < b) == (av < bv) && (s < t) == (sv < tv), "compare", W, x, y);
    expect((s < a) == (sv < av), "compare signed with unsigned", W, x, y);
    expect(value(hls::bits<W - 1, W / 2>(a)) == (av >> (W / 2)), "bits", W, x, y);
    expect(hls::bit(s, W - 1) == (sv < 0), "sign bit", W, x, y);
    hls::uint<W> counter = a;
    ++counter;
    expect(value(counter) == wrapped(i128{av} + 1, W, false), "increment wraps", W, x, y);
  }
}

// The logic's functions over family F on W-bit operands.
template <class F, int W>
void logic_suite(std::mt19937_64& rng, const char* family) {
  namespace lg = odoloc::logic;
  using S = lg::sint<F, W>;
  using U = lg::uint<F, W>;
  const auto fail = [&](bool ok, const char* what, std::int64_t x) {
    if (!ok && ++failures <= 10)
      std::printf("FAIL %s %s: W=%d x=%lld\n", family, what, W, static_cast<long long>(x));
  };
  for (int n = 0; n < 5000; ++n) {
    const auto x = static_cast<std::int64_t>(rng()) >> (rng() % 64);
    const S s = lg::wrap<S>(x);
    const U u = lg::wrap<U>(x);
    const std::int64_t sv = wrapped(x, W, true), uv = wrapped(x, W, false);
    fail(lg::to_s64(s) == sv && lg::to_s64(u) == uv, "wrap of a host integer", x);
    // Wider keeps the value (signed: by its sign), narrower keeps the low bits.
    fail(lg::to_s64(lg::wrap<lg::sint<F, W + 9> >(s)) == sv, "signed, wider", x);
    fail(lg::to_s64(lg::wrap<lg::uint<F, W + 9> >(s)) == wrapped(sv, W + 9, false),
         "signed into wider unsigned", x);
    fail(lg::to_s64(lg::wrap<lg::sint<F, W + 9> >(u)) == uv, "unsigned, wider", x);
    fail(lg::to_s64(lg::wrap<lg::sint<F, W - 3> >(s)) == wrapped(sv, W - 3, true), "narrower", x);
    fail(lg::to_s64(lg::wrap<lg::uint<F, W - 3> >(s)) == wrapped(sv, W - 3, false),
         "narrower unsigned", x);
    fail(lg::to_s64(lg::shr<3>(s)) == (sv >> 3), "shr", x);
    const auto amount = lg::wrap<lg::uint<F, 5> >(rng() % 32);
    fail(lg::to_s64(lg::shr_by(s, amount)) == (sv >> lg::to_s64(amount)), "shr_by", x);
    fail(lg::to_s64(lg::shl<7>(s)) == sv * 128, "shl grows", x);
    fail(lg::to_s64(lg::bits<W - 1, 2>(s)) == wrapped(sv >> 2, W - 2, false), "bits", x);
    fail(lg::to_s64(lg::bit<W - 1>(s)) == (sv < 0 ? 1 : 0), "sign bit", x);
    const auto high = lg::wrap<lg::uint<F, 3> >(x >> 40);
    fail(
        lg::to_s64(lg::cat(high, s)) == ((wrapped(x >> 40, 3, false) << W) | wrapped(sv, W, false)),
        "cat", x);
    fail(lg::to_s64(lg::round_shr<4>(s)) == ((sv + 8) >> 4), "round_shr", x);
    constexpr std::int64_t kMost = (std::int64_t{1} << (W - 4)) - 1;
    fail(lg::to_s64(lg::saturate<lg::sint<F, W - 3> >(s)) == (sv > kMost        ? kMost
                                                              : sv < -kMost - 1 ? -kMost - 1
                                                                                : sv),
         "saturate", x);
  }
}

template <class F>
void logic_suites(std::mt19937_64& rng, const char* family) {
  logic_suite<F, 5>(rng, family);
  logic_suite<F, 13>(rng, family);
  logic_suite<F, 22>(rng, family);
  logic_suite<F, 31>(rng, family);
  logic_suite<F, 47>(rng, family);
}

}  // namespace

TEST(HlsTypes, LogicFunctionsAreExactInThisFamilyAndTheModels) {
  std::mt19937_64 rng(29);
  failures = 0;
  logic_suites<hls::Family>(rng, hls::kTypeFamily);
  logic_suites<odoloc::rtl::Family>(rng, "model");
  // A 64-bit value through its two words and back (the model has 64-bit
  // integers; every family has Words).
  for (int n = 0; n < 1000; ++n) {
    const auto x = static_cast<std::int64_t>(rng());
    const auto words = odoloc::logic::to_words(odoloc::rtl::SInt<64>::truncate(x));
    odoloc::rtl::SInt<64> back;
    odoloc::logic::from_words(back, words);
    if (back.value() != x || words.hi.value() != (x >> 32) ||
        static_cast<std::int64_t>(words.lo.value()) != (x & 0xFFFFFFFF))
      ++failures;
  }
  EXPECT_EQ(failures, 0);
}

TEST(HlsTypes, EveryKernelExpressionIsExact) {
  std::mt19937_64 rng(12);
  failures = 0;
  suite<5>(rng);
  suite<8>(rng);
  suite<13>(rng);
  suite<16>(rng);
  suite<22>(rng);
  suite<31>(rng);
  std::printf("%s: %s\n", hls::kTypeFamily, failures == 0 ? "all expressions exact" : "FAILED");
  EXPECT_EQ(failures, 0);
}
