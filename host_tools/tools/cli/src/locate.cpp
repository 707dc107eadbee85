#include "odoloc/cli/locate.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <ostream>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/output/output_file.hpp"
#include "odoloc/process/gnuplot.hpp"
#include "odoloc/sw/kleeman_solver.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/yaml/reader.hpp"

namespace odoloc::cli {
namespace {

namespace fs = std::filesystem;
namespace loc = sw::locate;

struct SolverName {
  std::string_view name;
  LocateSolver solver;
};
constexpr std::array<SolverName, 3> kSolvers = {{{"gauss-newton", LocateSolver::kGaussNewton},
                                                 {"longsolve", LocateSolver::kLongsolve},
                                                 {"kleeman", LocateSolver::kKleeman}}};

// The picture's error ellipses: 2 sigma, magnified so that the largest is
// at least kVisibleEllipse of the picture's extent (a 2-sigma of millimetres
// in a room of metres would be a dot).
constexpr double kPlotSigmas = 2.0;
constexpr double kVisibleEllipse = 0.02;

// `decimals` decimals; "-" for NaN (no value), never "nan".
std::string number(double value, int decimals) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, decimals) : std::string{"-"};
}

double correlation(const Eigen::Matrix2d& c) {
  return c(0, 1) / std::sqrt(c(0, 0) * c(1, 1));
}

// "used:B0,B1,B2[1],B3 missing:B4 outlier:B5": the statuses in the order of
// BeaconStatus, used first; [k] marks a candidate other than the first, (B)
// the beacon a triangle-inequality rejection was against.
std::string beacon_summary(const loc::Fix& fix, const LocateLayout& layout) {
  std::vector<std::pair<loc::BeaconStatus, std::string>> groups;
  for (const loc::BeaconUse& u : fix.beacons) {
    std::string item = layout.ids.at(static_cast<std::size_t>(u.beacon));
    if (u.status == loc::BeaconStatus::kUsed && u.candidate > 0)
      item += fmt::format("[{}]", u.candidate);
    if (u.rejected_by >= 0)
      item += fmt::format("({})", layout.ids.at(static_cast<std::size_t>(u.rejected_by)));
    const auto group = std::ranges::find(groups, u.status, &decltype(groups)::value_type::first);
    if (group == groups.end())
      groups.emplace_back(u.status, fmt::format("{}:{}", loc::name(u.status), item));
    else
      group->second += "," + item;
  }
  std::ranges::sort(groups, {}, &decltype(groups)::value_type::first);
  std::string out;
  for (const auto& [status, text] : groups)
    out += (out.empty() ? "" : " ") + text;
  return out;
}

// Kleeman's solvers have no speed-of-sound state: their distances are
// rescaled to c_true / c_used first (d = k r + o becomes d / k = r + o / k).
loc::RangeSet rescaled(loc::RangeSet ranges, double speed_of_sound_mps) {
  const double scale = speed_of_sound_mps / ranges.speed_of_sound_mps;
  for (loc::BeaconRange& b : ranges.beacons) {
    for (loc::RangeCandidate& c : b.candidates) {
      c.distance_m *= scale;
      c.sd_m *= scale;
    }
  }
  ranges.speed_of_sound_mps = speed_of_sound_mps;
  return ranges;
}

loc::Vec2 centroid(const loc::BeaconLayout& layout) {
  loc::Vec2 sum{0, 0};
  for (const loc::Beacon& b : layout.beacons) {
    sum.x += b.position_m.x;
    sum.y += b.position_m.y;
  }
  const auto n = static_cast<double>(layout.beacons.size());
  return {sum.x / n, sum.y / n};
}

