// A scenario's path from a recorded trajectory CSV (path.trajectory,
// docs/scenarios.md): the tricycle drives a recorded line and circle back to
// their closed-form ends, every mistake in the CSV names its file and line,
// the shipped figure eight loads and is driven back within its measured
// departure, and a text without a directory cannot name a file.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "odoloc/sim/scenario_file.hpp"
#include "odoloc/world/tricycle.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::sim::Scenario;
using odoloc::world::Pose;
using odoloc::yaml::InputError;

constexpr long double kPi = std::numbers::pi_v<long double>;
constexpr long double kDeg = kPi / 180;

// The room tour with its path replaced by `path` and without its bumps.
std::string scenario_with(const std::string& path) {
  const std::string tour(odoloc::sim::find_builtin_scenario(odoloc::sim::kDefaultScenario)->text);
  return tour.substr(0, tour.find("path:\n")) + path + "\n" +
         tour.substr(tour.find("# What the SoC software is told"));
}

const char* const kTrajectoryPath = "path:\n  trajectory: {file: drive.csv}\n";

// Rear-midpoint poses (heading in radians) at times, written as the CSV.
struct Recorded {
  long double t, x, y, theta;
};
std::string csv_of(const std::vector<Recorded>& samples) {
  std::string text = "time_s,x_m,y_m,heading_deg\n";
  for (const Recorded& s : samples)
    text += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g}\n", static_cast<double>(s.t),
                        static_cast<double>(s.x), static_cast<double>(s.y),
                        static_cast<double>(s.theta / kDeg));
  return text;
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The scenario file in `dir` with the CSV beside it, loaded.
Scenario load(const fs::path& dir, const std::string& csv,
              const std::string& path = kTrajectoryPath) {
  write(dir / "drive.csv", csv);
  write(dir / "scenario.yaml", scenario_with(path));
  return odoloc::sim::load_scenario(dir / "scenario.yaml");
}

