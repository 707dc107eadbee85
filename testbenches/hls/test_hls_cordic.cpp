// The CORDIC kernel (hls/cordic_kernel.hpp) against the cycle model
// (rtl::SequentialCordic), compiled once per type family: every one of the
// 65536 angles through the kernel equals rtl::cordic::sincos, with the exact
// latency, and under seeded random load / clear / reset stimulus every
// register equals the model's after every clock.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <random>

#include "odoloc/hls/cordic_kernel.hpp"
#include "odoloc/rtl/cordic.hpp"

namespace {

namespace hc = odoloc::hls::cordic;
namespace rtl = odoloc::rtl;
using odoloc::hls::to_s64;

bool same(const hc::Registers& k, const rtl::SequentialCordicRegs& m) {
  return to_s64(k.x) == m.state.x.value() && to_s64(k.y) == m.state.y.value() &&
         to_s64(k.z) == m.state.z.value() &&
         to_s64(k.quadrant) == static_cast<long long>(m.state.quadrant.value()) &&
         to_s64(k.iteration) == static_cast<long long>(m.iteration.value()) &&
         to_s64(k.busy) == static_cast<long long>(m.busy.value()) &&
         to_s64(k.ready) == static_cast<long long>(m.ready.value()) &&
         to_s64(k.load_ignored) == static_cast<long long>(m.load_ignored.value()) &&
         to_s64(k.sin) == m.result.sin.value() && to_s64(k.cos) == m.result.cos.value();
}

TEST(HlsCordic, EveryAngleEqualsTheModelWithTheModelsLatency) {
  int mismatches = 0;
  for (std::uint32_t a = 0; a < 65536; ++a) {
    hc::Registers regs;
    hc::sequential_cordic(regs, true, hc::Angle(a), false, false);
    unsigned clocks = 0;
    while (to_s64(regs.ready) == 0 && clocks < 100) {
      hc::sequential_cordic(regs, false, hc::Angle(0), false, false);
      ++clocks;
    }
    const rtl::cordic::SinCos want =
        rtl::cordic::sincos(rtl::cordic::Angle::truncate(std::uint64_t{a}));
    if (clocks != rtl::SequentialCordic::kLatencyClocks || to_s64(regs.sin) != want.sin.value() ||
        to_s64(regs.cos) != want.cos.value())
      ++mismatches;
  }
  std::printf("%s: 65536 angles, %d mismatches\n", odoloc::hls::kTypeFamily, mismatches);
  EXPECT_EQ(mismatches, 0);
}

TEST(HlsCordic, EveryRegisterEqualsTheModelEveryClock) {
  std::mt19937_64 rng(5);
  hc::Registers kernel;
  rtl::SequentialCordic model;
  const int clocks = 400000;
  for (int t = 0; t < clocks; ++t) {
    const std::uint64_t draw = rng();
    const bool load = (draw & 7U) == 0;
    const bool clear = (draw >> 3 & 63U) == 0;
    const bool reset = (draw >> 9 & 4095U) == 0;
    const auto angle = static_cast<std::uint32_t>(draw >> 32 & 0xFFFFU);
    hc::sequential_cordic(kernel, load, hc::Angle(angle), clear, reset);
    model.commit(model.eval({rtl::UInt<1>{load ? 1U : 0U}, rtl::cordic::Angle{angle},
                             rtl::UInt<1>{clear ? 1U : 0U}, rtl::UInt<1>{reset ? 1U : 0U}}));
    ASSERT_TRUE(same(kernel, model.regs())) << "clock " << t;
  }
  std::printf("%s: %d clocks of random stimulus, every register identical\n",
              odoloc::hls::kTypeFamily, clocks);
}

}  // namespace
