// Odometry computation units, min-select and sequencer: exact arithmetic of
// each unit against integer references, and the kinematics of the whole
// fabric against physics (straight drives at any heading, constant-radius
// turns) within the quantisation bound of docs/odometry.md.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "odometry_bench.hpp"

namespace {

using odoloc::rtl::MinSelectPolicy;
using odoloc::rtl::SInt;
using odoloc::rtl::UInt;
using odoloc::tb::OdometryBench;
using odoloc::tb::SiPose;

constexpr double kDeg = M_PI / 180.0;
__extension__ using Int128 = __int128;  // exact references for 64-bit products

// Direction error of one step (docs/odometry.md): the heading is rounded to
// the CORDIC's 16-bit input (half of 2^-16 turn) and sin, cos are each within
// one 2^-14 LSB.
constexpr double kDirectionError = M_PI / 65536 + 1.4143 / 16384;

// Round-half-up division by 2^n of an exact integer: the datapath's rounding.
std::int64_t round_shift(Int128 v, int n) {
  return static_cast<std::int64_t>((v + (Int128{1} << (n - 1))) >> n);
}

TEST(RearUnit, IncrementsAreTheExactRoundedProducts) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> count(-(1 << 19), (1 << 19) - 1);
  std::uniform_int_distribution<std::uint64_t> scale(0, 0xFFFFFFFFULL);
  odoloc::rtl::RearOdometryUnit unit;
  for (int i = 0; i < 200'000; ++i) {
    const std::int64_t nl = count(rng), nr = count(rng);
    const std::uint64_t ks = scale(rng), kt = scale(rng);
    odoloc::rtl::clock_block(
        unit, {UInt<1>{1}, SInt<20>{nl}, SInt<20>{nr}, UInt<32>{ks}, UInt<32>{kt}, {}});
    ASSERT_EQ(unit.regs().ds.value(), round_shift(Int128{nl + nr} * ks, 8));
    ASSERT_EQ(unit.regs().dtheta.value(), (nr - nl) * static_cast<std::int64_t>(kt));
  }
}

TEST(FrontUnit, IncrementsAndSteeringClamp) {
  const odoloc::sw::VehicleGeometry g;
  const auto scales = odoloc::sw::odometry_scales(g);
  odoloc::rtl::FrontOdometryUnit unit;
  const auto start = [&](std::int64_t n_front, std::int64_t n_steer) {
    odoloc::rtl::clock_block(unit, {UInt<1>{1},
                                    UInt<1>{},
                                    SInt<20>{n_front},
                                    SInt<20>{n_steer},
                                    {},
                                    UInt<32>{scales.front_ds},
                                    UInt<32>{scales.front_dtheta},
                                    UInt<32>{scales.steer},
                                    UInt<32>{scales.steer_limit},
                                    {},
                                    {}});
  };
  const auto finish = [&](odoloc::rtl::cordic::SinCos sc) {
    odoloc::rtl::clock_block(
        unit, {UInt<1>{}, UInt<1>{1}, {}, {}, sc, UInt<32>{scales.front_ds}, {}, {}, {}, {}, {}});
  };
  // 30 degrees of steering, 1000 drive edges.
  const std::int64_t steer_edges = std::lround(30.0 / 360.0 / g.steering.turns_per_edge());
  start(1000, steer_edges);
  EXPECT_FALSE(unit.regs().clamped);
  const Int128 phi40 = Int128{steer_edges} * scales.steer;
  EXPECT_EQ(unit.regs().phi.value(), static_cast<std::int64_t>(phi40));
  const std::int64_t drive = round_shift(Int128{1000} * scales.front_ds, 8);
  EXPECT_EQ(unit.regs().drive.value(), drive);
  // The angle handed to the CORDIC is the mid-period angle (0 and 30 degrees).
  EXPECT_EQ(unit.cordic_angle().value(),
            static_cast<std::uint64_t>(round_shift(static_cast<std::int64_t>(phi40) / 2, 24)));
  const odoloc::rtl::cordic::SinCos sc{SInt<16>{8192}, SInt<16>{14189}};
  finish(sc);
  EXPECT_EQ(unit.regs().ds.value(), round_shift(Int128{drive} * 14189, 14));
  EXPECT_EQ(unit.regs().dtheta.value(),
            round_shift(Int128{round_shift(Int128{1000} * scales.front_dtheta, 8)} * 8192, 6));
  // Past the limit: clamped to +-40 degrees, flagged, sticky.
  start(0, steer_edges);
  EXPECT_TRUE(unit.regs().clamped);
  EXPECT_EQ(unit.regs().phi.value(), static_cast<std::int64_t>(scales.steer_limit) << 8);
  start(0, -4 * steer_edges);
  EXPECT_TRUE(unit.regs().clamped);
  EXPECT_EQ(unit.regs().phi.value(), -(static_cast<std::int64_t>(scales.steer_limit) << 8));
  start(0, 3 * steer_edges);
  EXPECT_FALSE(unit.regs().clamped);
  EXPECT_TRUE(unit.regs().clamp_flag);
}

