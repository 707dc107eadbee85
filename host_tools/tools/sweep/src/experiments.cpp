#include "odoloc/sweep/experiments.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "odoloc/board/beacon_ranges.hpp"
#include "odoloc/board/scenario_runner.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/kleeman_solver.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/sweep/error.hpp"
#include "odoloc/sweep/jobs.hpp"
#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/random.hpp"
#include "odoloc/world/scenarios.hpp"

namespace odoloc::sweep {
namespace {

namespace loc = sw::locate;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegree = std::numbers::pi / 180;

// ---------------------------------------------------------------- odometry

constexpr std::string_view kScenarios[] = {"straight", "both_rear", "one_rear", "front", "square"};
constexpr world::BumpCase kBumpCases[] = {world::BumpCase::kNone, world::BumpCase::kBothRear,
                                          world::BumpCase::kOneRear, world::BumpCase::kFront};
constexpr std::string_view kTunings[] = {"vehicle", "paper", "reset"};
constexpr board::MinSelectTuning kTuningValues[] = {board::MinSelectTuning::kVehicle,
                                                    board::MinSelectTuning::kPaper,
                                                    board::MinSelectTuning::kReset};

// The register map's names of the min-select policies, and its reset.
const std::vector<std::string_view>& policy_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> out;
    for (const regs::Enumerator& e : regs::odometry::cfg::policy.enums)
      out.push_back(e.name);
    return out;
  }();
  return names;
}
std::string_view reset_policy() {
  for (const regs::Enumerator& e : regs::odometry::cfg::policy.enums)
    if (e.value == regs::odometry::cfg::policy.reset)
      return e.name;
  throw std::logic_error("the register map has no name for the policy's reset");
}

const std::vector<ParameterInfo>& odometry_parameters() {
  static const std::vector<ParameterInfo> table = {
      {.name = "scenario",
       .meaning = "the drive: a straight run, with three bumps under both rear wheels, the left "
                  "rear wheel or the front wheel (world::bump_scenario), or the demo's 6 m square "
                  "with its bumps and front-wheel slip (world::default_square)",
       .choices = kScenarios,
       .default_choice = "straight"},
      {.name = "distance_m",
       .meaning = "length of the straight runs, metres (the square's path is fixed)",
       .min = 0.1,
       .max = 50,
       .default_number = 2},
      {.name = "bump_height_m",
       .meaning = "height of every bump, metres (0.3 m long); 0 removes them",
       .max = 0.05,
       .default_number = 0.025},
      {.name = "heading_deg",
       .meaning = "start heading, degrees counter-clockwise from +x",
       .min = -360,
       .max = 360},
      {.name = "heading_spread_deg",
       .meaning = "per trial, a uniform draw within +-spread/2 degrees added to heading_deg",
       .max = 360},
      {.name = "left_radius_error",
       .meaning = "left rear wheel: true radius over the nominal one the fabric assumes, minus 1",
       .min = -0.1,
       .max = 0.1},
      {.name = "right_radius_error",
       .meaning = "right rear wheel: true radius over the nominal one, minus 1",
       .min = -0.1,
       .max = 0.1},
      {.name = "front_radius_error",
       .meaning = "front wheel: true radius over the nominal one, minus 1",
       .min = -0.1,
       .max = 0.1},
      {.name = "radius_error_sd",
       .meaning = "per trial and wheel, a Gaussian radius error of this relative sd added to the "
                  "wheel's own",
       .max = 0.02},
      {.name = "policy",
       .meaning = "min-select policy (odometry.cfg.policy)",
       .choices = policy_names(),
       .default_choice = reset_policy()},
      {.name = "tuning",
       .meaning = "min-select memory and thresholds: for the vehicle, the paper's memoryless "
                  "rule, or the register resets",
       .choices = kTunings,
       .default_choice = "vehicle"},
  };
  return table;
}

constexpr MetricInfo kOdometryMetrics[] = {
    {"position_error_m", "final position error of the fabric's pose, metres"},
    {"heading_error_deg", "final heading error, fabric minus truth, degrees in (-180, 180]"},
    {"front_share", "share of the updates whose distance came from the front unit, 0..1"},
};

// --------------------------------------------------------------- beacons

constexpr std::string_view kLayouts[] = {"kleeman", "corners"};
// Kleeman's corner beacons (the mid-wall ones, 1 and 4, left out).
constexpr std::size_t kCornerBeacons[] = {0, 2, 3, 5};
constexpr std::string_view kSolvers[] = {"gauss_newton", "gauss_newton_c", "longsolve"};
// The temperature the solvers assume: distances are computed with its c.
constexpr double kAssumedTemperatureC = 20;
// The robot stands uniformly in the room, this far from the walls.
constexpr double kWallMarginM = 0.5;
// The cycle's unknown common offset, uniform in this range (metres).
constexpr double kOffsetLowM = -2;
constexpr double kOffsetHighM = 6;
// Fewest direct paths for range_scale_error (two fit any slope exactly).
constexpr std::size_t kMinScalePoints = 3;

