// Runs the localisation system to the end of its tour (docs/simulator.md):
// every frame to every sink; on live LCM connections the simulator status
// once per wall-clock second and the register bridge between steps; as fast
// as the machine can, or paced to real time, saying when it cannot keep up.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <vector>

#include "odoloc/bridge/register_bridge.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/sim/sinks.hpp"
#include "odoloc/sim/system.hpp"

namespace odoloc::sim {

struct RunnerOptions {
  bool realtime = false;     // pace simulated time to the wall clock
  bool allow_write = false;  // the register bridge carries out writes
  std::chrono::milliseconds status_period{1000};
  // Paced, a step this late (wall clock behind simulated time) is not
  // keeping up: said once on the warnings stream, and in the status.
  std::chrono::milliseconds lag_tolerance{100};
};

struct RunSummary {
  double simulated_s = 0;
  double wall_s = 0;
  std::uint64_t clocks = 0, skipped_clocks = 0;
  bool kept_up = true;  // paced: never later than lag_tolerance
  double worst_lag_s = 0;
  std::uint64_t malformed = 0;  // LCM messages received that did not decode
  bridge::RegisterBridge::Counters bridge;
};

class Runner {
 public:
  Runner(LocalisationSystem& system, const RunnerOptions& options);
  // Each frame goes to `sink` (which must outlive the runner).
  void add_sink(FrameSink& sink);
  // A connection that is published on and listened to (udpm, memq): the
  // status goes there, and the register bridge answers on it. Log files
  // (file://) take an LcmSink only. Must outlive the runner.
  void add_live(lcm::Connection& connection);
  // To the end of the tour, or until `stop` is set (then the sinks still
  // finish). `warnings`: the line saying the machine cannot keep up.
  RunSummary run(const std::atomic<bool>* stop, std::ostream& warnings);

 private:
  void publish_status(double real_time_factor, bool keeping_up);
  LocalisationSystem& system_;
  RunnerOptions options_;
  std::vector<FrameSink*> sinks_;
  std::vector<lcm::Connection*> live_;
  std::vector<std::unique_ptr<bridge::RegisterBridge>> bridges_;
};

}  // namespace odoloc::sim
