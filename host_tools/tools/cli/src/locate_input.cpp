#include "odoloc/cli/locate_input.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>

#include "odoloc/cli/errors.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/yaml/reader.hpp"

namespace odoloc::cli {
namespace {

using sw::locate::RangeCandidate;

[[noreturn]] void fail_at(std::string_view name, std::size_t line, std::string_view what) {
  throw UsageError(fmt::format("{}:{}: {}", name, line, what));
}

bool is_nan_text(std::string_view text) {
  return text.size() == 3 && std::tolower(static_cast<unsigned char>(text[0])) == 'n' &&
         std::tolower(static_cast<unsigned char>(text[1])) == 'a' &&
         std::tolower(static_cast<unsigned char>(text[2])) == 'n';
}

// Ids appear in CSV fields, the table and the plot's labels: no separators,
// quotes or spaces to escape anywhere.
bool is_id(std::string_view id) {
  return !id.empty() && std::ranges::all_of(id, [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.';
  });
}

std::string known_ids(const LocateLayout& layout) {
  return fmt::format("{}", fmt::join(layout.ids, ", "));
}

// ------------------------------------------------------------------ layout

constexpr std::size_t kMinBeacons = 3;   // no solver fixes with fewer
constexpr std::size_t kMaxBeacons = 64;  // BeaconLayout::validate
constexpr double kSamePlaceM = 1e-3;     // BeaconLayout::validate

LocateLayout parse_layout_checked(std::string_view text, std::string_view name) {
  const yaml::Reader r(name);
  const YAML::Node root = r.load(std::string{text});
  if (!root.IsMap())
    r.fail(root,
           "a layout is a YAML mapping with 'beacons' (and optionally 'speed_of_sound', "
           "'temperature')");
  r.check_keys(root, "layout", {"beacons", "speed_of_sound", "temperature"});
  LocateLayout out;
  if (const YAML::Node c = root["speed_of_sound"]) {
    out.speed_of_sound_mps = r.number(c, "layout: speed_of_sound");
    if (!(out.speed_of_sound_mps >= 100 && out.speed_of_sound_mps <= 2000))
      r.fail(c, "layout: speed_of_sound must be within 100..2000 m/s (air: 331.3 + 0.6 T)");
  }
  if (const YAML::Node t = root["temperature"]) {
    out.temperature_c = r.number(t, "layout: temperature");
    if (!(*out.temperature_c >= sw::locate::kMinTemperatureC &&
          *out.temperature_c <= sw::locate::kMaxTemperatureC))
      r.fail(t, fmt::format("layout: temperature must be within {}..{} degrees Celsius",
                            sw::locate::kMinTemperatureC, sw::locate::kMaxTemperatureC));
  }
  const YAML::Node beacons = root["beacons"];
  if (!beacons)
    r.fail(root, "layout: missing 'beacons'");
  if (!beacons.IsSequence())
    r.fail(beacons, "layout: beacons must be a list");
  if (beacons.size() < kMinBeacons || beacons.size() > kMaxBeacons)
    r.fail(beacons, fmt::format("layout: {} beacons; a layout has {} to {}", beacons.size(),
                                kMinBeacons, kMaxBeacons));
  std::vector<std::size_t> lines;
  for (std::size_t i = 0; i < beacons.size(); ++i) {
    const YAML::Node b = beacons[i];
    r.check_keys(b, fmt::format("beacons[{}]", i), {"id", "x", "y", "height"});
    std::string id = std::to_string(i);
    if (const YAML::Node n = b["id"]) {
      id = n.IsScalar() ? n.Scalar() : std::string{};
      if (!is_id(id))
        r.fail(n, fmt::format("beacons[{}]: id '{}': ids are letters, digits, '_', '-' and '.'", i,
                              output::printable_excerpt(id)));
    }
    const std::string where = fmt::format("beacon '{}'", id);
    if (const auto first = std::ranges::find(out.ids, id); first != out.ids.end())
      r.fail(b, fmt::format("{} given twice (first on line {})", where,
                            lines[static_cast<std::size_t>(first - out.ids.begin())]));
    const auto coordinate = [&](const char* key) {
      return r.number(r.required(b, key, where), fmt::format("{}: {}", where, key));
    };
    sw::locate::Beacon beacon{{coordinate("x"), coordinate("y")}};
    if (const YAML::Node h = b["height"])
      beacon.height_m = r.number(h, fmt::format("{}: height", where));
    for (std::size_t j = 0; j < i; ++j) {
      const sw::locate::Vec2 q = out.layout.beacons[j].position_m;
      if (std::hypot(beacon.position_m.x - q.x, beacon.position_m.y - q.y) < kSamePlaceM)
        r.fail(b, fmt::format("{} is at the place of beacon '{}' (line {}): closer than 1 mm",
                              where, out.ids[j], lines[j]));
    }
    out.layout.beacons.push_back(beacon);
    out.ids.push_back(std::move(id));
    lines.push_back(static_cast<std::size_t>(b.Mark().line) + 1);
  }
  return out;
}

// ---------------------------------------------------------------- arrivals

enum class Column : std::uint8_t { kCycle, kBeacon, kDistance, kTime, kSdM, kSdS, kCandidate };
constexpr std::size_t kColumnCount = 7;
constexpr std::array<std::string_view, kColumnCount> kColumnNames = {
    "cycle", "beacon", "distance_m", "time_s", "sd_m", "sd_s", "candidate"};

constexpr std::string_view kHeaderHelp =
    "the first line names the columns: cycle, beacon, distance_m or time_s, optionally sd_m (with "
    "distance_m) or sd_s (with time_s) and candidate";

// Where each column is in a row; -1 when absent.
using ColumnIndex = std::array<int, kColumnCount>;

int at(const ColumnIndex& index, Column c) {
  return index[static_cast<std::size_t>(c)];
}

ColumnIndex parse_header(const std::vector<std::string_view>& fields, std::string_view name,
                         std::size_t line) {
  ColumnIndex index;
  index.fill(-1);
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const auto known = std::ranges::find(kColumnNames, fields[i]);
    if (known == kColumnNames.end())
      fail_at(name, line,
              fmt::format("unknown column '{}' ({})", output::printable_excerpt(fields[i]),
                          kHeaderHelp));
    int& slot = index[static_cast<std::size_t>(known - kColumnNames.begin())];
    if (slot >= 0)
      fail_at(name, line, fmt::format("column '{}' named twice", fields[i]));
    slot = static_cast<int>(i);
  }
  const auto has = [&](Column c) { return at(index, c) >= 0; };
  if (!has(Column::kCycle) || !has(Column::kBeacon) || has(Column::kDistance) == has(Column::kTime))
    fail_at(name, line,
            has(Column::kDistance) && has(Column::kTime)
                ? std::string{"give distance_m or time_s, not both"}
                : fmt::format("missing columns ({})", kHeaderHelp));
  if (has(Column::kSdM) && !has(Column::kDistance))
    fail_at(name, line, "sd_m goes with distance_m; with time_s the deviation is sd_s");
  if (has(Column::kSdS) && !has(Column::kTime))
    fail_at(name, line, "sd_s goes with time_s; with distance_m the deviation is sd_m");
  return index;
}

struct Candidate {
  std::uint64_t index = 0;  // in order of arrival
  RangeCandidate range;
  std::size_t line = 0;
};

// Candidates per beacon of one cycle.
using CycleRows = std::vector<std::vector<Candidate>>;

std::uint64_t whole_number(std::string_view text, std::string_view column, std::string_view name,
                           std::size_t line) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size())
    fail_at(name, line,
            fmt::format("{} '{}' is not a whole number from 0 to 2^64 - 1", column,
                        output::printable_excerpt(text)));
  return value;
}

