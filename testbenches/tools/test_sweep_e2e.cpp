// `odoloc sweep` end to end with the real binary and the engines the issue
// names: a sweep run whole and as 4 shards through GNU parallel (skipped
// when GNU parallel is not installed) merges into byte-identical tables;
// the Slurm array template (examples/sweep/slurm-array.sbatch), run as a
// plain bash script with the SLURM_* variables of each task set by hand,
// does the same.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "odoloc/process/run_program.hpp"
#include "png_size.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::process::ProgramResult;

// The merged outputs that must not depend on the sharding.
constexpr const char* kTables[] = {"jobs.csv", "points.csv", "summary.md", "plots.gp"};

struct Sweep {
  const char* name;
  const char* yaml;
  int jobs;
};
// Both experiments, small: about a second in all.
const Sweep kSweeps[] = {
    {"odometry",
     "name: e2e-odometry\nexperiment: odometry\nseed: 9\ntrials: 2\ngrid:\n  distance_m: 0.5\n"
     "  policy: [per_component, front_only]\n  radius_error_sd: 0.005\n",
     4},
    {"beacons",
     "name: e2e-beacons\nexperiment: beacons\nseed: 9\ntrials: 5\ngrid:\n  echo_probability: [0, "
     "0.3]\n  layout: [kleeman, corners]\n",
     20},
};

fs::path fresh_dir(std::string_view tag) {
  return odoloc::tb::fresh_dir("odoloc_sweep_e2e", tag);
}

using odoloc::tb::slurp;

// `odoloc ARGS...` in `dir`; a test failure unless it succeeds.
void odoloc(const std::vector<std::string>& args, const fs::path& dir) {
  const ProgramResult r = odoloc::process::run_program(ODOLOC_CLI, args, dir);
  EXPECT_TRUE(r.ok()) << fmt::format("odoloc {}", fmt::join(args, " ")) << "\n" << r.message;
}

// Merges `files` into dir/`out` (with the plots) and checks the outputs.
void merge(const fs::path& dir, const std::string& out, const std::vector<std::string>& files,
           int jobs) {
  std::vector<std::string> args = {"sweep", "merge", "--out", out};
  args.insert(args.end(), files.begin(), files.end());
  odoloc(args, dir);
  std::istringstream rows(slurp(dir / out / "jobs.csv"));
  int lines = 0;
  for (std::string line; std::getline(rows, line);)
    ++lines;
  EXPECT_EQ(lines, jobs + 1) << out;  // the header and one row per job
  for (const fs::directory_entry& e : fs::directory_iterator(dir / out)) {
    if (e.path().extension() == ".png") {
      EXPECT_EQ(odoloc::tb::png_size(e.path()).width, 900U) << e.path();
    }
  }
}

void expect_same_tables(const fs::path& a, const fs::path& b) {
  for (const char* table : kTables) {
    const std::string left = slurp(a / table);
    EXPECT_FALSE(left.empty()) << a / table;
    EXPECT_TRUE(left == slurp(b / table)) << table << " differs between " << a << " and " << b;
  }
}

bool have_gnu_parallel() {
  const ProgramResult r = odoloc::process::run_program("parallel", {"--version"}, ".");
  return r.ok() && r.message.find("GNU parallel") != std::string::npos;
}

TEST(SweepEndToEnd, FourShardsThroughGnuParallelMergeToTheUnshardedTables) {
  if (!have_gnu_parallel())
    GTEST_SKIP() << "GNU parallel is not installed (Debian package parallel; "
                    "scripts/setup-debian.sh --tests installs it)";
  for (const Sweep& s : kSweeps) {
    SCOPED_TRACE(s.name);
    const fs::path dir = fresh_dir(fmt::format("parallel_{}", s.name));
    std::ofstream(dir / "spec.yaml") << s.yaml;
    odoloc({"sweep", "run", "spec.yaml", "--out", "whole.jsonl"}, dir);
    const ProgramResult shards = odoloc::process::run_program(
        "parallel",
        {"--will-cite", "--halt", "now,fail=1", ODOLOC_CLI, "sweep", "run", "spec.yaml", "--shard",
         "{}/4", "--out", "s{}.jsonl", ":::", "1", "2", "3", "4"},
        dir);
    ASSERT_TRUE(shards.ok()) << shards.message;
    for (int k = 1; k <= 4; ++k)
      EXPECT_TRUE(fs::exists(dir / fmt::format("s{}.jsonl", k)));
    merge(dir, "whole", {"whole.jsonl"}, s.jobs);
    merge(dir, "sharded", {"s3.jsonl", "s1.jsonl", "s4.jsonl", "s2.jsonl"}, s.jobs);
    expect_same_tables(dir / "whole", dir / "sharded");
  }
}

TEST(SweepEndToEnd, SlurmArrayTemplateRunsAsAPlainScript) {
  const std::string script = ODOLOC_SOURCE_DIR "/examples/sweep/slurm-array.sbatch";
  const ProgramResult syntax = odoloc::process::run_program("bash", {"-n", script}, ".");
  ASSERT_TRUE(syntax.ok()) << syntax.message;

  const Sweep& s = kSweeps[1];
  const fs::path dir = fresh_dir("slurm");
  std::ofstream(dir / "spec.yaml") << s.yaml;
  odoloc({"sweep", "run", "spec.yaml", "--out", "whole.jsonl"}, dir);
  const auto task = [&](int k, int n, int min, int max) {
    return odoloc::process::run_shell(
        fmt::format("SLURM_ARRAY_TASK_ID={} SLURM_ARRAY_TASK_COUNT={} SLURM_ARRAY_TASK_MIN={} "
                    "SLURM_ARRAY_TASK_MAX={} ODOLOC='{}' bash '{}' spec.yaml results",
                    k, n, min, max, ODOLOC_CLI, script),
        dir);
  };
  for (int k = 1; k <= 3; ++k) {
    const ProgramResult r = task(k, 3, 1, 3);
    EXPECT_TRUE(r.ok()) << "task " << k << ": " << r.message;
  }
  merge(dir, "whole", {"whole.jsonl"}, s.jobs);
  merge(dir, "slurm", {"results/shard-1.jsonl", "results/shard-2.jsonl", "results/shard-3.jsonl"},
        s.jobs);
  expect_same_tables(dir / "whole", dir / "slurm");

  // An array that is not 1-N would leave shards out: refused.
  const ProgramResult offset = task(2, 3, 2, 4);
  EXPECT_EQ(offset.exit_status, 2) << offset.message;
  EXPECT_NE(offset.message.find("the array must be 1-N"), std::string::npos) << offset.message;
  // Outside an array task: refused with the submission to use.
  const ProgramResult plain = odoloc::process::run_shell(
      fmt::format("ODOLOC='{}' bash '{}' spec.yaml results", ODOLOC_CLI, script), dir);
  EXPECT_NE(plain.exit_status, 0);
  EXPECT_NE(plain.message.find("sbatch --array=1-N"), std::string::npos) << plain.message;
}

}  // namespace
