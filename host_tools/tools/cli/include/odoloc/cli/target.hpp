// Where the tool's register accesses go: a `Target` gives the register bus
// and a way to let time pass. `open_target` picks the transport from the
// --target spec through one table of target kinds:
//   sim[:SCENARIO]              the simulated board (odoloc::board::SimTarget)
//   spidev:/dev/spidevB.C[@HZ]  a Linux spidev device (default 1 MHz)
//   lcm[:URL]                   a simulator's registers over LCM (its register bridge)
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "odoloc/regs.hpp"
#include "odoloc/sw/register_bus.hpp"

namespace odoloc::lcm {
class Connection;
}  // namespace odoloc::lcm

namespace odoloc::cli {

struct TargetOptions {
  bool crc = false;         // switch the fabric's SPI CRC-8 on first (top.ctrl.crc_enable)
  std::string vcd;          // sim only: write the chip's waveform of every frame here
  std::string vcd_pins;     // sim only: the four SPI pins of every frame, for sigrok and the like
  bool cycle_step = false;  // sim only: step every clock instead of fast-forwarding
  // Set by Ctrl-C: wait() and, on lcm, a bus request waiting for its answer
  // return early by throwing Interrupted.
  const std::atomic<bool>* stop = nullptr;
};

class Target {
 public:
  Target() = default;
  Target(const Target&) = delete;
  Target& operator=(const Target&) = delete;
  virtual ~Target() = default;

  virtual sw::RegisterBus& bus() = 0;
  // Lets `interval` pass: simulated time on the simulator (the fabric runs
  // for that long, as fast as the model goes), wall-clock sleep on hardware.
  // Throws Interrupted when the stop flag is set meanwhile.
  virtual void wait(std::chrono::nanoseconds interval) = 0;
  // Time since the target was opened, on the same clock as wait().
  [[nodiscard]] virtual std::chrono::nanoseconds elapsed() const = 0;
  // After the last command: closes what the target wrote (waveforms) and
  // throws when any of it was lost.
  virtual void finish() {}
};

// The longest simulated time one command may ask of the simulated board (a
// wait, or a watch's interval × (count − 1)), and about what it costs; longer
// requests are refused before anything runs. Fast-forwarding (the default)
// the board runs the square drive's 10 s in about 0.4 s of CPU, so 120 s
// take about 5 s; stepped clock by clock (--cycle-step) it runs about 25
// million fabric clocks (half a simulated second) per second of CPU, so 10 s
// take about 20 s.
struct SimulatedLimit {
  std::chrono::seconds max;  // simulated time per command
  std::chrono::seconds cpu;  // about the CPU time `max` takes
  std::string_view mode;     // for messages: "" or " with --cycle-step"
};
inline constexpr SimulatedLimit kFastForwardLimit{std::chrono::seconds{120},
                                                  std::chrono::seconds{5}, ""};
inline constexpr SimulatedLimit kCycleStepLimit{std::chrono::seconds{10}, std::chrono::seconds{20},
                                                " with --cycle-step"};
[[nodiscard]] constexpr SimulatedLimit simulated_limit(bool cycle_step) {
  return cycle_step ? kCycleStepLimit : kFastForwardLimit;
}

// True for sim and sim:SCENARIO.
[[nodiscard]] bool is_sim_spec(std::string_view spec);

inline constexpr std::uint32_t kSpidevDefaultHz = 1'000'000;
// docs/spi.md: each SCLK level must last spi.min_level_clocks fabric clocks.
inline constexpr std::uint32_t kSpidevMaxHz = regs::spi::kMaxSclkHz;

struct SpidevSpec {
  std::string device;
  std::uint32_t speed_hz = kSpidevDefaultHz;
};
// "/dev/spidev0.0" or "/dev/spidev0.0@2M" (the part after "spidev:").
[[nodiscard]] SpidevSpec parse_spidev_spec(std::string_view argument);

// Throws UsageError for a spec no target kind accepts; opens nothing.
void check_target_spec(std::string_view spec);
// Opens the target; UsageError for a bad spec or a device that cannot be
// opened, sw::BusError when the first transfers fail.
[[nodiscard]] std::unique_ptr<Target> open_target(std::string_view spec,
                                                  const TargetOptions& options);

// The target kinds' openers, given the spec after "KIND:" ("" when absent).
[[nodiscard]] std::unique_ptr<Target> open_sim_target(std::string_view argument,
                                                      const TargetOptions& options);
[[nodiscard]] std::unique_ptr<Target> open_spidev_target(std::string_view argument,
                                                         const TargetOptions& options);
// `argument`: an LCM URL; "" is lcm::kDefaultUrl. The bus is a
// bridge::LcmRegisterBus (requests time out after bridge::kDefaultTimeout);
// wait() sleeps wall-clock time. UsageError for --crc, --vcd, --vcd-pins and
// --cycle-step, and when LCM cannot open the URL.
[[nodiscard]] std::unique_ptr<Target> open_lcm_target(std::string_view argument,
                                                      const TargetOptions& options);

// An LCM connection for the tool (--target lcm, watch pose); UsageError with
// LCM's reason, naming the URL, when it cannot be opened.
[[nodiscard]] lcm::Connection open_lcm(const std::string& url);

}  // namespace odoloc::cli
