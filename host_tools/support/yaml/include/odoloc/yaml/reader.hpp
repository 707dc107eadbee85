// Reading a YAML input file whose every mistake is an error naming the file
// and the line (docs/host-tool.md, "Input files"): unknown and repeated
// keys, missing values, numbers that are not finite, values out of range.
// Used by the scenario files (docs/scenarios.md); the layouts and sweep
// specs share its number rules (finite_number, whole_number), and the CSV
// files beside them (odoloc locate's arrivals, a scenario's recorded
// trajectory) its field splitting (split_fields).
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace odoloc::yaml {

// A finite decimal number as the input files write it: an optional '+' or
// '-', digits, a fraction and an exponent (std::from_chars' general
// format). No spaces, no "+-", no nan or inf.
[[nodiscard]] std::optional<double> finite_number(std::string_view text);
// Decimal digits only, 0 .. 2^64 - 1: no sign, space, base prefix or fraction.
[[nodiscard]] std::optional<std::uint64_t> whole_number(std::string_view text);
// The fields of a CSV line (or a list like --triple's), trimmed of spaces,
// tabs and CRs. No quoting: ids and numbers need none.
[[nodiscard]] std::vector<std::string_view> split_fields(std::string_view text,
                                                         char separator = ',');

// "FILE:LINE: what" (or "FILE: what" where the node has no place).
// usage(): the file's content is wrong (false: the file could not be read).
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what, bool usage = true)
      : std::runtime_error(what), usage_(usage) {}
  [[nodiscard]] bool usage() const { return usage_; }

 private:
  bool usage_;
};

class Reader {
 public:
  // `file` names the input in every message; it must outlive the reader.
  explicit Reader(std::string_view file) : file_(file) {}

  // The one document of `text` (load_one_document); yaml-cpp's own errors
  // (syntax, a second document) become InputError at their line.
  [[nodiscard]] YAML::Node load(const std::string& text) const;

  [[noreturn]] void fail(const YAML::Node& at, std::string_view what) const;

  // `map` is a mapping whose keys are each one of `known`, each once.
  void check_keys(const YAML::Node& map, std::string_view where,
                  std::initializer_list<std::string_view> known) const;
  // map[key], which must be there.
  [[nodiscard]] YAML::Node required(const YAML::Node& map, std::string_view key,
                                    std::string_view where) const;
  [[nodiscard]] std::string scalar(const YAML::Node& node, std::string_view where) const;
  // A finite number in [least, most]; `where` names it ("layout: x").
  [[nodiscard]] double number(const YAML::Node& node, std::string_view where, double least = -1e300,
                              double most = 1e300) const;
  // map[key] as number(), or `fallback` when the key is absent.
  [[nodiscard]] double number_or(const YAML::Node& map, std::string_view key,
                                 std::string_view where, double fallback, double least = -1e300,
                                 double most = 1e300) const;
  // A whole number in [least, most].
  [[nodiscard]] std::uint64_t whole(const YAML::Node& node, std::string_view where,
                                    std::uint64_t least = 0,
                                    std::uint64_t most = ~std::uint64_t{0}) const;
  // A list of `size` numbers ([x, y] for size 2), or of any size >= 1 for
  // size 0.
  [[nodiscard]] std::vector<double> numbers(const YAML::Node& node, std::string_view where,
                                            std::size_t size = 0) const;
  // A sequence (possibly empty).
  void sequence(const YAML::Node& node, std::string_view where) const;

 private:
  std::string_view file_;
};

}  // namespace odoloc::yaml
