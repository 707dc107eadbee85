// The acoustic world against physics: times of flight against distance over
// the speed of sound (static) and against a long-double bisection of
// |p_rx(t) - p_tx| = c (t - t_emit) (moving robot, moving transmitter), echoes
// against independently mirrored image paths, occlusion, the threshold
// crossing tau ln(A / (A - V)), amplitudes against 1/r, the reference's air
// absorption and a power-series baffled piston, the carrier's edges and the
// phase difference 2 pi f dt, the papers' schedules, the pins clock by clock,
// seeded reproducibility and the statistics of noise and jitter.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"
#include "odoloc/world/tricycle.hpp"

namespace {

using odoloc::world::AcousticNoise;
using odoloc::world::AcousticPins;
using odoloc::world::AcousticRun;
using odoloc::world::AcousticWorld;
using odoloc::world::Arrival;
using odoloc::world::Beacon;
using odoloc::world::ComparatorKind;
using odoloc::world::Emission;
using odoloc::world::EmissionRecord;
using odoloc::world::KleemanTiming;
using odoloc::world::Obstacle;
using odoloc::world::PinLevels;
using odoloc::world::PinSource;
using odoloc::world::Pose;
using odoloc::world::Pulse;
using odoloc::world::Receiver;
using odoloc::world::Room;
using odoloc::world::Schedule;
using odoloc::world::simulate;
using odoloc::world::stationary;
using odoloc::world::Trajectory;
using odoloc::world::TriggeredTiming;
using odoloc::world::Vec2;
using odoloc::world::Wall;

constexpr double kPi = std::numbers::pi;
constexpr double kClockHz = 50e6;
constexpr double kClockS = 1 / kClockHz;

double deg(double degrees) {
  return degrees * kPi / 180;
}

// Independent references -----------------------------------------------------

// The reference's c = 331.3 sqrt(1 + T/273.15) m/s.
double speed_of_sound(double temperature_c) {
  return 331.3 * std::sqrt(1 + temperature_c / 273.15);
}

Vec2 body_point(const Pose& pose, Vec2 body) {
  return {pose.x_m + body.x_m * std::cos(pose.theta_rad) - body.y_m * std::sin(pose.theta_rad),
          pose.y_m + body.x_m * std::sin(pose.theta_rad) + body.y_m * std::cos(pose.theta_rad)};
}

double planar_distance(Vec2 a, Vec2 b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
}

// J1 by its power series (independent of std::cyl_bessel_j).
double bessel_j1(double x) {
  long double term = x / 2.0L;
  long double sum = term;
  const long double q = -(static_cast<long double>(x) * x) / 4;
  for (int m = 1; m < 40; ++m) {
    term *= q / (static_cast<long double>(m) * (m + 1));
    sum += term;
  }
  return static_cast<double>(sum);
}
double piston(double ka, double off_axis_rad) {
  const double x = ka * std::sin(off_axis_rad);
  return x == 0 ? 1.0 : 2 * bessel_j1(x) / x;
}

double db(double ratio) {
  return 20 * std::log10(ratio);
}

// A transmitter with one transducer along axis_rad; piston radius 0 hears
// the whole front half-plane equally.
Beacon beacon_at(Vec2 p, double axis_rad, double piston_radius_m = 0, double carrier_hz = 40e3) {
  Beacon b;
  b.position = p;
  b.axes_rad = {axis_rad};
  b.piston_radius_m = piston_radius_m;
  b.carrier_hz = carrier_hz;
  return b;
}
Receiver receiver_at(Vec2 p, double axis_rad, double piston_radius_m = 0) {
  Receiver r;
  r.position = p;
  r.axis_rad = axis_rad;
  r.piston_radius_m = piston_radius_m;
  return r;
}
Schedule one_emission(std::size_t beacon, double trigger_s, double duration_s) {
  return Schedule{{Emission{beacon, trigger_s, duration_s}}, {}};
}

// The level of a waveform at clock n: high when a pulse holds n / f.
bool level_at(const std::vector<Pulse>& waveform, std::uint64_t n) {
  const double t = static_cast<double>(n) / kClockHz;
  return std::any_of(waveform.begin(), waveform.end(),
                     [t](const Pulse& p) { return p.rise_s <= t && t < p.fall_s; });
}

std::vector<std::uint64_t> rising_clocks(const PinSource& pin) {
  std::vector<std::uint64_t> rises;
  for (std::size_t i = 0; i < pin.transitions().size(); i += 2)
    rises.push_back(pin.transitions()[i]);
  return rises;
}

struct Stats {
  double mean = 0;
  double sd = 0;
};
Stats stats(const std::vector<double>& v) {
  double sum = 0;
  for (const double x : v)
    sum += x;
  const double mean = sum / static_cast<double>(v.size());
  double sq = 0;
  for (const double x : v)
    sq += (x - mean) * (x - mean);
  return {mean, std::sqrt(sq / static_cast<double>(v.size() - 1))};
}

// Air and amplitude -----------------------------------------------------------

TEST(Acoustics, SpeedOfSoundAndAbsorptionMatchTheReference) {
  odoloc::world::Air air;
  EXPECT_NEAR(air.speed_of_sound_mps(), 343.2, 0.05);
  air.temperature_c = 0;
  EXPECT_DOUBLE_EQ(air.speed_of_sound_mps(), 331.3);
  // +0.6 m/s per degree C.
  air.temperature_c = 21;
  const double c21 = air.speed_of_sound_mps();
  air.temperature_c = 20;
  EXPECT_NEAR(c21 - air.speed_of_sound_mps(), 0.6, 0.02);
  // ISO 9613-1 values quoted by the reference (acoustics.md).
  EXPECT_NEAR(air.absorption_db_per_m(40e3), 1.3, 0.05);
  EXPECT_NEAR(air.absorption_db_per_m(32.5e3), 1.0, 0.05);
  air.relative_humidity = 0.2;
  EXPECT_NEAR(air.absorption_db_per_m(40e3), 0.8, 0.05);
}

// A receiver on the beacon's axis at each distance, facing it; returns the
// direct arrivals' amplitudes.
std::vector<double> on_axis_amplitudes(const std::vector<double>& distances, double carrier_hz,
                                       double humidity) {
  AcousticWorld w;
  w.air.relative_humidity = humidity;
  w.beacons = {beacon_at({0, 0}, 0, 0, carrier_hz)};
  for (const double d : distances) {
    Receiver r = receiver_at({d, 0}, kPi);
    r.resonance_hz = carrier_hz;
    w.receivers.push_back(r);
  }
  const AcousticRun run = simulate(w, one_emission(0, 0, 2.5e-3), stationary({}), 1, 1);
  std::vector<double> amplitudes;
  for (const auto& reception : run.emissions.at(0).receivers)
    amplitudes.push_back(reception.direct.amplitude_v);
  return amplitudes;
}

TEST(Acoustics, AmplitudeFallsAsOneOverDistanceWithAirAbsorption) {
  struct Case {
    double carrier_hz, humidity, reference_db_per_m;
  };
  for (const Case c : {Case{40e3, 0.5, 1.3}, Case{32.5e3, 0.5, 1.0}, Case{40e3, 0.2, 0.8}}) {
    SCOPED_TRACE(c.carrier_hz);
    const std::vector<double> r = {1.0, 2.0, 4.0, 8.0};
    const std::vector<double> a = on_axis_amplitudes(r, c.carrier_hz, c.humidity);
    EXPECT_NEAR(a[0], 12.5, 1e-9);  // Kleeman's 12.5 V at 1 m
    // A r = A_1m 10^(-alpha (r - 1) / 20): the absorption from two distances.
    const double alpha = -db(a[3] * r[3] / (a[0] * r[0])) / (r[3] - r[0]);
    EXPECT_NEAR(alpha, c.reference_db_per_m, 0.05);
    for (std::size_t i = 1; i < r.size(); ++i)
      EXPECT_NEAR(db(a[i] * r[i] / (a[0] * r[0])), -alpha * (r[i] - r[0]), 1e-9);
  }
}

TEST(Acoustics, DirectivityIsABaffledPistonAndMatchesKleemansFigures) {
  const double c = speed_of_sound(20);
  const double k = 2 * kPi * 40e3 / c;
  const double tx_radius = odoloc::world::kleeman_beacons(Room{}).at(0).piston_radius_m;
  const double rx_radius = odoloc::world::kleeman_octagon().at(0).piston_radius_m;

  // Transmitter: receivers on a 1 m circle at angles off its axis, facing it.
  AcousticWorld w;
  w.beacons = {beacon_at({0, 0}, 0, tx_radius)};
  const std::vector<double> angles = {0, 10, 22.5, 30, 45, 60};
  for (const double a : angles)
    w.receivers.push_back(receiver_at({std::cos(deg(a)), std::sin(deg(a))}, deg(a) + kPi));
  AcousticRun run = simulate(w, one_emission(0, 0, 2.5e-3), stationary({}), 1, 1);
  const auto& tx = run.emissions.at(0).receivers;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    SCOPED_TRACE(angles[i]);
    const double d = piston(k * tx_radius, deg(angles[i]));
    EXPECT_NEAR(tx[i].direct.amplitude_v / tx[0].direct.amplitude_v, std::abs(d), 1e-9);
    // A side lobe (60 degrees, past the first null) inverts the carrier:
    // its rising edges come half a period after arrival + k / f.
    EXPECT_EQ(tx[i].direct.inverted, d < 0);
    ASSERT_FALSE(run.channels[i].carrier.empty());
    const double phase = (run.channels[i].carrier[0].rise_s - tx[i].direct.true_time_s) * 40e3;
    EXPECT_NEAR(std::remainder(phase - (d < 0 ? 0.5 : 0.0), 1.0), 0, 1e-6);
  }
  EXPECT_LT(piston(k * tx_radius, deg(60)), 0);
  EXPECT_NEAR(db(tx[4].direct.amplitude_v / tx[0].direct.amplitude_v), -20, 0.3);  // Kleeman

