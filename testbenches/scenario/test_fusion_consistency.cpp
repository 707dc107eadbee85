// Consistency of the pose EKF by Monte Carlo (label scenario): a robot
// drives curves in Kleeman's 10 m room; the odometry increments carry
// exactly the noise the filter models; every 0.5 s a beacon cycle of six
// ranges with a random common offset (some beacons heard by an echo, up to
// 1 m long) and every 1 s a heading from directions of arrival. Over the
// runs, the average NEES (normalised estimation error squared) and the
// average NIS of the heading updates stay within their two-sided 95 %
// chi-square bounds (Bar-Shalom, Li and Kirubarajan, sec. 5.4), and a
// robot carried 1.5 m is found again: the gate does not lock it out.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "odoloc/sw/pose_ekf.hpp"

namespace {

using namespace odoloc::sw::fuse;

constexpr int kRuns = 100;
constexpr double kStepS = 0.01;
constexpr int kSteps = 6000;        // 60 s
constexpr int kCycleSteps = 50;     // a beacon cycle every 0.5 s
constexpr int kHeadingSteps = 100;  // a heading every 1 s
constexpr double kRangeSd = 0.005;
constexpr double kHeadingSd = 0.02;
constexpr double kBeaconHeight = 2.5;

const std::vector<Vector2>& beacons() {
  static const std::vector<Vector2> b = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {5, 0}, {5, 10}};
  return b;
}

struct Options {
  double echo_probability = 0;
  int kidnap_step = -1;  // the truth jumps 1.5 m here, the odometry does not see it
};

// Per check time (after each beacon cycle): NEES summed over the runs; per
// heading update: NIS summed over the runs. Also the error after a kidnap.
struct Sums {
  std::vector<double> nees;
  std::vector<double> nis;
  std::vector<double> error_after_kidnap_m;
  std::uint64_t gated_ranges = 0, accepted_ranges = 0, reopened = 0;
};

void run_once(std::mt19937_64& rng, const Options& o, Sums& sums) {
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u01;
  const EkfOptions ekf_options;
  const OdometryNoise& q = ekf_options.odometry;
  PoseEkf ekf(ekf_options);
  Pose truth;
  truth.x =
      Vector3(4 + 2 * u01(rng), 4 + 2 * u01(rng), wrap_angle(2 * std::numbers::pi * u01(rng)));
  const Vector3 start_sd(0.01, 0.01, 0.05);  // as after a solver's fix
  Pose start = truth;
  start.x += start_sd.cwiseProduct(Vector3(n01(rng), n01(rng), n01(rng)));
  ekf.initialise(0, start, start_sd.cwiseAbs2().asDiagonal());
  std::size_t check = 0, heading_update = 0;
  for (int k = 1; k <= kSteps; ++k) {
    const double t = k * kStepS;
    // A slalom at 0.5 m/s, turning towards the room's centre.
    const double speed = 0.5;
    const Vector2 to_centre = Vector2(5, 5) - truth.position();
    const double bearing = std::atan2(to_centre.y(), to_centre.x());
    const double turn = 0.6 * std::sin(0.3 * t) + 0.5 * wrap_angle(bearing - truth.heading());
    const Vector3 d(speed * kStepS, 0, turn * kStepS);
    const double dist = d.head<2>().norm();
    const double f2 = q.floor_sd * q.floor_sd;
    const Vector3 sd(
        std::sqrt(q.along_sd_per_sqrt_m * q.along_sd_per_sqrt_m * dist + f2),
        std::sqrt(q.across_sd_per_sqrt_m * q.across_sd_per_sqrt_m * dist + f2),
        std::sqrt(q.heading_sd_per_sqrt_m * q.heading_sd_per_sqrt_m * dist +
                  q.heading_sd_per_sqrt_rad * q.heading_sd_per_sqrt_rad * std::abs(d.z()) + f2));
    // The odometry measures d; the robot moved d plus the noise.
    truth = compose(truth, d + sd.cwiseProduct(Vector3(n01(rng), n01(rng), n01(rng))));
    if (k == o.kidnap_step)
      truth.x.head<2>() += Vector2(1.5, 0);
    ekf.predict(t, Increment{d});
    if (k % kCycleSteps == 0) {
      RangeSet set;
      const double offset = 3 * u01(rng);
      for (const Vector2& b : beacons()) {
        double r = std::sqrt((truth.position() - b).squaredNorm() + kBeaconHeight * kBeaconHeight);
        if (u01(rng) < o.echo_probability)
          r += 0.2 + 0.8 * u01(rng);  // the first arrival is a wall echo
        set.ranges.push_back({b, kBeaconHeight, r + offset + kRangeSd * n01(rng), kRangeSd});
      }
      ekf.update(t, set);
      const Estimate e = ekf.estimate();
      Vector3 err = e.pose.x - truth.x;
      err(2) = wrap_angle(err(2));
      if (check == sums.nees.size())
        sums.nees.push_back(0);
      sums.nees[check++] += err.dot(e.covariance.ldlt().solve(err));
      if (o.kidnap_step > 0 && k >= o.kidnap_step)
        sums.error_after_kidnap_m.push_back(err.head<2>().norm());
    }
    if (k % kHeadingSteps == 0) {
      ekf.update(t, HeadingFix{wrap_angle(truth.heading() + kHeadingSd * n01(rng)), kHeadingSd});
      if (heading_update == sums.nis.size())
        sums.nis.push_back(0);
      sums.nis[heading_update++] += ekf.stats(MeasurementType::kHeading).last_nis;
    }
  }
  sums.gated_ranges += ekf.stats(MeasurementType::kBeaconRange).gated;
  sums.accepted_ranges += ekf.stats(MeasurementType::kBeaconRange).accepted;
  for (std::size_t i = 0; i < kMeasurementTypes; ++i)
    sums.reopened += ekf.stats(static_cast<MeasurementType>(i)).reopened;
}

