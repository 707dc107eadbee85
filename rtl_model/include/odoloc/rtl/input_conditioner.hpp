// Input conditioning of asynchronous pins: two synchroniser flops, then a
// level filter per line. One piece of logic for every pin bank of the fabric:
// the EPPM's A/B pair (docs/eppm.md) and the ultrasonic comparators and sync
// input of the TOF capture unit (docs/tof-capture.md).
//
// Per line, a counter of consecutive samples whose level differs from the
// filtered level; the new level is taken on the N-th such sample (N =
// max(filter_clocks, 1)) and any sample equal to the filtered level restarts
// the count. A pulse of N clocks passes, one of N-1 clocks is rejected. A pin
// change first applied in clock t reaches `filtered` at the edge ending clock
// t+N+1 (docs/eppm.md, "Input conditioning and latency").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"

namespace odoloc::rtl {

// Lines travel packed, line i in bit i.
template <int Lines>
struct InputConditionerRegs {
  UInt<Lines> sync1, sync2, filtered;
  std::array<UInt<8>, Lines> stable{};  // per line: consecutive samples differing from `filtered`
  bool operator==(const InputConditionerRegs&) const = default;
  ODOLOC_FIELDS(sync1, sync2, filtered, stable)
};

template <int Lines>
class InputConditioner : public Registers<InputConditionerRegs<Lines>> {
  using Base = Registers<InputConditionerRegs<Lines>>;
  using Base::r_;

 public:
  using Regs = typename Base::Regs;
  struct In {
    UInt<Lines> pins;
    UInt<8> filter_clocks;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    // A line whose synchronised sample equals its filtered level restarts
    // its count (0, the initialiser); only the others run the filter.
    Regs n{.sync1 = in.pins, .sync2 = r_.sync1, .filtered = r_.filtered, .stable = {}};
    const std::uint64_t differ = (r_.sync2 ^ r_.filtered).value();
    if (differ == 0)
      return n;
    std::uint64_t flips = 0;
    // Unrolled with constant indices, so the compiler keeps the counters in
    // registers instead of a stack array.
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      (filter_line<I>(differ, in.filter_clocks, n, flips), ...);
    }
    (std::make_index_sequence<Lines>{});
    n.filtered = UInt<Lines>::truncate(r_.filtered.value() ^ flips);
    return n;
  }
  // Every stage holds the pins and no filter count runs.
  [[nodiscard]] bool settled() const {
    const bool counting = [&]<std::size_t... I>(std::index_sequence<I...>) {
      return (... || !r_.stable[I].is_zero());
    }
    (std::make_index_sequence<Lines>{});
    return r_.sync1 == r_.sync2 && r_.sync2 == r_.filtered && !counting;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.pins == r_.sync1 && in.reset.is_zero() && settled();
  }

 private:
  // Line I differs from its filtered level: takes the new level on the N-th
  // consecutive differing sample (N <= 1: the first), else counts it.
  template <std::size_t I>
  void filter_line(std::uint64_t differ, UInt<8> filter_clocks, Regs& n,
                   std::uint64_t& flips) const {
    if (((differ >> I) & 1U) == 0)
      return;
    const UInt<9> seen = r_.stable[I] + UInt<1>{1};
    if (seen >= filter_clocks)
      flips |= std::uint64_t{1} << I;
    else
      n.stable[I] = seen.template wrap<8>();  // seen < N <= 255
  }
};

}  // namespace odoloc::rtl
