// `odoloc sweep` in process (docs/sweep.md): the seeding rule against
// SplitMix64 values computed independently, shards as a partition of the
// jobs, the spec parser's messages (file, line, key) and its canonical form,
// the shard-file checks and the merge's, the statistics, the outputs'
// independence of the sharding, and results against independent references
// (a direct scenario run; wheel-radius and speed-of-sound errors from their
// physics). Random mutations of a spec and of a shard file must give a
// result or a SweepError naming the file, never a crash.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "odoloc/board/scenario_runner.hpp"
#include "odoloc/cli/app.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/sweep/error.hpp"
#include "odoloc/sweep/jobs.hpp"
#include "odoloc/sweep/merge.hpp"
#include "odoloc/sweep/shard_file.hpp"
#include "odoloc/sweep/spec.hpp"
#include "odoloc/world/scenarios.hpp"
#include "scratch_files.hpp"
#include "text_mutation.hpp"

namespace {

namespace fs = std::filesystem;
namespace sweep = odoloc::sweep;
namespace cli = odoloc::cli;

// A small beacon sweep: 2 x 2 points x 3 trials, milliseconds per job.
constexpr const char* kBeaconSpec = R"(name: echo-temperature
experiment: beacons
seed: 11
trials: 3
grid:
  echo_probability: [0, 0.5]
  temperature_c: [20, 35]
)";

// A fresh folder per call under the test's temporary directory.
fs::path fresh_dir(std::string_view tag) {
  static int serial = 0;
  return odoloc::tb::fresh_dir("odoloc_sweep", fmt::format("{}_{}", tag, ++serial));
}

using odoloc::tb::slurp;

// What parse_spec says about `yaml`; a test failure when it accepts it.
std::string spec_error(const std::string& yaml) {
  try {
    (void)sweep::parse_spec(yaml, "spec.yaml");
  } catch (const sweep::SweepError& e) {
    EXPECT_TRUE(e.usage()) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << yaml;
  return {};
}

std::string with_grid(std::string_view experiment, std::string_view grid) {
  return fmt::format("name: t\nexperiment: {}\nseed: 1\ntrials: 2\ngrid:\n{}", experiment, grid);
}

// ------------------------------------------------------------------ seeds

TEST(SweepSeeds, SplitMix64MatchesAnIndependentImplementation) {
  // Vigna's splitmix64.c seeded with 1234567 returns 6457827717110365317
  // first; the others from a Python transcription of the same function.
  EXPECT_EQ(sweep::splitmix64(1234567), 6457827717110365317U);
  EXPECT_EQ(sweep::splitmix64(0), 0xe220a8397b1dcdafU);
  EXPECT_EQ(sweep::job_seed(2026, 0, 0), 0x64646b7cd4c5e3e1U);
  EXPECT_EQ(sweep::job_seed(2026, 3, 1), 0xc73989fc6b4360f1U);
  EXPECT_EQ(sweep::job_seed(~0ULL, ~0ULL, 5), 0x122a049c67d4a975U);  // wraps modulo 2^64
}

TEST(SweepSeeds, EveryJobOfASpecHasItsOwnSeed) {
  std::vector<std::uint64_t> seeds;
  for (std::uint64_t p = 0; p < 300; ++p)
    for (std::uint64_t t = 0; t < 300; ++t)
      seeds.push_back(sweep::job_seed(7, p, t));
  std::ranges::sort(seeds);
  EXPECT_EQ(std::ranges::adjacent_find(seeds), seeds.end());
  EXPECT_NE(sweep::job_seed(7, 1, 0), sweep::job_seed(7, 0, 1));  // not a sum of point and trial
}

// ----------------------------------------------------------------- shards

TEST(SweepShards, ParseAndExplain) {
  EXPECT_EQ(sweep::parse_shard("1/1"), (sweep::Shard{1, 1}));
  EXPECT_EQ(sweep::parse_shard("3/4"), (sweep::Shard{3, 4}));
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"0/4", "--shard: '0/4': K counts from 1 to N (4)"},
      {"5/4", "--shard: '5/4': K counts from 1 to N (4)"},
      {"1/0", "--shard: '1/0': N counts the shards, 1 to 1000000"},
      {"x", "--shard: 'x': expected K/N, shard K of N (e.g. 2/4)"},
      {"1/", "--shard: '1/': K and N are whole numbers (e.g. 2/4)"},
      {"-1/4", "--shard: '-1/4': K and N are whole numbers (e.g. 2/4)"},
      {" 1/4", "--shard: ' 1/4': K and N are whole numbers (e.g. 2/4)"},
      {"1/4x", "--shard: '1/4x': K and N are whole numbers (e.g. 2/4)"},
      {"1/2/3", "--shard: '1/2/3': K and N are whole numbers (e.g. 2/4)"},
      {"1/2000000", "--shard: '1/2000000': N counts the shards, 1 to 1000000"},
  };
  for (const auto& [text, message] : bad) {
    try {
      (void)sweep::parse_shard(text);
      ADD_FAILURE() << text << " accepted";
    } catch (const sweep::SweepError& e) {
      EXPECT_TRUE(e.usage());
      EXPECT_EQ(e.what(), message);
    }
  }
}

