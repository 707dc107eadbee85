// Sequential CORDIC: exhaustive accuracy over all 65536 angles against long
// double, exact latency, LOAD-while-busy, the generated constants.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "odoloc/rtl/cordic.hpp"

namespace {

using odoloc::rtl::SequentialCordic;
using odoloc::rtl::UInt;
namespace cordic = odoloc::rtl::cordic;

constexpr long double kLsb = 1.0L / (1 << cordic::kOutputFractionBits);
constexpr long double kTwoPi = 2 * std::numbers::pi_v<long double>;

struct CordicRun {
  cordic::SinCos result;
  unsigned clocks_to_ready;
};

// LOAD at one clock, then clocks until RESULT_READY.
CordicRun compute(SequentialCordic& unit, unsigned angle) {
  odoloc::rtl::clock_block(unit, {UInt<1>{1}, cordic::Angle{angle}, {}, {}});
  unsigned clocks = 0;
  while (!unit.regs().ready && clocks < 100) {
    odoloc::rtl::clock_block(unit, {});
    ++clocks;
  }
  return {unit.regs().result, clocks};
}

long double error_lsb(cordic::Output value, long double exact) {
  return std::fabs(static_cast<long double>(value.value()) * kLsb - exact) / kLsb;
}

TEST(Cordic, ExhaustiveFaithfulWithinOneLsbAndExactLatency) {
  SequentialCordic unit;
  long double max_error = 0, sum_squares = 0;
  unsigned worst_angle = 0;
  for (unsigned angle = 0; angle < 65536; ++angle) {
    const CordicRun run = compute(unit, angle);
    ASSERT_EQ(run.clocks_to_ready, SequentialCordic::kLatencyClocks) << "angle " << angle;
    ASSERT_EQ(run.result, cordic::sincos(cordic::Angle{angle})) << "angle " << angle;
    const long double theta = kTwoPi * angle / 65536.0L;
    for (const long double e :
         {error_lsb(run.result.sin, std::sin(theta)), error_lsb(run.result.cos, std::cos(theta))}) {
      sum_squares += e * e;
      if (e > max_error) {
        max_error = e;
        worst_angle = angle;
      }
    }
  }
  const long double rms = std::sqrt(sum_squares / (2 * 65536));
  std::printf("CORDIC over 65536 angles: max error %.4Lf LSB (angle %u), RMS %.4Lf LSB\n",
              max_error, worst_angle, rms);
  RecordProperty("max_error_lsb", std::to_string(static_cast<double>(max_error)));
  RecordProperty("rms_error_lsb", std::to_string(static_cast<double>(rms)));
  EXPECT_LE(max_error, 1.0L);
  EXPECT_LT(rms, 0.5L);
}

// The paper's Fig. 8 cases. Degrees are not binary angles: the input itself
// is quantised to 360/65536 degrees, so the check allows that too.
void expect_degrees(double degrees) {
  SequentialCordic unit;
  const auto angle = static_cast<unsigned>(std::lround(degrees / 360.0 * 65536.0));
  const CordicRun run = compute(unit, angle);
  const long double input_error = std::fabs(angle * 360.0L / 65536 - degrees) * kTwoPi / 360;
  const long double tolerance = 1.0L + input_error / kLsb;
  const long double theta = degrees * kTwoPi / 360;
  EXPECT_LE(error_lsb(run.result.sin, std::sin(theta)), tolerance);
  EXPECT_LE(error_lsb(run.result.cos, std::cos(theta)), tolerance);
  EXPECT_EQ(run.clocks_to_ready * odoloc::rtl::kFabricClockPeriodNs, 320U);  // < 400 ns
}
TEST(Cordic, PaperCase30Degrees) {
  expect_degrees(30.0);
}
TEST(Cordic, PaperCase45Degrees) {
  expect_degrees(45.0);
}
TEST(Cordic, PaperCase60Degrees) {
  expect_degrees(60.0);
}

TEST(Cordic, ExactQuadrantAngles) {
  SequentialCordic unit;
  const int one = 1 << cordic::kOutputFractionBits;
  const int expected[4][2] = {{0, one}, {one, 0}, {0, -one}, {-one, 0}};
  for (unsigned q = 0; q < 4; ++q) {
    const CordicRun run = compute(unit, q * 16384);
    EXPECT_EQ(run.result.sin.value(), expected[q][0]) << q;
    EXPECT_EQ(run.result.cos.value(), expected[q][1]) << q;
  }
}

TEST(Cordic, LoadWhileBusyIsIgnoredAndFlagged) {
  SequentialCordic unit;
  odoloc::rtl::clock_block(unit, {UInt<1>{1}, cordic::Angle{5461}, {}, {}});
  for (unsigned k = 0; k < 5; ++k)
    odoloc::rtl::clock_block(unit, {});
  odoloc::rtl::clock_block(unit, {UInt<1>{1}, cordic::Angle{40000}, {}, {}});
  EXPECT_TRUE(unit.regs().load_ignored);
  unsigned clocks = 6;
  while (!unit.regs().ready) {
    odoloc::rtl::clock_block(unit, {});
    ++clocks;
  }
  EXPECT_EQ(clocks, SequentialCordic::kLatencyClocks);
  EXPECT_EQ(unit.regs().result, cordic::sincos(cordic::Angle{5461}));
  odoloc::rtl::clock_block(unit, {UInt<1>{}, {}, UInt<1>{1}, {}});
  EXPECT_FALSE(unit.regs().load_ignored);
  EXPECT_TRUE(unit.regs().ready);  // held until the next accepted LOAD
  // A LOAD after completion is accepted and drops RESULT_READY.
  odoloc::rtl::clock_block(unit, {UInt<1>{1}, cordic::Angle{40000}, {}, {}});
  EXPECT_FALSE(unit.regs().ready);
  EXPECT_TRUE(unit.regs().busy);
}

TEST(CordicConstants, PaperGainAndGeneratedTables) {
  // pi from Machin's formula, within one long double ulp (2.2e-19).
  EXPECT_LE(std::fabs(cordic::kPi - std::numbers::pi_v<long double>), 2.2e-19L);
  // The paper's 1/A16 for 16 micro-rotations with shifts 0..15.
  EXPECT_NEAR(static_cast<double>(cordic::kPaperInverseGain), 0.60725293510314, 1e-14);
  long double product = 1;
  for (int i = cordic::kFirstShift; i < cordic::kFirstShift + cordic::kIterations; ++i) {
    product *= std::sqrt(1.0L + std::ldexp(1.0L, -2 * i));
  }
  EXPECT_NEAR(static_cast<double>(cordic::kInverseGain), static_cast<double>(1 / product), 1e-15);
  EXPECT_EQ(cordic::kX0.value(),
            std::lround(static_cast<double>(std::ldexp(1 / product, cordic::kXyFractionBits))));
  for (int k = 0; k < cordic::kIterations; ++k) {
    const long double exact = std::atan(std::ldexp(1.0L, -(cordic::kFirstShift + k))) / kTwoPi *
                              (1 << cordic::kZUnitsBits);
    EXPECT_LE(std::fabs(cordic::kAtan.units[k] - exact), 0.5L) << k;
  }
}

}  // namespace
