#include "odoloc/sweep/spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "odoloc/output/printable.hpp"
#include "odoloc/sweep/error.hpp"
#include "odoloc/yaml/one_document.hpp"
#include "odoloc/yaml/reader.hpp"

namespace odoloc::sweep {
namespace {

constexpr std::array<std::string_view, 5> kKeys = {"name", "experiment", "seed", "trials", "grid"};
constexpr std::size_t kMaxNameLength = 80;

[[noreturn]] void usage_error(const std::string& what) {
  throw SweepError(true, what);
}

// "a, b, c or d"
std::string listed(std::span<const std::string_view> names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + std::string{names[i]};
  return out;
}

std::vector<std::string_view> parameter_names(Experiment experiment) {
  std::vector<std::string_view> names;
  for (const ParameterInfo& p : parameters(experiment))
    names.push_back(p.name);
  return names;
}

// Sweep names appear in titles and file headers: letters, digits, '_', '-', '.'.
bool is_sweep_name(std::string_view name) {
  return !name.empty() && name.size() <= kMaxNameLength && std::ranges::all_of(name, [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.';
  });
}

// The problem with one value of a parameter, or an empty string.
std::string check_value(const ParameterInfo& p, const Value& value) {
  if (p.is_choice()) {
    const auto* text = std::get_if<std::string>(&value);
    if (text == nullptr || std::ranges::find(p.choices, *text) == p.choices.end())
      return fmt::format("unknown value '{}' (expected {})",
                         text == nullptr ? to_text(value) : output::printable_excerpt(*text),
                         listed(p.choices));
    return {};
  }
  const auto* number = std::get_if<double>(&value);
  if (number == nullptr)
    return fmt::format("'{}' is not a finite number",
                       output::printable_excerpt(std::get<std::string>(value)));
  if (!(*number >= p.min && *number <= p.max))
    return fmt::format("{} is outside {}..{} ({})", *number, p.min, p.max, p.meaning);
  return {};
}

// The checks every spec passes, however it was read: jobs within bounds,
// and the parameters that do not combine.
std::string check_spec(const Spec& spec) {
  if (spec.experiment == Experiment::kOdometry) {
    const auto axis = [&](std::string_view name) {
      return std::ranges::find(spec.axes, name, &Axis::parameter);
    };
    const auto scenario = axis("scenario");
    const auto distance = axis("distance_m");
    if (distance != spec.axes.end() && distance->given && scenario != spec.axes.end() &&
        std::ranges::find(scenario->values, Value{std::string{"square"}}) != scenario->values.end())
      return "distance_m does not apply to scenario square (its path is fixed): sweep the "
             "square in a spec of its own";
  }
  std::uint64_t jobs = spec.trials;
  for (const Axis& a : spec.axes) {
    if (jobs > kMaxJobs / a.values.size())
      return fmt::format("more than {} jobs (points x trials): split the sweep", kMaxJobs);
    jobs *= a.values.size();
  }
  return {};
}

class Reader {
 public:
  explicit Reader(std::string_view file) : file_(file) {}

  [[noreturn]] void fail(const YAML::Node& at, std::string_view what) const {
    const YAML::Mark mark = at.Mark();
    if (mark.is_null())
      usage_error(fmt::format("{}: {}", file_, what));
    usage_error(fmt::format("{}:{}: {}", file_, mark.line + 1, what));
  }

  [[nodiscard]] std::string scalar(const YAML::Node& node, std::string_view key) const {
    if (!node.IsScalar())
      fail(node, fmt::format("{}: expected a single value, not {}", key,
                             node.IsNull() ? "nothing" : "a list or mapping"));
    return node.Scalar();
  }

  [[nodiscard]] std::uint64_t whole(const YAML::Node& node, std::string_view key,
                                    std::uint64_t least) const {
    const std::string text = scalar(node, key);
    const std::optional<std::uint64_t> v = yaml::whole_number(text);
    if (!v || *v < least)
      fail(node, fmt::format("{}: '{}' is not a whole number from {} to 2^64 - 1", key,
                             output::printable_excerpt(text), least));
    return *v;
  }

  [[nodiscard]] Value value(const ParameterInfo& p, const YAML::Node& node) const {
    const std::string where = fmt::format("grid: {}", p.name);
    const std::string text = scalar(node, where);
    Value v = text;
    if (!p.is_choice()) {
      if (const std::optional<double> number = yaml::finite_number(text))
        v = *number;
    }
    if (const std::string problem = check_value(p, v); !problem.empty())
      fail(node, fmt::format("{}: {}", where, problem));
    return v;
  }