// Kleeman's three-beacon fix on the usable triple whose fix would scatter
// least at `start` (DRMS from its sensitivity and the deviations).
loc::Fix best_triple_fix(const loc::BeaconLayout& layout, const loc::RangeSet& ranges,
                         loc::Vec2 start) {
  const loc::Prepared prepared = loc::prepare(layout, ranges);
  const std::vector<loc::Observation>& obs = prepared.primaries;
  std::optional<loc::Triple> best;
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < obs.size(); ++i) {
    for (std::size_t j = i + 1; j < obs.size(); ++j) {
      for (std::size_t k = j + 1; k < obs.size(); ++k) {
        const loc::Triple triple{obs[i].beacon, obs[j].beacon, obs[k].beacon};
        const std::optional<loc::TripleSensitivity> s =
            loc::triple_sensitivity(layout, triple, start);
        if (!s)
          continue;
        const Eigen::Vector3d variance(obs[i].sd_m * obs[i].sd_m, obs[j].sd_m * obs[j].sd_m,
                                       obs[k].sd_m * obs[k].sd_m);
        const double error = (*s * variance.asDiagonal() * s->transpose()).trace();
        if (error < least) {
          least = error;
          best = triple;
        }
      }
    }
  }
  if (best)
    return loc::solve_triple(layout, ranges, *best, start);
  loc::Fix fix;
  fix.solver = loc::Solver::kKleemanTriple;
  fix.speed_of_sound_mps = ranges.speed_of_sound_mps;
  fix.reason = obs.size() >= 3           ? loc::NoFixReason::kDegenerateGeometry
               : prepared.any_non_finite ? loc::NoFixReason::kNonFiniteInput
                                         : loc::NoFixReason::kTooFewBeacons;
  fix.beacons = prepared.uses;
  for (loc::BeaconUse& u : fix.beacons) {
    if (u.status == loc::BeaconStatus::kUsed)
      u.status = loc::BeaconStatus::kUnused;
  }
  return fix;
}

// The script's data blocks: beacons, then the valid fixes with their
// ellipses; and the ellipses' key title, which says the magnification.
struct PlotData {
  std::string blocks;
  std::string ellipse_title;
};

PlotData plot_data(std::span<const CycleFix> fixes, const LocateLayout& layout) {
  double low_x = std::numeric_limits<double>::infinity(), high_x = -low_x, low_y = low_x,
         high_y = -low_x, largest = 0;
  const auto extend = [&](loc::Vec2 p) {
    low_x = std::min(low_x, p.x);
    high_x = std::max(high_x, p.x);
    low_y = std::min(low_y, p.y);
    high_y = std::max(high_y, p.y);
  };
  PlotData out{"$beacons << EOD\n", "2-sigma error ellipses"};
  for (std::size_t i = 0; i < layout.ids.size(); ++i) {
    const loc::Vec2 p = layout.layout.beacons[i].position_m;
    extend(p);
    out.blocks += fmt::format("{} {} \"{}\"\n", p.x, p.y, layout.ids[i]);
  }
  std::vector<std::pair<const CycleFix*, ErrorEllipse>> valid;
  for (const CycleFix& f : fixes) {
    if (!f.fix.valid)
      continue;
    extend(f.fix.position_m);
    const ErrorEllipse e = f.fix.covariance_m2.allFinite()
                               ? error_ellipse(f.fix.covariance_m2, kPlotSigmas)
                               : ErrorEllipse{};
    largest = std::max(largest, e.major_m);
    valid.emplace_back(&f, e);
  }
  const double extent = std::max(high_x - low_x, high_y - low_y);
  double magnification = 1;
  if (largest > 0 && largest < kVisibleEllipse * extent) {
    magnification = std::pow(10.0, std::ceil(std::log10(kVisibleEllipse * extent / largest)));
    out.ellipse_title += fmt::format(", magnified {:g}x", magnification);
  }
  out.blocks += "EOD\n$fixes << EOD\n";
  for (const auto& [f, e] : valid) {
    // gnuplot's ellipses take diameters and degrees.
    out.blocks += fmt::format("{} {} {} {} {} \"{}\"\n", f->fix.position_m.x, f->fix.position_m.y,
                              2 * magnification * e.major_m, 2 * magnification * e.minor_m,
                              e.angle_rad * 180 / std::numbers::pi, f->cycle);
  }
  out.blocks += "EOD\n";
  return out;
}

