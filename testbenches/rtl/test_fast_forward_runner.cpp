// The scenario runner (the main job's engine) and the host tool's simulated
// board fast-forward the model between encoder edges and physics steps; with
// cycle_step they step every clock. Both give the same run to the bit: the
// runner's final poses, update counts, share of distance from the front unit
// and every track point, for each disturbance case and min-select policy;
// the board's register reads (EPPM counts and speeds, the pose, the update
// count, the TOF timestamp) every 20 ms of a drive.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>

#include "odoloc/board/scenario_runner.hpp"
#include "odoloc/board/sim_target.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc/world/scenarios.hpp"
#include "test_scale.hpp"

namespace {

using odoloc::board::RunOptions;
using odoloc::board::RunResult;
using odoloc::rtl::MinSelectPolicy;
using odoloc::world::BumpCase;

void expect_same_pose(const odoloc::world::Pose& a, const odoloc::world::Pose& b) {
  EXPECT_EQ(a.x_m, b.x_m);
  EXPECT_EQ(a.y_m, b.y_m);
  EXPECT_EQ(a.theta_rad, b.theta_rad);
}

// Every disturbance case with each policy, ordered so that the first four
// hold every case and both policies: a scaled run (ODOLOC_TEST_SCALE, the
// sanitize build's 0.5) takes the first share of them, at least those four.
struct Case {
  BumpCase bump;
  MinSelectPolicy policy;
};
constexpr std::array<Case, 8> kCases{{{BumpCase::kNone, MinSelectPolicy::kRearOnly},
                                      {BumpCase::kBothRear, MinSelectPolicy::kPerComponent},
                                      {BumpCase::kOneRear, MinSelectPolicy::kRearOnly},
                                      {BumpCase::kFront, MinSelectPolicy::kPerComponent},
                                      {BumpCase::kNone, MinSelectPolicy::kPerComponent},
                                      {BumpCase::kBothRear, MinSelectPolicy::kRearOnly},
                                      {BumpCase::kOneRear, MinSelectPolicy::kPerComponent},
                                      {BumpCase::kFront, MinSelectPolicy::kRearOnly}}};

TEST(FastForwardRunner, SameRunAsCycleStepping) {
  const auto cases = std::max<std::size_t>(
      4, static_cast<std::size_t>(kCases.size() * odoloc::tb::scaled(1'000'000) / 1'000'000));
  for (std::size_t c = 0; c < std::min(cases, kCases.size()); ++c) {
    const auto [bump, policy] = kCases[c];
    SCOPED_TRACE(testing::Message()
                 << odoloc::world::name(bump) << ", policy " << static_cast<int>(policy));
    const odoloc::world::Scenario scenario = odoloc::world::bump_scenario(bump, 0.3, 0.5);
    RunOptions options{.policy = policy, .record_every_clocks = 250'000};
    const RunResult forwarded = odoloc::board::run_scenario(scenario, options);
    options.cycle_step = true;
    const RunResult stepped = odoloc::board::run_scenario(scenario, options);
    expect_same_pose(forwarded.fabric, stepped.fabric);
    expect_same_pose(forwarded.truth, stepped.truth);
    EXPECT_EQ(forwarded.clocks, stepped.clocks);
    EXPECT_EQ(forwarded.updates, stepped.updates);
    EXPECT_EQ(forwarded.front_wins_ds, stepped.front_wins_ds);
    ASSERT_EQ(forwarded.track.size(), stepped.track.size());
    for (std::size_t i = 0; i < stepped.track.size(); ++i) {
      EXPECT_EQ(forwarded.track[i].time_s, stepped.track[i].time_s);
      expect_same_pose(forwarded.track[i].fabric, stepped.track[i].fabric);
      expect_same_pose(forwarded.track[i].truth, stepped.track[i].truth);
    }
    EXPECT_GT(stepped.updates, 2000U);  // a real drive, not an empty run
    EXPECT_EQ(stepped.skipped_clocks, 0U);
    EXPECT_GT(forwarded.skipped_clocks, forwarded.clocks / 2);  // the fast path was compared
  }
}

TEST(FastForwardRunner, SimulatedBoardReadsAsCycleStepping) {
  using namespace std::chrono_literals;
  namespace regs = odoloc::regs;
  odoloc::board::SimTargetOptions options;
  options.scenario = "bump_one_rear";
  odoloc::board::SimTarget forwarded(options);
  options.cycle_step = true;
  odoloc::board::SimTarget stepped(options);
  odoloc::sw::SpiRegisterBus stepped_bus(stepped.link(), {.crc = false, .confirm_writes = true});
  odoloc::sw::SpiRegisterBus forwarded_bus(forwarded.link(),
                                           {.crc = false, .confirm_writes = true});
  for (int k = 0; k < 30; ++k) {
    stepped.advance(20ms);
    forwarded.advance(20ms);
    for (const std::uint16_t base : {regs::eppm::kBase, regs::odometry::kBase, regs::tof::kBase}) {
      std::array<std::uint32_t, 32> a{}, b{};
      stepped_bus.read(base, a);
      forwarded_bus.read(base, b);
      ASSERT_EQ(a, b) << "block at " << base << ", read " << k;
    }
  }
  EXPECT_EQ(stepped.clocks(), forwarded.clocks());
  EXPECT_EQ(stepped.skipped_clocks(), 0U);
  EXPECT_GT(forwarded.skipped_clocks(), forwarded.clocks() / 2);
}

}  // namespace
