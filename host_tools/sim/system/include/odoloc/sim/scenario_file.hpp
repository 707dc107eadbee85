// Scenario files (docs/scenarios.md): the world of `odoloc sim` described
// in YAML, field by field: the room and its obstacles, the air, the noise,
// Kleeman's beacons, Liu's base station, the robot and its receivers, the
// path, the disturbances, and the survey (what the SoC software is told:
// the facts a real robot is given, never the truth). The main job's room
// tour is examples/scenarios/room-tour.yaml, built in (default_scenario).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/sw/liu_filter.hpp"
#include "odoloc/world/room_tour.hpp"
#include "odoloc/yaml/reader.hpp"

namespace odoloc::sim {

// Liu's base station as surveyed and calibrated.
struct SurveyedStation {
  world::Vec2 position;
  double t0_s = 0;                     // trigger to sound
  double station_laser_start_rad = 0;  // the lasers' encoder indices
  double robot_laser_start_rad = 0;
  double max_range_m = 15;  // bursts are listened for this far (Liu: 35 m outdoors)
};

// Thamma's stations and the robot's boxes as surveyed and calibrated.
struct SurveyedThamma {
  std::vector<world::Vec2> stations;  // in firing order, world frame
  double delay_s = 100e-6;            // t: trigger to sound plus the receivers' delay
  world::Vec2 head, tail;             // the boxes' centres, body frame
};

// The start mark as surveyed: the robot is placed on it (path.start) within
// these deviations, and the filter starts there (Liu's X(0|0), P(0|0)).
struct SurveyedStart {
  double sd_m = 0;  // per axis
  double heading_sd_rad = 0;
};

// What the SoC software is told about the world: surveyed positions, the
// calibrated transmitters and turbulence, a thermometer's temperature, and
// its own settings where a paper fixes them (Liu's filter).
struct Survey {
  std::vector<world::Vec2> beacons;  // Kleeman's, in firing order, world frame (m)
  double beacon_height_m = 0;        // above the receivers' plane
  double temperature_c = 20;         // the speed of sound follows it (world::Air)
  double envelope_tau_s = 0.5e-3;    // the transmitters' envelope time constant
  double path_jitter_s = 0;          // turbulence as calibrated: per path and per receiver
  double receiver_jitter_s = 0;
  std::optional<SurveyedStation> station;
  // Set: the filter starts on the start mark (required without beacons).
  std::optional<SurveyedStart> start;
  std::optional<SurveyedThamma> thamma;
  // Set: Liu et al.'s own filter runs beside the EKF (scenario key liu_filter).
  std::optional<sw::fuse::LiuFilterOptions> liu_filter;
};

// A stationary experiment (Kleeman's: the robot standing at surveyed
// points, the ultrasonic fixes' spread): instead of driving a path, the
// robot stands at each point in turn until it has that many fixes.
struct StandingPoint {
  world::Vec2 position;
  std::size_t fixes = 0;
  std::optional<world::Vec2> paper_sd_m;  // the paper's standard deviations in x and y
};
struct StandingGrid {
  double step_m = 1;    // points this far apart over the room's floor
  double margin_m = 1;  // from the walls
  std::size_t fixes = 3;
  std::optional<double> paper_worst_m;  // the paper's bound on every point's error
};
struct Stationary {
  std::vector<StandingPoint> points;
  std::optional<StandingGrid> grid;
};
// The grid's points: step_m apart, margin_m from the walls, row by row
// from (margin, margin).
[[nodiscard]] std::vector<world::Vec2> grid_points(const world::Room& room,
                                                   const StandingGrid& grid);

struct Scenario {
  world::RoomTour tour;  // the truth: what the world simulates
  Survey survey;         // what the SoC software is configured from
  std::uint64_t seed = 1;
  // Set: the scenario stands at points (tour.drive has no path; each
  // point's run sets its start and stands, sim::stand_at).
  std::optional<Stationary> stationary;
};

// Command-line changes to a file's path (`odoloc sim --laps --speed`).
struct ScenarioOverrides {
  std::optional<std::size_t> laps{};  // the path's laps (a path with laps)
  std::optional<double> speed_mps{};  // a square path's speed
};

// The scenario in `text`, named `file` in every error. The files it names
// (path.trajectory.file) are read from `directory`, the scenario file's own;
// without one (a built-in text, the fuzzer's) naming a file is an error.
// Throws yaml::InputError ("FILE:LINE: what") for YAML that is not a
// scenario: an unknown or repeated key, a missing one, a value that is not
// a finite number or is out of its range, a beacon or the start outside the
// room, fewer than 3 beacons, neither beacons nor a station, a survey whose
// beacons do not match, no survey.start without beacons, liu_filter without
// a station, an override the path does not have; and ("CSV:LINE: what")
// for a trajectory file the tricycle cannot drive.
[[nodiscard]] Scenario parse_scenario(const std::string& text, std::string_view file,
                                      const ScenarioOverrides& overrides = {},
                                      const std::optional<std::filesystem::path>& directory = {});
// The file at `path` (InputError also when it cannot be read); its
// directory is the scenario's.
[[nodiscard]] Scenario load_scenario(const std::filesystem::path& path,
                                     const ScenarioOverrides& overrides = {});
// The scenario files of examples/scenarios/, built into the program
// (cmake/EmbedFiles.cmake), keyed by their file names ("room-tour.yaml").
struct BuiltinScenario {
  std::string_view key;
  std::string_view text;
};
[[nodiscard]] std::span<const BuiltinScenario> builtin_scenarios();
// The built-in file `key`; nullptr for none.
[[nodiscard]] const BuiltinScenario* find_builtin_scenario(std::string_view key);
// room-tour.yaml: the main job.
inline constexpr std::string_view kDefaultScenario = "room-tour.yaml";
[[nodiscard]] Scenario default_scenario(const ScenarioOverrides& overrides = {});

}  // namespace odoloc::sim
