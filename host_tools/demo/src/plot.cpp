#include "odoloc/demo/plot.hpp"

#include <fstream>
#include <stdexcept>

namespace odoloc::demo {

std::filesystem::path write_plot_script(const std::filesystem::path& dir,
                                        const std::string& csv_name, const std::string& png_name,
                                        const std::string& title,
                                        const std::vector<PlotSeries>& series) {
  const auto script = dir / "trajectories.gp";
  std::ofstream gp(script);
  gp << "set terminal pngcairo size " << kPlotWidth << ',' << kPlotHeight << " font ',10'\n"
     << "set output '" << png_name << "'\n"
     << "set datafile separator ','\nset key autotitle columnhead\n"
     << "set multiplot layout 1,2 title '" << title << "'\n"
     << "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset grid\n"
     << "plot '" << csv_name << "' using 2:3 with lines lt 1 lw 4 title 'ground truth'";
  for (std::size_t i = 0; i < series.size(); ++i) {
    gp << ", '' using " << series[i].x_column << ':' << series[i].x_column + 1 << " with lines lt "
       << i + 2 << " title '" << series[i].label << "'";
  }
  gp << "\nset size noratio\nset xlabel 'time [s]'\nset ylabel 'position error [mm]'\n"
     << "set logscale y\nplot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    gp << (i ? ", " : "") << "'" << csv_name << "' using 1:(column(" << series[i].error_column
       << ")+1e-3) with lines lt " << i + 2 << " title '" << series[i].label << "'";
  }
  gp << "\nunset multiplot\n";
  gp.close();
  if (!gp)
    throw std::runtime_error("cannot write " + script.string());
  return script;
}

process::ProgramResult run_gnuplot(const std::filesystem::path& script) {
  const std::filesystem::path dir = script.has_parent_path() ? script.parent_path() : ".";
  return process::run_program("gnuplot", {script.filename().string()}, dir);
}

}  // namespace odoloc::demo
