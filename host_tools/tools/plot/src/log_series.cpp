#include "odoloc/plot/log_series.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <numbers>
#include <string_view>

#include "odoloc/lcm/channels.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc_lcm/beacon_fix_t.hpp"
#include "odoloc_lcm/pose_estimate_t.hpp"

namespace odoloc::plot {
namespace {

namespace fs = std::filesystem;
namespace channel = odoloc::lcm::channel;

// Every LCM log event starts with this word, big-endian (LCM's eventlog.c).
constexpr std::array<unsigned char, 4> kSyncWord = {0xED, 0xA1, 0xDA, 0x01};

// The pose sources in the order the tools draw and list them; others follow
// by name.
constexpr std::array<std::string_view, 4> kSourceOrder = {"fused", "odometry", "rear", "front"};

[[noreturn]] void usage_error(const std::string& what) {
  throw PlotError(true, what);
}

// A clear error before LCM's reader, which reads a missing file, a folder or
// a text file alike as a log without events.
void check_is_log(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec))
    usage_error(
        fmt::format("cannot read {}: it is a directory, not an LCM event log", file.string()));
  std::ifstream in(file, std::ios::binary);
  if (!in)
    usage_error(fmt::format("cannot open {}: {}", file.string(), std::strerror(errno)));
  std::array<char, kSyncWord.size()> head{};
  in.read(head.data(), head.size());
  if (in.gcount() == 0)
    usage_error(fmt::format("{} is empty: not an LCM event log", file.string()));
  if (!std::equal(kSyncWord.begin(), kSyncWord.end(), head.begin(), head.end(),
                  [](unsigned char a, char b) { return a == static_cast<unsigned char>(b); }))
    usage_error(
        fmt::format("{} is not an LCM event log: it does not start with LCM's sync word 0xEDA1DA01",
                    file.string()));
}

bool finite_position(double x, double y) {
  return std::isfinite(x) && std::isfinite(y);
}

Sample sample_of(const odoloc_lcm::pose_estimate_t& pose) {
  return {.utime = pose.utime,
          .x_m = pose.x,
          .y_m = pose.y,
          .theta_rad = pose.theta,
          .covariance_m2 = {pose.covariance[0], pose.covariance[1], pose.covariance[3],
                            pose.covariance[4]}};
}

Sample sample_of(const odoloc_lcm::beacon_fix_t& fix) {
  return {.utime = fix.utime,
          .x_m = fix.x,
          .y_m = fix.y,
          .theta_rad = kNoValue,
          .covariance_m2 = {fix.covariance[0], fix.covariance[1], fix.covariance[2],
                            fix.covariance[3]}};
}

void sort_by_time(Track& track) {
  std::ranges::stable_sort(track.samples, {}, &Sample::utime);
}

double rms(const std::vector<Error>& errors, double Error::*member) {
  double sum = 0;
  for (const Error& e : errors)
    sum += e.*member * e.*member;
  return std::sqrt(sum / static_cast<double>(errors.size()));
}

double degrees(double radians) {
  return radians * 180 / std::numbers::pi;
}

// "12.3"; "-" for no value.
std::string shown(double value, int decimals) {
  return std::isnan(value) ? std::string{"-"} : fmt::format("{:.{}f}", value, decimals);
}

}  // namespace

double wrap_angle(double angle_rad) {
  const double wrapped = std::remainder(angle_rad, 2 * std::numbers::pi);  // [−π, π]
  return wrapped == -std::numbers::pi ? std::numbers::pi : wrapped;
}

std::vector<Error> errors_against(std::span<const Sample> truth,
                                  std::span<const Sample> estimates) {
  std::vector<Error> out;
  if (truth.empty())
    return out;
  out.reserve(estimates.size());
  for (const Sample& e : estimates) {
    if (e.utime < truth.front().utime || e.utime > truth.back().utime)
      continue;
    const auto after = std::ranges::lower_bound(truth, e.utime, {}, &Sample::utime);
    double x = after->x_m, y = after->y_m, theta = after->theta_rad;
    if (after->utime != e.utime) {  // strictly between two truth samples
      const Sample& before = *std::prev(after);
      // In double: a difference of two int64 times may not fit one.
      const double f = (static_cast<double>(e.utime) - static_cast<double>(before.utime)) /
                       (static_cast<double>(after->utime) - static_cast<double>(before.utime));
      x = before.x_m + f * (after->x_m - before.x_m);
      y = before.y_m + f * (after->y_m - before.y_m);
      theta = before.theta_rad + f * wrap_angle(after->theta_rad - before.theta_rad);
    }
    out.push_back(
        {.utime = e.utime,
         .position_m = std::hypot(e.x_m - x, e.y_m - y),
         .heading_rad = std::isnan(e.theta_rad) ? kNoValue : wrap_angle(e.theta_rad - theta)});
  }
  return out;
}

ErrorSummary summarize(const Track& track) {
  ErrorSummary s;
  s.compared = track.errors.size();
  if (track.errors.empty())
    return s;
  // Errors are in time order, as the samples.
  s.final_position_m = track.errors.back().position_m;
  s.rms_position_m = rms(track.errors, &Error::position_m);
  s.final_heading_rad = track.errors.back().heading_rad;
  s.rms_heading_rad = rms(track.errors, &Error::heading_rad);  // NaN for fixes
  return s;
}

