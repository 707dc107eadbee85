// Every beacon solver on hostile data (seeded random): NaN, infinities,
// huge and denormal values, negative deviations, primaries out of range,
// random flags, collinear and coincident-looking layouts, zero or one beacon.
// Data never throws; a valid result is finite with a symmetric positive
// definite covariance; every beacon of the input gets exactly one status.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "odoloc/sw/beacon_heading.hpp"
#include "odoloc/sw/binaural_pose.hpp"
#include "odoloc/sw/kleeman_solver.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/sw/thamma_pose.hpp"

namespace {

namespace loc = odoloc::sw::locate;
namespace tof = odoloc::sw::tof;

constexpr double kInf = std::numeric_limits<double>::infinity();

class Hostile {
 public:
  explicit Hostile(std::uint64_t seed) : rng_(seed) {}

  // A plausible value most of the time, a nasty one otherwise.
  double value(double lo, double hi) {
    static constexpr std::array<double, 9> kNasty{
        std::numeric_limits<double>::quiet_NaN(),  kInf,  -kInf, 1e300, -1e300, 0.0, -1.0,
        std::numeric_limits<double>::denorm_min(), 1e-300};
    if (std::uniform_int_distribution<int>(0, 9)(rng_) == 0)
      return kNasty[rng_() % kNasty.size()];
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }

  loc::BeaconLayout layout() {
    loc::BeaconLayout layout;
    const auto n = static_cast<int>(rng_() % 9);
    const bool collinear = rng_() % 4 == 0;
    for (int i = 0; i < n; ++i) {
      const double x = std::uniform_real_distribution<double>(0, 10)(rng_);
      const double y = collinear ? 0.5 * x : std::uniform_real_distribution<double>(0, 10)(rng_);
      const double h = rng_() % 3 == 0 ? std::uniform_real_distribution<double>(0, 2)(rng_) : 0;
      layout.beacons.push_back({{x, y}, h});
    }
    try {
      layout.validate();
    } catch (const std::invalid_argument&) {
      layout.beacons.clear();  // two beacons at one place: configuration, tested elsewhere
    }
    return layout;
  }

  // A third of the sets are a real cycle (a robot inside, 1 mm noise) with at
  // most one nasty value; the rest are garbage.
  loc::RangeSet ranges(const loc::BeaconLayout& layout) {
    if (rng_() % 3 == 0) {
      loc::RangeSet set;
      std::uniform_real_distribution<double> u(1, 9);
      const double x = u(rng_);
      const loc::Vec2 p{x, u(rng_)};
      std::normal_distribution<double> noise(0, 1e-3);
      for (std::size_t i = 0; i < layout.beacons.size(); ++i)
        set.beacons.push_back({{{layout.range_m(i, p) + 1.5 + noise(rng_), 1e-3, {}}}, 0, {}});
      if (!set.beacons.empty() && rng_() % 2 == 0)
        set.beacons[rng_() % set.beacons.size()].candidates[0].distance_m = value(-1e300, 1e300);
      return set;
    }
    const std::size_t beacons = layout.beacons.size();
    loc::RangeSet set;
    set.speed_of_sound_mps = rng_() % 10 == 0 ? value(-1, 1) : 343.2;
    set.beacons.resize(beacons + rng_() % 2);
    for (loc::BeaconRange& b : set.beacons) {
      const auto candidates = rng_() % 4;
      for (std::uint64_t c = 0; c < candidates; ++c)
        b.candidates.push_back(
            {value(-2, 20), value(0, 0.01), loc::Flags(rng_() & ((1ULL << 33) - 1) & rng_())});
      b.primary = static_cast<int>(rng_() % 6) - 1;
      b.flags = loc::Flags(rng_() % 8 == 0 ? rng_() & ((1ULL << 33) - 1) : 0);
    }
    return set;
  }

  std::vector<tof::Doa> doas(std::size_t n) {
    std::vector<tof::Doa> out(n);
    for (tof::Doa& d : out) {
      d.valid = rng_() % 5 != 0;
      d.bearing_rad = value(-4, 4);
      d.sd_rad = value(0, 0.1);
      d.receivers = static_cast<int>(rng_() % 9);
    }
    return out;
  }

  tof::BinauralPairResult pair() {
    tof::BinauralPairResult p;
    p.tof_left_s = value(0, 0.02);
    p.tof_right_s = value(0, 0.02);
    p.coarse_difference_s = value(-1e-3, 1e-3);
    p.phase_rad = value(-4, 4);
    p.phase_sd_rad = value(0, 0.5);
    p.edges_used = static_cast<int>(rng_() % 10);
    p.difference_s = value(-1e-3, 1e-3);
    p.difference_sd_s = value(0, 1e-5);
    p.path_difference_m = value(-0.4, 0.4);
    p.flags = tof::Flags(rng_() % 4 == 0 ? rng_() & ((1ULL << 33) - 1) : 0);
    return p;
  }

