#include "odoloc/plot/log_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <string_view>
#include <vector>

#include "odoloc/output/output_file.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc/process/gnuplot.hpp"

namespace odoloc::plot {
namespace {

namespace fs = std::filesystem;
using process::gnuplot_string;

// Each known track keeps its colour in both panels (and across pictures);
// other sources take the palette's remaining colours in turn.
struct TrackColour {
  std::string_view name;
  std::string_view rgb;
};
constexpr std::array<TrackColour, 6> kColours = {{{"truth", "#000000"},
                                                  {"fused", "#d62728"},
                                                  {"odometry", "#1f77b4"},
                                                  {"rear", "#ff7f0e"},
                                                  {"front", "#2ca02c"},
                                                  {"fixes", "#9467bd"}}};
constexpr std::array<std::string_view, 5> kOtherColours = {"#8c564b", "#e377c2", "#7f7f7f",
                                                           "#bcbd22", "#17becf"};

// Errors below this are drawn at it: the error axis is logarithmic, and an
// estimate equal to the truth would otherwise vanish (or, alone, stop gnuplot).
constexpr double kErrorFloorMm = 1e-3;

// The panels' share of the picture; the rest, at the top, is the title's.
constexpr double kPanelHeight = 0.9;

// The trajectories' margin, a share of their larger extent, and the least
// extent shown, m: a robot that stands still is a cloud of fixes around a
// point, not a point in gnuplot's default ±1 m.
constexpr double kXyMargin = 0.05;
constexpr double kMinXyExtentM = 0.2;

// Ellipses of millimetres on trajectories of metres would be dots: each
// kind is magnified until its median one's largest radius is this share of
// the trajectories' extent, and the title says by how much.
constexpr double kVisibleEllipse = 0.01;
constexpr int kMaxMagnificationDecades = 9;

std::string colour_of(const std::string& name, std::size_t& others) {
  for (const TrackColour& c : kColours) {
    if (c.name == name)
      return std::string{c.rgb};
  }
  return std::string{kOtherColours[others++ % kOtherColours.size()]};
}

double seconds_since(std::int64_t utime, std::int64_t start_utime) {
  // In double: a difference of two int64 times may not fit one.
  return (static_cast<double>(utime) - static_cast<double>(start_utime)) / 1e6;
}

// The 95 % error ellipse of a sample: its centre and its closed polyline's
// offsets from it, kEllipsePoints of them, the first repeated last.
struct Ellipse {
  double x_m = 0;
  double y_m = 0;
  std::vector<std::array<double, 2>> offsets_m;
};

// The ellipse of `s`, or none when its position covariance is not a finite
// positive semi-definite one with a positive xx variance. With L the
// Cholesky factor of the covariance P (L Lᵀ = P), the points c + k L u for
// unit vectors u are exactly those at squared Mahalanobis distance k² from
// the centre c.
std::optional<Ellipse> ellipse_of(const Sample& s) {
  const auto& p = s.covariance_m2;
  const double xx = p[0], xy = (p[1] + p[2]) / 2, yy = p[3];
  if (!std::isfinite(xx) || !std::isfinite(xy) || !std::isfinite(yy) || xx <= 0 ||
      xx * yy - xy * xy < 0)
    return std::nullopt;
  const double l11 = std::sqrt(xx), l21 = xy / l11, l22 = std::sqrt(yy - l21 * l21);
  const double k = std::sqrt(kEllipseChi2);
  Ellipse e{.x_m = s.x_m, .y_m = s.y_m, .offsets_m = {}};
  for (std::size_t i = 0; i < kEllipsePoints; ++i) {
    // The last point is the first again, so that the line closes exactly.
    const double t = 2 * std::numbers::pi * static_cast<double>(i % (kEllipsePoints - 1)) /
                     static_cast<double>(kEllipsePoints - 1);
    const double u = std::cos(t), v = std::sin(t);
    e.offsets_m.push_back({k * l11 * u, k * (l21 * u + l22 * v)});
  }
  return e;
}

// The ellipses of one kind (the fused estimate's, the fixes'), drawn
// magnified by one factor.
struct EllipseSet {
  std::vector<Ellipse> ellipses;