std::vector<const Track*> estimate_tracks(const LogSeries& series) {
  std::vector<const Track*> out;
  for (const Track& t : series.sources)
    out.push_back(&t);
  if (!series.fixes.samples.empty())
    out.push_back(&series.fixes);
  return out;
}

LogSeries read_log(const fs::path& file) {
  check_is_log(file);
  ::lcm::LogFile log(file.string(), "r");
  if (!log.good())
    usage_error(fmt::format("cannot open {}: {}", file.string(), std::strerror(errno)));
  LogSeries series;
  series.file = file;
  series.truth.name = "truth";
  series.fixes.name = "fixes";
  std::map<std::string, Track, std::less<>> sources;
  off_t read_up_to = 0;  // byte after the last whole event
  for (const ::lcm::LogEvent* event = log.readNextEvent(); event != nullptr;
       event = log.readNextEvent()) {
    ++series.counts.events;
    read_up_to = ftello(log.getFilePtr());
    const auto size = static_cast<std::size_t>(event->datalen);
    if (event->channel == channel::kTruth || event->channel.starts_with(channel::kPosePrefix)) {
      odoloc_lcm::pose_estimate_t pose{};
      if (!odoloc::lcm::decode(event->data, size, pose) || !finite_position(pose.x, pose.y) ||
          !std::isfinite(pose.theta)) {
        ++series.counts.malformed;
        continue;
      }
      Track& track = event->channel == channel::kTruth ? series.truth : sources[pose.source];
      track.samples.push_back(sample_of(pose));
    } else if (event->channel == channel::kFix) {
      odoloc_lcm::beacon_fix_t fix{};
      if (!odoloc::lcm::decode(event->data, size, fix)) {
        ++series.counts.malformed;
        continue;
      }
      // An invalid fix's position is meaningless (the solvers send NaN).
      if (!fix.valid) {
        ++series.counts.invalid_fixes;
        continue;
      }
      if (!finite_position(fix.x, fix.y)) {
        ++series.counts.malformed;
        continue;
      }
      series.fixes.samples.push_back(sample_of(fix));
    } else {
      ++series.counts.other;
    }
  }
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (!ec && size > static_cast<std::uintmax_t>(read_up_to))
    series.counts.unread_bytes = size - static_cast<std::uintmax_t>(read_up_to);

  for (auto& [name, track] : sources)
    track.name = name;
  for (const std::string_view name : kSourceOrder) {
    if (const auto it = sources.find(name); it != sources.end()) {
      series.sources.push_back(std::move(it->second));
      sources.erase(it);
    }
  }
  for (auto& entry : sources)  // the others, by name
    series.sources.push_back(std::move(entry.second));

  std::vector<Track*> all{&series.truth, &series.fixes};
  for (Track& t : series.sources)
    all.push_back(&t);
  bool any = false;
  for (Track* t : all) {
    sort_by_time(*t);
    if (t->samples.empty())
      continue;
    series.start_utime =
        any ? std::min(series.start_utime, t->samples.front().utime) : t->samples.front().utime;
    any = true;
  }
  if (!any)
    usage_error(fmt::format(
        "{}: no {}, {}* or valid {} event that decodes ({} events, {} malformed): nothing to plot",
        file.string(), channel::kTruth, channel::kPosePrefix, channel::kFix, series.counts.events,
        series.counts.malformed));
  for (Track* t : all) {
    if (t != &series.truth)
      t->errors = errors_against(series.truth.samples, t->samples);
  }
  return series;
}

std::string summary_text(const LogSeries& series) {
  const LogCounts& c = series.counts;
  const Track& truth = series.truth;
  // Names from the command line and the log, shown as text (a source may
  // be anything a publisher sent).
  std::string out =
      fmt::format("{}: {} events; ", output::printable(series.file.string()), c.events);
  if (truth.samples.empty())
    out += "no truth (ODOLOC_TRUTH): no errors";
  else
    out += fmt::format("truth {} samples over {:.3f} s", truth.samples.size(),
                       (static_cast<double>(truth.samples.back().utime) -
                        static_cast<double>(truth.samples.front().utime)) /
                           1e6);
  out += fmt::format("; skipped: malformed {}, invalid fixes {}, other channels {}", c.malformed,
                     c.invalid_fixes, c.other);
  if (c.unread_bytes > 0)
    out += fmt::format("; {} bytes after the last whole event not read", c.unread_bytes);
  out += fmt::format("\n{:<12} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}\n", "source", "samples",
                     "compared", "final_mm", "rms_mm", "final_deg", "rms_deg");
  for (const Track* t : estimate_tracks(series)) {
    const ErrorSummary s = summarize(*t);
    out += fmt::format("{:<12} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}\n", output::printable(t->name),
                       t->samples.size(), s.compared, shown(s.final_position_m * 1e3, 1),
                       shown(s.rms_position_m * 1e3, 1), shown(degrees(s.final_heading_rad), 3),
                       shown(degrees(s.rms_heading_rad), 3));
  }
  return out;
}

}  // namespace odoloc::plot