  // Receiver: one 2 m away, turned 0 and 22.5 degrees away from the beacon.
  w.beacons = {beacon_at({0, 0}, 0)};
  w.receivers = {receiver_at({2, 0}, kPi, rx_radius),
                 receiver_at({2, 0}, kPi + deg(22.5), rx_radius)};
  run = simulate(w, one_emission(0, 0, 2.5e-3), stationary({}), 1, 1);
  const auto& rx = run.emissions.at(0).receivers;
  const double ratio = rx[1].direct.amplitude_v / rx[0].direct.amplitude_v;
  EXPECT_NEAR(ratio, piston(k * rx_radius, deg(22.5)), 1e-9);
  EXPECT_NEAR(db(ratio), -3, 0.2);  // Kleeman

  // Nothing behind a transducer.
  w.receivers = {receiver_at({-2, 0}, 0)};
  run = simulate(w, one_emission(0, 0, 2.5e-3), stationary({}), 1, 1);
  EXPECT_EQ(run.emissions.at(0).receivers.at(0).direct.amplitude_v, 0);
  EXPECT_FALSE(run.emissions.at(0).receivers.at(0).direct.above_threshold);
}

TEST(Acoustics, ReceiverResonanceRejectsTheOtherCarrier) {
  // Thamma's two carriers: a 32.5 kHz burst at a 40 kHz receiver of Q.
  AcousticWorld w;
  w.beacons = {beacon_at({0, 0}, 0, 0, 40e3), beacon_at({0, 0}, 0, 0, 32.5e3)};
  Receiver r = receiver_at({3, 0}, kPi);
  r.resonance_hz = 40e3;
  r.quality = 10;
  w.air.relative_humidity = 0;  // compare the carriers without their different absorption
  w.air.temperature_c = 20;
  w.receivers = {r};
  Schedule s{{Emission{0, 0, 1e-3}, Emission{1, 0.1, 1e-3}}, {}};
  const AcousticRun run = simulate(w, s, stationary({}), 1, 1);
  const double a40 = run.emissions.at(0).receivers.at(0).direct.amplitude_v;
  const double a325 = run.emissions.at(1).receivers.at(0).direct.amplitude_v;
  const double absorption = w.air.absorption_db_per_m(40e3) - w.air.absorption_db_per_m(32.5e3);
  const double detune = 10 * (32.5 / 40 - 40 / 32.5);
  EXPECT_NEAR(db(a325 / a40) - absorption * 2, db(1 / std::sqrt(1 + detune * detune)), 1e-9);
}

// Times of flight ------------------------------------------------------------

TEST(Acoustics, StaticArrivalIsDistanceOverTheSpeedOfSound) {
  const Pose robot{3.0, 4.0, 0.7};
  for (const double temperature : {-10.0, 20.0, 35.0}) {
    for (const double height : {0.0, 1.2}) {
      SCOPED_TRACE(testing::Message() << temperature << " degC, h " << height);
      AcousticWorld w;
      w.air.temperature_c = temperature;
      w.height_m = height;
      w.beacons = {beacon_at({0.2, 0.3}, deg(45)), beacon_at({9.5, 0.5}, deg(135)),
                   beacon_at({5.0, 9.8}, deg(-90))};
      w.beacons[1].electronics_delay_s = 123e-6;
      w.receivers = odoloc::world::kleeman_octagon({0.1, -0.05});
      Schedule s;
      for (std::size_t b = 0; b < 3; ++b)
        s.emissions.push_back({b, 0.01 + 0.1 * static_cast<double>(b), 2.5e-3});
      const AcousticRun run = simulate(w, s, stationary(robot), 1, 7);
      ASSERT_EQ(run.emissions.size(), 3U);
      const double c = speed_of_sound(temperature);
      for (const EmissionRecord& e : run.emissions) {
        const Beacon& b = w.beacons[e.emission.beacon];
        EXPECT_DOUBLE_EQ(e.emission_s, e.emission.trigger_s + b.electronics_delay_s);
        for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
          const Vec2 p = body_point(robot, w.receivers[ch].position);
          const double d = std::hypot(planar_distance(p, b.position), height);
          const Arrival& a = e.receivers[ch].direct;
          EXPECT_NEAR(a.true_time_s, e.emission_s + d / c, 1e-12);
          EXPECT_NEAR(a.path_m, d, 1e-9);
          EXPECT_EQ(a.time_s, a.true_time_s);  // no turbulence
          EXPECT_FALSE(a.occluded);
          // The pin sees the rise in the clock after it.
          if (a.above_threshold) {
            const auto rises = rising_clocks(PinSource(run.channels[ch].envelope, kClockHz));
            const double rise = a.above_threshold->rise_s;
            EXPECT_EQ(std::count(rises.begin(), rises.end(),
                                 static_cast<std::uint64_t>(std::ceil(rise * kClockHz))),
                      1);
          }
        }
      }
    }
  }
}

