// The pose EKF (soc_software pose_ekf.hpp) against independent references:
// chi-square tables, the closed-form (information form) Kalman update with
// Jacobians taken by central differences of each measurement function, the
// physics of a straight drive at any heading, Monte Carlo of the odometry
// noise model, and in-order processing for late measurements.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "odoloc/sw/pose_ekf.hpp"

namespace {

using namespace odoloc::sw::fuse;
constexpr double kPi = std::numbers::pi;

Pose pose(double x, double y, double theta) {
  Pose p;
  p.x = Vector3(x, y, theta);
  return p;
}

TEST(ChiSquare, MatchesTables) {
  // Abramowitz & Stegun table 26.8 / NIST quantiles.
  EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.841458820694124, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.99, 1), 6.634896601021214, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.95, 2), 5.991464547107979, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.999, 2), 13.815510557964274, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.95, 3), 7.814727903251178, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.025, 3), 0.2157952826238981, 1e-7);
  EXPECT_NEAR(chi_square_quantile(0.95, 4), 9.487729036781154, 1e-9);
  EXPECT_NEAR(chi_square_quantile(0.975, 300), 349.874, 0.01);
  EXPECT_NEAR(chi_square_cdf(2.0, 2), 1 - std::exp(-1.0), 1e-15);
  EXPECT_EQ(chi_square_cdf(-1.0, 3), 0.0);
  EXPECT_THROW(chi_square_quantile(1.0, 2), std::invalid_argument);
  EXPECT_THROW(chi_square_cdf(1.0, 0), std::invalid_argument);
}

TEST(PoseAlgebra, WrapAndComposeInvert) {
  EXPECT_DOUBLE_EQ(wrap_angle(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(-kPi), kPi);
  EXPECT_NEAR(wrap_angle(3 * kPi + 0.25), -kPi + 0.25, 1e-12);
  EXPECT_NEAR(wrap_angle(-7.0), -7.0 + 2 * kPi, 1e-12);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int i = 0; i < 1000; ++i) {
    const Pose a = pose(u(rng), u(rng), wrap_angle(u(rng)));
    const Pose b = pose(u(rng), u(rng), wrap_angle(u(rng)));
    const Pose back = compose(a, increment_between(a, b));
    EXPECT_NEAR((back.x.head<2>() - b.x.head<2>()).norm(), 0, 1e-12);
    EXPECT_NEAR(wrap_angle(back.heading() - b.heading()), 0, 1e-12);
  }
}

// The distance driven, from the increment between two poses on a circle of
// radius r swept by phi (arc r * phi, in long double) and on straight
// drives at any heading, forward and reversing.
TEST(PoseAlgebra, ArcLengthOfAnIncrement) {
  for (const double heading : {0.0, 0.7, -2.4, kPi}) {
    for (const double distance : {1e-6, 0.012, -0.3, 5.0}) {
      const Pose from = pose(3, -1, heading);
      const Pose to =
          pose(3 + distance * std::cos(heading), -1 + distance * std::sin(heading), heading);
      EXPECT_NEAR(arc_length(increment_between(from, to)), distance, 1e-13) << heading;
    }
    for (const long double radius : {0.25L, 1.7L, -4.0L}) {  // negative: turning right
      for (const long double phi : {1e-9L, 3e-5L, 2e-3L, 0.4L, 2.5L}) {
        // Centre to the robot's left at `radius`; heading turns by phi.
        const long double cx = 1 - radius * std::sin(static_cast<long double>(heading));
        const long double cy = 2 + radius * std::cos(static_cast<long double>(heading));
        const long double h1 = heading + phi * (radius > 0 ? 1 : -1);
        const Pose from = pose(1, 2, heading);
        const Pose to = pose(static_cast<double>(cx + radius * std::sin(h1)),
                             static_cast<double>(cy - radius * std::cos(h1)),
                             wrap_angle(static_cast<double>(h1)));
        const long double arc = std::abs(radius) * phi;
        EXPECT_NEAR(arc_length(increment_between(from, to)), static_cast<double>(arc),
                    1e-12 * (1 + static_cast<double>(arc) * 1e3))
            << "r " << static_cast<double>(radius) << " phi " << static_cast<double>(phi);
      }
    }
  }
  EXPECT_EQ(arc_length(Vector3::Zero()), 0.0);
  EXPECT_TRUE(std::isnan(arc_length(Vector3(std::nan(""), 0, 0))));
}