const std::vector<ParameterInfo>& beacon_parameters() {
  static const std::vector<ParameterInfo> table = {
      {.name = "layout",
       .meaning = "the beacons: Kleeman's six (world::kleeman_beacons) or his four corner ones",
       .choices = kLayouts,
       .default_choice = "kleeman"},
      {.name = "solver",
       .meaning = "all-beacon Gauss-Newton, the same with the speed of sound as a state "
                  "(Kleeman's self-calibration), or Kleeman's longsolve",
       .choices = kSolvers,
       .default_choice = "gauss_newton"},
      {.name = "echo_probability",
       .meaning = "per beacon, the chance an obstacle hides its direct path, so that the first "
                  "wavefront heard is a wall echo (or nothing)",
       .max = 1},
      {.name = "reflection",
       .meaning = "pressure reflection coefficient of the four walls (0: no echoes)",
       .max = 0.99,
       .default_number = 0.9},
      {.name = "temperature_c",
       .meaning = "true air temperature, degrees Celsius; the solvers assume 20",
       .min = -40,
       .max = 60,
       .default_number = kAssumedTemperatureC},
      {.name = "chain_sd_m",
       .meaning = "the capture chain's residual timing error per wavefront, sd in metres of path",
       .max = 0.05,
       .default_number = 0.7e-3},
      {.name = "path_jitter_s",
       .meaning = "turbulence: sd of a delay per emission and path, seconds",
       .max = 1e-4,
       .default_number = 1.5e-6},
      {.name = "receiver_jitter_s",
       .meaning = "turbulence: sd of a delay per receiver, seconds",
       .max = 1e-4,
       .default_number = 1e-6},
  };
  return table;
}

constexpr MetricInfo kBeaconMetrics[] = {
    {"fix_valid", "1 when the solver gave a valid fix, else 0"},
    {"fix_error_m", "distance from the fix to the true position, metres (no value without a fix)"},
    {"beacons_used", "beacons the fix rests on (no value without a fix)"},
    {"range_scale_error",
     "least-squares slope of the direct-path distances against the true ranges, minus 1 "
     "(c_assumed / c_true - 1 without noise; no value with fewer than 3 direct paths)"},
};

// ------------------------------------------------------------------ trials

double number(const Settings& s, std::string_view key) {
  return std::get<double>(s.find(key)->second);
}
const std::string& choice(const Settings& s, std::string_view key) {
  return std::get<std::string>(s.find(key)->second);
}
template <class Names>
std::size_t index_of(const Names& names, std::string_view name) {
  return static_cast<std::size_t>(std::ranges::find(names, name) - std::begin(names));
}

std::vector<double> odometry_trial(const Settings& s, std::uint64_t seed) {
  world::Random draws(seed, 0);
  const double heading_deg =
      number(s, "heading_deg") + number(s, "heading_spread_deg") * (draws.uniform() - 0.5);
  const std::string& name = choice(s, "scenario");
  world::Scenario scenario = name == "square"
                                 ? world::default_square()
                                 : world::bump_scenario(kBumpCases[index_of(kScenarios, name)],
                                                        number(s, "distance_m"), 0.0);
  scenario.start.theta_rad = heading_deg * kDegree;
  const double height = number(s, "bump_height_m");
  if (height == 0)
    scenario.disturbances.bumps.clear();  // the tricycle takes no flat bump
  for (world::Bump& b : scenario.disturbances.bumps)
    b.height_m = height;
  const double sd = number(s, "radius_error_sd");
  world::Geometry& g = scenario.geometry;
  for (const auto& [wheel, key] :
       {std::pair{&g.left_rear, "left_radius_error"},
        std::pair{&g.right_rear, "right_radius_error"}, std::pair{&g.front, "front_radius_error"}})
    wheel->true_radius_m = wheel->nominal_radius_m * (1 + number(s, key) + sd * draws.normal());

  board::RunOptions options;
  options.policy = static_cast<rtl::MinSelectPolicy>(
      regs::odometry::cfg::policy.enums[index_of(policy_names(), choice(s, "policy"))].value);
  options.tuning = kTuningValues[index_of(kTunings, choice(s, "tuning"))];
  board::RunResult r;
  try {
    r = board::run_scenario(scenario, options);
  } catch (const std::invalid_argument& e) {
    throw SweepError(true, fmt::format("the tricycle refuses the scenario: {}", e.what()));
  }
  return {r.position_error_m, r.heading_error_rad / kDegree,
          static_cast<double>(r.front_wins_ds) / static_cast<double>(r.updates)};
}

