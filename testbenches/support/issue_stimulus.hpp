// Issue 13's encoder stimulus, the one Verilator was measured under, for the
// per-clock benchmarks (odoloc_bench) and its own check (test_eppm_random).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
#include "odoloc/world/quadrature_source.hpp"

namespace odoloc::tb {

// Quadrature at 50 k, 20 k, 125 k and 4 k edges/s; the steering encoder
// reverses every 1.3 ms. The pins of each clock are those of
// world::QuadratureSource::tick() at rate(w, clock), but each source knows
// its next edge: a clock without one costs a counter per encoder, as in a
// testbench that schedules edge events, so the benchmarks time the model
// rather than four phase accumulators.
class IssueStimulus {
 public:
  using Pins = std::array<rtl::UInt<2>, rtl::kEncoderCount>;
  static constexpr std::array<double, rtl::kEncoderCount> kEdgesPerSecond = {50e3, 20e3, 125e3,
                                                                             4e3};
  static constexpr std::uint64_t kSteeringReversalClocks = 1U << 16;  // 1.3 ms

  // x4 edges per clock of encoder w in clock `clock` (counted from 0).
  static constexpr double rate(std::size_t w, std::uint64_t clock) {
    const double forward = kEdgesPerSecond[w] / rtl::kFabricClockHz;
    const bool reversed = w == 3 && (clock / kSteeringReversalClocks) % 2 == 1;
    return reversed ? -forward : forward;
  }

  IssueStimulus() {
    for (std::size_t w = 0; w < rtl::kEncoderCount; ++w) {
      sources_[w].set_rate(rate(w, 0));
      to_edge_[w] = sources_[w].ticks_to_next_edge();
    }
  }
  // Advances one clock; says whether any pin changed in it.
  bool tick() {
    bool changed = false;
    for (std::size_t w = 0; w < rtl::kEncoderCount; ++w) {
      if (++pending_[w] == to_edge_[w]) {
        catch_up(w);
        changed = true;
      }
    }
    ++clock_;
    if (clock_ % kSteeringReversalClocks == 0) {
      catch_up(3);
      sources_[3].set_rate(rate(3, clock_));
      to_edge_[3] = sources_[3].ticks_to_next_edge();
    }
    return changed;
  }
  // The A/B pins (A in bit 1) after the last tick().
  [[nodiscard]] const Pins& pins() const { return pins_; }
  [[nodiscard]] std::uint64_t clocks() const { return clock_; }

 private:
  void catch_up(std::size_t w) {
    sources_[w].skip(pending_[w]);
    pending_[w] = 0;
    pins_[w] = board::encoder_pins(sources_[w].level());
    to_edge_[w] = sources_[w].ticks_to_next_edge();
  }

  std::array<world::QuadratureSource, rtl::kEncoderCount> sources_{};
  std::array<std::uint64_t, rtl::kEncoderCount> pending_{};  // ticks not yet applied to sources_
  std::array<std::uint64_t, rtl::kEncoderCount> to_edge_{};  // ticks from the last catch-up
  Pins pins_{};
  std::uint64_t clock_ = 0;
};

}  // namespace odoloc::tb
