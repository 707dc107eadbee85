// `odoloc sweep` (docs/sweep.md): `run` one shard of a sweep described in
// YAML into a result file, `merge` the shard files of a run into one table,
// a summary and plots. No target: the experiments run on the simulated
// board and world in this process.
#pragma once

#include <atomic>
#include <iosfwd>
#include <string>
#include <vector>

#include "odoloc/sweep/jobs.hpp"

namespace odoloc::cli {

struct SweepRunCommand {
  std::string spec;  // YAML
  sweep::Shard shard;
  std::string out;  // the shard's result file (JSON Lines)
};

struct SweepMergeCommand {
  std::vector<std::string> files;  // every shard file of one run
  std::string out;                 // the folder for the table, summary and plots
  bool plot = true;                // run gnuplot on plots.gp
};

// The --shard value; UsageError as sweep::parse_shard explains it.
[[nodiscard]] sweep::Shard parse_shard_option(const std::string& text);

// Reads the spec, runs the shard's jobs (stopping with Interrupted between
// jobs when `stop` is set) and writes the result file, then one line (or
// JSON object) saying what it wrote. A mistake in the input is a
// UsageError, a failed write a FileError; no partial file is left.
void run_sweep_run(const SweepRunCommand& command, std::ostream& out, bool json,
                   const std::atomic<bool>* stop);

// Reads and checks the shard files, writes the folder, then one line (or
// JSON object) listing the files written. Errors as run_sweep_run's;
// Interrupted when `stop` is set (between shard files, while gnuplot runs:
// nothing is written).
void run_sweep_merge(const SweepMergeCommand& command, std::ostream& out, bool json,
                     const std::atomic<bool>* stop);

}  // namespace odoloc::cli