// A robot that drives at about 1 m/s while turning.
Pose moving_pose(long double t) {
  return {static_cast<double>(2 + t * std::cos(0.3L)),
          static_cast<double>(3 + t * std::sin(0.3L) + 0.2L * std::sin(3 * t)),
          static_cast<double>(0.3L + 0.8L * t)};
}

// |p(t) - source| = c (t - t_emit) by bisection in long double.
long double bisect_arrival(Vec2 source, long double t_emit, Vec2 body, long double c,
                           const auto& pose_of) {
  const auto g = [&](long double t) {
    const auto [x, y, theta] = pose_of(t);
    const long double px = x + body.x_m * std::cos(theta) - body.y_m * std::sin(theta);
    const long double py = y + body.x_m * std::sin(theta) + body.y_m * std::cos(theta);
    return std::hypot(px - source.x_m, py - source.y_m) - c * (t - t_emit);
  };
  long double lo = t_emit;
  long double hi = t_emit + 1;
  for (int i = 0; i < 200; ++i) {
    const long double mid = (lo + hi) / 2;
    (g(mid) > 0 ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

struct LongPose {
  long double x, y, theta;
};
LongPose moving_pose_long(long double t) {
  return {2 + t * std::cos(0.3L), 3 + t * std::sin(0.3L) + 0.2L * std::sin(3 * t), 0.3L + 0.8L * t};
}

TEST(Acoustics, MovingRobotArrivalSolvesTheFlightEquation) {
  AcousticWorld w;
  w.beacons = {beacon_at({9, 8}, deg(-135))};
  w.receivers = {receiver_at({0.1, 0.05}, 0), receiver_at({-0.2, 0.15}, deg(-30))};
  const Trajectory robot = [](double t) { return moving_pose(t); };
  const double t_emit = 0.5;
  const AcousticRun run = simulate(w, one_emission(0, t_emit, 2.5e-3), robot, 1, 3);
  const long double c = 331.3L * std::sqrt(1 + 20 / 273.15L);
  for (std::size_t ch = 0; ch < 2; ++ch) {
    SCOPED_TRACE(ch);
    const Arrival& a = run.emissions.at(0).receivers.at(ch).direct;
    const long double exact =
        bisect_arrival({9, 8}, t_emit, w.receivers[ch].position, c, moving_pose_long);
    EXPECT_NEAR(a.true_time_s, static_cast<double>(exact), 1e-10);
    // The motion matters: the receiver's position at the emission time is
    // tens of microseconds off.
    const Vec2 p0 = body_point(moving_pose(t_emit), w.receivers[ch].position);
    const double naive = t_emit + planar_distance(p0, {9, 8}) / static_cast<double>(c);
    EXPECT_GT(std::abs(naive - a.true_time_s), 10e-6);
    // Every carrier rising edge is the arrival of a wavefront that left at
    // phase 0: t_emit + k / f.
    const auto& carrier = run.channels[ch].carrier;
    ASSERT_GT(carrier.size(), 50U);
    for (const std::size_t i : {std::size_t{0}, std::size_t{17}, carrier.size() - 1}) {
      const long double left =
          t_emit + std::round((carrier[i].rise_s - a.true_time_s) * 40e3) / 40e3L;
      EXPECT_NEAR(carrier[i].rise_s,
                  static_cast<double>(
                      bisect_arrival({9, 8}, left, w.receivers[ch].position, c, moving_pose_long)),
                  1e-10);
    }
  }
}

TEST(Acoustics, MovingTransmitterEmitsFromItsPositionAtTheEmissionTime) {
  // The binaural pair: the transmitter on a robot driving sideways at 1 m/s.
  const Trajectory transmitter = [](double t) { return Pose{0.1 + t, 1.5, kPi}; };
  AcousticWorld w = odoloc::world::binaural_world(transmitter, 0.35);
  const double t_emit = 0.2;
  const AcousticRun run = simulate(w, one_emission(0, t_emit, 1e-3), stationary({}), 1, 1);
  const Vec2 source{0.1 + t_emit, 1.5};
  const double c = speed_of_sound(20);
  for (std::size_t ch = 0; ch < 2; ++ch) {
    const Vec2 p{ch == 0 ? -0.175 : 0.175, 0};
    EXPECT_NEAR(run.emissions.at(0).receivers.at(ch).direct.true_time_s,
                t_emit + planar_distance(source, p) / c, 1e-12);
  }
}

// Echoes and occlusion -------------------------------------------------------

Vec2 mirrored(Vec2 p, Wall wall, double width, double depth) {
  switch (wall) {
    case Wall::kXMin:
      return {-p.x_m, p.y_m};
    case Wall::kXMax:
      return {2 * width - p.x_m, p.y_m};
    case Wall::kYMin:
      return {p.x_m, -p.y_m};
    case Wall::kYMax:
      return {p.x_m, 2 * depth - p.y_m};
  }
  return p;
}

TEST(Acoustics, EchoDelayEqualsTheImagePathDifference) {
  AcousticWorld w;
  w.room = Room{8, 6, {0.9, 0.8, 0.7, 0.6}};
  w.beacons = {beacon_at({2, 1.5}, 0)};
  w.beacons[0].axes_rad = {0, kPi / 2, kPi, -kPi / 2};
  const Pose robot{5.5, 3.5, 0.4};
  w.receivers = {receiver_at({0.1, 0}, 0), receiver_at({0, 0.1}, kPi / 2),
                 receiver_at({-0.1, 0}, kPi), receiver_at({0, -0.1}, -kPi / 2)};
  const double c = speed_of_sound(20);
  const AcousticRun run = simulate(w, one_emission(0, 0.05, 2.5e-3), stationary(robot), 1, 1);
  for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
    SCOPED_TRACE(ch);
    const auto& reception = run.emissions.at(0).receivers.at(ch);
    ASSERT_EQ(reception.echoes.size(), 4U);
    const Vec2 p = body_point(robot, w.receivers[ch].position);
    for (const Arrival& echo : reception.echoes) {
      ASSERT_TRUE(echo.wall);
      const Vec2 image = mirrored({2, 1.5}, *echo.wall, 8, 6);
      EXPECT_NEAR(echo.source.x_m, image.x_m, 1e-12);
      EXPECT_NEAR(echo.source.y_m, image.y_m, 1e-12);
      const double delay = (planar_distance(image, p) - planar_distance({2, 1.5}, p)) / c;
      EXPECT_NEAR(echo.true_time_s - reception.direct.true_time_s, delay, 1e-12);
      EXPECT_GT(echo.true_time_s, reception.direct.true_time_s);  // never early
    }
  }
  // The echo's amplitude is proportional to its wall's reflection.
  AcousticWorld harder = w;
  harder.room->reflection = {0.45, 0.8, 0.7, 0.6};
  const AcousticRun run2 = simulate(harder, one_emission(0, 0.05, 2.5e-3), stationary(robot), 1, 1);
  for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
    const auto& e1 = run.emissions[0].receivers[ch].echoes;
    const auto& e2 = run2.emissions[0].receivers[ch].echoes;
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_NEAR(e2[i].amplitude_v, e1[i].amplitude_v * (*e1[i].wall == Wall::kXMin ? 0.5 : 1),
                  1e-12);
  }
}

TEST(Acoustics, OcclusionRemovesExactlyTheBlockedPaths) {
  AcousticWorld w;
  w.room = Room{5, 5, {0.9, 0.9, 0.9, 0.9}};
  w.beacons = {beacon_at({0.5, 2.5}, 0)};
  const Pose robot{3, 2.5, 0};
  w.receivers = {receiver_at({-0.1, 0.3}, kPi), receiver_at({-0.1, -0.3}, kPi)};
  const double c = speed_of_sound(20);
  const Schedule s = one_emission(0, 0, 2.5e-3);
  const AcousticRun clear = simulate(w, s, stationary(robot), 1, 1);
  // A screen across the direct path to receiver 0 (y = 2.65 at x = 1.7) and
  // its echo from the wall x = 0 (y = 2.694), clear of the others (the
  // nearest, the first leg of the echo from x = 5, passes at y = 2.555).
  w.obstacles = {Obstacle{{1.7, 2.6}, {1.7, 2.75}, 0}};
  const AcousticRun blocked = simulate(w, s, stationary(robot), 1, 1);

  const auto& r0 = blocked.emissions[0].receivers[0];
  EXPECT_TRUE(r0.direct.occluded);
  EXPECT_FALSE(r0.direct.above_threshold);
  for (const Arrival& echo : r0.echoes)
    EXPECT_EQ(echo.occluded, *echo.wall == Wall::kXMin) << static_cast<int>(*echo.wall);
  // Everything else is unchanged.
  const auto& clear0 = clear.emissions[0].receivers[0];
  EXPECT_FALSE(clear0.direct.occluded);
  EXPECT_EQ(clear0.direct.true_time_s, r0.direct.true_time_s);  // still recorded
  for (std::size_t i = 0; i < 4; ++i)
    if (*r0.echoes[i].wall != Wall::kXMin) {
      EXPECT_EQ(clear0.echoes[i].above_threshold, r0.echoes[i].above_threshold);
    }
  EXPECT_EQ(clear.channels[1].envelope, blocked.channels[1].envelope);
  EXPECT_FALSE(blocked.emissions[0].receivers[1].direct.occluded);

  // The first pulse on channel 0 is now an echo: later than the direct path
  // would have been, at the earliest unblocked image path (y walls).
  const Vec2 p0 = body_point(robot, w.receivers[0].position);
  const double direct = planar_distance({0.5, 2.5}, p0) / c;
  const double echo =
      std::min(planar_distance({0.5, -2.5}, p0), planar_distance({0.5, 7.5}, p0)) / c;
  const auto& wave = blocked.channels[0].envelope;
  ASSERT_FALSE(wave.empty());
  EXPECT_GT(wave.front().rise_s, direct);
  EXPECT_GT(wave.front().rise_s, echo);
  EXPECT_LT(wave.front().rise_s, echo + 1e-3);  // its threshold delay
  EXPECT_LT(clear.channels[0].envelope.front().rise_s, echo);

  // A disc on the direct path to receiver 1 blocks it alone.
  w.obstacles = {Obstacle{{1.7, 2.35}, {1.7, 2.35}, 0.03}};
  const AcousticRun disc = simulate(w, s, stationary(robot), 1, 1);
  EXPECT_FALSE(disc.emissions[0].receivers[0].direct.occluded);
  EXPECT_TRUE(disc.emissions[0].receivers[1].direct.occluded);
}

// Threshold crossing ---------------------------------------------------------

TEST(Acoustics, ThresholdDelayIsTauLnAOverAMinusVAndFallsWithAmplitude) {
  AcousticWorld w;
  w.beacons = {beacon_at({0, 0}, 0)};
  const double tau = w.beacons[0].envelope_tau_s;
  std::vector<double> distances;
  for (int i = 1; i < 32; ++i)
    distances.push_back(0.5 * i);
  for (const double d : distances)
    w.receivers.push_back(receiver_at({d, 0.001 * d}, kPi));
  const double duration = 2.5e-3;
  const AcousticRun run = simulate(w, one_emission(0, 0, duration), stationary({}), 1, 1);
  const double v = w.receivers[0].threshold_v;
  double last_delay = 0;
  double last_width = 1;
  std::size_t heard = 0;
  for (std::size_t ch = 0; ch < distances.size(); ++ch) {
    SCOPED_TRACE(distances[ch]);
    const Arrival& a = run.emissions[0].receivers[ch].direct;
    const double peak = a.amplitude_v * (1 - std::exp(-duration / tau));
    if (peak <= v) {
      EXPECT_FALSE(a.above_threshold);
      EXPECT_TRUE(run.channels[ch].envelope.empty());
      continue;
    }
    ++heard;
    ASSERT_TRUE(a.above_threshold);
    const double delay = a.above_threshold->rise_s - a.true_time_s;
    EXPECT_NEAR(delay, tau * std::log(a.amplitude_v / (a.amplitude_v - v)), 1e-12);
    EXPECT_NEAR(a.above_threshold->fall_s - a.true_time_s, duration + tau * std::log(peak / v),
                1e-12);
    // Weaker pulses cross later and are narrower above threshold.
    const double width = a.above_threshold->fall_s - a.above_threshold->rise_s;
    EXPECT_GT(delay, last_delay);
    EXPECT_LT(width, last_width);
    last_delay = delay;
    last_width = width;
    ASSERT_EQ(run.channels[ch].envelope.size(), 1U);
    EXPECT_EQ(run.channels[ch].envelope[0], *a.above_threshold);
  }
  EXPECT_GT(heard, 10U);
  EXPECT_LT(heard, distances.size());  // the far ones stay below threshold
}

// Carrier --------------------------------------------------------------------

TEST(Acoustics, CarrierRisesEveryPeriodWithThePhaseOfTheArrivalTimeDifference) {
  // The binaural pair, the transmitter 1.5 m ahead and 0.1 m to the side.
  AcousticWorld w = odoloc::world::binaural_world(stationary({0.1, 1.5, kPi}), 0.35);
  const double f = 40e3;
  const AcousticRun run = simulate(w, one_emission(0, 0.01, 1e-3), stationary({}), 1, 1);
  const double c = speed_of_sound(20);
  std::array<double, 2> arrival{};
  for (std::size_t ch = 0; ch < 2; ++ch) {
    SCOPED_TRACE(ch);
    const Arrival& a = run.emissions[0].receivers[ch].direct;
    arrival[ch] = 0.01 + planar_distance({0.1, 1.5}, {ch == 0 ? -0.175 : 0.175, 0}) / c;
    ASSERT_TRUE(a.above_threshold);
    const auto& carrier = run.channels[ch].carrier;
    ASSERT_GT(carrier.size(), 20U);
    // The first rising edge is the first carrier period after the envelope
    // crossing; then one every 1/f, each high for half a period.
    EXPECT_GE(carrier.front().rise_s, a.above_threshold->rise_s);
    EXPECT_LT(carrier.front().rise_s, a.above_threshold->rise_s + 1 / f);
    EXPECT_LT(carrier.back().rise_s, a.above_threshold->fall_s);
    for (std::size_t i = 0; i < carrier.size(); ++i) {
      const double k = std::round((carrier[i].rise_s - arrival[ch]) * f);
      EXPECT_NEAR(carrier[i].rise_s, arrival[ch] + k / f, 1e-12);
      EXPECT_NEAR(carrier[i].fall_s - carrier[i].rise_s, 0.5 / f, 1e-12);
      if (i > 0) {
        EXPECT_NEAR(carrier[i].rise_s - carrier[i - 1].rise_s, 1 / f, 1e-12);
      }
    }
  }
  // On the pins: the phase difference of the rising edges is 2 pi f dt
  // (mod 2 pi) within the clock quantisation.
  AcousticPins pins(run, ComparatorKind::kCarrier);
  const auto r0 = rising_clocks(pins.channel(0));
  const auto r1 = rising_clocks(pins.channel(1));
  const double expected = std::remainder(2 * kPi * f * (arrival[1] - arrival[0]), 2 * kPi);
  EXPECT_GT(std::abs(expected), 0.5);  // a phase worth measuring
  const double clock_phase = 2 * kPi * f * kClockS;
  for (std::size_t i = 0; i < std::min(r0.size(), r1.size()); ++i) {
    const double dt = (static_cast<double>(r1[i]) - static_cast<double>(r0[i])) * kClockS;
    EXPECT_NEAR(std::remainder(2 * kPi * f * dt - expected, 2 * kPi), 0, clock_phase);
  }
}

TEST(Acoustics, CarrierOfAReceivingRobotIsDopplerShifted) {
  // Receding at v along the line of sight: the period is c / ((c - v) f).
  const double v = 1.0;
  AcousticWorld w;
  w.beacons = {beacon_at({0, 0}, 0)};
  w.receivers = {receiver_at({0, 0}, kPi)};
  const Trajectory robot = [v](double t) { return Pose{2 + v * t, 0, 0}; };
  const AcousticRun run = simulate(w, one_emission(0, 0, 2.5e-3), robot, 1, 1);
  const double c = speed_of_sound(20);
  const auto& carrier = run.channels[0].carrier;
  ASSERT_GT(carrier.size(), 50U);
  for (std::size_t i = 1; i < carrier.size(); ++i)
    EXPECT_NEAR(carrier[i].rise_s - carrier[i - 1].rise_s, c / ((c - v) * 40e3), 1e-12);
}

TEST(Acoustics, OverlappingArrivalsFollowTheComparatorRule) {
  // Two beacons at different distances whose pulses overlap on one receiver.
  AcousticWorld w;
  w.beacons = {beacon_at({0, 0}, 0), beacon_at({0, 0.3}, 0)};
  w.receivers = {receiver_at({2, 0}, kPi)};
  Schedule s{{Emission{0, 0, 2.5e-3}, Emission{1, 1.3e-3, 2.5e-3}}, {}};
  const AcousticRun run = simulate(w, s, stationary({}), 1, 1);
  const auto a = *run.emissions[0].receivers[0].direct.above_threshold;
  const auto b = *run.emissions[1].receivers[0].direct.above_threshold;
  ASSERT_LT(a.rise_s, b.rise_s);
  ASSERT_LT(b.rise_s, a.fall_s);
  ASSERT_GT(b.fall_s, a.fall_s);
  // Envelope: the union.
  ASSERT_EQ(run.channels[0].envelope.size(), 1U);
  EXPECT_EQ(run.channels[0].envelope[0], (Pulse{a.rise_s, b.fall_s}));
  // Carrier: A's phase until A falls, then B's.
  const double f = 40e3;
  const double ta = run.emissions[0].receivers[0].direct.true_time_s;
  const double tb = run.emissions[1].receivers[0].direct.true_time_s;
  ASSERT_GT(std::abs(std::remainder((tb - ta) * f, 1.0)), 0.1);  // distinguishable phases
  std::size_t from_a = 0;
  std::size_t from_b = 0;
  for (const Pulse& p : run.channels[0].carrier) {
    const double phase_a = std::remainder((p.rise_s - ta) * f, 1.0);
    const double phase_b = std::remainder((p.rise_s - tb) * f, 1.0);
    if (p.rise_s < a.fall_s) {
      EXPECT_NEAR(phase_a, 0, 1e-6);
      ++from_a;
    } else {
      EXPECT_NEAR(phase_b, 0, 1e-6);
      ++from_b;
    }
  }
  EXPECT_NEAR(static_cast<double>(from_a), (a.fall_s - a.rise_s) * f, 1.5);
  EXPECT_NEAR(static_cast<double>(from_b), (b.fall_s - a.fall_s) * f, 1.5);
}

// Schedules ------------------------------------------------------------------

TEST(Acoustics, KleemanScheduleFiresInSlotsWithADoublePulseFromBeaconZero) {
  KleemanTiming timing;
  timing.cycle_sync_s = 10e-6;
  EXPECT_NEAR(timing.fire_s(), 0.150, 1e-12);
  EXPECT_NEAR(timing.fire_s(), 65536 * timing.timer_tick_s, 1e-15);
  const Schedule s = odoloc::world::kleeman_schedule(timing, 2, 0.25);
  ASSERT_EQ(s.emissions.size(), 14U);
  ASSERT_EQ(s.sync.size(), 2U);
  std::size_t i = 0;
  for (std::size_t cycle = 0; cycle < 2; ++cycle) {
    const double cycle_start = 0.25 + 0.9 * static_cast<double>(cycle);
    EXPECT_NEAR(s.sync[cycle].start_s, cycle_start, 1e-12);
    for (std::size_t b = 0; b < 6; ++b) {
      const Emission& e = s.emissions[i++];
      EXPECT_EQ(e.beacon, b);
      EXPECT_NEAR(e.trigger_s, cycle_start + 0.15 * static_cast<double>(b), 1e-12);
      EXPECT_EQ(e.duration_s, 2.5e-3);
      if (b == 0) {
        const Emission& second = s.emissions[i++];
        EXPECT_EQ(second.beacon, 0U);
        EXPECT_NEAR(second.trigger_s - e.trigger_s, 5.5e-3, 1e-12);  // start to start
        EXPECT_EQ(second.duration_s, 2.5e-3);
      }
    }
  }

  // Heard on the octagon: two equal pulses 5.5 ms apart from beacon 0, one
  // from each other beacon, in its slot.
  const AcousticWorld w = odoloc::world::kleeman_world();
  const Pose robot{4.0, 6.0, 0.3};
  const AcousticRun run = simulate(w, s, stationary(robot), 2.0, 1);
  ASSERT_EQ(run.emissions.size(), 14U);
  const auto& first = run.emissions[0].receivers;
  const auto loudest = static_cast<std::size_t>(std::max_element(first.begin(), first.end(),
                                                                 [](const auto& a, const auto& b) {
                                                                   return a.direct.amplitude_v <
                                                                          b.direct.amplitude_v;
                                                                 }) -
                                                first.begin());
  const auto& wave = run.channels[loudest].envelope;
  const auto pulse_after = [&](double t) {
    return *std::find_if(wave.begin(), wave.end(), [t](const Pulse& p) { return p.rise_s >= t; });
  };
  const Pulse p1 = pulse_after(0.25);
  const Pulse p2 = pulse_after(p1.fall_s);
  EXPECT_NEAR(p2.rise_s - p1.rise_s, 5.5e-3, 1e-9);
  EXPECT_NEAR(p2.fall_s - p1.fall_s, 5.5e-3, 1e-9);
  // Each beacon's direct arrival falls in its slot, after its trigger.
  for (const EmissionRecord& e : run.emissions) {
    double earliest = 1e9;
    for (const auto& r : e.receivers)
      earliest = std::min(earliest, r.direct.true_time_s);
    const double slot = e.emission.trigger_s;
    EXPECT_GT(earliest, slot);
    EXPECT_LT(earliest, slot + 0.05);  // within 17 m
  }
}

TEST(Acoustics, ThammaSyncPrecedesTheUltrasoundByTheFlightTimePlusTheDelay) {
  const AcousticWorld w = odoloc::world::thamma_world();
  const Pose robot{5.0, 2.0, kPi / 2};
  const TriggeredTiming timing;
  const Schedule s = odoloc::world::triggered_schedule(timing, w.beacons.size(), 1, 0.01);
  ASSERT_EQ(s.emissions.size(), 16U);
  ASSERT_EQ(s.sync.size(), 16U);
  const AcousticRun run = simulate(w, s, stationary(robot), 2.0, 1);
  ASSERT_EQ(run.sync.size(), 16U);
  const double c = speed_of_sound(20);
  const double delay = w.beacons[0].electronics_delay_s;
  EXPECT_GT(delay, 0);
  AcousticPins pins(run, ComparatorKind::kEnvelope);
  const auto sync_rises = rising_clocks(pins.sync());
  ASSERT_EQ(sync_rises.size(), 16U);
  for (std::size_t i = 0; i < 16; ++i) {
    const EmissionRecord& e = run.emissions[i];
    EXPECT_EQ(e.emission.beacon, i / 4);  // each station four times in turn
    EXPECT_NEAR(e.emission.trigger_s, 0.01 + 0.1 * static_cast<double>(i), 1e-12);
    const Vec2 station = w.beacons[e.emission.beacon].position;
    const double rf = planar_distance(station, {robot.x_m, robot.y_m}) / 299'792'458.0;
    EXPECT_NEAR(run.sync[i].rise_s, e.emission.trigger_s + rf, 1e-15);
    for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
      const Vec2 p = body_point(robot, w.receivers[ch].position);
      const double flight = planar_distance(station, p) / c;
      const Arrival& a = e.receivers[ch].direct;
      EXPECT_NEAR(a.true_time_s - run.sync[i].rise_s, flight + delay - rf, 1e-12);
    }
  }
  // On the pins: a head receiver's first rise after each sync comes at
  // least the flight and the delay later, at the first of its arrivals to
  // cross the threshold (near its wall a station's echo follows the direct
  // path within 0.1 ms and may be stronger: the union takes the earlier
  // crossing).
  for (std::size_t i = 0; i < 8; ++i) {  // the 40 kHz stations
    const auto& head = run.emissions[i].receivers;
    const std::size_t ch = static_cast<std::size_t>(
        std::max_element(head.begin(), head.begin() + 4,
                         [](const auto& a, const auto& b) {
                           return a.direct.amplitude_v < b.direct.amplitude_v;
                         }) -
        head.begin());
    const Arrival& direct = head[ch].direct;
    ASSERT_TRUE(direct.above_threshold);
    const double a = direct.amplitude_v;
    const double v = w.receivers[ch].threshold_v;
    const double tau = w.beacons[0].envelope_tau_s;
    EXPECT_NEAR(direct.above_threshold->rise_s - run.sync[i].rise_s,
                direct.true_time_s - run.sync[i].rise_s + tau * std::log(a / (a - v)), 1e-12);
    double first = direct.above_threshold->rise_s;
    for (const Arrival& echo : head[ch].echoes)
      if (echo.above_threshold)
        first = std::min(first, echo.above_threshold->rise_s);
    const auto rises = rising_clocks(pins.channel(ch));
    const auto rise = *std::lower_bound(rises.begin(), rises.end(), sync_rises[i]);
    EXPECT_EQ(rise, static_cast<std::uint64_t>(std::ceil(first * kClockHz)));
    EXPECT_GE(static_cast<double>(rise - sync_rises[i]) * kClockS,
              direct.true_time_s - run.sync[i].rise_s - kClockS);
  }
}