  void add(const Sample& s) {
    if (std::optional<Ellipse> e = ellipse_of(s))
      ellipses.push_back(std::move(*e));
  }

  // The least of 1, 2, 5, 10, 20, ... (at most 10⁹) that makes the median
  // ellipse's largest radius at least kVisibleEllipse of `extent_m`: the
  // median, so that the large ellipses of a start or of a kidnapping do not
  // leave the others at a few pixels.
  [[nodiscard]] double magnification(double extent_m) const {
    std::vector<double> radii;
    for (const Ellipse& e : ellipses) {
      double radius = 0;
      for (const auto& [dx, dy] : e.offsets_m)
        radius = std::max(radius, std::hypot(dx, dy));
      radii.push_back(radius);
    }
    if (radii.empty())
      return 1;
    const auto median = radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2);
    std::ranges::nth_element(radii, median);
    double decade = 1;
    for (int e = 0; e <= kMaxMagnificationDecades; ++e, decade *= 10) {
      for (const double step : {1.0, 2.0, 5.0}) {
        if (*median * step * decade >= kVisibleEllipse * extent_m)
          return step * decade;
      }
    }
    return decade / 10;
  }

  // The data block's lines: one polyline per ellipse, "x y" lines,
  // separated by one empty line (gnuplot's `with lines` breaks there).
  [[nodiscard]] std::string lines(double magnification) const {
    std::string out;
    for (const Ellipse& e : ellipses) {
      if (!out.empty())
        out += '\n';
      for (const auto& [dx, dy] : e.offsets_m)
        out += fmt::format("{} {}\n", e.x_m + magnification * dx, e.y_m + magnification * dy);
    }
    return out;
  }
};

EllipseSet fused_ellipses(const LogSeries& series, double every_s) {
  EllipseSet set;
  for (const Track& t : series.sources) {
    if (t.name != "fused")
      continue;
    bool first = true;
    std::int64_t last = 0;
    for (const Sample& s : t.samples) {
      if (!first && seconds_since(s.utime, last) < every_s)
        continue;
      first = false;
      last = s.utime;
      set.add(s);
    }
  }
  return set;
}

std::string data_block(std::string_view name, const std::string& lines) {
  return fmt::format("${} << EOD\n{}EOD\n", name, lines);
}

// The box around every track's samples (not the ellipses: a fix's wide one
// would shrink the trajectories to a dot), with a margin, and at least
// kMinXyExtentM wide and high.
struct Bounds {
  double low_x = std::numeric_limits<double>::infinity();
  double high_x = -std::numeric_limits<double>::infinity();
  double low_y = low_x;
  double high_y = high_x;

  explicit Bounds(const std::vector<const Track*>& tracks) {
    for (const Track* t : tracks) {
      for (const Sample& s : t->samples) {
        low_x = std::min(low_x, s.x_m);
        high_x = std::max(high_x, s.x_m);
        low_y = std::min(low_y, s.y_m);
        high_y = std::max(high_y, s.y_m);
      }
    }
  }
  [[nodiscard]] bool empty() const { return low_x > high_x; }
  // m, the larger side of the samples' box.
  [[nodiscard]] double extent() const {
    return empty() ? kMinXyExtentM : std::max({high_x - low_x, high_y - low_y, kMinXyExtentM});
  }
  // "set xrange [...]\nset yrange [...]\n"; nothing without a sample (gnuplot's own).
  [[nodiscard]] std::string ranges() const {
    if (empty())
      return {};
    const double margin = kXyMargin * extent();
    const auto range = [&](char axis, double low, double high) {
      const double half = std::max((high - low) / 2 + margin, kMinXyExtentM / 2);
      const double centre = (low + high) / 2;
      return fmt::format("set {}range [{}:{}]\n", axis, centre - half, centre + half);
    };
    return range('x', low_x, high_x) + range('y', low_y, high_y);
  }
};

std::string xy_lines(const Track& t) {
  std::string out;
  for (const Sample& s : t.samples)
    out += fmt::format("{} {}\n", s.x_m, s.y_m);
  return out;
}

// time [s], position error [mm], heading error [degrees] (poses only).
std::string error_lines(const Track& t, std::int64_t start_utime) {
  std::string out;
  for (const Error& e : t.errors) {
    out += fmt::format("{} {}", seconds_since(e.utime, start_utime), e.position_m * 1e3);
    if (!std::isnan(e.heading_rad))
      out += fmt::format(" {}", e.heading_rad * 180 / std::numbers::pi);
    out += '\n';
  }
  return out;
}

// "fused 30.0 / 30.0 mm, odometry 100.0 / 57.7 mm, ...": final and RMS
// position error of each compared track.
std::string error_title(const std::vector<const Track*>& tracks) {
  std::string out;
  for (const Track* t : tracks) {
    const ErrorSummary s = summarize(*t);
    if (s.compared == 0)
      continue;
    out += fmt::format("{}{} {:.1f} / {:.1f} mm", out.empty() ? "" : ", ", t->name,
                       s.final_position_m * 1e3, s.rms_position_m * 1e3);
  }
  return out;
}

}  // namespace

