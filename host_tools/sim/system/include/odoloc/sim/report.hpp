// The main job's table: each position source's error against the truth
// over a run of the localisation system (docs/simulator.md, "The table").
//
// Sources: rear-only and front-only odometry (reference runs of the fabric
// on the same drive), min-select odometry (the fabric's pose as the SoC
// reads it), the ultrasonic fixes alone (each valid fix against the truth
// at its time) and the fused estimate (from its initialisation on). Per
// source: the final error (the last sample, the robot standing back at its
// start), the RMS error over its samples, and the return-to-start error:
// how far the source's last position is from the start pose, which is
// where the truth ends (the path closes to well under a millimetre).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "odoloc/sw/pose_ekf.hpp"
#include "odoloc/world/tricycle.hpp"

namespace odoloc::sim {

enum class Source : std::uint8_t {
  kRearOdometry,
  kFrontOdometry,
  kMinSelect,
  kUltrasonic,
  kFused,
  kLiuFilter,  // Liu et al.'s own filter on the same run (liu_filter.hpp), when configured
};
inline constexpr std::size_t kSources = 6;
inline constexpr std::array<Source, kSources> kAllSources = {
    Source::kRearOdometry, Source::kFrontOdometry, Source::kMinSelect,
    Source::kUltrasonic,   Source::kFused,         Source::kLiuFilter};
std::string_view name(Source source);

struct SourceErrors {
  std::size_t samples = 0;
  double final_position_m = 0;   // |p - p_true| of the last sample
  double final_heading_rad = 0;  // wrapped; 0 for a source without heading
  double rms_position_m = 0;
  double rms_heading_rad = 0;
  double return_to_start_m = 0;  // |p_last - p_start|; NaN: the run was cut short
  bool has_heading = true;
  // At each return to the start (mark_return): |p - p_true|, Liu et al.'s
  // statistic (the calculated position against the point the robot
  // stopped at).
  std::vector<double> returns_m;
};

class ErrorReport {
 public:
  // `rows`: the table's sources, in kAllSources order (a source the run
  // cannot have, as the ultrasonic fixes of a lawn without beacons, is left
  // out; one it has may still have no samples: no fix at all).
  explicit ErrorReport(const world::Pose& start,
                       std::vector<Source> rows = {kAllSources.begin(), kAllSources.end()})
      : start_(start), rows_(std::move(rows)) {}
  // One sample of a source at a time its truth is known. A source without
  // heading (the ultrasonic fixes) passes has_heading = false.
  void add(Source source, const world::Pose& truth, const world::Pose& estimate,
           bool has_heading = true);
  [[nodiscard]] SourceErrors errors(Source source) const;
  [[nodiscard]] const std::vector<Source>& sources() const { return rows_; }
  // The robot stands back at its start after a lap: each source's last
  // sample's error is one return (SourceErrors::returns_m).
  void mark_return();
  // The run stopped before the tour's end (--duration): the robot is not
  // back at the start, so no source has a return-to-start error (NaN, "-").
  void cut_short() { returns_to_start_ = false; }
  // The table as text: one row per source with samples, in kAllSources
  // order; millimetres and degrees.
  [[nodiscard]] std::string table() const;

 private:
  struct Sums {
    std::size_t n = 0;
    double position2 = 0, heading2 = 0;
    world::Pose last, last_truth;
    bool has_heading = true;
    std::vector<double> returns;
  };
  world::Pose start_;
  std::vector<Source> rows_;
  bool returns_to_start_ = true;
  std::array<Sums, kSources> sums_{};
};

// Thamma's proposed study (sec. VII: "a statistical study based on the
// relationship between distance of vehicle from the transmitter and
// position error"): each ultrasonic pose's position and heading error,
// binned by the vehicle's distance from the nearest station.
class DistanceStudy {
 public:
  explicit DistanceStudy(double bin_m = 1.0) : bin_m_(bin_m) {}
  void add(double distance_m, double position_error_m, double heading_error_rad);
  // A cycle, with a pose or without.
  void count_cycle() { ++cycles_; }
  [[nodiscard]] std::size_t cycles() const { return cycles_; }
  [[nodiscard]] std::size_t poses() const;
  // One row per bin with poses: the distance range, the poses, RMS and
  // worst position error (mm), RMS heading error (degrees).
  [[nodiscard]] std::string table() const;
  struct Bin {
    std::size_t poses = 0;
    double position2 = 0, heading2 = 0, worst_m = 0;
  };
  [[nodiscard]] const std::vector<Bin>& bins() const { return bins_; }
  [[nodiscard]] double bin_m() const { return bin_m_; }

 private:
  double bin_m_;
  std::vector<Bin> bins_;  // index = floor(distance / bin_m)
  std::size_t cycles_ = 0;
};

// What the filter did with each measurement type it was given, one line
// per type with any: accepted, reopened, gated, refused (first passes, not
// replays; sw::fuse::TypeStats).
[[nodiscard]] std::string update_summary(const sw::fuse::PoseEkf& filter);

}  // namespace odoloc::sim
