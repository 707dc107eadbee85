// Thamma's head and tail (soc_software thamma_pose): his four corner
// stations and two receiver boxes from the acoustic world
// (world::thamma_stations, world::thamma_boxes), ranges computed in long
// double from known poses to the receiver nearest each station (the one
// that hears first), optionally with seeded noise. Checked: the triangle
// and the least-squares fix recover exact positions (both sides of the
// base, obtuse corners, stations above the receivers), their covariance
// matches the errors of noisy cases (normalised error squared), the pose at
// every heading including +-pi with the receiver offsets corrected, the
// separation check, degenerate geometry and bad input.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include "odoloc/sw/thamma_pose.hpp"
#include "odoloc/sw/tof_doa.hpp"
#include "odoloc/world/acoustic_systems.hpp"

namespace {

namespace locate = odoloc::sw::locate;
namespace tof = odoloc::sw::tof;
namespace world = odoloc::world;
using LD = long double;
using locate::NoFixReason;
constexpr LD kPiL = std::numbers::pi_v<LD>;
constexpr double kPi = std::numbers::pi;

struct P2 {
  LD x, y;
};

locate::BeaconLayout station_layout(double height_m = 0) {
  locate::BeaconLayout layout;
  for (const world::Beacon& b : world::thamma_stations(world::kleeman_room()))
    layout.beacons.push_back({{b.position.x_m, b.position.y_m}, height_m});
  return layout;
}

LD exact_range(const locate::BeaconLayout& layout, std::size_t s, P2 p) {
  const locate::Beacon& b = layout.beacons[s];
  const LD dx = p.x - b.position_m.x;
  const LD dy = p.y - b.position_m.y;
  return std::sqrt(dx * dx + dy * dy + static_cast<LD>(b.height_m) * b.height_m);
}

// Ranges from p to the listed stations (the others missing).
locate::RangeSet ranges_to(const locate::BeaconLayout& layout, P2 p, std::vector<int> heard,
                           double sd_m = 1e-3, std::mt19937_64* rng = nullptr) {
  locate::RangeSet set;
  std::normal_distribution<double> g(0, sd_m);
  for (std::size_t s = 0; s < layout.beacons.size(); ++s) {
    locate::BeaconRange r;
    if (std::find(heard.begin(), heard.end(), static_cast<int>(s)) != heard.end()) {
      const double noise = rng != nullptr ? g(*rng) : 0.0;
      r.candidates.push_back({static_cast<double>(exact_range(layout, s, p)) + noise, sd_m, {}});
      r.primary = 0;
    } else {
      r.flags.set(tof::Flag::kMissing);
    }
    set.beacons.push_back(r);
  }
  return set;
}

double distance(locate::Vec2 a, P2 b) {
  return static_cast<double>(std::hypot(a.x - b.x, a.y - b.y));
}

// ------------------------------------------------------------ the vehicle

struct Vehicle {
  LD x, y, theta;
  [[nodiscard]] P2 to_world(world::Vec2 body) const {
    return {x + std::cos(theta) * body.x_m - std::sin(theta) * body.y_m,
            y + std::sin(theta) * body.x_m + std::cos(theta) * body.y_m};
  }
};

const std::vector<world::Receiver>& receivers() {
  static const std::vector<world::Receiver> r = world::thamma_boxes();
  return r;
}

locate::ThammaBody thamma_body(bool with_receivers = true) {
  locate::ThammaBody body;  // head (0.6, 0), tail (-0.2, 0): world::thamma_boxes' defaults
  if (with_receivers)
    for (const world::Receiver& r : receivers())
      body.receivers.receivers.push_back({{r.position.x_m, r.position.y_m}, r.axis_rad});
  return body;
}

// Station s's burst: the box of its frequency (stations 0, 1: head at
// 40 kHz; 2, 3: tail at 32.5 kHz; or every box with all_boxes) hears it
// first at its receiver nearest to the station.
tof::ThammaMeasurement burst(const locate::BeaconLayout& layout, const Vehicle& v, int station,
                             bool all_boxes = false, double sd_m = 1e-3,
                             std::mt19937_64* rng = nullptr) {
  tof::ThammaMeasurement m;
  std::normal_distribution<double> g(0, sd_m);
  for (int box = 0; box < 2; ++box) {
    tof::ThammaBoxResult b;
    b.box = box;
    if (!all_boxes && (station < 2) != (box == 0)) {
      b.flags.set(tof::Flag::kMissing);
      b.repeats.push_back({std::nan(""), -1, tof::Flag::kMissing});
      m.boxes.push_back(b);
      continue;
    }
    int nearest = -1;
    LD best = 1e9L;
    for (int ch = 4 * box; ch < 4 * box + 4; ++ch) {
      const LD d = exact_range(layout, static_cast<std::size_t>(station),
                               v.to_world(receivers()[static_cast<std::size_t>(ch)].position));
      if (d < best)
        best = d, nearest = ch;
    }
    b.used = 1;
    b.distance_m = static_cast<double>(best) + (rng != nullptr ? g(*rng) : 0.0);
    b.distance_sd_m = sd_m;
    b.tof_s = b.distance_m / 343.2;
    b.repeats.push_back({b.tof_s, nearest, {}});
    m.boxes.push_back(b);
  }
  return m;
}

std::vector<tof::ThammaMeasurement> bursts(const locate::BeaconLayout& layout, const Vehicle& v,
                                           bool all_boxes = false, double sd_m = 1e-3,
                                           std::mt19937_64* rng = nullptr) {
  std::vector<tof::ThammaMeasurement> out;
  for (int s = 0; s < 4; ++s)
    out.push_back(burst(layout, v, s, all_boxes, sd_m, rng));
  return out;
}

// -------------------------------------------------------------- the fixes

TEST(ThammaFix, TriangleRecoversTheVertexOnEitherSideOfTheBase) {
  const locate::BeaconLayout layout = station_layout();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.3, 9.7);
  std::vector<P2> points{
      {6, 8},         // c = |AB| the longest side, C acute (Thamma's step 5 calls it exterior)
      {0.02L, 3},     // obtuse at B (outside the base's end, within the hull margin)
      {9.99L, 0.5L},  // obtuse at C, outside the hull by 4 cm
      {5, 0.3L},      // close to the base
  };
  for (int i = 0; i < 200; ++i)
    points.push_back({u(rng), u(rng)});
  for (const P2 a : points) {
    // Head: base stations 0 -> 1 (Thamma's vertex is left of B -> C);
    // tail: stations 2 -> 3, whose left is outside the room: the hull decides.
    for (const std::vector<int>& base : {std::vector<int>{0, 1}, std::vector<int>{2, 3}}) {
      const locate::Fix fix = locate::thamma_trilateration(layout, ranges_to(layout, a, base));
      ASSERT_TRUE(fix.valid) << locate::name(fix.reason) << " at " << static_cast<double>(a.x)
                             << ", " << static_cast<double>(a.y);
      EXPECT_EQ(fix.solver, locate::Solver::kThammaTrilateration);
      EXPECT_LT(distance(fix.position_m, a), 1e-9);
      EXPECT_EQ(fix.dof, 0);
      EXPECT_EQ(fix.used(), 2);
      EXPECT_EQ(fix.offset_m, 0);
    }
  }
}