void plot(std::span<const CycleFix> fixes, const LocateLayout& layout, const std::string& output,
          const std::atomic<bool>* stop) {
  process::ProgramResult result;
  try {
    result = process::draw_with_gnuplot(plot_script(fixes, layout, output), output, {}, stop);
  } catch (const output::OutputError& e) {
    if (e.usage())
      throw UsageError(fmt::format("--plot: {}", e.what()));
    throw FileError(fmt::format("--plot: {}", e.what()));
  }
  if (result.interrupted)
    throw Interrupted();
  if (!result.launched)
    throw FileError(
        fmt::format("--plot: cannot run gnuplot (install gnuplot-nox): {}", result.message));
  // gnuplot exits 1 when it cannot draw, as for any error.
  if (!result.ok())
    throw FileError(fmt::format("--plot: gnuplot did not draw {}: {}", output,
                                process::one_line(result.message)));
}

}  // namespace

LocateSolver parse_solver(std::string_view name) {
  for (const SolverName& s : kSolvers) {
    if (s.name == name)
      return s.solver;
  }
  throw UsageError(
      fmt::format("--solver: unknown solver '{}' (gauss-newton, longsolve or kleeman)", name));
}

double parse_temperature(std::string_view text) {
  const std::optional<double> t = yaml::finite_number(text);
  if (!t || !(*t >= loc::kMinTemperatureC && *t <= loc::kMaxTemperatureC))
    throw UsageError(
        fmt::format("--temperature: '{}' is not a temperature within {}..{} degrees Celsius", text,
                    loc::kMinTemperatureC, loc::kMaxTemperatureC));
  return *t;
}

std::vector<std::string> parse_triple(std::string_view text) {
  const std::vector<std::string_view> fields = yaml::split_fields(text);
  const std::vector<std::string> ids(fields.begin(), fields.end());
  const bool distinct = ids.size() == 3 && ids[0] != ids[1] && ids[0] != ids[2] &&
                        ids[1] != ids[2] &&
                        std::ranges::none_of(ids, [](const std::string& id) { return id.empty(); });
  if (!distinct)
    throw UsageError(
        fmt::format("--triple: '{}' is not three different beacon ids, ID,ID,ID", text));
  return ids;
}

void check_locate(const LocateCommand& command) {
  if (command.calibrate_c && command.solver != LocateSolver::kGaussNewton)
    throw UsageError("--calibrate-c needs --solver gauss-newton (Kleeman's solvers assume c)");
  if (!command.triple.empty() && command.solver != LocateSolver::kKleeman)
    throw UsageError("--triple goes with --solver kleeman");
  if (!command.plot.empty()) {
    const std::string extension = fs::path(command.plot).extension().string();
    if (extension != ".png" && extension != ".svg")
      throw UsageError(
          fmt::format("--plot: '{}' does not end in .png or .svg (the extension picks the format)",
                      command.plot));
  }
}