std::string plot_script(const LogSeries& series, const std::string& png_name,
                        double ellipse_every_s) {
  if (!std::isfinite(ellipse_every_s) || ellipse_every_s <= 0)
    throw PlotError(true, fmt::format("the ellipse period must be a positive number of seconds, "
                                      "not {}",
                                      ellipse_every_s));
  const std::vector<const Track*> estimates = estimate_tracks(series);
  std::string script = fmt::format(
      "# Written by odoloc plot from {}; run it in the picture's folder: gnuplot SCRIPT\n"
      "set terminal pngcairo noenhanced size {},{} font 'sans,10'\n{}",
      output::printable(series.file.string()), kPlotWidth, kPlotHeight,
      process::gnuplot_output(png_name));

  // The data: trajectories, errors, ellipses.
  std::size_t others = 0;
  std::string xy_plot, position_plot, heading_plot;
  const auto add_to = [](std::string& plot, const std::string& item) {
    plot += (plot.empty() ? "plot " : ", \\\n     ") + item;
  };
  if (!series.truth.samples.empty()) {
    script += data_block("xy_truth", xy_lines(series.truth));
    add_to(xy_plot, "$xy_truth using 1:2 with lines lw 2 lc rgb '#000000' title 'truth'");
  }
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    const Track& t = *estimates[i];
    const bool fixes = &t == &series.fixes;
    const std::string colour = colour_of(t.name, others);
    const std::string title = gnuplot_string(t.name);
    // Fixes, and a source of one sample (which a line would not show), as points.
    const std::string_view style =
        fixes || t.samples.size() == 1 ? "points pt 7 ps 0.6" : "lines lw 1.5";
    script += data_block(fmt::format("xy_{}", i), xy_lines(t));
    add_to(xy_plot,
           fmt::format("$xy_{} using 1:2 with {} lc rgb '{}' title {}", i, style, colour, title));
    if (t.errors.empty())
      continue;
    script += data_block(fmt::format("error_{}", i), error_lines(t, series.start_utime));
    add_to(position_plot,
           fmt::format("$error_{} using 1:($2 > {} ? $2 : {}) with {} lc rgb '{}' title {}", i,
                       kErrorFloorMm, kErrorFloorMm, style, colour, title));
    if (!fixes)
      add_to(heading_plot, fmt::format("$error_{} using 1:3 with {} lc rgb '{}' title {}", i, style,
                                       colour, title));
  }
  const Bounds bounds([&] {
    std::vector<const Track*> all = estimates;
    all.push_back(&series.truth);
    return all;
  }());
  std::string ellipse_titles;
  const auto add_ellipses = [&](const EllipseSet& set, std::string_view name, std::string_view what,
                                std::string_view style) {
    if (set.ellipses.empty())
      return;
    const double magnification = set.magnification(bounds.extent());
    script += data_block(fmt::format("ellipses_{}", name), set.lines(magnification));
    add_to(xy_plot, fmt::format("$ellipses_{} using 1:2 with lines lw 0.8 {} lc rgb '{}' notitle",
                                name, style, colour_of(std::string{name}, others)));
    ellipse_titles += fmt::format(
        "{}{}{} ({})", ellipse_titles.empty() ? "" : ", ", what,
        magnification == 1 ? std::string{} : fmt::format(", magnified {:g}x", magnification),
        style.empty() ? "solid" : "dashed");
  };
  add_ellipses(fused_ellipses(series, ellipse_every_s), "fused",
               fmt::format("fused every {:g} s", ellipse_every_s), "");
  EllipseSet fix_ellipses;
  for (const Sample& s : series.fixes.samples)
    fix_ellipses.add(s);
  add_ellipses(fix_ellipses, "fixes", "fixes", "dt 2");

  // The panels.
  const bool errors = !position_plot.empty();
  // Two lines joined by gnuplot's own "\n": a line break inside a constant
  // would be shown as an escape.
  std::string title = gnuplot_string("odoloc plot: " + series.file.string());
  if (errors)
    title += ".\"\\n\"." + gnuplot_string("position error, final / RMS: " + error_title(estimates));
  // The ellipses are said in the panel's title: in the key, below the tracks,
  // their long entries would take a second column.
  std::string xy_title = "(a) trajectories, equal axis scale";
  if (!ellipse_titles.empty())
    xy_title += "; 95 % error ellipses: " + ellipse_titles;
  // Keys above the plots, where they cover no data; the two error plots
  // share the colours, hence the upper one's key, and the time axis, hence
  // the lower one's label and the same margins.
  script += fmt::format(
      "set multiplot title {}\nset grid\nset key outside top center horizontal\n"
      "set origin 0,0\nset size ratio -1 {},{}\n{}set xlabel 'x [m]'\nset ylabel 'y [m]'\n"
      "set title {}\n{}\nset autoscale xy\n",
      title, errors ? 0.5 : 1.0, kPanelHeight, bounds.ranges(), gnuplot_string(xy_title), xy_plot);
  if (errors) {
    script += fmt::format(
        "set size noratio 0.5,{0}\nset origin 0.5,{0}\nset lmargin 10\nset rmargin 3\n"
        "unset xlabel\nset ylabel 'position error [mm]'\nset logscale y\n"
        "set title '(b) errors against the truth at the estimate''s time'\n{1}\n"
        "unset logscale y\nset origin 0.5,0\nunset title\nunset key\n"
        "set xlabel 'time since the first sample [s]'\nset ylabel 'heading error [degrees]'\n{2}\n",
        kPanelHeight / 2, position_plot, heading_plot);
  }
  return script + "unset multiplot\nset output\n";
}