TEST(ThammaFix, StationsAboveTheReceivers) {
  const locate::BeaconLayout layout = station_layout(1.5);
  for (const P2 a : {P2{2, 3}, P2{7.5L, 1.2L}, P2{5, 9}}) {
    const locate::Fix tri = locate::thamma_trilateration(layout, ranges_to(layout, a, {0, 1}));
    const locate::Fix ls = locate::thamma_least_squares(layout, ranges_to(layout, a, {0, 1, 2, 3}));
    ASSERT_TRUE(tri.valid && ls.valid);
    EXPECT_LT(distance(tri.position_m, a), 1e-9);
    EXPECT_LT(distance(ls.position_m, a), 1e-9);
  }
}

TEST(ThammaFix, LeastSquaresOverEveryStationIsExact) {
  const locate::BeaconLayout layout = station_layout();
  constexpr double kSd = 2e-3;
  for (const P2 a : {P2{5, 5}, P2{1, 1}, P2{8.5L, 2}, P2{3, 9.5L}}) {
    const locate::Fix fix =
        locate::thamma_least_squares(layout, ranges_to(layout, a, {0, 1, 2, 3}, kSd));
    ASSERT_TRUE(fix.valid) << locate::name(fix.reason);
    EXPECT_EQ(fix.solver, locate::Solver::kThammaLeastSquares);
    EXPECT_LT(distance(fix.position_m, a), 1e-9);
    EXPECT_EQ(fix.dof, 2);
    EXPECT_LT(fix.chi2, 1e-12);
    EXPECT_LE(fix.iterations, 5);
    // Independent: H rows the unit vectors from the stations, long double.
    LD h11 = 0, h12 = 0, h22 = 0;
    for (std::size_t s = 0; s < 4; ++s) {
      const LD d = exact_range(layout, s, a);
      const LD ux = (a.x - layout.beacons[s].position_m.x) / d;
      const LD uy = (a.y - layout.beacons[s].position_m.y) / d;
      h11 += ux * ux, h12 += ux * uy, h22 += uy * uy;
    }
    const LD det = h11 * h22 - h12 * h12;
    EXPECT_NEAR(fix.hdop, static_cast<double>(std::sqrt((h11 + h22) / det)), 1e-9);
    EXPECT_NEAR(fix.covariance_m2(0, 0), static_cast<double>(kSd * kSd * h22 / det), 1e-15);
    EXPECT_NEAR(fix.covariance_m2(0, 1), static_cast<double>(-kSd * kSd * h12 / det), 1e-15);
    for (const locate::BeaconUse& use : fix.beacons)
      EXPECT_NEAR(use.residual_m, 0, 1e-9);
  }
}