std::vector<CycleFix> locate_fixes(const LocateLayout& layout, std::span<const ArrivalCycle> cycles,
                                   const LocateCommand& command, const std::atomic<bool>* stop) {
  const std::optional<double> temperature =
      command.temperature_c ? command.temperature_c : layout.temperature_c;
  std::optional<loc::Triple> triple;
  if (!command.triple.empty()) {
    loc::Triple t{};
    for (std::size_t i = 0; i < 3; ++i) {
      const std::optional<int> b = layout.find(command.triple[i]);
      if (!b)
        throw UsageError(fmt::format("--triple: unknown beacon '{}' (the layout's: {})",
                                     command.triple[i], fmt::join(layout.ids, ", ")));
      t.at(i) = *b;
    }
    triple = t;
  }
  loc::Longsolve longsolve;
  std::optional<loc::Vec2> last;  // the previous valid fix
  std::vector<CycleFix> out;
  for (const ArrivalCycle& c : cycles) {
    if (stop != nullptr && stop->load())
      throw Interrupted();
    CycleFix f{c.cycle, {}};
    if (command.solver == LocateSolver::kGaussNewton) {
      loc::MultilaterationOptions options;
      options.temperature_c = temperature;
      options.calibrate_speed_of_sound = command.calibrate_c;
      options.prior_position_m = last;
      f.fix = loc::multilaterate(layout.layout, c.ranges, options);
    } else {
      const loc::RangeSet ranges =
          temperature ? rescaled(c.ranges, loc::speed_of_sound_mps(*temperature)) : c.ranges;
      const loc::Vec2 start = last.value_or(centroid(layout.layout));
      if (command.solver == LocateSolver::kLongsolve)
        f.fix = longsolve.solve(layout.layout, ranges);
      else if (triple)
        f.fix = loc::solve_triple(layout.layout, ranges, *triple, start);
      else
        f.fix = best_triple_fix(layout.layout, ranges, start);
      // The offset and residuals in the file's units, as gauss-newton reports them.
      const double back = c.ranges.speed_of_sound_mps / ranges.speed_of_sound_mps;
      f.fix.offset_m *= back;
      f.fix.offset_sd_m *= back;
      for (loc::BeaconUse& u : f.fix.beacons)
        u.residual_m *= back;
    }
    if (f.fix.valid)
      last = f.fix.position_m;
    out.push_back(std::move(f));
  }
  return out;
}

nlohmann::json fix_json(const CycleFix& f, const LocateLayout& layout) {
  const loc::Fix& fix = f.fix;
  const Eigen::Matrix2d& c = fix.covariance_m2;
  const auto id = [&](int beacon) -> nlohmann::json {
    if (beacon < 0)
      return nullptr;
    return layout.ids.at(static_cast<std::size_t>(beacon));
  };
  nlohmann::json beacons = nlohmann::json::array();
  for (const loc::BeaconUse& u : fix.beacons) {
    beacons.push_back({{"id", id(u.beacon)},
                       {"beacon", u.beacon},
                       {"status", loc::name(u.status)},
                       {"candidate", u.candidate},
                       {"residual_m", u.residual_m},
                       {"rejected_by", id(u.rejected_by)}});
  }
  nlohmann::json mirror = nullptr;
  if (fix.mirror_m)
    mirror = {{"x_m", fix.mirror_m->x}, {"y_m", fix.mirror_m->y}};
  // NaN (no value) is written as null.
  return {{"cycle", f.cycle},
          {"solver", loc::name(fix.solver)},
          {"valid", fix.valid},
          {"reason", loc::name(fix.reason)},
          {"x_m", fix.position_m.x},
          {"y_m", fix.position_m.y},
          {"covariance_m2", {{c(0, 0), c(0, 1)}, {c(1, 0), c(1, 1)}}},
          {"sd_x_m", std::sqrt(c(0, 0))},
          {"sd_y_m", std::sqrt(c(1, 1))},
          {"corr", correlation(c)},
          {"hdop", fix.hdop},
          {"offset_m", fix.offset_m},
          {"offset_sd_m", fix.offset_sd_m},
          {"speed_of_sound_mps", fix.speed_of_sound_mps},
          {"speed_of_sound_sd_mps", fix.speed_of_sound_sd_mps},
          {"speed_of_sound_estimated", fix.speed_of_sound_estimated},
          {"iterations", fix.iterations},
          {"chi2", fix.chi2},
          {"dof", fix.dof},
          {"used", fix.used()},
          {"mirror_m", std::move(mirror)},
          {"beacons", std::move(beacons)}};
}