TEST(SweepShards, EveryJobIsInExactlyOneShard) {
  for (std::uint64_t n = 1; n <= 9; ++n) {
    for (std::uint64_t jobs = 0; jobs <= 40; ++jobs) {
      std::vector<int> owners(jobs, 0);
      for (std::uint64_t k = 1; k <= n; ++k) {
        const sweep::Shard shard{k, n};
        std::uint64_t count = 0;
        for (std::uint64_t j = 0; j < jobs; ++j) {
          owners[j] += shard.owns(j) ? 1 : 0;
          count += shard.owns(j) ? 1 : 0;
        }
        EXPECT_EQ(shard.size(jobs), count) << k << "/" << n << " of " << jobs;
        EXPECT_LE(count, jobs / n + 1);
        EXPECT_GE(count, jobs / n);
      }
      EXPECT_TRUE(std::ranges::all_of(owners, [](int o) { return o == 1; })) << n << " " << jobs;
    }
  }
}

// ------------------------------------------------------------------- spec

TEST(SweepSpec, GridIsTheCartesianProductFirstKeySlowest) {
  const sweep::Spec s =
      sweep::parse_spec(with_grid("odometry", R"(  policy: [per_component, rear_only, front_only]
  bump_height_m: [0, 0.01]
  distance_m: 1
)"),
                        "spec.yaml");
  EXPECT_EQ(s.name, "t");
  EXPECT_EQ(s.experiment, sweep::Experiment::kOdometry);
  EXPECT_EQ(s.trials, 2U);
  ASSERT_EQ(s.axes.size(), sweep::parameters(sweep::Experiment::kOdometry).size());
  EXPECT_EQ(s.axes[0].parameter, "policy");
  EXPECT_EQ(s.axes[1].parameter, "bump_height_m");
  EXPECT_EQ(s.axes[2].parameter, "distance_m");
  EXPECT_TRUE(s.axes[2].given);
  EXPECT_FALSE(s.axes[3].given);  // the defaults follow, in the documented order
  EXPECT_EQ(s.axes[3].parameter, "scenario");
  EXPECT_EQ(s.points(), 6U);
  EXPECT_EQ(s.jobs(), 12U);
  const std::vector<std::pair<std::string, double>> expected = {
      {"per_component", 0}, {"per_component", 0.01}, {"rear_only", 0},
      {"rear_only", 0.01},  {"front_only", 0},       {"front_only", 0.01}};
  for (std::uint64_t p = 0; p < s.points(); ++p) {
    const sweep::Settings settings = s.settings(p);
    EXPECT_EQ(std::get<std::string>(settings.at("policy")), expected[p].first) << p;
    EXPECT_EQ(std::get<double>(settings.at("bump_height_m")), expected[p].second) << p;
    EXPECT_EQ(std::get<double>(settings.at("distance_m")), 1.0);
    EXPECT_EQ(std::get<std::string>(settings.at("scenario")), "straight");  // the default
    EXPECT_EQ(settings.size(), s.axes.size());
  }
}

