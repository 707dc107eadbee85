// `odoloc plot` (host_tools/tools/plot, docs/host-tool.md): a log written through
// LCM's file provider with known series (a truth circle, a fused estimate 3 cm
// outside it and 0.02 rad ahead, an odometry drifting linearly, fixes with
// chosen errors, malformed events) is read back; the errors and their
// summaries are checked against the values built in, by closed forms of the
// test's own; the script's ellipses are counted and measured; the picture is
// drawn, also of a log without truth; a truncated last event is reported;
// and the command's errors (a missing log, a text file, no gnuplot, ...)
// come with their messages and exit codes.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <stdlib.h>  // setenv, unsetenv

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/cli/app.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/plot/log_plot.hpp"
#include "odoloc/plot/log_series.hpp"
#include "odoloc/process/run_program.hpp"
#include "odoloc_lcm/beacon_fix_t.hpp"
#include "odoloc_lcm/pose_estimate_t.hpp"
#include "odoloc_lcm/sim_status_t.hpp"
#include "png_size.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
namespace plot = odoloc::plot;
namespace channel = odoloc::lcm::channel;
using std::numbers::pi;

// The truth: a circle of 2 m at 0.2 rad/s, 100 Hz for 10 s (µs 0 … 10 000 000).
constexpr double kRadius = 2.0;
constexpr double kOmega = 0.2;
constexpr std::int64_t kTick = 10'000;  // µs
constexpr int kTruthTicks = 1000;       // samples 0 … 1000
// The fused estimate: half a tick after each truth sample (so its truth is
// interpolated), 3 cm radially outside, heading 0.02 rad ahead.
constexpr std::int64_t kFusedOffset = kTick / 2;
constexpr int kFusedSamples = 1000;
constexpr double kFusedRadial = 0.03;
constexpr double kFusedHeading = 0.02;
constexpr double kFusedCovariance[9] = {4e-4, 1e-4, 0, 1e-4, 2.5e-4, 0, 0, 0, 1e-3};
// The odometry: on each truth sample, x ahead by 1 cm per second, heading
// behind by 1 mrad per second.
constexpr double kDriftMps = 0.01;
constexpr double kHeadingDriftRadps = 1e-3;
// Fixes at 0.5 s, 1.5 s, …, 9.5 s; the one of index 4 invalid, the one of
// index 7 with a covariance that is not positive semi-definite (no ellipse).
constexpr int kFixes = 10;
constexpr int kInvalidFix = 4;
constexpr int kIndefiniteFix = 7;

double seconds(std::int64_t utime) {
  return static_cast<double>(utime) / 1e6;
}

// The test's own wrap, by atan2 rather than the library's remainder.
double wrapped(double angle) {
  return std::atan2(std::sin(angle), std::cos(angle));
}

odoloc_lcm::pose_estimate_t pose(const char* source, std::int64_t utime, double x, double y,
                                 double theta) {
  odoloc_lcm::pose_estimate_t m{};
  m.utime = utime;
  m.source = source;
  m.x = x;
  m.y = y;
  m.theta = theta;
  return m;
}

odoloc_lcm::pose_estimate_t truth_at(std::int64_t utime) {
  const double phi = kOmega * seconds(utime);
  return pose("truth", utime, kRadius * std::cos(phi), kRadius * std::sin(phi),
              wrapped(phi + pi / 2));
}

// Fix k's error: 1 cm × (k + 1), in the direction 0.7 k rad.
double fix_error(int k) {
  return 0.01 * (k + 1);
}

std::int64_t fix_utime(int k) {
  return 500'000 + std::int64_t{k} * 1'000'000;
}

std::int64_t fused_utime(int i) {
  return i * kTick + kFusedOffset;
}

// Events on the plotted channels that must be counted as malformed, and
// events on others.
constexpr std::uint64_t kMalformed = 4;
constexpr std::uint64_t kOther = 2;

