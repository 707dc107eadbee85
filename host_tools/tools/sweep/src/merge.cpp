#include "odoloc/sweep/merge.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "odoloc/output/output_file.hpp"
#include "odoloc/process/gnuplot.hpp"
#include "odoloc/sweep/error.hpp"

namespace odoloc::sweep {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kNamedShards = 5;  // missing shards named in a message, at most
constexpr int kPlotWidth = 900;          // pixels
constexpr int kPanelHeight = 220;        // per metric
constexpr int kTitleHeight = 60;

[[noreturn]] void usage_error(const std::string& what) {
  throw SweepError(true, what);
}

// The axes the grid names (the tables' parameter columns) and those it
// sweeps (two values or more: the plots' x axes, the points' titles).
std::vector<std::size_t> given_axes(const Spec& spec) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < spec.axes.size(); ++i)
    if (spec.axes[i].given)
      out.push_back(i);
  return out;
}
std::vector<std::size_t> swept_axes(const Spec& spec) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < spec.axes.size(); ++i)
    if (spec.axes[i].values.size() > 1)
      out.push_back(i);
  return out;
}

const Value& value_at(const Spec& spec, std::uint64_t point, std::size_t axis) {
  return spec.axes[axis].values[spec.value_index(point, axis)];
}

// "a=1, b=x" over `axes` at `point`.
std::string settings_of(const Spec& spec, std::uint64_t point, std::span<const std::size_t> axes) {
  std::string out;
  for (const std::size_t a : axes)
    out += fmt::format("{}{}={}", out.empty() ? "" : ", ", spec.axes[a].parameter,
                       to_text(value_at(spec, point, a)));
  return out;
}

// Markdown's numbers: six significant digits, "-" for no value.
std::string readable(double value) {
  return std::isnan(value) ? std::string{"-"} : fmt::format("{:.6g}", value);
}

}  // namespace

MergedSweep merge(std::vector<ShardFile> files) {
  if (files.empty())
    usage_error("no shard file given");
  const ShardFile& first = files.front();
  for (const ShardFile& f : files) {
    if (f.hash != first.hash)
      usage_error(fmt::format(
          "{} is from another sweep (spec {} '{}') than {} (spec {} '{}'): merge the shards of "
          "one run",
          f.name, f.hash, f.spec.name, first.name, first.hash, first.spec.name));
    if (f.shard.n != first.shard.n)
      usage_error(
          fmt::format("{} is shard {}/{} but {} is shard {}/{}: the shards of one run "
                      "share N",
                      f.name, f.shard.k, f.shard.n, first.name, first.shard.k, first.shard.n));
  }
  const std::uint64_t n = first.shard.n;
  std::vector<const ShardFile*> by_k(static_cast<std::size_t>(n), nullptr);
  for (const ShardFile& f : files) {
    const ShardFile*& slot = by_k[static_cast<std::size_t>(f.shard.k - 1)];
    if (slot != nullptr)
      usage_error(
          fmt::format("shard {}/{} given twice: {} and {}", f.shard.k, n, slot->name, f.name));
    slot = &f;
  }
  std::vector<std::string> missing;
  for (std::size_t k = 0; k < by_k.size(); ++k)
    if (by_k[k] == nullptr)
      missing.push_back(fmt::format("{}/{}", k + 1, n));
  if (!missing.empty()) {
    const std::size_t count = missing.size();
    missing.resize(std::min(count, kNamedShards));
    usage_error(fmt::format("{} of {} shards missing: {}{} (give every shard file of the run)",
                            count, n, fmt::join(missing, ", "),
                            count > kNamedShards ? ", ..." : ""));
  }
  MergedSweep out{first.spec, first.hash, {}};
  for (ShardFile& f : files)
    std::ranges::move(f.jobs, std::back_inserter(out.jobs));
  std::ranges::sort(out.jobs, {}, &JobResult::job);
  return out;
}

Statistics statistics(std::span<const double> values) {
  std::vector<double> v;
  std::ranges::copy_if(values, std::back_inserter(v), [](double x) { return !std::isnan(x); });
  Statistics s;
  s.n = v.size();
  if (v.empty()) {
    s.mean = s.rms = s.p95 = std::nan("");
    return s;
  }
  double sum = 0, squares = 0;
  for (const double x : v) {  // in trial order: the same sums whatever the sharding
    sum += x;
    squares += x * x;
  }
  const auto count = static_cast<double>(v.size());
  s.mean = sum / count;
  s.rms = std::sqrt(squares / count);
  std::ranges::sort(v);
  s.p95 = v[(95 * v.size() + 99) / 100 - 1];  // rank ceil(0.95 n), in integers
  return s;
}