TEST(SweepSpec, MistakesNameTheFileLineAndKey) {
  const std::string head = "name: t\nexperiment: odometry\nseed: 1\ntrials: 2\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {head + "trails: 3\ngrid: {policy: rear_only}\n",
       "spec.yaml:5: unknown key 'trails' (expected name, experiment, seed, trials or grid)"},
      {head, "spec.yaml:1: missing 'grid'"},
      {"name: t\nexperiment: odometr\nseed: 1\ntrials: 2\ngrid: {policy: rear_only}\n",
       "spec.yaml:2: unknown experiment 'odometr' (expected odometry or beacons)"},
      {with_grid("odometry", "  bump_hieght_m: [0.01]\n"),
       "spec.yaml:6: grid: unknown odometry parameter 'bump_hieght_m' (expected scenario, "
       "distance_m, bump_height_m, heading_deg, heading_spread_deg, left_radius_error, "
       "right_radius_error, front_radius_error, radius_error_sd, policy or tuning)"},
      {with_grid("beacons", "  policy: [rear_only]\n"),
       "spec.yaml:6: grid: unknown beacons parameter 'policy' (expected layout, solver, "
       "echo_probability, reflection, temperature_c, chain_sd_m, path_jitter_s or "
       "receiver_jitter_s)"},
      {with_grid("odometry", "  bump_height_m: []\n"),
       "spec.yaml:6: grid: bump_height_m: an empty list (give at least one value)"},
      {with_grid("odometry", "  bump_height_m:\n"),
       "spec.yaml:6: grid: bump_height_m: no value (give one, or a list)"},
      {with_grid("odometry", "  bump_height_m: [0.01, .nan]\n"),
       "spec.yaml:6: grid: bump_height_m: '.nan' is not a finite number"},
      {with_grid("odometry", "  bump_height_m: [nan]\n"),
       "spec.yaml:6: grid: bump_height_m: 'nan' is not a finite number"},
      // "+-" is no sign (the layout's and the scenario's rule too).
      {with_grid("odometry", "  heading_deg: [+-5]\n"),
       "spec.yaml:6: grid: heading_deg: '+-5' is not a finite number"},
      {with_grid("odometry", "  bump_height_m:\n    - 0.01\n    - -0.01\n"),
       "spec.yaml:8: grid: bump_height_m: -0.01 is outside 0..0.05 (height of every bump, metres "
       "(0.3 m long); 0 removes them)"},
      {with_grid("beacons", "  echo_probability: [0.1, 1.5]\n"),
       "spec.yaml:6: grid: echo_probability: 1.5 is outside 0..1 (per beacon, the chance an "
       "obstacle hides its direct path, so that the first wavefront heard is a wall echo (or "
       "nothing))"},
      {with_grid("odometry", "  policy: [rear_only, rear]\n"),
       "spec.yaml:6: grid: policy: unknown value 'rear' (expected per_component, whole_set, "
       "rear_only or front_only)"},
      {with_grid("odometry", "  policy: [rear_only, rear_only]\n"),
       "spec.yaml:6: grid: policy: rear_only given twice"},
      {with_grid("odometry", "  policy: rear_only\n  policy: front_only\n"),
       "spec.yaml:7: grid: 'policy' given twice"},
      {with_grid("odometry", "  policy: [[rear_only]]\n"),
       "spec.yaml:6: grid: policy: expected a single value, not a list or mapping"},
      {with_grid("odometry", "  scenario: [straight, square]\n  distance_m: [1, 2]\n"),
       "spec.yaml:6: grid: distance_m does not apply to scenario square (its path is fixed): "
       "sweep the square in a spec of its own"},
      {"name: t\nexperiment: odometry\nseed: 1\ntrials: 2\ngrid: {}\n",
       "spec.yaml:5: grid: expected a mapping of parameters to lists of values (at least one)"},
      {"name: t\nexperiment: odometry\nseed: -1\ntrials: 2\ngrid: {policy: rear_only}\n",
       "spec.yaml:3: seed: '-1' is not a whole number from 0 to 2^64 - 1"},
      {"name: t\nexperiment: odometry\nseed: 1.5\ntrials: 2\ngrid: {policy: rear_only}\n",
       "spec.yaml:3: seed: '1.5' is not a whole number from 0 to 2^64 - 1"},
      {"name: t\nexperiment: odometry\nseed: 1\ntrials: 0\ngrid: {policy: rear_only}\n",
       "spec.yaml:4: trials: '0' is not a whole number from 1 to 2^64 - 1"},
      {"name: t\nexperiment: odometry\nseed: 1\ntrials: 1000000000\ngrid:\n  policy: [rear_only, "
       "front_only]\n",
       "spec.yaml:6: grid: more than 1000000000 jobs (points x trials): split the sweep"},
      {"name: my sweep\nexperiment: odometry\nseed: 1\ntrials: 1\ngrid: {policy: rear_only}\n",
       "spec.yaml:1: name: 'my sweep': up to 80 letters, digits, '_', '-' and '.'"},
      {"name: t\nexperiment: odometry\ngrid: [\n",
       "spec.yaml:4: YAML: end of sequence flow not found"},
      {"- a list\n",
       "spec.yaml:1: a spec is a YAML mapping of name, experiment, seed, trials or grid"},
      {"", "spec.yaml: a spec is a YAML mapping of name, experiment, seed, trials or grid"},
      {head + "grid: {policy: rear_only}\n---\ntrials: 3\n",
       "spec.yaml:6: YAML: a second document ('---' or '...')"},
      {head + "grid: {policy: rear_only}\n...\n# a comment is no document\ntrials: 3\n",
       "spec.yaml:8: YAML: a second document ('---' or '...')"},
  };
  for (const auto& [yaml, message] : cases)
    EXPECT_EQ(spec_error(yaml), message) << yaml;
}

