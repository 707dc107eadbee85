// Liu et al.'s filter (soc_software/fuse/include/odoloc/sw/liu_filter.hpp)
// against closed forms: the first step's gain with the paper's numbers, the
// Riccati fixed point of its covariance, the error variance it really
// reaches on a standing robot (Monte Carlo), the gates, eqs. 14.9/14.10 and
// 14.17-14.19 against the geometry they come from.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "odoloc/sw/liu_filter.hpp"

namespace {

using odoloc::sw::fuse::LiuFilter;
using odoloc::sw::fuse::LiuFilterOptions;
using odoloc::sw::fuse::Outcome;
using odoloc::sw::fuse::Pose;
using odoloc::sw::fuse::Vector2;
using odoloc::sw::fuse::Vector3;
using odoloc::sw::fuse::wrap_angle;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;

Pose pose(double x, double y, double theta) {
  return Pose{Vector3(x, y, theta)};
}

// The robot's laser angle of the station, from the truth (body frame).
double robot_bearing(const Vector3& truth, const Vector2& station) {
  return wrap_angle(std::atan2(station.y() - truth(1), station.x() - truth(0)) - truth(2));
}

// Paper's numbers, in mm^2: P(0|0) = Q = R = 1000, so the first step has
// P(1|0) = 2000, K = 2000/3000 and P(1|1) = 2000/3.
TEST(LiuFilter, FirstStepWithThePapersSettings) {
  LiuFilter f;
  f.initialise(0, pose(0, 1.2, 0));  // Liu's X(0|0) = (0, 1200) mm
  const Vector2 fix(0.030, 1.260);
  ASSERT_EQ(f.fuse_fix(fix), Outcome::kAccepted);
  EXPECT_NEAR(f.estimate().pose.x(0), 0.030 * 2 / 3, 1e-15);
  EXPECT_NEAR(f.estimate().pose.x(1), 1.2 + 0.060 * 2 / 3, 1e-15);
  EXPECT_NEAR(f.estimate().covariance_m2(0, 0), 2e-3 / 3, 1e-18);
  EXPECT_NEAR(f.estimate().covariance_m2(1, 1), 2e-3 / 3, 1e-18);
  EXPECT_EQ(f.estimate().covariance_m2(0, 1), 0);
}

// P(k|k) converges to the fixed point of P = (P + Q) R / (P + Q + R):
// P^2 + Q P - Q R = 0, P = (-Q + sqrt(Q^2 + 4 Q R)) / 2 (618 mm^2 for
// Liu's settings), whatever P(0|0) is.
TEST(LiuFilter, CovarianceReachesTheRiccatiFixedPoint) {
  for (const double p0 : {1e-6, 1e-3, 1.0}) {
    LiuFilterOptions o;
    o.initial_var_m2 = p0;
    o.process_var_m2 = 4e-4;
    o.fix_var_m2 = 9e-4;
    LiuFilter f(o);
    f.initialise(0, pose(2, 3, 1));
    for (int k = 0; k < 200; ++k)
      ASSERT_EQ(f.fuse_fix({2, 3}), Outcome::kAccepted);
    const double q = o.process_var_m2, r = o.fix_var_m2;
    const double fixed = (-q + std::sqrt(q * q + 4 * q * r)) / 2;
    EXPECT_NEAR(f.estimate().covariance_m2(0, 0), fixed, 1e-15) << p0;
    EXPECT_NEAR(f.estimate().covariance_m2(1, 1), fixed, 1e-15) << p0;
  }
  LiuFilter paper;
  paper.initialise(0, pose(0, 1.2, 0));
  for (int k = 0; k < 200; ++k)
    paper.fuse_fix({0, 1.2});
  EXPECT_NEAR(paper.estimate().covariance_m2(0, 0), 1e-3 * (std::sqrt(5.0) - 1) / 2, 1e-15);
}

// On a standing robot the estimate's error obeys e_k = (1 - K) e_(k-1) + K n_k
// with the steady gain K, so its variance is K R / (2 - K): below the
// filter's own P, which budgets Q for motion that did not happen.
TEST(LiuFilter, StandingRobotErrorVarianceMatchesItsClosedForm) {
  const LiuFilterOptions o;
  LiuFilter f(o);
  const Vector2 truth(4, 5);
  f.initialise(0, pose(truth.x(), truth.y(), 0));
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0, std::sqrt(o.fix_var_m2));
  double sum2 = 0;
  int n = 0;
  for (int k = 0; k < 40000; ++k) {
    const Vector2 fix = truth + Vector2(noise(rng), noise(rng));
    f.fuse_fix(fix);  // a few beyond the 15 cm gate are dropped
    if (k >= 100) {
      sum2 += (f.estimate().pose.position() - truth).squaredNorm() / 2;
      ++n;
    }
  }
  const double q = o.process_var_m2, r = o.fix_var_m2;
  const double p = (-q + std::sqrt(q * q + 4 * q * r)) / 2;
  const double gain = (p + q) / (p + q + r);
  EXPECT_NEAR(sum2 / n / (gain * r / (2 - gain)), 1.0, 0.03);
  EXPECT_LT(sum2 / n, p);
}