// Writes the log through LCM's file provider; returns the number of events.
std::uint64_t write_test_log(const fs::path& file) {
  odoloc::lcm::Connection log("file://" + file.string() + "?mode=w");
  std::uint64_t events = 0;
  const auto publish = [&](const char* name, const auto& message) {
    log.publish(name, message);
    ++events;
  };
  const auto publish_raw = [&](const char* name, const std::vector<std::uint8_t>& bytes) {
    log.publish_raw(name, bytes.data(), bytes.size());
    ++events;
  };
  odoloc_lcm::sim_status_t status{};
  status.pacing = "fast";
  publish(channel::kSimStatus, status);
  for (int i = 0; i <= kTruthTicks; ++i) {
    const std::int64_t utime = i * kTick;
    const odoloc_lcm::pose_estimate_t truth = truth_at(utime);
    publish(channel::kTruth, truth);
    const double t = seconds(utime);
    publish(channel::kPoseOdometry, pose("odometry", utime, truth.x + kDriftMps * t, truth.y,
                                         wrapped(truth.theta - kHeadingDriftRadps * t)));
    if (i < kFusedSamples) {
      const std::int64_t fused_time = fused_utime(i);
      const double phi = kOmega * seconds(fused_time);
      odoloc_lcm::pose_estimate_t fused =
          pose("fused", fused_time, (kRadius + kFusedRadial) * std::cos(phi),
               (kRadius + kFusedRadial) * std::sin(phi), wrapped(phi + pi / 2 + kFusedHeading));
      std::copy(std::begin(kFusedCovariance), std::end(kFusedCovariance), fused.covariance);
      publish(channel::kPoseFused, fused);
    }
    if (i % 100 == 50) {
      const int k = i / 100;
      odoloc_lcm::beacon_fix_t fix{};
      fix.utime = fix_utime(k);
      fix.solver = "gauss_newton";
      fix.x = truth.x + fix_error(k) * std::cos(0.7 * k);
      fix.y = truth.y + fix_error(k) * std::sin(0.7 * k);
      const double covariance[4] = {9e-4, k == kIndefiniteFix ? 5e-3 : 2e-4,
                                    k == kIndefiniteFix ? 5e-3 : 2e-4, 4e-4};
      std::copy(std::begin(covariance), std::end(covariance), fix.covariance);
      fix.valid = k != kInvalidFix;
      if (!fix.valid)  // as the solvers send it: its position is meaningless
        fix.x = fix.y = std::nan("");
      publish(channel::kFix, fix);
    }
  }
  // A source the tool does not know (on its own ODOLOC_POSE_* channel),
  // published before the known ones: one sample at the circle's centre; and
  // one with nothing to compare, after the truth's end.
  publish("ODOLOC_POSE_WHEEL_ONLY", pose("wheel_only", 2'000'000, 0, 0, 0));
  for (int i = 1; i <= 5; ++i)
    publish(channel::kPoseRear, pose("rear", 10'000'000 + i * 100'000, 1, 1, 0));
  // Malformed: bytes that are no message, a truncated pose, a pose on the
  // fixes' channel (another type's fingerprint), a pose with a NaN position.
  publish_raw(channel::kPoseFused, {1, 2, 3, 4, 5, 6, 7, 8, 9});
  std::vector<std::uint8_t> truncated = odoloc::lcm::encode(truth_at(0));
  truncated.pop_back();
  publish_raw(channel::kTruth, truncated);
  publish_raw(channel::kFix, odoloc::lcm::encode(truth_at(0)));
  publish(channel::kPoseFused, pose("fused", 3'000'000, std::nan(""), 0, 0));
  // Another channel's garbage is not the plot's business.
  publish_raw(channel::kEncoders, {0xde, 0xad});
  return events;
}

const plot::Track& source(const plot::LogSeries& series, const std::string& name) {
  for (const plot::Track& t : series.sources) {
    if (t.name == name)
      return t;
  }
  ADD_FAILURE() << "no source " << name;
  static const plot::Track kNone;
  return kNone;
}

// The lines of data block `name` in `script`, without its EOD.
std::vector<std::string> block_lines(const std::string& script, const std::string& name) {
  const std::string head = "$" + name + " << EOD\n";
  const std::size_t start = script.find(head);
  if (start == std::string::npos)
    return {};
  const std::size_t end = script.find("EOD\n", start + head.size());
  std::istringstream in(script.substr(start + head.size(), end - start - head.size()));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    lines.push_back(line);
  return lines;
}

struct Point {
  double x, y;
};

// The polylines of an ellipse block (separated by empty lines).
std::vector<std::vector<Point>> polylines(const std::vector<std::string>& lines) {
  std::vector<std::vector<Point>> out(lines.empty() ? 0 : 1);
  for (const std::string& line : lines) {
    if (line.empty()) {
      out.emplace_back();
      continue;
    }
    std::istringstream in(line);
    Point p{};
    in >> p.x >> p.y;
    out.back().push_back(p);
  }
  return out;
}

// Each polyline closed, of kEllipsePoints points, all at squared Mahalanobis
// distance 5.991 (χ², 2 dof, 95 %) from its centre under `covariance`
// (xx, xy, yy); returns the centres (the mean of the distinct points).
std::vector<Point> check_ellipses(const std::vector<std::vector<Point>>& ellipses, double xx,
                                  double xy, double yy) {
  std::vector<Point> centres;
  const double det = xx * yy - xy * xy;
  for (const std::vector<Point>& e : ellipses) {
    EXPECT_EQ(e.size(), plot::kEllipsePoints);
    if (e.size() != plot::kEllipsePoints)
      continue;
    EXPECT_EQ(e.front().x, e.back().x);
    EXPECT_EQ(e.front().y, e.back().y);
    Point c{0, 0};
    for (std::size_t i = 0; i + 1 < e.size(); ++i) {
      c.x += e[i].x / static_cast<double>(e.size() - 1);
      c.y += e[i].y / static_cast<double>(e.size() - 1);
    }
    for (const Point& p : e) {
      const double dx = p.x - c.x, dy = p.y - c.y;
      EXPECT_NEAR((yy * dx * dx - 2 * xy * dx * dy + xx * dy * dy) / det, 5.991, 1e-3);
    }
    centres.push_back(c);
  }
  return centres;
}

class PlotLog : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(odoloc::tb::fresh_dir("odoloc_plot", "log"));
    log_ = new fs::path(*dir_ / "circle.lcmlog");
    events_ = write_test_log(*log_);
  }
  static void TearDownTestSuite() {
    delete log_;
    delete dir_;
  }
  static fs::path* dir_;
  static fs::path* log_;
  static std::uint64_t events_;
};
fs::path* PlotLog::dir_ = nullptr;
fs::path* PlotLog::log_ = nullptr;
std::uint64_t PlotLog::events_ = 0;

