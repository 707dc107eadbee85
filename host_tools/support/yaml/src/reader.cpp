#include "odoloc/yaml/reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <vector>

#include "odoloc/output/printable.hpp"
#include "odoloc/yaml/one_document.hpp"

namespace odoloc::yaml {

std::optional<double> finite_number(std::string_view text) {
  if (text.starts_with('+') && !text.substr(1).starts_with('-'))
    text.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size() ||
      !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::optional<std::uint64_t> whole_number(std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size())
    return std::nullopt;
  return value;
}

namespace {

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && space(s.front()))
    s.remove_prefix(1);
  while (!s.empty() && space(s.back()))
    s.remove_suffix(1);
  return s;
}

}  // namespace

std::vector<std::string_view> split_fields(std::string_view text, char separator) {
  std::vector<std::string_view> fields;
  for (std::size_t start = 0;;) {
    const std::size_t end = text.find(separator, start);
    fields.push_back(trim(text.substr(start, end - start)));
    if (end == std::string_view::npos)
      return fields;
    start = end + 1;
  }
}

YAML::Node Reader::load(const std::string& text) const {
  try {
    return load_one_document(text);
  } catch (const YAML::Exception& e) {  // syntax, nesting too deep, a second document
    const std::string what = fmt::format("YAML: {}", output::printable_excerpt(e.msg, 200));
    if (e.mark.is_null())
      throw InputError(fmt::format("{}: {}", file_, what));
    throw InputError(fmt::format("{}:{}: {}", file_, e.mark.line + 1, what));
  }
}

void Reader::fail(const YAML::Node& at, std::string_view what) const {
  const YAML::Mark mark = at.Mark();
  if (mark.is_null())
    throw InputError(fmt::format("{}: {}", file_, what));
  throw InputError(fmt::format("{}:{}: {}", file_, mark.line + 1, what));
}

void Reader::check_keys(const YAML::Node& map, std::string_view where,
                        std::initializer_list<std::string_view> known) const {
  if (!map.IsMap())
    fail(map, fmt::format("{}: expected a mapping of {}", where, fmt::join(known, ", ")));
  std::vector<std::string> seen;
  for (const auto& kv : map) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string{};
    if (std::ranges::find(known, key) == known.end())
      fail(kv.first, fmt::format("{}: unknown key '{}' (known: {})", where,
                                 output::printable_excerpt(key), fmt::join(known, ", ")));
    if (std::ranges::find(seen, key) != seen.end())
      fail(kv.first, fmt::format("{}: '{}' given twice", where, output::printable_excerpt(key)));
    seen.push_back(key);
  }
}

YAML::Node Reader::required(const YAML::Node& map, std::string_view key,
                            std::string_view where) const {
  YAML::Node value = map[std::string{key}];
  if (!value || value.IsNull())
    fail(map, fmt::format("{}: missing '{}'", where, key));
  return value;
}

std::string Reader::scalar(const YAML::Node& node, std::string_view where) const {
  if (!node.IsScalar())
    fail(node, fmt::format("{}: expected a single value, not {}", where,
                           node.IsNull() ? "nothing" : "a list or mapping"));
  return node.Scalar();
}

double Reader::number(const YAML::Node& node, std::string_view where, double least,
                      double most) const {
  const std::optional<double> v =
      node.IsScalar() ? finite_number(node.Scalar()) : std::optional<double>{};
  if (!v)
    fail(node, fmt::format("{} must be a finite number, not '{}'", where,
                           node.IsScalar() ? output::printable_excerpt(node.Scalar())
                                           : "a list or mapping"));
  if (!(*v >= least && *v <= most))
    fail(node, fmt::format("{}: {} is outside [{}, {}]", where, *v, least, most));
  return *v;
}

double Reader::number_or(const YAML::Node& map, std::string_view key, std::string_view where,
                         double fallback, double least, double most) const {
  const YAML::Node value = map[std::string{key}];
  if (!value)
    return fallback;
  return number(value, fmt::format("{}.{}", where, key), least, most);
}

std::uint64_t Reader::whole(const YAML::Node& node, std::string_view where, std::uint64_t least,
                            std::uint64_t most) const {
  const std::string text = scalar(node, where);
  const std::optional<std::uint64_t> v = whole_number(text);
  if (!v || *v < least || *v > most)
    fail(node, fmt::format("{}: '{}' is not a whole number from {} to {}", where,
                           output::printable_excerpt(text), least, most));
  return *v;
}

std::vector<double> Reader::numbers(const YAML::Node& node, std::string_view where,
                                    std::size_t size) const {
  if (!node.IsSequence() || (size != 0 && node.size() != size) || node.size() == 0)
    fail(node, size == 0 ? fmt::format("{}: expected a list of numbers", where)
                         : fmt::format("{}: expected a list of {} numbers", where, size));
  std::vector<double> out;
  for (const YAML::Node& item : node)
    out.push_back(number(item, where));
  return out;
}

void Reader::sequence(const YAML::Node& node, std::string_view where) const {
  if (!node.IsSequence())
    fail(node, fmt::format("{}: expected a list", where));
}

}  // namespace odoloc::yaml