// Physics: driving straight ahead at any heading moves along that heading,
// and the along-track variance is the per-metre variance times the length
// (no heading noise configured, so nothing couples into it).
TEST(PoseEkf, StraightDriveAtAnyHeading) {
  for (const double heading : {0.0, 0.3, 1.5707963, 2.9, -2.2, kPi}) {
    EkfOptions options;
    options.odometry.heading_sd_per_sqrt_m = 0;
    options.odometry.heading_sd_per_sqrt_rad = 0;
    PoseEkf ekf(options);
    ekf.initialise(0, pose(1, 2, heading), Matrix3::Identity() * 1e-10);
    for (int k = 1; k <= 500; ++k)
      ASSERT_EQ(ekf.predict(k * 0.01, Increment{Vector3(0.01, 0, 0)}), Outcome::kAccepted);
    const Estimate e = ekf.estimate();
    EXPECT_NEAR(e.pose.x(0), 1 + 5 * std::cos(heading), 1e-12);
    EXPECT_NEAR(e.pose.x(1), 2 + 5 * std::sin(heading), 1e-12);
    EXPECT_NEAR(wrap_angle(e.pose.heading() - heading), 0, 1e-12);
    const Eigen::Vector2d along(std::cos(heading), std::sin(heading));
    const Eigen::Vector2d across(-std::sin(heading), std::cos(heading));
    const Matrix2 Pp = e.covariance.topLeftCorner<2, 2>();
    const double floor = options.odometry.floor_sd * options.odometry.floor_sd;
    const double a = options.odometry.along_sd_per_sqrt_m,
                 c = options.odometry.across_sd_per_sqrt_m;
    EXPECT_NEAR(along.dot(Pp * along), a * a * 5 + 500 * floor + 1e-10, 1e-9);
    // Across: the side slip, plus the floor on the heading carried over the lever arm.
    EXPECT_GT(across.dot(Pp * across), c * c * 5);
    EXPECT_LT(across.dot(Pp * across), c * c * 5 + 1e-6);
  }
}