TEST(SweepSpec, CanonicalFormRoundTripsAndItsHashSeesEveryChange) {
  const sweep::Spec s = sweep::parse_spec(kBeaconSpec, "spec.yaml");
  const sweep::Spec back = sweep::spec_from_json(sweep::to_json(s), "");
  EXPECT_EQ(back, s);
  EXPECT_EQ(sweep::spec_hash(back), sweep::spec_hash(s));
  EXPECT_EQ(sweep::spec_hash(s).size(), 16U);
  // Comments, spacing and flow style do not change what is computed.
  const sweep::Spec restyled = sweep::parse_spec(
      "# same sweep\nname:   echo-temperature\nexperiment: beacons\nseed: 11\ntrials: 3\n"
      "grid: {echo_probability: [0.0, 0.5], temperature_c: [2e1, 35]}\n",
      "other.yaml");
  EXPECT_EQ(sweep::spec_hash(restyled), sweep::spec_hash(s));
  std::vector<sweep::Spec> changed(5, s);
  changed[0].seed += 1;
  changed[1].trials += 1;
  changed[2].axes[0].values[1] = 0.25;
  changed[3].name = "other";
  std::swap(changed[4].axes[0], changed[4].axes[1]);  // another point order
  for (const sweep::Spec& c : changed)
    EXPECT_NE(sweep::spec_hash(c), sweep::spec_hash(s));
}

TEST(SweepSpec, RandomMutationsGiveASpecOrAClearError) {
  const std::string base = std::string{kBeaconSpec} + "  layout: corners\n";
  std::mt19937_64 rng(2026);
  const std::string alphabet = "-:[]{},#\"' \n\t0123456789.eEaxnz_&*!|>%@`";
  int accepted = 0, refused = 0;
  for (int i = 0; i < 4000; ++i) {
    std::string text = odoloc::tb::mutated(base, rng, alphabet, 4, 8);
    if (rng() % 4 == 0 && !text.empty()) {  // a line repeated: a key given twice, a list longer
      const std::size_t at = rng() % text.size();
      const std::size_t start =
          text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
      const std::size_t end = text.find('\n', at);
      text.insert(start, text.substr(start, end == std::string::npos ? std::string::npos
                                                                     : end - start + 1));
    }
    try {
      const sweep::Spec s = sweep::parse_spec(text, "spec.yaml");
      ++accepted;
      EXPECT_LE(s.jobs(), sweep::kMaxJobs);
      EXPECT_EQ(sweep::spec_from_json(sweep::to_json(s), ""), s) << text;
    } catch (const sweep::SweepError& e) {
      ++refused;
      EXPECT_TRUE(e.usage());
      EXPECT_TRUE(std::string_view{e.what()}.starts_with("spec.yaml")) << e.what();
      EXPECT_EQ(std::string_view{e.what()}.find('\n'), std::string_view::npos) << e.what();
    }
  }
  std::printf("spec mutations: %d accepted, %d refused\n", accepted, refused);
  EXPECT_GT(accepted, 50);   // the mutations also make valid specs ...
  EXPECT_GT(refused, 1000);  // ... and mostly broken ones
}

// ------------------------------------------------------- shard files, merge

// Writes the spec's shards k/n for every k into `dir`; their paths.
std::vector<fs::path> run_all_shards(const sweep::Spec& spec, std::uint64_t n,
                                     const fs::path& dir) {
  std::vector<fs::path> paths;
  for (std::uint64_t k = 1; k <= n; ++k) {
    paths.push_back(dir / fmt::format("s{}.jsonl", k));
    EXPECT_EQ(sweep::run_shard(spec, {k, n}, paths.back()), sweep::Shard({k, n}).size(spec.jobs()));
  }
  return paths;
}

sweep::MergedSweep merged(const std::vector<fs::path>& paths) {
  std::vector<sweep::ShardFile> files;
  for (const fs::path& p : paths)
    files.push_back(sweep::load_shard_file(p));
  return sweep::merge(std::move(files));
}

std::string merge_error(const std::vector<fs::path>& paths) {
  try {
    (void)merged(paths);
  } catch (const sweep::SweepError& e) {
    EXPECT_TRUE(e.usage());
    return e.what();
  }
  ADD_FAILURE() << "merged";
  return {};
}

