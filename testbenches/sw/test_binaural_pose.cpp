// Binaural relative pose (soc_software binaural_pose): two robots, each a
// transmitter at its origin and a receiver pair at (-b/2, 0), (+b/2, 0)
// looking along +y. The pair results are built from the exact geometry of a
// known relative pose in long double (robot 2's frame is the world; robot 1
// at (x, y) with its x axis at q + pi), then checked: exact recovery over
// the paper's range, the paper's special cases, noisy seeded cases whose
// errors match the propagated covariance (normalised error squared), the
// singular configurations, bad input.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "odoloc/sw/binaural_pose.hpp"
#include "odoloc/sw/tof_doa.hpp"

namespace {

namespace locate = odoloc::sw::locate;
namespace tof = odoloc::sw::tof;
using LD = long double;
using locate::BinauralReason;
constexpr LD kPiL = std::numbers::pi_v<LD>;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;

constexpr LD kC = 343.2L;
constexpr LD kB = 0.35L;

struct Noise {
  double range_sd_m = 0;  // per coarse range
  double phase_sd_m = 0;  // on the path difference
};

// What robot j's pair measures of a transmitter at (tx, ty) in its frame.
tof::BinauralPairResult hear(LD tx, LD ty, std::mt19937_64* rng = nullptr, Noise noise = {},
                             double reported_phase_sd_m = 10e-6) {
  const LD left = std::hypot(tx + kB / 2, ty);
  const LD right = std::hypot(tx - kB / 2, ty);
  double n_left = 0, n_right = 0, n_phase = 0;
  if (rng != nullptr) {
    std::normal_distribution<double> g(0, 1);
    n_left = noise.range_sd_m * g(*rng);
    n_right = noise.range_sd_m * g(*rng);
    n_phase = noise.phase_sd_m * g(*rng);
  }
  tof::BinauralPairResult r;
  r.tof_left_s = static_cast<double>((left + n_left) / kC);
  r.tof_right_s = static_cast<double>((right + n_right) / kC);
  r.coarse_difference_s = r.tof_left_s - r.tof_right_s;
  r.path_difference_m = static_cast<double>(left - right) + n_phase;
  r.difference_s = r.path_difference_m / static_cast<double>(kC);
  r.difference_sd_s = reported_phase_sd_m / static_cast<double>(kC);
  return r;
}

// Robot 1 at (x, y) in robot 2's frame, its x axis at q + pi.
struct Relative {
  LD x, y, q;
  // Robot 2's transmitter (robot 2's origin) in robot 1's frame: R(-phi)(-p).
  [[nodiscard]] std::pair<LD, LD> robot2_in_robot1() const {
    const LD phi = q + kPiL;
    return {-(std::cos(phi) * x + std::sin(phi) * y), -(-std::sin(phi) * x + std::cos(phi) * y)};
  }
};

locate::RelativePose measure(const Relative& r, std::mt19937_64* rng = nullptr, Noise noise = {},
                             const locate::BinauralOptions& options = {}) {
  const auto [x2, y2] = r.robot2_in_robot1();
  return locate::relative_pose(hear(r.x, r.y, rng, noise), hear(x2, y2, rng, noise), options);
}

locate::BinauralOptions options_for(Noise noise) {
  locate::BinauralOptions o;
  o.range_sd_m = noise.range_sd_m;
  return o;
}

TEST(BinauralPose, ExactGeometryOverThePapersRange) {
  int cases = 0;
  // Sec. 4: 0.5-5.5 m apart, sideways up to 0.3 m at 1.5 m, relative
  // orientation +-25 deg (and beyond, flagged).
  for (const LD distance : {0.5L, 1.0L, 1.5L, 3.0L, 5.5L})
    for (const LD lateral : {-0.3L, -0.1L, 0.0L, 0.05L, 0.3L})
      for (const LD q_deg : {-40.0L, -24.9L, -9.5L, 0.0L, 3.0L, 24.9L, 40.0L}) {
        const Relative r{lateral, distance, q_deg * kPiL / 180};
        const locate::RelativePose pose = measure(r);
        ASSERT_TRUE(pose.valid) << locate::name(pose.reason);
        EXPECT_NEAR(pose.robot1_in_robot2.position_m.x, static_cast<double>(r.x), 1e-9);
        EXPECT_NEAR(pose.robot1_in_robot2.position_m.y, static_cast<double>(r.y), 1e-9);
        EXPECT_NEAR(tof::angle_difference(pose.relative_orientation_rad, static_cast<double>(r.q)),
                    0, 1e-9);
        EXPECT_NEAR(tof::angle_difference(pose.heading_rad(), static_cast<double>(r.q + kPiL)), 0,
                    1e-9);
        const auto [x2, y2] = r.robot2_in_robot1();
        EXPECT_NEAR(pose.a1_rad, static_cast<double>(std::atan2(r.x, r.y)), 1e-9);
        EXPECT_NEAR(pose.a2_rad, static_cast<double>(std::atan2(y2, x2)), 1e-9);
        EXPECT_TRUE(pose.robot1_in_robot2.phase_used);
        EXPECT_EQ(pose.beyond_orientation_limit, std::abs(q_deg) > 25.0L);
        EXPECT_NEAR(pose.distance_mismatch_m, 0, 1e-9);
        // Seen from robot 1 the orientation is the opposite.
        const locate::RelativePose back = locate::relative_pose(hear(x2, y2), hear(r.x, r.y));
        EXPECT_NEAR(back.relative_orientation_rad, -pose.relative_orientation_rad, 1e-9);
        ++cases;
      }
  EXPECT_EQ(cases, 175);
}

TEST(BinauralPose, ThePapersSpecialCases) {
  // Aligned, facing each other: a1 = 0, a2 = 90 deg, q = 0 (the text says
  // a1 = a2 = 90 deg, which eq. 9 does not give).
  const locate::RelativePose aligned = measure({0, 1.5L, 0});
  ASSERT_TRUE(aligned.valid);
  EXPECT_NEAR(aligned.a1_rad, 0, 1e-12);
  EXPECT_NEAR(aligned.a2_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(aligned.relative_orientation_rad, 0, 1e-12);
  // Parallel with a lateral offset: a1 + a2 = 90 deg, q = 0; robot 1 sees
  // robot 2 where robot 2 sees robot 1 ("symmetric").
  const locate::RelativePose offset = measure({0.3L, 1.5L, 0});
  EXPECT_NEAR(offset.a1_rad + offset.a2_rad, kPi / 2, 1e-12);
  EXPECT_NEAR(offset.robot2_in_robot1.position_m.x, 0.3, 1e-12);
  EXPECT_NEAR(offset.robot2_in_robot1.position_m.y, 1.5, 1e-12);
  // Aligned, robot 1 turned by q: a1 = 0 and q = 90 deg - a2.
  const locate::RelativePose turned = measure({0, 1.443L, 9.5L * kPiL / 180});
  EXPECT_NEAR(turned.a1_rad, 0, 1e-12);
  EXPECT_NEAR(turned.relative_orientation_rad, kPi / 2 - turned.a2_rad, 1e-12);
  EXPECT_NEAR(turned.relative_orientation_rad, 9.5 * kDeg, 1e-12);
  // Robot 2 on robot 1's left (X'_2 < 0): the printed tan^-1 would put a2
  // in the wrong quadrant (q off by 180 deg); atan2 does not.
  const locate::RelativePose left = measure({0.2L, 1.5L, -20 * kPiL / 180});
  ASSERT_LT(left.robot2_in_robot1.position_m.x, 0);
  EXPECT_NEAR(left.relative_orientation_rad, -20 * kDeg, 1e-12);
}

// Normalised error squared of (x, y, q) against the reported covariance,
// averaged over n seeded trials: chi^2 with 3n degrees of freedom.
double mean_nees(Noise noise, bool phase, int n, std::uint64_t seed, double* q_rms = nullptr) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  double sum = 0, q2 = 0;
  locate::BinauralOptions options = options_for(noise);
  for (int i = 0; i < n; ++i) {
    const Relative r{-0.3L + 0.6L * u(rng), 0.8L + 3.0L * u(rng), (-25 + 50 * u(rng)) * kPiL / 180};
    const auto [x2, y2] = r.robot2_in_robot1();
    tof::BinauralPairResult a = hear(r.x, r.y, &rng, noise, noise.phase_sd_m);
    tof::BinauralPairResult b = hear(x2, y2, &rng, noise, noise.phase_sd_m);
    if (!phase) {
      a.flags.set(tof::Flag::kAmbiguous);
      b.flags.set(tof::Flag::kAmbiguous);
    }
    const locate::RelativePose pose = locate::relative_pose(a, b, options);
    EXPECT_TRUE(pose.robot1_in_robot2.valid && pose.robot2_in_robot1.valid);
    EXPECT_EQ(pose.robot1_in_robot2.phase_used, phase);
    const Eigen::Vector3d e(
        pose.robot1_in_robot2.position_m.x - static_cast<double>(r.x),
        pose.robot1_in_robot2.position_m.y - static_cast<double>(r.y),
        tof::angle_difference(pose.relative_orientation_rad, static_cast<double>(r.q)));
    sum += e.dot(pose.covariance.ldlt().solve(e));
    q2 += e.z() * e.z();
  }
  if (q_rms != nullptr)
    *q_rms = std::sqrt(q2 / n);
  return sum / n;
}

TEST(BinauralPose, NoisyErrorsMatchThePropagatedCovariance) {
  constexpr int kTrials = 3000;
  // chi^2(3n)/n: mean 3, sd sqrt(6/n); 3.3 sd is the 99.9 % interval.
  const double tolerance = 3.3 * std::sqrt(6.0 / kTrials);
  double q_rms_phase = 0, q_rms_coarse = 0;
  const double with_phase = mean_nees({3e-3, 10e-6}, true, kTrials, 11, &q_rms_phase);
  const double coarse_only = mean_nees({3e-3, 10e-6}, false, kTrials, 12, &q_rms_coarse);
  std::printf(
      "binaural NEES (3 dof): %.3f with phase (q rms %.4f deg), %.3f coarse only "
      "(q rms %.3f deg)\n",
      with_phase, q_rms_phase / kDeg, coarse_only, q_rms_coarse / kDeg);
  EXPECT_NEAR(with_phase, 3.0, tolerance);
  EXPECT_NEAR(coarse_only, 3.0, tolerance);
  // The phase is what makes the orientation good (paper: +-0.05 deg).
  EXPECT_LT(q_rms_phase, 0.01 * kDeg);
  EXPECT_GT(q_rms_coarse, 20 * q_rms_phase);
}

TEST(BinauralPose, SingularConfigurations) {
  // The transmitter on the baseline's extension: tangent circles.
  const locate::TransmitterFix axis = locate::locate_transmitter(hear(2.0L, 0));
  EXPECT_FALSE(axis.valid);
  EXPECT_EQ(axis.reason, BinauralReason::kOnBaselineAxis);
  // Just off the axis, within the noise of front/back: still unresolved.
  locate::BinauralOptions noisy;
  noisy.range_sd_m = 3e-3;
  EXPECT_EQ(locate::locate_transmitter(hear(2.0L, 0.01L), noisy).reason,
            BinauralReason::kOnBaselineAxis);
  EXPECT_TRUE(locate::locate_transmitter(hear(2.0L, 0.3L), noisy).valid);
  // An echo on the left receiver: its range exceeds the right's by more than b.
  tof::BinauralPairResult echo = hear(0.1L, 1.5L);
  echo.tof_left_s += 0.5 / static_cast<double>(kC);
  echo.path_difference_m += 0.5;
  EXPECT_EQ(locate::locate_transmitter(echo).reason, BinauralReason::kNoIntersection);
  // Both ranges shorter than half the baseline: the circles do not meet.
  tof::BinauralPairResult short_ranges = hear(0, 1);
  short_ranges.tof_left_s = short_ranges.tof_right_s = 0.1 / static_cast<double>(kC);
  short_ranges.path_difference_m = 0;
  EXPECT_EQ(locate::locate_transmitter(short_ranges).reason, BinauralReason::kNoIntersection);
}

TEST(BinauralPose, OrientationLimitIsFlaggedNotRejected) {
  const locate::RelativePose inside = measure({0, 1.5L, 24 * kPiL / 180});
  const locate::RelativePose outside = measure({0, 1.5L, -26 * kPiL / 180});
  EXPECT_TRUE(inside.valid);
  EXPECT_FALSE(inside.beyond_orientation_limit);
  EXPECT_TRUE(outside.valid);
  EXPECT_TRUE(outside.beyond_orientation_limit);
  locate::BinauralOptions wide;
  wide.max_relative_orientation_rad = 30 * kDeg;
  EXPECT_FALSE(measure({0, 1.5L, -26 * kPiL / 180}, nullptr, {}, wide).beyond_orientation_limit);
}

TEST(BinauralPose, DistancesThatDisagreeAreInconsistent) {
  const Relative r{0.1L, 2.0L, 5 * kPiL / 180};
  const auto [x2, y2] = r.robot2_in_robot1();
  tof::BinauralPairResult far = hear(x2, y2);
  far.tof_left_s += 0.05 / static_cast<double>(kC);  // both 5 cm long: a delay miscalibrated
  far.tof_right_s += 0.05 / static_cast<double>(kC);
  const locate::RelativePose pose = locate::relative_pose(hear(r.x, r.y), far);
  EXPECT_FALSE(pose.valid);
  EXPECT_EQ(pose.reason, BinauralReason::kInconsistent);
  EXPECT_NEAR(pose.distance_mismatch_m, -0.05, 1e-3);
  EXPECT_TRUE(std::isfinite(pose.relative_orientation_rad));  // kept for the caller
}

TEST(BinauralPose, MissingAndNonFiniteInput) {
  tof::BinauralPairResult missing;  // tof's silent receiver: kMissing | kInvalid, NaN times
  missing.flags.set(tof::Flag::kMissing).set(tof::Flag::kInvalid);
  EXPECT_EQ(locate::locate_transmitter(missing).reason, BinauralReason::kMissingData);
  tof::BinauralPairResult nan = hear(0, 1.5L);
  nan.tof_right_s = std::nan("");
  EXPECT_EQ(locate::locate_transmitter(nan).reason, BinauralReason::kNonFiniteInput);
  tof::BinauralPairResult inf = hear(0, 1.5L);
  inf.tof_left_s = INFINITY;
  EXPECT_EQ(locate::locate_transmitter(inf).reason, BinauralReason::kNonFiniteInput);
  // No common carrier edge (tof: kInvalid, phase NaN): the coarse ranges alone.
  tof::BinauralPairResult coarse = hear(0.2L, 1.5L);
  coarse.path_difference_m = coarse.difference_s = coarse.difference_sd_s = std::nan("");
  coarse.flags.set(tof::Flag::kInvalid);
  const locate::TransmitterFix fix = locate::locate_transmitter(coarse);
  EXPECT_TRUE(fix.valid);
  EXPECT_FALSE(fix.phase_used);
  EXPECT_NEAR(fix.position_m.x, 0.2, 1e-9);
  EXPECT_NEAR(fix.path_difference_sd_m, std::sqrt(2.0) * 3e-3, 1e-12);
  // A relative pose with one pair missing takes that pair's reason.
  const locate::RelativePose pose = locate::relative_pose(hear(0, 1.5L), missing);
  EXPECT_FALSE(pose.valid);
  EXPECT_EQ(pose.reason, BinauralReason::kMissingData);
  EXPECT_TRUE(pose.robot1_in_robot2.valid);
  // The flags travel with the fix.
  tof::BinauralPairResult unverified = hear(0, 1.5L);
  unverified.flags.set(tof::Flag::kCycleUnverified);
  EXPECT_TRUE(locate::locate_transmitter(unverified).flags.has(tof::Flag::kCycleUnverified));
}

TEST(BinauralPose, InvalidOptionsThrow) {
  const tof::BinauralPairResult r = hear(0, 1.5L);
  for (const auto& bad : std::initializer_list<void (*)(locate::BinauralOptions&)>{
           [](locate::BinauralOptions& o) { o.baseline_m = 0; },
           [](locate::BinauralOptions& o) { o.speed_of_sound_mps = std::nan(""); },
           [](locate::BinauralOptions& o) { o.range_sd_m = -1; },
           [](locate::BinauralOptions& o) { o.min_path_difference_sd_m = 0; },
           [](locate::BinauralOptions& o) { o.gate_sigmas = 0; },
           [](locate::BinauralOptions& o) { o.max_relative_orientation_rad = 4; }}) {
    locate::BinauralOptions o;
    bad(o);
    EXPECT_THROW(locate::locate_transmitter(r, o), std::invalid_argument);
  }
}

}  // namespace
