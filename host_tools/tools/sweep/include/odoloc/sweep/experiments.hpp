// The experiments a sweep runs (docs/sweep.md#experiments): what each takes
// (its parameters, with units, ranges and defaults), what one trial measures
// (its metrics), and one trial run on the existing engines.
//
//   odometry  board::run_scenario: the ground-truth tricycle drives a
//             world scenario, its encoders drive the cycle-accurate odometry
//             fabric (fast-forwarded), the final pose is compared with the truth.
//   beacons   one of Kleeman's beacon cycles in the acoustic world (echoes,
//             occlusion, turbulence, air temperature), its arrivals formed
//             into a range set (board::measure_kleeman_cycle) and solved by
//             the SoC software's beacon solvers.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace odoloc::sweep {

enum class Experiment : std::uint8_t { kOdometry, kBeacons };

inline constexpr std::string_view kExperimentNames[] = {"odometry", "beacons"};
[[nodiscard]] std::string_view name(Experiment experiment);

// A parameter's value: a number in the parameter's unit, or one of its names.
using Value = std::variant<double, std::string>;

struct ParameterInfo {
  std::string_view name;
  std::string_view meaning;  // one sentence with the unit, as docs/sweep.md gives it
  // Not empty: the parameter takes one of these names; empty: a finite number
  // in [min, max].
  std::span<const std::string_view> choices = {};
  double min = 0;
  double max = 0;
  double default_number = 0;
  std::string_view default_choice = {};

  [[nodiscard]] bool is_choice() const { return !choices.empty(); }
  [[nodiscard]] Value default_value() const;
};

struct MetricInfo {
  std::string_view name;
  std::string_view meaning;  // with the unit; when it has no value (NaN)
};

// In their documented order.
[[nodiscard]] std::span<const ParameterInfo> parameters(Experiment experiment);
[[nodiscard]] std::span<const MetricInfo> metrics(Experiment experiment);
// nullptr when the experiment has no such parameter.
[[nodiscard]] const ParameterInfo* find_parameter(Experiment experiment, std::string_view name);

// Every parameter's value at one point of the grid.
using Settings = std::map<std::string, Value, std::less<>>;

// One trial: the values of metrics(experiment), in that order; NaN where a
// trial has none (no fix). Every random draw comes from `seed` (its draws
// and their order: docs/sweep.md), so the same seed gives the same values.
// Throws SweepError (usage) when the engine refuses the settings (a bump
// the wheel cannot follow); run_job adds the job, point and settings.
[[nodiscard]] std::vector<double> run_trial(Experiment experiment, const Settings& settings,
                                            std::uint64_t seed);

}  // namespace odoloc::sweep