// Pins -----------------------------------------------------------------------

TEST(Acoustics, PinSourceSamplesEachClockAtItsStart) {
  // Pulses in clocks: [1.5, 3.9) and the touching [3.9, 6.2) make one pulse
  // on clocks 2..6; [10.1, 10.9) holds no clock start; [11.99999, 12.0001)
  // holds one.
  const std::vector<Pulse> wave = {{1.5 * kClockS, 3.9 * kClockS},
                                   {3.9 * kClockS, 6.2 * kClockS},
                                   {10.1 * kClockS, 10.9 * kClockS},
                                   {11.99999 * kClockS, 12.0001 * kClockS},
                                   {20.5 * kClockS, 24.5 * kClockS}};
  PinSource pin(wave, kClockHz);
  EXPECT_EQ(pin.transitions(), (std::vector<std::uint64_t>{2, 7, 12, 13, 21, 25}));
  bool previous = false;
  for (std::uint64_t n = 0; n < 40; ++n) {
    const bool expected = level_at(wave, n);
    // next_transition_clock(): the first clock >= n that differs from n - 1.
    std::uint64_t next = PinSource::kNever;
    bool last = previous;
    for (std::uint64_t m = n; m < 40; ++m) {
      if (level_at(wave, m) != last) {
        next = m;
        break;
      }
      last = level_at(wave, m);
    }
    EXPECT_EQ(pin.next_transition_clock(), next) << n;
    EXPECT_EQ(pin.level(), previous);
    EXPECT_EQ(pin.clock(), n);
    EXPECT_EQ(pin.tick(), expected) << n;
    previous = expected;
  }
  pin.skip_to(12);
  EXPECT_FALSE(pin.level());
  EXPECT_EQ(pin.next_transition_clock(), 12U);
  EXPECT_TRUE(pin.tick());
  pin.skip_to(3);  // rewind
  EXPECT_TRUE(pin.level());
  EXPECT_EQ(pin.next_transition_clock(), 7U);
}