// A fix further than the gate is dropped, and still counts as a
// step: P grows by Q.
TEST(LiuFilter, FixGateAtItsDistance) {
  LiuFilter f;
  f.initialise(0, pose(1, 1, 0));
  EXPECT_EQ(f.fuse_fix({1.1501, 1}), Outcome::kGated);
  EXPECT_EQ(f.estimate().pose.position(), Vector2(1, 1));
  EXPECT_NEAR(f.estimate().covariance_m2(0, 0), 2e-3, 1e-18);
  EXPECT_EQ(f.fuse_fix({1, 1.1499}), Outcome::kAccepted);
  EXPECT_EQ(f.stats().fixes, 1U);
  EXPECT_EQ(f.stats().fixes_gated, 1U);
}

// A fix measured before the newest prediction: the innovation is taken
// where the robot was then, and the correction moves the track, exactly as
// fusing it then and driving on.
TEST(LiuFilter, LateFixEqualsAFixThenAndTheMotionSince) {
  const Vector3 since(0.30, 0.02, 0.25);
  LiuFilter then, late;
  for (LiuFilter* f : {&then, &late})
    f->initialise(0, pose(2, 3, 0.8));
  const Vector2 fix(2.05, 2.96);
  ASSERT_EQ(then.fuse_fix(fix), Outcome::kAccepted);
  then.predict(1, since);
  late.predict(1, since);
  ASSERT_EQ(late.fuse_fix(fix, since), Outcome::kAccepted);
  EXPECT_NEAR((late.estimate().pose.x - then.estimate().pose.x).norm(), 0, 1e-15);
  EXPECT_EQ(late.estimate().covariance_m2, then.estimate().covariance_m2);
}

// Dead reckoning is the odometry's own track: a straight drive at any
// heading ends where cos and sin of the heading put it.
TEST(LiuFilter, DeadReckoningOfAStraightDriveAtAnyHeading) {
  for (double heading = -kPi + 0.05; heading < kPi; heading += 0.4) {
    LiuFilter f;
    f.initialise(0, pose(1, 2, heading));
    for (int k = 1; k <= 100; ++k)
      ASSERT_EQ(f.predict(k * 0.01, {0.005, 0, 0}), Outcome::kAccepted);
    const long double h = heading;
    EXPECT_NEAR(f.estimate().pose.x(0), static_cast<double>(1 + 0.5L * std::cos(h)), 1e-12);
    EXPECT_NEAR(f.estimate().pose.x(1), static_cast<double>(2 + 0.5L * std::sin(h)), 1e-12);
    EXPECT_NEAR(f.estimate().pose.heading(), heading, 1e-12);
    EXPECT_EQ(f.estimate().covariance_m2(0, 0), 1e-3);  // dead reckoning leaves P
  }
}

