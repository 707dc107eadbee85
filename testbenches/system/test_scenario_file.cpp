// Scenario files (odoloc/sim/scenario_file.hpp, docs/scenarios.md): the
// built-in room tour, overrides, and every mistake an error with the file
// and the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "odoloc/sim/scenario_file.hpp"

namespace {

using odoloc::sim::parse_scenario;
using odoloc::sim::Scenario;
using odoloc::yaml::InputError;

std::string room_tour_text() {
  return std::string(odoloc::sim::find_builtin_scenario(odoloc::sim::kDefaultScenario)->text);
}

// The text with the first `from` replaced by `to` (which must be there).
std::string edited(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos)
    text.replace(at, from.size(), to);
  return text;
}

// The message parse_scenario throws for `text` ("" when it parses).
std::string error_of(const std::string& text, const odoloc::sim::ScenarioOverrides& o = {}) {
  try {
    static_cast<void>(parse_scenario(text, "my.yaml", o));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The 1-based line of the first occurrence of `needle` in the text.
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

TEST(ScenarioFile, TheRoomTourIsKleemansRoomWithLiusStation) {
  const Scenario s = odoloc::sim::default_scenario();
  EXPECT_EQ(s.tour.name, "2 laps of the 6 m square in Kleeman's room");
  EXPECT_EQ(s.seed, 1U);
  EXPECT_EQ(s.tour.timing.beacon_count, 6U);
  ASSERT_EQ(s.tour.acoustics.beacons.size(), 7U);  // and the station's transmitter
  EXPECT_EQ(s.tour.timing.reserved_slots, 1U);
  ASSERT_TRUE(s.tour.station.has_value());
  EXPECT_EQ(s.tour.station->transmitter, 6U);
  EXPECT_EQ(s.tour.acoustics.receivers.size(), 8U);
  EXPECT_DOUBLE_EQ(s.tour.timing.fire_s(), 0.150);
  // Per lap: both rear wheels (two bumps), the right rear and the front.
  EXPECT_EQ(s.tour.drive.disturbances.bumps.size(), 8U);
  EXPECT_EQ(s.tour.drive.disturbances.slips.size(), 2U);
  // A perfect survey: the SoC is told where the beacons stand.
  ASSERT_EQ(s.survey.beacons.size(), 6U);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(s.survey.beacons[i].x_m, s.tour.acoustics.beacons[i].position.x_m);
    EXPECT_EQ(s.survey.beacons[i].y_m, s.tour.acoustics.beacons[i].position.y_m);
  }
  EXPECT_DOUBLE_EQ(s.tour.drive.geometry.left_rear.true_radius_m, 0.05 * 1.002);
}

// d(duration)/d(1/speed) is the lap's length: 4 (side - 2 r) + 2 pi r with
// the turn radius r = L / tan(steer); the steering stops do not depend on
// the speed. One lap more adds one lap's time.
TEST(ScenarioFile, LapsAndSpeedOverridesChangeThePathAsItsGeometrySays) {
  const double r = 0.50 / std::tan(30 * std::numbers::pi / 180);
  const double lap_m = 4 * (6 - 2 * r) + 2 * std::numbers::pi * r;
  const double slow = odoloc::sim::default_scenario({.laps = 1, .speed_mps = 0.5}).tour.duration_s;
  const double fast = odoloc::sim::default_scenario({.laps = 1, .speed_mps = 1.0}).tour.duration_s;
  EXPECT_NEAR(slow - fast, lap_m * (1 / 0.5 - 1 / 1.0), 1e-9);
  const Scenario three = odoloc::sim::default_scenario({.laps = 3});
  EXPECT_NEAR(three.tour.duration_s - odoloc::sim::default_scenario().tour.duration_s, slow - 6.0,
              1e-9);  // a lap at 0.5 m/s, without the two 3 s waits
  EXPECT_EQ(three.tour.name, "3 laps of the 6 m square in Kleeman's room");
  EXPECT_EQ(three.tour.drive.disturbances.bumps.size(), 12U);
  // Lap 2's slip starts two lap lengths on from lap 0's.
  EXPECT_NEAR(three.tour.drive.disturbances.slips[2].start_m - 19.0, 2 * lap_m, 1e-9);
}

TEST(ScenarioFile, AMovedBeaconMovesInTheWorldAndNotInTheSurvey) {
  const std::string text =
      edited(room_tour_text(), "{position: [9.95, 9.95]", "{position: [9.5, 9.0]");
  const Scenario s = parse_scenario(text, "moved.yaml");
  EXPECT_EQ(s.tour.acoustics.beacons[3].position.x_m, 9.5);
  EXPECT_EQ(s.tour.acoustics.beacons[3].position.y_m, 9.0);
  EXPECT_EQ(s.survey.beacons[3].x_m, 9.95);  // the SoC still believes the survey
}

TEST(ScenarioFile, ASegmentPathLastsItsDistancesAndDurations) {
  std::string text = room_tour_text();
  text = edited(text, "  laps: 2\n  square: {side_m: 6, speed_mps: 0.5, steer_deg: 30}\n",
                "  segments:\n    - {speed_mps: 0.4, distance_m: 2}\n"
                "    - {speed_mps: -0.2, duration_s: 1.5}\n");
  text = edited(text, "  each_lap: true\n", "");
  const Scenario s = parse_scenario(text, "line.yaml");
  EXPECT_NEAR(s.tour.duration_s, 3 + 2 / 0.4 + 1.5 + 3, 1e-12);
  EXPECT_EQ(s.tour.name, "the 6 m square in Kleeman's room");
  const std::string laps = error_of(text, {.laps = 2});
  EXPECT_TRUE(laps.starts_with("my.yaml:" + std::to_string(line_of(text, "  start: {x_m: 2")) +
                               ": --laps: this scenario's path has no laps"))
      << laps;
}

TEST(ScenarioFile, KleemansStationaryPointsAndGrid) {
  const odoloc::sim::BuiltinScenario* file =
      odoloc::sim::find_builtin_scenario("kleeman-stationary.yaml");
  ASSERT_NE(file, nullptr);
  const Scenario s = parse_scenario(std::string(file->text), file->key);
  ASSERT_TRUE(s.stationary.has_value());
  const odoloc::sim::Stationary& st = *s.stationary;
  ASSERT_EQ(st.points.size(), 3U);
  EXPECT_EQ(st.points[1].position.x_m, 4.003);
  EXPECT_EQ(st.points[1].fixes, 1684U);  // the paper's sample counts
  ASSERT_TRUE(st.points[2].paper_sd_m.has_value());
  EXPECT_DOUBLE_EQ(st.points[2].paper_sd_m->x_m, 0.0085);
  EXPECT_FALSE(s.tour.station.has_value());
  EXPECT_DOUBLE_EQ(s.tour.timing.cycle_s(), 0.9);  // six beacons, no reserved slot
  ASSERT_TRUE(st.grid.has_value());
  // 1 m apart, 1 m from the walls of the 10 m room: 9 x 9 points.
  const std::vector<odoloc::world::Vec2> grid =
      odoloc::sim::grid_points(*s.tour.acoustics.room, *st.grid);
  ASSERT_EQ(grid.size(), 81U);
  EXPECT_EQ(grid.front().x_m, 1.0);
  EXPECT_EQ(grid.back().y_m, 9.0);
  // A stationary scenario has no path, and a point stands inside the room.
  const std::string text(file->text);
  EXPECT_NE(error_of(text + "path: {start: {x_m: 1, y_m: 1}, segments: [{duration_s: 1}]}\n")
                .find("a path or stationary points, not both"),
            std::string::npos);
  EXPECT_NE(error_of(edited(text, "[7.339, 5.885]", "[7.339, 10.5]"))
                .find("stationary point (7.339, 10.5) m is outside the room"),
            std::string::npos);
  EXPECT_NE(
      error_of(edited(text, "fixes: 532", "fixes: 1")).find("point.fixes: '1' is not a whole"),
      std::string::npos);
}

struct Mistake {
  const char* from;
  const char* to;
  const char* message;  // part of the error
  const char* at;       // the line the error names: the first line holding this (a
                        // mapping's or list's line is its first entry's)
};

TEST(ScenarioFile, EveryMistakeNamesTheFileAndTheLine) {
  const Mistake mistakes[] = {
      {"seed: 1\n", "seed: 1\nsede: 2\n", "unknown key 'sede'", "sede: 2"},
      {"seed: 1\n", "seed: 1\nseed: 2\n", "'seed' given twice", "seed: 2"},
      {"  width_m: 10\n", "  width_m: nan\n", "must be a finite number, not 'nan'", "width_m: nan"},
      {"  depth_m: 10\n", "  depth_m: 1e999\n", "must be a finite number", "depth_m: 1e999"},
      {"{position: [5.0, 9.95], axes_deg", "{position: [5.0, 10.5], axes_deg",
       "beacon 4 at (5, 10.5) m is outside the 10 x 10 m room", "[5.0, 10.5]"},
      {"    - [0.05, 9.95]\n", "", "survey.beacons: 5 positions for 6 beacons",
       "    - [0.05, 0.05]\n"},
      {"{wheel: right_rear, at_m", "{wheel: rear_right, at_m", "unknown wheel 'rear_right'",
       "rear_right"},
      {"reflection: [0.9, 0.9, 0.9, 0.9]", "reflection: [0.9, 0.9, 1.5, 0.9]",
       "each coefficient is in [0, 1]", "reflection"},
      {"  start: {x_m: 2, y_m: 2", "  start: {x_m: 12, y_m: 2", "path.start (12, 2) m is outside",
       "x_m: 12"},
      {"from_m: 19.0, to_m: 20.0", "from_m: 19.0, to_m: 18.0", "to_m must be beyond from_m",
       "to_m: 18.0"},
      {"  fire_s: 0.150\n", "  fire_s: [0.150]\n", "must be a finite number, not 'a list",
       "fire_s: ["},
      {"    station_laser_start_deg: -80\n", "", "missing 'station_laser_start_deg'",
       "    position: [0.3, 5.0]\n    t0_s"},
      // What the world refuses, at the section that asked for it.
      {"steer_deg: 30}", "steer_deg: 2}", "square_path: the turn radius exceeds half the side",
       "side_m: 6"},
      {"  receivers:\n    octagon", "  steering: {limit_deg: 20}\n  receivers:\n    octagon",
       "segment steers beyond the limit", "  start: {x_m: 2"},
      {"height_m: 0.025, length_m: 0.30}\n    - {wheel: right_rear",
       "height_m: 0.2, length_m: 0.05}\n    - {wheel: right_rear", "bump too sharp for the wheel",
       "  each_lap: true"},
      {"  fire_s: 0.150\n", "  fire_s: 0.150\n  pulse_s: 0.1\n", "the pulses do not fit in a slot",
       "  height_m: 0\n  fire_s"},
      // yaml-cpp names the line where it found the list unclosed.
      {"name: the 6 m square", "name: [the 6 m square", "YAML:", "seed: 1"},
  };
  const std::string base = room_tour_text();
  for (const Mistake& m : mistakes) {
    const std::string text = edited(base, m.from, m.to);
    const std::string error = error_of(text);
    EXPECT_NE(error.find(m.message), std::string::npos) << m.message << "\ngot: " << error;
    const std::string place = "my.yaml:" + std::to_string(line_of(text, m.at)) + ":";
    EXPECT_TRUE(error.starts_with(place)) << place << "\ngot: " << error;
  }
  EXPECT_NE(error_of(base + "---\nname: again\n").find("a second document"), std::string::npos);
  EXPECT_NE(error_of("[1, 2]").find("a scenario is a YAML mapping"), std::string::npos);
  EXPECT_NE(error_of(base, {.laps = 0}).find("--laps must be 1 to 100"), std::string::npos);
  EXPECT_NE(error_of(base, {.speed_mps = 2.0}).find("--speed must be in (0, 1.5]"),
            std::string::npos);
}

std::string lawn_text() {
  return std::string(odoloc::sim::find_builtin_scenario("liu-lawn.yaml")->text);
}

// Liu's lawn: no beacons (the station's timer alone: one slot), no walls,
// the start mark and the paper's filter settings in SI units.
TEST(ScenarioFile, LiusLawnHasTheStationAloneAndThePapersFilter) {
  const Scenario s = parse_scenario(lawn_text(), "liu-lawn.yaml");
  EXPECT_EQ(s.tour.timing.beacon_count, 0U);
  EXPECT_EQ(s.tour.timing.reserved_slots, 1U);
  ASSERT_EQ(s.tour.acoustics.beacons.size(), 1U);  // the station's transmitter
  EXPECT_FALSE(s.tour.acoustics.room.has_value());
  ASSERT_TRUE(s.tour.station.has_value());
  EXPECT_EQ(s.tour.station->transmitter, 0U);
  EXPECT_TRUE(s.survey.beacons.empty());
  ASSERT_TRUE(s.survey.start.has_value());
  EXPECT_DOUBLE_EQ(s.survey.start->sd_m, 0.0316);
  ASSERT_TRUE(s.survey.station.has_value());
  EXPECT_DOUBLE_EQ(s.survey.station->max_range_m, 35);
  ASSERT_TRUE(s.survey.liu_filter.has_value());
  const odoloc::sw::fuse::LiuFilterOptions paper;
  EXPECT_NEAR(s.survey.liu_filter->process_var_m2, paper.process_var_m2, 1e-18);
  EXPECT_NEAR(s.survey.liu_filter->fix_var_m2, 1e-3, 1e-18);
  EXPECT_NEAR(s.survey.liu_filter->fix_gate_m, 0.15, 1e-15);
  EXPECT_NEAR(s.survey.liu_filter->heading_gate_rad, paper.heading_gate_rad, 1e-15);
  EXPECT_NEAR(s.survey.liu_filter->laser_heading_var_rad2, paper.laser_heading_var_rad2, 1e-18);
  EXPECT_EQ(s.tour.drive.start.y_m, 1.2);  // Liu's X(0|0) = (0, 1200) mm
  // Two laps with a stop at the start between them: three 3 s waits.
  const auto waits = std::ranges::count_if(s.tour.drive.path.segments, [](const auto& seg) {
    return seg.speed_mps == 0 && seg.end == odoloc::world::Segment::End::kDuration &&
           seg.amount == 3.0;
  });
  EXPECT_EQ(waits, 3);
}

TEST(ScenarioFile, LawnMistakesNameTheFileAndTheLine) {
  const Mistake mistakes[] = {
      {"  start: {sd_m: 0.0316, heading_sd_deg: 1}\n", "",
       "survey: missing 'start' (without beacons", "  temperature_c: 20\n  envelope"},
      {"  fix_gate_mm: 150\n", "  fix_gate_mm: 0\n", "fix_gate_mm", "fix_gate_mm: 0"},
      {"liu_filter:\n", "liu_filters:\n", "unknown key 'liu_filters'", "liu_filters:"},
      {"    max_range_m: 35\n", "    max_range_m: nan\n", "must be a finite number",
       "max_range_m: nan"},
  };
  const std::string base = lawn_text();
  for (const Mistake& m : mistakes) {
    const std::string text = edited(base, m.from, m.to);
    const std::string error = error_of(text);
    EXPECT_NE(error.find(m.message), std::string::npos) << m.message << "\ngot: " << error;
    const std::string place = "my.yaml:" + std::to_string(line_of(text, m.at)) + ":";
    EXPECT_TRUE(error.starts_with(place)) << place << "\ngot: " << error;
  }
  // Without its station the lawn has nothing to localise with; Kleeman's
  // stationary room has no station for Liu's filter; the room tour has one.
  const std::string no_station =
      base.substr(0, base.find("station:\n  position")) + base.substr(base.find("robot:\n"));
  EXPECT_NE(error_of(no_station).find("no 'beacons', 'station' or 'thamma'"), std::string::npos)
      << error_of(no_station);
  const std::string kleeman(odoloc::sim::find_builtin_scenario("kleeman-stationary.yaml")->text);
  EXPECT_NE(error_of(kleeman + "liu_filter: {}\n").find("Liu's filter needs the 'station'"),
            std::string::npos);
  EXPECT_EQ(error_of(room_tour_text() + "liu_filter: {}\n"), "");
}

std::string thamma_text() {
  return std::string(odoloc::sim::find_builtin_scenario("thamma-room.yaml")->text);
}

// Thamma's room: four stations in firing order (two 40 kHz, two 32.5 kHz),
// the head and tail boxes (eight receivers), no beacons and no base station.
TEST(ScenarioFile, ThammasRoomHasItsStationsAndBoxes) {
  const Scenario s = parse_scenario(thamma_text(), "thamma-room.yaml");
  ASSERT_TRUE(s.tour.thamma.has_value());
  EXPECT_EQ(s.tour.timing.beacon_count, 0U);
  EXPECT_FALSE(s.tour.station.has_value());
  ASSERT_EQ(s.tour.acoustics.beacons.size(), 4U);
  EXPECT_EQ(s.tour.acoustics.beacons[0].carrier_hz, 40e3);
  EXPECT_EQ(s.tour.acoustics.beacons[3].carrier_hz, 32.5e3);
  EXPECT_EQ(s.tour.acoustics.receivers.size(), 8U);
  EXPECT_EQ(s.tour.acoustics.receivers[4].resonance_hz, 32.5e3);  // the tail box
  EXPECT_DOUBLE_EQ(s.tour.thamma->timing.cycle_s(4), 1.7);
  ASSERT_TRUE(s.survey.thamma.has_value());
  EXPECT_EQ(s.survey.thamma->stations.size(), 4U);
  EXPECT_DOUBLE_EQ(s.survey.thamma->head.x_m, 0.6);
}

TEST(ScenarioFile, ThammaMistakesNameTheFileAndTheLine) {
  const Mistake mistakes[] = {
      {"  cycle_gap_s: 0.1\n", "  cycle_gap_s: 0.01\n", "cycle_gap_s must be at least half",
       "  repeats: 4"},
      {"    stations: [[0.05, 0.05], [9.95, 0.05], [0.05, 9.95], [9.95, 9.95]]",
       "    stations: [[0.05, 0.05], [9.95, 0.05], [0.05, 9.95]]",
       "survey.thamma.stations: 3 positions for 4 stations", "    stations: [[0.05"},
      {"    boxes: {head: [0.6, 0], tail: [-0.2, 0]}",
       "    boxes: {head: [0.6, 0], tail: [-0.2, 0]}\n    octagon: {side_m: 0.05}",
       "one of octagon, list or boxes", "    boxes:"},
      {"    - {position: [9.95, 9.95], axes_deg", "    - {position: [10.95, 9.95], axes_deg",
       "station 3 at (10.95, 9.95) m is outside", "[10.95, 9.95]"},
  };
  const std::string base = thamma_text();
  for (const Mistake& m : mistakes) {
    const std::string text = edited(base, m.from, m.to);
    const std::string error = error_of(text);
    EXPECT_NE(error.find(m.message), std::string::npos) << m.message << "\ngot: " << error;
    const std::string place = "my.yaml:" + std::to_string(line_of(text, m.at)) + ":";
    EXPECT_TRUE(error.starts_with(place)) << place << "\ngot: " << error;
  }
  // Thamma's stations and Kleeman's beacons share neither the receivers
  // nor the sync input.
  std::string tour = room_tour_text();
  const std::string thamma_section = base.substr(
      base.find("thamma:\n  repeats"), base.find("robot:\n") - base.find("thamma:\n  repeats"));
  EXPECT_NE(error_of(tour + thamma_section).find("Thamma's stations exclude"), std::string::npos);
}

// Random byte edits of the room tour: each parses or is an InputError,
// nothing else (no crash, no other exception, no hang).
TEST(ScenarioFile, EditedFilesParseOrFailCleanly) {
  const std::string base = room_tour_text();
  std::mt19937_64 rng(29);
  const std::string alphabet = "0123456789-.:,[]{}#'\" \nabez_";
  int failed = 0;
  for (int i = 0; i < 400; ++i) {
    std::string text = base;
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0:
          text.erase(at, 1 + rng() % 8);
          break;
        case 1:
          text.insert(at, 1, alphabet[rng() % alphabet.size()]);
          break;
        default:
          text[at] = alphabet[rng() % alphabet.size()];
      }
    }
    try {
      static_cast<void>(parse_scenario(text, "edited.yaml"));
    } catch (const InputError& e) {
      ++failed;
      EXPECT_TRUE(std::string(e.what()).starts_with("edited.yaml")) << e.what();
    }
  }
  EXPECT_GT(failed, 100);  // the edits do break files
}

}  // namespace
