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

// Encoder pins held for a number of clocks: A/B (A in bit 1), clocks >= 1.
struct PinRun {
  UInt<2> pins;
  std::uint64_t clocks = 1;
};

// The runs of encoder pins that hold for a whole skip: runs(w, max) is
// encoder w's pins for max clocks.
inline auto held_runs(const std::array<UInt<2>, kEncoderCount>& pins) {
  return [&pins](std::size_t w, std::uint64_t max) { return PinRun{pins[w], max}; };
}

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
  // n clocks in which each encoder's pins follow their own waveform and the
  // other inputs hold: runs(w, max) returns encoder w's next PinRun, at
  // most max clocks long. Each EPPM walks its own runs alone, a pin change
  // costing that EPPM's events only. Returns the pins of the last clock.
  template <class Runs>
  std::array<UInt<2>, kEncoderCount> advance(std::uint64_t n, In in, const Config& cfg,
                                             Runs&& runs) {
    std::array<UInt<2>, kEncoderCount> last{};
    for (std::size_t w = 0; w < kEncoderCount; ++w) {
      for (std::uint64_t left = n; left != 0;) {
        const PinRun run = runs(w, left);
        in[w].a = run.pins.bit<1>();
        in[w].b = run.pins.bit<0>();
        eppm_[w].advance(run.clocks, in[w], cfg[w]);
        left -= run.clocks;
        last[w] = run.pins;
      }
    }
    return last;
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