// Eqs. 14.9 and 14.10: the station laser's angle and the range give back
// the point they were measured from, for a station anywhere.
TEST(LiuFilter, AbsolutePositionInvertsBearingAndRange) {
  const Vector2 station(0.3, 5.0);
  for (const Vector2& point : {Vector2(4, 7), Vector2(-2, 1), Vector2(0.3, -6), Vector2(9, 5)}) {
    const Vector2 d = point - station;
    const Vector2 back = LiuFilter::absolute_position(station, std::atan2(d.y(), d.x()), d.norm());
    EXPECT_NEAR((back - point).norm(), 0, 1e-14);
  }
}

// Eqs. 14.17-14.19: with theta_d 1 degree off and sigma_d = sigma_l, the
// heading lands halfway to the laser's (which is the truth: the estimate's
// position is exact), at any heading and station; across +-pi too; 3
// degrees or more off is gated.
TEST(LiuFilter, HeadingFromTheRobotsLaserAtAnyHeading) {
  const Vector2 station(0.5, -1.0);
  for (double heading = -kPi + 0.002; heading < kPi; heading += 0.3) {
    const Vector3 truth(3, 4, heading);
    LiuFilter f;
    f.initialise(0, pose(3, 4, heading + 1 * kDeg));
    ASSERT_EQ(f.fuse_heading(robot_bearing(truth, station), station), Outcome::kAccepted);
    EXPECT_NEAR(wrap_angle(f.estimate().pose.heading() - heading), 0.5 * kDeg, 1e-12) << heading;
    LiuFilter far;
    far.initialise(0, pose(3, 4, heading - 3.01 * kDeg));
    EXPECT_EQ(far.fuse_heading(robot_bearing(truth, station), station), Outcome::kGated);
    EXPECT_NEAR(far.estimate().pose.heading(), wrap_angle(heading - 3.01 * kDeg), 1e-15);
  }
  // theta_d just past -pi, the truth just below pi.
  const Vector3 truth(3, 4, kPi - 0.005);
  LiuFilter f;
  f.initialise(0, pose(3, 4, -kPi + 0.005));
  ASSERT_EQ(f.fuse_heading(robot_bearing(truth, station), station), Outcome::kAccepted);
  EXPECT_NEAR(std::abs(f.estimate().pose.heading()), kPi, 1e-12);
}

TEST(LiuFilter, BadInputChangesNothing) {
  EXPECT_THROW(LiuFilter(LiuFilterOptions{.fix_gate_m = 0}), std::invalid_argument);
  EXPECT_THROW(LiuFilter(LiuFilterOptions{.process_var_m2 = NAN}), std::invalid_argument);
  LiuFilter f;
  EXPECT_EQ(f.fuse_fix({1, 1}), Outcome::kNotInitialised);
  EXPECT_EQ(f.predict(0.01, {0.1, 0, 0}), Outcome::kNotInitialised);
  EXPECT_THROW(f.initialise(0, pose(NAN, 0, 0)), std::invalid_argument);
  f.initialise(0, pose(1, 1, 0.5));
  EXPECT_EQ(f.fuse_fix({NAN, 1}), Outcome::kNonFinite);
  EXPECT_EQ(f.predict(0.01, {INFINITY, 0, 0}), Outcome::kNonFinite);
  EXPECT_EQ(f.fuse_heading(NAN, {0, 0}), Outcome::kNonFinite);
  EXPECT_EQ(f.fuse_heading(0.1, {1, 1}), Outcome::kDegenerate);
  EXPECT_EQ(f.estimate().pose.x, Vector3(1, 1, 0.5));
  EXPECT_EQ(f.estimate().covariance_m2(0, 0), 1e-3);
  EXPECT_EQ(f.stats().refused, 5U);
}

}  // namespace
