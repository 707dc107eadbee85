#include "odoloc/sim/runner.hpp"

#include <algorithm>
#include <ostream>
#include <thread>

#include "odoloc/lcm/channels.hpp"
#include "odoloc_lcm/sim_status_t.hpp"

namespace odoloc::sim {

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

Runner::Runner(LocalisationSystem& system, const RunnerOptions& options)
    : system_(system), options_(options) {}

void Runner::add_sink(FrameSink& sink) {
  sinks_.push_back(&sink);
}

void Runner::add_live(lcm::Connection& connection) {
  live_.push_back(&connection);
  bridges_.push_back(
      std::make_unique<bridge::RegisterBridge>(connection, system_.bus(), options_.allow_write));
}

void Runner::publish_status(double real_time_factor, bool keeping_up) {
  odoloc_lcm::sim_status_t status{};
  status.utime = std::llround(system_.time_s() * 1e6);
  status.fabric_clocks = static_cast<std::int64_t>(system_.clocks());
  status.real_time_factor = real_time_factor;
  status.keeping_up = keeping_up;
  status.write_allowed = options_.allow_write;
  status.pacing = options_.realtime ? "realtime" : "fast";
  for (lcm::Connection* c : live_) {
    status.malformed_messages = static_cast<std::int64_t>(c->malformed());
    c->publish(lcm::channel::kSimStatus, status);
  }
}

RunSummary Runner::run(const std::atomic<bool>* stop, std::ostream& warnings) {
  RunSummary summary;
  // The sinks compare with the reference runs from the first frame on:
  // waiting for them here keeps a paced run from starting late.
  (void)system_.reference(rtl::MinSelectPolicy::kRearOnly);
  (void)system_.reference(rtl::MinSelectPolicy::kFrontOnly);
  const Clock::time_point start = Clock::now();
  const double sim_start = system_.time_s();
  Clock::time_point last_status = start;
  double sim_at_last_status = sim_start;
  bool keeping_up = true;
  bool warned = false;
  const auto ended = [&] { return system_.done() || (stop != nullptr && stop->load()); };
  while (!ended()) {
    const Frame frame = system_.step();
    for (FrameSink* sink : sinks_)
      sink->frame(frame, system_);
    for (lcm::Connection* c : live_)
      while (c->handle(std::chrono::milliseconds{0})) {
      }
    const double simulated = frame.time_s - sim_start;
    if (options_.realtime) {
      const auto due = start + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(simulated));
      const double lag = seconds(Clock::now() - due);
      summary.worst_lag_s = std::max(summary.worst_lag_s, lag);
      keeping_up = lag <= std::chrono::duration<double>(options_.lag_tolerance).count();
      if (!keeping_up && !warned) {
        warnings << "odoloc sim: this machine cannot keep up with real time (" << lag
                 << " s behind at " << frame.time_s << " s simulated); running on, late\n";
        warned = true;
      }
      summary.kept_up = summary.kept_up && keeping_up;
      std::this_thread::sleep_until(due);
    }
    const Clock::time_point now = Clock::now();
    if (now - last_status >= options_.status_period) {
      publish_status((frame.time_s - sim_at_last_status) / seconds(now - last_status), keeping_up);
      last_status = now;
      sim_at_last_status = frame.time_s;
    }
  }
  for (FrameSink* sink : sinks_)
    sink->finish(system_);
  summary.simulated_s = system_.time_s() - sim_start;
  summary.wall_s = seconds(Clock::now() - start);
  summary.clocks = system_.clocks();
  summary.skipped_clocks = system_.skipped_clocks();
  for (lcm::Connection* c : live_)
    summary.malformed += c->malformed();
  for (const auto& b : bridges_) {
    const bridge::RegisterBridge::Counters k = b->counters();
    summary.bridge.served += k.served;
    summary.bridge.refused += k.refused;
    summary.bridge.errors += k.errors;
    summary.bridge.malformed += k.malformed;
  }
  return summary;
}

}  // namespace odoloc::sim
