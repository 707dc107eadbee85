// Ground-truth tricycle simulator against physics: straight lines at any
// heading, circles of radius L/tan(phi), a closed square, steering ramps
// against an independent RK4 integration, bump arc lengths against numerical
// quadrature, slip and radius error against their definitions. Every run also
// decodes the four A/B waveforms independently and requires legal transitions
// whose counts equal the true edge counts.
//
// ODOLOC_TEST_SCALE < 1 shortens the drives (e.g. 0.2 under sanitizers).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "odoloc/world/tricycle.hpp"

namespace {

using odoloc::world::bump_extra_length;
using odoloc::world::bump_under_both_rear;
using odoloc::world::bump_under_front;
using odoloc::world::bump_under_one_rear;
using odoloc::world::Disturbances;
using odoloc::world::Encoder;
using odoloc::world::Geometry;
using odoloc::world::index;
using odoloc::world::kEncoderCount;
using odoloc::world::Options;
using odoloc::world::Path;
using odoloc::world::Pose;
using odoloc::world::QuadratureLevels;
using odoloc::world::Segment;
using odoloc::world::Slip;
using odoloc::world::square_path;
using odoloc::world::straight_path;
using odoloc::world::TricycleSimulator;
using odoloc::world::Wheel;
using Edges = std::array<std::int64_t, kEncoderCount>;

constexpr double kPi = std::numbers::pi;
constexpr double kPoseTolerance = 1e-9;  // metres and radians
constexpr std::size_t kLeft = index(Encoder::kLeftRear);
constexpr std::size_t kRight = index(Encoder::kRightRear);
constexpr std::size_t kFront = index(Encoder::kFrontDrive);
constexpr std::size_t kSteer = index(Encoder::kSteering);

double deg(double degrees) {
  return degrees * kPi / 180;
}

double scale() {
  const char* env = std::getenv("ODOLOC_TEST_SCALE");  // NOLINT(concurrency-mt-unsafe)
  const double s = env != nullptr ? std::strtod(env, nullptr) : 1.0;
  return s > 0 && s < 1 ? s : 1.0;
}

// Wraps an angle difference to (-pi, pi].
double angle_diff(double a, double b) {
  return std::remainder(a - b, 2 * kPi);
}

Options start_at(double x, double y, double theta, std::uint32_t record_every = 0) {
  Options options;
  options.start = {x, y, theta};
  options.record_every_steps = record_every;
  return options;
}

// Decodes each A/B waveform x4 (Gray order AB = 00, 10, 11, 01 is forward)
// clock by clock; a jump of two quarters is illegal.
class WaveformDecoder {
 public:
  void tick(TricycleSimulator& sim) {
    // Indexed by A * 2 + B.
    static constexpr std::array<int, 4> kQuarterOfAb = {0, 3, 1, 2};
    const std::array<QuadratureLevels, kEncoderCount> ab = sim.tick();
    for (std::size_t e = 0; e < kEncoderCount; ++e) {
      const int q = kQuarterOfAb[(ab[e].a ? 2U : 0U) + (ab[e].b ? 1U : 0U)];
      const int step = (q - quarter_[e] + 4) % 4;
      legal_ = legal_ && step != 2;
      decoded_[e] += step == 1 ? 1 : step == 3 ? -1 : 0;
      quarter_[e] = q;
    }
  }
  // Runs to the end of the path; the waveforms must be legal and decode to
  // the true edge counts.
  Edges finish(TricycleSimulator& sim) {
    while (!sim.done())
      tick(sim);
    EXPECT_TRUE(legal_) << "a waveform skipped a quadrature state";
    EXPECT_EQ(decoded_, sim.true_edges()) << "decoded waveform differs from the true edge count";
    return sim.true_edges();
  }

