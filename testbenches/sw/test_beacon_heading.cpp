// Heading from directions of arrival (soc_software beacon_heading):
// Kleeman's six beacons (tb::kleeman_layout, as the acoustic world places them), bearings computed
// in long double from a known pose, optionally with seeded DOA noise and a position error drawn
// from the fix's covariance. Checked: exact recovery at every heading including +-pi, the +-pi cut
// inside the averaging, errors against the propagated sd (normalised error squared, position
// covariance included), outlier rejection, and every way the input can be unusable.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "beacon_geometry.hpp"
#include "odoloc/sw/beacon_heading.hpp"
#include "odoloc/sw/tof_doa.hpp"

namespace {

namespace locate = odoloc::sw::locate;
namespace tof = odoloc::sw::tof;
using LD = long double;
using locate::DoaStatus;
using locate::HeadingReason;
constexpr LD kPiL = std::numbers::pi_v<LD>;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;

using odoloc::tb::kleeman_layout;

// A valid fix at p with covariance cov.
locate::Fix fix_at(double x, double y, const Eigen::Matrix2d& cov = Eigen::Matrix2d::Zero()) {
  locate::Fix fix;
  fix.valid = true;
  fix.reason = locate::NoFixReason::kNone;
  fix.position_m = {x, y};
  fix.covariance_m2 = cov;
  return fix;
}

// The exact bearing of every beacon from the robot at (x, y, theta), robot
// frame, in (-pi, pi].
std::vector<tof::Doa> exact_doas(const locate::BeaconLayout& layout, LD x, LD y, LD theta,
                                 double sd_rad) {
  std::vector<tof::Doa> doas;
  for (const locate::Beacon& b : layout.beacons) {
    const LD psi = std::atan2(b.position_m.y - y, b.position_m.x - x);
    LD bearing = std::remainder(psi - theta, 2 * kPiL);
    if (bearing <= -kPiL)
      bearing += 2 * kPiL;
    doas.push_back({true, static_cast<double>(bearing), sd_rad, 0, 3});
  }
  return doas;
}

TEST(BeaconHeading, ExactAtEveryHeadingIncludingPi) {
  const locate::BeaconLayout layout = kleeman_layout();
  std::vector<LD> headings{kPiL, kPiL - 1e-12L, -kPiL + 1e-12L, -kPiL / 2, 0, 1e-12L, 2.0L};
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  for (int i = 0; i < 100; ++i)
    headings.push_back(angle(rng));
  double worst = 0;
  for (const LD theta : headings)
    for (const auto& [x, y] : {std::pair{5.0L, 5.0L}, {1.3L, 8.2L}, {9.0L, 0.7L}}) {
      const locate::Heading h =
          locate::beacon_heading(fix_at(static_cast<double>(x), static_cast<double>(y)), layout,
                                 exact_doas(layout, x, y, theta, 0.5 * kDeg));
      ASSERT_TRUE(h.valid) << locate::name(h.reason);
      worst = std::max(worst,
                       std::abs(tof::angle_difference(h.heading_rad, static_cast<double>(theta))));
      EXPECT_GT(h.heading_rad, -kPi);
      EXPECT_LE(h.heading_rad, kPi);
      EXPECT_EQ(h.used(), 6);
      EXPECT_EQ(h.dof, 5);
      // No position uncertainty: sd = sigma / sqrt(n).
      EXPECT_NEAR(h.sd_rad, 0.5 * kDeg / std::sqrt(6.0), 1e-15);
      EXPECT_LT(h.circular_sd_rad, 1e-9);
    }
  EXPECT_LT(worst, 1e-12);
}

TEST(BeaconHeading, HeadingsStraddlingThePiCut) {
  // Per-beacon headings scattered by 3 deg around pi - 0.5 deg fall on both
  // sides of +-pi; the mean must not collapse toward 0.
  const locate::BeaconLayout layout = kleeman_layout();
  std::mt19937_64 rng(2);
  std::normal_distribution<double> g(0, 3 * kDeg);
  for (const LD theta : {kPiL - 0.5L * kPiL / 180, -kPiL + 0.2L * kPiL / 180, kPiL}) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<tof::Doa> doas = exact_doas(layout, 4, 6, theta, 3 * kDeg);
      for (tof::Doa& d : doas)
        d.bearing_rad = tof::angle_difference(d.bearing_rad + g(rng), 0);
      const locate::Heading h = locate::beacon_heading(fix_at(4, 6), layout, doas);
      ASSERT_TRUE(h.valid) << locate::name(h.reason);
      EXPECT_LT(std::abs(tof::angle_difference(h.heading_rad, static_cast<double>(theta))),
                5 * h.sd_rad);
      EXPECT_GT(h.heading_rad, -kPi);
      EXPECT_LE(h.heading_rad, kPi);
    }
  }
}