// Indices 0, 1, ... without gaps, and in order of arrival: a later
// candidate is never a shorter distance (NaN ones aside).
std::vector<RangeCandidate> candidates_of(std::vector<Candidate>& rows, std::uint64_t cycle,
                                          std::string_view id, std::string_view name) {
  std::ranges::sort(rows, {}, &Candidate::index);
  std::vector<RangeCandidate> out;
  const Candidate* previous = nullptr;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Candidate& c = rows[k];
    const std::string what =
        fmt::format("candidate {} of beacon '{}' in cycle {}", c.index, id, cycle);
    if (c.index != k)
      fail_at(name, c.line, fmt::format("{} without a candidate {}", what, k));
    if (std::isfinite(c.range.distance_m)) {
      if (previous != nullptr && c.range.distance_m < previous->range.distance_m)
        fail_at(name, c.line,
                fmt::format("{} ({} m) arrives before candidate {} ({} m, line {}): candidates "
                            "are in order of arrival",
                            what, c.range.distance_m, previous->index, previous->range.distance_m,
                            previous->line));
      if (previous != nullptr && c.range.distance_m == previous->range.distance_m)
        fail_at(name, c.line,
                fmt::format("{} ({} m) arrives with candidate {} (line {}): one wavefront given "
                            "twice?",
                            what, c.range.distance_m, previous->index, previous->line));
      previous = &c;
    }
    out.push_back(c.range);
  }
  return out;
}

}  // namespace