// The predicted covariance against Monte Carlo of the noise model itself:
// increments drawn with Q(d) in the robot frame, composed exactly.
TEST(PoseEkf, PredictCovarianceMatchesMonteCarlo) {
  EkfOptions options;
  options.odometry.along_sd_per_sqrt_m = 0.02;
  options.odometry.across_sd_per_sqrt_m = 0.01;
  options.odometry.heading_sd_per_sqrt_m = 0.01;
  options.odometry.heading_sd_per_sqrt_rad = 0.03;
  PoseEkf ekf(options);
  const Matrix3 P0 = Vector3(1e-4, 1e-4, 1e-5).asDiagonal();
  ekf.initialise(0, pose(0, 0, 0.4), P0);
  // A quarter circle of 2 m radius in 100 steps.
  const Vector3 d(kPi / 100, 0, kPi / 200);
  for (int k = 1; k <= 100; ++k)
    ekf.predict(k * 0.01, Increment{d});
  const Estimate e = ekf.estimate();
  std::mt19937_64 rng(17);
  std::normal_distribution<double> n01;
  const OdometryNoise& q = options.odometry;
  const double dist = d.head<2>().norm();
  const double f2 = q.floor_sd * q.floor_sd;
  const Vector3 sd(std::sqrt(q.along_sd_per_sqrt_m * q.along_sd_per_sqrt_m * dist + f2),
                   std::sqrt(q.across_sd_per_sqrt_m * q.across_sd_per_sqrt_m * dist + f2),
                   std::sqrt(q.heading_sd_per_sqrt_m * q.heading_sd_per_sqrt_m * dist +
                             q.heading_sd_per_sqrt_rad * q.heading_sd_per_sqrt_rad * d.z() + f2));
  const Eigen::LLT<Matrix3> chol(P0);
  constexpr int kRuns = 20000;
  Vector3 mean = Vector3::Zero();
  std::vector<Vector3> ends;
  for (int r = 0; r < kRuns; ++r) {
    Pose p = pose(0, 0, 0.4);
    p.x += chol.matrixL() * Vector3(n01(rng), n01(rng), n01(rng));
    for (int k = 0; k < 100; ++k)
      p = compose(p, d + sd.cwiseProduct(Vector3(n01(rng), n01(rng), n01(rng))));
    ends.push_back(p.x);
    mean += p.x / kRuns;
  }
  Matrix3 sample = Matrix3::Zero();
  for (const Vector3& v : ends)
    sample += (v - mean) * (v - mean).transpose() / (kRuns - 1);
  // The linearisation is first order; the sample's own error is about
  // sqrt(2/N) = 1 %: agree within 5 % per element of the scale.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double scale = std::sqrt(sample(i, i) * sample(j, j));
      EXPECT_NEAR(e.covariance(i, j), sample(i, j), 0.05 * scale) << i << "," << j;
    }
  }
  EXPECT_NEAR((mean.head<2>() - e.pose.x.head<2>()).norm(), 0, 0.01);
}

// The reference update: information form with a numerical Jacobian.
struct Reference {
  Vector3 x;
  Matrix3 P;
};
Reference reference_update(const Vector3& x, const Matrix3& P,
                           const std::function<Eigen::VectorXd(const Vector3&)>& h,
                           const Eigen::VectorXd& z, const Eigen::MatrixXd& R,
                           const std::vector<bool>& angle) {
  const Eigen::VectorXd hx = h(x);
  Eigen::MatrixXd H(hx.size(), 3);
  for (int j = 0; j < 3; ++j) {
    constexpr double kStep = 1e-6;
    Vector3 a = x, b = x;
    a(j) += kStep;
    b(j) -= kStep;
    Eigen::VectorXd diff = h(a) - h(b);
    for (int i = 0; i < diff.size(); ++i)
      if (angle[static_cast<std::size_t>(i)])
        diff(i) = wrap_angle(diff(i));
    H.col(j) = diff / (2 * kStep);
  }
  Eigen::VectorXd nu = z - hx;
  for (int i = 0; i < nu.size(); ++i)
    if (angle[static_cast<std::size_t>(i)])
      nu(i) = wrap_angle(nu(i));
  const Matrix3 info = P.inverse() + H.transpose() * R.inverse() * H;
  const Matrix3 Pn = info.inverse();
  Vector3 xn = x + Pn * H.transpose() * R.inverse() * nu;
  xn(2) = wrap_angle(xn(2));
  return {xn, Pn};
}