std::vector<std::vector<Statistics>> point_statistics(const MergedSweep& sweep) {
  const Spec& spec = sweep.spec;
  const std::size_t metric_count = metrics(spec.experiment).size();
  std::vector<std::vector<Statistics>> out;
  for (std::uint64_t p = 0; p < spec.points(); ++p) {
    std::vector<Statistics> per_metric;
    for (std::size_t m = 0; m < metric_count; ++m) {
      std::vector<double> values;
      for (std::uint64_t t = 0; t < spec.trials; ++t)
        values.push_back(sweep.jobs[static_cast<std::size_t>(p * spec.trials + t)].metrics[m]);
      per_metric.push_back(statistics(values));
    }
    out.push_back(std::move(per_metric));
  }
  return out;
}

std::string jobs_csv(const MergedSweep& sweep) {
  const Spec& spec = sweep.spec;
  const std::vector<std::size_t> given = given_axes(spec);
  std::string out = "job,point,trial,seed";
  for (const std::size_t a : given)
    out += fmt::format(",{}", spec.axes[a].parameter);
  for (const MetricInfo& m : metrics(spec.experiment))
    out += fmt::format(",{}", m.name);
  out += '\n';
  for (const JobResult& j : sweep.jobs) {
    out += fmt::format("{},{},{},{:016x}", j.job, j.point, j.trial, j.seed);
    for (const std::size_t a : given)
      out += fmt::format(",{}", to_text(value_at(spec, j.point, a)));
    for (const double v : j.metrics)
      out += fmt::format(",{}", v);
    out += '\n';
  }
  return out;
}

std::string points_csv(const MergedSweep& sweep) {
  const Spec& spec = sweep.spec;
  const std::vector<std::size_t> given = given_axes(spec);
  std::string out = "point";
  for (const std::size_t a : given)
    out += fmt::format(",{}", spec.axes[a].parameter);
  out += ",trials";
  for (const MetricInfo& m : metrics(spec.experiment))
    out += fmt::format(",{0}_n,{0}_mean,{0}_rms,{0}_p95", m.name);
  out += '\n';
  const std::vector<std::vector<Statistics>> stats = point_statistics(sweep);
  for (std::uint64_t p = 0; p < spec.points(); ++p) {
    out += std::to_string(p);
    for (const std::size_t a : given)
      out += fmt::format(",{}", to_text(value_at(spec, p, a)));
    out += fmt::format(",{}", spec.trials);
    for (const Statistics& s : stats[static_cast<std::size_t>(p)])
      out += fmt::format(",{},{},{},{}", s.n, s.mean, s.rms, s.p95);
    out += '\n';
  }
  return out;
}

std::string summary_markdown(const MergedSweep& sweep) {
  const Spec& spec = sweep.spec;
  std::string out = fmt::format(
      "# Sweep {}\n\nExperiment {}, seed {}, {} trials per point, {} points, {} jobs; spec "
      "{}.\n\nHeld at one value:",
      spec.name, name(spec.experiment), spec.seed, spec.trials, spec.points(), spec.jobs(),
      sweep.hash);
  for (const Axis& a : spec.axes) {
    if (a.values.size() == 1)
      out +=
          fmt::format(" {}={}{}", a.parameter, to_text(a.values[0]), a.given ? "" : " (default)");
  }
  out += ".\n";
  const std::vector<std::size_t> swept = swept_axes(spec);
  const std::vector<std::vector<Statistics>> stats = point_statistics(sweep);
  const std::span<const MetricInfo> names = metrics(spec.experiment);
  for (std::uint64_t p = 0; p < spec.points(); ++p) {
    out += fmt::format(
        "\n## Point {}{}{}\n\n| metric | n | mean | RMS | p95 |\n|---|---:|---:|---:|---:|\n", p,
        swept.empty() ? "" : ": ", settings_of(spec, p, swept));
    for (std::size_t m = 0; m < names.size(); ++m) {
      const Statistics& s = stats[static_cast<std::size_t>(p)][m];
      out += fmt::format("| {} | {} | {} | {} | {} |\n", names[m].name, s.n, readable(s.mean),
                         readable(s.rms), readable(s.p95));
    }
  }
  return out;
}

std::vector<std::string> plot_files(const Spec& spec) {
  std::vector<std::string> out;
  for (const std::size_t a : swept_axes(spec))
    out.push_back(spec.axes[a].parameter + ".png");
  return out;
}