TEST_F(PlotLog, CountsEveryEventAndSkipsTheMalformed) {
  const plot::LogSeries s = plot::read_log(*log_);
  EXPECT_EQ(s.counts.events, events_);
  EXPECT_EQ(s.counts.malformed, kMalformed);
  EXPECT_EQ(s.counts.invalid_fixes, 1U);
  EXPECT_EQ(s.counts.other, kOther);
  EXPECT_EQ(s.counts.unread_bytes, 0U);
  EXPECT_EQ(s.truth.samples.size(), static_cast<std::size_t>(kTruthTicks + 1));
  EXPECT_EQ(s.fixes.samples.size(), static_cast<std::size_t>(kFixes - 1));
  EXPECT_EQ(s.start_utime, 0);
  // Known sources first in their order, then the others by name.
  std::vector<std::string> names;
  for (const plot::Track& t : s.sources)
    names.push_back(t.name);
  EXPECT_EQ(names, (std::vector<std::string>{"fused", "odometry", "rear", "wheel_only"}));
  EXPECT_EQ(source(s, "fused").samples.size(), static_cast<std::size_t>(kFusedSamples));
}

TEST_F(PlotLog, ErrorsAgainstTheInterpolatedTruth) {
  const plot::LogSeries s = plot::read_log(*log_);
  // Fused: the truth half a tick away lies on the chord between two samples,
  // R (1 − cos(ω Δt / 2)) inside the circle; the heading interpolates
  // exactly, across ±π too.
  const double fused_error = kFusedRadial + kRadius * (1 - std::cos(kOmega * seconds(kTick) / 2));
  const plot::Track& fused = source(s, "fused");
  ASSERT_EQ(fused.errors.size(), static_cast<std::size_t>(kFusedSamples));
  for (int i = 0; i < kFusedSamples; ++i) {
    const plot::Error& e = fused.errors[static_cast<std::size_t>(i)];
    EXPECT_EQ(e.utime, fused_utime(i));
    EXPECT_NEAR(e.position_m, fused_error, 1e-12) << i;
    EXPECT_NEAR(e.heading_rad, kFusedHeading, 1e-12) << i;
  }
  const plot::ErrorSummary f = plot::summarize(fused);
  EXPECT_NEAR(f.final_position_m, fused_error, 1e-12);
  EXPECT_NEAR(f.rms_position_m, fused_error, 1e-12);
  EXPECT_NEAR(f.rms_heading_rad, kFusedHeading, 1e-12);

  // Odometry: error v t on samples t_i = i / 100, i = 0 … n; its RMS is
  // v / 100 · sqrt(Σ i² / (n + 1)) = v / 100 · sqrt(n (2n + 1) / 6).
  const plot::ErrorSummary o = plot::summarize(source(s, "odometry"));
  const double n = kTruthTicks;
  EXPECT_EQ(o.compared, static_cast<std::size_t>(kTruthTicks + 1));
  EXPECT_NEAR(o.final_position_m, kDriftMps * 10, 1e-12);
  EXPECT_NEAR(o.rms_position_m, kDriftMps / 100 * std::sqrt(n * (2 * n + 1) / 6), 1e-12);
  EXPECT_NEAR(o.final_heading_rad, -kHeadingDriftRadps * 10, 1e-12);
  EXPECT_NEAR(o.rms_heading_rad, kHeadingDriftRadps / 100 * std::sqrt(n * (2 * n + 1) / 6), 1e-12);

  // Fixes: the chosen errors, the invalid one left out; no heading.
  double sum = 0;
  for (int k = 0; k < kFixes; ++k)
    sum += k == kInvalidFix ? 0 : fix_error(k) * fix_error(k);
  const plot::ErrorSummary x = plot::summarize(s.fixes);
  EXPECT_EQ(x.compared, static_cast<std::size_t>(kFixes - 1));
  EXPECT_NEAR(x.final_position_m, fix_error(kFixes - 1), 1e-12);
  EXPECT_NEAR(x.rms_position_m, std::sqrt(sum / (kFixes - 1)), 1e-12);
  EXPECT_TRUE(std::isnan(x.final_heading_rad));
  for (const plot::Error& e : s.fixes.errors) {
    const int k = static_cast<int>((e.utime - 500'000) / 1'000'000);
    EXPECT_EQ(e.utime, fix_utime(k));
    EXPECT_NEAR(e.position_m, fix_error(k), 1e-12) << k;
  }

  // At the centre: the radius away.
  EXPECT_NEAR(plot::summarize(source(s, "wheel_only")).final_position_m, kRadius, 1e-12);
  // After the truth's end: nothing to compare.
  EXPECT_EQ(plot::summarize(source(s, "rear")).compared, 0U);
  EXPECT_TRUE(std::isnan(plot::summarize(source(s, "rear")).rms_position_m));
}

TEST_F(PlotLog, ATruncatedLastEventIsReportedAsUnreadBytes) {
  // The last event (garbage on ODOLOC_ENCODERS): LCM's 28-byte header, the
  // channel's name, 2 bytes of data; cut 5 bytes short.
  const std::uint64_t last_event = 28 + std::string_view{channel::kEncoders}.size() + 2;
  const fs::path cut = *dir_ / "cut.lcmlog";
  fs::copy_file(*log_, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(cut) - 5);
  const plot::LogSeries s = plot::read_log(cut);
  EXPECT_EQ(s.counts.events, events_ - 1);
  EXPECT_EQ(s.counts.other, kOther - 1);
  EXPECT_EQ(s.counts.unread_bytes, last_event - 5);
  EXPECT_NE(plot::summary_text(s).find(
                fmt::format("; {} bytes after the last whole event not read", last_event - 5)),
            std::string::npos)
      << plot::summary_text(s);
}

TEST(PlotLogWithoutTruth, DrawsTheTrajectoriesAlone) {
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_plot", "no_truth");
  {
    odoloc::lcm::Connection log("file://" + (dir / "robot.lcmlog").string() + "?mode=w");
    for (int i = 0; i < 3; ++i)
      log.publish(channel::kPoseFused, pose("fused", i * kTick, 0.1 * i, 0, 0));
  }
  const plot::LogSeries s = plot::read_log(dir / "robot.lcmlog");
  EXPECT_TRUE(s.truth.samples.empty());
  ASSERT_EQ(s.sources.size(), 1U);
  EXPECT_TRUE(s.sources[0].errors.empty());
  EXPECT_NE(plot::summary_text(s).find("no truth (ODOLOC_TRUTH): no errors"), std::string::npos);
  const std::string script = plot::plot_script(s, "robot.png", 1);
  EXPECT_EQ(script.find("$error_"), std::string::npos);
  EXPECT_EQ(script.find("set logscale y"), std::string::npos);
  (void)plot::draw(s, {.png = dir / "robot.png"});
  EXPECT_EQ(odoloc::tb::png_size(dir / "robot.png").width,
            static_cast<std::uint32_t>(plot::kPlotWidth));

  // Nothing that decodes: nothing to plot.
  {
    odoloc::lcm::Connection log("file://" + (dir / "junk.lcmlog").string() + "?mode=w");
    const std::vector<std::uint8_t> junk = {1, 2, 3};
    log.publish_raw(channel::kPoseFused, junk.data(), junk.size());
  }
  try {
    (void)plot::read_log(dir / "junk.lcmlog");
    ADD_FAILURE() << "no error";
  } catch (const plot::PlotError& e) {
    EXPECT_TRUE(e.usage());
    EXPECT_EQ(std::string{e.what()},
              (dir / "junk.lcmlog").string() +
                  ": no ODOLOC_TRUTH, ODOLOC_POSE_* or valid ODOLOC_FIX event that decodes (1 "
                  "events, 1 malformed): nothing to plot");
  }
}

// LCM has no authentication: any local publisher can plant a source name
// in a recorded log. Names that gnuplot would run (backquotes, a quote and
// a line break, a macro) and terminal escapes are data: drawn as text,
// shown escaped in the summary, and nothing runs (the marker is absolute:
// gnuplot runs in a staging folder).
TEST(PlotHostileLog, SourceNamesAreDataForGnuplotAndTheTerminal) {
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_plot", "hostile");
  const std::string touch = "touch " + (dir / "X").string();
  const std::vector<std::string> names = {"fused`" + touch + "`", "o'\nsystem('" + touch + "')#",
                                          "@m $x;`" + touch + "`\xff", "\x1b[2J\x1b]0;t\x07"};
  {
    odoloc::lcm::Connection log("file://" + (dir / "planted.lcmlog").string() + "?mode=w");
    for (int i = 0; i < 20; ++i) {
      log.publish(channel::kTruth, truth_at(i * kTick));
      for (std::size_t n = 0; n < names.size(); ++n) {
        const odoloc_lcm::pose_estimate_t t = truth_at(i * kTick);
        log.publish(channel::kPoseFused, pose(names[n].c_str(), i * kTick,
                                              t.x + 0.01 * static_cast<double>(n), t.y, t.theta));
      }
    }
  }
  const plot::LogSeries s = plot::read_log(dir / "planted.lcmlog");
  ASSERT_EQ(s.sources.size(), names.size());
  const std::string summary = plot::summary_text(s);
  EXPECT_EQ(summary.find('\x1b'), std::string::npos) << "an escape reached the terminal";
  EXPECT_NE(summary.find("\\x1b[2J"), std::string::npos) << summary;
  (void)plot::draw(s, {.png = dir / "planted.png", .keep_script = true});
  EXPECT_EQ(odoloc::tb::png_size(dir / "planted.png").width,
            static_cast<std::uint32_t>(plot::kPlotWidth));
  EXPECT_FALSE(fs::exists(dir / "X")) << "a source name ran as a command";
  // The kept script, run again by a user in the folder, runs nothing either.
  const odoloc::process::ProgramResult again =
      odoloc::process::run_program("gnuplot", {"planted.gp"}, dir);
  EXPECT_TRUE(again.ok()) << again.message;
  EXPECT_FALSE(fs::exists(dir / "X"));
}

TEST(PlotErrors, HeadingTakesTheShorterWayRoundAndTimesOutsideTheTruthGetNone) {
  std::vector<plot::Sample> truth(2);
  truth[0] = {.utime = 100, .x_m = 0, .y_m = 0, .theta_rad = pi - 0.1};
  truth[1] = {.utime = 200, .x_m = 1, .y_m = 2, .theta_rad = -pi + 0.1};
  const std::vector<plot::Sample> estimates = {
      {.utime = 99, .x_m = 0, .y_m = 0, .theta_rad = 0},              // before: none
      {.utime = 100, .x_m = 0.3, .y_m = 0.4, .theta_rad = pi - 0.1},  // on a sample
      {.utime = 150, .x_m = 0.5, .y_m = 1, .theta_rad = -pi + 0.05},  // truth (0.5, 1, π)
      {.utime = 175, .x_m = 0.75, .y_m = 1.5, .theta_rad = plot::kNoValue},
      {.utime = 201, .x_m = 0, .y_m = 0, .theta_rad = 0},  // after: none
  };
  const std::vector<plot::Error> e = plot::errors_against(truth, estimates);
  ASSERT_EQ(e.size(), 3U);
  EXPECT_EQ(e[0].utime, 100);
  EXPECT_DOUBLE_EQ(e[0].position_m, 0.5);
  EXPECT_NEAR(e[0].heading_rad, 0, 1e-15);
  EXPECT_EQ(e[1].utime, 150);
  EXPECT_NEAR(e[1].position_m, 0, 1e-15);
  EXPECT_NEAR(e[1].heading_rad, 0.05, 1e-12);  // not 2π − 0.05, not π
  EXPECT_NEAR(e[2].position_m, 0, 1e-15);
  EXPECT_TRUE(std::isnan(e[2].heading_rad));
  EXPECT_DOUBLE_EQ(plot::wrap_angle(-pi), pi);
  EXPECT_DOUBLE_EQ(plot::wrap_angle(3 * pi), pi);
  EXPECT_NEAR(plot::wrap_angle(2 * pi + 0.25), 0.25, 1e-15);
}

TEST_F(PlotLog, TheScriptDrawsTheEllipsesOfTheCovariances) {
  const plot::LogSeries s = plot::read_log(*log_);
  for (const double every : {1.0, 2.5}) {
    SCOPED_TRACE(every);
    const std::string script = plot::plot_script(s, "out.png", every);
    // Fused samples at 5 ms + 10 ms i over 9.99 s: one ellipse at the first,
    // then every `every` seconds.
    const std::size_t expected =
        static_cast<std::size_t>(
            std::floor(seconds(fused_utime(kFusedSamples - 1) - fused_utime(0)) / every)) +
        1;
    const auto fused = polylines(block_lines(script, "ellipses_fused"));
    ASSERT_EQ(fused.size(), expected);
    const std::vector<Point> centres =
        check_ellipses(fused, kFusedCovariance[0], kFusedCovariance[1], kFusedCovariance[4]);
    for (std::size_t j = 0; j < centres.size(); ++j) {
      const double phi = kOmega * (seconds(fused_utime(0)) + every * static_cast<double>(j));
      EXPECT_NEAR(centres[j].x, (kRadius + kFusedRadial) * std::cos(phi), 1e-9) << j;
      EXPECT_NEAR(centres[j].y, (kRadius + kFusedRadial) * std::sin(phi), 1e-9) << j;
    }
    EXPECT_NE(script.find("$ellipses_fused using 1:2 with lines"), std::string::npos);
  }
  // Every valid fix but the one whose covariance is indefinite.
  const std::string script = plot::plot_script(s, "out.png", 1);
  const auto fixes = polylines(block_lines(script, "ellipses_fixes"));
  EXPECT_EQ(fixes.size(), static_cast<std::size_t>(kFixes - 2));
  check_ellipses(fixes, 9e-4, 2e-4, 4e-4);
  EXPECT_NE(script.find("$ellipses_fixes using 1:2 with lines"), std::string::npos);
  // The title names the log and every compared track's final / RMS error.
  EXPECT_NE(script.find("circle.lcmlog"), std::string::npos);
  EXPECT_NE(script.find("odometry 100.0 / 57.7 mm"), std::string::npos) << script.substr(0, 400);
  EXPECT_THROW((void)plot::plot_script(s, "out.png", 0), plot::PlotError);
}

TEST_F(PlotLog, SmallEllipsesAreMagnifiedAndTheTitleSaysBy) {
  plot::LogSeries s = plot::read_log(*log_);
  // The fused ellipses alone, their covariance 1000 times smaller: semi-axes
  // of about 1.6 mm on trajectories of about 3 m, to be magnified 20 times
  // (not 10, too small; nor 100, more than needed).
  constexpr double kScale = 1e-3;
  for (plot::Track& t : s.sources) {
    for (plot::Sample& sample : t.samples) {
      for (double& c : sample.covariance_m2)
        c *= kScale;
    }
  }
  s.fixes = {};
  const std::string script = plot::plot_script(s, "out.png", 1);
  EXPECT_EQ(plot::plot_script(plot::read_log(*log_), "out.png", 1).find("magnified"),
            std::string::npos);  // the test log's ellipses are large enough
  const std::string said = "fused every 1 s, magnified ";
  const std::size_t at = script.find(said);
  ASSERT_NE(at, std::string::npos) << script.substr(0, 300);
  const double m = std::stod(script.substr(at + said.size()));
  // One of 1, 2, 5 times a power of ten, …
  const double decade = std::pow(10, std::floor(std::log10(m) + 1e-9));
  const double step = std::round(m / decade);
  EXPECT_TRUE(step == 1 || step == 2 || step == 5) << m;
  EXPECT_DOUBLE_EQ(step * decade, m);
  // … the least that makes the (every) ellipse's semi-major axis, k √λmax,
  // 1 % of the larger side of the samples' box.
  const double xx = kScale * kFusedCovariance[0], xy = kScale * kFusedCovariance[1],
               yy = kScale * kFusedCovariance[4];
  const double lambda_max = (xx + yy) / 2 + std::hypot((xx - yy) / 2, xy);
  const double radius = std::sqrt(5.991464547107979 * lambda_max);
  double low_x = 1e9, high_x = -1e9, low_y = 1e9, high_y = -1e9;
  for (const plot::Track* t :
       {&s.truth, &s.sources[0], &s.sources[1], &s.sources[2], &s.sources[3]}) {
    for (const plot::Sample& sample : t->samples) {
      low_x = std::min(low_x, sample.x_m);
      high_x = std::max(high_x, sample.x_m);
      low_y = std::min(low_y, sample.y_m);
      high_y = std::max(high_y, sample.y_m);
    }
  }
  const double visible = 0.01 * std::max(high_x - low_x, high_y - low_y);
  EXPECT_GE(radius * m, visible * (1 - 1e-3));
  EXPECT_LT(radius * m * (step == 5 ? 0.4 : 0.5), visible);
  // Magnified about their centres: squared Mahalanobis distance 5.991 under
  // the covariance times m².
  const auto fused = polylines(block_lines(script, "ellipses_fused"));
  EXPECT_EQ(fused.size(), 10U);
  check_ellipses(fused, m * m * xx, m * m * xy, m * m * yy);
  EXPECT_EQ(block_lines(script, "ellipses_fixes").size(), 0U);
}

TEST_F(PlotLog, DrawsThePicture) {
  const fs::path png = *dir_ / "picture" / "circle.png";
  fs::create_directories(png.parent_path());
  const fs::path script =
      plot::draw(plot::read_log(*log_), {.png = png, .ellipse_every_s = 1, .keep_script = true});
  const odoloc::tb::PngSize size = odoloc::tb::png_size(png);
  EXPECT_EQ(size.width, static_cast<std::uint32_t>(plot::kPlotWidth));
  EXPECT_EQ(size.height, static_cast<std::uint32_t>(plot::kPlotHeight));
  EXPECT_EQ(script, *dir_ / "picture" / "circle.gp");
  EXPECT_TRUE(fs::is_regular_file(script));
}

// Runs the host tool in process; its exit code, stdout and stderr.
struct CliRun {
  int code;
  std::string out, err;
};
CliRun odoloc_cli(const std::vector<std::string>& args) {
  std::istringstream in;
  std::ostringstream out, err;
  const int code = odoloc::cli::run_cli(args, {in, out, err});
  return {code, out.str(), err.str()};
}

// An environment variable set for the object's lifetime (gnuplot's PATH, the
// temporary folder), then restored.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    const char* old = std::getenv(name);
    if (old != nullptr)
      old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST_F(PlotLog, TheCommandWritesNextToTheLogAndPrintsTheSummary) {
  const fs::path log = *dir_ / "copy.lcmlog";
  fs::copy_file(*log_, log, fs::copy_options::overwrite_existing);
  // The temporary script goes to TMPDIR, and away again.
  const fs::path tmp = *dir_ / "tmp";
  fs::create_directories(tmp);
  const CliRun run = [&] {
    const ScopedEnv tmpdir("TMPDIR", tmp.string());
    return odoloc_cli({"plot", log.string()});
  }();
  EXPECT_EQ(run.code, odoloc::cli::kExitOk) << run.err;
  EXPECT_TRUE(fs::is_empty(tmp));
  EXPECT_EQ(odoloc::tb::png_size(*dir_ / "copy.png").width,
            static_cast<std::uint32_t>(plot::kPlotWidth));
  EXPECT_FALSE(fs::exists(*dir_ / "copy.gp"));
  EXPECT_NE(run.out.find(fmt::format("skipped: malformed {}, invalid fixes 1, other channels {}",
                                     kMalformed, kOther)),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("odometry         1001     1001     100.0      57.7"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("picture: " + (*dir_ / "copy.png").string()), std::string::npos);
  const CliRun json = odoloc_cli({"--json", "plot", log.string(), "--out",
                                  (*dir_ / "j.png").string(), "--ellipse-every", "2"});
  EXPECT_EQ(json.code, odoloc::cli::kExitOk) << json.err;
  EXPECT_NE(json.out.find("\"malformed\":4"), std::string::npos) << json.out;
}

TEST_F(PlotLog, BadInputIsAUsageErrorNamingTheFile) {
  const fs::path text = *dir_ / "notes.txt";
  std::ofstream(text) << "not a log\n";
  const fs::path empty = *dir_ / "empty.lcmlog";
  std::ofstream{empty};
  const fs::path missing = *dir_ / "missing.lcmlog";
  const struct {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"plot", missing.string()},
       "odoloc: cannot open " + missing.string() + ": No such file or directory\n"},
      {{"plot", text.string()},
       "odoloc: " + text.string() +
           " is not an LCM event log: it does not start with LCM's sync word 0xEDA1DA01\n"},
      {{"plot", empty.string()}, "odoloc: " + empty.string() + " is empty: not an LCM event log\n"},
      {{"plot", dir_->string()},
       "odoloc: cannot read " + dir_->string() + ": it is a directory, not an LCM event log\n"},
      {{"plot", log_->string(), "--out", log_->string()},
       "odoloc: the picture " + log_->string() + " would replace the log itself\n"},
      {{"plot", log_->string(), "--out", (*dir_ / "nowhere" / "x.png").string()},
       "odoloc: cannot write " + (*dir_ / "nowhere" / "x.png").string() + ": the folder " +
           (*dir_ / "nowhere").string() + " does not exist\n"},
      {{"plot", log_->string(), "--ellipse-every", "0"},
       "odoloc: --ellipse-every: '0' is not a positive number of seconds\n"},
      {{"plot", log_->string(), "--target", "sim"},
       "odoloc: --target does not apply to plot: it reads a log file and opens no target\n"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args[1]);
    const CliRun run = odoloc_cli(c.args);
    EXPECT_EQ(run.code, odoloc::cli::kExitUsage);
    EXPECT_EQ(run.err, c.message);
  }
}

TEST_F(PlotLog, WithoutGnuplotTheErrorSaysToInstallIt) {
  const fs::path nowhere = *dir_ / "no-programs";
  fs::create_directories(nowhere);
  const CliRun run = [&] {
    const ScopedEnv path("PATH", nowhere.string());
    return odoloc_cli({"plot", log_->string(), "--out", (*dir_ / "never.png").string()});
  }();
  EXPECT_EQ(run.code, odoloc::cli::kExitBus);
  EXPECT_NE(run.err.find("cannot run gnuplot (install it: apt-get install gnuplot-nox)"),
            std::string::npos)
      << run.err;
  EXPECT_FALSE(fs::exists(*dir_ / "never.png"));
}

}  // namespace
