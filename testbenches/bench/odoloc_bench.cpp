// Speed targets live here, not in timed tests: `odoloc_bench` (Google Benchmark).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "beacon_geometry.hpp"
#include "issue_stimulus.hpp"
#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/board/world_stimulus.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
#include "odoloc/sw/kleeman_solver.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/sw/pose_ekf.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"
#include "odoloc/world/quadrature_source.hpp"
#include "odoloc/world/scenarios.hpp"
#include "odoloc/world/tricycle.hpp"
#include "odometry_bench.hpp"
#include "synthetic_pins.hpp"

namespace {

using odoloc::board::encoder_pins;
using odoloc::rtl::EncoderFabric;
using odoloc::rtl::kEncoderCount;
using odoloc::tb::IssueStimulus;
using odoloc::tb::SyntheticPins;
using odoloc::world::QuadratureSource;

// Four encoders at four speeds; the steering encoder reverses every 1.3 ms.
template <odoloc::rtl::Gating G>
void step_four_eppms(benchmark::State& state) {
  EncoderFabric fabric;
  EncoderFabric::Config cfg{};
  EncoderFabric::In in{};
  IssueStimulus stimulus;
  for (auto _ : state) {
    for (int i = 0; i < 1024; ++i) {
      if (stimulus.tick()) {
        for (std::size_t w = 0; w < kEncoderCount; ++w) {
          in[w].a = stimulus.pins()[w].bit<1>();
          in[w].b = stimulus.pins()[w].bit<0>();
        }
      }
      fabric.step<G>(in, cfg);
    }
    benchmark::DoNotOptimize(fabric);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(stimulus.clocks()));
  state.counters["left_rear_count"] =
      static_cast<double>(fabric.eppm(odoloc::rtl::Encoder::kLeftRear).count().value());
}
void BM_FourEppm_CycleStep(benchmark::State& state) {
  step_four_eppms<odoloc::rtl::Gating::kOn>(state);
}
BENCHMARK(BM_FourEppm_CycleStep);

// Every block evaluated every clock: the cost when all pins toggle at once.
void BM_FourEppm_CycleStep_Ungated(benchmark::State& state) {
  step_four_eppms<odoloc::rtl::Gating::kOff>(state);
}
BENCHMARK(BM_FourEppm_CycleStep_Ungated);

// The whole odometry fabric (four EPPMs, CORDIC, both units, min-select,
// pose) on a 1 m/s left turn at 20 degrees of steering, updating every 100 us.
void BM_OdometryFabric_CycleStep(benchmark::State& state) {
  odoloc::tb::OdometryBench bench;
  bench.steer_to(20.0 * M_PI / 180.0);
  bench.drive(1.0, 20.0 * M_PI / 180.0);
  const std::uint64_t start = bench.clocks;
  for (auto _ : state) {
    bench.run(1024);
    benchmark::DoNotOptimize(bench.fabric);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(bench.clocks - start));
  state.counters["updates"] = static_cast<double>(bench.fabric.sequencer().updates.value());
}
BENCHMARK(BM_OdometryFabric_CycleStep);

// The whole chip (fabric, capture unit, register file, idle SPI slave)
// stepped clock by clock under issue 13's stimulus, cs_n high: compare with
// BM_FourEppm_CycleStep for the cost of the rest of the chip on every clock.
void BM_OdolocChip_CycleStep(benchmark::State& state) {
  odoloc::rtl::OdolocChip chip;
  odoloc::rtl::ChipPins pins;
  IssueStimulus stimulus;
  for (auto _ : state) {
    for (int i = 0; i < 1024; ++i) {
      if (stimulus.tick())
        pins.encoders = stimulus.pins();
      chip.step(pins);
    }
    benchmark::DoNotOptimize(chip);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(stimulus.clocks()));
  state.counters["chip_bytes"] = sizeof(odoloc::rtl::OdolocChip);  // memory per instance
}
BENCHMARK(BM_OdolocChip_CycleStep);

// The chip behind the board's link, a per-clock function driving four
// encoders at 200 k, 20 k, 1 M and 2 k edges/s (reversed): every clock
// through ChipLink::advance and its stimulus calls, SPI idle.
void BM_ChipLink_CycleStep(benchmark::State& state) {
  std::array<QuadratureSource, 4> sources{QuadratureSource(0.004), QuadratureSource(0.0004),
                                          QuadratureSource(0.02), QuadratureSource(-0.00004)};
  odoloc::board::ChipLink link({.half_period = 4}, [&](auto& pins) {
    for (std::size_t w = 0; w < 4; ++w)
      pins.encoders[w] = encoder_pins(sources[w].tick());
  });
  for (auto _ : state)
    link.advance(1024);
  state.SetItemsProcessed(static_cast<std::int64_t>(link.clocks()));
}
BENCHMARK(BM_ChipLink_CycleStep);

// The same chip with the ultrasonic capture unit armed on all eight
// channels, during Kleeman's beacon cycles (the acoustic world's envelope
// comparators on the pins, echoes included), the encoders moving as above;
// no SPI. Compare with BM_ChipLink_CycleStep: the channels' share.
void BM_OdolocChip_CycleStep_BeaconCycle(benchmark::State& state) {
  namespace world = odoloc::world;
  const world::AcousticWorld room = world::kleeman_world();
  const world::KleemanTiming timing;
  const world::AcousticRun run =
      world::simulate(room, world::kleeman_schedule(timing, 1), world::stationary({4.0, 3.0, 0.3}),
                      timing.cycle_s(), 1);
  world::AcousticPins acoustic(run, world::ComparatorKind::kEnvelope);
  std::array<QuadratureSource, 4> sources{QuadratureSource(0.004), QuadratureSource(0.0004),
                                          QuadratureSource(0.02), QuadratureSource(-0.00004)};
  odoloc::board::ChipLink link({.half_period = 4}, [&](auto& pins) {
    for (std::size_t w = 0; w < 4; ++w)
      pins.encoders[w] = encoder_pins(sources[w].tick());
    pins.comparators = decltype(pins.comparators)::truncate(acoustic.tick().channels);
  });
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = false});
  bus.write(odoloc::regs::tof::command::kAddress, odoloc::regs::tof::command::arm.set(0, 0xFF));
  const std::uint64_t start = link.clocks();
  for (auto _ : state) {
    link.advance(1024);
    if (acoustic.clock() >= static_cast<std::uint64_t>(timing.cycle_s() * 50e6)) {
      state.PauseTiming();
      acoustic.skip_to(0);  // the next cycle: the same waveforms again
      state.ResumeTiming();
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(link.clocks() - start));
}
BENCHMARK(BM_OdolocChip_CycleStep_BeaconCycle);

