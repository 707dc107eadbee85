// `odoloc sweep merge` (docs/sweep.md#merging): the shard files of one run
// into one table, a summary per point and plots.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "odoloc/sweep/shard_file.hpp"

namespace odoloc::sweep {

struct MergedSweep {
  Spec spec;
  std::string hash;
  std::vector<JobResult> jobs;  // every job of the spec, in job order
};

// Checks that the files are the shards of one run: one spec (hash), one N,
// each K once and none missing (each file already holds exactly its jobs).
// Throws SweepError (usage) naming the files: "s3.jsonl is from another
// sweep ...", "shard 2/4 given twice: a.jsonl and b.jsonl", "missing shards
// 3/4, 4/4". The order of the files does not matter.
[[nodiscard]] MergedSweep merge(std::vector<ShardFile> files);

// Over the values that are numbers (NaN: no value, left out): their count,
// mean, root mean square and 95th percentile (nearest rank: the
// ceil(0.95 n)-th smallest). NaN statistics when n is 0.
struct Statistics {
  std::uint64_t n = 0;
  double mean = 0;
  double rms = 0;
  double p95 = 0;
};
[[nodiscard]] Statistics statistics(std::span<const double> values);

// Per point (in point order), per metric: the statistics over its trials.
[[nodiscard]] std::vector<std::vector<Statistics>> point_statistics(const MergedSweep& sweep);

// The outputs, as text. jobs.csv: job,point,trial,seed, the grid's
// parameters, the metrics (one row per job). points.csv: point, the grid's
// parameters, trials, then per metric _n, _mean, _rms, _p95. summary.md:
// the spec and per point a table of the statistics. plots.gp: a gnuplot
// script drawing, for each parameter the grid sweeps (two values or more),
// PARAMETER.png: every metric's mean (solid) and p95 (dashed) against it,
// one line per combination of the other swept parameters. Numbers in the
// CSV files in their shortest round-trip form ("nan": no value).
[[nodiscard]] std::string jobs_csv(const MergedSweep& sweep);
[[nodiscard]] std::string points_csv(const MergedSweep& sweep);
[[nodiscard]] std::string summary_markdown(const MergedSweep& sweep);
[[nodiscard]] std::string plot_script(const MergedSweep& sweep);
// The pictures plot_script draws.
[[nodiscard]] std::vector<std::string> plot_files(const Spec& spec);

// Writes the four files and, with `draw`, the pictures gnuplot draws from
// plots.gp into `dir` (an output::OutputFolder: created when absent, its
// parent must exist). Everything is made in a staging folder in `dir` first
// and each file then delivered as an output::OutputFile (whole; a device or
// FIFO written to, a symbolic link followed). Returns the paths written.
// Throws SweepError: usage when `dir` or a file in it cannot be written;
// otherwise a failed write, or gnuplot missing or failing; process::
// Interrupted when `stop` is set while gnuplot runs. Nothing is delivered
// then.
std::vector<std::filesystem::path> write_merged(const MergedSweep& sweep,
                                                const std::filesystem::path& dir, bool draw,
                                                const std::atomic<bool>* stop = nullptr);

}  // namespace odoloc::sweep