std::vector<ArrivalCycle> parse_arrivals(std::string_view csv, std::string_view name,
                                         const LocateLayout& layout) {
  if (csv.starts_with("\xEF\xBB\xBF"))  // a UTF-8 byte-order mark, as spreadsheets write
    csv.remove_prefix(3);
  std::optional<ColumnIndex> index;
  std::size_t columns = 0;
  std::map<std::uint64_t, CycleRows> cycles;
  const std::vector<std::string_view> lines = yaml::split_fields(csv, '\n');
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::size_t line = i + 1;
    const std::string_view text = lines[i];
    if (text.empty() || text.starts_with('#'))
      continue;
    const std::vector<std::string_view> fields = yaml::split_fields(text);
    if (!index) {
      index = parse_header(fields, name, line);
      columns = fields.size();
      continue;
    }
    if (fields.size() != columns)
      fail_at(name, line, fmt::format("{} fields; the header names {}", fields.size(), columns));
    const auto field = [&](Column c) {
      const int at_column = at(*index, c);
      return at_column < 0 ? std::string_view{} : fields[static_cast<std::size_t>(at_column)];
    };
    const bool times = at(*index, Column::kTime) >= 0;
    const std::uint64_t cycle = whole_number(field(Column::kCycle), "cycle", name, line);
    const std::string_view id = field(Column::kBeacon);
    const std::optional<int> beacon = layout.find(id);
    if (!beacon)
      fail_at(name, line,
              fmt::format("unknown beacon '{}' (the layout's: {})", output::printable_excerpt(id),
                          known_ids(layout)));
    // The measurement: empty or nan is one that failed, and stays NaN.
    const std::string_view column = times ? "time_s" : "distance_m";
    const std::string_view value = field(times ? Column::kTime : Column::kDistance);
    RangeCandidate range;
    range.sd_m = kDefaultSdM;
    if (!value.empty() && !is_nan_text(value)) {
      const std::optional<double> v = yaml::finite_number(value);
      if (!v)
        fail_at(name, line,
                fmt::format("{} '{}' is not a number (empty or nan: no measurement)", column,
                            output::printable_excerpt(value)));
      range.distance_m = times ? *v * layout.speed_of_sound_mps : *v;
      if (!std::isfinite(range.distance_m))
        fail_at(name, line,
                fmt::format("{} '{}' is out of range (its distance overflows)", column,
                            output::printable_excerpt(value)));
    }
    const std::string_view sd_column = times ? "sd_s" : "sd_m";
    if (const std::string_view sd = field(times ? Column::kSdS : Column::kSdM);
        !sd.empty() && !is_nan_text(sd)) {
      const std::optional<double> v = yaml::finite_number(sd);
      if (!v || *v < 0)
        fail_at(name, line,
                fmt::format("{} '{}' is not a deviation: a finite number >= 0 (empty or nan: "
                            "the default, {} m)",
                            sd_column, output::printable_excerpt(sd), kDefaultSdM));
      range.sd_m = times ? *v * layout.speed_of_sound_mps : *v;
      if (!std::isfinite(range.sd_m))
        fail_at(name, line,
                fmt::format("{} '{}' is out of range (it overflows in metres)", sd_column,
                            output::printable_excerpt(sd)));
    }
    CycleRows& rows = cycles[cycle];
    rows.resize(layout.ids.size());
    std::vector<Candidate>& slot = rows[static_cast<std::size_t>(*beacon)];
    Candidate c{slot.size(), range, line};
    if (at(*index, Column::kCandidate) >= 0) {
      c.index = whole_number(field(Column::kCandidate), "candidate", name, line);
      if (const auto twin = std::ranges::find(slot, c.index, &Candidate::index); twin != slot.end())
        fail_at(name, line,
                fmt::format("candidate {} of beacon '{}' in cycle {} given twice (first on line "
                            "{})",
                            c.index, id, cycle, twin->line));
    }
    slot.push_back(c);
  }
  if (!index)
    throw UsageError(fmt::format("{}: no header ({})", name, kHeaderHelp));
  if (cycles.empty())
    throw UsageError(fmt::format("{}: no arrivals after the header", name));

  std::vector<ArrivalCycle> out;
  for (auto& [cycle, rows] : cycles) {
    ArrivalCycle ac{cycle, {}};
    ac.ranges.speed_of_sound_mps = layout.speed_of_sound_mps;
    for (std::size_t b = 0; b < rows.size(); ++b) {
      sw::locate::BeaconRange range;
      range.candidates = candidates_of(rows[b], cycle, layout.ids[b], name);
      range.primary = range.candidates.empty() ? -1 : 0;
      ac.ranges.beacons.push_back(std::move(range));
    }
    out.push_back(std::move(ac));
  }
  return out;
}

namespace {

std::string read_text(const std::string& path, std::string_view what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw UsageError(fmt::format("cannot read {} {}: it is a directory", what, path));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw UsageError(fmt::format("cannot open {} {}: {}", what, path, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad())
    throw UsageError(fmt::format("cannot read {} {}: {}", what, path, std::strerror(errno)));
  return std::move(text).str();
}

}  // namespace

std::optional<int> LocateLayout::find(std::string_view id) const {
  const auto it = std::ranges::find(ids, id);
  if (it == ids.end())
    return std::nullopt;
  return static_cast<int>(it - ids.begin());
}

LocateLayout parse_layout(std::string_view yaml, std::string_view name) {
  try {
    return parse_layout_checked(yaml, name);
  } catch (const yaml::InputError& e) {
    throw UsageError(e.what());
  }
}

LocateLayout load_layout(const std::string& path) {
  return parse_layout(read_text(path, "layout"), path);
}

std::vector<ArrivalCycle> load_arrivals(const std::string& path, const LocateLayout& layout) {
  return parse_arrivals(read_text(path, "arrivals"), path, layout);
}

}  // namespace odoloc::cli
