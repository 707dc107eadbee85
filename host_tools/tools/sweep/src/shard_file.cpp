#include "odoloc/sweep/shard_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "odoloc/sweep/error.hpp"

namespace odoloc::sweep {
namespace {

using nlohmann::json;

// Missing jobs named in a message, at most this many.
constexpr std::size_t kNamedJobs = 5;

std::string settings_text(const Spec& spec, std::uint64_t point) {
  std::string out;
  for (std::size_t i = 0; i < spec.axes.size(); ++i) {
    const Axis& a = spec.axes[i];
    if (a.given)
      out += fmt::format("{}{}={}", out.empty() ? "" : ", ", a.parameter,
                         to_text(a.values[spec.value_index(point, i)]));
  }
  return out;
}

std::optional<std::uint64_t> hex_seed(const json& value) {
  if (!value.is_string())
    return std::nullopt;
  const std::string& text = value.get_ref<const std::string&>();
  std::uint64_t seed = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), seed, 16);
  if (text.size() != 16 || ec != std::errc{} || end != text.data() + text.size())
    return std::nullopt;
  return seed;
}

class FileReader {
 public:
  explicit FileReader(std::string_view name) : name_(name) {}

  [[noreturn]] void fail(std::size_t line, std::string_view what) const {
    throw SweepError(true, fmt::format("{}:{}: {}", name_, line, what));
  }

  [[nodiscard]] json object(std::string_view text, std::size_t line) const {
    json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object())
      fail(line, line == 1 ? "not a shard file of odoloc sweep run (its first line is not a JSON "
                             "object)"
                           : "not a JSON object (a truncated or edited file?)");
    return j;
  }

  void header(const json& h, ShardFile& out) const {
    const auto has = [&](const char* key) { return h.contains(key); };
    if (!has("format") || h["format"] != std::string{kShardFormat})
      fail(1, fmt::format("not a shard file of odoloc sweep run (format '{}' expected)",
                          kShardFormat));
    if (h.size() != 6 || !has("spec") || !has("spec_hash") || !has("shard") || !has("shards") ||
        !has("jobs") || !h["spec_hash"].is_string() || !h["shard"].is_number_unsigned() ||
        !h["shards"].is_number_unsigned() || !h["jobs"].is_number_unsigned())
      fail(1, "the header needs exactly format, jobs, shard, shards, spec and spec_hash");
    out.spec = spec_from_json(h["spec"], fmt::format("{}:1: ", name_));
    out.hash = h["spec_hash"].get<std::string>();
    if (out.hash != spec_hash(out.spec))
      fail(1, "the spec does not match its hash (an edited file?)");
    try {
      out.shard = parse_shard(
          fmt::format("{}/{}", h["shard"].get<std::uint64_t>(), h["shards"].get<std::uint64_t>()));
    } catch (const SweepError& e) {
      fail(1, e.what());
    }
    if (h["jobs"].get<std::uint64_t>() != out.spec.jobs())
      fail(1, fmt::format("the header says {} jobs, its spec has {}",
                          h["jobs"].get<std::uint64_t>(), out.spec.jobs()));
  }

  [[nodiscard]] JobResult job(const json& j, const ShardFile& file, std::size_t line) const {
    const Spec& spec = file.spec;
    const std::span<const MetricInfo> names = metrics(spec.experiment);
    if (j.size() != 5 || !j.contains("job") || !j["job"].is_number_unsigned() ||
        !j.contains("point") || !j["point"].is_number_unsigned() || !j.contains("trial") ||
        !j["trial"].is_number_unsigned() || !j.contains("seed") || !j.contains("metrics") ||
        !j["metrics"].is_object())
      fail(line, "a job line has exactly job, metrics, point, seed and trial");
    JobResult r;
    r.job = j["job"].get<std::uint64_t>();
    r.point = j["point"].get<std::uint64_t>();
    r.trial = j["trial"].get<std::uint64_t>();
    if (r.job >= spec.jobs())
      fail(line, fmt::format("job {}: the spec has jobs 0 to {}", r.job, spec.jobs() - 1));
    if (!file.shard.owns(r.job))
      fail(line, fmt::format("job {} is not in shard {}/{}", r.job, file.shard.k, file.shard.n));
    if (r.point != r.job / spec.trials || r.trial != r.job % spec.trials)
      fail(line, fmt::format("job {} is point {} trial {}, not point {} trial {}", r.job,
                             r.job / spec.trials, r.job % spec.trials, r.point, r.trial));
    const std::optional<std::uint64_t> seed = hex_seed(j["seed"]);
    const std::uint64_t expected = job_seed(spec.seed, r.point, r.trial);
    if (seed != expected)
      fail(line, fmt::format("job {}: seed {} is not the seeding rule's {:016x}", r.job,
                             j["seed"].dump(), expected));
    r.seed = expected;
    const json& values = j["metrics"];
    if (values.size() != names.size())
      fail(line, fmt::format("job {}: {} metrics, the {} experiment has {}", r.job, values.size(),
                             name(spec.experiment), names.size()));
    for (const MetricInfo& m : names) {
      const auto it = values.find(m.name);
      if (it == values.end() || !(it->is_number() || it->is_null()))
        fail(line, fmt::format("job {}: metric {} is missing or not a number", r.job, m.name));
      r.metrics.push_back(it->is_null() ? std::nan("") : it->get<double>());
    }
    return r;
  }

 private:
  std::string_view name_;
};

}  // namespace