odoloc::rtl::MinSelect::In select_input(MinSelectPolicy policy, std::int64_t rear_ds,
                                        std::int64_t rear_dtheta, std::int64_t front_ds,
                                        std::int64_t front_dtheta, unsigned shift = 0,
                                        std::uint32_t threshold = 0) {
  using odoloc::rtl::Distance;
  using odoloc::rtl::Heading;
  return {UInt<1>{1},
          {Distance{rear_ds}, Heading{rear_dtheta}},
          Distance{front_ds},
          Heading{front_dtheta},
          UInt<2>{static_cast<unsigned>(policy)},
          UInt<4>{shift},
          UInt<32>{threshold},
          UInt<32>{threshold},
          {}};
}

TEST(MinSelect, PaperRuleForEveryPolicyAndTheStatusBits) {
  struct Case {
    MinSelectPolicy policy;
    std::int64_t ds, dtheta;
    unsigned ds_front, dtheta_front;
  };
  for (const Case& c : {Case{MinSelectPolicy::kPerComponent, -900, -50, 1, 0},
                        Case{MinSelectPolicy::kWholeSet, -900, 70, 1, 1},
                        Case{MinSelectPolicy::kRearOnly, 1000, -50, 0, 0},
                        Case{MinSelectPolicy::kFrontOnly, -900, 70, 1, 1}}) {
    odoloc::rtl::MinSelect select;
    odoloc::rtl::clock_block(select, select_input(c.policy, 1000, -50, -900, 70));
    EXPECT_EQ(select.regs().ds.value(), c.ds);
    EXPECT_EQ(select.regs().dtheta.value(), c.dtheta);
    EXPECT_EQ(select.regs().ds_from_front.value(), c.ds_front);
    EXPECT_EQ(select.regs().dtheta_from_front.value(), c.dtheta_front);
  }
  // Ties go to the rear.
  odoloc::rtl::MinSelect select;
  odoloc::rtl::clock_block(select, select_input(MinSelectPolicy::kPerComponent, 5, 5, -5, -5));
  EXPECT_FALSE(select.regs().ds_from_front);
  EXPECT_FALSE(select.regs().dtheta_from_front);
}

