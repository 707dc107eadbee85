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

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "odoloc/board/beacon_ranges.hpp"
#include "odoloc/board/chip_link.hpp"
#include "odoloc/sw/beacon_cycle.hpp"
#include "odoloc/sw/beacon_fix.hpp"
#include "odoloc/sw/beacon_heading.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc/sw/tof_capture_driver.hpp"
#include "odoloc/sw/tof_sync_modes.hpp"
#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"
#include "test_scale.hpp"

namespace {

namespace world = odoloc::world;
namespace tof = odoloc::sw::tof;
namespace loc = odoloc::sw::locate;
using odoloc::board::ChipLink;
using odoloc::sw::SpiRegisterBus;

constexpr double kClockHz = 50e6;
constexpr double kReadPeriodS = 0.02;  // the driver drains the FIFOs every 20 ms

// The acoustic world's comparators on the chip's pins, the driver reading
// the capture unit every 20 ms over the pin-level SPI master (CRC on): every
// batch of the run, in order.
struct PinChain {
  std::vector<tof::CaptureBatch> batches;
  tof::Timebase timebase;

  PinChain(const world::AcousticRun& run, const std::vector<world::ComparatorKind>& kinds,
           const tof::CaptureSetup& setup, double end_s) {
    world::AcousticPins pins(run, kinds, kClockHz);
    ChipLink link({.half_period = 4}, [&](odoloc::rtl::ChipPins& p) {
      const world::PinLevels levels = pins.tick();
      p.comparators = decltype(p.comparators)::truncate(levels.channels);
      p.tof_sync = decltype(p.tof_sync)::truncate(levels.sync ? 1 : 0);
    });
    SpiRegisterBus bus(link, {.crc = true, .confirm_writes = true});
    tof::CaptureDriver driver(bus, setup);
    std::uint32_t armed = 0;
    for (unsigned c = 0; c < tof::kCaptureChannels; ++c)
      armed |= setup.channels[c].enabled ? 1U << c : 0U;
    driver.arm(armed);
    timebase = driver.timebase();
    const auto read_clocks = static_cast<std::uint64_t>(kReadPeriodS * kClockHz);
    const auto end_clock = static_cast<std::uint64_t>(end_s * kClockHz);
    while (link.clocks() < end_clock) {
      link.advance(read_clocks);
      batches.push_back(driver.read());
    }
  }
  // Every batch's events and sync edges in one, incidents included.
  [[nodiscard]] tof::CaptureBatch merged() const {
    tof::CaptureBatch all = batches.front();
    for (std::size_t i = 1; i < batches.size(); ++i) {
      const tof::CaptureBatch& b = batches[i];
      for (std::size_t c = 0; c < b.channels.size(); ++c) {
        auto& to = all.channels[c];
        to.envelope.insert(to.envelope.end(), b.channels[c].envelope.begin(),
                           b.channels[c].envelope.end());
        to.carrier.insert(to.carrier.end(), b.channels[c].carrier.begin(),
                          b.channels[c].carrier.end());
      }
      all.sync.insert(all.sync.end(), b.sync.begin(), b.sync.end());
      all.incidents.insert(all.incidents.end(), b.incidents.begin(), b.incidents.end());
    }
    return all;
  }
};

struct ChainResult {
  std::vector<tof::CycleMeasurement> cycles;
  std::vector<double> true_distance_m;  // per beacon, robot origin to beacon (3-D)
};

// Runs `cycles` of Kleeman's beacon cycles with the robot standing at `pose`.
ChainResult run_chain(const world::Pose& pose, std::size_t cycles, std::uint64_t seed) {
  const world::AcousticWorld w = world::kleeman_world();
  const world::KleemanTiming timing;
  const double start_s = 0.013;  // the first burst, not at the chip's reset
  const world::Schedule schedule = world::kleeman_schedule(timing, cycles, start_s);
  const double end_s = start_s + static_cast<double>(cycles) * timing.cycle_s() + 0.1;
  const world::AcousticRun run = world::simulate(w, schedule, world::stationary(pose), end_s, seed);
  tof::CaptureSetup setup;
  for (auto& c : setup.channels)
    c.enabled = true;
  const PinChain chain(run, {w.receivers.size(), world::ComparatorKind::kEnvelope}, setup, end_s);

  tof::KleemanConfig config = odoloc::board::kleeman_config(w, timing);
  config.timebase = chain.timebase;
  tof::BeaconCycleDecoder decoder(config);

  ChainResult result;
  for (const tof::CaptureBatch& batch : chain.batches)
    for (tof::CycleMeasurement& m : decoder.push(batch))
      result.cycles.push_back(std::move(m));
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
  // The whole chain, pins to fix: the all-beacon estimator on every locked cycle.
  const loc::BeaconLayout layout = odoloc::board::beacon_layout(w);
  double fix_e2 = 0, fix_nees = 0, heading_z2 = 0, heading_e2 = 0;
  int fixes = 0, cycles = 0, headings = 0;
  for (int k = 0; k < poses; ++k) {
    const world::Pose pose{.x_m = xy(rng), .y_m = xy(rng), .theta_rad = heading(rng)};
    const ChainResult r = run_chain(pose, 2, 100 + static_cast<std::uint64_t>(k));
    for (const tof::CycleMeasurement& c : r.cycles) {
      if (!c.locked())
        continue;
      ++cycles;
      const loc::Fix fix = loc::multilaterate(layout, loc::range_set(c));
      if (fix.valid) {
        const Eigen::Vector2d e(fix.position_m.x - pose.x_m, fix.position_m.y - pose.y_m);
        fix_e2 += e.squaredNorm();
        fix_nees += e.dot(fix.covariance_m2.inverse() * e);
        ++fixes;
        const loc::Heading h = loc::beacon_heading(fix, layout, loc::used_directions(c, fix));
        if (h.valid) {
          const double eh = wrap_angle(h.heading_rad - pose.theta_rad);
          heading_e2 += eh * eh;
          heading_z2 += eh * eh / (h.sd_rad * h.sd_rad);
          ++headings;
        }
      }
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
  // The fixes: every locked cycle gives one, within 3 mm, and no worse than
  // the reported covariance says (mean NEES below 4). This world has no
  // turbulence, so the decoder's 1 us timing model makes the covariance
  // conservative here (NEES about 0.1; test_beacon_solvers checks NEES = 2
  // where the noise model is the true one).
  ASSERT_GT(fixes, 0);
  std::printf(
      "  fixes (multilaterate): %d of %d locked cycles, RMS error %.2f mm, mean NEES %.2f\n", fixes,
      cycles, 1e3 * std::sqrt(fix_e2 / fixes), fix_nees / fixes);
  EXPECT_EQ(fixes, cycles);
  EXPECT_LT(std::sqrt(fix_e2 / fixes), 3e-3);
  EXPECT_LT(fix_nees / fixes, 4.0);
  // Heading from the directions of arrival and the fix: every fix gives one,
  // within its reported sd (z^2 averages 1; below 4 over a few cycles).
  std::printf("  heading (beacon_heading): %d of %d fixes, RMS error %.3f deg, mean z^2 %.2f\n",
              headings, fixes,
              std::sqrt(heading_e2 / std::max(headings, 1)) * 180 / std::numbers::pi,
              heading_z2 / std::max(headings, 1));
  EXPECT_EQ(headings, fixes);
  EXPECT_LT(std::sqrt(heading_e2 / headings), 0.5 * std::numbers::pi / 180);
  EXPECT_LT(heading_z2 / headings, 4.0);
}

// Thamma's RF-synchronised ranging at the pin level: four base stations,
// four repeats each, the sync pin stamped beside the head and tail boxes'
// envelope pulses. The time of flight of the box tuned to a station's
// carrier is the true flight time to the box's first receiver that hears
// it within 10 us (3.4 mm), the spread of the four repeats below 2 us.
// Walls absorbing: with Thamma's corner stations 5 cm from two walls, the
// wall echoes come 0.1-0.3 ms after the direct pulse and, where the direct
// path is weak, merge with it into one comparator pulse that rises late
// (docs/tof-capture.md, "limits"); the method has no way to see that.
TEST(TofChain, ThammaSyncReferencedRangingAtThePinLevel) {
  world::AcousticWorld w = world::thamma_world();
  w.room->reflection = {0, 0, 0, 0};
  const world::TriggeredTiming timing;
  const world::Pose pose{.x_m = 3.0, .y_m = 3.0, .theta_rad = std::numbers::pi / 4};
  const double start_s = 0.011;
  const world::Schedule schedule = world::triggered_schedule(timing, w.beacons.size(), 1, start_s);
  const double end_s = schedule.emissions.back().trigger_s + 0.06;
  const world::AcousticRun run = world::simulate(w, schedule, world::stationary(pose), end_s, 5);
  tof::CaptureSetup setup;
  setup.sync_enable = true;
  for (auto& c : setup.channels)
    c.enabled = true;
  const PinChain chain(run, {w.receivers.size(), world::ComparatorKind::kEnvelope}, setup, end_s);
  const tof::CaptureBatch all = chain.merged();
  ASSERT_EQ(all.sync.size(), w.beacons.size() * timing.repeats);

  tof::ThammaConfig config;
  config.fixed_delay_s = w.beacons[0].electronics_delay_s;
  config.envelope.rise_s = w.beacons[0].envelope_tau_s;
  config.envelope.fall_s = w.beacons[0].envelope_tau_s;
  config.envelope.burst_s = timing.pulse_s;
  config.speed_of_sound_mps = w.air.speed_of_sound_mps();
  for (std::size_t station = 0; station < w.beacons.size(); ++station) {
    const std::span<const tof::Tick> sync(all.sync.data() + station * timing.repeats,
                                          timing.repeats);
    const tof::ThammaMeasurement m =
        tof::measure_thamma(config, chain.timebase, sync, all.channels, all.incidents);
    const std::size_t box = w.beacons[station].carrier_hz == config.boxes[0].carrier_hz ? 0 : 1;
    const tof::ThammaBoxResult& r = m.boxes[box];
    const world::EmissionRecord& e = run.emissions[station * timing.repeats];
    // Truth: the earliest direct arrival among the box's receivers that
    // heard it (a receiver facing away may be nearer and deaf).
    double truth = std::numeric_limits<double>::infinity();
    for (const int c : config.boxes[box].channels) {
      const world::Arrival& a = e.receivers[static_cast<std::size_t>(c)].direct;
      if (a.above_threshold)
        truth = std::min(truth, a.true_time_s - e.emission_s);
    }
    EXPECT_EQ(r.used, static_cast<int>(timing.repeats)) << "station " << station;
    EXPECT_NEAR(r.tof_s, truth, 10e-6) << "station " << station << " " << tof::to_string(r.flags);
    EXPECT_LT(r.spread_s, 2e-6) << "station " << station;
  }
}

// The binaural pair at the pin level: each receiver drives two channels,
// its carrier comparator (carrier mode: the first 8 rising edges) and its
// envelope comparator (envelope mode: the compensated onset picks the whole
// carrier periods). The path difference |left - source| - |right - source|
// comes out within 50 um. Without the envelope channels the left receiver,
// 8 degrees off the transmitter's narrow beam, crosses its threshold two
// carrier periods later than the right one: the carrier-only result is two
// wavelengths off, and says so (kCycleUnverified).
TEST(TofChain, BinauralPhaseDifferenceAtThePinLevel) {
  // Within the Polaroid-size pistons' beam (2 and 8 degrees off axis); the
  // path difference, 17 mm, is two wavelengths.
  const world::Pose other{.x_m = 0.1, .y_m = 2.0, .theta_rad = std::numbers::pi};
  world::AcousticWorld w = world::binaural_world(world::stationary(other));
  w.receivers.push_back(w.receivers[0]);  // channel 2: the left receiver's envelope
  w.receivers.push_back(w.receivers[1]);  // channel 3: the right receiver's envelope
  const world::TriggeredTiming timing{.repeats = 1};
  const world::Schedule schedule = world::triggered_schedule(timing, 1, 1, 0.005);
  const double end_s = 0.05;
  const world::AcousticRun run = world::simulate(w, schedule, world::stationary({}), end_s, 9);
  tof::CaptureSetup setup;
  setup.sync_enable = true;
  for (unsigned c = 0; c < 2; ++c)
    setup.channels[c] = {.enabled = true, .mode = tof::ChannelMode::kCarrier, .edges = 8};
  for (unsigned c = 2; c < 4; ++c)
    setup.channels[c] = {.enabled = true, .mode = tof::ChannelMode::kEnvelope};
  const PinChain chain(run,
                       {world::ComparatorKind::kCarrier, world::ComparatorKind::kCarrier,
                        world::ComparatorKind::kEnvelope, world::ComparatorKind::kEnvelope},
                       setup, end_s);
  const tof::CaptureBatch all = chain.merged();
  ASSERT_EQ(all.sync.size(), 1U);
  ASSERT_EQ(all.channels[0].carrier.size(), 8U);
  ASSERT_EQ(all.channels[1].carrier.size(), 8U);

  const world::Reception& left = run.emissions[0].receivers[0];
  const world::Reception& right = run.emissions[0].receivers[1];
  const double truth_m = left.direct.path_m - right.direct.path_m;
  tof::BinauralConfig config;
  config.speed_of_sound_mps = w.air.speed_of_sound_mps();
  config.envelope.rise_s = w.beacons[0].envelope_tau_s;
  config.envelope.fall_s = w.beacons[0].envelope_tau_s;
  config.envelope.burst_s = timing.pulse_s;
  const auto measure = [&] {
    return tof::measure_binaural(config, chain.timebase, all.sync.front(), all.channels,
                                 all.incidents);
  };
  const tof::BinauralMeasurement carrier_only = measure();
  EXPECT_TRUE(carrier_only.pairs[0].flags.has(tof::Flag::kCycleUnverified));
  config.pairs[0].left_envelope = 2;
  config.pairs[0].right_envelope = 3;
  const tof::BinauralMeasurement m = measure();
  ASSERT_EQ(m.pairs.size(), 1U);
  EXPECT_FALSE(m.pairs[0].flags.any()) << tof::to_string(m.pairs[0].flags);
  EXPECT_NEAR(m.pairs[0].path_difference_m, truth_m, 50e-6);
  EXPECT_LT(m.pairs[0].phase_sd_rad, 2 * std::numbers::pi * 40e3 * 40e-9);
  std::printf("binaural: path difference %.4f mm (truth %.4f mm), carrier edges only %.4f mm\n",
              m.pairs[0].path_difference_m * 1e3, truth_m * 1e3,
              carrier_only.pairs[0].path_difference_m * 1e3);
}

}  // namespace