// Mean normalised error squared over n seeded fixes: chi^2(2n)/n.
double fix_nees(bool least_squares, std::vector<int> heard, int n, std::uint64_t seed) {
  const locate::BeaconLayout layout = station_layout();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(1, 9);
  double sum = 0;
  int rejected = 0;
  for (int i = 0; i < n; ++i) {
    const P2 a{u(rng), u(rng)};
    const locate::RangeSet r = ranges_to(layout, a, heard, 5e-3, &rng);
    const locate::Fix fix = least_squares ? locate::thamma_least_squares(layout, r)
                                          : locate::thamma_trilateration(layout, r);
    // A 4-sigma residual gate rejects about 1 in 16 000 good ranges.
    EXPECT_TRUE(fix.valid || fix.reason == NoFixReason::kInconsistent) << locate::name(fix.reason);
    rejected += fix.valid ? 0 : 1;
    const Eigen::Vector2d e(fix.position_m.x - static_cast<double>(a.x),
                            fix.position_m.y - static_cast<double>(a.y));
    sum += e.dot(fix.covariance_m2.ldlt().solve(e));
  }
  EXPECT_LE(rejected, n / 500);
  return sum / n;
}

TEST(ThammaFix, NoisyErrorsMatchTheCovariance) {
  constexpr int kTrials = 2000;
  const double tolerance = 3.3 * std::sqrt(4.0 / kTrials);  // chi^2(2n)/n: mean 2, sd sqrt(4/n)
  const double tri = fix_nees(false, {0, 1}, kTrials, 21);
  const double ls2 = fix_nees(true, {2, 3}, kTrials, 22);
  const double ls4 = fix_nees(true, {0, 1, 2, 3}, kTrials, 23);
  std::printf(
      "Thamma fix NEES (2 dof): triangle %.3f, least squares 2 stations %.3f, "
      "4 stations %.3f\n",
      tri, ls2, ls4);
  EXPECT_NEAR(tri, 2.0, tolerance);
  EXPECT_NEAR(ls2, 2.0, tolerance);
  EXPECT_NEAR(ls4, 2.0, tolerance);
}