class UpdateVsReference : public ::testing::Test {
 protected:
  void check(const Measurement& m, const std::function<Eigen::VectorXd(const Vector3&)>& h,
             const Eigen::VectorXd& z, const Eigen::MatrixXd& R, const std::vector<bool>& angle) {
    const Vector3 x0(2.0, -1.0, 2.8);
    Matrix3 P0;
    P0 << 0.04, 0.01, 0.002, 0.01, 0.09, -0.003, 0.002, -0.003, 0.01;
    PoseEkf ekf;
    ekf.initialise(0, Pose{x0}, P0);
    ASSERT_EQ(ekf.update(0, m), Outcome::kAccepted) << name(type_of(m));
    const Reference ref = reference_update(x0, P0, h, z, R, angle);
    const Estimate e = ekf.estimate();
    EXPECT_NEAR((e.pose.x.head<2>() - ref.x.head<2>()).norm(), 0, 1e-7) << name(type_of(m));
    EXPECT_NEAR(wrap_angle(e.pose.heading() - ref.x(2)), 0, 1e-7) << name(type_of(m));
    EXPECT_NEAR((e.covariance - ref.P).norm(), 0, 1e-8) << name(type_of(m));
  }
  static Eigen::VectorXd v1(double a) { return Eigen::VectorXd::Constant(1, a); }
  static Eigen::MatrixXd r1(double sd) { return Eigen::MatrixXd::Constant(1, 1, sd * sd); }
};

TEST_F(UpdateVsReference, PositionFix) {
  PositionFix f{Vector2(2.3, -0.8), (Matrix2() << 0.02, 0.005, 0.005, 0.03).finished()};
  check(f, [](const Vector3& x) -> Eigen::VectorXd { return x.head<2>(); }, f.position_m,
        f.covariance_m2, {false, false});
}

TEST_F(UpdateVsReference, BodyPointFix) {  // Thamma's head box 0.6 m ahead
  BodyPointFix f{Vector2(0.6, 0.05), Vector2(1.5, -0.7), Matrix2::Identity() * 0.01};
  check(f,
        [&](const Vector3& x) -> Eigen::VectorXd {
          return compose(Pose{x}, Vector3(f.body_point_m.x(), f.body_point_m.y(), 0)).position();
        },
        f.position_m, f.covariance_m2, {false, false});
}

TEST_F(UpdateVsReference, HeadingAcrossTheWrap) {
  HeadingFix f{-3.1, 0.1};  // the state is at 2.8: the innovation is +0.38, not -5.9
  check(f, [](const Vector3& x) { return v1(x(2)); }, v1(f.heading_rad), r1(f.sd_rad), {true});
}

TEST_F(UpdateVsReference, StationBearing) {  // Liu's alpha, the base station at (-1, 0.5)
  StationBearing b{Vector2(-1, 0.5), -0.45, 0.01};
  check(b, [&](const Vector3& x) { return v1(std::atan2(x(1) - 0.5, x(0) + 1)); },
        v1(b.bearing_rad), r1(b.sd_rad), {true});
}

TEST_F(UpdateVsReference, StationRange) {  // Liu's d_rb, the transmitter 0.3 m higher
  StationRange r{Vector2(-1, 0.5), 0.3, 3.4, 0.02};
  check(r,
        [&](const Vector3& x) {
          return v1(std::sqrt((x.head<2>() - r.station_m).squaredNorm() + 0.09));
        },
        v1(r.distance_m), r1(r.sd_m), {false});
}

TEST_F(UpdateVsReference, RobotBearing) {  // Liu's beta: the station seen from the robot
  RobotBearing b{Vector2(-1, 0.5), -0.05, 0.01};
  check(b, [&](const Vector3& x) { return v1(std::atan2(0.5 - x(1), -1 - x(0)) - x(2)); },
        v1(b.bearing_rad), r1(b.sd_rad), {true});
}

// Liu eq. 14.18 read as printed, theta = pi - (beta - alpha), is the same
// geometry: the bearing from the robot to the station is alpha + pi.
TEST(PoseEkf, LiuHeadingEquationAgreesWithRobotBearing) {
  const Vector3 truth(3.0, 4.0, 0.7);
  const double alpha = std::atan2(truth(1), truth(0));  // station at the origin
  const double beta = wrap_angle(std::atan2(-truth(1), -truth(0)) - truth(2));
  EXPECT_NEAR(wrap_angle(kPi - (beta - alpha) - truth(2)), 0, 1e-12);
}

