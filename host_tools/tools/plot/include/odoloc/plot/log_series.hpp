// The series of an LCM event log that `odoloc plot` draws (docs/host-tool.md):
// the ground truth (ODOLOC_TRUTH), every pose source (ODOLOC_POSE_*: fused,
// odometry, rear, front, ...) and the valid beacon fixes (ODOLOC_FIX), each
// with its errors against the truth interpolated at the estimate's time.
// Reads the log with LCM's own reader; decodes with odoloc::lcm::decode, so
// an event that does not decode is counted and skipped, never fatal.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace odoloc::plot {

// What went wrong, in one line naming the file. usage(): the log is at
// fault (missing, unreadable, a directory, not an LCM event log, nothing to
// plot in it) or the request is (a non-positive ellipse period, a picture
// in a folder that does not exist or that is the log itself): the host tool
// exits 2; otherwise writing the
// script or drawing the picture failed (no gnuplot, gnuplot's error): exit 1.
class PlotError : public std::runtime_error {
 public:
  PlotError(bool usage, const std::string& what) : std::runtime_error(what), usage_(usage) {}
  [[nodiscard]] bool usage() const { return usage_; }

 private:
  bool usage_;
};

inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// One logged position: a pose estimate, or a beacon fix (no heading).
struct Sample {
  std::int64_t utime = 0;  // µs, the message's utime (simulated time in a simulator's log)
  double x_m = 0;
  double y_m = 0;
  double theta_rad = kNoValue;  // heading as logged; NaN for a fix
  // The position block of the covariance, m², row-major xx, xy, yx, yy
  // (pose_estimate_t's covariance[0, 1, 3, 4], beacon_fix_t's covariance).
  std::array<double, 4> covariance_m2{};
};

// An estimate's error against the truth at the estimate's time.
struct Error {
  std::int64_t utime = 0;         // µs, the estimate's
  double position_m = 0;          // Euclidean distance to the truth's position
  double heading_rad = kNoValue;  // estimate − truth, wrapped to (−π, π]; NaN for a fix
};

// One series: its samples in time order (equal times in log order) and the
// errors of those within the truth's time span.
struct Track {
  std::string name;  // "truth", a pose source as logged ("fused", ...), or "fixes"
  std::vector<Sample> samples;
  std::vector<Error> errors;
};

// Events of the log by what became of them.
struct LogCounts {
  std::uint64_t events = 0;  // every event LCM's reader returned
  // On ODOLOC_TRUTH, ODOLOC_POSE_* or ODOLOC_FIX but not their type's message,
  // or (a pose, a valid fix) with a non-finite position or (a pose) heading:
  // skipped.
  std::uint64_t malformed = 0;
  std::uint64_t invalid_fixes = 0;  // beacon_fix_t with valid false: no position, skipped
  std::uint64_t other = 0;          // on the other channels: not plotted
  // Bytes after the last whole event (a truncated last event, or a header
  // LCM's reader refused, after which it reads nothing more).
  std::uint64_t unread_bytes = 0;
};

struct LogSeries {
  std::filesystem::path file;
  Track truth;                 // name "truth"; empty: no errors anywhere
  std::vector<Track> sources;  // fused, odometry, rear, front (those logged), then others by name
  Track fixes;                 // name "fixes", the valid fixes only
  LogCounts counts;
  std::int64_t start_utime = 0;  // µs, the earliest sample of any track: the plots' time zero
};

// Reads `file`. Throws PlotError (usage) naming the file when it cannot be
// opened, is a directory, does not start with LCM's event sync word (a text
// file, an empty file) or holds no truth, pose or valid fix that decodes.
[[nodiscard]] LogSeries read_log(const std::filesystem::path& file);

// The errors of `estimates` against `truth` (both in time order), linearly
// interpolated at each estimate's utime (heading along the shorter way
// round); estimates outside the truth's time span get none. Fixes (NaN
// heading) get a NaN heading error.
[[nodiscard]] std::vector<Error> errors_against(std::span<const Sample> truth,
                                                std::span<const Sample> estimates);

// `angle_rad` wrapped to (−π, π].
[[nodiscard]] double wrap_angle(double angle_rad);

// A track's errors summed up; NaN where it has no error (nothing within the
// truth's span, or a fix's heading).
struct ErrorSummary {
  std::size_t compared = 0;            // errors
  double final_position_m = kNoValue;  // of the latest estimate compared
  double rms_position_m = kNoValue;
  double final_heading_rad = kNoValue;
  double rms_heading_rad = kNoValue;
};
[[nodiscard]] ErrorSummary summarize(const Track& track);

// The tracks compared with the truth, in drawing order: the sources, then
// the fixes (when any).
[[nodiscard]] std::vector<const Track*> estimate_tracks(const LogSeries& series);

// A text table for the user: a line on the log (events, truth, what was
// skipped), then per source and the fixes: samples, compared, final and RMS
// position error (mm), final and RMS heading error (degrees); "-" for none.
[[nodiscard]] std::string summary_text(const LogSeries& series);

}  // namespace odoloc::plot
