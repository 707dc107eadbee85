// The simulated board: the whole fabric chip (rtl::OdolocChip) behind a
// pin-level SPI master, optionally with the ground-truth robot driving its
// encoder pins so counts move. The host tool's `--target sim`.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::board {

struct SimTargetOptions {
  std::string scenario = "none";  // one of SimTarget::scenarios()
  unsigned sclk_half_period = 4;  // fabric clocks per SCLK level (>= 4: 6.25 MHz)
  std::string vcd_path;           // non-empty: the chip's waveform of every frame (VCD)
  std::string vcd_pins_path;      // non-empty: only the four SPI pins during every frame (VCD)
  bool cycle_step = false;        // step every clock instead of fast-forwarding (same results)
};

class SimTarget {
 public:
  // Throws std::invalid_argument for an unknown scenario or a bad option.
  explicit SimTarget(const SimTargetOptions& options);
  SimTarget(const SimTarget&) = delete;
  SimTarget& operator=(const SimTarget&) = delete;
  ~SimTarget();

  // Frames clock the fabric (and the scenario) while they shift.
  [[nodiscard]] sw::SpiLink& link();
  // Runs the fabric for `simulated` time with cs_n high.
  void advance(std::chrono::nanoseconds simulated);
  [[nodiscard]] std::uint64_t clocks() const;
  // Clocks fast-forwarded rather than stepped (0 with cycle_step).
  [[nodiscard]] std::uint64_t skipped_clocks() const;
  // Simulated time since construction.
  [[nodiscard]] std::chrono::nanoseconds elapsed() const;

  // Flushes and closes the waveform files; std::runtime_error naming the
  // file when anything written to one was lost (disk full, I/O error).
  // Idempotent; the destructor closes without checking.
  void finish();

  // "none", then the scenario names.
  static std::vector<std::string> scenarios();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace odoloc::board