TEST(SweepMerge, ShardsGiveTheUnshardedTablesByteForByte) {
  const sweep::Spec spec = sweep::parse_spec(kBeaconSpec, "spec.yaml");
  const fs::path dir = fresh_dir("bytes");
  const sweep::MergedSweep whole = merged(run_all_shards(spec, 1, dir / "."));
  ASSERT_EQ(whole.jobs.size(), spec.jobs());
  for (const std::uint64_t n : {2U, 3U, 5U, 12U, 13U}) {  // 13: more shards than jobs
    const fs::path sub = dir / std::to_string(n);
    fs::create_directory(sub);
    std::vector<fs::path> paths = run_all_shards(spec, n, sub);
    std::ranges::reverse(paths);  // the order of the files does not matter
    const sweep::MergedSweep m = merged(paths);
    for (std::size_t j = 0; j < whole.jobs.size(); ++j)
      EXPECT_TRUE(m.jobs[j].same_as(whole.jobs[j])) << "job " << j << " with " << n << " shards";
    EXPECT_EQ(sweep::jobs_csv(m), sweep::jobs_csv(whole));
    EXPECT_EQ(sweep::points_csv(m), sweep::points_csv(whole));
    EXPECT_EQ(sweep::summary_markdown(m), sweep::summary_markdown(whole));
    EXPECT_EQ(sweep::plot_script(m), sweep::plot_script(whole));
  }
  // A job's values do not depend on which jobs ran before it in the process.
  const sweep::JobResult again = sweep::run_job(spec, 7);
  EXPECT_TRUE(again.same_as(whole.jobs[7]));
}

TEST(SweepMerge, FilesThatDoNotMakeOneRunAreRefusedByName) {
  const sweep::Spec spec = sweep::parse_spec(kBeaconSpec, "spec.yaml");
  sweep::Spec other = spec;
  other.seed = 12;
  const fs::path dir = fresh_dir("checks");
  fs::create_directories(dir / "four");
  fs::create_directories(dir / "three");
  fs::create_directories(dir / "other");
  const std::vector<fs::path> four = run_all_shards(spec, 4, dir / "four");
  const std::vector<fs::path> three = run_all_shards(spec, 3, dir / "three");
  const std::vector<fs::path> others = run_all_shards(other, 4, dir / "other");
  const auto name = [](const fs::path& p) { return p.string(); };

  EXPECT_EQ(
      merge_error({four[0], four[1], others[2], four[3]}),
      fmt::format("{} is from another sweep (spec {} 'echo-temperature') than {} (spec {} "
                  "'echo-temperature'): merge the shards of one run",
                  name(others[2]), sweep::spec_hash(other), name(four[0]), sweep::spec_hash(spec)));
  EXPECT_EQ(merge_error({four[0], three[1]}),
            fmt::format("{} is shard 2/3 but {} is shard 1/4: the shards of one run share N",
                        name(three[1]), name(four[0])));
  const fs::path copy = dir / "copy.jsonl";
  fs::copy_file(four[1], copy);
  EXPECT_EQ(merge_error({four[0], four[1], four[2], four[3], copy}),
            fmt::format("shard 2/4 given twice: {} and {}", name(four[1]), name(copy)));
  EXPECT_EQ(merge_error({four[1], four[3]}),
            "2 of 4 shards missing: 1/4, 3/4 (give every shard file of the run)");
  EXPECT_EQ(merge_error({}), "no shard file given");
}

// The lines of a file, each with its newline.
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    lines.push_back(line + "\n");
  return lines;
}