TEST(ThammaFix, MirrorAmbiguousWithoutAHullAroundIt) {
  locate::BeaconLayout two = station_layout();
  two.beacons.resize(2);  // stations 0 and 1 only: the hull is their segment
  const locate::RangeSet r = ranges_to(two, {5, 3}, {0, 1});
  for (const locate::Fix& fix :
       {locate::thamma_trilateration(two, r), locate::thamma_least_squares(two, r)}) {
    EXPECT_FALSE(fix.valid);
    EXPECT_EQ(fix.reason, NoFixReason::kMirrorAmbiguous);
    ASSERT_TRUE(fix.mirror_m.has_value());
    const double y_sum = fix.position_m.y + fix.mirror_m->y;  // mirrored across y = 0.05
    EXPECT_NEAR(y_sum, 0.1, 1e-9);
    EXPECT_NEAR(std::abs(fix.position_m.y - 0.05), 2.95, 1e-9);
  }
  // A third range decides the side.
  locate::BeaconLayout three = station_layout();
  three.beacons.resize(3);
  const locate::Fix fix = locate::thamma_trilateration(three, ranges_to(three, {5, 3}, {0, 1, 2}));
  EXPECT_TRUE(fix.valid) << locate::name(fix.reason);
  EXPECT_LT(distance(fix.position_m, {5, 3}), 1e-9);
}

TEST(ThammaFix, DegenerateInconsistentAndOutside) {
  const locate::BeaconLayout layout = station_layout();
  // On the base line between stations 0 and 1: tangent circles.
  const locate::RangeSet on_line = ranges_to(layout, {4, 0.05L}, {0, 1});
  EXPECT_EQ(locate::thamma_trilateration(layout, on_line).reason, NoFixReason::kDegenerateGeometry);
  EXPECT_EQ(locate::thamma_least_squares(layout, on_line).reason, NoFixReason::kDegenerateGeometry);
  // Both ranges 1 m short: the circles miss each other by 2 m.
  locate::RangeSet short_ranges = ranges_to(layout, {5, 2}, {0, 1});
  for (const int s : {0, 1})
    short_ranges.beacons[static_cast<std::size_t>(s)].candidates[0].distance_m -= 2.0;
  EXPECT_EQ(locate::thamma_trilateration(layout, short_ranges).reason, NoFixReason::kInconsistent);
  // One range of four 0.3 m long (an echo): the residual test.
  locate::RangeSet echo = ranges_to(layout, {4, 6}, {0, 1, 2, 3});
  echo.beacons[2].candidates[0].distance_m += 0.3;
  const locate::Fix bad = locate::thamma_least_squares(layout, echo);
  EXPECT_FALSE(bad.valid);
  EXPECT_EQ(bad.reason, NoFixReason::kInconsistent);
  EXPECT_GT(bad.chi2, 1000);
  // Far outside the stations' hull.
  EXPECT_EQ(
      locate::thamma_least_squares(layout, ranges_to(layout, {-1.5L, 5}, {0, 1, 2, 3})).reason,
      NoFixReason::kOutsideHull);
}

TEST(ThammaFix, MissingAndNonFiniteRanges) {
  const locate::BeaconLayout layout = station_layout();
  locate::RangeSet r = ranges_to(layout, {5, 5}, {0, 1});
  r.beacons[1].candidates[0].distance_m = std::nan("");
  const locate::Fix one = locate::thamma_least_squares(layout, r);
  EXPECT_FALSE(one.valid);
  EXPECT_EQ(one.reason, NoFixReason::kTooFewBeacons);
  EXPECT_EQ(one.beacons[1].status, locate::BeaconStatus::kNonFinite);
  EXPECT_EQ(one.beacons[2].status, locate::BeaconStatus::kMissing);
  r.beacons[0].candidates[0].sd_m = INFINITY;
  EXPECT_EQ(locate::thamma_trilateration(layout, r).reason, NoFixReason::kNonFiniteInput);
  EXPECT_EQ(locate::thamma_trilateration(layout, {}).reason, NoFixReason::kTooFewBeacons);
  // More ranges than stations: the extra one is not in the layout.
  locate::RangeSet extra = ranges_to(layout, {5, 5}, {0, 1, 2, 3});
  extra.beacons.push_back(extra.beacons[0]);
  const locate::Fix fix = locate::thamma_least_squares(layout, extra);
  EXPECT_TRUE(fix.valid);
  EXPECT_EQ(fix.beacons[4].status, locate::BeaconStatus::kNotInLayout);
}

