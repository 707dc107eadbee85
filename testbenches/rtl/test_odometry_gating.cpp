// Activity gating of the odometry fabric is invisible: a fabric stepped with
// Gating::kOn matches one stepped with Gating::kOff, every register of every
// block after every clock, under moving encoders, frequent updates and random
// set-pose, clear-flags and reset strobes. Every register is compared
// through the blocks' traces, which name every register.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "odoloc/board/encoder_pins.hpp"
#include "odometry_bench.hpp"
#include "register_dump.hpp"

namespace {

using odoloc::rtl::Encoder;
using odoloc::rtl::Gating;
using odoloc::rtl::kEncoderCount;
using odoloc::rtl::OdometryFabric;
using odoloc::rtl::UInt;

TEST(OdometryGating, GatedAndUngatedAgreeEveryClock) {
  std::mt19937_64 rng(2026);
  odoloc::tb::OdometryBench bench;  // its configuration, two fabrics of our own
  auto cfg = bench.cfg;
  cfg.odometry.cfg.update_clocks = UInt<16>{300};
  OdometryFabric gated, full;
  OdometryFabric::In in{};
  std::array<odoloc::world::QuadratureSource, kEncoderCount> sources{};
  std::uniform_real_distribution<double> rate(-0.02, 0.02);
  std::uint64_t updates = 0, last = 0;
  for (std::uint64_t clock = 0; clock < 600'000; ++clock) {
    if (clock % 20'000 == 0) {
      for (auto& s : sources)
        s.set_rate(rng() % 4 == 0 ? 0.0 : rate(rng));
    }
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      in.pins[w] = odoloc::board::encoder_pins(sources[w].tick());
    const auto strobe = [&](unsigned one_in) { return UInt<1>::truncate(rng() % one_in == 0); };
    in.odometry.command = {.set_pose = strobe(50'000), .clear_flags = strobe(300'000)};
    cfg.odometry.set_x.bits = odoloc::rtl::SInt<64>::truncate(static_cast<std::int64_t>(rng()));
    cfg.odometry.set_y.bits = odoloc::rtl::SInt<64>::truncate(static_cast<std::int64_t>(rng()));
    cfg.odometry.set_theta.bits = UInt<40>::truncate(rng());
    for (auto& clear : in.eppm)
      clear.status = {.phase_error = strobe(100'000),
                      .carry = strobe(100'000),
                      .borrow = strobe(100'000),
                      .period_overflow = strobe(100'000)};
    in.odometry.status = {.overrun = strobe(60'000), .steer_clamped = strobe(60'000)};
    in.reset = strobe(200'000);
    gated.step<Gating::kOn>(in, cfg);
    full.step<Gating::kOff>(in, cfg);
    const std::string diff = odoloc::tb::first_difference(gated, full);
    ASSERT_TRUE(diff.empty()) << "clock " << clock << ": " << diff;
    const std::uint64_t now = full.sequencer().updates.value();
    updates += now > last ? now - last : 0;
    last = now;
  }
  EXPECT_GT(updates, 100U);  // the comparison covered many complete updates
}

}  // namespace
