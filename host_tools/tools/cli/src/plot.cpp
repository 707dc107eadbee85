#include "odoloc/cli/plot.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/cli/locate_input.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc/plot/log_plot.hpp"
#include "odoloc/plot/log_series.hpp"
#include "odoloc/yaml/reader.hpp"

namespace odoloc::cli {
namespace {

nlohmann::json summary_json(const plot::LogSeries& series) {
  nlohmann::json tracks = nlohmann::json::array();
  for (const plot::Track* t : plot::estimate_tracks(series)) {
    const plot::ErrorSummary s = plot::summarize(*t);
    // NaN (nothing compared, a fix's heading) is JSON's null.
    tracks.push_back({{"source", t->name},
                      {"samples", t->samples.size()},
                      {"compared", s.compared},
                      {"final_position_m", s.final_position_m},
                      {"rms_position_m", s.rms_position_m},
                      {"final_heading_rad", s.final_heading_rad},
                      {"rms_heading_rad", s.rms_heading_rad}});
  }
  const plot::LogCounts& c = series.counts;
  return {{"log", series.file.string()},
          {"events", c.events},
          {"truth_samples", series.truth.samples.size()},
          {"malformed", c.malformed},
          {"invalid_fixes", c.invalid_fixes},
          {"other_channels", c.other},
          {"unread_bytes", c.unread_bytes},
          {"tracks", std::move(tracks)}};
}

}  // namespace

double parse_ellipse_every(std::string_view text) {
  const std::optional<double> seconds = yaml::finite_number(text);
  if (!seconds || *seconds <= 0)
    throw UsageError(
        fmt::format("--ellipse-every: '{}' is not a positive number of seconds", text));
  return *seconds;
}

void run_plot(const PlotCommand& command, std::ostream& out, bool json,
              const std::atomic<bool>* stop) {
  const plot::LogSeries series =
      translated<plot::PlotError>([&] { return plot::read_log(command.log); });
  if (!json)
    out << plot::summary_text(series) << std::flush;  // before gnuplot, which may fail
  const plot::DrawOptions options{.png = command.out.empty() ? plot::default_png(command.log)
                                                             : std::filesystem::path(command.out),
                                  .ellipse_every_s = command.ellipse_every_s,
                                  .keep_script = command.keep_script,
                                  .stop = stop};
  const std::filesystem::path script =
      translated<plot::PlotError>([&] { return plot::draw(series, options); });
  if (json) {
    nlohmann::json doc = summary_json(series);
    doc["png"] = options.png.string();
    doc["script"] = script.empty() ? nlohmann::json(nullptr) : nlohmann::json(script.string());
    out << json_line(doc) << '\n';
    return;
  }
  out << fmt::format(
      "picture: {}{}\n", output::printable(options.png.string()),
      script.empty() ? "" : fmt::format(" (script: {})", output::printable(script.string())));
}

}  // namespace odoloc::cli