TEST(ThammaFix, BadConfigurationThrows) {
  locate::BeaconLayout twins = station_layout();
  twins.beacons[1] = twins.beacons[0];
  EXPECT_THROW(locate::thamma_trilateration(twins, {}), std::invalid_argument);
  locate::ThammaOptions options;
  options.gate_sigmas = 0;
  EXPECT_THROW(locate::thamma_least_squares(station_layout(), {}, options), std::invalid_argument);
}

// --------------------------------------------------------------- the pose

TEST(ThammaPose, ExactPoseAtEveryHeadingWithTheReceiverOffsets) {
  const locate::BeaconLayout layout = station_layout();
  double worst_position = 0, worst_heading = 0, worst_uncorrected = 0;
  int most_passes = 0;
  const std::vector<LD> headings{-kPiL + 1e-9L, -2.5L,    -kPiL / 2, -0.3L,        0,
                                 0.7L,          kPiL / 2, 2.9L,      kPiL - 1e-9L, kPiL};
  for (const LD theta : headings)
    for (const P2 p : {P2{5, 5}, P2{2, 2.5L}, P2{8, 3}, P2{3.5L, 7.8L}})
      for (const bool all_boxes : {false, true}) {
        const Vehicle v{p.x, p.y, theta};
        const auto m = bursts(layout, v, all_boxes);
        for (const bool least_squares : {true, false}) {
          locate::ThammaPoseOptions options;
          options.least_squares = least_squares;
          const locate::ThammaPose pose = locate::thamma_pose(layout, m, thamma_body(), options);
          ASSERT_TRUE(pose.valid) << locate::name(pose.reason) << " head "
                                  << locate::name(pose.head.reason) << " tail "
                                  << locate::name(pose.tail.reason);
          worst_position = std::max(worst_position, distance(pose.position_m, p));
          worst_heading = std::max(
              worst_heading,
              std::abs(tof::angle_difference(pose.heading_rad, static_cast<double>(theta))));
          EXPECT_GT(pose.heading_rad, -kPi);
          EXPECT_LE(pose.heading_rad, kPi);
          most_passes = std::max(most_passes, pose.passes);
        }
        // The receivers left out: each range taken to end at the box centre.
        const locate::ThammaPose plain = locate::thamma_pose(layout, m, thamma_body(false));
        worst_uncorrected = std::max(worst_uncorrected, distance(plain.position_m, p));
      }
  std::printf(
      "Thamma pose, exact ranges: worst %.3g m, %.3g rad, %d passes; without the "
      "receiver offsets %.1f mm\n",
      worst_position, worst_heading, most_passes, worst_uncorrected * 1e3);
  EXPECT_LT(worst_position, 1e-8);
  EXPECT_LT(worst_heading, 1e-8);
  EXPECT_LE(most_passes, 7);           // secant steps: superlinear
  EXPECT_GT(worst_uncorrected, 0.02);  // the offsets matter: centimetres
}

TEST(ThammaPose, NoisyPoseMatchesItsCovariance) {
  const locate::BeaconLayout layout = station_layout();
  constexpr int kTrials = 1500;
  constexpr double kSd = 3e-3;
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(1.5, 8.5);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  double nees3 = 0, nees1 = 0, heading2 = 0;
  for (int i = 0; i < kTrials; ++i) {
    const Vehicle v{u(rng), u(rng), angle(rng)};
    const locate::ThammaPose pose =
        locate::thamma_pose(layout, bursts(layout, v, false, kSd, &rng), thamma_body());
    EXPECT_TRUE(pose.valid || pose.reason == locate::ThammaPoseReason::kSeparationMismatch)
        << locate::name(pose.reason);
    const double dh = tof::angle_difference(pose.heading_rad, static_cast<double>(v.theta));
    const Eigen::Vector3d e(pose.position_m.x - static_cast<double>(v.x),
                            pose.position_m.y - static_cast<double>(v.y), dh);
    nees3 += e.dot(pose.covariance.ldlt().solve(e));
    nees1 += dh * dh / (pose.heading_sd_rad * pose.heading_sd_rad);
    heading2 += dh * dh;
  }
  nees3 /= kTrials, nees1 /= kTrials;
  std::printf(
      "Thamma pose NEES: %.3f (x, y, heading; 3 dof), %.3f (heading); heading rms "
      "%.3f deg at %.0f mm range sd\n",
      nees3, nees1, std::sqrt(heading2 / kTrials) * 180 / kPi, kSd * 1e3);
  EXPECT_NEAR(nees3, 3.0, 3.3 * std::sqrt(6.0 / kTrials));
  EXPECT_NEAR(nees1, 1.0, 3.3 * std::sqrt(2.0 / kTrials));
}

