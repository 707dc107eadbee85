#include "odoloc/cli/sim_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
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
  for (const sim::Source s : sim::kAllSources) {
    const sim::SourceErrors e = report.errors(s);
    rows.push_back({{"source", sim::name(s)},
                    {"samples", e.samples},
                    {"final_position_m", e.final_position_m},
                    {"final_heading_rad",
                     e.has_heading ? nlohmann::json(e.final_heading_rad) : nlohmann::json(nullptr)},
                    {"rms_position_m", e.rms_position_m},
                    {"rms_heading_rad",
                     e.has_heading ? nlohmann::json(e.rms_heading_rad) : nlohmann::json(nullptr)},
                    {"return_to_start_m", e.return_to_start_m}});
  }
  return rows;
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
  sim::ErrorSink errors(tour.drive.start);
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
  const sim::SourceErrors fused = report.errors(sim::Source::kFused);
  if (system.cut_short())
    out << "\nreturn to start: none, the run stopped before the tour's end (--duration)\n";
  else
    out << fmt::format(
        "\nreturn to start (the robot stops where it started): fused estimate {:.1f} mm from "
        "the start (Liu et al. report about 100 mm)\n",
        fused.return_to_start_m * 1e3);
  out << '\n' << sim::update_summary(system.localiser().filter());
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