// Kleeman's room: six beacons 2.5 m up, ranges with a common offset; the
// filter, 5 cm off (a running filter; the first pose comes from a solver's
// fix), lands on the truth, and an echo 0.6 m long is gated.
TEST(PoseEkf, BeaconRangesWithCommonOffsetAndAnEcho) {
  const std::vector<Vector2> beacons = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {5, 0}, {5, 10}};
  const Vector3 truth(3.7, 6.2, 0.4);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0, 0.002);
  for (const bool echo : {false, true}) {
    PoseEkf ekf;
    ekf.initialise(0, pose(3.74, 6.17, 0.4), Vector3(0.01, 0.01, 0.01).asDiagonal());
    RangeSet set;
    for (std::size_t i = 0; i < beacons.size(); ++i) {
      const double range = std::sqrt((truth.head<2>() - beacons[i]).squaredNorm() + 2.5 * 2.5);
      set.ranges.push_back({beacons[i], 2.5, range + 0.37 + noise(rng), 0.002});
    }
    if (echo)
      set.ranges[1].distance_m += 0.6;
    EXPECT_EQ(ekf.update(0, set), Outcome::kAccepted);
    const Estimate e = ekf.estimate();
    EXPECT_NEAR((e.pose.position() - truth.head<2>()).norm(), 0, 0.005) << "echo " << echo;
    // Six ranges are five measurements: the first pins the offset.
    EXPECT_EQ(ekf.stats(MeasurementType::kBeaconRange).gated, echo ? 1U : 0U);
    EXPECT_EQ(ekf.stats(MeasurementType::kBeaconRange).accepted, echo ? 4U : 5U);
    // The position is now known to a few mm: the covariance says so.
    const double position_variance = e.covariance.topLeftCorner<2, 2>().trace();
    EXPECT_LT(position_variance, 1e-4);
  }
}

// A robot driving at 0.5 m/s hears a cycle's six beacons 0.15 s apart
// (0.375 m between the first and the last): with each range's motion from
// odometry the set lands on the pose at the set's time, at any heading;
// without it, centimetres off. A heading 0.05 rad off is pulled towards
// the truth (the motion makes it observable: the Jacobian's heading column).
TEST(PoseEkf, BeaconRangesFromAMovingRobot) {
  const std::vector<Vector2> beacons = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {5, 0}, {5, 10}};
  for (const double heading : {0.0, 0.9, 2.2, -2.7}) {
    const Vector3 truth(4.2, 5.1, heading);
    const auto range_set = [&](bool compensated) {
      RangeSet set;
      for (std::size_t i = 0; i < beacons.size(); ++i) {
        const Vector2 motion(0.5 * 0.15 * static_cast<double>(i), 0);
        const Vector2 at = compose(Pose{truth}, Vector3(motion.x(), motion.y(), 0)).position();
        const double range = std::sqrt((at - beacons[i]).squaredNorm() + 2.5 * 2.5);
        set.ranges.push_back(
            {beacons[i], 2.5, range + 0.37, 0.002, compensated ? motion : Vector2::Zero()});
      }
      return set;
    };
    for (const bool compensated : {true, false}) {
      PoseEkf ekf;
      ekf.initialise(0, pose(4.23, 5.08, heading), Vector3(1e-3, 1e-3, 1e-4).asDiagonal());
      ekf.update(0, range_set(compensated));
      const double error = (ekf.estimate().pose.position() - truth.head<2>()).norm();
      if (compensated)
        EXPECT_LT(error, 0.002) << "heading " << heading;
      else
        EXPECT_GT(error, 0.02) << "heading " << heading;
    }
    PoseEkf turned;
    turned.initialise(0, pose(4.2, 5.1, heading + 0.05), Vector3(1e-4, 1e-4, 0.01).asDiagonal());
    turned.update(0, range_set(true));
    EXPECT_LT(std::abs(wrap_angle(turned.estimate().pose.heading() - heading)), 0.025)
        << "heading " << heading;
  }
}

