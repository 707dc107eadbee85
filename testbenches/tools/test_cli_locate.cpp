// `odoloc locate` in process (docs/host-tool.md#beacon-fixes-locate): the
// layout and arrivals parsers with every message and its line, the options,
// the solvers on exact ranges computed in long double from known positions,
// the table, the JSON, the error ellipses and the gnuplot script. The real
// binary, the files and the picture: test_cli_e2e.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "beacon_geometry.hpp"
#include "odoloc/cli/app.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/locate.hpp"
#include "odoloc/cli/locate_input.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "usage_message.hpp"

namespace {

namespace cli = odoloc::cli;
namespace loc = odoloc::sw::locate;
using nlohmann::json;

using odoloc::tb::message_of;

constexpr const char* kFourBeacons =
    "beacons:\n"
    "  - {id: B0, x: 0, y: 0}\n"
    "  - {id: B1, x: 4, y: 0}\n"
    "  - {id: B2, x: 4, y: 3}\n"
    "  - {id: B3, x: 0, y: 3}\n";

cli::LocateLayout four_beacons() {
  return cli::parse_layout(kFourBeacons, "layout.yaml");
}

std::vector<cli::ArrivalCycle> arrivals(const std::string& csv) {
  return cli::parse_arrivals(csv, "arrivals.csv", four_beacons());
}

// ----------------------------------------------------------------- layout

TEST(LocateLayout, IdsPositionsHeightsAndTheAir) {
  const cli::LocateLayout l = cli::parse_layout(
      "# a comment\n"
      "speed_of_sound: 340.5\n"
      "temperature: 12.5\n"
      "beacons:\n"
      "  - {id: west, x: 0.05, y: 0.05, height: 1.2}\n"
      "  - x: 2.5\n"
      "    y: -1e-1\n"
      "  - {id: B-2.a_b, x: +4, y: 3, height: -0.5}\n",
      "layout.yaml");
  ASSERT_EQ(l.layout.beacons.size(), 3U);
  EXPECT_EQ(l.ids, (std::vector<std::string>{"west", "1", "B-2.a_b"}));  // default: the index
  EXPECT_DOUBLE_EQ(l.layout.beacons[0].position_m.x, 0.05);
  EXPECT_DOUBLE_EQ(l.layout.beacons[0].height_m, 1.2);
  EXPECT_DOUBLE_EQ(l.layout.beacons[1].position_m.y, -0.1);
  EXPECT_DOUBLE_EQ(l.layout.beacons[1].height_m, 0.0);
  EXPECT_DOUBLE_EQ(l.layout.beacons[2].position_m.x, 4.0);
  EXPECT_DOUBLE_EQ(l.layout.beacons[2].height_m, -0.5);
  EXPECT_DOUBLE_EQ(l.speed_of_sound_mps, 340.5);
  EXPECT_EQ(l.temperature_c, 12.5);
  EXPECT_EQ(l.find("1"), 1);
  EXPECT_EQ(l.find("B1"), std::nullopt);

  const cli::LocateLayout plain = four_beacons();
  EXPECT_DOUBLE_EQ(plain.speed_of_sound_mps, cli::kDefaultSpeedOfSoundMps);
  EXPECT_FALSE(plain.temperature_c);
}

TEST(LocateLayout, EveryMistakeNamesTheFileTheLineAndTheKey) {
  const std::string three = "  - {id: A, x: 0, y: 0}\n  - {id: B, x: 1, y: 0}\n";
  const struct {
    std::string yaml, message;
  } cases[] = {
      {"",
       "layout.yaml: a layout is a YAML mapping with 'beacons' (and optionally "
       "'speed_of_sound', 'temperature')"},
      {"beacons: [\n", "layout.yaml:2: YAML: end of sequence flow not found"},
      {"- 1\n- 2\n",
       "layout.yaml:1: a layout is a YAML mapping with 'beacons' (and optionally "
       "'speed_of_sound', 'temperature')"},
      {"temperature: 20\nbeacon:\n" + three,
       "layout.yaml:2: layout: unknown key 'beacon' (known: beacons, speed_of_sound, "
       "temperature)"},
      {"temperature: 20\ntemperature: 21\nbeacons:\n" + three,
       "layout.yaml:2: layout: 'temperature' given twice"},
      {"speed_of_sound: 343\n", "layout.yaml:1: layout: missing 'beacons'"},
      {"beacons: 5\n", "layout.yaml:1: layout: beacons must be a list"},
      {"beacons:\n" + three, "layout.yaml:2: layout: 2 beacons; a layout has 3 to 64"},
      {"speed_of_sound: 0\nbeacons:\n" + three,
       "layout.yaml:1: layout: speed_of_sound must be within 100..2000 m/s (air: 331.3 + 0.6 T)"},
      {"speed_of_sound: fast\nbeacons:\n" + three,
       "layout.yaml:1: layout: speed_of_sound must be a finite number, not 'fast'"},
      {"temperature: -273.15\nbeacons:\n" + three,
       "layout.yaml:1: layout: temperature must be within -100..100 degrees Celsius"},
      {"beacons:\n" + three + "  - 5\n",
       "layout.yaml:4: beacons[2]: expected a mapping of id, x, y, height"},
      {"beacons:\n" + three + "  - {id: C, x: 1, y: 1, hieght: 2}\n",
       "layout.yaml:4: beacons[2]: unknown key 'hieght' (known: id, x, y, height)"},
      {"beacons:\n" + three + "  - {id: C, x: 1, x: 2, y: 1}\n",
       "layout.yaml:4: beacons[2]: 'x' given twice"},
      {"beacons:\n" + three + "  - {id: C, x: 1}\n", "layout.yaml:4: beacon 'C': missing 'y'"},
      {"beacons:\n" + three + "  - {x: 1,\n     y: .nan}\n",
       "layout.yaml:5: beacon '2': y must be a finite number, not '.nan'"},
      {"beacons:\n" + three + "  - {id: C, x: .inf, y: 1}\n",
       "layout.yaml:4: beacon 'C': x must be a finite number, not '.inf'"},
      {"beacons:\n" + three + "  - {id: C, x: [1, 2], y: 1}\n",
       "layout.yaml:4: beacon 'C': x must be a finite number, not 'a list or mapping'"},
      {"beacons:\n" + three + "  - {id: C, x: 1, y: 1, height: 1m}\n",
       "layout.yaml:4: beacon 'C': height must be a finite number, not '1m'"},
      {"beacons:\n" + three + "  - {id: 'C 1', x: 1, y: 1}\n",
       "layout.yaml:4: beacons[2]: id 'C 1': ids are letters, digits, '_', '-' and '.'"},
      {"beacons:\n" + three + "  - {id: A, x: 1, y: 1}\n",
       "layout.yaml:4: beacon 'A' given twice (first on line 2)"},
      {"beacons:\n" + three + "  - {id: C, x: 1.0005, y: 0}\n",
       "layout.yaml:4: beacon 'C' is at the place of beacon 'B' (line 3): closer than 1 mm"},
      // A second document (yaml-cpp alone would read the first and drop it).
      {"beacons:\n" + three + "  - {id: C, x: 1, y: 1}\n---\nbeacons: []\n",
       "layout.yaml:5: YAML: a second document ('---' or '...')"},
      {"beacons:\n" + three + "  - {id: C, x: 1, y: 1}\n...\ntemperature: 40\n",
       "layout.yaml:6: YAML: a second document ('---' or '...')"},
      {"beacons:\n" + three + "  - {id: \"C\\x01\", x: 1, y: 1}\n",
       "layout.yaml:4: beacons[2]: id 'C\\x01': ids are letters, digits, '_', '-' and '.'"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.yaml);
    EXPECT_EQ(message_of([&] { (void)cli::parse_layout(c.yaml, "layout.yaml"); }), c.message);
  }
  std::string many = "beacons:\n";
  for (int i = 0; i < 65; ++i)
    many += fmt::format("  - {{x: {}, y: 0}}\n", i);
  EXPECT_EQ(message_of([&] { (void)cli::parse_layout(many, "layout.yaml"); }),
            "layout.yaml:2: layout: 65 beacons; a layout has 3 to 64");
}

// --------------------------------------------------------------- arrivals

TEST(LocateArrivals, CandidatesInOrderOfArrivalMissingAndFailedMeasurements) {
  const std::vector<cli::ArrivalCycle> cycles = arrivals(
      "\xEF\xBB\xBF# recorded on the bench\r\n"
      "cycle, beacon ,distance_m,sd_m\r\n"
      "\n"
      "7,B0,2.5,0.002\r\n"
      "7,B1,3.25,\n"
      "7,B1,4.0,nan\n"  // B1: two candidates, the echo second
      "7,B2,nan,0.001\n"
      "7,B3,,\n"
      "3,B0,+1.5,0\n"
      "# B1 missing in cycle 3\n"
      "3,B2,-0.25,1e-3\n");
  ASSERT_EQ(cycles.size(), 2U);
  EXPECT_EQ(cycles[0].cycle, 3U);  // ascending, whatever the file's order
  EXPECT_EQ(cycles[1].cycle, 7U);
  for (const cli::ArrivalCycle& c : cycles) {
    EXPECT_DOUBLE_EQ(c.ranges.speed_of_sound_mps, cli::kDefaultSpeedOfSoundMps);
    ASSERT_EQ(c.ranges.beacons.size(), 4U);  // every beacon of the layout
  }
  const auto& c3 = cycles[0].ranges.beacons;
  EXPECT_DOUBLE_EQ(c3[0].candidates.at(0).distance_m, 1.5);
  EXPECT_DOUBLE_EQ(c3[0].candidates.at(0).sd_m, 0.0);
  EXPECT_TRUE(c3[1].candidates.empty());
  EXPECT_EQ(c3[1].primary, -1);
  EXPECT_DOUBLE_EQ(c3[2].candidates.at(0).distance_m, -0.25);  // the offset may be negative
  const auto& c7 = cycles[1].ranges.beacons;
  EXPECT_EQ(c7[0].primary, 0);
  EXPECT_DOUBLE_EQ(c7[0].candidates.at(0).sd_m, 0.002);
  ASSERT_EQ(c7[1].candidates.size(), 2U);
  EXPECT_DOUBLE_EQ(c7[1].candidates[0].distance_m, 3.25);
  EXPECT_DOUBLE_EQ(c7[1].candidates[0].sd_m, cli::kDefaultSdM);  // empty: the default
  EXPECT_DOUBLE_EQ(c7[1].candidates[1].distance_m, 4.0);
  EXPECT_DOUBLE_EQ(c7[1].candidates[1].sd_m, cli::kDefaultSdM);  // nan: the default
  EXPECT_TRUE(std::isnan(c7[2].candidates.at(0).distance_m));    // nan: a failed measurement
  EXPECT_TRUE(std::isnan(c7[3].candidates.at(0).distance_m));    // empty: the same
  EXPECT_EQ(c7[3].primary, 0);
}

TEST(LocateArrivals, CandidateColumnAndTimes) {
  // The candidate column numbers them; the rows may come in any order.
  const std::vector<cli::ArrivalCycle> numbered = arrivals(
      "candidate,cycle,beacon,distance_m\n"
      "1,0,B0,3.0\n"
      "0,0,B1,2.0\n"
      "0,0,B0,2.5\n");
  ASSERT_EQ(numbered.size(), 1U);
  const auto& b0 = numbered[0].ranges.beacons[0].candidates;
  ASSERT_EQ(b0.size(), 2U);
  EXPECT_DOUBLE_EQ(b0[0].distance_m, 2.5);
  EXPECT_DOUBLE_EQ(b0[1].distance_m, 3.0);

  // Times become distances with the layout's speed of sound, deviations too.
  cli::LocateLayout layout = four_beacons();
  layout.speed_of_sound_mps = 340;
  const std::vector<cli::ArrivalCycle> timed = cli::parse_arrivals(
      "cycle,beacon,time_s,sd_s\n0,B0,0.01,1e-5\n0,B1,0.02,\n", "arrivals.csv", layout);
  const auto& t = timed.at(0).ranges;
  EXPECT_DOUBLE_EQ(t.speed_of_sound_mps, 340);
  EXPECT_DOUBLE_EQ(t.beacons[0].candidates.at(0).distance_m, 3.4);
  EXPECT_DOUBLE_EQ(t.beacons[0].candidates.at(0).sd_m, 340 * 1e-5);
  EXPECT_DOUBLE_EQ(t.beacons[1].candidates.at(0).distance_m, 6.8);
  EXPECT_DOUBLE_EQ(t.beacons[1].candidates.at(0).sd_m, cli::kDefaultSdM);
}

TEST(LocateArrivals, EveryMistakeNamesTheFileAndTheLine) {
  const std::string help =
      "the first line names the columns: cycle, beacon, distance_m or time_s, optionally sd_m "
      "(with distance_m) or sd_s (with time_s) and candidate";
  const std::string header = "cycle,beacon,distance_m,sd_m\n";
  const struct {
    std::string csv, message;
  } cases[] = {
      {"", "arrivals.csv: no header (" + help + ")"},
      {"# only a comment\n\n", "arrivals.csv: no header (" + help + ")"},
      {header, "arrivals.csv: no arrivals after the header"},
      {"0,B0,1.5\n", "arrivals.csv:1: unknown column '0' (" + help + ")"},
      {"# c\ncycle,beacon,distance,sd_m\n",
       "arrivals.csv:2: unknown column 'distance' (" + help + ")"},
      {"cycle,beacon,distance_m,time_s\n", "arrivals.csv:1: give distance_m or time_s, not both"},
      {"cycle,distance_m\n", "arrivals.csv:1: missing columns (" + help + ")"},
      {"cycle,beacon\n", "arrivals.csv:1: missing columns (" + help + ")"},
      {"cycle,beacon,distance_m,distance_m\n", "arrivals.csv:1: column 'distance_m' named twice"},
      {"cycle,beacon,distance_m,sd_s\n",
       "arrivals.csv:1: sd_s goes with time_s; with distance_m the deviation is sd_m"},
      {"cycle,beacon,time_s,sd_m\n",
       "arrivals.csv:1: sd_m goes with distance_m; with time_s the deviation is sd_s"},
      {header + "0,B0,1.5\n", "arrivals.csv:2: 3 fields; the header names 4"},
      {header + "0,B0,1.5,0.001,\n", "arrivals.csv:2: 5 fields; the header names 4"},
      {header + "0,B0,1.5,0.001\n-1,B0,1.5,0.001\n",
       "arrivals.csv:3: cycle '-1' is not a whole number from 0 to 2^64 - 1"},
      {header + "1.5,B0,1.5,0.001\n",
       "arrivals.csv:2: cycle '1.5' is not a whole number from 0 to 2^64 - 1"},
      {header + ",B0,1.5,0.001\n",
       "arrivals.csv:2: cycle '' is not a whole number from 0 to 2^64 - 1"},
      {header + "18446744073709551616,B0,1.5,0.001\n",
       "arrivals.csv:2: cycle '18446744073709551616' is not a whole number from 0 to 2^64 - 1"},
      {header + "0,B9,1.5,0.001\n",
       "arrivals.csv:2: unknown beacon 'B9' (the layout's: B0, B1, B2, B3)"},
      {header + "0,b0,1.5,0.001\n",
       "arrivals.csv:2: unknown beacon 'b0' (the layout's: B0, B1, B2, B3)"},
      {header + "0,B0,1.5m,0.001\n",
       "arrivals.csv:2: distance_m '1.5m' is not a number (empty or nan: no measurement)"},
      {header + "0,B0,inf,0.001\n",
       "arrivals.csv:2: distance_m 'inf' is not a number (empty or nan: no measurement)"},
      {"cycle,beacon,time_s\n0,B0,1e999\n",
       "arrivals.csv:2: time_s '1e999' is not a number (empty or nan: no measurement)"},
      {header + "0,B0,1.5,-0.001\n",
       "arrivals.csv:2: sd_m '-0.001' is not a deviation: a finite number >= 0 (empty or nan: "
       "the default, 0.001 m)"},
      {"cycle,beacon,time_s,sd_s\n0,B0,0.01,x\n",
       "arrivals.csv:2: sd_s 'x' is not a deviation: a finite number >= 0 (empty or nan: the "
       "default, 0.001 m)"},
      {"cycle,beacon,distance_m,candidate\n0,B0,1.5,0\n0,B0,1.7,first\n",
       "arrivals.csv:3: candidate 'first' is not a whole number from 0 to 2^64 - 1"},
      {"cycle,beacon,distance_m,candidate\n0,B0,1.5,0\n0,B1,1.5,0\n0,B0,1.7,0\n",
       "arrivals.csv:4: candidate 0 of beacon 'B0' in cycle 0 given twice (first on line 2)"},
      {"cycle,beacon,distance_m,candidate\n0,B0,1.5,0\n0,B0,1.7,2\n",
       "arrivals.csv:3: candidate 2 of beacon 'B0' in cycle 0 without a candidate 1"},
      {header + "0,B0,2,0.001\n0,B0,2,0.001\n",
       "arrivals.csv:3: candidate 1 of beacon 'B0' in cycle 0 (2 m) arrives with candidate 0 "
       "(line 2): one wavefront given twice?"},
      {"cycle,beacon,time_s,sd_s\n0,B0,1e307,1e-6\n",
       "arrivals.csv:2: time_s '1e307' is out of range (its distance overflows)"},
      {"cycle,beacon,time_s,sd_s\n0,B0,0.01,1e307\n",
       "arrivals.csv:2: sd_s '1e307' is out of range (it overflows in metres)"},
      {"cycle,beacon,distance_m,candidate\n4,B2,1.7,1\n",
       "arrivals.csv:2: candidate 1 of beacon 'B2' in cycle 4 without a candidate 0"},
      {header + "0,B0,2,0.001\n0,B0,nan,0.001\n0,B0,1.5,0.001\n",
       "arrivals.csv:4: candidate 2 of beacon 'B0' in cycle 0 (1.5 m) arrives before candidate 0 "
       "(2 m, line 2): candidates are in order of arrival"},
      {header + "0,B\x1b[31m,1.5,0.001\n",
       "arrivals.csv:2: unknown beacon 'B\\x1b[31m' (the layout's: B0, B1, B2, B3)"},
      {header + "0,B0," + std::string(60, '9') + "x,0.001\n",
       "arrivals.csv:2: distance_m '" + std::string(40, '9') +
           "...' is not a number (empty or nan: no measurement)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.csv);
    EXPECT_EQ(message_of([&] { (void)arrivals(c.csv); }), c.message);
  }
}

TEST(LocateArrivals, FilesThatCannotBeReadAreUsageErrors) {
  EXPECT_EQ(message_of([] { (void)cli::load_layout("/nonexistent/layout.yaml"); }),
            "cannot open layout /nonexistent/layout.yaml: No such file or directory");
  const std::string dir = ::testing::TempDir();
  EXPECT_EQ(message_of([&] { (void)cli::load_arrivals(dir, four_beacons()); }),
            fmt::format("cannot read arrivals {}: it is a directory", dir));
}

// ---------------------------------------------------------------- options

TEST(LocateOptions, EachIsCheckedAloneAndTogether) {
  EXPECT_EQ(cli::parse_solver("gauss-newton"), cli::LocateSolver::kGaussNewton);
  EXPECT_EQ(cli::parse_solver("longsolve"), cli::LocateSolver::kLongsolve);
  EXPECT_EQ(cli::parse_solver("kleeman"), cli::LocateSolver::kKleeman);
  EXPECT_EQ(message_of([] { (void)cli::parse_solver("gauss_newton"); }),
            "--solver: unknown solver 'gauss_newton' (gauss-newton, longsolve or kleeman)");
  EXPECT_DOUBLE_EQ(cli::parse_temperature("-5.5"), -5.5);
  EXPECT_DOUBLE_EQ(cli::parse_temperature("100"), 100);  // the limits are inclusive
  EXPECT_DOUBLE_EQ(cli::parse_temperature("-100"), -100);
  for (const char* bad : {"-273.15", "100.5", "1e6", "warm", "nan", "20C"})
    EXPECT_EQ(message_of([&] { (void)cli::parse_temperature(bad); }),
              fmt::format("--temperature: '{}' is not a temperature within -100..100 degrees "
                          "Celsius",
                          bad));
  EXPECT_EQ(cli::parse_triple("B0,B2,B4"), (std::vector<std::string>{"B0", "B2", "B4"}));
  for (const char* bad : {"B0,B2", "B0,B2,B0", "B0,,B2", "B0,B1,B2,B3"})
    EXPECT_EQ(message_of([&] { (void)cli::parse_triple(bad); }),
              fmt::format("--triple: '{}' is not three different beacon ids, ID,ID,ID", bad));

  cli::LocateCommand c;
  EXPECT_NO_THROW(cli::check_locate(c));
  c.calibrate_c = true;
  c.solver = cli::LocateSolver::kLongsolve;
  EXPECT_EQ(message_of([&] { cli::check_locate(c); }),
            "--calibrate-c needs --solver gauss-newton (Kleeman's solvers assume c)");
  c = {};
  c.triple = {"B0", "B1", "B2"};
  EXPECT_EQ(message_of([&] { cli::check_locate(c); }), "--triple goes with --solver kleeman");
  c.solver = cli::LocateSolver::kKleeman;
  EXPECT_NO_THROW(cli::check_locate(c));
  c.plot = "fixes.pdf";
  EXPECT_EQ(message_of([&] { cli::check_locate(c); }),
            "--plot: 'fixes.pdf' does not end in .png or .svg (the extension picks the format)");
  c.plot = "out/fixes.svg";
  EXPECT_NO_THROW(cli::check_locate(c));
}

// ------------------------------------------------------------------ fixes

// Kleeman's six beacons in a 5 m x 4 m room, ids B0..B5.
cli::LocateLayout room(double height_m = 0.8) {
  cli::LocateLayout l;
  l.layout = odoloc::tb::kleeman_layout(5, 4, 0.05, height_m);
  for (std::size_t i = 0; i < l.layout.beacons.size(); ++i)
    l.ids.push_back(fmt::format("B{}", i));
  return l;
}

const std::vector<loc::Vec2> kPath = {{1.0, 1.0}, {1.6, 1.3}, {2.2, 1.7}, {2.9, 2.2}, {3.6, 2.6}};

// Exact ranges along kPath, each cycle with its own offset; `scale` is
// c_used / c_true.
std::vector<cli::ArrivalCycle> exact_cycles(const cli::LocateLayout& l, long double scale = 1) {
  std::vector<cli::ArrivalCycle> cycles;
  for (std::size_t i = 0; i < kPath.size(); ++i)
    cycles.push_back({10 + i, odoloc::tb::exact_range_set(l.layout, kPath[i],
                                                          0.3 + 0.05 * static_cast<double>(i), 1e-3,
                                                          nullptr, scale)});
  return cycles;
}

void expect_on_path(const std::vector<cli::CycleFix>& fixes, loc::Solver solver, double tol) {
  ASSERT_EQ(fixes.size(), kPath.size());
  for (std::size_t i = 0; i < kPath.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(fixes[i].cycle, 10 + i);
    EXPECT_EQ(fixes[i].fix.solver, solver);
    ASSERT_TRUE(fixes[i].fix.valid) << loc::name(fixes[i].fix.reason);
    EXPECT_NEAR(fixes[i].fix.position_m.x, kPath[i].x, tol);
    EXPECT_NEAR(fixes[i].fix.position_m.y, kPath[i].y, tol);
  }
}

TEST(LocateFixes, EverySolverFindsThePathFromExactRanges) {
  const cli::LocateLayout l = room();
  const std::vector<cli::ArrivalCycle> cycles = exact_cycles(l);
  cli::LocateCommand c;
  expect_on_path(cli::locate_fixes(l, cycles, c), loc::Solver::kGaussNewton, 1e-9);
  c.solver = cli::LocateSolver::kLongsolve;
  expect_on_path(cli::locate_fixes(l, cycles, c), loc::Solver::kLongsolve, 1e-6);
  c.solver = cli::LocateSolver::kKleeman;
  expect_on_path(cli::locate_fixes(l, cycles, c), loc::Solver::kKleemanTriple, 1e-6);
  c.triple = {"B0", "B2", "B4"};
  const std::vector<cli::CycleFix> triple = cli::locate_fixes(l, cycles, c);
  expect_on_path(triple, loc::Solver::kKleemanTriple, 1e-6);
  for (const cli::CycleFix& f : triple) {
    EXPECT_EQ(f.fix.used(), 3);
    EXPECT_EQ(f.fix.beacons[1].status, loc::BeaconStatus::kUnused);
  }
  c.triple = {"B0", "B9", "B4"};
  EXPECT_EQ(message_of([&] { (void)cli::locate_fixes(l, cycles, c); }),
            "--triple: unknown beacon 'B9' (the layout's: B0, B1, B2, B3, B4, B5)");
}

// Distances computed with 343.2 m/s in air at 5 C: the temperature (the
// command's over the layout's) corrects every solver.
TEST(LocateFixes, TheTemperatureRescalesTheDistances) {
  cli::LocateLayout l = room();
  const double c_true = loc::speed_of_sound_mps(5);
  const std::vector<cli::ArrivalCycle> cycles =
      exact_cycles(l, static_cast<long double>(l.speed_of_sound_mps) / c_true);
  cli::LocateCommand c;
  const std::vector<cli::CycleFix> uncorrected = cli::locate_fixes(l, cycles, c);
  EXPECT_GT(std::hypot(uncorrected[0].fix.position_m.x - kPath[0].x,
                       uncorrected[0].fix.position_m.y - kPath[0].y),
            1e-3);
  l.temperature_c = 5;
  for (const cli::LocateSolver s : {cli::LocateSolver::kGaussNewton, cli::LocateSolver::kLongsolve,
                                    cli::LocateSolver::kKleeman}) {
    c.solver = s;
    const std::vector<cli::CycleFix> fixes = cli::locate_fixes(l, cycles, c);
    expect_on_path(fixes, fixes.front().fix.solver, 1e-6);
    EXPECT_NEAR(fixes.front().fix.speed_of_sound_mps, c_true, 1e-9);
    // The offset in the file's units whatever the solver (Kleeman's solve
    // rescaled distances): exact_cycles' 0.3 m + 0.05 m per cycle.
    for (std::size_t i = 0; i < fixes.size(); ++i)
      EXPECT_NEAR(fixes[i].fix.offset_m, 0.3 + 0.05 * static_cast<double>(i), 1e-6)
          << loc::name(fixes[i].fix.solver);
  }
  l.temperature_c = 30;
  c.temperature_c = 5;
  c.solver = cli::LocateSolver::kGaussNewton;
  expect_on_path(cli::locate_fixes(l, cycles, c), loc::Solver::kGaussNewton, 1e-6);
  // Estimated instead (five or more beacons): the prior on c (half the 3 %
  // tolerance around the assumed 343.2 m/s) pulls it a little.
  l.temperature_c.reset();
  c.temperature_c.reset();
  c.calibrate_c = true;
  const std::vector<cli::CycleFix> calibrated = cli::locate_fixes(l, cycles, c);
  expect_on_path(calibrated, loc::Solver::kGaussNewton, 1e-4);
  EXPECT_NEAR(calibrated.front().fix.speed_of_sound_mps, c_true, 0.1);
  EXPECT_GT(calibrated.front().fix.speed_of_sound_sd_mps, 0);
}

TEST(LocateFixes, TooFewBeaconsIsAFixWithItsReason) {
  const cli::LocateLayout l = room();
  std::vector<cli::ArrivalCycle> cycles = exact_cycles(l);
  for (std::size_t b = 2; b < 6; ++b)
    cycles[0].ranges.beacons[b] = {};  // no candidates: missing
  cycles[0].ranges.beacons[2].candidates = {{loc::kNaN, 1e-3, {}}};
  cycles[0].ranges.beacons[2].primary = 0;
  for (const cli::LocateSolver s : {cli::LocateSolver::kGaussNewton, cli::LocateSolver::kLongsolve,
                                    cli::LocateSolver::kKleeman}) {
    cli::LocateCommand c;
    c.solver = s;
    const std::vector<cli::CycleFix> fixes = cli::locate_fixes(l, cycles, c);
    ASSERT_EQ(fixes.size(), kPath.size());
    const loc::Fix& f = fixes[0].fix;
    EXPECT_FALSE(f.valid);
    EXPECT_EQ(f.beacons.at(2).status, loc::BeaconStatus::kNonFinite);
    EXPECT_EQ(f.beacons.at(3).status, loc::BeaconStatus::kMissing);
    EXPECT_TRUE(fixes[1].fix.valid);  // the next cycle is not held up
  }
}

// ----------------------------------------------------------------- output

cli::CycleFix sample_fix() {
  cli::CycleFix f{42, {}};
  f.fix.valid = true;
  f.fix.reason = loc::NoFixReason::kNone;
  f.fix.position_m = {1.25, 2.5};
  f.fix.covariance_m2 << 4e-6, -1e-6, -1e-6, 1e-6;
  f.fix.hdop = 1.5;
  f.fix.offset_m = 0.3;
  f.fix.speed_of_sound_mps = 343.2;
  f.fix.iterations = 4;
  f.fix.beacons = {{0, loc::BeaconStatus::kUsed, 0, 1e-4, -1},
                   {1, loc::BeaconStatus::kUsed, 1, -2e-4, -1},
                   {2, loc::BeaconStatus::kOutlier, -1, 0.8, -1},
                   {3, loc::BeaconStatus::kMissing, -1, loc::kNaN, -1},
                   {4, loc::BeaconStatus::kTriangleInequality, -1, loc::kNaN, 0},
                   {5, loc::BeaconStatus::kUsed, 0, 0, -1}};
  return f;
}

TEST(LocateOutput, TheTableHasOneLinePerCycleAndEveryBeaconsFate) {
  const cli::LocateLayout l = room();
  cli::CycleFix none{43, {}};
  none.fix.beacons = {{0, loc::BeaconStatus::kUsed, 0, loc::kNaN, -1}};
  const std::vector<cli::CycleFix> fixes = {sample_fix(), none};
  const std::string table = cli::fix_table(fixes, l);
  std::istringstream lines(table);
  std::string header, first, second, extra;
  std::getline(lines, header);
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_FALSE(std::getline(lines, extra));
  EXPECT_EQ(header,
            "cycle  solver          valid  reason                    x_m       y_m   sd_x_m   "
            "sd_y_m    corr   hdop  offset_m   c_mps  iter  beacons");
  EXPECT_EQ(first,
            "   42  gauss_newton    yes    none                   1.2500    2.5000  0.00200  "
            "0.00100  -0.500   1.50    0.3000   343.2     4  used:B0,B1[1],B5 missing:B3 "
            "triangle_inequality:B4(B0) outlier:B2");
  EXPECT_EQ(second,
            "   43  gauss_newton    no     too_few_beacons             -         -        -        "
            "-       -      -         -       -     0  used:B0");
}

TEST(LocateOutput, JsonCarriesTheWholeFixWithNullForNoValue) {
  const cli::LocateLayout l = room();
  const json j = json::parse(cli::fix_json(sample_fix(), l).dump());
  EXPECT_EQ(j["cycle"], 42);
  EXPECT_EQ(j["solver"], "gauss_newton");
  EXPECT_EQ(j["valid"], true);
  EXPECT_EQ(j["reason"], "none");
  EXPECT_EQ(j["x_m"], 1.25);
  EXPECT_EQ(j["covariance_m2"], json::parse("[[4e-6,-1e-6],[-1e-6,1e-6]]"));
  EXPECT_DOUBLE_EQ(j["sd_x_m"].get<double>(), 2e-3);
  EXPECT_DOUBLE_EQ(j["corr"].get<double>(), -0.5);
  EXPECT_EQ(j["used"], 3);
  EXPECT_TRUE(j["offset_sd_m"].is_null());  // NaN
  EXPECT_TRUE(j["chi2"].is_null());
  EXPECT_TRUE(j["mirror_m"].is_null());
  ASSERT_EQ(j["beacons"].size(), 6U);
  EXPECT_EQ(j["beacons"][1], json::parse(R"({"id":"B1","beacon":1,"status":"used","candidate":1,
                                              "residual_m":-2e-4,"rejected_by":null})"));
  EXPECT_EQ(j["beacons"][4]["rejected_by"], "B0");
  EXPECT_TRUE(j["beacons"][3]["residual_m"].is_null());

  cli::CycleFix mirrored = sample_fix();
  mirrored.fix.mirror_m = loc::Vec2{3, 1};
  EXPECT_EQ(cli::fix_json(mirrored, l)["mirror_m"], json::parse(R"({"x_m":3.0,"y_m":1.0})"));
}

TEST(LocateOutput, ErrorEllipsesFromTheEigenDecomposition) {
  // sd 3 mm along 30 degrees, 1 mm across.
  const double a = std::numbers::pi / 6;
  Eigen::Matrix2d r;
  r << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  const Eigen::Matrix2d cov = r * Eigen::Vector2d(9e-6, 1e-6).asDiagonal() * r.transpose();
  const cli::ErrorEllipse e = cli::error_ellipse(cov, 2);
  EXPECT_NEAR(e.major_m, 6e-3, 1e-12);
  EXPECT_NEAR(e.minor_m, 2e-3, 1e-12);
  EXPECT_NEAR(e.angle_rad, a, 1e-9);
  // The axis is folded into (-pi/2, pi/2]; a circle has no preferred one.
  const cli::ErrorEllipse steep =
      cli::error_ellipse(r.transpose() * Eigen::Vector2d(9e-6, 1e-6).asDiagonal() * r, 1);
  EXPECT_NEAR(steep.angle_rad, -a, 1e-9);
  const cli::ErrorEllipse round = cli::error_ellipse(Eigen::Matrix2d::Identity() * 4e-6, 1);
  EXPECT_NEAR(round.major_m, 2e-3, 1e-12);
  EXPECT_NEAR(round.minor_m, 2e-3, 1e-12);
}

TEST(LocateOutput, ThePlotScriptPicksTheTerminalAndMagnifiesTheEllipses) {
  const cli::LocateLayout l = room();
  const std::vector<cli::CycleFix> fixes = {sample_fix()};
  const std::string png = cli::plot_script(fixes, l, "it's.png");
  EXPECT_NE(png.find("set terminal pngcairo noenhanced size 1000,800"), std::string::npos) << png;
  // The output, a gnuplot string constant: the default of `picture`.
  EXPECT_NE(png.find("if (!exists(\"picture\")) picture = 'it''s.png'\nset output picture\n"),
            std::string::npos)
      << png;
  EXPECT_NE(png.find("\"B5\""), std::string::npos) << png;
  // 2 sigma of the major axis is 4.5 mm: magnified 100x in a 5 m room.
  EXPECT_NE(png.find("title '2-sigma error ellipses, magnified 100x'"), std::string::npos) << png;
  EXPECT_NE(png.find("with ellipses"), std::string::npos) << png;
  EXPECT_NE(png.find("1 fixes of 1 cycles"), std::string::npos) << png;
  const std::string svg = cli::plot_script({}, l, "fixes.svg");
  EXPECT_NE(svg.find("set terminal svg noenhanced size 1000,800"), std::string::npos) << svg;
  EXPECT_EQ(svg.find("with ellipses"), std::string::npos) << svg;  // no fix, no ellipses
}

// ------------------------------------------------------------- the command

TEST(LocateRun, RunsFromFilesWithoutATarget) {
  const std::string dir = ::testing::TempDir();
  const std::string layout = dir + "locate_layout.yaml";
  const std::string csv = dir + "locate_arrivals.csv";
  std::ofstream(layout) << kFourBeacons;
  std::ofstream(csv) << "cycle,beacon,distance_m\n"
                     << fmt::format("0,B0,{}\n0,B1,{}\n0,B2,{}\n0,B3,{}\n1,B0,1\n",
                                    std::hypot(1.0, 1.0), std::hypot(3.0, 1.0),
                                    std::hypot(3.0, 2.0), std::hypot(1.0, 2.0));
  const cli::TargetOpener no_target =
      [](std::string_view, const cli::TargetOptions&) -> std::unique_ptr<cli::Target> {
    throw std::logic_error("locate opened a target");
  };
  std::istringstream in;
  std::ostringstream out, err;
  const std::vector<std::string> args = {"locate", "--layout", layout, "--arrivals", csv, "--json"};
  EXPECT_EQ(cli::run_cli(args, {in, out, err}, no_target), cli::kExitOk) << err.str();
  std::istringstream lines(out.str());
  std::vector<json> docs;
  for (std::string line; std::getline(lines, line);)
    docs.push_back(json::parse(line));
  ASSERT_EQ(docs.size(), 2U);
  EXPECT_EQ(docs[0]["valid"], true);
  EXPECT_NEAR(docs[0]["x_m"].get<double>(), 1, 1e-9);
  EXPECT_NEAR(docs[0]["y_m"].get<double>(), 1, 1e-9);
  EXPECT_EQ(docs[1]["valid"], false);
  EXPECT_EQ(docs[1]["reason"], "too_few_beacons");

  std::ostringstream out2, err2;
  const std::vector<std::string> bad = {"locate", "--layout", layout, "--arrivals", layout};
  EXPECT_EQ(cli::run_cli(bad, {in, out2, err2}, no_target), cli::kExitUsage);
  EXPECT_EQ(err2.str(), fmt::format("odoloc: {}:1: unknown column 'beacons:' ({})\n", layout,
                                    "the first line names the columns: cycle, beacon, distance_m "
                                    "or time_s, optionally sd_m (with distance_m) or sd_s (with "
                                    "time_s) and candidate"));
  std::ostringstream out3, err3;
  const std::vector<std::string> missing = {"locate", "--layout", layout};
  EXPECT_EQ(cli::run_cli(missing, {in, out3, err3}, no_target), cli::kExitUsage);
  EXPECT_NE(err3.str().find("--arrivals is required"), std::string::npos) << err3.str();
  // Board options given with locate are a mistake, not a silent no-op.
  for (const std::vector<std::string>& global : {std::vector<std::string>{"-t", "spidev:/dev/nope"},
                                                 {"--crc"},
                                                 {"--vcd", "v.vcd"},
                                                 {"--vcd-pins", "p.vcd"}}) {
    std::vector<std::string> with = global;
    with.insert(with.end(), args.begin(), args.end());
    std::ostringstream out4, err4;
    EXPECT_EQ(cli::run_cli(with, {in, out4, err4}, no_target), cli::kExitUsage) << global[0];
    EXPECT_EQ(err4.str(), fmt::format("odoloc: {} does not apply to locate: it reads files and "
                                      "opens no target\n",
                                      global[0] == "-t" ? "--target" : global[0]));
  }
  // The JSON says whether c was estimated.
  EXPECT_EQ(docs[0]["speed_of_sound_estimated"], false);
}

}  // namespace