  [[nodiscard]] Axis axis(const ParameterInfo& p, const YAML::Node& key,
                          const YAML::Node& node) const {
    Axis a{std::string{p.name}, {}, true};
    if (node.IsNull())  // its mark is where the next key starts: name this one's line
      fail(key, fmt::format("grid: {}: no value (give one, or a list)", p.name));
    if (node.IsSequence() && node.size() == 0)
      fail(node, fmt::format("grid: {}: an empty list (give at least one value)", p.name));
    const auto add = [&](const YAML::Node& item) {
      Value v = value(p, item);
      if (std::ranges::find(a.values, v) != a.values.end())
        fail(item, fmt::format("grid: {}: {} given twice", p.name, to_text(v)));
      a.values.push_back(std::move(v));
    };
    if (node.IsSequence()) {
      for (const YAML::Node& item : node)
        add(item);
    } else {
      add(node);  // a single value: a one-point axis
    }
    return a;
  }

  // The keys of a mapping: each once, each one of `known` (a `noun`).
  void check_keys(const YAML::Node& map, std::string_view prefix, std::string_view noun,
                  std::span<const std::string_view> known) const {
    std::vector<std::string> seen;
    for (const auto& kv : map) {
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string{};
      if (std::ranges::find(known, key) == known.end())
        fail(kv.first, fmt::format("{}unknown {} '{}' (expected {})", prefix, noun,
                                   output::printable_excerpt(key), listed(known)));
      if (std::ranges::find(seen, key) != seen.end())
        fail(kv.first, fmt::format("{}'{}' given twice", prefix, key));
      seen.push_back(key);
    }
  }

  [[nodiscard]] Spec spec(const YAML::Node& root) const {
    if (!root.IsMap())
      fail(root, fmt::format("a spec is a YAML mapping of {}", listed(kKeys)));
    check_keys(root, "", "key", kKeys);
    for (const std::string_view key : kKeys) {
      if (!root[std::string{key}])
        fail(root, fmt::format("missing '{}'", key));
    }
    Spec s;
    s.name = scalar(root["name"], "name");
    if (!is_sweep_name(s.name))
      fail(root["name"], fmt::format("name: '{}': up to {} letters, digits, '_', '-' and '.'",
                                     output::printable_excerpt(s.name), kMaxNameLength));
    const std::string experiment = scalar(root["experiment"], "experiment");
    const auto known = std::ranges::find(kExperimentNames, experiment);
    if (known == std::end(kExperimentNames))
      fail(root["experiment"],
           fmt::format("unknown experiment '{}' (expected {})",
                       output::printable_excerpt(experiment), listed(kExperimentNames)));
    s.experiment = static_cast<Experiment>(known - std::begin(kExperimentNames));
    s.seed = whole(root["seed"], "seed", 0);
    s.trials = whole(root["trials"], "trials", 1);
    const YAML::Node grid = root["grid"];
    if (!grid.IsMap() || grid.size() == 0)
      fail(grid, "grid: expected a mapping of parameters to lists of values (at least one)");
    const std::vector<std::string_view> names = parameter_names(s.experiment);
    check_keys(grid, "grid: ", fmt::format("{} parameter", experiment), names);
    for (const auto& kv : grid)
      s.axes.push_back(axis(*find_parameter(s.experiment, kv.first.Scalar()), kv.first, kv.second));
    for (const ParameterInfo& p : parameters(s.experiment)) {
      if (std::ranges::find(s.axes, p.name, &Axis::parameter) == s.axes.end())
        s.axes.push_back({std::string{p.name}, {p.default_value()}, false});
    }
    if (const std::string problem = check_spec(s); !problem.empty())
      fail(grid, fmt::format("grid: {}", problem));
    return s;
  }

 private:
  std::string_view file_;
};

}  // namespace

std::uint64_t Spec::points() const {
  std::uint64_t n = 1;
  for (const Axis& a : axes)
    n *= a.values.size();
  return n;
}

std::uint64_t Spec::jobs() const {
  return points() * trials;
}

std::size_t Spec::value_index(std::uint64_t point, std::size_t axis) const {
  std::uint64_t stride = 1;
  for (std::size_t i = axis + 1; i < axes.size(); ++i)
    stride *= axes[i].values.size();
  return static_cast<std::size_t>(point / stride % axes[axis].values.size());
}

Settings Spec::settings(std::uint64_t point) const {
  Settings s;
  for (std::size_t i = 0; i < axes.size(); ++i)
    s.emplace(axes[i].parameter, axes[i].values[value_index(point, i)]);
  return s;
}

Spec parse_spec(std::string_view yaml, std::string_view file) {
  const Reader reader(file);
  try {
    return reader.spec(yaml::load_one_document(std::string{yaml}));
  } catch (const YAML::Exception& e) {  // syntax, nesting too deep, ...
    const std::string message = fmt::format("YAML: {}", output::printable_excerpt(e.msg));
    if (e.mark.is_null())
      usage_error(fmt::format("{}: {}", file, message));
    usage_error(fmt::format("{}:{}: {}", file, e.mark.line + 1, message));
  }
}

Spec load_spec(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    usage_error(fmt::format("cannot read spec {}: it is a directory", path.string()));
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in)
    usage_error(fmt::format("cannot read spec {}", path.string()));
  return parse_spec(text.str(), path.string());
}