std::string plot_script(const MergedSweep& sweep) {
  const Spec& spec = sweep.spec;
  const std::span<const MetricInfo> names = metrics(spec.experiment);
  const std::vector<std::size_t> swept = swept_axes(spec);
  const std::vector<std::vector<Statistics>> stats = point_statistics(sweep);
  std::string out = fmt::format(
      "# Written by odoloc sweep merge; run it in this folder: gnuplot plots.gp\n"
      "set terminal pngcairo noenhanced size {},{} font ',10'\nset grid\nset key outside right "
      "top\n",
      kPlotWidth, kTitleHeight + kPanelHeight * static_cast<int>(names.size()));
  for (const std::size_t x_axis : swept) {
    const Axis& axis = spec.axes[x_axis];
    const bool named = std::holds_alternative<std::string>(axis.values.front());
    std::vector<std::size_t> others;
    std::ranges::copy_if(swept, std::back_inserter(others),
                         [&](std::size_t a) { return a != x_axis; });
    // One series per combination of the other swept values, in point order.
    std::map<std::vector<std::size_t>, std::size_t> series_of;
    std::vector<std::string> labels, blocks;
    for (std::uint64_t p = 0; p < spec.points(); ++p) {
      std::vector<std::size_t> key;
      for (const std::size_t a : others)
        key.push_back(spec.value_index(p, a));
      const auto [it, fresh] = series_of.try_emplace(key, labels.size());
      if (fresh) {
        labels.push_back(others.empty() ? std::string{"all points"} : settings_of(spec, p, others));
        blocks.emplace_back();
      }
      std::string& block = blocks[it->second];
      const std::size_t index = spec.value_index(p, x_axis);
      block += named ? std::to_string(index) : to_text(axis.values[index]);
      for (const Statistics& s : stats[static_cast<std::size_t>(p)])
        block += fmt::format(" {} {}", s.mean, s.p95);
      block += '\n';
    }
    for (std::size_t s = 0; s < blocks.size(); ++s)
      out += fmt::format("$d{}_{} << EOD\n{}EOD\n", x_axis, s, blocks[s]);
    // Every name from the spec (its own, a parameter's, a value's) as a
    // gnuplot string constant: data, never code.
    const std::string parameter = process::gnuplot_string(axis.parameter);
    out += fmt::format(
        "set output {}\nset multiplot layout {},1 title {}\nset xlabel {}\n",
        process::gnuplot_string(axis.parameter + ".png"), names.size(),
        process::gnuplot_string(fmt::format("{}: metrics against {} (mean solid, p95 dashed)",
                                            spec.name, axis.parameter)),
        parameter);
    if (named) {
      std::vector<std::string> tics;
      for (std::size_t i = 0; i < axis.values.size(); ++i)
        tics.push_back(fmt::format("{} {}", process::gnuplot_string(to_text(axis.values[i])), i));
      out += fmt::format("set xtics ({})\nset xrange [-0.5:{}.5]\n", fmt::join(tics, ", "),
                         axis.values.size() - 1);
    } else {
      out += "set xtics autofreq\nset autoscale x\n";
    }
    for (std::size_t m = 0; m < names.size(); ++m) {
      out += fmt::format("set ylabel {}\nplot", process::gnuplot_string(names[m].name));
      for (std::size_t s = 0; s < blocks.size(); ++s)
        out += fmt::format(
            "{0} $d{1}_{2} using 1:{3} with linespoints lc {4} pt 7 title {5}, $d{1}_{2} using "
            "1:{6} with lines dt 2 lc {4} notitle",
            s == 0 ? "" : ",", x_axis, s, 2 + 2 * m, s + 1, process::gnuplot_string(labels[s]),
            3 + 2 * m);
      out += '\n';
    }
    out += "unset multiplot\nset output\n";
  }
  return out;
}

std::vector<fs::path> write_merged(const MergedSweep& sweep, const fs::path& dir, bool draw,
                                   const std::atomic<bool>* stop) {
  return writing([&] {
    output::OutputFolder folder(dir);
    std::vector<std::string> names = {"jobs.csv", "points.csv", "summary.md", "plots.gp"};
    const std::vector<std::string> pictures = plot_files(sweep.spec);
    if (draw)
      names.insert(names.end(), pictures.begin(), pictures.end());
    // Every output is checked before anything is made; all are made in the
    // staging folder, then delivered: an error or a signal leaves `dir` as
    // it was.
    std::vector<std::unique_ptr<output::OutputFile>> outputs;
    for (const std::string& name : names)
      outputs.push_back(std::make_unique<output::OutputFile>(dir / name));
    const output::Staging staging(dir, "merge");
    for (const auto& [file, text] :
         {std::pair{"jobs.csv", jobs_csv(sweep)}, std::pair{"points.csv", points_csv(sweep)},
          std::pair{"summary.md", summary_markdown(sweep)},
          std::pair{"plots.gp", plot_script(sweep)}})
      output::write_file(staging.dir() / file, text);
    if (draw && !pictures.empty()) {
      const process::ProgramResult gnuplot =
          process::run_program("gnuplot", {"plots.gp"}, staging.dir(), stop);
      if (gnuplot.interrupted)
        throw process::Interrupted();
      if (!gnuplot.ok())
        throw SweepError(false,
                         gnuplot.launched
                             ? fmt::format("gnuplot failed on {}: {}", (dir / "plots.gp").string(),
                                           process::one_line(gnuplot.message))
                             : fmt::format("cannot run gnuplot (install gnuplot-nox, or pass "
                                           "--no-plot): {}",
                                           process::one_line(gnuplot.message)));
    }
    std::vector<fs::path> written;
    for (std::size_t i = 0; i < names.size(); ++i) {
      outputs[i]->commit_from(staging.dir() / names[i]);
      written.push_back(dir / names[i]);
    }
    folder.keep();
    return written;
  });
}

}  // namespace odoloc::sweep