 private:
  std::array<int, kEncoderCount> quarter_{};
  Edges decoded_{};
  bool legal_ = true;
};

Edges run(TricycleSimulator& sim) {
  return WaveformDecoder{}.finish(sim);
}

void expect_pose_near(const Pose& actual, const Pose& expected, double tolerance) {
  EXPECT_NEAR(actual.x_m, expected.x_m, tolerance);
  EXPECT_NEAR(actual.y_m, expected.y_m, tolerance);
  EXPECT_NEAR(angle_diff(actual.theta_rad, expected.theta_rad), 0, tolerance);
}

// Edges of a wheel rolling `metres` without slip: metres / (2 pi R) * 4 N G.
double edges_for(const odoloc::world::WheelEncoder& w, double metres) {
  return metres / (2 * kPi * w.true_radius_m) * 4 * w.lines * w.gear;
}

// Extra arc length of the raised-cosine bump over [0, u] by composite Simpson,
// independent of the simulator's elliptic-integral form.
double simpson_bump_extra(double h, double l, double u) {
  const int n = 20'000;
  const double step = u / n;
  const auto excess = [h, l](double v) {
    const double slope = kPi * h / l * std::sin(2 * kPi * v / l);
    return std::sqrt(1 + slope * slope) - 1;
  };
  double sum = excess(0) + excess(u);
  for (int i = 1; i < n; ++i)
    sum += (i % 2 == 1 ? 4 : 2) * excess(i * step);
  return sum * step / 3;
}

TEST(Tricycle, StraightDriveMovesAlongTheHeadingAtAnyHeading) {
  const Geometry g;
  const double distance = 0.8 * scale();
  const double speed = 2.0;
  for (const double heading : {0.0, 30.0, 90.0, 135.0, -120.0}) {
    SCOPED_TRACE(heading);
    const double theta = deg(heading);
    TricycleSimulator sim(g, straight_path(distance, speed), {}, start_at(1.5, -2.0, theta));
    WaveformDecoder decoder;

    // Mid-step, mid-path: the truth is exact at any clock.
    for (std::uint64_t i = 0; i < 1'234'567; ++i)
      decoder.tick(sim);
    const double t = 1'234'567 / 50e6;
    const auto mid = sim.pose();
    expect_pose_near(mid.pose,
                     {1.5 + speed * t * std::cos(theta), -2.0 + speed * t * std::sin(theta), theta},
                     kPoseTolerance);
    EXPECT_NEAR(mid.distance_m, speed * t, kPoseTolerance);
    EXPECT_NEAR(static_cast<double>(sim.true_edges()[kLeft]), edges_for(g.left_rear, speed * t),
                1.0);

    const Edges edges = decoder.finish(sim);
    const auto end = sim.pose();
    expect_pose_near(end.pose,
                     {1.5 + distance * std::cos(theta), -2.0 + distance * std::sin(theta), theta},
                     kPoseTolerance);
    EXPECT_NEAR(end.pose.theta_rad, theta, 1e-15);
    EXPECT_NEAR(static_cast<double>(edges[kLeft]), edges_for(g.left_rear, distance), 1.0);
    EXPECT_NEAR(static_cast<double>(edges[kRight]), edges_for(g.right_rear, distance), 1.0);
    EXPECT_NEAR(static_cast<double>(edges[kFront]), edges_for(g.front, distance), 1.0);
    EXPECT_EQ(edges[kSteer], 0);
  }
}

TEST(Tricycle, ReverseDriveMovesBackwardsAndCountsDown) {
  const Geometry g;
  const double distance = 0.3 * scale();
  TricycleSimulator sim(g, straight_path(distance, -1.0), {}, start_at(0, 0, deg(45)));
  const Edges edges = run(sim);
  const double back = -distance / std::numbers::sqrt2;
  expect_pose_near(sim.pose().pose, {back, back, deg(45)}, kPoseTolerance);
  EXPECT_NEAR(sim.distance(), distance, kPoseTolerance);  // the odometer is a path length
  EXPECT_NEAR(static_cast<double>(edges[kLeft]), -edges_for(g.left_rear, distance), 1.0);
  EXPECT_NEAR(static_cast<double>(edges[kFront]), -edges_for(g.front, distance), 1.0);
}

TEST(Tricycle, SteeringFollowsItsRateLimitAndItsEncoder) {
  const Geometry g;
  const double rate = 2.0;
  const double target = deg(30);
  TricycleSimulator sim(g, {{Segment::steer_to(target)}, rate}, {}, start_at(0.1, 0.2, 0.3));
  WaveformDecoder decoder;
  for (int i = 0; i < 3'333'333; ++i)
    decoder.tick(sim);
  EXPECT_NEAR(sim.pose().steer_rad, rate * 3'333'333 / 50e6, 1e-12);
  const Edges edges = decoder.finish(sim);
  const double ramp_s = target / rate;
  // Done at the first step boundary after the ramp.
  EXPECT_EQ(sim.clock(), static_cast<std::uint64_t>(std::ceil(ramp_s / 10e-6)) * 500);
  EXPECT_EQ(sim.pose().steer_rad, target);
  const double steering_edges = target / (2 * kPi) * 4 * g.steering.lines * g.steering.gear;
  EXPECT_NEAR(static_cast<double>(edges[kSteer]), steering_edges, 1.0);
  // Steering in place rolls nothing and moves nothing.
  EXPECT_EQ(edges[kLeft], 0);
  EXPECT_EQ(edges[kRight], 0);
  EXPECT_EQ(edges[kFront], 0);
  expect_pose_near(sim.pose().pose, {0.1, 0.2, 0.3}, 0);
}

TEST(Tricycle, ConstantSteeringDrivesACircleOfRadiusLOverTanPhi) {
  const Geometry g;
  const double phi = deg(35);
  const double radius = g.wheelbase_m / std::tan(phi);
  const double turns = scale();
  const double arc = 2 * kPi * radius * turns;
  const Pose start{0.3, 0.7, deg(60)};
  const Path path{{Segment::steer_to(phi), Segment::distance(3.0, phi, arc)}, 4.0};
  TricycleSimulator sim(g, path, {}, start_at(start.x_m, start.y_m, start.theta_rad, 20));
  const Edges edges = run(sim);

  // Instantaneous centre: radius to the left of the heading.
  const double cx = start.x_m - radius * std::sin(start.theta_rad);
  const double cy = start.y_m + radius * std::cos(start.theta_rad);
  const double inner = radius - g.track_m / 2;
  const double outer = radius + g.track_m / 2;
  const auto& samples = sim.trajectory();
  ASSERT_GT(samples.size(), 100U);
  EXPECT_EQ(samples.front().truth.time_s, 0);
  for (const auto& sample : samples) {
    const Pose& p = sample.truth.pose;
    EXPECT_NEAR(std::hypot(p.x_m - cx, p.y_m - cy), radius, kPoseTolerance);
    // Heading is tangent: the centre is always on the left.
    EXPECT_NEAR(angle_diff(std::atan2(cy - p.y_m, cx - p.x_m), p.theta_rad + kPi / 2), 0,
                kPoseTolerance);
    const double s = sample.truth.distance_m;
    if (s < 0.05)
      continue;
    const double left = sample.edges[kLeft] / g.left_rear.true_edges_per_metre();
    const double right = sample.edges[kRight] / g.right_rear.true_edges_per_metre();
    const double front = sample.edges[kFront] / g.front.true_edges_per_metre();
    EXPECT_NEAR(left / right, inner / outer, kPoseTolerance);
    EXPECT_NEAR(left, s * inner / radius, kPoseTolerance);
    EXPECT_NEAR(front, s / std::cos(phi), kPoseTolerance);
  }
  const auto end = sim.pose();
  EXPECT_EQ(samples.back().truth.pose.x_m, end.pose.x_m);  // the end of the path is recorded
  const double swept = arc / radius;
  EXPECT_NEAR(end.pose.theta_rad, start.theta_rad + swept, kPoseTolerance);
  if (turns == 1.0)
    expect_pose_near(end.pose, start, kPoseTolerance);
  EXPECT_NEAR(static_cast<double>(edges[kLeft]), edges_for(g.left_rear, swept * inner), 1.0);
  EXPECT_NEAR(static_cast<double>(edges[kRight]), edges_for(g.right_rear, swept * outer), 1.0);
  EXPECT_NEAR(static_cast<double>(edges[kFront]), edges_for(g.front, arc / std::cos(phi)), 1.0);
}

TEST(Tricycle, SquarePathReturnsToItsStartAtAnyHeading) {
  Geometry g;
  g.wheelbase_m = 0.25;  // a small robot keeps the drive short
  const double side = 0.8;
  const double phi = deg(40);
  const double radius = g.wheelbase_m / std::tan(phi);
  Path path = square_path(g, side, 4.0, phi);
  path.steer_rate_radps = 10;
  const std::vector<double> headings =
      scale() < 1 ? std::vector<double>{77} : std::vector<double>{0, 77, -150};
  for (const double heading : headings) {
    SCOPED_TRACE(heading);
    const Pose start{-1.0, 2.0, deg(heading)};
    TricycleSimulator sim(g, path, {}, start_at(start.x_m, start.y_m, start.theta_rad, 5));
    run(sim);
    const auto end = sim.pose();
    expect_pose_near(end.pose, start, kPoseTolerance);
    EXPECT_NEAR(end.pose.theta_rad, start.theta_rad + 2 * kPi, kPoseTolerance);
    EXPECT_NEAR(end.distance_m, 4 * (side - 2 * radius) + 2 * kPi * radius, kPoseTolerance);

    // In the start frame the path spans x in [-r, side - r], y in [0, side].
    double min_x = 0, max_x = 0, min_y = 0, max_y = 0;
    for (const auto& sample : sim.trajectory()) {
      const double dx = sample.truth.pose.x_m - start.x_m;
      const double dy = sample.truth.pose.y_m - start.y_m;
      const double along = dx * std::cos(start.theta_rad) + dy * std::sin(start.theta_rad);
      const double across = -dx * std::sin(start.theta_rad) + dy * std::cos(start.theta_rad);
      min_x = std::min(min_x, along);
      max_x = std::max(max_x, along);
      min_y = std::min(min_y, across);
      max_y = std::max(max_y, across);
    }
    EXPECT_NEAR(min_x, -radius, kPoseTolerance);
    EXPECT_NEAR(max_x, side - radius, kPoseTolerance);
    EXPECT_NEAR(min_y, 0, kPoseTolerance);
    EXPECT_NEAR(max_y, side, kPoseTolerance);
  }
}

// Reference: classic RK4 on (x, y, theta, sL, sR, sF) with a fine step and the
// steering ramp written from the path's definition.
struct Reference {
  Pose pose;
  std::array<double, 3> wheel_m{};
};
Reference rk4_reference(const Geometry& g, const Pose& start, double speed, double rate,
                        const std::vector<std::array<double, 2>>& legs) {
  // Steering angle at time t: each leg ramps toward its target from where the
  // previous leg left it.
  const auto steer_at = [&](double t) {
    double phi = 0;
    for (const auto& [target, seconds] : legs) {
      const double in_leg = std::min(t, seconds);
      phi += std::clamp(target - phi, -rate * in_leg, rate * in_leg);
      t -= seconds;
      if (t <= 0)
        break;
    }
    return phi;
  };
  using State = std::array<double, 6>;
  const auto derivative = [&](double t, const State& s) {
    const double phi = steer_at(t);
    const double omega = speed * std::tan(phi) / g.wheelbase_m;
    return State{
        speed * std::cos(s[2]),        speed * std::sin(s[2]),        omega,
        speed - omega * g.track_m / 2, speed + omega * g.track_m / 2, speed / std::cos(phi)};
  };
  double total = 0;
  for (const auto& leg : legs)
    total += leg[1];
  const int steps = 400'000;
  const double h = total / steps;
  State s{start.x_m, start.y_m, start.theta_rad, 0, 0, 0};
  for (int i = 0; i < steps; ++i) {
    const double t = i * h;
    const auto add = [](const State& a, const State& b, double k) {
      State r;
      for (std::size_t j = 0; j < r.size(); ++j)
        r[j] = a[j] + k * b[j];
      return r;
    };
    const State k1 = derivative(t, s);
    const State k2 = derivative(t + h / 2, add(s, k1, h / 2));
    const State k3 = derivative(t + h / 2, add(s, k2, h / 2));
    const State k4 = derivative(t + h, add(s, k3, h));
    for (std::size_t j = 0; j < s.size(); ++j)
      s[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  return {{s[0], s[1], s[2]}, {s[3], s[4], s[5]}};
}

TEST(Tricycle, SteeringWhileDrivingMatchesAnIndependentIntegration) {
  const Geometry g;
  const double speed = 1.5;
  const double rate = 1.5;
  // (target, seconds): ramp left and hold, then ramp right through zero.
  const std::vector<std::array<double, 2>> legs = {{deg(30), 0.4 * scale()},
                                                   {deg(-20), 0.5 * scale()}};
  Path path{{}, rate};
  for (const auto& [target, seconds] : legs)
    path.segments.push_back(Segment::duration(speed, target, seconds));
  const Pose start{0.5, -0.25, deg(-40)};
  const Reference ref = rk4_reference(g, start, speed, rate, legs);
  for (const std::uint32_t clocks_per_step : {50U, 500U, 5000U}) {
    SCOPED_TRACE(clocks_per_step);
    Options options = start_at(start.x_m, start.y_m, start.theta_rad);
    options.clocks_per_step = clocks_per_step;
    TricycleSimulator sim(g, path, {}, options);
    const Edges edges = run(sim);
    const auto end = sim.pose();
    expect_pose_near(end.pose, ref.pose, kPoseTolerance);
    EXPECT_NEAR(end.pose.theta_rad, ref.pose.theta_rad, kPoseTolerance);
    EXPECT_NEAR(static_cast<double>(edges[kLeft]), edges_for(g.left_rear, ref.wheel_m[0]), 1.0);
    EXPECT_NEAR(static_cast<double>(edges[kRight]), edges_for(g.right_rear, ref.wheel_m[1]), 1.0);
    EXPECT_NEAR(static_cast<double>(edges[kFront]), edges_for(g.front, ref.wheel_m[2]), 1.0);
  }
}

TEST(Tricycle, BumpExtraLengthIsTheProfileArcLengthExcess) {
  for (const auto& [h, l] : {std::array<double, 2>{0.02, 0.3}, {0.005, 0.1}, {0.05, 1.0}}) {
    SCOPED_TRACE(testing::Message() << h << " x " << l);
    const double expected = simpson_bump_extra(h, l, l);
    EXPECT_NEAR(bump_extra_length(h, l), expected, 1e-12 * l);
    // Small-slope limit: l (pi h / l)^2 / 4.
    EXPECT_NEAR(bump_extra_length(h, l) / (kPi * kPi * h * h / (4 * l)), 1, 0.02);
  }
}

struct Outcome {
  Edges edges;
  odoloc::world::TruePose end;
};
Outcome drive_straight(const Geometry& g, double distance, Disturbances disturbances) {
  TricycleSimulator sim(g, straight_path(distance, 2.0), std::move(disturbances),
                        start_at(0.2, 0.1, deg(20)));
  const Edges edges = run(sim);
  return {edges, sim.pose()};
}

TEST(Tricycle, BumpPresetsOverCountOnlyTheWheelsOnTheHump) {
  const Geometry g;
  const double h = 0.02;
  const double l = 0.3;
  const double start = 0.1;
  const double distance = start + l + 0.05;
  const double extra = simpson_bump_extra(h, l, l);
  const Outcome flat = drive_straight(g, distance, {});

  struct Case {
    const char* name;
    Disturbances disturbances;
    std::array<bool, 3> bumped;
  };
  const std::vector<Case> cases = {
      {"Fig. 4a both rear", bump_under_both_rear(start, h, l), {true, true, false}},
      {"Fig. 4b one rear",
       bump_under_one_rear(Wheel::kRightRear, start, h, l),
       {false, true, false}},
      {"Fig. 4c front", bump_under_front(start, h, l), {false, false, true}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Outcome bumped = drive_straight(g, distance, c.disturbances);
    for (const Wheel w : {Wheel::kLeftRear, Wheel::kRightRear, Wheel::kFront}) {
      const std::size_t e = index(odoloc::world::encoder(w));
      const bool hit = c.bumped[index(w)];
      const double over = static_cast<double>(bumped.edges[e] - flat.edges[e]);
      EXPECT_NEAR(over, hit ? edges_for(g.wheel(w), extra) : 0.0, hit ? 1.5 : 0.0)
          << "wheel " << index(w);
    }
    EXPECT_EQ(bumped.edges[kSteer], flat.edges[kSteer]);
    // Same pose up to rounding: the bump only adds split points to the steps.
    expect_pose_near(bumped.end.pose, flat.end.pose, 1e-12);
  }
  EXPECT_GT(edges_for(g.left_rear, extra), 30);  // the effect is many edges, not noise
}

TEST(Tricycle, BumpOverCountGrowsAlongTheProfile) {
  const Geometry g;
  const double h = 0.02;
  const double l = 0.3;
  const double start = 0.1;
  TricycleSimulator sim(g, straight_path(start + l + 0.05, 2.0),
                        bump_under_one_rear(Wheel::kLeftRear, start, h, l), start_at(0, 0, 0, 37));
  run(sim);
  int on_bump = 0;
  for (const auto& sample : sim.trajectory()) {
    const double s = sample.truth.distance_m;
    const double rolled = sample.edges[kLeft] / g.left_rear.true_edges_per_metre();
    const double expected = s > start ? simpson_bump_extra(h, l, std::min(s - start, l)) : 0.0;
    EXPECT_NEAR(rolled - s, expected, 1e-10) << "at " << s << " m";
    on_bump += s > start && s < start + l ? 1 : 0;
  }
  EXPECT_GT(on_bump, 300);
}

TEST(Tricycle, DrivingBackOverABumpUnwindsItsOverCount) {
  const Geometry g;
  // Forward to the top of the hump, then back to the start.
  const Path path{{Segment::distance(1.0, 0, 0.25), Segment::distance(-1.0, 0, 0.25)}};
  TricycleSimulator sim(g, path, bump_under_front(0.1, 0.02, 0.3), start_at(0, 0, 0, 1000));
  const Edges edges = run(sim);
  for (const std::size_t e : {kLeft, kRight, kFront})
    EXPECT_LE(std::abs(edges[e]), 1) << e;
  EXPECT_NEAR(sim.trajectory().back().edges[kFront], 0, 1e-6);
  // Half-way up, the front wheel had over-counted half the hump.
  const auto top = std::find_if(sim.trajectory().begin(), sim.trajectory().end(),
                                [](const auto& s) { return s.truth.distance_m >= 0.25; });
  ASSERT_NE(top, sim.trajectory().end());
  EXPECT_NEAR(top->edges[kFront] / g.front.true_edges_per_metre() - 0.25,
              bump_extra_length(0.02, 0.3) / 2, 1e-9);
}

TEST(Tricycle, SlipOverCountsByItsRatio) {
  const Geometry g;
  const double distance = 0.6;
  const Slip slip{Wheel::kFront, 0.2, 0.5, 0.05};
  const Outcome flat = drive_straight(g, distance, {});
  const Outcome slipping = drive_straight(g, distance, Disturbances{.bumps = {}, .slips = {slip}});
  EXPECT_NEAR(static_cast<double>(slipping.edges[kFront] - flat.edges[kFront]),
              edges_for(g.front, (slip.end_m - slip.start_m) * slip.ratio), 1.5);
  EXPECT_EQ(slipping.edges[kLeft], flat.edges[kLeft]);
  EXPECT_EQ(slipping.edges[kRight], flat.edges[kRight]);
  expect_pose_near(slipping.end.pose, flat.end.pose, 1e-12);
}

TEST(Tricycle, LargerTrueRadiusCountsProportionallyFewerEdges) {
  const Geometry nominal;
  Geometry worn = nominal;
  worn.left_rear.true_radius_m *= 1.01;
  const double distance = 0.5;
  const Outcome a = drive_straight(nominal, distance, {});
  const Outcome b = drive_straight(worn, distance, {});
  const double expected = distance / (2 * kPi * 1.01 * nominal.left_rear.nominal_radius_m) * 4 *
                          nominal.left_rear.lines * nominal.left_rear.gear;
  EXPECT_NEAR(static_cast<double>(b.edges[kLeft]), expected, 1.0);
  EXPECT_NEAR(static_cast<double>(b.edges[kLeft]) / static_cast<double>(a.edges[kLeft]), 1 / 1.01,
              2 / static_cast<double>(a.edges[kLeft]));
  EXPECT_EQ(b.edges[kRight], a.edges[kRight]);
  expect_pose_near(b.end.pose, a.end.pose, 0);
}

TEST(Tricycle, RejectsInconsistentConfigurations) {
  const Geometry g;
  EXPECT_THROW(TricycleSimulator(g, {{Segment::steer_to(deg(41))}}), std::invalid_argument);
  EXPECT_THROW(TricycleSimulator(g, {{Segment::distance(0, 0, 1)}}), std::invalid_argument);
  EXPECT_THROW(TricycleSimulator(g, straight_path(1, 1), bump_under_front(0, 0.05, 0.1)),
               std::invalid_argument);  // too sharp for a 75 mm wheel
  // A bump or slip names a Wheel, which cannot be the steering encoder; a
  // value outside the enum is rejected too.
  static_assert(!std::is_convertible_v<Encoder, Wheel>);
  const auto no_wheel = static_cast<Wheel>(odoloc::world::kWheelCount);
  EXPECT_THROW(TricycleSimulator(g, straight_path(1, 1),
                                 Disturbances{.bumps = {}, .slips = {{no_wheel, 0, 1, 0.1}}}),
               std::invalid_argument);
  EXPECT_THROW(TricycleSimulator(g, straight_path(1, 1),
                                 Disturbances{.bumps = {{no_wheel, 0, 0.02, 0.3}}, .slips = {}}),
               std::invalid_argument);
  EXPECT_THROW((void)g.wheel(no_wheel), std::invalid_argument);
  EXPECT_THROW(square_path(g, 1.0, 1, deg(30)), std::invalid_argument);  // radius 0.87 m > side/2
  // 1000 m/s on a 50 mm wheel is beyond one edge per clock.
  TricycleSimulator too_fast(g, straight_path(1, 1000));
  EXPECT_THROW(too_fast.tick(), std::range_error);
}

}  // namespace