fs::path default_png(const fs::path& log) {
  fs::path png = log;
  return png.replace_extension(".png");
}

fs::path draw(const LogSeries& series, const DrawOptions& options) {
  std::error_code ec, log_ec;
  const fs::path png = fs::weakly_canonical(options.png, ec);
  if (!ec && png == fs::weakly_canonical(series.file, log_ec) && !log_ec)
    throw PlotError(
        true, fmt::format("the picture {} would replace the log itself", options.png.string()));
  const std::string script =
      plot_script(series, options.png.filename().string(), options.ellipse_every_s);
  const fs::path script_path =
      options.keep_script ? fs::path(options.png).replace_extension(".gp") : fs::path{};
  process::ProgramResult gnuplot;
  try {
    gnuplot = process::draw_with_gnuplot(script, options.png, script_path, options.stop);
  } catch (const output::OutputError& e) {
    throw PlotError(e.usage(), e.what());
  }
  if (gnuplot.interrupted)
    throw process::Interrupted();
  if (!gnuplot.launched)
    throw PlotError(false, fmt::format("cannot run gnuplot (install it: apt-get install "
                                       "gnuplot-nox): {}",
                                       process::one_line(gnuplot.message)));
  if (!gnuplot.ok())
    throw PlotError(false, fmt::format("gnuplot did not draw {}: {}", options.png.string(),
                                       process::one_line(gnuplot.message)));
  return script_path;
}

}  // namespace odoloc::plot