TEST(MinSelect, LeakySumsIgnoreQuantisationAndHysteresisHoldsTheChoice) {
  odoloc::rtl::MinSelect select;
  const auto clock = [&](std::int64_t rear, std::int64_t front) {
    odoloc::rtl::clock_block(select,
                             select_input(MinSelectPolicy::kPerComponent, rear, 0, front, 0, 4, 3));
  };
  // Quantisation: the rear reads 101, 99, 101, ... against 100. The sums
  // telescope, so the difference never reaches the threshold.
  for (int i = 0; i < 1000; ++i) {
    clock(i % 2 == 0 ? 101 : 99, 100);
    ASSERT_FALSE(select.regs().ds_from_front) << i;
  }
  // A sustained rear over-count of 1 per update takes over within a few updates.
  int updates = 0;
  while (!select.regs().ds_from_front && updates < 100) {
    clock(101, 100);
    ++updates;
  }
  EXPECT_LE(updates, 5);
  EXPECT_EQ(select.regs().ds.value(), 100);
  // Agreement again: the front keeps the component (hysteresis)...
  for (int i = 0; i < 1000; ++i) {
    clock(i % 2 == 0 ? 101 : 99, 100);
    ASSERT_TRUE(select.regs().ds_from_front) << i;
  }
  // ...until the front over-counts by more than the threshold.
  updates = 0;
  while (select.regs().ds_from_front && updates < 100) {
    clock(100, 101);
    ++updates;
  }
  EXPECT_LE(updates, 8);
  EXPECT_EQ(select.regs().ds.value(), 100);
}

TEST(OdometrySequencer, UpdateLatencyIsExactAndOverrunIsFlagged) {
  OdometryBench bench;
  bench.drive(1.0, 0.0);
  bench.run(20'000);
  while (bench.fabric.phase() != odoloc::rtl::OdometryPhase::kLatch)
    bench.step();
  const std::uint64_t latch = bench.clocks;
  const auto updates = bench.fabric.sequencer().updates;
  const auto pose = bench.fabric.pose();
  const auto report = bench.fabric.report();
  while (bench.fabric.sequencer().updates == updates) {
    // The pose and the report change on the update count's edge, not before.
    ASSERT_EQ(bench.fabric.pose(), pose) << bench.clocks - latch;
    ASSERT_EQ(bench.fabric.report(), report) << bench.clocks - latch;
    bench.step();
  }
  EXPECT_NE(bench.fabric.pose(), pose);
  EXPECT_NE(bench.fabric.report(), report);
  EXPECT_EQ(bench.clocks - 1 - latch, odoloc::rtl::OdometrySequencer::kUpdateLatencyClocks);
  EXPECT_EQ(odoloc::rtl::OdometrySequencer::kUpdateLatencyClocks, 39U);  // 780 ns << 100 us
  EXPECT_FALSE(bench.fabric.sequencer().overrun);
  bench.cfg.odometry.cfg.update_clocks = UInt<16>{30};
  bench.run(200);
  EXPECT_TRUE(bench.fabric.sequencer().overrun);
}

struct Drive {
  MinSelectPolicy policy;
  double heading_deg;
  double v;
  double phi_deg;
  double seconds;
};

// Runs a drive from a set pose and compares the last update's pose with the
// analytic pose at the clock that latched its counts.
void check_drive(const Drive& d) {
  SCOPED_TRACE(testing::Message() << "policy " << static_cast<int>(d.policy) << " heading "
                                  << d.heading_deg << " v " << d.v << " phi " << d.phi_deg);
  OdometryBench bench(d.policy);
  const SiPose start{1.5, -2.0, d.heading_deg * kDeg};
  bench.set_pose(start);
  const double phi = bench.steer_to(d.phi_deg * kDeg);
  bench.run_to_next_update();  // the steering is taken in before the drive starts
  const std::uint64_t drive_start = bench.clocks;
  bench.drive(d.v, phi);
  bench.run(static_cast<std::uint64_t>(d.seconds * odoloc::sw::kFabricClockHz));
  bench.drive(0.0, phi);
  bench.run_to_next_update();
  // The latched counts trail the pins by the EPPM latency.
  const double t = (static_cast<double>(bench.latch_clock) - static_cast<double>(drive_start) -
                    static_cast<double>(bench.cfg.eppm[0].cfg.filter_clocks.value() + 3)) /
                   odoloc::sw::kFabricClockHz;
  const double s = d.v * std::min(t, d.seconds);
  const double curvature = std::tan(phi) / bench.geometry.wheelbase_m;
  SiPose truth = start;
  truth.theta = start.theta + s * curvature;
  if (curvature == 0) {
    truth.x += s * std::cos(start.theta);
    truth.y += s * std::sin(start.theta);
  } else {
    truth.x += (std::sin(truth.theta) - std::sin(start.theta)) / curvature;
    truth.y -= (std::cos(truth.theta) - std::cos(start.theta)) / curvature;
  }

  // Heading error: one edge per wheel; the front unit adds its per-update
  // sin(phi) error (CORDIC input and output rounding) over the distance.
  const auto& g = bench.geometry;
  const double rear_heading_error = 2 * g.rear.metres_per_edge() / g.rear_track_m;
  const double front_heading_error =
      (g.front.metres_per_edge() + std::abs(s) / std::cos(phi) * kDirectionError) / g.wheelbase_m;
  const double heading_error = std::max(rear_heading_error, front_heading_error);
  const double position_error = std::abs(s) * (kDirectionError + heading_error) +
                                2 * std::max(g.rear.metres_per_edge(), g.front.metres_per_edge());
  const SiPose got = odoloc::tb::si_pose(bench.fabric.pose());
  EXPECT_LE(std::abs(odoloc::tb::angle_difference(got.theta, truth.theta)), heading_error);
  EXPECT_LE(std::hypot(got.x - truth.x, got.y - truth.y), position_error)
      << "got (" << got.x << ", " << got.y << ") truth (" << truth.x << ", " << truth.y << ")";
}

TEST(OdometryKinematics, StraightDriveAtAnyHeadingBothUnits) {
  for (const MinSelectPolicy policy :
       {MinSelectPolicy::kRearOnly, MinSelectPolicy::kFrontOnly, MinSelectPolicy::kPerComponent}) {
    for (const double heading : {0.0, 30.0, 90.0, 135.0, 180.0, -120.0}) {
      check_drive({policy, heading, 1.0, 0.0, 0.1});
    }
  }
  check_drive({MinSelectPolicy::kRearOnly, 45.0, -0.8, 0.0, 0.1});  // reverse
}

TEST(OdometryKinematics, ConstantRadiusTurnsBothUnits) {
  for (const MinSelectPolicy policy : {MinSelectPolicy::kRearOnly, MinSelectPolicy::kFrontOnly}) {
    check_drive({policy, 10.0, 0.8, 25.0, 0.2});
    check_drive({policy, -70.0, 0.5, -35.0, 0.2});
    check_drive({policy, 160.0, -0.6, 15.0, 0.2});
  }
}

}  // namespace

