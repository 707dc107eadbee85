// The files of `odoloc locate` (docs/host-tool.md#beacon-fixes-locate): a
// beacon layout in YAML and the recorded arrivals in CSV, read into the
// solvers' types (odoloc/sw/beacon_fix.hpp). Every mistake is a UsageError of one line
// naming the file and the line: "layout.yaml:7: beacon 'B2': missing 'y'".
// A missing or failed measurement is data, not a mistake: it reaches the
// solvers, which report it per beacon.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/sw/beacon_fix.hpp"

namespace odoloc::cli {

// The capture chain's speed of sound (20 C dry air), for files that give none.
inline constexpr double kDefaultSpeedOfSoundMps = 343.2;
// A distance without a deviation: about 3 us of timing noise.
inline constexpr double kDefaultSdM = 1e-3;

struct LocateLayout {
  sw::locate::BeaconLayout layout;
  std::vector<std::string> ids;  // one per beacon, in layout order
  // The speed of sound the arrivals' distances were computed with (and
  // their times are converted with).
  double speed_of_sound_mps = kDefaultSpeedOfSoundMps;
  std::optional<double> temperature_c;  // the air's, when known

  // The beacon number of `id`; nullopt when the layout has no such beacon.
  [[nodiscard]] std::optional<int> find(std::string_view id) const;
};

// One cycle's range set: one BeaconRange per beacon of the layout, its
// candidates in order of arrival, primary 0 (-1 without candidates).
struct ArrivalCycle {
  std::uint64_t cycle = 0;
  sw::locate::RangeSet ranges;
};

// `name` prefixes the messages (the file's path).
[[nodiscard]] LocateLayout parse_layout(std::string_view yaml, std::string_view name);
// Cycles in ascending order. Times are converted with the layout's speed of
// sound; the range sets carry it.
[[nodiscard]] std::vector<ArrivalCycle> parse_arrivals(std::string_view csv, std::string_view name,
                                                       const LocateLayout& layout);

// The same on a file; UsageError when it cannot be read.
[[nodiscard]] LocateLayout load_layout(const std::string& path);
[[nodiscard]] std::vector<ArrivalCycle> load_arrivals(const std::string& path,
                                                      const LocateLayout& layout);

}  // namespace odoloc::cli