TEST(ThammaPose, SeparationMismatchIsFlagged) {
  const locate::BeaconLayout layout = station_layout();
  auto m = bursts(layout, {5, 5, 0});
  m[1].boxes[0].distance_m += 0.1;  // the head's range to station 1 via an echo
  const locate::ThammaPose pose = locate::thamma_pose(layout, m, thamma_body());
  EXPECT_FALSE(pose.valid);
  EXPECT_EQ(pose.reason, locate::ThammaPoseReason::kSeparationMismatch);
  EXPECT_TRUE(pose.head.valid &&
              pose.tail.valid);  // two ranges each: nothing to check within a box
  EXPECT_GT(std::abs(pose.separation_error_m), 10 * pose.separation_sd_m);
  EXPECT_TRUE(std::isfinite(pose.heading_rad));  // kept for the caller
}

TEST(ThammaPose, MissingStationsAndBadConfiguration) {
  const locate::BeaconLayout layout = station_layout();
  const Vehicle v{4, 6, 1};
  auto m = bursts(layout, v);
  // Station 1's burst lost (no sync): the head hears one station only.
  m[1].flags.set(tof::Flag::kInvalid);
  m[1].boxes[0] = {};
  m[1].boxes[0].flags.set(tof::Flag::kMissing);
  const locate::ThammaPose no_head = locate::thamma_pose(layout, m, thamma_body());
  EXPECT_FALSE(no_head.valid);
  EXPECT_EQ(no_head.reason, locate::ThammaPoseReason::kNoHeadFix);
  EXPECT_EQ(no_head.head.reason, NoFixReason::kTooFewBeacons);
  EXPECT_TRUE(std::isnan(no_head.heading_rad));
  // The tail's ranges NaN.
  auto nan = bursts(layout, v);
  nan[2].boxes[1].distance_m = nan[3].boxes[1].distance_m = std::nan("");
  const locate::ThammaPose no_tail = locate::thamma_pose(layout, nan, thamma_body());
  EXPECT_EQ(no_tail.reason, locate::ThammaPoseReason::kNoTailFix);
  EXPECT_EQ(no_tail.tail.reason, NoFixReason::kNonFiniteInput);
  // No bursts at all.
  EXPECT_EQ(locate::thamma_pose(layout, {}, thamma_body()).reason,
            locate::ThammaPoseReason::kNoHeadFix);
  // box_ranges: a box index the measurements do not have is missing.
  const locate::RangeSet none = locate::box_ranges(bursts(layout, v), 5);
  ASSERT_EQ(none.beacons.size(), 4U);
  EXPECT_TRUE(none.beacons[0].flags.has(tof::Flag::kMissing));
  // Configuration errors throw.
  locate::ThammaBody same = thamma_body();
  same.tail_m = same.head_m;
  EXPECT_THROW(locate::thamma_pose(layout, m, same), std::invalid_argument);
  locate::ThammaBody boxes = thamma_body();
  boxes.tail_box = boxes.head_box;
  EXPECT_THROW(locate::thamma_pose(layout, m, boxes), std::invalid_argument);
  locate::ThammaPoseOptions options;
  options.max_passes = 0;
  EXPECT_THROW(locate::thamma_pose(layout, m, thamma_body(), options), std::invalid_argument);
}

}  // namespace
