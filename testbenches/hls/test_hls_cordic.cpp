// The CORDIC kernel (hls/cordic_kernel.hpp) against the cycle model
// (rtl::SequentialCordic), compiled once per type family. Both run the same
// logic (logic/cordic.hpp), so this checks the type family and the port
// mapping: every one of the 65536 angles through the kernel equals the
// model's sincos with the model's latency, and under the reference's seeded
// random load / clear / reset stimulus every output equals the model's after
// every clock.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>

#include "hls_kernel_check.hpp"
#include "odoloc/hls/cordic_kernel.hpp"
#include "odoloc/rtl/cordic.hpp"

namespace {

namespace hc = odoloc::hls::cordic;
namespace rtl = odoloc::rtl;
using odoloc::hls::to_s64;

TEST(HlsCordic, EveryAngleEqualsTheModelWithTheModelsLatency) {
  int mismatches = 0;
  for (std::uint32_t a = 0; a < 65536; ++a) {
    hc::Registers regs;
    hc::Outputs out;
    hc::Inputs in{};
    in.load = 1;
    in.angle = a;
    hc::step(regs, in, out);
    in.load = 0;
    unsigned clocks = 0;
    while (to_s64(out.ready) == 0 && clocks < 100) {
      hc::step(regs, in, out);
      ++clocks;
    }
    const rtl::cordic::SinCos want =
        rtl::cordic::sincos(rtl::cordic::Angle::truncate(std::uint64_t{a}));
    if (clocks != rtl::SequentialCordic::kLatencyClocks || to_s64(out.sin) != want.sin.value() ||
        to_s64(out.cos) != want.cos.value())
      ++mismatches;
  }
  std::printf("%s: 65536 angles, %d mismatches\n", odoloc::hls::kTypeFamily, mismatches);
  EXPECT_EQ(mismatches, 0);
}

TEST(HlsCordic, EveryOutputEqualsTheModelEveryClock) {
  const auto check = odoloc::tb::check_kernel<hc::Inputs, hc::Outputs, hc::Registers>(
      "cordic", 5, odoloc::tb::hls_calls(1000000), hc::step);
  EXPECT_EQ(check.names_error, "");
  EXPECT_GT(check.calls, 0U);
  EXPECT_EQ(check.mismatches, 0U) << check.first_mismatch;
}

}  // namespace