nlohmann::json to_json(const Spec& spec) {
  nlohmann::json axes = nlohmann::json::array();
  for (const Axis& a : spec.axes) {
    nlohmann::json values = nlohmann::json::array();
    for (const Value& v : a.values)
      std::visit([&](const auto& x) { values.push_back(x); }, v);
    axes.push_back({{"parameter", a.parameter}, {"values", std::move(values)}, {"given", a.given}});
  }
  return {{"name", spec.name},
          {"experiment", name(spec.experiment)},
          {"seed", spec.seed},
          {"trials", spec.trials},
          {"axes", std::move(axes)}};
}

Spec spec_from_json(const nlohmann::json& json, std::string_view where) {
  const auto fail = [&](std::string_view what) { usage_error(fmt::format("{}{}", where, what)); };
  const auto field = [&](std::string_view key) -> const nlohmann::json& {
    if (!json.is_object() || !json.contains(key))
      fail(fmt::format("spec: missing '{}'", key));
    return json.at(key);
  };
  Spec s;
  const nlohmann::json& name_field = field("name");
  if (!name_field.is_string() || !is_sweep_name(name_field.get<std::string>()))
    fail("spec: bad name");
  s.name = name_field.get<std::string>();
  const nlohmann::json& experiment = field("experiment");
  const auto known = experiment.is_string()
                         ? std::ranges::find(kExperimentNames, experiment.get<std::string>())
                         : std::end(kExperimentNames);
  if (known == std::end(kExperimentNames))
    fail("spec: unknown experiment");
  s.experiment = static_cast<Experiment>(known - std::begin(kExperimentNames));
  const nlohmann::json& seed = field("seed");
  const nlohmann::json& trials = field("trials");
  if (!seed.is_number_unsigned() || !trials.is_number_unsigned() || trials.get<std::uint64_t>() < 1)
    fail("spec: seed and trials are whole numbers (trials at least 1)");
  s.seed = seed.get<std::uint64_t>();
  s.trials = trials.get<std::uint64_t>();
  const nlohmann::json& axes = field("axes");
  if (!axes.is_array() || json.size() != 5)
    fail("spec: expected name, experiment, seed, trials and axes");
  for (const nlohmann::json& a : axes) {
    if (!a.is_object() || a.size() != 3 || !a.contains("parameter") || !a.contains("values") ||
        !a.contains("given") || !a["parameter"].is_string() || !a["values"].is_array() ||
        a["values"].empty() || !a["given"].is_boolean())
      fail("spec: an axis is {\"parameter\", \"values\" (not empty), \"given\"}");
    const std::string parameter = a["parameter"].get<std::string>();
    const ParameterInfo* p = find_parameter(s.experiment, parameter);
    if (p == nullptr || std::ranges::find(s.axes, parameter, &Axis::parameter) != s.axes.end())
      fail(fmt::format("spec: parameter '{}' unknown or given twice",
                       output::printable_excerpt(parameter)));
    Axis axis{parameter, {}, a["given"].get<bool>()};
    for (const nlohmann::json& v : a["values"]) {
      Value value;
      if (v.is_number())
        value = v.get<double>();
      else if (v.is_string())
        value = v.get<std::string>();
      else
        fail(fmt::format("spec: {}: a value is a number or a name", parameter));
      if (const std::string problem = check_value(*p, value); !problem.empty())
        fail(fmt::format("spec: {}: {}", parameter, problem));
      if (std::ranges::find(axis.values, value) != axis.values.end())
        fail(fmt::format("spec: {}: {} given twice", parameter, to_text(value)));
      axis.values.push_back(std::move(value));
    }
    if (!axis.given && axis.values.size() != 1)
      fail(fmt::format("spec: {}: a default has one value", parameter));
    s.axes.push_back(std::move(axis));
  }
  if (s.axes.size() != parameters(s.experiment).size())
    fail("spec: not every parameter of the experiment is there");
  if (const std::string problem = check_spec(s); !problem.empty())
    fail(fmt::format("spec: {}", problem));
  return s;
}

std::string spec_hash(const Spec& spec) {
  std::uint64_t h = 0xcbf29ce484222325U;  // FNV-1a 64: offset basis and prime
  for (const char c : to_json(spec).dump()) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3U;
  }
  return fmt::format("{:016x}", h);
}

std::string to_text(const Value& value) {
  if (const auto* number = std::get_if<double>(&value))
    return fmt::format("{}", *number);
  return std::get<std::string>(value);
}

}  // namespace odoloc::sweep