TEST(BeaconHeading, NoisyErrorsMatchThePropagatedSd) {
  // The position error is common to every beacon's bearing: drawn from the
  // fix's covariance (5 cm by 3 cm, correlated), DOA noise 0.1-0.5 deg.
  const locate::BeaconLayout layout = kleeman_layout();
  Eigen::Matrix2d cov;
  cov << 2.5e-3, 5e-4, 5e-4, 1e-3;
  const Eigen::Matrix2d chol = cov.llt().matrixL();
  constexpr int kTrials = 4000;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  double nees = 0;
  for (int i = 0; i < kTrials; ++i) {
    const LD x = 1 + 8 * u(rng), y = 1 + 8 * u(rng), theta = (2 * u(rng) - 1) * kPiL;
    std::vector<tof::Doa> doas = exact_doas(layout, x, y, theta, 0);
    for (tof::Doa& d : doas) {
      d.sd_rad = (0.1 + 0.4 * u(rng)) * kDeg;
      d.bearing_rad = tof::angle_difference(d.bearing_rad + d.sd_rad * g(rng), 0);
    }
    const Eigen::Vector2d e = chol * Eigen::Vector2d(g(rng), g(rng));
    const locate::Heading h = locate::beacon_heading(
        fix_at(static_cast<double>(x) + e.x(), static_cast<double>(y) + e.y(), cov), layout, doas);
    const double err = tof::angle_difference(h.heading_rad, static_cast<double>(theta));
    nees += err * err / (h.sd_rad * h.sd_rad);
  }
  nees /= kTrials;
  std::printf("heading NEES (1 dof): %.3f\n", nees);
  EXPECT_NEAR(nees, 1.0, 3.3 * std::sqrt(2.0 / kTrials));
}

TEST(BeaconHeading, EchoDirectionsAreRejected) {
  const locate::BeaconLayout layout = kleeman_layout();
  const LD theta = 2.5L;
  std::vector<tof::Doa> doas = exact_doas(layout, 3, 4, theta, 0.5 * kDeg);
  doas[2].bearing_rad += 25 * kDeg;
  const locate::Heading one = locate::beacon_heading(fix_at(3, 4), layout, doas);
  ASSERT_TRUE(one.valid);
  EXPECT_EQ(one.beacons[2].status, DoaStatus::kOutlier);
  EXPECT_EQ(one.rejected(), 1);
  EXPECT_EQ(one.used(), 5);
  EXPECT_NEAR(one.beacons[2].residual_rad, -25 * kDeg, 1e-9);  // heading_i = psi - beta
  EXPECT_NEAR(tof::angle_difference(one.heading_rad, static_cast<double>(theta)), 0, 1e-12);
  doas[5].bearing_rad -= 40 * kDeg;
  const locate::Heading two = locate::beacon_heading(fix_at(3, 4), layout, doas);
  ASSERT_TRUE(two.valid);
  EXPECT_EQ(two.rejected(), 2);
  EXPECT_EQ(two.beacons[5].status, DoaStatus::kOutlier);
  EXPECT_NEAR(tof::angle_difference(two.heading_rad, static_cast<double>(theta)), 0, 1e-12);
  // Two beacons that disagree: either could be wrong.
  std::vector<tof::Doa> pair(doas.begin(), doas.begin() + 3);
  pair[0].valid = false;
  const locate::Heading split = locate::beacon_heading(fix_at(3, 4), layout, pair);
  EXPECT_FALSE(split.valid);
  EXPECT_EQ(split.reason, HeadingReason::kInconsistent);
  EXPECT_EQ(split.used(), 2);
}

TEST(BeaconHeading, OneBeaconCarriesThePositionUncertainty) {
  const locate::BeaconLayout layout = kleeman_layout();
  Eigen::Matrix2d cov;
  cov << 1e-4, 0, 0, 4e-4;
  std::vector<tof::Doa> doas = exact_doas(layout, 6, 3, -1.0L, 1 * kDeg);
  for (std::size_t i = 1; i < doas.size(); ++i)
    doas[i].valid = false;
  const locate::Heading h = locate::beacon_heading(fix_at(6, 3, cov), layout, doas);
  ASSERT_TRUE(h.valid);
  EXPECT_EQ(h.dof, 0);
  EXPECT_NEAR(h.heading_rad, -1.0, 1e-12);
  // Beacon 0 at (0.05, 0.05): d psi = (dy, -dx) . dP / rho^2.
  const LD dx = 0.05L - 6, dy = 0.05L - 3, rho2 = dx * dx + dy * dy;
  const LD var = (1 * kDeg) * (1 * kDeg) + (dy * dy * 1e-4L + dx * dx * 4e-4L) / (rho2 * rho2);
  EXPECT_NEAR(h.sd_rad, static_cast<double>(std::sqrt(var)), 1e-15);
  EXPECT_EQ(h.beacons[1].status, DoaStatus::kNoDoa);
}

