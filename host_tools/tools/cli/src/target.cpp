#include "odoloc/cli/target.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <thread>

#include "odoloc/bridge/lcm_register_bus.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/spidev_link.hpp"
#include "odoloc/cli/values.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::cli {
namespace {

void check_stop(const std::atomic<bool>* stop) {
  if (stop != nullptr && stop->load())
    throw Interrupted();
}

// A target on real time: wait() sleeps, elapsed() is wall-clock.
class WallClockTarget : public Target {
 public:
  explicit WallClockTarget(const std::atomic<bool>* stop) : stop_(stop) {}
  // Sleeps in slices of 10 ms so that Ctrl-C ends the wait promptly.
  void wait(std::chrono::nanoseconds interval) override {
    const auto until = std::chrono::steady_clock::now() + interval;
    for (;;) {
      check_stop(stop_);
      const auto now = std::chrono::steady_clock::now();
      if (now >= until)
        return;
      std::this_thread::sleep_for(std::min<std::chrono::nanoseconds>(until - now, kSlice));
    }
  }
  [[nodiscard]] std::chrono::nanoseconds elapsed() const override {
    return std::chrono::steady_clock::now() - start_;
  }

 private:
  static constexpr std::chrono::nanoseconds kSlice = std::chrono::milliseconds{10};

  const std::atomic<bool>* stop_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

class SpidevTarget final : public WallClockTarget {
 public:
  SpidevTarget(const SpidevSpec& spec, const TargetOptions& options)
      : WallClockTarget(options.stop),
        link_(spec.device, spec.speed_hz),
        bus_(link_, {.crc = options.crc}) {}
  sw::RegisterBus& bus() override { return bus_; }

 private:
  SpidevLink link_;
  sw::SpiRegisterBus bus_;
};

// A simulator's registers through its register bridge (docs/lcm.md).
class LcmTarget final : public WallClockTarget {
 public:
  LcmTarget(const std::string& url, const TargetOptions& options)
      : WallClockTarget(options.stop),
        connection_(open_lcm(url)),
        bus_(connection_, {.timeout = bridge::kDefaultTimeout,
                           .poll = [stop = options.stop] { check_stop(stop); }}) {}
  sw::RegisterBus& bus() override { return bus_; }

 private:
  lcm::Connection connection_;
  bridge::LcmRegisterBus bus_;
};

// One row per kind of target; a new transport is one opener and one row.
using Opener = std::unique_ptr<Target> (*)(std::string_view argument, const TargetOptions&);
struct TargetKind {
  std::string_view name;
  std::string_view syntax;
  Opener open;
};
constexpr TargetKind kTargetKinds[] = {
    {"sim", "sim[:SCENARIO]", open_sim_target},
    {"spidev", "spidev:/dev/spidevB.C[@HZ]", open_spidev_target},
    {"lcm", "lcm[:URL]", open_lcm_target},
};

struct Match {
  const TargetKind* kind;
  std::string_view argument;
};

Match match(std::string_view spec) {
  for (const TargetKind& k : kTargetKinds) {
    if (spec == k.name)
      return {&k, {}};
    if (spec.starts_with(k.name) && spec.size() > k.name.size() && spec[k.name.size()] == ':')
      return {&k, spec.substr(k.name.size() + 1)};
  }
  std::string expected;
  for (std::size_t i = 0; i < std::size(kTargetKinds); ++i) {
    if (i > 0)
      expected += i + 1 == std::size(kTargetKinds) ? " or " : ", ";
    expected += kTargetKinds[i].syntax;
  }
  throw UsageError(fmt::format("unknown target '{}'; expected {}", spec, expected));
}

}  // namespace

SpidevSpec parse_spidev_spec(std::string_view argument) {
  SpidevSpec spec;
  const std::size_t at = argument.rfind('@');
  spec.device = std::string{argument.substr(0, at)};
  if (spec.device.empty())
    throw UsageError("target spidev needs a device: spidev:/dev/spidevB.C[@HZ]");
  if (at != std::string_view::npos)
    spec.speed_hz = parse_frequency(argument.substr(at + 1));
  if (spec.speed_hz > kSpidevMaxHz)
    throw UsageError(fmt::format(
        "SPI clock {} Hz is above the fabric's limit of {} Hz (4 fabric clocks per SCLK level, "
        "docs/spi.md)",
        spec.speed_hz, kSpidevMaxHz));
  return spec;
}

std::unique_ptr<Target> open_spidev_target(std::string_view argument,
                                           const TargetOptions& options) {
  if (!options.vcd.empty() || !options.vcd_pins.empty() || options.cycle_step)
    throw UsageError(
        "--vcd, --vcd-pins and --cycle-step act on the simulated chip: they need --target sim");
  return std::make_unique<SpidevTarget>(parse_spidev_spec(argument), options);
}

std::unique_ptr<Target> open_lcm_target(std::string_view argument, const TargetOptions& options) {
  if (options.crc || !options.vcd.empty() || !options.vcd_pins.empty() || options.cycle_step)
    throw UsageError(
        "--crc, --vcd, --vcd-pins and --cycle-step act on an SPI link or the simulated chip in "
        "this process; target lcm reaches the simulator's registers through its register "
        "bridge, which frames them itself");
  return std::make_unique<LcmTarget>(
      argument.empty() ? std::string{lcm::kDefaultUrl} : std::string{argument}, options);
}

lcm::Connection open_lcm(const std::string& url) {
  try {
    return lcm::Connection(url);
  } catch (const lcm::LcmError& e) {
    throw UsageError(e.what());
  }
}

bool is_sim_spec(std::string_view spec) {
  return match(spec).kind->open == open_sim_target;
}

void check_target_spec(std::string_view spec) {
  (void)match(spec);
}

std::unique_ptr<Target> open_target(std::string_view spec, const TargetOptions& options) {
  const Match m = match(spec);
  return m.kind->open(m.argument, options);
}

}  // namespace odoloc::cli
