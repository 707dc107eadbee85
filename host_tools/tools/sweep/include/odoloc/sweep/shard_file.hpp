// Shard result files (docs/sweep.md#shard-files): JSON Lines. The first line
// is the header,
//   {"format":"odoloc-sweep-shard 1","jobs":24,"shard":2,"shards":4,
//    "spec":{canonical spec},"spec_hash":"<16 hex digits>"}
// then one line per job of the shard, in job order,
//   {"job":5,"metrics":{"position_error_m":0.0012,...},"point":2,"seed":"<16 hex>","trial":1}
// numbers in their shortest round-trip form, a metric without a value null.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/sweep/jobs.hpp"
#include "odoloc/sweep/spec.hpp"

namespace odoloc::sweep {

inline constexpr std::string_view kShardFormat = "odoloc-sweep-shard 1";

struct JobResult {
  std::uint64_t job = 0;
  std::uint64_t point = 0;
  std::uint64_t trial = 0;
  std::uint64_t seed = 0;
  std::vector<double> metrics;  // metrics(experiment) order; NaN: no value

  // NaN equals NaN here: two runs agree when both have no value.
  [[nodiscard]] bool same_as(const JobResult& other) const;
};

// Runs job `job` of the spec: its point's settings, its seed.
[[nodiscard]] JobResult run_job(const Spec& spec, std::uint64_t job);

// Runs the shard's jobs in job order into `out` (an AtomicFile: the file
// appears only when every job ran). `between_jobs`, when set, is called
// before each job and may throw to stop the run. Returns the number of jobs
// run. Throws SweepError: usage when `out` cannot be created (before any
// job runs) or the engine refuses a point (naming the job, point and
// settings), else when writing failed.
std::uint64_t run_shard(const Spec& spec, Shard shard, const std::filesystem::path& out,
                        const std::function<void()>& between_jobs = {});

[[nodiscard]] std::string header_line(const Spec& spec, Shard shard);
[[nodiscard]] std::string job_line(const Spec& spec, const JobResult& result);

struct ShardFile {
  std::string name;  // the file's path, for messages
  Spec spec;
  std::string hash;
  Shard shard;
  std::vector<JobResult> jobs;  // every job of the shard, in job order
};

// Parses and checks one file: the format, the spec against its hash, and
// that the jobs are exactly the shard's, each once, with the point, trial
// and seed the spec gives them and one value (or null) per metric. Throws
// SweepError (usage) "NAME:LINE: ..." naming what is wrong; a missing job
// ("jobs 9, 13 of shard 2/4 missing") points at a truncated file.
[[nodiscard]] ShardFile parse_shard_file(std::string_view text, std::string_view name);
// The same on a file; SweepError (usage) when it cannot be read.
[[nodiscard]] ShardFile load_shard_file(const std::filesystem::path& path);

}  // namespace odoloc::sweep
