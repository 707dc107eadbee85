// Kleeman's stationary experiment as shipped (examples/scenarios/
// kleeman-stationary.yaml), run through the whole system: the robot
// standing at his three points, the spread of the ultrasonic fixes alone
// against the Cramer-Rao bound of the geometry and the world's noise,
// computed here from first principles (not by the SoC's solver).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "odoloc/sim/stationary.hpp"

namespace {

using odoloc::sim::Scenario;

// The fixes' covariance at `p` when every beacon's range has the sd
// sigma_m and an unknown common offset (Kleeman's robot has no link to the
// beacons: the emission time is not known, so each range is the flight
// distance plus one shared offset): sigma^2 ((H^T H)^-1), H's rows
// [u_x, u_y, 1] with u the unit vector from the beacon to the robot.
Eigen::Matrix2d cramer_rao(const Scenario& s, odoloc::world::Vec2 p, double sigma_m) {
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < s.tour.timing.beacon_count; ++i) {
    const odoloc::world::Vec2 b = s.tour.acoustics.beacons[i].position;
    const double d = std::hypot(p.x_m - b.x_m, p.y_m - b.y_m);
    const Eigen::Vector3d h((p.x_m - b.x_m) / d, (p.y_m - b.y_m) / d, 1);
    information += h * h.transpose();
  }
  return sigma_m * sigma_m * information.inverse().topLeftCorner<2, 2>();
}

// A spread that one wrong fix cannot move: 1.4826 x the median absolute
// deviation from the median, which is the standard deviation for Gaussian
// samples. Also counts the samples beyond 6 such deviations.
struct RobustSpread {
  double median = 0;
  double sd = 0;
  int outliers = 0;
};
RobustSpread robust(std::vector<double> v) {
  const auto median = [](std::vector<double> x) {
    std::sort(x.begin(), x.end());
    const std::size_t n = x.size();
    return n % 2 == 1 ? x[n / 2] : (x[n / 2 - 1] + x[n / 2]) / 2;
  };
  RobustSpread r;
  r.median = median(v);
  std::vector<double> deviation;
  for (const double x : v)
    deviation.push_back(std::abs(x - r.median));
  r.sd = 1.4826 * median(deviation);
  for (const double d : deviation)
    r.outliers += d > 6 * r.sd ? 1 : 0;
  return r;
}

TEST(KleemanStationary, FixSpreadAtHisPointsIsTheCramerRaoBound) {
  const odoloc::sim::BuiltinScenario* file =
      odoloc::sim::find_builtin_scenario("kleeman-stationary.yaml");
  ASSERT_NE(file, nullptr);
  const Scenario s = odoloc::sim::parse_scenario(std::string(file->text), file->key);
  ASSERT_TRUE(s.stationary.has_value());
  ASSERT_EQ(s.stationary->points.size(), 3U);
  // The range noise: the turbulence's delay per path, common to the
  // receivers, and one per receiver, averaged over the two or three that
  // hear a beacon (k = 2 here; k = 1 to 8 moves sigma by under 5 %).
  const odoloc::world::AcousticNoise& n = s.tour.acoustics.noise;
  const double c = s.tour.acoustics.air.speed_of_sound_mps();
  const double sigma_m = c * std::sqrt(n.path_jitter_sd_s * n.path_jitter_sd_s +
                                       n.receiver_jitter_sd_s * n.receiver_jitter_sd_s / 2);
  constexpr std::size_t kFixes = 80;  // the paper's 532 to 1684 take minutes
  for (const odoloc::sim::StandingPoint& point : s.stationary->points) {
    const odoloc::sim::Standing r = odoloc::sim::measure_standing(
        s, point.position, kFixes, {.seed = s.seed, .encoder_period_s = 1.0});
    ASSERT_EQ(r.fixes.size(), kFixes) << r.cycles << " cycles";
    const Eigen::Matrix2d bound = cramer_rao(s, point.position, sigma_m);
    const double sd_x = std::sqrt(bound(0, 0)), sd_y = std::sqrt(bound(1, 1));
    std::vector<double> xs, ys;
    for (const odoloc::world::Vec2& f : r.fixes) {
      xs.push_back(f.x_m);
      ys.push_back(f.y_m);
    }
    const RobustSpread x = robust(xs), y = robust(ys);
    std::printf(
        "(%.3f, %.3f): sd x %.2f mm (robust %.2f, bound %.2f), sd y %.2f mm (robust "
        "%.2f, bound %.2f), median error %.2f mm, %d outliers, worst %.1f mm\n",
        point.position.x_m, point.position.y_m, r.sd_m.x_m * 1e3, x.sd * 1e3, sd_x * 1e3,
        r.sd_m.y_m * 1e3, y.sd * 1e3, sd_y * 1e3,
        std::hypot(x.median - point.position.x_m, y.median - point.position.y_m) * 1e3,
        x.outliers + y.outliers, r.worst_m * 1e3);
    // An efficient estimator meets the bound. The robust sd of 80 fixes
    // has a relative sd of about 1.65/sqrt(2 x 79) = 13 %, so 0.6 is beyond
    // 3 sigma below; above, 1.7 leaves room for the chain's own error,
    // which the bound leaves out (the 20 ns capture tick, the envelope's
    // threshold delay per receiver). Measured: 0.76 to 1.18 (seeds 1, 7).
    EXPECT_GT(x.sd, 0.6 * sd_x);
    EXPECT_LT(x.sd, 1.7 * sd_x);
    EXPECT_GT(y.sd, 0.6 * sd_y);
    EXPECT_LT(y.sd, 1.7 * sd_y);
    // A wrong fix (a noise pulse or an echo taken for an arrival: the world
    // sends 0.5 noise pulses a second per channel) is rare: one in 80 (it
    // counts in x and in y).
    EXPECT_LE(x.outliers + y.outliers, 2);
    // The median: within 4 of its standard errors (1.25 sd / sqrt(n)), plus
    // 1 mm of the chain's systematic error, which the bound does not model
    // either: a threshold delay that depends on each beacon's amplitude
    // beyond the decoder's envelope model. Measured 0.05 to 0.27 mm (seeds
    // 1, 7); with Kleeman's 12.5 V (fainter beacons) it was 1.5 mm at his
    // second point.
    const double standard_error = 1.25 / std::sqrt(static_cast<double>(kFixes));
    EXPECT_LT(std::abs(x.median - point.position.x_m), 4 * sd_x * standard_error + 1e-3);
    EXPECT_LT(std::abs(y.median - point.position.y_m), 4 * sd_y * standard_error + 1e-3);
  }
}

}  // namespace
