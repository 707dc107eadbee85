// A single EPPM with its configuration and pin levels, stepped clock by clock:
// the common harness of the EPPM testbenches.
#pragma once

#include <cstdint>

#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/rtl/eppm.hpp"
#include "odoloc/world/quadrature_source.hpp"

namespace odoloc::tb {

struct EppmBench {
  rtl::Eppm dut;
  rtl::EppmConfig cfg;
  rtl::EppmInputs in;
  std::uint64_t steps = 0;

  void set_pins(unsigned ab) {
    in.a = rtl::UInt<1>::truncate(ab >> 1);
    in.b = rtl::UInt<1>::truncate(ab);
  }
  [[nodiscard]] unsigned pins() const {
    return static_cast<unsigned>(in.a.value() * 2 + in.b.value());
  }
  // Clocks with the current inputs; strobes last one clock.
  void clock(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) {
      dut.step(in, cfg);
      in.latch_clear = in.reset = rtl::UInt<1>{};
      in.clear = {};
      ++steps;
    }
  }
  void latch_clear() {
    in.latch_clear = rtl::UInt<1>{1};
    clock();
  }
  void clear_flags() {
    const rtl::UInt<1> one{1};
    in.clear.status = {.phase_error = one, .carry = one, .borrow = one, .period_overflow = one};
    clock();
  }
  // Drives the pins from a quadrature source for n clocks.
  void run(world::QuadratureSource& source, std::uint64_t n) {
    for (std::uint64_t i = 0; i < n; ++i) {
      set_pins(static_cast<unsigned>(board::encoder_pins(source.tick()).value()));
      clock();
    }
  }
  [[nodiscard]] std::int64_t count() const { return dut.count().value(); }
  // Clocks from a pin change to the counter: synchroniser, filter, decoder.
  [[nodiscard]] unsigned latency() const {
    const auto n = static_cast<unsigned>(cfg.cfg.filter_clocks.value());
    return (n > 1 ? n : 1U) + 3;
  }
};

}  // namespace odoloc::tb