bool JobResult::same_as(const JobResult& other) const {
  if (job != other.job || point != other.point || trial != other.trial || seed != other.seed ||
      metrics.size() != other.metrics.size())
    return false;
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    const bool both_nan = std::isnan(metrics[i]) && std::isnan(other.metrics[i]);
    if (!both_nan && metrics[i] != other.metrics[i])
      return false;
  }
  return true;
}

JobResult run_job(const Spec& spec, std::uint64_t job) {
  JobResult r;
  r.job = job;
  r.point = job / spec.trials;
  r.trial = job % spec.trials;
  r.seed = job_seed(spec.seed, r.point, r.trial);
  try {
    r.metrics = run_trial(spec.experiment, spec.settings(r.point), r.seed);
  } catch (const SweepError& e) {
    throw SweepError(e.usage(), fmt::format("job {} (point {}: {}; trial {}): {}", job, r.point,
                                            settings_text(spec, r.point), r.trial, e.what()));
  }
  return r;
}

std::uint64_t run_shard(const Spec& spec, Shard shard, const std::filesystem::path& out,
                        const std::function<void()>& between_jobs) {
  output::OutputFile file = writing([&] { return output::OutputFile(out); });
  file.out() << header_line(spec, shard);
  std::uint64_t run = 0;
  for (std::uint64_t job = shard.k - 1; job < spec.jobs(); job += shard.n) {
    if (between_jobs)
      between_jobs();
    file.out() << job_line(spec, run_job(spec, job));
    ++run;
  }
  writing([&] { file.commit(); });
  return run;
}

std::string header_line(const Spec& spec, Shard shard) {
  return json{{"format", std::string{kShardFormat}},
              {"jobs", spec.jobs()},
              {"shard", shard.k},
              {"shards", shard.n},
              {"spec", to_json(spec)},
              {"spec_hash", spec_hash(spec)}}
             .dump() +
         '\n';
}

std::string job_line(const Spec& spec, const JobResult& result) {
  json values = json::object();
  const std::span<const MetricInfo> names = metrics(spec.experiment);
  for (std::size_t i = 0; i < names.size(); ++i)
    values[std::string{names[i].name}] = result.metrics.at(i);  // NaN dumps as null
  return json{{"job", result.job},
              {"metrics", std::move(values)},
              {"point", result.point},
              {"seed", fmt::format("{:016x}", result.seed)},
              {"trial", result.trial}}
             .dump() +
         '\n';
}

ShardFile parse_shard_file(std::string_view text, std::string_view name) {
  const FileReader reader(name);
  ShardFile out;
  out.name = std::string{name};
  std::size_t line = 0;
  // The line of each job seen: a map, since a header may promise many jobs.
  std::map<std::uint64_t, std::size_t> seen_on;
  while (!text.empty()) {
    ++line;
    const std::size_t end = text.find('\n');
    if (end == std::string_view::npos)
      reader.fail(line, "the last line does not end with a newline (a truncated file?)");
    const std::string_view content = text.substr(0, end);
    text.remove_prefix(end + 1);
    const json j = reader.object(content, line);
    if (line == 1) {
      reader.header(j, out);
      continue;
    }
    JobResult r = reader.job(j, out, line);
    const auto [first, fresh] = seen_on.try_emplace(r.job, line);
    if (!fresh)
      reader.fail(line, fmt::format("job {} given twice (first on line {})", r.job, first->second));
    out.jobs.push_back(std::move(r));
  }
  if (line == 0)
    throw SweepError(true, fmt::format("{}: empty file, not a shard file", name));
  const std::uint64_t expected = out.shard.size(out.spec.jobs());
  if (seen_on.size() != expected) {
    // The first few gaps in the shard's job sequence k - 1, k - 1 + n, ...
    std::vector<std::string> missing;
    auto present = seen_on.begin();
    for (std::uint64_t job = out.shard.k - 1; job < out.spec.jobs() && missing.size() < kNamedJobs;
         job += out.shard.n) {
      if (present != seen_on.end() && present->first == job)
        ++present;
      else
        missing.push_back(std::to_string(job));
    }
    const std::uint64_t count = expected - seen_on.size();
    throw SweepError(
        true, fmt::format("{}: {} of the {} jobs of shard {}/{} missing (jobs {}{}): a truncated "
                          "file, or a run that did not finish?",
                          name, count, expected, out.shard.k, out.shard.n, fmt::join(missing, ", "),
                          count > missing.size() ? ", ..." : ""));
  }
  std::ranges::sort(out.jobs, {}, &JobResult::job);
  return out;
}

ShardFile load_shard_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw SweepError(true, fmt::format("cannot read {}: it is a directory", path.string()));
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in)
    throw SweepError(true, fmt::format("cannot read {}", path.string()));
  return parse_shard_file(text.str(), path.string());
}

}  // namespace odoloc::sweep