namespace {

// Why min-select keeps a memory (docs/odometry.md): the paper's memoryless
// minimum of two quantised 100 us increments under-reads a clean straight
// drive by several percent; the leaky comparison does not.
double straight_drive_reading(odoloc::board::MinSelectTuning tuning) {
  OdometryBench bench(MinSelectPolicy::kPerComponent, tuning);
  bench.run_to_next_update();
  const std::uint64_t start = bench.clocks;
  bench.drive(1.0, 0.0);
  bench.run(5'000'000);
  bench.drive(0.0, 0.0);
  bench.run_to_next_update();
  const double truth = static_cast<double>(bench.latch_clock - start) / odoloc::sw::kFabricClockHz;
  return odoloc::tb::si_pose(bench.fabric.pose()).x / std::min(truth, 0.1);
}

TEST(MinSelect, MemorylessPaperRuleIsBiasedByQuantisation) {
  const double paper = straight_drive_reading(odoloc::board::MinSelectTuning::kPaper);
  const double leaky = straight_drive_reading(odoloc::board::MinSelectTuning::kVehicle);
  const double reset = straight_drive_reading(odoloc::board::MinSelectTuning::kReset);
  std::printf("straight 0.1 m: paper min-select reads %.4f, leaky min-select %.6f of the truth\n",
              paper, leaky);
  EXPECT_LT(paper, 0.99);
  EXPECT_NEAR(leaky, 1.0, 5e-4);
  EXPECT_NEAR(reset, 1.0, 5e-4);  // the reset values are the leaky rule too
}

}  // namespace