std::string error_of(const fs::path& dir, const std::string& csv,
                     const std::string& path = kTrajectoryPath) {
  try {
    static_cast<void>(load(dir, csv, path));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The scenario's drive to its end; the steering rate is the path's. A
// 5 MHz clock with 50 clocks a step keeps the scenario's 10 us step (the
// truth does not depend on the clock) at a tenth of the ticks, and stays
// below one steering edge a clock at 3600 degrees/s.
odoloc::world::TricycleSimulator driven(const odoloc::world::Scenario& drive,
                                        std::uint32_t record_every_steps = 0) {
  odoloc::world::Options options;
  options.start = drive.start;
  options.clock_hz = 5e6;
  options.clocks_per_step = 50;
  options.record_every_steps = record_every_steps;
  odoloc::world::TricycleSimulator truth(drive.geometry, drive.path, {}, options);
  while (!truth.done())
    truth.tick();
  return truth;
}

double wrapped(double rad) {
  return std::remainder(rad, 2 * std::numbers::pi);
}

// A straight line has no steering: the converted segments are driven
// exactly, so the end is the closed form's to the simulator's rounding
// (docs/tricycle-simulator.md: 1e-9 m). Each line drives 1 m, stands 1 s
// and drives 1 m more, at 20 Hz; -0.4 m/s drives it backwards.
TEST(TrajectoryFile, ARecordedLineEndsWhereItsClosedFormDoes) {
  const fs::path dir = odoloc::tb::fresh_dir("trajectory", "line");
  for (const long double speed : {0.5L, -0.4L}) {
    for (const long double heading_deg : {0.0L, 30.0L, 90.0L, 135.0L, -120.0L}) {
      const long double theta = heading_deg * kDeg, x0 = 5, y0 = 4, dt = 0.05L;
      const int moving = static_cast<int>(std::lround(1 / std::fabs(speed) / dt));
      std::vector<Recorded> samples;
      long double s = 0;  // signed distance along the heading
      for (int k = 0; k <= 2 * moving + 20; ++k) {
        samples.push_back({k * dt, x0 + s * std::cos(theta), y0 + s * std::sin(theta), theta});
        if (k < moving || k >= moving + 20)
          s += speed * dt;
      }
      const Scenario scenario = load(dir, csv_of(samples));
      const Pose start = scenario.tour.drive.start;  // the first sample
      EXPECT_NEAR(start.x_m, 5, 1e-15);
      EXPECT_NEAR(start.theta_rad, static_cast<double>(theta), 1e-15);
      EXPECT_NEAR(scenario.tour.duration_s, static_cast<double>(samples.back().t), 1e-12);
      const odoloc::world::TruePose end = driven(scenario.tour.drive).pose();
      const long double sign = speed > 0 ? 1 : -1;
      SCOPED_TRACE(fmt::format("speed {} heading {}", static_cast<double>(speed),
                               static_cast<double>(heading_deg)));
      EXPECT_NEAR(end.pose.x_m, static_cast<double>(x0 + sign * 2 * std::cos(theta)), 1e-9);
      EXPECT_NEAR(end.pose.y_m, static_cast<double>(y0 + sign * 2 * std::sin(theta)), 1e-9);
      EXPECT_NEAR(end.pose.theta_rad, static_cast<double>(theta), 1e-12);
      EXPECT_NEAR(end.distance_m, 2, 1e-9);
      EXPECT_EQ(end.steer_rad, 0);
    }
  }
  fs::remove_all(dir);
}

// A circle of radius R at speed v (signed curvature k = +-1/R, v < 0 in
// reverse): theta = theta0 + k v t, p = p0 + (sin theta - sin theta0,
// cos theta0 - cos theta) / k. Its converted segments all steer
// phi = atan(L k); the tricycle starts straight and reaches phi at the rate
// w after tau = |phi| / w, having turned less than the recording by
//   delta = (v / L) sgn(phi) (tau tan|phi| - ln(sec phi) / w),
// (the integral of tan phi - tan(w t) over the ramp). From then on it turns
// as the recording does, so it ends delta behind the recorded heading, and
// its position is off by at most |delta| (|v| tau + 2R): the heading lags by
// at most delta over the ramp's |v| tau metres, and what follows is the
// recording's arc turned by delta, whose chord is at most 2R. A pause
// halfway or at the end changes nothing (the steering stays), and
// standing for longer than tau first takes the lag away (the steering
// turns while standing).
TEST(TrajectoryFile, ARecordedCircleEndsBehindItsClosedFormByTheSteeringLag) {
  const fs::path dir = odoloc::tb::fresh_dir("trajectory", "circle");
  const long double wheelbase = 0.5L, radius = 1.5L, dt = 0.1L;
  struct Case {
    long double speed, curvature, rate_degps;
    int pause = 0;  // sample intervals standing halfway and at the end
    int first = 0;  // sample intervals standing first
  };
  for (const Case c : {Case{0.5L, 1 / radius, 57.3L}, Case{0.5L, -1 / radius, 57.3L},
                       Case{-0.4L, 1 / radius, 57.3L}, Case{0.5L, 1 / radius, 3600},
                       Case{0.5L, -1 / radius, 57.3L, 10}, Case{0.5L, 1 / radius, 57.3L, 0, 2},
                       Case{-0.4L, -1 / radius, 57.3L, 10, 10}}) {
    const long double theta0 = 0.3L, x0 = 5, y0 = 5;
    const int intervals =
        static_cast<int>(std::lround(300 * kDeg * radius / std::fabs(c.speed) / dt));
    std::vector<Recorded> samples;
    for (int k = 0; k < c.first; ++k)
      samples.push_back({k * dt, x0, y0, theta0});
    for (int k = 0; k <= intervals; ++k) {
      const long double theta = theta0 + c.curvature * c.speed * k * dt;
      const Recorded r{k * dt, x0 + (std::sin(theta) - std::sin(theta0)) / c.curvature,
                       y0 + (std::cos(theta0) - std::cos(theta)) / c.curvature, theta};
      const int stand = k == intervals / 2 || k == intervals ? c.pause : 0;
      const long double at = r.t + (c.first + (k > intervals / 2 ? c.pause : 0)) * dt;
      for (int p = 0; p <= stand; ++p)
        samples.push_back({at + p * dt, r.x, r.y, r.theta});
    }
    const Scenario scenario =
        load(dir, csv_of(samples),
             fmt::format("path:\n  steer_rate_degps: {}\n  trajectory: {{file: drive.csv}}\n",
                         static_cast<double>(c.rate_degps)));
    const long double phi = std::atan(wheelbase * c.curvature);
    const long double rate = c.rate_degps * kDeg;
    // The ramp while driving: what standing first leaves of it.
    const long double tau = std::max(0.0L, std::fabs(phi) / rate - c.first * dt);
    const long double ramp_start = std::fabs(phi) - tau * rate;
    const long double delta =
        c.speed / wheelbase * (phi > 0 ? 1 : -1) *
        (tau * std::tan(std::fabs(phi)) - std::log(std::cos(ramp_start) / std::cos(phi)) / rate);
    const odoloc::world::TruePose end = driven(scenario.tour.drive).pose();
    const Recorded& last = samples.back();
    SCOPED_TRACE(fmt::format("speed {} curvature {} rate {} pause {} first {}",
                             static_cast<double>(c.speed), static_cast<double>(c.curvature),
                             static_cast<double>(c.rate_degps), c.pause, c.first));
    EXPECT_NEAR(end.steer_rad, static_cast<double>(phi), 1e-12);
    EXPECT_NEAR(end.pose.theta_rad, static_cast<double>(last.theta - delta), 1e-9);
    const double off = std::hypot(end.pose.x_m - static_cast<double>(last.x),
                                  end.pose.y_m - static_cast<double>(last.y));
    const long double bound = std::fabs(delta) * (std::fabs(c.speed) * tau + 2 * radius);
    EXPECT_LE(off, static_cast<double>(bound) + 1e-9) << "delta " << static_cast<double>(delta);
    // The lag is there: the end is off by about |delta| times the chord
    // from the ramp's end to the end, R at 300 degrees round.
    EXPECT_GE(off, static_cast<double>(std::fabs(delta) * radius) * 0.5);
    if (tau == 0) {
      EXPECT_LT(off, 1e-9);  // no lag at all
    }
  }
  fs::remove_all(dir);
}

struct CsvMistake {
  std::string csv;
  const char* message;  // part of the error
  int line;             // the CSV line it names
};

// The 1-based line of the first occurrence of `needle` in the text.
int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

// Every mistake in the CSV is an error "CSV:LINE: what", the CSV named by
// its path from the scenario's directory.
TEST(TrajectoryFile, EveryMistakeNamesTheCsvAndItsLine) {
  const fs::path dir = odoloc::tb::fresh_dir("trajectory", "mistakes");
  const std::string start = "time_s,x_m,y_m,heading_deg\n0,5,5,0\n0.1,5.05,5,0\n";
  // 0.02 m along a circle of 0.3 m in 0.04 s: steering atan(0.5 / 0.3).
  const double turn = 0.02 / 0.3;
  const std::string tight =
      fmt::format("0.14,{:.17g},{:.17g},{:.17g}\n", 5.05 + 0.3 * std::sin(turn),
                  5 + 0.3 * (1 - std::cos(turn)), turn * 180 / std::numbers::pi);
  const CsvMistake mistakes[] = {
      {start, "", 0},  // the base parses
      {"", "an empty file: a trajectory starts with the header", 1},
      {"\n\n", "an empty file", 1},
      {"time_s,x_m,y_m\n0,5,5\n", "the header is 'time_s,x_m,y_m,heading_deg'", 1},
      {"time_s,x_m,y_m,heading_deg,speed_mps\n0,5,5,0,0\n", "these columns, no others", 1},
      {"time,x,y,heading\n", "not 'time,x,y,heading'", 1},
      {"time_s,x_m,y_m,heading_deg\n", "0 samples: a trajectory needs two at least", 1},
      {"time_s,x_m,y_m,heading_deg\n0,5,5,0\n", "1 sample: a trajectory needs two", 2},
      {start + "0.2,5.1,5\n", "3 values; the header names 4", 4},
      {start + "\n0.2,5.1,5,0,1\n", "5 values", 5},
      {start + "0.2,nan,5,0\n", "x_m must be a finite number, not 'nan'", 4},
      {start + "0.2,5.1,inf,0\n", "y_m must be a finite number, not 'inf'", 4},
      {start + "0.2,5.1,5,1e999\n", "heading_deg must be a finite number", 4},
      {start + "0.2s,5.1,5,0\n", "time_s must be a finite number, not '0.2s'", 4},
      {start + "0.1,5.1,5,0\n", "time_s 0.1 is not after the previous sample's 0.1 (line 3)", 4},
      {start + "0.05,5.1,5,0\n", "time_s 0.05 is not after", 4},
      {start + "0.2,5.21,5,0\n", "1.600 m/s since line 3: faster than 1.5 m/s", 4},
      {start + "0.2,5.1,5.002,0\n",
       "2.0 mm sideways to the heading since line 3: a tricycle cannot slide", 4},
      {start + "0.2,5.05,5,5\n", "turns 5.000 degrees on the spot since line 3", 4},
      {start + tight,
       "the turn since line 3 needs 59.04 degrees of steering, beyond robot.steering.limit_deg "
       "40.00",
       4},
      {"time_s,x_m,y_m,heading_deg\n0,9.9,5,0\n0.1,9.95,5,0\n0.2,10.05,5,0\n",
       "(10.05, 5) m is outside the 10 x 10 m room", 4},
  };
  const std::string csv = (dir / "drive.csv").string();
  for (const CsvMistake& m : mistakes) {
    const std::string error = error_of(dir, m.csv);
    SCOPED_TRACE(m.csv);
    if (m.line == 0) {
      EXPECT_EQ(error, "");
      continue;
    }
    EXPECT_NE(error.find(m.message), std::string::npos) << m.message << "\ngot: " << error;
    const std::string place = fmt::format("{}:{}: ", csv, m.line);
    EXPECT_TRUE(error.starts_with(place)) << place << "\ngot: " << error;
  }
  fs::remove_all(dir);
}

// path.start, when given, is the first sample's to 1 mm and 0.1 degree (an
// error at the scenario's line otherwise); a file that is not there is the
// scenario's error, at the line of `file`; a path is one kind.
TEST(TrajectoryFile, TheStartAndTheFileAreTheScenariosErrors) {
  const fs::path dir = odoloc::tb::fresh_dir("trajectory", "start");
  const std::string yaml = (dir / "scenario.yaml").string();
  const std::string csv = "time_s,x_m,y_m,heading_deg\n0,5,5,10\n0.1,5.05,5.0088,10\n";
  const auto path_with = [](const std::string& start, const std::string& file) {
    return fmt::format("path:\n  start: {}\n  trajectory: {{file: {}}}\n", start, file);
  };
  // Within the tolerance: the robot is set down on the first sample.
  const Scenario near =
      load(dir, csv, path_with("{x_m: 5.0007, y_m: 5, heading_deg: 10.09}", "drive.csv"));
  EXPECT_EQ(near.tour.drive.start.x_m, 5);
  EXPECT_NEAR(near.tour.drive.start.theta_rad, 10 * std::numbers::pi / 180, 1e-15);
  const std::string far_path = path_with("{x_m: 5.002, y_m: 5, heading_deg: 10}", "drive.csv");
  const std::string far = error_of(dir, csv, far_path);
  EXPECT_TRUE(far.starts_with(fmt::format(
      "{}:{}: path.start (5.002, 5) m, 10 deg is not the trajectory's first sample (5, 5) m, 10 "
      "deg ({}:2) within 1 mm and 0.1 degree",
      yaml, line_of(scenario_with(far_path), "  start: {x_m: 5.002"),
      (dir / "drive.csv").string())))
      << far;
  EXPECT_NE(error_of(dir, csv, path_with("{x_m: 5, y_m: 5, heading_deg: 10.2}", "drive.csv"))
                .find("is not the trajectory's first sample"),
            std::string::npos);
  for (const auto& [name, message] :
       {std::pair<std::string, std::string>{"nowhere.csv", "no such file '"},
        {".", "' is not a regular file"},
        {"''", "path.trajectory.file: expected a file name"}}) {
    const std::string path = path_with("{x_m: 5, y_m: 5, heading_deg: 10}", name);
    const std::string error = error_of(dir, csv, path);
    EXPECT_TRUE(error.starts_with(
        fmt::format("{}:{}: ", yaml, line_of(scenario_with(path), "  trajectory:"))))
        << error;
    EXPECT_NE(error.find(message), std::string::npos) << error;
  }
  EXPECT_NE(error_of(dir, csv,
                     "path:\n  square: {side_m: 6, speed_mps: 0.5, steer_deg: 30}\n"
                     "  trajectory: {file: drive.csv}\n")
                .find("path: one of square, segments and trajectory"),
            std::string::npos);
  write(dir / "scenario.yaml", scenario_with(kTrajectoryPath));
  try {
    static_cast<void>(odoloc::sim::load_scenario(yaml, {.speed_mps = 1.0}));
    ADD_FAILURE() << "--speed with a trajectory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--speed: only a square path"), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

// A built-in text or the fuzzer's has no directory to read a file from.
TEST(TrajectoryFile, ATextWithoutADirectoryCannotNameAFile) {
  const std::string text = scenario_with(kTrajectoryPath);
  const int line = line_of(text, "  trajectory:");
  try {
    static_cast<void>(odoloc::sim::parse_scenario(text, "my.yaml"));
    ADD_FAILURE() << "a trajectory without a directory";
  } catch (const InputError& e) {
    EXPECT_EQ(
        std::string(e.what()),
        fmt::format("my.yaml:{}: path.trajectory.file: a trajectory file needs a scenario file on "
                    "disk (this scenario is a text without a directory: built in, or the fuzzer's)",
                    line));
  }
}

// The shipped figure eight loads, and the tricycle drives it back within
// its measured departure (docs/scenarios.md, "The figure eight, as
// recorded and driven").
TEST(TrajectoryFile, TheShippedFigureEightIsDrivenBackWithinItsDeparture) {
  const fs::path yaml = fs::path(ODOLOC_EXAMPLES_DIR) / "recorded" / "figure-eight.yaml";
  const Scenario s = odoloc::sim::load_scenario(yaml);
  EXPECT_EQ(s.tour.name, "2 laps of the figure eight in Kleeman's room");
  EXPECT_EQ(s.tour.timing.beacon_count, 6U);
  ASSERT_TRUE(s.tour.station.has_value());
  EXPECT_EQ(s.tour.drive.start.x_m, 5);
  EXPECT_NEAR(s.tour.drive.start.theta_rad, 40.601295 * std::numbers::pi / 180, 1e-15);
  // The recording, read independently: its samples at 20 Hz.
  std::ifstream csv(yaml.parent_path() / "figure-eight.csv");
  std::string row;
  std::getline(csv, row);
  std::vector<Recorded> recorded;
  for (double t = 0, x = 0, y = 0, h = 0; std::getline(csv, row);) {
    ASSERT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf,%lf", &t, &x, &y, &h), 4) << row;
    recorded.push_back({t, x, y, h * kDeg});
  }
  ASSERT_EQ(recorded.size(), 848U);
  const double wait_s = 3, lap_s = static_cast<double>(recorded.back().t);
  EXPECT_NEAR(s.tour.duration_s, 2 * wait_s + 2 * lap_s, 1e-9);
  // The truth every 50 ms (5000 steps of 10 us) from the start: the wait's
  // and the laps' samples fall on it.
  const odoloc::world::TricycleSimulator truth = driven(s.tour.drive, 5000);
  const std::size_t waited = 60;  // samples of the truth before the first lap: 3 s
  const std::vector<odoloc::world::TrajectorySample>& samples = truth.trajectory();
  double worst_m = 0, worst_rad = 0, worst_at_s = 0;
  double end_m = 0, end_rad = 0;
  for (int lap = 0; lap < 2; ++lap) {
    for (std::size_t k = 0; k < recorded.size(); ++k) {
      const std::size_t i = waited + static_cast<std::size_t>(lap) * (recorded.size() - 1) + k;
      ASSERT_LT(i, samples.size());
      const odoloc::world::TruePose& p = samples[i].truth;
      const Recorded& r = recorded[k];
      ASSERT_NEAR(p.time_s, wait_s + lap * lap_s + static_cast<double>(r.t), 1e-9);
      const double m =
          std::hypot(p.pose.x_m - static_cast<double>(r.x), p.pose.y_m - static_cast<double>(r.y));
      const double rad = std::abs(wrapped(p.pose.theta_rad - static_cast<double>(r.theta)));
      if (m > worst_m) {
        worst_m = m;
        worst_at_s = p.time_s;
      }
      worst_rad = std::max(worst_rad, rad);
      end_m = m;
      end_rad = rad;
    }
  }
  std::printf(
      "figure eight: the truth departs from the recording by %.2f mm at most (at %.2f s), "
      "%.3f deg at most; at the end %.2f mm, %.3f deg\n",
      worst_m * 1e3, worst_at_s, worst_rad / std::numbers::pi * 180, end_m * 1e3,
      end_rad / std::numbers::pi * 180);
  EXPECT_LT(worst_m, 0.01);
  EXPECT_LT(worst_rad, 0.2 * std::numbers::pi / 180);
}

}  // namespace
