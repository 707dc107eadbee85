// The picture of `odoloc plot` (docs/host-tool.md): a gnuplot script, its
// data inline, drawing one PNG of a log's series (log_series.hpp):
//  (a) left, the XY trajectories at equal axis scale: truth, every pose
//      source, the fixes as points, the fused estimate's 95 % error ellipses
//      every `ellipse_every_s` seconds and every fix's (magnified when
//      small);
//  (b) right, against time since the log's first sample: the position error
//      of each source (mm, log scale) and the fixes' (points) above, the
//      heading error (degrees) below.
// A log without truth has no errors: the picture is then panel (a) alone.
#pragma once

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <string>

#include "odoloc/plot/log_series.hpp"

namespace odoloc::plot {

// The picture, pixels.
inline constexpr int kPlotWidth = 1600;
inline constexpr int kPlotHeight = 800;

// −2 ln 0.05: the 95 % quantile of χ² with 2 degrees of freedom, the squared
// Mahalanobis radius of the drawn ellipses.
inline constexpr double kEllipseChi2 = 5.991464547107979;
// Points of each drawn ellipse's closed polyline (the first repeated last).
inline constexpr std::size_t kEllipsePoints = 49;

// The script: the data blocks $ellipses_fused and $ellipses_fixes hold one
// closed polyline per ellipse, kEllipsePoints "x y" lines each, ellipses
// separated by one empty line; each kind magnified about the centres by the
// least of 1, 2, 5, 10, 20, ... that makes its median ellipse's largest
// radius 1 % of the larger side of the trajectories' box, which panel (a)'s
// title says ("magnified 20x"). The fused ellipses are those of the first
// fused sample and then of each first sample at least `ellipse_every_s`
// seconds after the last one chosen; a fix has its own. An ellipse needs a
// finite, positive semi-definite position covariance with positive xx
// variance, or it is left out (the sample stays chosen). The picture goes
// to the gnuplot variable `picture`, by default `png_name`
// (process::gnuplot_output); every name in the script is a
// process::gnuplot_string. Throws PlotError (usage) when `ellipse_every_s`
// is not a positive finite number.
[[nodiscard]] std::string plot_script(const LogSeries& series, const std::string& png_name,
                                      double ellipse_every_s);

struct DrawOptions {
  // The picture to write: an output::OutputFile (a file is replaced whole,
  // a device or FIFO written to, a symbolic link followed).
  std::filesystem::path png;
  double ellipse_every_s = 1.0;  // s, > 0
  // Keep the script next to the picture (png with extension .gp), to edit
  // and run again (`cd DIR && gnuplot NAME.gp`); else it is a temporary file.
  bool keep_script = false;
  const std::atomic<bool>* stop = nullptr;  // set: gnuplot is ended, nothing written
};

// `log` with its extension replaced by .png ("run.lcmlog" → "run.png").
[[nodiscard]] std::filesystem::path default_png(const std::filesystem::path& log);

// Draws the picture with gnuplot in a private staging folder and delivers
// it (process::draw_with_gnuplot). Returns the kept script's path, or an
// empty path. Throws PlotError: usage when the ellipse period is bad, the
// picture cannot be written there (a folder, a missing folder, a link to
// nothing) or would replace the log itself; otherwise when an output cannot
// be written, gnuplot cannot be run ("install gnuplot-nox") or does not
// draw the picture (its message on one line; nothing is written).
// process::Interrupted when `stop` was set.
std::filesystem::path draw(const LogSeries& series, const DrawOptions& options);

}  // namespace odoloc::plot
