// From EPPM register values to physical units, and back to register settings.
// The SoC side of the encoder module: pure arithmetic, no fabric access.
//
// Derivation (docs/eppm.md): an encoder of N lines per revolution, decoded x4,
// on a shaft geared G:1 to a wheel of radius R gives 4*N*G edges per wheel
// revolution, so one edge is 2*pi*R/(4*N*G) = pi*R/(2*N*G) metres (the paper's
// delta-P). Pulse mode: C edges in T seconds -> v = C * dP / T. Period mode:
// C reference ticks of f_ref per edge -> v = dP * f_ref / C. The paper prints
// the period formula without R; the units show R belongs there.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

#include "odoloc/regs.hpp"

namespace odoloc::sw {

inline constexpr double kFabricClockHz = regs::kFabricClockHz;

struct EncoderGeometry {
  double wheel_radius_m = 0.1;
  double lines_per_rev = 500;  // N
  double gear_ratio = 30;      // G: encoder shaft turns per wheel turn
  double edges_per_line = 4;   // x4 decoding (2 for x2, 1 for x1)

  [[nodiscard]] double metres_per_edge() const {
    return 2.0 * std::numbers::pi * wheel_radius_m / (edges_per_line * lines_per_rev * gear_ratio);
  }
};

struct SpeedTiming {
  // The register resets: eppm.*.window (pulse-mode window T in fabric clocks)
  // and eppm.*.prescale (a reference tick every prescale+1 clocks).
  std::uint32_t window_clocks = regs::eppm::window::clocks.reset;
  std::uint32_t prescale = regs::eppm::prescale::divider.reset;
  double fabric_clock_hz = kFabricClockHz;

  [[nodiscard]] double window_s() const { return window_clocks / fabric_clock_hz; }
  [[nodiscard]] double reference_hz() const { return fabric_clock_hz / (prescale + 1.0); }

  // Relative quantisation error of each mode at an edge rate (edges/s): pulse
  // mode is off by at most one edge per window, period mode by about one tick
  // per edge.
  [[nodiscard]] double pulse_relative_error(double edges_per_s) const {
    return 1.0 / (std::abs(edges_per_s) * window_s());
  }
  [[nodiscard]] double period_relative_error(double edges_per_s) const {
    return std::abs(edges_per_s) / reference_hz();
  }
  // Edges per window where both errors are equal: C* = sqrt(T * f_ref).
  [[nodiscard]] double crossover_edges_per_window() const {
    return std::sqrt(window_s() * reference_hz());
  }
};

// Automatic-switch thresholds around the crossover: period mode below
// C*/band, pulse mode from C*·band, the mode held in between.
struct SwitchThresholds {
  std::uint32_t to_period_below;
  std::uint32_t to_pulse_at;
};
inline SwitchThresholds switch_thresholds(const SpeedTiming& timing, double band = 1.25) {
  const double c = timing.crossover_edges_per_window();
  const auto below = static_cast<std::uint32_t>(std::floor(c / band));
  const auto at = static_cast<std::uint32_t>(std::ceil(c * band));
  return {below, at > below ? at : below + 1};
}

// Speed word (signed value + mode bit) to metres per second.
inline double speed_mps(std::int32_t value, bool pulse_mode, const EncoderGeometry& geometry,
                        const SpeedTiming& timing) {
  if (value == 0)
    return 0.0;
  const double dp = geometry.metres_per_edge();
  return pulse_mode ? value * dp / timing.window_s() : dp * timing.reference_hz() / value;
}

}  // namespace odoloc::sw