TEST(Acoustics, PinsReproduceTheWaveformsClockByClockAndPredictTheirTransitions) {
  AcousticWorld w = odoloc::world::kleeman_world();
  w.noise.noise_rate_hz = 20;
  const KleemanTiming timing;
  const Schedule s = odoloc::world::kleeman_schedule(timing, 1, 0.001);
  const Pose robot{3.0, 7.0, -0.4};
  const AcousticRun run = simulate(w, s, stationary(robot), 0.3, 5);
  for (const ComparatorKind kind : {ComparatorKind::kEnvelope, ComparatorKind::kCarrier}) {
    SCOPED_TRACE(static_cast<int>(kind));
    AcousticPins pins(run, kind);
    // Every transition clock of every pin against the waveform's levels.
    std::size_t transitions = 0;
    for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
      const auto& wave = run.channels[ch](kind);
      std::uint64_t previous = 0;
      for (const std::uint64_t n : pins.channel(ch).transitions()) {
        ASSERT_GT(n, previous);
        EXPECT_NE(level_at(wave, n), level_at(wave, n - 1)) << n;
        previous = n;
        ++transitions;
      }
      EXPECT_EQ(pins.channel(ch).transitions().size(), 2 * wave.size());
    }
    EXPECT_GT(transitions, 20U);
    // Clock by clock over 0.3 s: a level changes exactly at
    // next_transition_clock(); a fast-forward visits the same changes.
    PinLevels previous;
    std::vector<std::uint64_t> changes;
    const std::uint64_t clocks = 15'000'000;
    for (std::uint64_t n = 0; n < clocks; ++n) {
      const std::uint64_t predicted = pins.next_transition_clock();
      const PinLevels levels = pins.tick();
      if (levels != previous) {
        ASSERT_EQ(predicted, n);
        changes.push_back(n);
      } else {
        ASSERT_GT(predicted, n);
      }
      previous = levels;
    }
    AcousticPins jumping(run, kind);
    std::vector<std::uint64_t> jumps;
    for (std::uint64_t n = jumping.next_transition_clock(); n < clocks;
         n = jumping.next_transition_clock()) {
      jumping.skip_to(n);
      jumping.tick();
      jumps.push_back(n);
    }
    EXPECT_EQ(jumps, changes);
  }
}

