#include "odoloc/demo/plot.hpp"

#include <sstream>

#include "odoloc/output/output_file.hpp"
#include "odoloc/process/gnuplot.hpp"

namespace odoloc::demo {

std::filesystem::path write_plot_script(const std::filesystem::path& dir,
                                        const std::string& csv_name, const std::string& png_name,
                                        const std::string& title,
                                        const std::vector<PlotSeries>& series) {
  using process::gnuplot_string;
  const auto script = dir / "trajectories.gp";
  const std::string csv = gnuplot_string(csv_name);
  std::ostringstream gp;
  gp << "set terminal pngcairo noenhanced size " << kPlotWidth << ',' << kPlotHeight
     << " font ',10'\n"
     << "set output " << gnuplot_string(png_name) << "\n"
     << "set datafile separator ','\nset key autotitle columnhead\n"
     << "set multiplot layout 1,2 title " << gnuplot_string(title) << "\n"
     << "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset grid\n"
     << "plot " << csv << " using 2:3 with lines lt 1 lw 4 title 'ground truth'";
  for (std::size_t i = 0; i < series.size(); ++i) {
    gp << ", '' using " << series[i].x_column << ':' << series[i].x_column + 1 << " with lines lt "
       << i + 2 << " title " << gnuplot_string(series[i].label);
  }
  gp << "\nset size noratio\nset xlabel 'time [s]'\nset ylabel 'position error [mm]'\n"
     << "set logscale y\nplot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    gp << (i ? ", " : "") << csv << " using 1:(column(" << series[i].error_column
       << ")+1e-3) with lines lt " << i + 2 << " title " << gnuplot_string(series[i].label);
  }
  gp << "\nunset multiplot\n";
  output::write_file(script, gp.str());
  return script;
}

process::ProgramResult run_gnuplot(const std::filesystem::path& script) {
  const std::filesystem::path dir = script.has_parent_path() ? script.parent_path() : ".";
  return process::run_program("gnuplot", {script.filename().string()}, dir);
}

}  // namespace odoloc::demo
