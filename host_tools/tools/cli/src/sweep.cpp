#include "odoloc/cli/sweep.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <ostream>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc/sweep/error.hpp"
#include "odoloc/sweep/merge.hpp"
#include "odoloc/sweep/shard_file.hpp"

namespace odoloc::cli {

sweep::Shard parse_shard_option(const std::string& text) {
  return translated<sweep::SweepError>([&] { return sweep::parse_shard(text); });
}

void run_sweep_run(const SweepRunCommand& command, std::ostream& out, bool json,
                   const std::atomic<bool>* stop) {
  const sweep::Spec spec =
      translated<sweep::SweepError>([&] { return sweep::load_spec(command.spec); });
  const std::uint64_t jobs = translated<sweep::SweepError>([&] {
    return sweep::run_shard(spec, command.shard, command.out, [stop] {
      if (stop != nullptr && stop->load())
        throw Interrupted();
    });
  });
  const std::string hash = sweep::spec_hash(spec);
  if (json) {
    out << json_line(nlohmann::json{{"file", command.out},
                                    {"sweep", spec.name},
                                    {"spec_hash", hash},
                                    {"shard", command.shard.k},
                                    {"shards", command.shard.n},
                                    {"jobs", jobs},
                                    {"total_jobs", spec.jobs()}})
        << '\n';
    return;
  }
  out << fmt::format("{}: shard {}/{} of sweep {} (spec {}): {} of {} jobs\n",
                     output::printable(command.out), command.shard.k, command.shard.n,
                     output::printable(spec.name), hash, jobs, spec.jobs());
}

void run_sweep_merge(const SweepMergeCommand& command, std::ostream& out, bool json,
                     const std::atomic<bool>* stop) {
  const sweep::MergedSweep merged = translated<sweep::SweepError>([&] {
    std::vector<sweep::ShardFile> files;
    for (const std::string& f : command.files) {
      if (stop != nullptr && stop->load())
        throw Interrupted();
      files.push_back(sweep::load_shard_file(f));
    }
    return sweep::merge(std::move(files));
  });
  const std::vector<std::filesystem::path> written = translated<sweep::SweepError>(
      [&] { return sweep::write_merged(merged, command.out, command.plot, stop); });
  std::vector<std::string> names;
  for (const std::filesystem::path& p : written)
    names.push_back(p.filename().string());
  if (json) {
    out << json_line(nlohmann::json{{"folder", command.out},
                                    {"files", names},
                                    {"sweep", merged.spec.name},
                                    {"spec_hash", merged.hash},
                                    {"jobs", merged.jobs.size()}})
        << '\n';
    return;
  }
  out << fmt::format("{}: {} jobs of sweep {} (spec {}): {}\n", output::printable(command.out),
                     merged.jobs.size(), output::printable(merged.spec.name), merged.hash,
                     fmt::join(names, " "));
}

}  // namespace odoloc::cli
