// odoloc::hls::uint/sint against exact arithmetic: the same source compiled
// once per type family (ODOLOC_HLS_TYPES = 0 own, 1 ap_int.h, 2 ac_int.h),
// each build checking every expression the kernels may use against __int128
// arithmetic wrapped by hand, on seeded random operands of several widths.
// All three agreeing with the reference is what makes them interchangeable.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <random>

#include "odoloc/hls/types.hpp"

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

}  // namespace

TEST(HlsTypes, EveryKernelExpressionIsExact) {
  std::mt19937_64 rng(12);
  suite<5>(rng);
  suite<8>(rng);
  suite<13>(rng);
  suite<16>(rng);
  suite<22>(rng);
  suite<31>(rng);
  std::printf("%s: %s\n", hls::kTypeFamily, failures == 0 ? "all expressions exact" : "FAILED");
  EXPECT_EQ(failures, 0);
}
