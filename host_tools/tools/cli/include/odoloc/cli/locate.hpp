// `odoloc locate` (docs/host-tool.md#beacon-fixes-locate): beacon fixes
// from a layout and recorded arrivals, with the soc_software solvers, as a
// table, JSON Lines or a gnuplot picture. No target: the command reads files only.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/cli/locate_input.hpp"
#include "odoloc/sw/beacon_fix.hpp"

namespace odoloc::cli {

enum class LocateSolver : std::uint8_t {
  kGaussNewton,  // multilaterate(): every beacon, echoes tried, optionally c estimated
  kLongsolve,    // Kleeman's longsolve, one instance following the robot over the cycles
  kKleeman,      // Kleeman's three-beacon solver
};

struct LocateCommand {
  std::string layout;    // YAML
  std::string arrivals;  // CSV
  LocateSolver solver = LocateSolver::kGaussNewton;
  std::optional<double> temperature_c;  // overrides the layout's
  bool calibrate_c = false;             // gauss-newton: c as a state
  // kleeman: three beacon ids; empty: per cycle the usable triple with the
  // least predicted error at the start point.
  std::vector<std::string> triple;
  std::string plot;  // OUT.png or OUT.svg; empty: no plot
};

// The option values, checked alone and together (no file is read); each
// throws UsageError naming the option.
[[nodiscard]] LocateSolver parse_solver(std::string_view name);
[[nodiscard]] double parse_temperature(std::string_view text);
[[nodiscard]] std::vector<std::string> parse_triple(std::string_view text);
void check_locate(const LocateCommand& command);

struct CycleFix {
  std::uint64_t cycle = 0;
  sw::locate::Fix fix;
};

// One fix per cycle, in the cycles' order. The temperature (the command's,
// else the layout's) sets the speed of sound the solvers assume; the
// previous valid fix is the next start point (kleeman) and decides between
// mirror solutions (gauss-newton with three beacons). Interrupted when
// `stop` is set (checked before each cycle).
[[nodiscard]] std::vector<CycleFix> locate_fixes(const LocateLayout& layout,
                                                 std::span<const ArrivalCycle> cycles,
                                                 const LocateCommand& command,
                                                 const std::atomic<bool>* stop = nullptr);

// One JSON object: the whole Fix, beacons by id.
[[nodiscard]] nlohmann::json fix_json(const CycleFix& fix, const LocateLayout& layout);
// A header line, then one line per cycle.
[[nodiscard]] std::string fix_table(std::span<const CycleFix> fixes, const LocateLayout& layout);

// The error ellipse of a 2 x 2 covariance at `sigmas`: semi-axes (major
// first) and the major axis' angle from +x, radians in (-pi/2, pi/2].
struct ErrorEllipse {
  double major_m = 0;
  double minor_m = 0;
  double angle_rad = 0;
};
[[nodiscard]] ErrorEllipse error_ellipse(const Eigen::Matrix2d& covariance_m2, double sigmas);

// The picture --plot draws, pixels (PNG) or points (SVG).
inline constexpr int kLocatePlotWidth = 1000;
inline constexpr int kLocatePlotHeight = 800;

// The gnuplot script drawing beacons, valid fixes and their 2-sigma
// ellipses (the terminal from `output`'s extension, .png or .svg) into the
// variable `picture`, by default `output`'s file name
// (process::gnuplot_output).
[[nodiscard]] std::string plot_script(std::span<const CycleFix> fixes, const LocateLayout& layout,
                                      const std::string& output);

// Reads the files, solves, prints (text, or one JSON object per line per
// cycle), then plots (process::draw_with_gnuplot: the picture is an
// output::OutputFile); FileError when gnuplot does not draw the picture,
// Interrupted when `stop` is set.
void run_locate(const LocateCommand& command, std::ostream& out, bool json,
                const std::atomic<bool>* stop);

}  // namespace odoloc::cli