std::string shard_error(const std::string& text) {
  try {
    (void)sweep::parse_shard_file(text, "s.jsonl");
  } catch (const sweep::SweepError& e) {
    EXPECT_TRUE(e.usage());
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

TEST(SweepShardFile, DamagedFilesAreRefusedWithTheirLine) {
  const sweep::Spec spec = sweep::parse_spec(kBeaconSpec, "spec.yaml");
  const fs::path dir = fresh_dir("damage");
  const std::vector<fs::path> paths = run_all_shards(spec, 2, dir);
  const std::string text = slurp(paths[1]);  // shard 2/2: jobs 1, 3, 5, 7, 9, 11
  const std::vector<std::string> lines = lines_of(text);
  ASSERT_EQ(lines.size(), 7U);
  const auto joined = [](const std::vector<std::string>& l) {
    std::string out;
    for (const std::string& s : l)
      out += s;
    return out;
  };
  EXPECT_EQ(sweep::parse_shard_file(text, "s.jsonl").jobs.size(), 6U);

  std::vector<std::string> cut(lines.begin(), lines.end() - 2);
  EXPECT_EQ(shard_error(joined(cut)),
            "s.jsonl: 2 of the 6 jobs of shard 2/2 missing (jobs 9, 11): a truncated file, or a "
            "run that did not finish?");
  EXPECT_EQ(shard_error(text.substr(0, text.size() - 20)),
            "s.jsonl:7: the last line does not end with a newline (a truncated file?)");
  std::vector<std::string> twice = lines;
  twice.push_back(lines[2]);
  EXPECT_EQ(shard_error(joined(twice)), "s.jsonl:8: job 3 given twice (first on line 3)");
  std::vector<std::string> foreign = lines;
  foreign[3] = lines_of(slurp(paths[0]))[1];  // job 0 belongs to shard 1/2
  EXPECT_EQ(shard_error(joined(foreign)), "s.jsonl:4: job 0 is not in shard 2/2");
  std::vector<std::string> reseeded = lines;
  const std::size_t seed_at = reseeded[1].find("\"seed\":\"") + 8;
  reseeded[1][seed_at] = reseeded[1][seed_at] == '0' ? '1' : '0';
  EXPECT_TRUE(shard_error(joined(reseeded)).starts_with("s.jsonl:2: job 1: seed \""))
      << shard_error(joined(reseeded));
  std::vector<std::string> edited = lines;
  edited[0].replace(edited[0].find("\"seed\":11"), 9, "\"seed\":12");
  EXPECT_EQ(shard_error(joined(edited)),
            "s.jsonl:1: the spec does not match its hash (an edited file?)");
  EXPECT_EQ(shard_error("hello\n"),
            "s.jsonl:1: not a shard file of odoloc sweep run (its first line is not a JSON "
            "object)");
  EXPECT_EQ(shard_error(""), "s.jsonl: empty file, not a shard file");
  std::vector<std::string> blank = lines;
  blank.insert(blank.begin() + 2, "\n");
  EXPECT_EQ(shard_error(joined(blank)),
            "s.jsonl:3: not a JSON object (a truncated or edited file?)");
}

TEST(SweepShardFile, RandomMutationsGiveAFileOrAClearError) {
  const sweep::Spec spec = sweep::parse_spec(kBeaconSpec, "spec.yaml");
  const fs::path dir = fresh_dir("fuzz");
  const std::string text = slurp(run_all_shards(spec, 3, dir)[0]);
  std::mt19937_64 rng(13);
  const std::string alphabet = "{}[]\":,0123456789.-eE \nnulltrfa";
  int accepted = 0, refused = 0;
  for (int i = 0; i < 3000; ++i) {
    const std::string t = odoloc::tb::mutated(text, rng, alphabet, 3, 6);
    try {
      const sweep::ShardFile f = sweep::parse_shard_file(t, "s.jsonl");
      ++accepted;
      EXPECT_EQ(f.jobs.size(), f.shard.size(f.spec.jobs()));
    } catch (const sweep::SweepError& e) {
      ++refused;
      EXPECT_TRUE(std::string_view{e.what()}.starts_with("s.jsonl")) << e.what();
    }
  }
  std::printf("shard-file mutations: %d accepted, %d refused\n", accepted, refused);
  EXPECT_GT(refused, 1000);
  EXPECT_GT(accepted, 20);  // edits of a metric's digits are data, not damage
}

// ------------------------------------------------------------- statistics

TEST(SweepStatistics, MeanRmsAndNearestRankPercentile) {
  const double nan = std::nan("");
  const std::vector<double> v = {4, nan, 1, 3, 2};
  const sweep::Statistics s = sweep::statistics(v);
  EXPECT_EQ(s.n, 4U);
  EXPECT_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(7.5));
  EXPECT_EQ(s.p95, 4);
  std::vector<double> hundred, twenty;
  for (int i = 100; i >= 1; --i)
    hundred.push_back(i);
  for (int i = 1; i <= 20; ++i)
    twenty.push_back(i);
  EXPECT_EQ(sweep::statistics(hundred).p95, 95);  // the 95th smallest
  EXPECT_EQ(sweep::statistics(twenty).p95, 19);   // rank ceil(19) = 19, not 20
  const sweep::Statistics none = sweep::statistics(std::vector<double>{nan, nan});
  EXPECT_EQ(none.n, 0U);
  EXPECT_TRUE(std::isnan(none.mean) && std::isnan(none.rms) && std::isnan(none.p95));
}

// -------------------------------------------------------------- references

sweep::Spec odometry_spec(std::string_view grid, std::uint64_t trials = 1) {
  return sweep::parse_spec(
      fmt::format("name: ref\nexperiment: odometry\nseed: 5\ntrials: {}\ngrid:\n{}", trials, grid),
      "ref.yaml");
}

TEST(SweepReference, UndisturbedOdometryIsTheDirectScenarioRun) {
  const sweep::Spec spec = odometry_spec("  policy: [per_component]\n  distance_m: 1\n");
  const sweep::JobResult r = sweep::run_job(spec, 0);
  odoloc::board::RunOptions options;
  options.policy = odoloc::rtl::MinSelectPolicy::kPerComponent;
  const odoloc::board::RunResult direct = odoloc::board::run_scenario(
      odoloc::world::bump_scenario(odoloc::world::BumpCase::kNone, 1.0, 0.0), options);
  ASSERT_EQ(r.metrics.size(), 3U);
  EXPECT_EQ(r.metrics[0], direct.position_error_m);
  EXPECT_EQ(r.metrics[1], direct.heading_error_rad * 180 / std::numbers::pi);
  EXPECT_EQ(r.metrics[2],
            static_cast<double>(direct.front_wins_ds) / static_cast<double>(direct.updates));
}

// Both rear wheels 1 % larger than the fabric assumes: rear-only odometry
// counts 1/1.01 of the distance, so after d metres straight ahead it is
// d (1 - 1/1.01) behind (quantisation: an edge is 0.08 mm).
TEST(SweepReference, RearRadiusErrorShortensTheRearDistance) {
  const sweep::Spec spec = odometry_spec(
      "  policy: [rear_only]\n  distance_m: 1.5\n  left_radius_error: 0.01\n"
      "  right_radius_error: 0.01\n  heading_deg: 40\n");
  const double expected = 1.5 * (1 - 1 / 1.01);
  EXPECT_NEAR(sweep::run_job(spec, 0).metrics[0], expected, 0.3e-3);
}

// The speed of sound the solvers assume (20 C) over the air's scales every
// range: without noise or echoes, range_scale_error is exactly
// c(20)/c(T) - 1, c(T) = 331.3 sqrt(1 + T/273.15), here in long double.
// (A robot that hears fewer than three beacons directly has no value.)
TEST(SweepReference, TemperatureScalesTheRangesByTheRatioOfSpeedsOfSound) {
  const sweep::Spec spec = sweep::parse_spec(
      "name: ref\nexperiment: beacons\nseed: 3\ntrials: 10\ngrid:\n  temperature_c: [-10, 20, "
      "35]\n  reflection: 0\n  chain_sd_m: 0\n  path_jitter_s: 0\n  receiver_jitter_s: 0\n",
      "ref.yaml");
  const auto c = [](long double t) { return 331.3L * std::sqrt(1.0L + t / 273.15L); };
  const std::vector<long double> temperatures = {-10, 20, 35};
  int scaled = 0, exact_fixes = 0;
  for (std::uint64_t j = 0; j < spec.jobs(); ++j) {
    const sweep::JobResult r = sweep::run_job(spec, j);
    const long double t = temperatures[r.point];
    if (!std::isnan(r.metrics[3])) {
      ++scaled;
      EXPECT_NEAR(r.metrics[3], static_cast<double>(c(20) / c(t) - 1), 1e-9)
          << "T " << static_cast<double>(t);
    }
    if (r.point == 1 && r.metrics[0] == 1.0) {  // at the assumed temperature, a fix is exact
      ++exact_fixes;
      EXPECT_LT(r.metrics[1], 1e-9);
    }
  }
  EXPECT_GE(scaled, 25);      // of 30
  EXPECT_GE(exact_fixes, 7);  // of 10
}

// ----------------------------------------------------------- outputs, CLI

TEST(SweepOutputs, NoPartialFileIsLeftBehind) {
  const sweep::Spec spec = sweep::parse_spec(kBeaconSpec, "spec.yaml");
  const fs::path dir = fresh_dir("partial");
  try {
    (void)sweep::run_shard(spec, {1, 1}, dir / "missing" / "s.jsonl");
    ADD_FAILURE() << "wrote into a missing folder";
  } catch (const sweep::SweepError& e) {
    EXPECT_TRUE(e.usage());
    EXPECT_EQ(std::string{e.what()},
              fmt::format("cannot write {}: the folder {} does not exist",
                          (dir / "missing" / "s.jsonl").string(), (dir / "missing").string()));
  }
  int calls = 0;
  EXPECT_THROW((void)sweep::run_shard(spec, {1, 1}, dir / "s.jsonl",
                                      [&] {
                                        if (++calls == 3)
                                          throw std::runtime_error("stop");
                                      }),
               std::runtime_error);
  EXPECT_TRUE(fs::is_empty(dir)) << "a stopped run left a file";
  try {
    (void)sweep::write_merged(merged(run_all_shards(spec, 1, dir)), dir / "no" / "out", false);
    ADD_FAILURE() << "merged into a missing parent";
  } catch (const sweep::SweepError& e) {
    EXPECT_TRUE(e.usage());
    EXPECT_TRUE(std::string_view{e.what()}.find("cannot create the folder") != std::string::npos)
        << e.what();
  }
}

struct CliRun {
  int code = -1;
  std::string out, err;
};
CliRun cli_run(const std::vector<std::string>& args, const std::atomic<bool>* stop = nullptr) {
  std::istringstream in;
  std::ostringstream out, err;
  const cli::TargetOpener no_target =
      [](std::string_view, const cli::TargetOptions&) -> std::unique_ptr<cli::Target> {
    throw std::logic_error("sweep opened a target");
  };
  CliRun r;
  r.code = cli::run_cli(args, {in, out, err}, no_target, stop);
  r.out = out.str();
  r.err = err.str();
  return r;
}

TEST(SweepCli, ExitCodesAndMessages) {
  const fs::path dir = fresh_dir("cli");
  const std::string spec = (dir / "spec.yaml").string();
  std::ofstream(spec) << kBeaconSpec;
  const std::string out = (dir / "s.jsonl").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> usage = {
      {{"sweep", "run", spec, "--shard", "0/4", "--out", out},
       "odoloc: --shard: '0/4': K counts from 1 to N (4)\n"},
      {{"sweep", "run", spec, "--shard", "x", "--out", out},
       "odoloc: --shard: 'x': expected K/N, shard K of N (e.g. 2/4)\n"},
      {{"sweep", "run", spec, "--out", (dir / "none" / "s.jsonl").string()},
       fmt::format("odoloc: cannot write {}: the folder {} does not exist\n",
                   (dir / "none" / "s.jsonl").string(), (dir / "none").string())},
      {{"sweep", "run", (dir / "absent.yaml").string(), "--out", out},
       fmt::format("odoloc: cannot read spec {}\n", (dir / "absent.yaml").string())},
      {{"sweep", "run", spec, "--out", out, "--target", "sim"},
       "odoloc: --target does not apply to sweep run: it simulates in process and opens no "
       "target\n"},
      {{"sweep"}, "odoloc: sweep needs a command: run or merge\n"},
      {{"sweep", "rn"},
       "odoloc: unknown sweep command 'rn'; did you mean run? (expected run or merge)\n"},
      {{"sweep", "merge", "--out", (dir / "m").string(), (dir / "absent.jsonl").string()},
       fmt::format("odoloc: cannot read {}\n", (dir / "absent.jsonl").string())},
  };
  for (const auto& [args, message] : usage) {
    const CliRun r = cli_run(args);
    EXPECT_EQ(r.code, cli::kExitUsage) << args[1];
    EXPECT_EQ(r.err, message);
    EXPECT_FALSE(fs::exists(out));
  }
  const CliRun ok = cli_run({"sweep", "run", spec, "--out", out, "--shard", "2/2"});
  EXPECT_EQ(ok.code, cli::kExitOk) << ok.err;
  EXPECT_EQ(ok.out, fmt::format("{}: shard 2/2 of sweep echo-temperature (spec {}): 6 of 12 "
                                "jobs\n",
                                out, sweep::spec_hash(sweep::load_spec(spec))));
  const CliRun missing = cli_run({"sweep", "merge", "--out", (dir / "m").string(), out});
  EXPECT_EQ(missing.code, cli::kExitUsage);
  EXPECT_EQ(missing.err, "odoloc: 1 of 2 shards missing: 1/2 (give every shard file of the run)\n");
  EXPECT_FALSE(fs::exists(dir / "m"));

  // Ctrl-C between jobs: exit 130, no file.
  const std::atomic<bool> stop{true};
  const std::string stopped = (dir / "stopped.jsonl").string();
  EXPECT_EQ(cli_run({"sweep", "run", spec, "--out", stopped}, &stop).code, cli::kExitInterrupted);
  EXPECT_EQ(std::ranges::distance(fs::directory_iterator(dir)), 2);  // spec.yaml, s.jsonl
}

}  // namespace