std::string fix_table(std::span<const CycleFix> fixes, const LocateLayout& layout) {
  constexpr std::string_view kRow =
      "{:>5}  {:<14}  {:<5}  {:<19}  {:>8}  {:>8}  {:>7}  {:>7}  {:>6}  {:>5}  {:>8}  {:>6}  "
      "{:>4}  {}\n";
  std::string out = fmt::format(kRow, "cycle", "solver", "valid", "reason", "x_m", "y_m", "sd_x_m",
                                "sd_y_m", "corr", "hdop", "offset_m", "c_mps", "iter", "beacons");
  for (const CycleFix& f : fixes) {
    const loc::Fix& fix = f.fix;
    const Eigen::Matrix2d& c = fix.covariance_m2;
    const double corr = correlation(c);
    out += fmt::format(
        kRow, f.cycle, loc::name(fix.solver), fix.valid ? "yes" : "no", loc::name(fix.reason),
        number(fix.position_m.x, 4), number(fix.position_m.y, 4), number(std::sqrt(c(0, 0)), 5),
        number(std::sqrt(c(1, 1)), 5), std::isfinite(corr) ? fmt::format("{:+.3f}", corr) : "-",
        number(fix.hdop, 2), number(fix.offset_m, 4), number(fix.speed_of_sound_mps, 1),
        fix.iterations, beacon_summary(fix, layout));
  }
  return out;
}

ErrorEllipse error_ellipse(const Eigen::Matrix2d& covariance_m2, double sigmas) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance_m2);
  const Eigen::Vector2d values = eigen.eigenvalues().cwiseMax(0.0);  // ascending
  const Eigen::Vector2d major = eigen.eigenvectors().col(1);
  double angle = std::atan2(major.y(), major.x());
  // An axis has no direction: fold into (-pi/2, pi/2].
  if (angle <= -std::numbers::pi / 2)
    angle += std::numbers::pi;
  else if (angle > std::numbers::pi / 2)
    angle -= std::numbers::pi;
  return {sigmas * std::sqrt(values(1)), sigmas * std::sqrt(values(0)), angle};
}

std::string plot_script(std::span<const CycleFix> fixes, const LocateLayout& layout,
                        const std::string& output) {
  const bool svg = fs::path(output).extension() == ".svg";
  const PlotData data = plot_data(fixes, layout);
  const auto valid = std::ranges::count_if(fixes, [](const CycleFix& f) { return f.fix.valid; });
  const std::string_view solver = fixes.empty() ? "" : loc::name(fixes.front().fix.solver);
  std::string script = fmt::format(
      "set terminal {} noenhanced size {},{} font 'sans,10'\n{}{}"
      "set title 'odoloc locate ({}): {} fixes of {} cycles'\n"
      "set size ratio -1\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset grid\n"
      "set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05\n"
      "set key below\nset style ellipse units xy\n"
      "plot $beacons using 1:2 with points pt 5 ps 1.5 lc rgb '#1f77b4' title 'beacons', \\\n"
      "  $beacons using 1:2:3 with labels offset 1.2,1.2 notitle",
      svg ? "svg" : "pngcairo", kLocatePlotWidth, kLocatePlotHeight,
      process::gnuplot_output(fs::path(output).filename().string()), data.blocks, solver, valid,
      fixes.size());
  // Cycle numbers on at most about 40 fixes: more would merge into a band.
  constexpr long kMaxLabels = 40;
  const long label_every = std::max(1L, (valid + kMaxLabels - 1) / kMaxLabels);
  if (valid > 0)
    script += fmt::format(
        ", \\\n  $fixes using 1:2:3:4:5 with ellipses lc rgb '#d62728' title '{}', \\\n"
        "  $fixes using 1:2 with points pt 7 ps 0.6 lc rgb '#2ca02c' title 'fixes', \\\n"
        "  $fixes using 1:2:6 every {} with labels offset 0.9,-0.9 font 'sans,8' notitle",
        data.ellipse_title, label_every);
  return script + "\n";
}

void run_locate(const LocateCommand& command, std::ostream& out, bool json,
                const std::atomic<bool>* stop) {
  const LocateLayout layout = load_layout(command.layout);
  const std::vector<ArrivalCycle> cycles = load_arrivals(command.arrivals, layout);
  const std::vector<CycleFix> fixes = locate_fixes(layout, cycles, command, stop);
  if (json) {
    for (const CycleFix& f : fixes)
      out << json_line(fix_json(f, layout)) << '\n';
  } else {
    out << fix_table(fixes, layout);
  }
  out << std::flush;
  if (!command.plot.empty())
    plot(fixes, layout, command.plot, stop);
}

}  // namespace odoloc::cli
