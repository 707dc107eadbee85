// `odoloc sim` (docs/simulator.md): the whole localisation system in one
// process, the project's main job. The world (the room tour), the chip at
// the pin level and the SoC software over the register bus; every stage
// published on LCM and/or written to a directory (LCM log, CSV, plot); the
// table of each source's errors at the end. No target: it simulates its own
// board.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

namespace odoloc::cli {

struct SimCommand {
  // A scenario file (docs/scenarios.md) or the name of a built-in one
  // (examples/scenarios/); empty: the main job's, room-tour.yaml.
  std::string scenario;
  std::optional<std::size_t> laps;    // the path's laps, for the scenario's
  std::optional<double> speed_mps;    // a square path's speed, for the scenario's
  std::optional<std::uint64_t> seed;  // for the scenario's
  // Given: stop after this much simulated time, (0, 10000] s (the table
  // then covers it); none: the whole tour.
  std::optional<double> duration_s;
  // Non-empty: write DIR/odoloc.lcmlog (an LCM event log), DIR/trajectories.csv,
  // DIR/fixes.csv and DIR/localisation.png (unless no_plot), all at the end
  // (nothing when the run fails or is interrupted).
  std::string out;
  // Publish live here (the register bridge listens there too). Empty: the
  // default URL when there is no --out, else nothing live.
  std::string lcm_url;
  bool realtime = false;     // paced to the wall clock
  bool allow_write = false;  // the register bridge carries out writes
  bool no_plot = false;
  bool cycle_step = false;        // the chip stepped every clock (bit-identical, slower)
  bool no_beacon_ranges = false;  // the beacons only initialise; the base station corrects
};

// Runs the tour; prints what it runs, then the table (with `json`, one JSON
// object: the table and the run's figures). UsageError for bad options or an
// LCM URL that cannot be opened; FileError when an output cannot be written
// or the plot fails; Interrupted when `stop` is set (no file is written).
void run_sim(const SimCommand& command, std::ostream& out, bool json,
             const std::atomic<bool>* stop);

}  // namespace odoloc::cli