TEST(BeaconHeading, UnusableInput) {
  const locate::BeaconLayout layout = kleeman_layout();
  const std::vector<tof::Doa> good = exact_doas(layout, 5, 5, 0.3L, kDeg);
  // No valid DOA at all.
  std::vector<tof::Doa> none(6);
  EXPECT_EQ(locate::beacon_heading(fix_at(5, 5), layout, none).reason, HeadingReason::kNoValidDoa);
  EXPECT_EQ(locate::beacon_heading(fix_at(5, 5), layout, {}).reason, HeadingReason::kNoValidDoa);
  // NaN bearing, infinite sd, more DOAs than beacons.
  std::vector<tof::Doa> odd = good;
  odd.at(1).bearing_rad = std::nan("");  // at(): GCC 12 sees a null vector in odd[i] here
  odd.at(3).sd_rad = INFINITY;
  odd.push_back(good[0]);
  const locate::Heading h = locate::beacon_heading(fix_at(5, 5), layout, odd);
  ASSERT_TRUE(h.valid);
  EXPECT_EQ(h.beacons[1].status, DoaStatus::kNonFinite);
  EXPECT_EQ(h.beacons[3].status, DoaStatus::kNonFinite);
  EXPECT_EQ(h.beacons[6].status, DoaStatus::kNotInLayout);
  EXPECT_EQ(h.used(), 4);
  EXPECT_NEAR(h.heading_rad, 0.3, 1e-12);
  // No position: invalid fix, NaN position, NaN covariance.
  locate::Fix invalid = fix_at(5, 5);
  invalid.valid = false;
  EXPECT_EQ(locate::beacon_heading(invalid, layout, good).reason, HeadingReason::kNoPosition);
  EXPECT_EQ(locate::beacon_heading(fix_at(std::nan(""), 5), layout, good).reason,
            HeadingReason::kNoPosition);
  EXPECT_EQ(
      locate::beacon_heading(fix_at(5, 5, Eigen::Matrix2d::Constant(std::nan(""))), layout, good)
          .reason,
      HeadingReason::kNoPosition);
  // Standing on a beacon: no bearing to it.
  const locate::Beacon& b0 = layout.beacons[0];
  const std::vector<tof::Doa> at =
      exact_doas(layout, b0.position_m.x + 0.01, b0.position_m.y, 0.3L, kDeg);
  const locate::Heading on =
      locate::beacon_heading(fix_at(b0.position_m.x + 0.01, b0.position_m.y), layout, at);
  EXPECT_TRUE(on.valid);
  EXPECT_EQ(on.beacons[0].status, DoaStatus::kAtBeacon);
  // Bad options throw.
  locate::HeadingOptions options;
  options.outlier_sigmas = 0;
  EXPECT_THROW(locate::beacon_heading(fix_at(5, 5), layout, good, options), std::invalid_argument);
}

TEST(BeaconHeading, UsedDirectionsFollowTheFix) {
  tof::CycleMeasurement cycle;
  cycle.beacons.resize(3);
  for (std::size_t b = 0; b < 3; ++b)
    for (int k = 0; k < 2; ++k) {
      tof::Arrival a;
      a.doa = {true, 0.1 * static_cast<double>(b) + k, 0.01, 0, 3};
      cycle.beacons[b].candidates.push_back(a);
    }
  locate::Fix fix;
  fix.beacons = {{0, locate::BeaconStatus::kUsed, 1},
                 {1, locate::BeaconStatus::kOutlier, -1},
                 {2, locate::BeaconStatus::kUsed, 0}};
  const std::vector<tof::Doa> d = locate::used_directions(cycle, fix);
  ASSERT_EQ(d.size(), 3U);
  EXPECT_TRUE(d[0].valid);
  EXPECT_DOUBLE_EQ(d[0].bearing_rad, 1.0);  // the echo candidate the fix chose
  EXPECT_FALSE(d[1].valid);
  EXPECT_DOUBLE_EQ(d[2].bearing_rad, 0.2);
}

}  // namespace
