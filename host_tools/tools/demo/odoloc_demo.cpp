// odoloc_demo, the main job: the ground-truth tricycle drives the built-in
// 6 m square (22.5 m of path) with bumps under both rear wheels, under one rear wheel, under
// the front wheel and a front-wheel slip; its encoder waveforms drive the
// cycle-accurate odometry fabric clock by clock, once per min-select policy.
// Prints the final pose error of each, writes the trajectories as CSV and
// plots them with gnuplot.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "odoloc/board/scenario_runner.hpp"
#include "odoloc/demo/plot.hpp"
#include "odoloc/output/output_file.hpp"
#include "odoloc/world/scenarios.hpp"

namespace {

using odoloc::board::MinSelectTuning;
using odoloc::board::RunOptions;
using odoloc::board::RunResult;
using odoloc::rtl::MinSelectPolicy;

struct Variant {
  const char* label;
  const char* column;
  RunOptions options;
};

constexpr std::uint64_t kRecordEveryClocks = 500'000;  // 10 ms

// Throws output::OutputError when the file cannot be written completely
// (an output::OutputFile: whole or not at all).
void write_csv(const std::filesystem::path& file, const std::vector<Variant>& variants,
               const std::vector<RunResult>& results) {
  odoloc::output::OutputFile csv(file);
  std::ostream& out = csv.out();
  out << "time_s,truth_x_m,truth_y_m,truth_theta_rad";
  for (const Variant& v : variants) {
    out << ',' << v.column << "_x_m," << v.column << "_y_m," << v.column << "_error_mm";
  }
  out << '\n';
  const std::size_t rows = results.front().track.size();
  for (std::size_t i = 0; i < rows; ++i) {
    const auto& t = results.front().track[i];
    out << t.time_s << ',' << t.truth.x_m << ',' << t.truth.y_m << ',' << t.truth.theta_rad;
    for (const RunResult& r : results) {
      const auto& p = r.track[i];
      out << ',' << p.fabric.x_m << ',' << p.fabric.y_m << ','
          << 1e3 * std::hypot(p.fabric.x_m - p.truth.x_m, p.fabric.y_m - p.truth.y_m);
    }
    out << '\n';
  }
  csv.commit();
}

// The CSV's columns per variant: x, y, error after the four truth columns.
std::vector<odoloc::demo::PlotSeries> plot_series(const std::vector<Variant>& variants) {
  std::vector<odoloc::demo::PlotSeries> series;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const int first = 5 + 3 * static_cast<int>(i);
    series.push_back({variants[i].label, first, first + 2});
  }
  return series;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"odoloc odometry demo: ground-truth tricycle -> cycle-accurate odometry fabric"};
  std::string out_dir = "odoloc-demo";
  bool paper = false;
  app.add_option("--out", out_dir, "directory for trajectories.csv and trajectories.png");
  bool cycle_step = false;
  app.add_flag("--paper", paper, "also run the paper's memoryless min-select");
  app.add_flag("--cycle-step", cycle_step,
               "step the fabric every clock instead of fast-forwarding between events "
               "(bit-identical results, slower; for comparison)");
  CLI11_PARSE(app, argc, argv);

  const odoloc::world::Scenario scenario = odoloc::world::default_square();
  std::vector<Variant> variants = {
      {"rear only",
       "rear",
       {MinSelectPolicy::kRearOnly, MinSelectTuning::kVehicle, kRecordEveryClocks}},
      {"front only",
       "front",
       {MinSelectPolicy::kFrontOnly, MinSelectTuning::kVehicle, kRecordEveryClocks}},
      {"min-select",
       "minsel",
       {MinSelectPolicy::kPerComponent, MinSelectTuning::kVehicle, kRecordEveryClocks}},
  };
  if (paper) {
    variants.push_back(
        {"min-select (paper, memoryless)",
         "paper",
         {MinSelectPolicy::kPerComponent, MinSelectTuning::kPaper, kRecordEveryClocks}});
  }

  std::printf("odoloc odometry demo: %s\n", scenario.name.c_str());
  std::printf(
      "fabric: 4 EPPMs, sequential CORDIC, rear/front units, min-select; 50 MHz, "
      "update every 100 us\n");
  std::printf("running %zu cycle-accurate simulations on %u threads...\n", variants.size(),
              std::max(1U, std::thread::hardware_concurrency()));
  const auto start = std::chrono::steady_clock::now();
  for (Variant& v : variants)
    v.options.cycle_step = cycle_step;
  std::vector<RunResult> results(variants.size());
  {
    std::vector<std::jthread> workers;
    for (std::size_t i = 0; i < variants.size(); ++i) {
      workers.emplace_back(
          [&, i] { results[i] = odoloc::board::run_scenario(scenario, variants[i].options); });
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const auto& truth = results.front().truth;
  std::printf("\npath %.2f m, ground truth end pose x %.4f m, y %.4f m, heading %.3f deg\n\n",
              results.front().distance_m, truth.x_m, truth.y_m, truth.theta_rad * 180 / M_PI);
  std::printf("%-32s %10s %10s %12s %14s %16s\n", "odometry", "x [m]", "y [m]", "pos err [mm]",
              "head err [deg]", "ds from front");
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const RunResult& r = results[i];
    std::printf("%-32s %10.4f %10.4f %12.2f %14.4f %15.1f%%\n", variants[i].label, r.fabric.x_m,
                r.fabric.y_m, 1e3 * r.position_error_m, r.heading_error_rad * 180 / M_PI,
                100.0 * static_cast<double>(r.front_wins_ds) / static_cast<double>(r.updates));
  }
  std::uint64_t clocks = 0;
  for (const RunResult& r : results)
    clocks += r.clocks;
  std::printf("\nsimulated %zu x %.1f s (%.2f G clocks, %s) in %.1f s wall (%.1f M clocks/s)\n",
              results.size(), static_cast<double>(results.front().clocks) / 50e6,
              static_cast<double>(clocks) / 1e9, cycle_step ? "cycle-stepped" : "fast-forward",
              wall_s, static_cast<double>(clocks) / wall_s / 1e6);

  const std::filesystem::path dir(out_dir);
  try {
    std::filesystem::create_directories(dir);
    write_csv(dir / "trajectories.csv", variants, results);
    std::printf("wrote %s\n", (dir / "trajectories.csv").string().c_str());
    const auto script = odoloc::demo::write_plot_script(
        dir, "trajectories.csv", "trajectories.png",
        "odoloc: 6 m square (rounded corners) with bumps and slip", plot_series(variants));
    const odoloc::process::ProgramResult gnuplot = odoloc::demo::run_gnuplot(script);
    if (!gnuplot.ok()) {
      std::fprintf(stderr, "odoloc_demo: the plot failed%s:\n%s\n(script: %s)\n",
                   gnuplot.launched ? "" : " (install gnuplot-nox)", gnuplot.message.c_str(),
                   script.string().c_str());
      return 1;
    }
    std::printf("wrote %s\n", (dir / "trajectories.png").string().c_str());
  } catch (const std::exception& e) {  // filesystem or write errors
    std::fprintf(stderr, "odoloc_demo: %s\n", e.what());
    return 1;
  }
  return 0;
}
