// Quadrature encoder waveform source: a 64-bit phase accumulator (NCO) whose
// quarter cycles are the x4 edges. It knows the true edge count, so it is the
// ground truth of benchmarks, demos and scenario tests. It produces plain
// A/B levels; the board turns them into the chip's pin type.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace odoloc::world {

// The two output levels of a quadrature encoder. A leads B when moving
// forward: over one cycle AB = 00, 10, 11, 01.
struct QuadratureLevels {
  bool a = false;
  bool b = false;

  friend constexpr bool operator==(const QuadratureLevels&, const QuadratureLevels&) = default;
};

class QuadratureSource {
 public:
  static constexpr int kFractionBits = 30;  // phase units per x4 edge: 2^30

  // edges_per_clock: x4 edges per fabric clock, signed (negative: B leads A).
  QuadratureSource() = default;
  explicit QuadratureSource(double edges_per_clock) { set_rate(edges_per_clock); }
  void set_rate(double edges_per_clock) {
    increment_ =
        static_cast<std::int64_t>(std::llround(std::ldexp(edges_per_clock, kFractionBits)));
  }
  [[nodiscard]] double rate() const {
    return std::ldexp(static_cast<double>(increment_), -kFractionBits);
  }

  // Advances one clock; returns the A/B levels after it.
  QuadratureLevels tick() {
    phase_ += increment_;
    return level();
  }
  [[nodiscard]] QuadratureLevels level() const {
    // Quarter q = 0,1,2,3 -> AB = 00,10,11,01 (A leads B when moving
    // forward): B is q's high bit, A the Gray code's low bit. Bit operations
    // rather than a table, as the benchmarks' stimulus runs every clock.
    const auto q = static_cast<unsigned>(edges() & 3);
    return {.a = ((q ^ (q >> 1U)) & 1U) != 0, .b = (q >> 1U) != 0};
  }
  // Signed x4 edges since construction (floor of the phase).
  [[nodiscard]] std::int64_t edges() const { return phase_ >> kFractionBits; }

  // For fast-forward: ticks until the next edge (the smallest k >= 1 after
  // which edges() differs; the k-1 ticks before it keep the levels), or
  // kNever when standing still.
  static constexpr std::uint64_t kNever = ~std::uint64_t{0};
  [[nodiscard]] std::uint64_t ticks_to_next_edge() const {
    if (increment_ == 0)
      return kNever;
    const std::int64_t floor = edges() * (std::int64_t{1} << kFractionBits);
    if (increment_ > 0) {
      const std::int64_t distance = floor + (std::int64_t{1} << kFractionBits) - phase_;
      return static_cast<std::uint64_t>((distance + increment_ - 1) / increment_);
    }
    return static_cast<std::uint64_t>((phase_ - floor) / -increment_) + 1;
  }
  // `ticks` ticks at once.
  void skip(std::uint64_t ticks) { phase_ += static_cast<std::int64_t>(ticks) * increment_; }

 private:
  std::int64_t phase_ = 0;
  std::int64_t increment_ = 0;
};

}  // namespace odoloc::world