// Reproducibility and statistics --------------------------------------------

TEST(Acoustics, SeededRunsReproduceBitForBit) {
  AcousticWorld w = odoloc::world::kleeman_world();
  w.noise = {2e-6, 0.3e-6, 0.05, 5, 0.1e-3, 2e-3};
  const Schedule s = odoloc::world::kleeman_schedule({}, 1);
  const Trajectory robot = [](double t) { return Pose{2 + t, 3 + 0.5 * t, 0.2 * t}; };
  const AcousticRun a = simulate(w, s, robot, 1.0, 42);
  const AcousticRun b = simulate(w, s, robot, 1.0, 42);
  const AcousticRun c = simulate(w, s, robot, 1.0, 43);
  std::size_t noise = 0;
  for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
    EXPECT_EQ(a.channels[ch].envelope, b.channels[ch].envelope);
    EXPECT_EQ(a.channels[ch].carrier, b.channels[ch].carrier);
    EXPECT_NE(a.channels[ch].envelope, c.channels[ch].envelope);
    ASSERT_EQ(a.noise[ch].size(), b.noise[ch].size());
    for (std::size_t i = 0; i < a.noise[ch].size(); ++i) {
      EXPECT_EQ(a.noise[ch][i].pulse, b.noise[ch][i].pulse);
      EXPECT_EQ(a.noise[ch][i].phase_rad, b.noise[ch][i].phase_rad);
    }
    noise += a.noise[ch].size();
  }
  EXPECT_GT(noise, 0U);
  ASSERT_EQ(a.emissions.size(), b.emissions.size());
  for (std::size_t i = 0; i < a.emissions.size(); ++i)
    for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
      const Arrival& x = a.emissions[i].receivers[ch].direct;
      const Arrival& y = b.emissions[i].receivers[ch].direct;
      EXPECT_EQ(x.time_s, y.time_s);
      EXPECT_EQ(x.amplitude_v, y.amplitude_v);
      EXPECT_EQ(x.above_threshold, y.above_threshold);
      EXPECT_EQ(a.emissions[i].receivers[ch].noise_pulses,
                b.emissions[i].receivers[ch].noise_pulses);
    }
}

