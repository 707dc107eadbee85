// The encoder half of the odometry fabric: four EPPMs on one 50 MHz clock.
#pragma once

#include <array>
#include <cstddef>

#include "odoloc/rtl/eppm.hpp"

namespace odoloc::rtl {

enum class Wheel : std::uint8_t { kLeftRear = 0, kRightRear = 1, kFrontDrive = 2, kSteering = 3 };
inline constexpr std::size_t kWheelCount = 4;
inline constexpr std::array<const char*, kWheelCount> kWheelNames = {"left_rear", "right_rear",
                                                                     "front_drive", "steering"};

class EncoderFabric {
 public:
  using Inputs = std::array<EppmInputs, kWheelCount>;
  using Configs = std::array<EppmConfig, kWheelCount>;

  // The EPPMs share no signal, so clocking them one after another is one edge.
  template <Gating G = Gating::kOn>
  [[gnu::flatten]] void step(const Inputs& in, const Configs& cfg) {
    for (std::size_t w = 0; w < kWheelCount; ++w)
      eppm_[w].step<G>(in[w], cfg[w]);
  }
  void reset_now() {
    for (auto& e : eppm_)
      e.reset_now();
  }

  [[nodiscard]] const Eppm& eppm(Wheel w) const { return eppm_[static_cast<std::size_t>(w)]; }

  template <class V>
  void trace(V& v) const {
    for (std::size_t w = 0; w < kWheelCount; ++w)
      trace_scope(v, kWheelNames[w], eppm_[w]);
  }

 private:
  std::array<Eppm, kWheelCount> eppm_;
};

}  // namespace odoloc::rtl