// Fast-forward (OdolocChip::advance) with the pins held: the chip skips
// analytically between its own events (EPPM windows, odometry updates every
// 100 us, timestamp epochs), and the SoC reads 8 EPPM words every 100 ms
// over SPI. items/s are effective fabric clocks per second (compare with
// BM_OdolocChip_CycleStep; `skipped` is the share not stepped).
void BM_OdolocChip_FastForward_EncodersStill(benchmark::State& state) {
  odoloc::board::ChipLink link({.half_period = 4});
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = false});
  std::array<std::uint32_t, 8> words{};
  constexpr std::uint64_t kReadPeriodClocks = 5'000'000;  // 100 ms
  for (auto _ : state) {
    link.advance(kReadPeriodClocks);
    bus.read(odoloc::regs::eppm::kBase, words);
    benchmark::DoNotOptimize(words);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(link.clocks()));
  state.counters["skipped"] =
      static_cast<double>(link.skipped_clocks()) / static_cast<double>(link.clocks());
}
BENCHMARK(BM_OdolocChip_FastForward_EncodersStill);

// The default long run (issue 13): the tricycle drives laps of the 6 m square
// at 1 m/s (all four encoders moving; 1 ms physics steps), Kleeman's beacons
// fire one every 150 ms around it onto the capture unit's eight envelope
// comparators, and the SoC reads the EPPM block and channel 0's FIFO (32
// words each) every 100 ms over SPI. Args: simulated seconds, cycle_step.
// items/s: effective fabric clocks per second; realtime: x the 50 MHz fabric.
// The world (the truth's trajectory, the acoustic run) is built untimed.
void BM_Patrol(benchmark::State& state) {
  namespace world = odoloc::world;
  const auto seconds = static_cast<double>(state.range(0));
  const bool cycle_step = state.range(1) != 0;
  const world::Scenario scenario = world::patrol(seconds);
  world::Options options;
  options.start = scenario.start;
  options.clocks_per_step = 50'000;
  options.record_every_steps = 10;
  const auto clocks = static_cast<std::uint64_t>(seconds * odoloc::rtl::kFabricClockHz);
  world::TricycleSimulator prepass(scenario.geometry, scenario.path, scenario.disturbances,
                                   options);
  while (prepass.clock() < clocks) {
    prepass.tick();
    prepass.skip(std::min(prepass.hold_ticks(), clocks - prepass.clock()));
  }
  const world::KleemanTiming timing;
  const auto cycles = static_cast<std::size_t>(std::ceil(seconds / timing.cycle_s()));
  const world::AcousticRun run =
      world::simulate(world::kleeman_world(), world::kleeman_schedule(timing, cycles),
                      world::interpolate(prepass.trajectory()), seconds, 1);
  constexpr std::uint64_t kReadPeriodClocks = 5'000'000;  // 100 ms
  std::uint64_t skipped = 0;
  for (auto _ : state) {
    world::TricycleSimulator truth(scenario.geometry, scenario.path, scenario.disturbances,
                                   options);
    world::AcousticPins acoustics(run, world::ComparatorKind::kEnvelope);
    odoloc::board::WorldStimulus stimulus(&truth, &acoustics);
    odoloc::board::ChipLink link({.half_period = 4}, stimulus);
    link.set_cycle_step(cycle_step);
    odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = false});
    bus.write(odoloc::regs::tof::command::kAddress, odoloc::regs::tof::command::arm.set(0, 0xFF));
    std::array<std::uint32_t, 32> words{};
    while (link.clocks() < clocks) {
      link.advance(std::min(kReadPeriodClocks, clocks - link.clocks()));
      bus.read(odoloc::regs::eppm::kBase, words);
      bus.read(odoloc::regs::tof_channel::status::address(0), words);
      benchmark::DoNotOptimize(words);
    }
    skipped = link.skipped_clocks();
    state.SetItemsProcessed(static_cast<std::int64_t>(link.clocks()));
  }
  state.counters["skipped"] = static_cast<double>(skipped) / static_cast<double>(clocks);
  state.counters["realtime"] = benchmark::Counter(seconds, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Patrol)
    ->ArgNames({"seconds", "cycle_step"})
    ->Args({600, 0})
    ->Args({60, 0})
    ->Args({2, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

// ---- how cost grows with work ---------------------------------------------
// Runs the chip on SyntheticPins (SPI idle) for 20 ms of fabric time per
// iteration: items/s are fabric clocks per second (fast-forward: effective).
void run_scaling(benchmark::State& state, std::size_t encoders, double edges_per_second,
                 std::size_t channels, bool cycle_step) {
  SyntheticPins pins(encoders, edges_per_second, channels);
  odoloc::board::ChipLink link({.half_period = 4}, pins);
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = false});
  bus.write(odoloc::regs::tof::command::kAddress, odoloc::regs::tof::command::arm.set(0, 0xFF));
  link.set_cycle_step(cycle_step);
  constexpr std::uint64_t kClocksPerIteration = 1'000'000;  // 20 ms
  const std::uint64_t start = link.clocks();
  for (auto _ : state)
    link.advance(kClocksPerIteration);
  state.SetItemsProcessed(static_cast<std::int64_t>(link.clocks() - start));
  state.counters["chip_bytes"] = sizeof(odoloc::rtl::OdolocChip);
}
constexpr double kScalingEdgesPerSecond = 100e3;  // about 1 m/s on the front wheel