// A robot carried 2 m away: the fixes are gated, then let back in after
// reopen_after rejections spanning reopen_after_s, and the filter follows.
TEST(PoseEkf, GateLetsBackInAfterARunOfRejections) {
  EkfOptions options;
  options.gate.reopen_after = 5;
  options.gate.reopen_after_s = 1.0;
  PoseEkf ekf(options);
  ekf.initialise(0, pose(0, 0, 0), Vector3(1e-4, 1e-4, 1e-4).asDiagonal());
  const PositionFix far{Vector2(2, 0), Matrix2::Identity() * 1e-4};
  std::vector<Outcome> outcomes;
  for (int k = 1; k <= 8; ++k)
    outcomes.push_back(ekf.update(0.3 * k, far));
  // Five rejections by 1.5 s; the sixth (1.8 s) spans 1.5 s >= 1 s: reopened.
  const std::vector<Outcome> want = {Outcome::kGated,    Outcome::kGated,   Outcome::kGated,
                                     Outcome::kGated,    Outcome::kGated,   Outcome::kReopened,
                                     Outcome::kAccepted, Outcome::kAccepted};
  EXPECT_EQ(outcomes, want);
  EXPECT_NEAR(ekf.estimate().pose.x(0), 2, 0.01);
  EXPECT_EQ(ekf.stats(MeasurementType::kPositionFix).gated, 5U);
  EXPECT_EQ(ekf.stats(MeasurementType::kPositionFix).reopened, 1U);
}

// Measurements that arrive late are fused at their capture times: the
// result equals processing every input in time order. Two late ones, the
// second replaying over the first's replay.
TEST(PoseEkf, LateMeasurementsEqualInOrder) {
  const auto run = [](bool late) {
    PoseEkf ekf;
    ekf.initialise(0, pose(0, 0, 0.2), Vector3(0.01, 0.01, 0.001).asDiagonal());
    const PositionFix fix{Vector2(0.26, 0.07), Matrix2::Identity() * 4e-4};
    const HeadingFix heading{0.25, 0.02};
    for (int k = 1; k <= 50; ++k) {
      ekf.predict(k * 0.01, Increment{Vector3(0.01, 0, 0.001)});
      if (!late && k == 25)
        ekf.update(0.255, fix);
      if (!late && k == 30)
        ekf.update(0.30, heading);
    }
    if (late) {
      EXPECT_EQ(ekf.update(0.255, fix), Outcome::kAccepted);
      EXPECT_EQ(ekf.update(0.30, heading), Outcome::kAccepted);
    }
    EXPECT_LE(ekf.history_length(), 52U);  // 0.5 s of inputs, within history_s
    return ekf.estimate();
  };
  const Estimate in_order = run(false), late = run(true);
  EXPECT_LT((in_order.pose.x - late.pose.x).norm(), 1e-12);
  EXPECT_LT((in_order.covariance - late.covariance).norm(), 1e-14);
  EXPECT_EQ(in_order.time_s, late.time_s);
}

