// The beacon solvers against the Cramer-Rao bound, by seeded Monte Carlo over
// Kleeman's 10 m room with 6 beacons, on measurement sets made by the
// acoustic world (host_tools/sim/world): its geometry, wall echoes (image
// sources), occlusion, spreading, air absorption, directivity and threshold
// decide which wavefronts the robot hears and when; its turbulence jitter
// and a Gaussian for the capture chain's residual timing error (rise-time
// compensation, quantisation: test_tof_chain measures about 1 mm) make the
// noise. The measurement set is formed as the capture chain forms it
// (docs/tof-measurements.md): per beacon every wavefront heard, earliest
// first, timed at the robot origin, with one unknown common offset per cycle.
//
// Prints, per run: the RMS error of each solver beside the bound's RMS, the
// normalised estimation error squared (NEES), false fixes (beyond 10 sigma of
// the reported covariance) and no-fix counts. docs/beacon-solvers.md quotes
// the figures.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "odoloc/board/beacon_ranges.hpp"
#include "odoloc/sw/kleeman_solver.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"

namespace {

namespace loc = odoloc::sw::locate;
namespace world = odoloc::world;

// Residual timing error of the capture chain per wavefront (metres of path).
constexpr double kChainSdM = 0.7e-3;
constexpr double kPathJitterS = 1.5e-6;      // turbulence, per emission and path
constexpr double kReceiverJitterS = 1.0e-6;  // per receiver

world::AcousticWorld room_world(double temperature_c = 20) {
  world::AcousticWorld w = world::kleeman_world();
  w.air.temperature_c = temperature_c;
  w.noise.path_jitter_sd_s = kPathJitterS;
  w.noise.receiver_jitter_sd_s = kReceiverJitterS;
  return w;
}

struct Sample {
  loc::Vec2 truth;
  loc::RangeSet set;
  std::vector<int> direct;   // beacons whose first candidate is the direct path
  std::vector<double> sd_m;  // their reported sd
  bool corrupted = false;    // the echo-corrupted beacon's direct path was blocked
  double bound_rms_m = 0;    // the Cramer-Rao bound's RMS with the direct beacons
};

// One beacon cycle with the robot standing at `pose`; `block` >= 0 puts a
// 10 cm disc 0.4 m from the robot on the direct path to that beacon, so its
// first wavefront is an echo (or nothing).
// Distances are c_assumed x time (the world's c when 0).
Sample measure(world::AcousticWorld w, const world::Pose& pose, int block, double c_assumed,
               std::mt19937_64& rng) {
  Sample s;
  s.truth = {pose.x_m, pose.y_m};
  if (block >= 0) {
    w.obstacles.push_back(
        world::direct_path_blocker(w, {pose.x_m, pose.y_m}, static_cast<std::size_t>(block)));
    s.corrupted = true;
  }
  std::normal_distribution<double> chain(0.0, kChainSdM);
  const std::uint64_t world_seed = rng();
  const double offset = std::uniform_real_distribution<double>(-2.0, 6.0)(rng);
  odoloc::board::MeasuredCycle cycle = odoloc::board::measure_kleeman_cycle(
      w, pose, c_assumed > 0 ? c_assumed : w.air.speed_of_sound_mps(), offset, kChainSdM,
      world_seed, [&] { return chain(rng); });
  s.set = std::move(cycle.ranges);
  s.direct = std::move(cycle.direct);
  s.sd_m = std::move(cycle.direct_sd_m);
  return s;
}

// One solver's results over a run, beside the bound of the same samples.
struct Tally {
  std::string name;
  int fixes = 0, no_fix = 0, false_fixes = 0;
  int unbounded = 0;  // fixes where fewer than three beacons were heard directly (no bound)
  double sum_e2 = 0, sum_nees = 0, sum_bound2 = 0, sum_ratio = 0;
  void add(const loc::Fix& fix, const Sample& s) {
    if (!fix.valid) {
      ++no_fix;
      return;
    }
    ++fixes;
    const Eigen::Vector2d e(fix.position_m.x - s.truth.x, fix.position_m.y - s.truth.y);
    const double n = e.dot(fix.covariance_m2.inverse() * e);
    sum_e2 += e.squaredNorm();
    sum_nees += n;
    if (std::isfinite(s.bound_rms_m)) {
      sum_bound2 += s.bound_rms_m * s.bound_rms_m;
      sum_ratio += e.squaredNorm() / (s.bound_rms_m * s.bound_rms_m);
    } else {
      ++unbounded;
    }
    false_fixes += n > 100.0 ? 1 : 0;  // beyond 10 sigma
  }
  [[nodiscard]] double rms() const { return std::sqrt(sum_e2 / std::max(fixes, 1)); }
  [[nodiscard]] double bound_rms() const {
    return std::sqrt(sum_bound2 / std::max(fixes - unbounded, 1));
  }
  [[nodiscard]] double mean_nees() const { return sum_nees / std::max(fixes, 1); }
  // Mean of |error|^2 / trace(bound): 1 for an efficient estimator, and far
  // less sensitive than the RMS ratio to the few points of poor geometry.
  [[nodiscard]] double mean_bound_ratio() const {
    return sum_ratio / std::max(fixes - unbounded, 1);
  }
  // The mean of n chi^2(2) draws: 95 % within 2 +- 1.96 * 2 / sqrt(n).
  [[nodiscard]] double nees_half_interval() const {
    return 1.96 * 2.0 / std::sqrt(static_cast<double>(std::max(fixes, 1)));
  }
  void print() const {
    std::printf(
        "  %-15s fixes %4d  no fix %4d  RMS %7.3f mm  CRLB RMS %6.3f mm (x %.2f; mean "
        "e^2/CRLB %.2f)  NEES %.2f (95 %%: %.2f..%.2f)  false %d%s\n",
        name.c_str(), fixes, no_fix, 1e3 * rms(), 1e3 * bound_rms(), rms() / bound_rms(),
        mean_bound_ratio(), mean_nees(), 2 - nees_half_interval(), 2 + nees_half_interval(),
        false_fixes,
        unbounded > 0 ? ("  (" + std::to_string(unbounded) + " on < 3 direct paths)").c_str() : "");
  }
};

struct RunSpec {
  int points = 600;
  int block_beacon = -1;  // the echo-corrupted beacon, or -1
  double block_probability = 0;
  std::uint64_t seed = 1;
  double temperature_c = 20;               // the air's
  double c_assumed = 0;                    // the c distances are computed with (0: the air's)
  bool with_speed = false;                 // the bound with c unknown
  double speed_prior_sd = loc::kInfinity;  // ... and this prior on c_used/c_true
};

std::vector<Sample> make_run(const RunSpec& spec) {
  const world::AcousticWorld w = room_world(spec.temperature_c);
  const loc::BeaconLayout layout = odoloc::board::beacon_layout(w);
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> u(0.5, 9.5);
  std::uniform_real_distribution<double> heading(-3.14159, 3.14159);
  std::bernoulli_distribution blocked(spec.block_probability);
  std::vector<Sample> run;
  for (int i = 0; i < spec.points; ++i) {
    const double x = u(rng);
    const world::Pose pose{x, u(rng), heading(rng)};
    const int block = spec.block_beacon >= 0 && blocked(rng) ? spec.block_beacon : -1;
    Sample s = measure(w, pose, block, spec.c_assumed, rng);
    s.bound_rms_m = loc::cramer_rao_bound(layout, s.truth, s.direct, s.sd_m, spec.with_speed,
                                          spec.speed_prior_sd)
                        .rms_m;
    run.push_back(std::move(s));
  }
  return run;
}

// Samples where at least four beacons were heard on their direct path and
// nothing else came first: every one must give a fix.
int checkable(const std::vector<Sample>& run) {
  return static_cast<int>(std::count_if(run.begin(), run.end(), [](const Sample& s) {
    int heard = 0;
    for (const loc::BeaconRange& b : s.set.beacons)
      heard += b.candidates.empty() ? 0 : 1;
    return s.direct.size() >= 4 && heard == static_cast<int>(s.direct.size());
  }));
}

// The three position solvers on one run: the all-beacon estimator,
// longsolve (a fresh one per point: each stands alone), and Kleeman's
// three-beacon iteration on the triple longsolve ranked best, started from
// the room's centre.
struct SolverTallies {
  Tally gn{"gauss-newton"};
  Tally longsolve{"longsolve"};
  Tally triple{"kleeman triple"};
  void add(const loc::BeaconLayout& layout, const Sample& s, const loc::Fix& gn_fix) {
    gn.add(gn_fix, s);
    loc::Longsolve solver;
    longsolve.add(solver.solve(layout, s.set), s);
    if (const std::optional<loc::Triple> best = solver.best_triple())
      triple.add(loc::solve_triple(layout, s.set, *best, {5, 5}), s);
    else
      ++triple.no_fix;
  }
  void print() const {
    gn.print();
    longsolve.print();
    triple.print();
  }
};

TEST(BeaconSolversMonteCarlo, CleanDataReachesTheBound) {
  const loc::BeaconLayout layout = odoloc::board::beacon_layout(room_world());
  const std::vector<Sample> run = make_run({.points = 600, .seed = 2026});
  SolverTallies all;
  const Tally& gn = all.gn;
  for (const Sample& s : run)
    all.add(layout, s, loc::multilaterate(layout, s.set));
  const int expected = checkable(run);
  std::printf("clean: %zu points, %d heard >= 4 beacons directly and nothing earlier\n", run.size(),
              expected);
  all.print();
  EXPECT_LE(gn.rms(), 1.2 * gn.bound_rms());
  EXPECT_EQ(gn.false_fixes, 0);
  EXPECT_GE(gn.fixes, expected);
  EXPECT_NEAR(gn.mean_nees(), 2.0, gn.nees_half_interval());
}

TEST(BeaconSolversMonteCarlo, OneEchoCorruptedBeacon) {
  const loc::BeaconLayout layout = odoloc::board::beacon_layout(room_world());
  const std::vector<Sample> run =
      make_run({.points = 2000, .block_beacon = 1, .block_probability = 0.3, .seed = 7});
  SolverTallies all;
  const Tally& gn = all.gn;
  int corrupted = 0, rejected = 0;
  for (const Sample& s : run) {
    const loc::Fix fix = loc::multilaterate(layout, s.set);
    all.add(layout, s, fix);
    if (s.corrupted && !s.set.beacons[1].candidates.empty()) {
      ++corrupted;
      rejected += fix.valid && fix.beacons[1].status != loc::BeaconStatus::kUsed ? 1 : 0;
    }
  }
  std::printf(
      "beacon 1 echo-corrupted in 30 %% of cycles: %zu points, %d with the echo heard (%d "
      "rejected in a valid fix)\n",
      run.size(), corrupted, rejected);
  all.print();
  EXPECT_LE(gn.rms(), 2.0 * gn.bound_rms());
  EXPECT_LT(gn.false_fixes, std::max(1, gn.fixes / 1000));  // below 0.1 %
  EXPECT_NEAR(gn.mean_nees(), 2.0, gn.nees_half_interval());
  EXPECT_GT(corrupted, 200);  // the run exercises the echoes
}

// Kleeman's self-calibration: the air at 28 C, the distances computed with
// 20 C's 343.2 m/s (a 1.3 % range error), c a state.
TEST(BeaconSolversMonteCarlo, SelfCalibratedSpeedOfSound) {
  const loc::BeaconLayout layout = odoloc::board::beacon_layout(room_world());
  const double c_true = room_world(28).air.speed_of_sound_mps();
  const double prior_sd = loc::MultilaterationOptions{}.speed_of_sound_tolerance / 2;
  const std::vector<Sample> run = make_run({.points = 800,
                                            .seed = 28,
                                            .temperature_c = 28,
                                            .c_assumed = 343.2,
                                            .with_speed = true,
                                            .speed_prior_sd = prior_sd});
  loc::MultilaterationOptions options;
  options.calibrate_speed_of_sound = true;
  // Fixes on five or more beacons estimate c; on four, c stays at the prior
  // (1.3 % off) and the covariance carries the prior's 1.5 %.
  Tally estimated{"gn, c from data"};
  Tally held{"gn, c prior"};
  double z2 = 0, err2 = 0, sd_sum = 0;
  for (const Sample& s : run) {
    const loc::Fix fix = loc::multilaterate(layout, s.set, options);
    (fix.speed_of_sound_estimated ? estimated : held).add(fix, s);
    if (fix.valid && fix.speed_of_sound_estimated) {
      const double e = fix.speed_of_sound_mps - c_true;
      z2 += e * e / (fix.speed_of_sound_sd_mps * fix.speed_of_sound_sd_mps);
      err2 += e * e;
      sd_sum += fix.speed_of_sound_sd_mps;
    }
  }
  const int n = estimated.fixes;
  std::printf(
      "c unknown (air 28 C = %.2f m/s, assumed 343.2 m/s, prior sd %.1f %%): %d fixes estimated c: "
      "RMS error %.3f m/s (%.3f %%), mean reported sd %.3f m/s, mean z^2 %.2f\n",
      c_true, 100 * prior_sd, n, std::sqrt(err2 / n), 100 * std::sqrt(err2 / n) / c_true,
      sd_sum / n, z2 / n);
  estimated.print();
  held.print();
  EXPECT_LE(estimated.rms(), 1.2 * estimated.bound_rms());
  EXPECT_EQ(estimated.false_fixes + held.false_fixes, 0);
  EXPECT_NEAR(estimated.mean_nees(), 2.0, estimated.nees_half_interval());
  EXPECT_GT(n, 300);
  // z^2 of c averages 1 (chi^2(1): 95 % within 1 +- 1.96 sqrt(2/n)).
  EXPECT_NEAR(z2 / n, 1.0, 1.96 * std::sqrt(2.0 / n));
  // Kleeman resolved c to 0.25 %.
  EXPECT_LT(std::sqrt(err2 / n) / c_true, 0.0025);
}

}  // namespace
