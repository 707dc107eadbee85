// A sweep's description (docs/sweep.md#the-spec): a YAML file with its
// name, experiment, seed, trials per point and a grid of parameter values,
// whose cartesian product is the points.
//
//   name: bump-height
//   experiment: odometry
//   seed: 2026
//   trials: 4
//   grid:                      # the first key varies slowest
//     bump_height_m: [0, 0.01, 0.025]
//     policy: [per_component, rear_only]
//
// Every parameter the grid does not name keeps its default. The canonical
// form (to_json) holds every parameter, so its hash identifies what a run
// computes, and every shard file carries it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/sweep/experiments.hpp"

namespace odoloc::sweep {

// The most jobs (points x trials) one spec may describe.
inline constexpr std::uint64_t kMaxJobs = 1'000'000'000;

// One parameter's values: a grid key, or a default (given == false, one value).
struct Axis {
  std::string parameter;
  std::vector<Value> values;  // not empty, no value twice
  bool given = true;          // named in the spec's grid

  bool operator==(const Axis&) const = default;
};

struct Spec {
  std::string name;
  Experiment experiment = Experiment::kOdometry;
  std::uint64_t seed = 0;
  std::uint64_t trials = 1;
  // Every parameter of the experiment once: the grid's keys in the file's
  // order, then the others in parameters() order with their default.
  std::vector<Axis> axes;

  bool operator==(const Spec&) const = default;

  // The product of the axes' sizes; point p has axis i's value
  // (p / stride_i) % size_i, stride_i the product of the later axes' sizes
  // (the first axis varies slowest).
  [[nodiscard]] std::uint64_t points() const;
  // points() x trials; job j is trial j % trials of point j / trials.
  [[nodiscard]] std::uint64_t jobs() const;
  // Every parameter's value at point p < points().
  [[nodiscard]] Settings settings(std::uint64_t point) const;
  // The index into axes[axis].values of point p.
  [[nodiscard]] std::size_t value_index(std::uint64_t point, std::size_t axis) const;
};

// `file` names the input in messages. Throws SweepError (usage) naming the
// file, the line and the key: YAML syntax, unknown or repeated keys, an
// unknown experiment or parameter, an empty list, a value out of range or
// not finite, a name the parameter does not take, a value given twice, a
// seed or trial count that is not a whole number, more than kMaxJobs jobs.
[[nodiscard]] Spec parse_spec(std::string_view yaml, std::string_view file);
// The same on a file; SweepError (usage) when it cannot be read.
[[nodiscard]] Spec load_spec(const std::filesystem::path& path);

// The canonical form: {"name", "experiment", "seed", "trials", "axes": [{"parameter",
// "values", "given"}...]}, numbers as doubles, names as strings.
[[nodiscard]] nlohmann::json to_json(const Spec& spec);
// Back from the canonical form, checked as parse_spec checks YAML (and that
// every parameter of the experiment is there once); SweepError (usage)
// prefixed with `where`.
[[nodiscard]] Spec spec_from_json(const nlohmann::json& json, std::string_view where);

// 16 lowercase hex digits: FNV-1a (64 bits) of to_json(spec).dump().
[[nodiscard]] std::string spec_hash(const Spec& spec);

// A value as the tables print it: a number in its shortest round-trip
// form ("0.025", "1e-06"), a name as it is.
[[nodiscard]] std::string to_text(const Value& value);

}  // namespace odoloc::sweep
