// --target sim[:SCENARIO]: the simulated board in this process. Every run of
// the tool starts a fresh chip; `odoloc script` keeps one across commands.
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "odoloc/board/sim_target.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/target.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::cli {
namespace {

class SimBoard final : public Target {
 public:
  SimBoard(const std::string& scenario, const TargetOptions& options)
      : sim_({.scenario = scenario,
              .vcd_path = options.vcd,
              .vcd_pins_path = options.vcd_pins,
              .cycle_step = options.cycle_step}),
        bus_(sim_.link(), {.crc = options.crc}),
        stop_(options.stop) {}
  sw::RegisterBus& bus() override { return bus_; }
  // Simulated time: the fabric (and the scenario's robot) runs for
  // `interval`, as fast as the model goes, in slices of kSlice so that
  // Ctrl-C ends it within a few milliseconds.
  void wait(std::chrono::nanoseconds interval) override {
    while (interval.count() > 0) {
      if (stop_ != nullptr && stop_->load())
        throw Interrupted();
      const std::chrono::nanoseconds step = std::min(interval, kSlice);
      sim_.advance(step);
      interval -= step;
    }
  }
  [[nodiscard]] std::chrono::nanoseconds elapsed() const override { return sim_.elapsed(); }
  void finish() override {
    try {
      sim_.finish();
    } catch (const std::runtime_error& e) {
      throw FileError(e.what());
    }
  }

 private:
  // 50 000 fabric clocks: about 2 ms of CPU.
  static constexpr std::chrono::nanoseconds kSlice = std::chrono::milliseconds{1};

  board::SimTarget sim_;
  sw::SpiRegisterBus bus_;
  const std::atomic<bool>* stop_;
};

}  // namespace

std::unique_ptr<Target> open_sim_target(std::string_view argument, const TargetOptions& options) {
  const std::string scenario = argument.empty() ? "none" : std::string{argument};
  const std::vector<std::string> known = board::SimTarget::scenarios();
  if (std::ranges::find(known, scenario) == known.end())
    throw UsageError(fmt::format("unknown scenario '{}' for target sim; expected one of {}",
                                 scenario, fmt::join(known, ", ")));
  try {
    return std::make_unique<SimBoard>(scenario, options);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("target sim:{}: {}", scenario, e.what()));
  }
}

}  // namespace odoloc::cli
