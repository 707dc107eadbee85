// libFuzzer target: the files of `odoloc locate`, the files users write
// (docs/host-tool.md#beacon-fixes-locate). Every input is read as an
// arrivals CSV against a fixed six-beacon layout, and as a layout YAML.
// Seeded with examples/locate/.
//
// Invariants: each parser returns or throws UsageError (never another
// exception, a crash, a hang or a sanitizer finding), whose message is one
// line without control characters, starting with the file's name. An
// accepted layout has 3 to 64 beacons with one distinct id each and passes
// BeaconLayout::validate(). Accepted arrivals: cycles strictly ascending,
// one BeaconRange per beacon of the layout, primary 0 (-1 without
// candidates), every candidate's distance finite or NaN with a finite sd >= 0,
// the finite ones in order of arrival, and the layout's speed of sound.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_require.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/locate_input.hpp"

namespace {

namespace cli = odoloc::cli;

using odoloc::tb::require;

void check_message(const cli::UsageError& e, const std::string& name, const std::string& input) {
  const std::string message = e.what();
  require(message.starts_with(name + ":"), "a message without the file's name", message);
  for (const char c : message)
    require(static_cast<unsigned char>(c) >= 0x20 && c != 0x7F, "a control character in a message",
            message + "\n" + input);
}

const cli::LocateLayout& six_beacons() {
  static const cli::LocateLayout layout = cli::parse_layout(
      "beacons:\n"
      "  - {id: B0, x: 0.05, y: 0.05, height: 1.2}\n"
      "  - {id: B1, x: 2.5, y: 0.05, height: 1.2}\n"
      "  - {id: B2, x: 4.95, y: 0.05, height: 1.2}\n"
      "  - {id: B3, x: 4.95, y: 3.95, height: 1.2}\n"
      "  - {id: B4, x: 2.5, y: 3.95, height: 1.2}\n"
      "  - {x: 0.05, y: 3.95, height: 1.2}\n",  // id "5"
      "layout.yaml");
  return layout;
}

void arrivals(const std::string& input) {
  const cli::LocateLayout& layout = six_beacons();
  std::vector<cli::ArrivalCycle> cycles;
  try {
    cycles = cli::parse_arrivals(input, "arrivals.csv", layout);
  } catch (const cli::UsageError& e) {
    check_message(e, "arrivals.csv", input);
    return;
  }
  require(!cycles.empty(), "accepted arrivals without a cycle", input);
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    require(i == 0 || cycles[i - 1].cycle < cycles[i].cycle, "cycles out of order", input);
    const odoloc::sw::locate::RangeSet& ranges = cycles[i].ranges;
    require(ranges.speed_of_sound_mps == layout.speed_of_sound_mps, "another speed of sound",
            input);
    require(ranges.beacons.size() == layout.ids.size(), "not one range per beacon", input);
    for (const odoloc::sw::locate::BeaconRange& b : ranges.beacons) {
      require(b.primary == (b.candidates.empty() ? -1 : 0), "a primary other than the first",
              input);
      double last = -INFINITY;
      for (const odoloc::sw::locate::RangeCandidate& c : b.candidates) {
        require(std::isfinite(c.sd_m) && c.sd_m >= 0, "a deviation not finite or negative", input);
        require(!std::isinf(c.distance_m), "an infinite distance", input);
        if (std::isnan(c.distance_m))
          continue;
        require(c.distance_m >= last, "candidates not in order of arrival", input);
        last = c.distance_m;
      }
    }
  }
}

void layout(const std::string& input) {
  cli::LocateLayout parsed;
  try {
    parsed = cli::parse_layout(input, "layout.yaml");
  } catch (const cli::UsageError& e) {
    check_message(e, "layout.yaml", input);
    return;
  }
  const std::size_t n = parsed.layout.beacons.size();
  require(n >= 3 && n <= 64 && parsed.ids.size() == n, "a layout of the wrong size", input);
  for (std::size_t i = 0; i < n; ++i) {
    require(parsed.find(parsed.ids[i]) == static_cast<int>(i), "ids not distinct", input);
  }
  require(std::isfinite(parsed.speed_of_sound_mps) && parsed.speed_of_sound_mps > 0,
          "a bad speed of sound", input);
  try {
    parsed.layout.validate();
  } catch (const std::invalid_argument& e) {
    require(false, e.what(), input);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  arrivals(input);
  layout(input);
  return 0;
}
