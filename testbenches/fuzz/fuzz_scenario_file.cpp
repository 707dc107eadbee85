// libFuzzer target: scenario files (`odoloc sim --scenario`, the files users
// write and copy; docs/scenarios.md). Seeded with examples/scenarios/.
//
// Invariants: parse_scenario returns or throws yaml::InputError (never
// another exception, a crash, a hang or a sanitizer finding), whose message
// is one line without control characters, starting with the file's name.
// An accepted scenario has 3 to 16 Kleeman beacons and one surveyed
// position for each, a station's transmitter after them, 1 to 8 receivers,
// every beacon inside the room, and a finite, non-negative duration.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_require.hpp"
#include "odoloc/sim/scenario_file.hpp"

namespace {

using odoloc::tb::require;

void check_accepted(const odoloc::sim::Scenario& s, const std::string& input) {
  const odoloc::world::RoomTour& t = s.tour;
  const std::size_t n = t.timing.beacon_count;
  // Kleeman's 3 to 16 beacons, or none with Liu's station or Thamma's stations.
  require((n >= 3 && n <= 16) || (n == 0 && (t.station || t.thamma)),
          "a beacon count outside 3..16 without another system", input);
  require(s.survey.beacons.size() == n, "a survey without one position per beacon", input);
  if (t.thamma) {
    require(n == 0 && !t.station, "Thamma's stations beside beacons or a station", input);
    require(t.acoustics.beacons.size() >= 2 && t.acoustics.beacons.size() <= 16 &&
                s.survey.thamma && s.survey.thamma->stations.size() == t.acoustics.beacons.size(),
            "Thamma's stations not 2..16 or not surveyed one by one", input);
  } else {
    require(t.acoustics.beacons.size() == n + (t.station ? 1 : 0), "beacons besides the station's",
            input);
  }
  require(n > 0 || t.thamma || s.survey.start, "no beacons and no start mark", input);
  require(!t.station || t.station->transmitter == n, "the station's transmitter misplaced", input);
  require(!t.acoustics.receivers.empty() && t.acoustics.receivers.size() <= 8,
          "a receiver count outside 1..8", input);
  require(std::isfinite(t.duration_s) && t.duration_s >= 0, "a duration not finite", input);
  if (t.acoustics.room) {
    for (const odoloc::world::Beacon& b : t.acoustics.beacons)
      require(b.position.x_m >= 0 && b.position.x_m <= t.acoustics.room->width_m &&
                  b.position.y_m >= 0 && b.position.y_m <= t.acoustics.room->depth_m,
              "a beacon outside the room", input);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  try {
    check_accepted(odoloc::sim::parse_scenario(input, "fuzz.yaml"), input);
  } catch (const odoloc::yaml::InputError& e) {
    const std::string message = e.what();
    require(message.starts_with("fuzz.yaml"), "a message without the file's name", message);
    for (const char c : message)
      require(static_cast<unsigned char>(c) >= 0x20 && c != 0x7F,
              "a control character in a message", message + "\n" + input);
  }
  return 0;
}
