// The whole ultrasonic capture chain at the pin level: Kleeman's beacons fire
// in the acoustic world (echoes, directivity, absorption, envelope rise),
// the comparator waveforms drive the chip's pins clock by clock, the capture
// unit timestamps them, the SoC driver drains the FIFOs over the pin-level
// SPI master, and the beacon-cycle decoder turns the batches into
// measurement sets. Each beacon's distance (with the common offset removed:
// relative to beacon 0, as the decoder defines it) is compared with the
// geometric ground truth, and the direction of arrival with the true bearing.
//
// Prints the figures docs/tof-capture.md quotes (per beacon: mean and
// standard deviation of the distance error over the seeded poses; the DOA
// error). ODOLOC_TEST_SCALE < 1 runs fewer poses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/sw/beacon_cycle.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc/sw/tof_capture_driver.hpp"
#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"
#include "test_scale.hpp"

namespace {

namespace world = odoloc::world;
namespace tof = odoloc::sw::tof;
using odoloc::board::ChipLink;
using odoloc::sw::SpiRegisterBus;

constexpr double kClockHz = 50e6;
constexpr double kReadPeriodS = 0.02;  // the driver drains the FIFOs every 20 ms

struct ChainResult {
  std::vector<tof::CycleMeasurement> cycles;
  std::vector<double> true_distance_m;  // per beacon, robot origin to beacon (3-D)
};

// Runs `cycles` beacon cycles with the robot standing at `pose`.
ChainResult run_chain(const world::Pose& pose, std::size_t cycles, std::uint64_t seed) {
  world::AcousticWorld w = world::kleeman_world();
  const world::KleemanTiming timing;
  const double start_s = 0.013;  // the first burst, not at the chip's reset
  const world::Schedule schedule = world::kleeman_schedule(timing, cycles, start_s);
  const double end_s = start_s + static_cast<double>(cycles) * timing.cycle_s() + 0.1;
  const world::AcousticRun run = world::simulate(w, schedule, world::stationary(pose), end_s, seed);
  world::AcousticPins pins(run, world::ComparatorKind::kEnvelope, kClockHz);

  ChipLink link({.half_period = 4}, [&](odoloc::rtl::ChipPins& p) {
    const world::PinLevels levels = pins.tick();
    p.comparators = decltype(p.comparators)::truncate(levels.channels);
  });
  SpiRegisterBus bus(link, {.crc = true, .confirm_writes = true});
  tof::CaptureSetup setup;
  for (auto& c : setup.channels)
    c.enabled = true;
  tof::CaptureDriver driver(bus, setup);
  driver.arm(0xFF);

  tof::KleemanConfig config;
  config.schedule.fire_period_s = timing.fire_s();
  config.schedule.pulse_s = timing.pulse_s;
  config.schedule.double_spacing_s = timing.double_pulse_s;
  config.envelope.rise_s = w.beacons[0].envelope_tau_s;  // the receiver model, calibrated
  config.envelope.fall_s = w.beacons[0].envelope_tau_s;
  config.envelope.burst_s = timing.pulse_s;
  config.timebase = driver.timebase();
  config.speed_of_sound_mps = w.air.speed_of_sound_mps();
  for (const world::Beacon& b : w.beacons)
    config.beacon_positions.push_back({b.position.x_m, b.position.y_m});
  tof::BeaconCycleDecoder decoder(config);

  ChainResult result;
  const auto read_clocks = static_cast<std::uint64_t>(kReadPeriodS * kClockHz);
  const auto end_clock = static_cast<std::uint64_t>(end_s * kClockHz);
  while (link.clocks() < end_clock) {
    link.advance(read_clocks);
    for (tof::CycleMeasurement& m : decoder.push(driver.read()))
      result.cycles.push_back(std::move(m));
  }
  for (const world::Beacon& b : w.beacons) {
    const double dx = b.position.x_m - pose.x_m, dy = b.position.y_m - pose.y_m;
    result.true_distance_m.push_back(std::sqrt(dx * dx + dy * dy + w.height_m * w.height_m));
  }
  return result;
}

double wrap_angle(double a) {
  return std::remainder(a, 2 * std::numbers::pi);
}

// One pose, three cycles: the decoder locks, and every beacon's direct
// distance relative to beacon 0 is the geometric one within 3 mm, its
// direction of arrival the true bearing within 2 degrees.
TEST(TofChain, KleemanCycleAtThePinLevelMatchesTheGroundTruth) {
  const world::Pose pose{.x_m = 3.7, .y_m = 4.6, .theta_rad = 0.4};
  const ChainResult r = run_chain(pose, 3, 1);
  const auto locked = std::ranges::count_if(r.cycles, [](const auto& c) { return c.locked(); });
  ASSERT_GE(locked, 1) << "no locked cycle";
  const world::AcousticWorld w = world::kleeman_world();
  for (const tof::CycleMeasurement& c : r.cycles) {
    if (!c.locked())
      continue;
    for (const tof::BeaconMeasurement& b : c.beacons) {
      const tof::Arrival* a = b.direct();
      ASSERT_NE(a, nullptr) << "beacon " << b.beacon << " " << tof::to_string(b.flags);
      const double truth =
          r.true_distance_m[static_cast<std::size_t>(b.beacon)] - r.true_distance_m[0];
      EXPECT_NEAR(a->distance_m, truth, 3e-3)
          << "beacon " << b.beacon << " cycle " << c.sequence << " " << tof::to_string(a->flags);
      if (a->doa.valid) {
        const auto& p = w.beacons[static_cast<std::size_t>(b.beacon)].position;
        const double bearing = std::atan2(p.y_m - pose.y_m, p.x_m - pose.x_m) - pose.theta_rad;
        EXPECT_LT(std::abs(wrap_angle(a->doa.bearing_rad - bearing)), 2.0 * std::numbers::pi / 180)
            << "beacon " << b.beacon;
      }
    }
  }
}

// Seeded Monte Carlo over robot poses in the 10 m room (clean data):
// distance error per beacon (mean, sd) and DOA error, printed for the docs.
TEST(TofChain, MonteCarloDistanceAndDirectionErrors) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> xy(1.5, 8.5), heading(-std::numbers::pi, std::numbers::pi);
  const int poses = std::max(2, static_cast<int>(odoloc::tb::scaled(6000) / 1000));
  const world::AcousticWorld w = world::kleeman_world();
  const std::size_t n = w.beacons.size();
  std::vector<std::vector<double>> errors(n);
  std::vector<double> doa_errors;
  for (int k = 0; k < poses; ++k) {
    const world::Pose pose{.x_m = xy(rng), .y_m = xy(rng), .theta_rad = heading(rng)};
    const ChainResult r = run_chain(pose, 2, 100 + static_cast<std::uint64_t>(k));
    for (const tof::CycleMeasurement& c : r.cycles) {
      if (!c.locked())
        continue;
      for (const tof::BeaconMeasurement& b : c.beacons) {
        const tof::Arrival* a = b.direct();
        if (a == nullptr || a->flags.has(tof::Flag::kInvalid))
          continue;
        const auto i = static_cast<std::size_t>(b.beacon);
        errors[i].push_back(a->distance_m - (r.true_distance_m[i] - r.true_distance_m[0]));
        if (a->doa.valid) {
          const auto& p = w.beacons[i].position;
          doa_errors.push_back(
              wrap_angle(a->doa.bearing_rad -
                         (std::atan2(p.y_m - pose.y_m, p.x_m - pose.x_m) - pose.theta_rad)));
        }
      }
    }
  }
  const auto stats = [](const std::vector<double>& v) {
    double mean = 0, sq = 0;
    for (double e : v)
      mean += e;
    mean /= static_cast<double>(v.size());
    for (double e : v)
      sq += (e - mean) * (e - mean);
    return std::pair{mean, std::sqrt(sq / std::max<double>(1, static_cast<double>(v.size()) - 1))};
  };
  std::printf("capture chain, %d poses, clean data: distance error relative to beacon 0\n", poses);
  for (std::size_t i = 1; i < n; ++i) {
    ASSERT_GE(errors[i].size(), static_cast<std::size_t>(poses) / 2) << "beacon " << i;
    const auto [mean, sd] = stats(errors[i]);
    std::printf("  beacon %zu: n %zu, mean %+.2f mm, sd %.2f mm\n", i, errors[i].size(), mean * 1e3,
                sd * 1e3);
    EXPECT_LT(std::abs(mean), 2e-3) << "beacon " << i;
    EXPECT_LT(sd, 3e-3) << "beacon " << i;
  }
  ASSERT_FALSE(doa_errors.empty());
  double rms = 0, worst = 0;
  for (double e : doa_errors) {
    rms += e * e;
    worst = std::max(worst, std::abs(e));
  }
  rms = std::sqrt(rms / static_cast<double>(doa_errors.size()));
  std::printf("  direction of arrival: n %zu, rms %.3f deg, worst %.3f deg\n", doa_errors.size(),
              rms * 180 / std::numbers::pi, worst * 180 / std::numbers::pi);
  EXPECT_LT(rms, 1.0 * std::numbers::pi / 180);
}

}  // namespace
