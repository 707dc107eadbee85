// odoloc_eppm_demo: the encoder fabric (four EPPMs) driven by a built-in drive
// scenario. Prints, for each phase of the drive, what each EPPM reads against
// the ground truth, and checks that the read-increment sums equal the true
// edge counts. Optional VCD dump of the first clocks.
#include <CLI/CLI.hpp>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
#include "odoloc/rtl/vcd.hpp"
#include "odoloc/sw/eppm_units.hpp"
#include "odoloc/world/quadrature_source.hpp"

namespace {

using odoloc::rtl::EncoderFabric;
using odoloc::rtl::kEncoderCount;

// "left_rear", ...: the register map's names of the EPPM instances.
std::string encoder_name(std::size_t w) {
  return std::string(odoloc::regs::eppm::kInstanceNames[w]);
}
using odoloc::world::QuadratureSource;

// Wheel surface speeds in m/s for each phase of the default drive.
struct Phase {
  const char* name;
  double seconds;
  std::array<double, kEncoderCount> mps;  // left rear, right rear, front drive, steering
};
constexpr std::array<Phase, 4> kDefaultDrive = {{
    {"creep", 0.06, {0.020, 0.020, 0.020, 0.000}},
    {"cruise, left turn", 0.10, {0.900, 1.100, 1.050, 0.004}},
    {"fast straight", 0.06, {2.000, 2.000, 2.000, -0.004}},
    {"reverse", 0.08, {-0.300, -0.300, -0.300, 0.0}},
}};

// The odometry's reset control period (100 us).
constexpr std::uint32_t kLatchEveryClocks = odoloc::regs::odometry::cfg::update_clocks.reset;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"odoloc encoder-fabric demo: four EPPMs on a built-in drive"};
  std::string vcd_path;
  std::uint64_t vcd_clocks = 20'000;
  app.add_option("--vcd", vcd_path, "write a VCD waveform of the first clocks to this file");
  app.add_option("--vcd-clocks", vcd_clocks, "clocks to dump with --vcd")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  const odoloc::sw::EncoderGeometry geometry;
  const odoloc::sw::SpeedTiming timing;
  const auto thresholds = odoloc::sw::switch_thresholds(timing);
  EncoderFabric::Config cfg{};
  for (auto& c : cfg) {
    c.window.clocks = odoloc::rtl::UInt<23>{timing.window_clocks};
    c.prescale.divider = odoloc::rtl::UInt<16>{timing.prescale};
    c.to_period_below.edges = odoloc::rtl::UInt<23>{thresholds.to_period_below};
    c.to_pulse_at.edges = odoloc::rtl::UInt<23>{thresholds.to_pulse_at};
  }

  EncoderFabric fabric;
  EncoderFabric::In in{};
  std::array<QuadratureSource, kEncoderCount> sources{};
  std::array<std::int64_t, kEncoderCount> increments_sum{};

  std::ofstream vcd_file;
  std::unique_ptr<odoloc::rtl::VcdWriter> vcd;
  if (!vcd_path.empty()) {
    vcd_file.open(vcd_path);
    if (!vcd_file) {
      std::fprintf(stderr, "odoloc_eppm_demo: cannot write %s\n", vcd_path.c_str());
      return 1;
    }
    vcd = std::make_unique<odoloc::rtl::VcdWriter>(vcd_file, "encoder_fabric");
    vcd->declare(fabric);
  }

  std::printf(
      "odoloc encoder fabric demo: 4 EPPMs at %.0f MHz, window %.1f ms, reference %.2f MHz\n",
      odoloc::rtl::kFabricClockHz / 1e6, timing.window_s() * 1e3, timing.reference_hz() / 1e6);
  std::printf(
      "wheel: R = %.3f m, %g lines x4, gear %g:1 -> %.2f um per edge; switch period<%u, pulse>=%u "
      "edges/window\n\n",
      geometry.wheel_radius_m, geometry.lines_per_rev, geometry.gear_ratio,
      geometry.metres_per_edge() * 1e6, thresholds.to_period_below, thresholds.to_pulse_at);
  std::printf("%-18s %-12s %10s %10s %6s %9s %9s\n", "phase", "wheel", "true m/s", "read m/s",
              "mode", "error %", "bound %");

  const auto start = std::chrono::steady_clock::now();
  std::uint64_t clock = 0;
  for (const Phase& phase : kDefaultDrive) {
    for (std::size_t w = 0; w < kEncoderCount; ++w) {
      sources[w].set_rate(phase.mps[w] / geometry.metres_per_edge() / odoloc::rtl::kFabricClockHz);
    }
    const auto phase_clocks =
        static_cast<std::uint64_t>(phase.seconds * odoloc::rtl::kFabricClockHz);
    for (std::uint64_t i = 0; i < phase_clocks; ++i, ++clock) {
      const bool latch = clock % kLatchEveryClocks == kLatchEveryClocks - 1;
      for (std::size_t w = 0; w < kEncoderCount; ++w) {
        const auto ab = odoloc::board::encoder_pins(sources[w].tick());
        in[w].a = ab.bit<1>();
        in[w].b = ab.bit<0>();
        in[w].latch_clear = odoloc::rtl::UInt<1>::truncate(latch);
      }
      fabric.step(in, cfg);
      if (latch) {
        for (std::size_t w = 0; w < kEncoderCount; ++w) {
          increments_sum[w] +=
              fabric.eppm(static_cast<odoloc::rtl::Encoder>(w)).counter().latched.value();
        }
      }
      if (vcd && clock < vcd_clocks)
        vcd->sample(fabric, clock);
    }
    for (std::size_t w = 0; w < kEncoderCount; ++w) {
      const auto s = fabric.eppm(static_cast<odoloc::rtl::Encoder>(w)).status(cfg[w]).speed;
      const bool pulse = s.mode.value() == 1;
      const double read = odoloc::sw::speed_mps(static_cast<std::int32_t>(s.value.value()), pulse,
                                                geometry, timing);
      const double truth = phase.mps[w];
      const double edges_per_s = truth / geometry.metres_per_edge();
      const double bound = pulse ? timing.pulse_relative_error(edges_per_s)
                                 : timing.period_relative_error(edges_per_s);
      const char* mode = s.stalled.value() ? "stall" : pulse ? "pulse" : "period";
      const char* note = s.valid.value() ? "" : "  (invalid sample)";
      if (truth == 0.0) {
        std::printf("%-18s %-12s %10.4f %10.4f %6s %9s %9s%s\n", w == 0 ? phase.name : "",
                    encoder_name(w).c_str(), truth, read, mode, "-", "-", note);
      } else {
        std::printf("%-18s %-12s %10.4f %10.4f %6s %9.3f %9.3f%s\n", w == 0 ? phase.name : "",
                    encoder_name(w).c_str(), truth, read, mode, 100.0 * (read - truth) / truth,
                    100.0 * bound, note);
      }
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::printf("\n%-12s %14s %14s %14s\n", "wheel", "true edges", "sum of reads", "in counter");
  int mismatches = 0;
  for (std::size_t w = 0; w < kEncoderCount; ++w) {
    const auto& eppm = fabric.eppm(static_cast<odoloc::rtl::Encoder>(w));
    const std::int64_t counted = increments_sum[w] + eppm.count().value();
    // The pins reach the counter through a 2-flop synchroniser, the filter
    // and the decoder: edges of the last few clocks are still in flight.
    const std::int64_t in_flight = sources[w].edges() - counted;
    if (std::llabs(in_flight) > 1)
      ++mismatches;
    std::printf("%-12s %14lld %14lld %14lld\n", encoder_name(w).c_str(),
                static_cast<long long>(sources[w].edges()),
                static_cast<long long>(increments_sum[w]),
                static_cast<long long>(eppm.count().value()));
  }
  std::printf(
      "\nsimulated %.3f s (%llu clocks) in %.3f s wall: %.1f M clocks/s (%.1fx real time)\n",
      static_cast<double>(clock) / odoloc::rtl::kFabricClockHz,
      static_cast<unsigned long long>(clock), wall_s, static_cast<double>(clock) / wall_s / 1e6,
      static_cast<double>(clock) / odoloc::rtl::kFabricClockHz / wall_s);
  if (vcd) {
    vcd.reset();
    vcd_file.close();
    if (!vcd_file) {
      std::fprintf(stderr, "odoloc_eppm_demo: cannot write %s\n", vcd_path.c_str());
      return 1;
    }
    std::printf("waveform: %s (first %llu clocks)\n", vcd_path.c_str(),
                static_cast<unsigned long long>(vcd_clocks));
  }
  if (mismatches != 0) {
    std::printf("FAIL: %d wheel(s) lost or doubled edges\n", mismatches);
    return 1;
  }
  std::printf("OK: every edge accounted for\n");
  return 0;
}