// Least-squares slope of the direct paths' first candidates against their
// true ranges; NaN with fewer than kMinScalePoints of them.
double range_scale(const board::MeasuredCycle& m, const loc::BeaconLayout& layout,
                   loc::Vec2 truth) {
  if (m.direct.size() < kMinScalePoints)
    return kNaN;
  std::vector<double> range, distance;
  for (const int b : m.direct) {
    range.push_back(layout.range_m(static_cast<std::size_t>(b), truth));
    distance.push_back(m.ranges.beacons[static_cast<std::size_t>(b)].candidates[0].distance_m);
  }
  const auto n = static_cast<double>(range.size());
  double mean_r = 0, mean_d = 0;
  for (std::size_t i = 0; i < range.size(); ++i) {
    mean_r += range[i] / n;
    mean_d += distance[i] / n;
  }
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < range.size(); ++i) {
    sxy += (range[i] - mean_r) * (distance[i] - mean_d);
    sxx += (range[i] - mean_r) * (range[i] - mean_r);
  }
  return sxy / sxx;
}

std::vector<double> beacon_trial(const Settings& s, std::uint64_t seed) {
  world::AcousticWorld w = world::kleeman_world();
  if (choice(s, "layout") == "corners") {
    std::vector<world::Beacon> corners;
    for (const std::size_t b : kCornerBeacons)
      corners.push_back(w.beacons[b]);
    w.beacons = std::move(corners);
  }
  w.air.temperature_c = number(s, "temperature_c");
  w.room->reflection.fill(number(s, "reflection"));
  w.noise.path_jitter_sd_s = number(s, "path_jitter_s");
  w.noise.receiver_jitter_sd_s = number(s, "receiver_jitter_s");

  world::Random draws(seed, 0);
  const world::Pose pose{kWallMarginM + (w.room->width_m - 2 * kWallMarginM) * draws.uniform(),
                         kWallMarginM + (w.room->depth_m - 2 * kWallMarginM) * draws.uniform(),
                         std::numbers::pi * (2 * draws.uniform() - 1)};
  const double echo_probability = number(s, "echo_probability");
  const std::size_t beacons = w.beacons.size();
  for (std::size_t b = 0; b < beacons; ++b) {
    if (draws.uniform() < echo_probability)
      w.obstacles.push_back(world::direct_path_blocker(w, {pose.x_m, pose.y_m}, b));
  }
  const double offset = kOffsetLowM + (kOffsetHighM - kOffsetLowM) * draws.uniform();
  const double chain_sd = number(s, "chain_sd_m");
  const board::MeasuredCycle m = board::measure_kleeman_cycle(
      w, pose, loc::speed_of_sound_mps(kAssumedTemperatureC), offset, chain_sd, splitmix64(seed),
      [&] { return chain_sd * draws.normal(); });

  const loc::BeaconLayout layout = board::beacon_layout(w);
  const std::string& solver = choice(s, "solver");
  loc::Fix fix;
  if (solver == "longsolve") {
    fix = loc::Longsolve().solve(layout, m.ranges);
  } else {
    loc::MultilaterationOptions options;
    options.calibrate_speed_of_sound = solver == "gauss_newton_c";
    fix = loc::multilaterate(layout, m.ranges, options);
  }
  const loc::Vec2 truth{pose.x_m, pose.y_m};
  return {fix.valid ? 1.0 : 0.0,
          fix.valid ? std::hypot(fix.position_m.x - truth.x, fix.position_m.y - truth.y) : kNaN,
          fix.valid ? static_cast<double>(fix.used()) : kNaN, range_scale(m, layout, truth) - 1};
}

}  // namespace

std::string_view name(Experiment experiment) {
  return kExperimentNames[static_cast<std::size_t>(experiment)];
}

Value ParameterInfo::default_value() const {
  if (is_choice())
    return std::string{default_choice};
  return default_number;
}

std::span<const ParameterInfo> parameters(Experiment experiment) {
  return experiment == Experiment::kOdometry ? odometry_parameters() : beacon_parameters();
}

std::span<const MetricInfo> metrics(Experiment experiment) {
  if (experiment == Experiment::kOdometry)
    return kOdometryMetrics;
  return kBeaconMetrics;
}

const ParameterInfo* find_parameter(Experiment experiment, std::string_view name) {
  const std::span<const ParameterInfo> all = parameters(experiment);
  const auto it = std::ranges::find(all, name, &ParameterInfo::name);
  return it == all.end() ? nullptr : &*it;
}

std::vector<double> run_trial(Experiment experiment, const Settings& settings, std::uint64_t seed) {
  return experiment == Experiment::kOdometry ? odometry_trial(settings, seed)
                                             : beacon_trial(settings, seed);
}

}  // namespace odoloc::sweep
