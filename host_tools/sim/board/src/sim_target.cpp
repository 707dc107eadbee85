#include "odoloc/board/sim_target.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/world_stimulus.hpp"
#include "odoloc/world/scenarios.hpp"
#include "odoloc/world/tricycle.hpp"

namespace odoloc::board {
namespace {

using ScenarioMaker = std::function<world::Scenario()>;

const std::map<std::string, ScenarioMaker, std::less<>>& scenario_table() {
  static const std::map<std::string, ScenarioMaker, std::less<>> table{
      {"square", [] { return world::default_square(); }},
      {"straight", [] { return world::bump_scenario(world::BumpCase::kNone); }},
      {"bump_one_rear", [] { return world::bump_scenario(world::BumpCase::kOneRear); }},
  };
  return table;
}

// The scenario's ground-truth robot, if any ("none": the pins stay).
std::optional<world::TricycleSimulator> make_truth(const std::string& name) {
  if (name == "none")
    return std::nullopt;
  const auto it = scenario_table().find(name);
  if (it == scenario_table().end())
    throw std::invalid_argument("unknown scenario '" + name + "'");
  const world::Scenario s = it->second();
  world::Options truth_options;
  truth_options.start = s.start;
  return std::optional<world::TricycleSimulator>(std::in_place, s.geometry, s.path, s.disturbances,
                                                 truth_options);
}

}  // namespace

// The chip, plus the ground-truth robot when a scenario drives the encoders.
class SimTarget::Impl {
 public:
  explicit Impl(const SimTargetOptions& options)
      : truth_(make_truth(options.scenario)),
        stimulus_(truth_ ? &*truth_ : nullptr, nullptr),
        link_({.half_period = checked_half_period(options.sclk_half_period)}, stimulus_) {
    link_.set_cycle_step(options.cycle_step);
    if (!options.vcd_path.empty()) {
      open(vcd_file_, options.vcd_path);
      vcd_.emplace(vcd_file_);
      link_.trace_frames(*vcd_);
    }
    if (!options.vcd_pins_path.empty()) {
      open(pins_file_, options.vcd_pins_path);
      pins_vcd_.emplace(pins_file_);
      link_.trace_pins(*pins_vcd_);
    }
  }
  ChipLink& link() { return link_; }

  void finish() {
    close(vcd_file_, vcd_path_);
    close(pins_file_, pins_path_);
  }

 private:
  void open(std::ofstream& file, const std::string& path) {
    file.open(path);
    if (!file)
      throw std::invalid_argument("cannot write the waveform to '" + path +
                                  "': " + std::strerror(errno));
    (&file == &vcd_file_ ? vcd_path_ : pins_path_) = path;
  }
  static void close(std::ofstream& file, const std::string& path) {
    if (!file.is_open())
      return;
    errno = 0;
    file.flush();
    file.close();
    if (!file)
      throw std::runtime_error("writing the waveform to '" + path + "' failed" +
                               (errno != 0 ? std::string{": "} + std::strerror(errno) : ""));
  }
  static unsigned checked_half_period(unsigned half_period) {
    if (half_period < rtl::SpiSlave::kMinLevelClocks)
      throw std::invalid_argument("SCLK half period of " + std::to_string(half_period) +
                                  " clocks: the slave needs at least " +
                                  std::to_string(rtl::SpiSlave::kMinLevelClocks));
    return half_period;
  }
  std::optional<world::TricycleSimulator> truth_;  // before link_, which drives it
  WorldStimulus stimulus_;
  ChipLink link_;
  std::ofstream vcd_file_, pins_file_;
  std::string vcd_path_, pins_path_;
  std::optional<rtl::VcdWriter> vcd_;  // after link_: destroyed first, flushed before the file
  std::optional<rtl::VcdWriter> pins_vcd_;
};

SimTarget::SimTarget(const SimTargetOptions& options) : impl_(std::make_unique<Impl>(options)) {}
SimTarget::~SimTarget() = default;

sw::SpiLink& SimTarget::link() {
  return impl_->link();
}

void SimTarget::advance(std::chrono::nanoseconds simulated) {
  if (simulated.count() < 0)
    throw std::invalid_argument("cannot advance by a negative time");
  impl_->link().advance(static_cast<std::uint64_t>(simulated.count()) / rtl::kFabricClockPeriodNs);
}

std::uint64_t SimTarget::clocks() const {
  return impl_->link().clocks();
}

std::uint64_t SimTarget::skipped_clocks() const {
  return impl_->link().skipped_clocks();
}

std::chrono::nanoseconds SimTarget::elapsed() const {
  return std::chrono::nanoseconds{static_cast<std::int64_t>(clocks() * rtl::kFabricClockPeriodNs)};
}

void SimTarget::finish() {
  impl_->finish();
}

std::vector<std::string> SimTarget::scenarios() {
  std::vector<std::string> names{"none"};
  for (const auto& [name, make] : scenario_table())
    names.push_back(name);
  return names;
}

}  // namespace odoloc::board
