// The whole localisation system in one process (`odoloc sim`, the main
// job): the world (world::RoomTour: the ground-truth tricycle, the acoustic
// world), the cycle-accurate chip at the pin level (board::ChipLink, with
// the world on its sensor pins and fast-forward between their changes), and
// the SoC software (sw::Localiser), which reaches the chip only through the
// register bus over the pin-level SPI master (CRC on), as on a board.
// docs/simulator.md.
//
// Two clocks: simulated time (fabric clocks / 50 MHz since the chip's
// reset, the truth's time) and the SoC's robot clock (the capture unit's
// timestamp from where its driver started); to_sim_time() converts.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "odoloc/board/scenario_runner.hpp"
#include "odoloc/sim/scenario_file.hpp"
#include "odoloc/sw/localiser.hpp"
#include "odoloc/sw/register_bus.hpp"
#include "odoloc/world/room_tour.hpp"

namespace odoloc::sim {

struct SystemOptions {
  std::uint64_t seed =
      1;                 // the acoustic world's random draws (the scenario's: the caller's choice)
  double step_s = 0.01;  // the SoC loop's period (simulated seconds)
  bool cycle_step = false;  // step every fabric clock (bit-identical, slower)
  // The encoder modules are read for LCM (ODOLOC_ENCODERS) this often; the
  // localisation does not need them (the fabric integrates the odometry).
  double encoder_period_s = 0.1;
  // > 0: the run ends at this simulated time, before the tour's end (the
  // world, the chip and the reference runs stop there too).
  double until_s = 0;
  // false: Kleeman's beacons only initialise the filter; then Liu's base
  // station alone corrects the odometry (sw::LocaliserConfig).
  bool fuse_beacon_ranges = true;
  // Set meanwhile (a signal): the reference runs end early, so that the
  // caller, which polls the same flag, is not kept waiting for them.
  const std::atomic<bool>* stop = nullptr;
};

// One encoder module as read (eppm.count, eppm.speed, eppm.status).
struct EncoderRead {
  std::int32_t count = 0;  // 20-bit, sign-extended
  std::int32_t speed = 0;  // 24-bit, sign-extended
  bool pulse_mode = false, valid = false, stalled = false, forward = false;
};

// One pass of the SoC loop and the truth at its read.
struct Frame {
  double time_s = 0;  // simulated time of the odometry read
  std::uint64_t clocks = 0;
  world::Pose truth;
  // The encoder modules in register-map order, read every encoder_period_s.
  std::optional<std::array<EncoderRead, 4>> encoders;
  sw::LocaliserStep soc;
};

class LocalisationSystem {
 public:
  // Runs the world's pre-pass (the tricycle's trajectory for the acoustic
  // world, then every arrival of every beacon burst), starts the rear-only
  // and front-only reference runs in the background, and brings the SoC
  // software up over the bus, configured from the scenario's survey (never
  // from its truth). Throws what the world and the SoC software throw for a
  // bad set-up.
  LocalisationSystem(Scenario scenario, const SystemOptions& options);
  LocalisationSystem(const LocalisationSystem&) = delete;
  LocalisationSystem& operator=(const LocalisationSystem&) = delete;
  ~LocalisationSystem();

  // The tour is over (its last wait included), or until_s is reached.
  [[nodiscard]] bool done() const;
  // Runs the chip to the next step time, then one pass of the SoC loop, and
  // reads the encoder modules.
  Frame step();

  // The register bus the SoC software uses: register accesses between
  // steps (the register bridge) go through the same pin-level SPI master.
  [[nodiscard]] sw::RegisterBus& bus();
  // The tour, its duration_s cut to until_s.
  [[nodiscard]] const world::RoomTour& tour() const { return tour_; }
  // The run ends before the tour's end (until_s): no return to the start.
  [[nodiscard]] bool cut_short() const { return cut_short_; }
  [[nodiscard]] const sw::Localiser& localiser() const;
  [[nodiscard]] std::uint64_t clocks() const;
  [[nodiscard]] std::uint64_t skipped_clocks() const;
  [[nodiscard]] double time_s() const;

  // The truth at a simulated time (the pre-pass's trajectory, interpolated
  // every 1 ms: within 0.1 mm of the tricycle's own).
  [[nodiscard]] world::Pose truth_at(double time_s) const;
  // A robot-clock time of the SoC (known after the first step) as simulated time.
  [[nodiscard]] double to_sim_time(double soc_time_s) const;
  // The reference odometry of one policy (rear-only or front-only) on the
  // same drive, every 10 ms of simulated time (board::run_scenario); waits
  // for its background run.
  [[nodiscard]] const board::RunResult& reference(rtl::MinSelectPolicy policy);

 private:
  class Chip;
  static std::array<EncoderRead, 4> read_encoders(sw::RegisterBus& bus);
  world::RoomTour tour_;
  Survey survey_;
  SystemOptions options_;
  world::Trajectory trajectory_;
  std::unique_ptr<Chip> chip_;
  std::uint64_t steps_ = 0;
  bool cut_short_ = false;
  double soc_offset_s_ = 0;  // simulated time minus robot-clock time
  std::future<board::RunResult> rear_future_, front_future_;
  std::unique_ptr<board::RunResult> rear_, front_;
};

}  // namespace odoloc::sim