TEST(Acoustics, JitterAndAmplitudeFluctuationHaveTheirParameters) {
  const double path_sd = 2e-6;
  const double receiver_sd = 1e-6;
  const double amplitude_sd = 0.1;
  AcousticWorld w;
  w.beacons = {beacon_at({0, 0}, 0)};
  w.receivers = {receiver_at({2, 0.05}, kPi), receiver_at({2, -0.05}, kPi)};
  w.noise.path_jitter_sd_s = path_sd;
  w.noise.receiver_jitter_sd_s = receiver_sd;
  TriggeredTiming timing;
  timing.repeats = 800;
  timing.period_s = 20e-3;
  const Schedule s = odoloc::world::triggered_schedule(timing, 1, 1);
  const double n = 800;
  const double c = speed_of_sound(20);
  const double flight = std::hypot(2.0, 0.05) / c;

  // Arrival jitter, measured on the envelope waveform: rise - trigger minus
  // its mean (the constant flight and threshold delay).
  const AcousticRun run = simulate(w, s, stationary({}), 17, 9);
  std::array<std::vector<double>, 2> rise;
  std::vector<double> true_error;
  for (std::size_t ch = 0; ch < 2; ++ch) {
    ASSERT_EQ(run.channels[ch].envelope.size(), 800U);
    for (std::size_t i = 0; i < 800; ++i)
      rise[ch].push_back(run.channels[ch].envelope[i].rise_s - s.emissions[i].trigger_s);
  }
  for (std::size_t i = 0; i < 800; ++i)
    true_error.push_back(run.emissions[i].receivers[0].direct.true_time_s -
                         s.emissions[i].trigger_s - flight);
  EXPECT_LT(std::abs(stats(true_error).mean), 1e-12);  // no bias in the truth
  EXPECT_LT(stats(true_error).sd, 1e-12);
  const double total_sd = std::hypot(path_sd, receiver_sd);
  for (std::size_t ch = 0; ch < 2; ++ch) {
    const Stats st = stats(rise[ch]);
    const double a = run.emissions[0].receivers[ch].direct.amplitude_v;
    const double v = w.receivers[ch].threshold_v;
    const double nominal = flight + w.beacons[0].envelope_tau_s * std::log(a / (a - v));
    EXPECT_NEAR(st.mean, nominal, 4 * total_sd / std::sqrt(n));
    EXPECT_NEAR(st.sd, total_sd, 4 * total_sd / std::sqrt(2 * n));
  }
  // The path jitter is common to the array: the difference keeps only the
  // receivers' own.
  std::vector<double> difference;
  for (std::size_t i = 0; i < 800; ++i)
    difference.push_back(rise[1][i] - rise[0][i]);
  const double difference_sd = std::sqrt(2.0) * receiver_sd;
  EXPECT_NEAR(stats(difference).mean, 0, 4 * difference_sd / std::sqrt(n));
  EXPECT_NEAR(stats(difference).sd, difference_sd, 4 * difference_sd / std::sqrt(2 * n));

  // Amplitude: recovered from each pulse's width above threshold, which
  // carries it: width = T + tau ln(A (1 - e^(-T/tau)) / V) - tau ln(A / (A - V)).
  w.noise = {};
  const AcousticRun ideal = simulate(w, s, stationary({}), 17, 11);
  w.noise.amplitude_sd = amplitude_sd;
  const AcousticRun amp = simulate(w, s, stationary({}), 17, 11);
  const double tau = w.beacons[0].envelope_tau_s;
  const double duration = timing.pulse_s;
  const double v = w.receivers[0].threshold_v;
  // The inverse: A = V (1 + e^((width - T)/tau) / (1 - e^(-T/tau))).
  const auto amplitude_of = [&](const Pulse& p) {
    return v *
           (1 + std::exp((p.fall_s - p.rise_s - duration) / tau) / (1 - std::exp(-duration / tau)));
  };
  const double a0 = amplitude_of(ideal.channels[0].envelope[0]);
  EXPECT_NEAR(a0, ideal.emissions[0].receivers[0].direct.amplitude_v, 1e-9);
  std::vector<double> relative;
  for (const Pulse& p : amp.channels[0].envelope)
    relative.push_back(amplitude_of(p) / a0 - 1);
  ASSERT_EQ(relative.size(), 800U);
  EXPECT_NEAR(stats(relative).mean, 0, 4 * amplitude_sd / std::sqrt(n));
  EXPECT_NEAR(stats(relative).sd, amplitude_sd, 4 * amplitude_sd / std::sqrt(2 * n));
}