// Args: encoders moving (100 k edges/s each), cycle_step.
void BM_Scaling_Encoders(benchmark::State& state) {
  run_scaling(state, static_cast<std::size_t>(state.range(0)), kScalingEdgesPerSecond, 0,
              state.range(1) != 0);
}
BENCHMARK(BM_Scaling_Encoders)
    ->ArgNames({"encoders", "cycle_step"})
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}});

// Args: edges per second on one encoder, cycle_step.
void BM_Scaling_EdgeRate(benchmark::State& state) {
  run_scaling(state, 1, static_cast<double>(state.range(0)), 0, state.range(1) != 0);
}
BENCHMARK(BM_Scaling_EdgeRate)
    ->ArgNames({"edges_per_s", "cycle_step"})
    ->ArgsProduct({{1'000, 10'000, 100'000, 1'000'000}, {0, 1}});

// Args: comparator channels pulsing (1 kHz), cycle_step; encoders still.
void BM_Scaling_TofChannels(benchmark::State& state) {
  run_scaling(state, 0, 0, static_cast<std::size_t>(state.range(0)), state.range(1) != 0);
}
BENCHMARK(BM_Scaling_TofChannels)
    ->ArgNames({"channels", "cycle_step"})
    ->ArgsProduct({{0, 1, 2, 4, 8}, {0, 1}});

// Register reads through the sim target: SoC bus -> frame codec -> pin-level
// master -> chip, 32-word bursts at the fastest legal SCLK (6.25 MHz).
void BM_SimBus_Read32Words(benchmark::State& state) {
  odoloc::board::ChipLink link({.half_period = 4});
  odoloc::sw::SpiRegisterBus bus(link, {.crc = state.range(0) != 0, .confirm_writes = false});
  std::array<std::uint32_t, 32> words{};
  for (auto _ : state) {
    bus.read(odoloc::regs::eppm::kBase, words);
    benchmark::DoNotOptimize(words);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * words.size()));
  state.counters["fabric_clocks_per_word"] =
      static_cast<double>(link.clocks()) / static_cast<double>(state.iterations() * words.size());
}
BENCHMARK(BM_SimBus_Read32Words)->Arg(0)->Arg(1);

// One 6-beacon fix (issue 11's target for the all-beacon estimator with
// its consensus: <= 20 us). Kleeman's room, a robot inside it, 1 mm noise,
// beacon 1's first arrival a wall echo 0.6 m long, its direct pulse missing.
odoloc::sw::locate::RangeSet six_beacon_cycle(const odoloc::sw::locate::BeaconLayout& layout) {
  std::mt19937_64 rng(3);
  odoloc::sw::locate::RangeSet set =
      odoloc::tb::exact_range_set(layout, {3.7, 6.2}, 2.5, 1e-3, &rng);
  set.beacons[1].candidates[0].distance_m += 0.6;
  return set;
}

void BM_Fix_Multilateration(benchmark::State& state) {
  const odoloc::sw::locate::BeaconLayout layout = odoloc::tb::kleeman_layout();
  const odoloc::sw::locate::RangeSet set = six_beacon_cycle(layout);
  odoloc::sw::locate::MultilaterationOptions options;
  options.robust = state.range(0) != 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(odoloc::sw::locate::multilaterate(layout, set, options));
  state.SetLabel(options.robust ? "consensus over 20 triples + Gauss-Newton"
                                : "linear start + Gauss-Newton");
}
BENCHMARK(BM_Fix_Multilateration)->Arg(1)->Arg(0);

// Kleeman's longsolve on the same cycle: a fresh solver (all 20 triples'
// errors estimated, the paper's step 2 on a first call) or one that has
// seen the robot here (errors kept: steps 1, 3, 4 only).
void BM_Fix_Longsolve(benchmark::State& state) {
  const odoloc::sw::locate::BeaconLayout layout = odoloc::tb::kleeman_layout();
  const odoloc::sw::locate::RangeSet set = six_beacon_cycle(layout);
  odoloc::sw::locate::Longsolve warm;
  benchmark::DoNotOptimize(warm.solve(layout, set));
  for (auto _ : state) {
    if (state.range(0) != 0) {
      odoloc::sw::locate::Longsolve fresh;
      benchmark::DoNotOptimize(fresh.solve(layout, set));
    } else {
      benchmark::DoNotOptimize(warm.solve(layout, set));
    }
  }
  state.SetLabel(state.range(0) != 0 ? "first call" : "errors kept");
}
BENCHMARK(BM_Fix_Longsolve)->Arg(1)->Arg(0);

// Kleeman's eq. 4 iterated on one triple from 1 m away.
void BM_Fix_KleemanTriple(benchmark::State& state) {
  const odoloc::sw::locate::BeaconLayout layout = odoloc::tb::kleeman_layout();
  const odoloc::sw::locate::RangeSet set = six_beacon_cycle(layout);
  for (auto _ : state)
    benchmark::DoNotOptimize(odoloc::sw::locate::solve_triple(layout, set, {0, 2, 4}, {4.4, 5.5}));
}
BENCHMARK(BM_Fix_KleemanTriple);

// The pose EKF (issue 14): one prediction from an odometry increment; one
// position fix; one Kleeman cycle of six ranges with the common offset.
void BM_Ekf_Predict(benchmark::State& state) {
  namespace fuse = odoloc::sw::fuse;
  fuse::EkfOptions options;
  options.history_s = 0;  // the predict alone, no history kept
  fuse::PoseEkf ekf(options);
  ekf.initialise(0, fuse::Pose{}, fuse::Matrix3::Identity() * 1e-2);
  double t = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(ekf.predict(t += 0.01, fuse::Increment{{0.01, 0.0, 0.001}}));
}
BENCHMARK(BM_Ekf_Predict);

void BM_Ekf_Update(benchmark::State& state) {
  namespace fuse = odoloc::sw::fuse;
  const odoloc::sw::locate::BeaconLayout layout = odoloc::tb::kleeman_layout();
  const fuse::Vector2 robot(3.7, 6.2);
  fuse::RangeSet cycle;
  for (const odoloc::sw::locate::Beacon& b : layout.beacons) {
    const fuse::Vector2 at(b.position_m.x, b.position_m.y);
    cycle.ranges.push_back(
        {at, b.height_m, std::hypot((robot - at).norm(), b.height_m) + 0.3, 0.002});
  }
  const fuse::PositionFix fix{robot, fuse::Matrix2::Identity() * 1e-4};
  fuse::EkfOptions options;
  options.history_s = 0;
  fuse::PoseEkf ekf(options);
  ekf.initialise(0, fuse::Pose{{3.71, 6.19, 0.4}}, fuse::Matrix3::Identity() * 1e-2);
  double t = 0;
  for (auto _ : state) {  // the same measurement again: the same work each time
    if (state.range(0) != 0)
      benchmark::DoNotOptimize(ekf.update(t += 0.01, cycle));
    else
      benchmark::DoNotOptimize(ekf.update(t += 0.01, fix));
  }
  state.SetLabel(state.range(0) != 0 ? "six beacon ranges, common offset" : "position fix");
}
BENCHMARK(BM_Ekf_Update)->Arg(0)->Arg(1);

}  // namespace

BENCHMARK_MAIN();
