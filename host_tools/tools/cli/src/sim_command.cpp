#include "odoloc/cli/sim_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <ostream>
#include <string_view>
#include <utility>
#include <vector>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc/output/output_file.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc/plot/log_plot.hpp"
#include "odoloc/plot/log_series.hpp"
#include "odoloc/sim/runner.hpp"
#include "odoloc/sim/scenario_file.hpp"
#include "odoloc/sim/stationary.hpp"
#include "odoloc/yaml/reader.hpp"

namespace odoloc::cli {

namespace {

std::unique_ptr<lcm::Connection> open_lcm(const std::string& url) {
  try {
    return std::make_unique<lcm::Connection>(url);
  } catch (const lcm::LcmError& e) {
    throw UsageError(e.what());
  }
}

nlohmann::json table_json(const sim::ErrorReport& report) {
  nlohmann::json rows = nlohmann::json::array();
  for (const sim::Source s : report.sources()) {
    const sim::SourceErrors e = report.errors(s);
    rows.push_back({{"source", sim::name(s)},
                    {"samples", e.samples},
                    {"final_position_m", e.final_position_m},
                    {"final_heading_rad",
                     e.has_heading ? nlohmann::json(e.final_heading_rad) : nlohmann::json(nullptr)},
                    {"rms_position_m", e.rms_position_m},
                    {"rms_heading_rad",
                     e.has_heading ? nlohmann::json(e.rms_heading_rad) : nlohmann::json(nullptr)},
                    {"return_to_start_m", e.return_to_start_m},
                    {"returns_m", e.returns_m}});
  }
  return rows;
}

// With two or more stops back at the start (path.lap_wait_s): each filter's
// error at every stop, RMS and worst, Liu et al.'s way ("" otherwise).
std::string returns_line(const sim::ErrorReport& report, bool liu_station) {
  std::vector<std::string> parts;
  std::size_t count = 0;
  for (const sim::Source s : {sim::Source::kLiuFilter, sim::Source::kFused}) {
    const sim::SourceErrors e = report.errors(s);
    if (e.returns_m.size() < 2)
      continue;
    double sum2 = 0;
    for (const double r : e.returns_m)
      sum2 += r * r;
    count = e.returns_m.size();
    parts.push_back(fmt::format("{} RMS {:.1f} mm, worst {:.1f} mm", sim::name(s),
                                std::sqrt(sum2 / static_cast<double>(count)) * 1e3,
                                *std::ranges::max_element(e.returns_m) * 1e3));
  }
  if (parts.empty())
    return "";
  return fmt::format(
      "returns to the start ({} stops; the estimate against where the robot stopped): {}{}\n",
      count, fmt::join(parts, "; "),
      liu_station ? " (Liu et al.: 20 returns within about 100 mm)" : "");
}

nlohmann::json updates_json(const sw::fuse::PoseEkf& filter) {
  nlohmann::json types = nlohmann::json::object();
  for (std::size_t i = 0; i < sw::fuse::kMeasurementTypes; ++i) {
    const auto type = static_cast<sw::fuse::MeasurementType>(i);
    const sw::fuse::TypeStats& s = filter.stats(type);
    types[std::string(sw::fuse::name(type))] = {{"accepted", s.accepted},
                                                {"reopened", s.reopened},
                                                {"gated", s.gated},
                                                {"refused", s.refused}};
  }
  return types;
}

// Kleeman's stationary experiment: each point's fixes, their spread beside
// the paper's, then the grid's worst error beside the paper's bound.
void run_stationary(const sim::Scenario& scenario, const sim::SystemOptions& options,
                    std::ostream& out, bool json) {
  const sim::Stationary& plan = *scenario.stationary;
  const auto mm = [](double m) { return m * 1e3; };
  // Millimetres to one decimal, "-" for a figure there is none of (no fix).
  const auto figure = [&](double m) {
    return std::isnan(m) ? std::string("-") : fmt::format("{:.1f}", mm(m));
  };
  nlohmann::json points = nlohmann::json::array();
  if (!json)
    out << fmt::format(
               "odoloc sim: {}, seed {}: the robot standing, the ultrasonic fixes alone\n\n",
               output::printable(scenario.tour.name), options.seed)
        << fmt::format("{:<18} {:>6} {:>7} {:>11} {:>10} {:>10} {:>10}   {}\n", "point (m)",
                       "fixes", "cycles", "mean error", "sd x (mm)", "sd y (mm)", "worst (mm)",
                       "the paper's sd x / y (mm)")
        << std::flush;
  const auto row = [&](const sim::Standing& s, const std::optional<world::Vec2>& paper) {
    const double mean_error = std::hypot(s.mean_m.x_m - s.truth.x_m, s.mean_m.y_m - s.truth.y_m);
    if (json) {
      nlohmann::json p = {{"x_m", s.truth.x_m},         {"y_m", s.truth.y_m},
                          {"fixes", s.fixes.size()},    {"cycles", s.cycles},
                          {"mean_error_m", mean_error}, {"sd_x_m", s.sd_m.x_m},
                          {"sd_y_m", s.sd_m.y_m},       {"worst_m", s.worst_m}};
      if (paper)
        p["paper_sd_m"] = {paper->x_m, paper->y_m};
      points.push_back(p);
      return;
    }
    out << fmt::format("({:.3f}, {:.3f})   {:>6} {:>7} {:>8} mm {:>10} {:>10} {:>10}   {}\n",
                       s.truth.x_m, s.truth.y_m, s.fixes.size(), s.cycles, figure(mean_error),
                       figure(s.sd_m.x_m), figure(s.sd_m.y_m), figure(s.worst_m),
                       paper ? fmt::format("{:.1f} / {:.1f}", mm(paper->x_m), mm(paper->y_m))
                             : std::string("-"))
        << std::flush;
  };
  for (const sim::StandingPoint& p : plan.points)
    row(sim::measure_standing(scenario, p.position, p.fixes, options), p.paper_sd_m);
  nlohmann::json grid_json;
  if (plan.grid) {
    const std::vector<world::Vec2> grid =
        sim::grid_points(*scenario.tour.acoustics.room, *plan.grid);
    double worst_m = 0;
    world::Vec2 worst_at;
    std::vector<world::Vec2> short_of_fixes;  // far beacons unheard (docs/scenarios.md)
    for (const world::Vec2& p : grid) {
      const sim::Standing s = sim::measure_standing(scenario, p, plan.grid->fixes, options);
      if (s.fixes.size() < plan.grid->fixes)
        short_of_fixes.push_back(p);
      if (s.worst_m >= worst_m) {
        worst_m = s.worst_m;
        worst_at = p;
      }
    }
    const std::string paper =
        plan.grid->paper_worst_m
            ? fmt::format(" (the paper: within {:.0f} mm)", mm(*plan.grid->paper_worst_m))
            : std::string();
    if (json) {
      nlohmann::json short_json = nlohmann::json::array();
      for (const world::Vec2& p : short_of_fixes)
        short_json.push_back({p.x_m, p.y_m});
      grid_json = {{"points", grid.size()},     {"fixes_each", plan.grid->fixes},
                   {"worst_m", worst_m},        {"worst_x_m", worst_at.x_m},
                   {"worst_y_m", worst_at.y_m}, {"short_of_fixes", short_json}};
      if (plan.grid->paper_worst_m)
        grid_json["paper_worst_m"] = *plan.grid->paper_worst_m;
    } else {
      std::vector<std::string> named;
      for (const world::Vec2& p : short_of_fixes)
        named.push_back(fmt::format("({:g}, {:g})", p.x_m, p.y_m));
      out << fmt::format(
          "\nover the floor: {} points {} m apart, {} fixes each: the worst fix {:.1f} mm from "
          "the truth, at ({:.2f}, {:.2f}){}\n",
          grid.size(), plan.grid->step_m, plan.grid->fixes, mm(worst_m), worst_at.x_m, worst_at.y_m,
          paper);
      if (!short_of_fixes.empty())
        out << fmt::format("{} points had fewer fixes: {}\n", short_of_fixes.size(),
                           fmt::join(named, " "));
    }
  }
  if (json) {
    nlohmann::json j = {{"scenario", scenario.tour.name}, {"points", points}};
    if (plan.grid)
      j["grid"] = grid_json;
    out << json_line(j) << '\n';
  }
}

}  // namespace

void run_sim(const SimCommand& command, std::ostream& out, bool json,
             const std::atomic<bool>* stop) {
  const auto started = std::chrono::steady_clock::now();
  // A file, else a built-in scenario's name; the room tour by default.
  const sim::ScenarioOverrides overrides{.laps = command.laps, .speed_mps = command.speed_mps};
  sim::Scenario scenario = translated<yaml::InputError>([&] {
    if (command.scenario.empty())
      return sim::default_scenario(overrides);
    if (std::filesystem::exists(command.scenario) || !sim::find_builtin_scenario(command.scenario))
      return sim::load_scenario(command.scenario, overrides);
    const sim::BuiltinScenario& builtin = *sim::find_builtin_scenario(command.scenario);
    return sim::parse_scenario(std::string(builtin.text), fmt::format("{} (built in)", builtin.key),
                               overrides);
  });
  const std::uint64_t seed = command.seed.value_or(scenario.seed);
  if (command.duration_s && !(*command.duration_s > 0 && *command.duration_s <= 1e4))
    throw UsageError("--duration must be more than 0 and at most 10000 s");
  if (scenario.stationary) {
    if (!command.out.empty() || !command.lcm_url.empty() || command.realtime ||
        command.duration_s || command.no_beacon_ranges)
      throw UsageError(
          "a stationary scenario prints its table only: no --out, --lcm-url, --realtime, "
          "--duration or --no-beacon-ranges");
    run_stationary(scenario, {.seed = seed, .cycle_step = command.cycle_step, .stop = stop}, out,
                   json);
    return;
  }
  // With --out every file is made in a staging folder in DIR and delivered
  // only when the run and the plot are done (output::OutputFile: whole, a
  // device or FIFO written to, a link followed): an error or a signal leaves
  // DIR as it was.
  const std::filesystem::path dir = command.out;
  std::vector<std::string> names;
  if (!command.out.empty()) {
    names = {"odoloc.lcmlog", "trajectories.csv", "fixes.csv"};
    if (!command.no_plot)
      names.emplace_back("localisation.png");
  }
  std::optional<output::OutputFolder> folder;
  std::vector<std::unique_ptr<output::OutputFile>> outputs;
  std::optional<output::Staging> staging;
  translated<output::OutputError>([&] {
    if (names.empty())
      return;
    folder.emplace(dir, output::OutputFolder::Create::kParents);
    for (const std::string& name : names)
      outputs.push_back(std::make_unique<output::OutputFile>(dir / name));
    staging.emplace(dir, "sim");
  });
  const auto staged = [&](std::string_view name) {
    return staging ? staging->dir() / name : std::filesystem::path{};
  };
  const std::filesystem::path log = staged("odoloc.lcmlog");
  const std::filesystem::path trajectories_csv = staged("trajectories.csv");
  const std::filesystem::path fixes_csv = staged("fixes.csv");
  const std::filesystem::path png =
      command.no_plot ? std::filesystem::path{} : staged("localisation.png");
  const std::string live_url =
      !command.lcm_url.empty() ? command.lcm_url : (command.out.empty() ? lcm::kDefaultUrl : "");
  // Opened before the minute of simulation: a bad URL fails at once.
  std::unique_ptr<lcm::Connection> live = live_url.empty() ? nullptr : open_lcm(live_url);

  sim::LocalisationSystem system(std::move(scenario),
                                 {.seed = seed,
                                  .step_s = 0.01,
                                  .cycle_step = command.cycle_step,
                                  .encoder_period_s = 0.1,
                                  .until_s = command.duration_s.value_or(0),
                                  .fuse_beacon_ranges = !command.no_beacon_ranges,
                                  .stop = stop});
  const world::RoomTour& tour = system.tour();
  if (!json)
    out << fmt::format("odoloc sim: {}, {:.1f} s to simulate, seed {}{}\n",
                       output::printable(tour.name),  // a scenario file's: data
                       tour.duration_s, seed,
                       live ? fmt::format("; publishing on {}", live_url) : std::string())
        << std::flush;
  sim::Runner runner(system, {.realtime = command.realtime, .allow_write = command.allow_write});
  sim::ErrorSink errors(system);
  runner.add_sink(errors);
  std::optional<sim::CsvSink> csv;
  if (!command.out.empty()) {
    try {
      csv.emplace(trajectories_csv.string(), fixes_csv.string());
    } catch (const std::runtime_error& e) {
      throw FileError(e.what());
    }
    runner.add_sink(*csv);
  }
  std::optional<sim::LcmSink> live_sink, log_sink;
  if (live) {
    live_sink.emplace(*live);
    runner.add_sink(*live_sink);
    runner.add_live(*live);
  }
  if (!log.empty()) {
    try {
      log_sink.emplace(log.string());
    } catch (const std::runtime_error& e) {
      throw FileError(e.what());
    }
    runner.add_sink(*log_sink);
  }
  sim::RunSummary summary;
  try {
    summary = runner.run(stop, std::cerr);
  } catch (const std::runtime_error& e) {  // a sink's file
    throw FileError(e.what());
  }
  if (stop != nullptr && stop->load())
    throw Interrupted();
  if (!png.empty()) {
    try {
      // Titled with the log as delivered, not its staging name.
      plot::LogSeries series = plot::read_log(log);
      series.file = dir / "odoloc.lcmlog";
      plot::draw(series, {.png = png, .ellipse_every_s = 1.0, .keep_script = false, .stop = stop});
    } catch (const plot::PlotError& e) {
      throw FileError(e.what());
    }
  }
  translated<output::OutputError>([&] {
    for (std::size_t i = 0; i < outputs.size(); ++i)
      outputs[i]->commit_from(staged(names[i]));
  });
  if (folder)
    folder->keep();

  const sim::ErrorReport& report = errors.report();
  // Everything: the world's pre-pass, the reference runs, the loop, the plot.
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (json) {
    nlohmann::json j = {{"scenario", tour.name},
                        {"simulated_s", summary.simulated_s},
                        {"wall_s", wall_s},
                        {"loop_wall_s", summary.wall_s},
                        {"fabric_clocks", summary.clocks},
                        {"skipped_clocks", summary.skipped_clocks},
                        {"kept_up", summary.kept_up},
                        {"malformed_messages", summary.malformed},
                        {"table", table_json(report)},
                        {"filter_updates", updates_json(system.localiser().filter())}};
    if (const sim::DistanceStudy* study = errors.distance_study()) {
      nlohmann::json bins = nlohmann::json::array();
      for (std::size_t i = 0; i < study->bins().size(); ++i) {
        const sim::DistanceStudy::Bin& b = study->bins()[i];
        if (b.poses == 0)
          continue;
        const auto n = static_cast<double>(b.poses);
        bins.push_back({{"from_m", static_cast<double>(i) * study->bin_m()},
                        {"to_m", static_cast<double>(i + 1) * study->bin_m()},
                        {"poses", b.poses},
                        {"rms_position_m", std::sqrt(b.position2 / n)},
                        {"worst_position_m", b.worst_m},
                        {"rms_heading_rad", std::sqrt(b.heading2 / n)}});
      }
      j["thamma"] = {{"cycles", study->cycles()}, {"poses", study->poses()}, {"by_distance", bins}};
    }
    if (const sw::fuse::LiuFilter* liu = system.localiser().liu_filter())
      j["liu_filter"] = {{"fixes", liu->stats().fixes},
                         {"fixes_gated", liu->stats().fixes_gated},
                         {"headings", liu->stats().headings},
                         {"headings_gated", liu->stats().headings_gated}};
    if (!command.out.empty())
      j["files"] = {{"log", (dir / "odoloc.lcmlog").string()},
                    {"trajectories", (dir / "trajectories.csv").string()},
                    {"fixes", (dir / "fixes.csv").string()},
                    {"plot", command.no_plot ? "" : (dir / "localisation.png").string()}};
    out << json_line(j) << '\n';
    return;
  }
  out << fmt::format(
             "{:.1f} s simulated in {:.1f} s of which the loop {:.1f} s ({:.1f}x real time), {} "
             "fabric clocks\n\n",
             summary.simulated_s, wall_s, summary.wall_s, summary.simulated_s / summary.wall_s,
             summary.clocks)
      << report.table();
  // The papers' figures beside ours: Liu's return to the start (with his
  // base station), Kurian's min-select against either set of wheels alone.
  const sim::SourceErrors fused = report.errors(sim::Source::kFused);
  if (system.cut_short())
    out << "\nreturn to start: none, the run stopped before the tour's end (--duration)\n";
  else if (const sim::SourceErrors liu = report.errors(sim::Source::kLiuFilter); liu.samples > 0)
    out << fmt::format(
        "\nreturn to start (the robot stops where it started): Liu et al.'s filter {:.1f} mm, "
        "the fused estimate {:.1f} mm from the start (Liu et al. report about 100 mm)\n",
        liu.return_to_start_m * 1e3, fused.return_to_start_m * 1e3);
  else
    out << fmt::format(
        "\nreturn to start (the robot stops where it started): fused estimate {:.1f} mm from "
        "the start{}\n",
        fused.return_to_start_m * 1e3,
        system.tour().station ? " (Liu et al. report about 100 mm)" : "");
  if (const std::string returns = returns_line(report, system.tour().station.has_value());
      !returns.empty())
    out << returns;
  // Kurian's comparison where the drive has something for min-select to drop.
  const world::Disturbances& disturbances = system.tour().drive.disturbances;
  if (!disturbances.bumps.empty() || !disturbances.slips.empty())
    out << fmt::format(
        "humps and slip: min-select odometry RMS {:.1f} mm beside rear-only {:.1f} mm and "
        "front-only {:.1f} mm (Kurian et al.: the smaller increments drop the over-counts; they "
        "give no figure)\n",
        report.errors(sim::Source::kMinSelect).rms_position_m * 1e3,
        report.errors(sim::Source::kRearOdometry).rms_position_m * 1e3,
        report.errors(sim::Source::kFrontOdometry).rms_position_m * 1e3);
  if (const sim::DistanceStudy* study = errors.distance_study()) {
    out << fmt::format(
               "\nThamma's poses against the distance from the stations ({} of {} cycles gave a "
               "pose; Thamma proposes the study and gives no figure):\n",
               study->poses(), study->cycles())
        << study->table();
  }
  out << '\n' << sim::update_summary(system.localiser().filter());
  if (const sw::fuse::LiuFilter* liu = system.localiser().liu_filter())
    out << fmt::format(
        "Liu et al.'s filter: {} fixes fused, {} gated (beyond {:.0f} mm); {} headings fused, {} "
        "gated (beyond {:.1f} deg)\n",
        liu->stats().fixes, liu->stats().fixes_gated, liu->options().fix_gate_m * 1e3,
        liu->stats().headings, liu->stats().headings_gated,
        liu->options().heading_gate_rad * 180 / std::numbers::pi);
  if (live)
    out << fmt::format("register bridge: {} served, {} refused, {} errors; {} malformed messages\n",
                       summary.bridge.served, summary.bridge.refused, summary.bridge.errors,
                       summary.malformed);
  if (!command.out.empty()) {
    std::vector<std::string> written;
    for (const std::string& name : names)
      written.push_back(output::printable((dir / name).string()));
    out << fmt::format("wrote {}\n", fmt::join(written, ", "));
  }
}

}  // namespace odoloc::cli