TEST(Acoustics, NoisePulsesArePoissonWithUniformWidths) {
  const double rate = 20;
  const double span = 50;
  const double min_width = 0.1e-3;
  const double max_width = 0.5e-3;
  AcousticWorld w;
  w.receivers = {receiver_at({0, 0}, 0), receiver_at({0, 0.1}, 0)};
  w.noise.noise_rate_hz = rate;
  w.noise.noise_min_width_s = min_width;
  w.noise.noise_max_width_s = max_width;
  const AcousticRun run = simulate(w, {}, stationary({}), span, 5);
  const double expected = rate * span;
  for (std::size_t ch = 0; ch < 2; ++ch) {
    SCOPED_TRACE(ch);
    const auto& wave = run.channels[ch].envelope;
    // Overlapping pulses merge (rate x width ~ 0.6 %): count them from the
    // waveform and compare with the Poisson mean and sd.
    EXPECT_NEAR(static_cast<double>(wave.size()), expected, 4 * std::sqrt(expected));
    std::vector<double> widths;
    std::vector<double> gaps;
    for (std::size_t i = 0; i < wave.size(); ++i) {
      if (wave[i].fall_s - wave[i].rise_s <= max_width + 1e-12)
        widths.push_back(wave[i].fall_s - wave[i].rise_s);
      if (i > 0)
        gaps.push_back(wave[i].rise_s - wave[i - 1].rise_s);
    }
    const Stats width = stats(widths);
    const double width_sd = (max_width - min_width) / std::sqrt(12.0);
    EXPECT_NEAR(width.mean, (min_width + max_width) / 2, 4 * width_sd / std::sqrt(expected));
    EXPECT_NEAR(width.sd, width_sd, 0.1 * width_sd);
    EXPECT_GE(*std::min_element(widths.begin(), widths.end()), min_width);
    // Exponential gaps: mean = sd = 1 / rate.
    const Stats gap = stats(gaps);
    EXPECT_NEAR(gap.mean, 1 / rate, 4 / rate / std::sqrt(expected));
    EXPECT_NEAR(gap.sd, 1 / rate, 0.2 / rate);
    // The carrier rings at the receiver's resonance inside each noise pulse.
    const auto& carrier = run.channels[ch].carrier;
    ASSERT_GT(carrier.size(), wave.size());
    EXPECT_NEAR(carrier[1].rise_s - carrier[0].rise_s, 1 / 40e3, 1e-12);
  }
}

TEST(Acoustics, ReceptionsCountTheNoisePulsesOfTheirSlot) {
  AcousticWorld w = odoloc::world::kleeman_world();
  w.noise.noise_rate_hz = 30;
  const Schedule s = odoloc::world::kleeman_schedule({}, 2, 0.1);
  const AcousticRun run = simulate(w, s, stationary({5, 5, 0}), 2.0, 3);
  for (std::size_t ch = 0; ch < w.receivers.size(); ++ch) {
    std::size_t counted = 0;
    for (const EmissionRecord& e : run.emissions)
      counted += e.receivers[ch].noise_pulses;
    const auto& noise = run.noise[ch];
    const auto after_first = std::count_if(noise.begin(), noise.end(), [&](const auto& p) {
      return p.pulse.rise_s >= run.emissions.front().emission_s;
    });
    EXPECT_EQ(counted, static_cast<std::size_t>(after_first));
  }
}

// Interfaces -----------------------------------------------------------------

TEST(Acoustics, InterpolatedTricycleTrajectoryFollowsTheTruth) {
  odoloc::world::Options options;
  options.start = {1.0, 2.0, 0.5};
  options.record_every_steps = 100;  // 1 ms
  odoloc::world::TricycleSimulator sim(odoloc::world::Geometry{},
                                       odoloc::world::straight_path(0.05, 1.0), {}, options);
  while (!sim.done())
    sim.tick();
  const Trajectory robot = odoloc::world::interpolate(sim.trajectory());
  for (const double t : {0.0, 0.0123, 0.0371, 0.049}) {
    const Pose p = robot(t);
    EXPECT_NEAR(p.x_m, 1.0 + t * std::cos(0.5), 1e-9);
    EXPECT_NEAR(p.y_m, 2.0 + t * std::sin(0.5), 1e-9);
    EXPECT_NEAR(p.theta_rad, 0.5, 1e-12);
  }
  EXPECT_NEAR(robot(10).x_m, 1.0 + 0.05 * std::cos(0.5), 1e-9);  // holds after the end
  EXPECT_THROW(odoloc::world::interpolate({}), std::invalid_argument);
}

TEST(Acoustics, RejectsInconsistentWorldsAndSchedules) {
  AcousticWorld w = odoloc::world::kleeman_world();
  const Trajectory robot = stationary({5, 5, 0});
  EXPECT_THROW(simulate(w, one_emission(6, 0, 1e-3), robot, 1, 1), std::invalid_argument);
  EXPECT_THROW(simulate(w, one_emission(0, 0, 0), robot, 1, 1), std::invalid_argument);
  EXPECT_THROW(simulate(w, one_emission(0, 0, 1e-3), {}, 1, 1), std::invalid_argument);
  AcousticWorld bad = w;
  bad.receivers[0].threshold_v = 0;
  EXPECT_THROW(simulate(bad, {}, robot, 1, 1), std::invalid_argument);
  bad = w;
  bad.beacons[0].axes_rad.clear();
  EXPECT_THROW(simulate(bad, {}, robot, 1, 1), std::invalid_argument);
  bad = w;
  bad.room->reflection[2] = 1.5;
  EXPECT_THROW(simulate(bad, {}, robot, 1, 1), std::invalid_argument);
  KleemanTiming timing;
  timing.double_pulse_s = 0.2;
  EXPECT_THROW(odoloc::world::kleeman_schedule(timing, 1), std::invalid_argument);
  AcousticRun run = simulate(w, {}, robot, 1, 1);
  EXPECT_THROW((AcousticPins{run, std::vector<ComparatorKind>(3)}), std::invalid_argument);
}

}  // namespace