// The history holds history_s of inputs, not the whole drive.
TEST(PoseEkf, HistoryIsBounded) {
  PoseEkf ekf;
  ekf.initialise(0, pose(0, 0, 0), Matrix3::Identity() * 0.01);
  for (int k = 1; k <= 10'000; ++k)
    ekf.predict(k * 0.01, Increment{Vector3(0.01, 0, 0)});
  EXPECT_EQ(ekf.history_length(), 101U);  // 99.00 s to 100.00 s
}

TEST(PoseEkf, TooLateNonFiniteAndUninitialisedChangeNothing) {
  PoseEkf ekf;
  EXPECT_EQ(ekf.update(0, PositionFix{}), Outcome::kNotInitialised);
  EXPECT_EQ(ekf.predict(0, Increment{}), Outcome::kNotInitialised);
  ekf.initialise(0, pose(1, 1, 0), Matrix3::Identity() * 0.01);
  for (int k = 1; k <= 300; ++k)
    ekf.predict(k * 0.01, Increment{Vector3(0.01, 0, 0)});
  const Estimate before = ekf.estimate();
  const double nan = std::nan("");
  EXPECT_EQ(ekf.update(0.5, PositionFix{Vector2(1, 1), Matrix2::Identity()}), Outcome::kTooLate);
  EXPECT_EQ(ekf.update(3, PositionFix{Vector2(nan, 1), Matrix2::Identity()}), Outcome::kNonFinite);
  EXPECT_EQ(ekf.update(3, PositionFix{Vector2(1, 1), -Matrix2::Identity()}), Outcome::kNonFinite);
  EXPECT_EQ(ekf.update(3, HeadingFix{0.1, 0}), Outcome::kNonFinite);
  EXPECT_EQ(ekf.update(nan, HeadingFix{0.1, 0.1}), Outcome::kNonFinite);
  EXPECT_EQ(ekf.predict(3, Increment{Vector3(nan, 0, 0)}), Outcome::kNonFinite);
  EXPECT_EQ(ekf.update(3, RangeSet{}), Outcome::kDegenerate);
  EXPECT_EQ(ekf.update(3, StationBearing{before.pose.position(), 0.1, 0.01}), Outcome::kDegenerate);
  const Estimate after = ekf.estimate();
  EXPECT_EQ(after.pose.x, before.pose.x);
  EXPECT_EQ(after.covariance, before.covariance);
  // Before initialisation, too late, NaN, a negative covariance.
  EXPECT_EQ(ekf.stats(MeasurementType::kPositionFix).refused, 4U);
  EXPECT_THROW(ekf.initialise(0, pose(0, 0, 0), -Matrix3::Identity()), std::invalid_argument);
  EkfOptions bad;
  bad.gate.probability = 1;
  EXPECT_THROW(PoseEkf{bad}, std::invalid_argument);
}

TEST(PoseEkf, TimesOutToOdometryOnlyAndSaysSo) {
  EkfOptions options;
  options.timeout_s = 2;
  PoseEkf ekf(options);
  EXPECT_TRUE(ekf.estimate().odometry_only);  // not initialised
  ekf.initialise(0, pose(0, 0, 0), Matrix3::Identity() * 0.01);
  EXPECT_FALSE(ekf.estimate().odometry_only);
  ekf.predict(1.9, Increment{Vector3(0.5, 0, 0)});
  EXPECT_FALSE(ekf.estimate().odometry_only);
  ekf.predict(2.1, Increment{Vector3(0.1, 0, 0)});
  EXPECT_TRUE(ekf.estimate().odometry_only);
  ekf.update(2.1, PositionFix{Vector2(0.6, 0), Matrix2::Identity() * 0.01});
  EXPECT_FALSE(ekf.estimate().odometry_only);
  EXPECT_EQ(ekf.estimate().last_absolute_s, 2.1);
}

// Thousands of near-exact fixes and headings never drive the covariance to
// zero or below: every eigenvalue stays at least min_variance.
TEST(PoseEkf, CovarianceNeverCollapses) {
  PoseEkf ekf;
  ekf.initialise(0, pose(0, 0, 0), Matrix3::Identity());
  for (int k = 1; k <= 5000; ++k) {
    ekf.update(k * 1e-3, PositionFix{Vector2(0, 0), Matrix2::Identity() * 1e-20});
    ekf.update(k * 1e-3, HeadingFix{0, 1e-10});
    const Eigen::SelfAdjointEigenSolver<Matrix3> eig(ekf.estimate().covariance);
    ASSERT_GE(eig.eigenvalues().minCoeff(), ekf.options().min_variance * (1 - 1e-9)) << k;
    ASSERT_TRUE(ekf.estimate().covariance.isApprox(ekf.estimate().covariance.transpose()));
  }
}

}  // namespace
