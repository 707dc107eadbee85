#include "odoloc/cli/watch_pose.hpp"

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <ostream>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/cli/target.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc_lcm/pose_estimate_t.hpp"

namespace odoloc::cli {
namespace {

using Pose = odoloc_lcm::pose_estimate_t;

constexpr std::array<std::string_view, 7> kSources = {"fused", "odometry", "rear", "front",
                                                      "liu",   "truth",    "all"};
// How often an idle watch looks at the stop flag.
constexpr std::chrono::milliseconds kSlice{10};

double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}
double seconds(std::int64_t utime) {
  return static_cast<double>(utime) * 1e-6;
}

// Standard deviations from the covariance's diagonal (a negative variance,
// which no estimator should send, gives NaN: shown, not hidden).
struct Deviations {
  double x_m, y_m, theta_rad;
};
Deviations deviations(const Pose& pose) {
  return {std::sqrt(pose.covariance[0]), std::sqrt(pose.covariance[4]),
          std::sqrt(pose.covariance[8])};
}

constexpr std::string_view kRow =
    "{:>11}  {:<8}  {:>10}  {:>10}  {:>9}  {:>9}  {:>9}  {:>12}  {}\n";

std::string header() {
  return fmt::format(kRow, "time_s", "source", "x_m", "y_m", "theta_deg", "sd_x_m", "sd_y_m",
                     "sd_theta_deg", "odometry_only");
}

std::string line(const Pose& pose) {
  const Deviations sd = deviations(pose);
  return fmt::format(kRow, fmt::format("{:.6f}", seconds(pose.utime)),
                     output::printable(pose.source), fmt::format("{:.6f}", pose.x),
                     fmt::format("{:.6f}", pose.y), fmt::format("{:.4f}", degrees(pose.theta)),
                     fmt::format("{:.6f}", sd.x_m), fmt::format("{:.6f}", sd.y_m),
                     fmt::format("{:.4f}", degrees(sd.theta_rad)),
                     pose.odometry_only ? "yes" : "no");
}

nlohmann::json document(const Pose& pose) {
  const Deviations sd = deviations(pose);
  return {{"utime_us", pose.utime},
          {"time_s", seconds(pose.utime)},
          {"source", pose.source},
          {"x_m", pose.x},
          {"y_m", pose.y},
          {"theta_rad", pose.theta},
          {"theta_deg", degrees(pose.theta)},
          {"sd_x_m", sd.x_m},
          {"sd_y_m", sd.y_m},
          {"sd_theta_rad", sd.theta_rad},
          {"covariance", pose.covariance},
          {"odometry_only", pose.odometry_only != 0},  // an LCM boolean is an int8_t
          {"last_update_utime_us", pose.last_update_utime}};
}

}  // namespace

std::string parse_pose_source(std::string_view text) {
  for (const std::string_view source : kSources)
    if (text == source)
      return std::string{text};
  throw UsageError(
      fmt::format("unknown pose source '{}'; expected fused, odometry, rear, front, liu, "
                  "truth or all",
                  text));
}

void run_watch_pose(const WatchPoseCommand& cmd, std::ostream& out, bool json,
                    const std::atomic<bool>* stop) {
  const bool all = cmd.source == "all";
  std::uint64_t printed = 0;
  lcm::Connection connection = open_lcm(cmd.url);
  const auto print = [&](const Pose& pose, const lcm::Receipt&) {
    if ((cmd.count != 0 && printed == cmd.count) || (!all && pose.source != cmd.source))
      return;
    if (json)
      out << json_line(document(pose)) << '\n';
    else
      out << (printed == 0 ? header() : std::string{}) << line(pose);
    out << std::flush;
    ++printed;
  };
  for (const lcm::channel::PoseStream& stream : lcm::channel::kPoseStreams)
    if (all || cmd.source == stream.source)
      connection.subscribe<Pose>(stream.channel, print);
  if (all || cmd.source == "truth")
    connection.subscribe<Pose>(lcm::channel::kTruth, print);
  while (cmd.count == 0 || printed < cmd.count) {
    if (stop != nullptr && stop->load())
      throw Interrupted();
    (void)connection.handle(kSlice);
  }
}

}  // namespace odoloc::cli