  std::mt19937_64& rng() { return rng_; }

 private:
  std::mt19937_64 rng_;
};

void expect_sane(const loc::Fix& fix, const loc::RangeSet& set) {
  ASSERT_EQ(fix.beacons.size(), set.beacons.size());
  for (std::size_t i = 0; i < fix.beacons.size(); ++i)
    EXPECT_EQ(fix.beacons[i].beacon, static_cast<int>(i));
  if (!fix.valid) {
    EXPECT_NE(fix.reason, loc::NoFixReason::kNone);
    return;
  }
  EXPECT_EQ(fix.reason, loc::NoFixReason::kNone);
  ASSERT_TRUE(std::isfinite(fix.position_m.x) && std::isfinite(fix.position_m.y));
  ASSERT_TRUE(fix.covariance_m2.allFinite());
  EXPECT_NEAR(fix.covariance_m2(0, 1), fix.covariance_m2(1, 0),
              1e-9 * fix.covariance_m2.cwiseAbs().maxCoeff());
  EXPECT_GT(
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(fix.covariance_m2).eigenvalues().minCoeff(),
      0.0);
  for (const loc::BeaconUse& u : fix.beacons)
    if (u.status == loc::BeaconStatus::kUsed) {
      ASSERT_GE(u.candidate, 0);
      const loc::RangeCandidate& c = set.beacons[static_cast<std::size_t>(u.beacon)]
                                         .candidates[static_cast<std::size_t>(u.candidate)];
      EXPECT_TRUE(std::isfinite(c.distance_m) && std::isfinite(c.sd_m) && c.sd_m >= 0);
    }
}

TEST(SolverRobustness, HostileDataNeverThrows) {
  Hostile h(2026);
  int valid = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const loc::BeaconLayout layout = h.layout();
    const loc::RangeSet set = h.ranges(layout);
    loc::Fix gn, ls, triple, thamma_tri, thamma_ls;
    ASSERT_NO_THROW(gn = loc::multilaterate(layout, set)) << trial;
    loc::MultilaterationOptions calibrate;
    calibrate.calibrate_speed_of_sound = true;
    ASSERT_NO_THROW((void)loc::multilaterate(layout, set, calibrate)) << trial;
    loc::Longsolve longsolve;
    ASSERT_NO_THROW(ls = longsolve.solve(layout, set)) << trial;
    if (layout.beacons.size() >= 3) {
      const loc::Triple t{0, 1, 2};
      ASSERT_NO_THROW(triple = loc::solve_triple(layout, set, t, {5, 5})) << trial;
      expect_sane(triple, set);
    }
    ASSERT_NO_THROW(thamma_tri = loc::thamma_trilateration(layout, set)) << trial;
    ASSERT_NO_THROW(thamma_ls = loc::thamma_least_squares(layout, set)) << trial;
    for (const loc::Fix* f : {&gn, &ls, &thamma_tri, &thamma_ls})
      expect_sane(*f, set);
    const std::vector<tof::Doa> doas = h.doas(set.beacons.size());
    loc::Heading heading;
    ASSERT_NO_THROW(heading = loc::beacon_heading(gn, layout, doas)) << trial;
    if (heading.valid) {
      EXPECT_TRUE(std::isfinite(heading.heading_rad) && std::isfinite(heading.sd_rad));
      EXPECT_GT(heading.sd_rad, 0);
    }
    valid += gn.valid ? 1 : 0;
  }
  EXPECT_GT(valid, 0);  // some of the plausible draws do give fixes
}

TEST(SolverRobustness, BinauralHostileDataNeverThrows) {
  Hostile h(7);
  for (int trial = 0; trial < 4000; ++trial) {
    const tof::BinauralPairResult a = h.pair();
    const tof::BinauralPairResult b = h.pair();
    loc::RelativePose pose;
    ASSERT_NO_THROW(pose = loc::relative_pose(a, b)) << trial;
    if (pose.valid) {
      EXPECT_TRUE(std::isfinite(pose.relative_orientation_rad));
      EXPECT_TRUE(pose.covariance.allFinite())
          << trial << " a: " << a.tof_left_s << " " << a.tof_right_s << " " << a.phase_rad << " "
          << a.phase_sd_rad << " " << a.path_difference_m << " " << a.difference_sd_s << " "
          << a.edges_used << " " << a.flags.bits() << " b: " << b.tof_left_s << " " << b.tof_right_s
          << " " << b.phase_rad << " " << b.phase_sd_rad << " " << b.path_difference_m << " "
          << b.difference_sd_s << " " << b.edges_used << " " << b.flags.bits() << "\n"
          << pose.covariance;
    } else {
      EXPECT_NE(pose.reason, loc::BinauralReason::kNone);
    }
  }
}

}  // namespace
