// The demo's plot step: a gnuplot script next to its data, run by gnuplot in
// that directory, with gnuplot's own messages kept.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "odoloc/process/run_program.hpp"

namespace odoloc::demo {

// One trajectory of trajectories.csv: its x column (y follows), its error
// column, and its legend.
struct PlotSeries {
  std::string label;
  int x_column;
  int error_column;
};

// The PNG the script draws.
inline constexpr int kPlotWidth = 1400;
inline constexpr int kPlotHeight = 650;

// Writes `dir`/trajectories.gp: two panels (trajectories with the ground truth
// in columns 2:3, position error over time in column 1) of `dir`/`csv_name`
// into `dir`/`png_name`. Every path in the script is relative to `dir`, so
// `cd dir && gnuplot trajectories.gp` works; every name in it is a
// process::gnuplot_string. Throws output::OutputError when the script
// cannot be written (output::write_file).
std::filesystem::path write_plot_script(const std::filesystem::path& dir,
                                        const std::string& csv_name, const std::string& png_name,
                                        const std::string& title,
                                        const std::vector<PlotSeries>& series);

// Runs gnuplot on `script` in the script's directory.
process::ProgramResult run_gnuplot(const std::filesystem::path& script);

}  // namespace odoloc::demo
