// The encoder half of the odometry fabric: four EPPMs on one 50 MHz clock.
#pragma once

#include <array>
#include <cstddef>
#include <utility>

#include "odoloc/rtl/eppm.hpp"

namespace odoloc::rtl {

// The EPPM instances, in register-map order (regs::eppm::kInstanceNames).
enum class Encoder : std::uint8_t { kLeftRear = 0, kRightRear = 1, kFrontDrive = 2, kSteering = 3 };
inline constexpr std::size_t kEncoderCount = regs::eppm::kInstances;
static_assert(kEncoderCount == 4 && regs::eppm::kInstanceNames[3] == "steering");

class EncoderFabric {
 public:
  using In = std::array<EppmInputs, kEncoderCount>;
  using Config = std::array<EppmConfig, kEncoderCount>;

  // The EPPMs share no signal: each one's wires are its own inputs.
  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  [[gnu::flatten]] void step(const In& in, const Config& cfg, const Order& order = {}) {
    [&]<std::size_t... W>(std::index_sequence<W...>) {
      order([&] { eppm_[W].template step<G>(in[W], cfg[W], order); }...);
    }
    (std::make_index_sequence<kEncoderCount>{});
  }
  // n clocks with `in` held (clocked.hpp): the EPPMs share no signal, so
  // each one steps through its own events and skips between them.
  void advance(std::uint64_t n, const In& in, const Config& cfg) {
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      eppm_[w].advance(n, in[w], cfg[w]);
  }
  [[nodiscard]] bool idle(const In& in, const Config& cfg) const {
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      if (!eppm_[w].idle(in[w], cfg[w]))
        return false;
    return true;
  }
  void reset_now() {
    for (auto& e : eppm_)
      e.reset_now();
  }

  [[nodiscard]] const Eppm& eppm(Encoder w) const { return eppm_[static_cast<std::size_t>(w)]; }

  template <class V>
  void trace(V& v) const {
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      trace_scope(v, regs::eppm::kInstanceNames[w], eppm_[w]);
  }

 private:
  std::array<Eppm, kEncoderCount> eppm_;
};

}  // namespace odoloc::rtl