// Share of the averages inside the two-sided 95 % bounds of
// chi-square(dof * runs) / runs.
double share_inside(const std::vector<double>& sums, int dof) {
  const double lo = chi_square_quantile(0.025, dof * kRuns) / kRuns;
  const double hi = chi_square_quantile(0.975, dof * kRuns) / kRuns;
  int inside = 0;
  for (const double s : sums) {
    const double mean = s / kRuns;
    inside += mean >= lo && mean <= hi ? 1 : 0;
  }
  return static_cast<double>(inside) / static_cast<double>(sums.size());
}

class FusionConsistency : public ::testing::TestWithParam<double> {};

TEST_P(FusionConsistency, NeesAndNisWithinTheir95PercentBounds) {
  const double echo_probability = GetParam();
  std::mt19937_64 rng(echo_probability > 0 ? 22 : 21);
  Sums sums;
  for (int r = 0; r < kRuns; ++r)
    run_once(rng, {.echo_probability = echo_probability, .kidnap_step = -1}, sums);
  // 95 % of the points of a consistent filter fall inside: ask for 90 %
  // (2.5 sigma of the binomial below 95 % over 120 points), 85 % with
  // echoes (a cycle whose echoes fit each other can pass the gate).
  const double nees_inside = share_inside(sums.nees, 3);
  const double nis_inside = share_inside(sums.nis, 1);
  const double least = echo_probability > 0 ? 0.85 : 0.90;
  EXPECT_GE(nees_inside, least) << "NEES, echo probability " << echo_probability;
  EXPECT_GE(nis_inside, least) << "NIS, echo probability " << echo_probability;
  // The time average over every point and run: chi-square(3 N T) / (N T).
  double total = 0;
  for (const double s : sums.nees)
    total += s;
  const auto points = static_cast<int>(sums.nees.size()) * kRuns;
  EXPECT_GE(total / points, chi_square_quantile(0.025, 3 * points) / points);
  EXPECT_LE(total / points, chi_square_quantile(0.975, 3 * points) / points);
  // Echoes are the gated ones: as many as were made, give or take.
  const double cycles = static_cast<double>(sums.nees.size()) * kRuns;
  const double echoes = cycles * 6 * echo_probability;
  EXPECT_NEAR(static_cast<double>(sums.gated_ranges), echoes,
              4 * std::sqrt(echoes) + 0.005 * cycles * 6);
  EXPECT_EQ(sums.reopened, 0U);
  std::printf(
      "echo probability %.1f: average NEES %.3f (95 %% bounds %.3f to %.3f), %.1f %% of "
      "the %zu check times inside; heading NIS inside %.1f %%; %llu of %llu ranges gated\n",
      echo_probability, total / points, chi_square_quantile(0.025, 3 * points) / points,
      chi_square_quantile(0.975, 3 * points) / points, 100 * nees_inside, sums.nees.size(),
      100 * nis_inside, static_cast<unsigned long long>(sums.gated_ranges),
      static_cast<unsigned long long>(sums.gated_ranges + sums.accepted_ranges));
}

INSTANTIATE_TEST_SUITE_P(CleanAndEchoes, FusionConsistency, ::testing::Values(0.0, 0.2));

// The robot is carried 1.5 m at 20 s: its ranges are gated, then let back in,
// and within 5 s of the jump every run is back within 5 cm.
TEST(FusionConsistency, KidnappedRobotIsFoundAgain) {
  std::mt19937_64 rng(23);
  for (int r = 0; r < 20; ++r) {
    Sums sums;
    run_once(rng, {.echo_probability = 0, .kidnap_step = 2000}, sums);
    ASSERT_GE(sums.reopened, 1U) << "run " << r;
    // Cycles every 0.5 s from the jump: the 11th is 5 s after it.
    ASSERT_GT(sums.error_after_kidnap_m.size(), 11U);
    for (std::size_t i = 10; i < sums.error_after_kidnap_m.size(); ++i)
      ASSERT_LT(sums.error_after_kidnap_m[i], 0.05) << "run " << r << ", cycle " << i;
  }
}

}  // namespace
