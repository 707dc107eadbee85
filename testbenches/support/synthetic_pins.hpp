// Synthetic sensor pins for the scaling benchmarks (odoloc_bench) and the
// moving-encoder instruction count (bench/counts/fast_forward_moving.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
#include "odoloc/world/quadrature_source.hpp"

namespace odoloc::tb {

// Synthetic sensor pins for the scaling benchmarks: `encoders` encoders at
// `edges_per_second` each (the rest still), and `channels` comparators each
// pulsing 100 us high every 1 ms (the capture unit armed on all eight; its
// FIFOs fill, then count overflows: the same work per pulse). Knows when its
// pins next change, so the link fast-forwards between them.
class SyntheticPins final : public board::SensorStimulus {
 public:
  static constexpr std::uint64_t kPulsePeriod = 50'000;  // 1 ms
  static constexpr std::uint64_t kPulseWidth = 5'000;    // 100 us
  SyntheticPins(std::size_t encoders, double edges_per_second, std::size_t channels)
      : channels_(channels) {
    for (std::size_t w = 0; w < encoders; ++w)
      sources_[w].set_rate(edges_per_second / rtl::kFabricClockHz);
  }
  void tick(rtl::ChipPins& pins) override {
    for (std::size_t w = 0; w < rtl::kEncoderCount; ++w)
      pins.encoders[w] = board::encoder_pins(sources_[w].tick());
    const bool high = clock_ % kPulsePeriod < kPulseWidth;
    pins.comparators = decltype(pins.comparators)::truncate(high ? (1U << channels_) - 1 : 0U);
    ++clock_;
  }
  [[nodiscard]] std::uint64_t hold() const override {
    std::uint64_t hold = kForever;
    for (const world::QuadratureSource& s : sources_)
      hold = std::min(hold, s.ticks_to_next_edge() - 1);
    if (channels_ != 0) {
      const std::uint64_t phase = clock_ % kPulsePeriod;
      hold = std::min(hold, (phase < kPulseWidth ? kPulseWidth : kPulsePeriod) - phase);
    }
    return hold;
  }
  void skip(std::uint64_t clocks) override {
    for (world::QuadratureSource& s : sources_)
      s.skip(clocks);
    clock_ += clocks;
  }

 private:
  std::array<world::QuadratureSource, rtl::kEncoderCount> sources_{};
  std::size_t channels_;
  std::uint64_t clock_ = 0;
};

}  // namespace odoloc::tb
