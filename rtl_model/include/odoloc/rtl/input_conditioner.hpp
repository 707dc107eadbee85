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
    // One aggregate of scalars, so the next state stays in registers.
    return [&]<std::size_t... I>(std::index_sequence<I...>) {
      const std::array<Line, Lines> lines{filter_line<I>(in.filter_clocks)...};
      return InputConditionerRegs<Lines>{
          .sync1 = in.pins,
          .sync2 = r_.sync1,
          .filtered = UInt<Lines>::truncate(((std::uint64_t{lines[I].level.value()} << I) | ...)),
          .stable = {lines[I].stable...}};
    }
    (std::make_index_sequence<Lines>{});
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

  // Fast-forward from settled() with new pins held and no reset: the pins
  // pass the two synchroniser flops (2 clocks), then every line that differs
  // counts N = max(filter_clocks, 1) samples and takes the new level in the
  // N-th, all in the same clock. clocks_to_take: N + 2; held_from_settled:
  // the registers after k <= N + 2 of those clocks.
  [[nodiscard]] static constexpr std::uint64_t clocks_to_take(UInt<8> filter_clocks) {
    return (filter_clocks.is_zero() ? 1 : filter_clocks.value()) + 2;
  }
  [[nodiscard]] Regs held_from_settled(UInt<Lines> pins, UInt<8> filter_clocks,
                                       std::uint64_t k) const {
    Regs n = r_;
    n.sync1 = pins;
    if (k >= 2)
      n.sync2 = pins;
    if (k == clocks_to_take(filter_clocks)) {
      n.filtered = pins;
      return n;
    }
    if (k >= 3) {
      const std::uint64_t changing = (pins.value() ^ r_.filtered.value());
      for (std::size_t i = 0; i < Lines; ++i)
        if (((changing >> i) & 1U) != 0)
          n.stable[i] = UInt<8>::truncate(k - 2);  // k - 2 < N <= 255
    }
    return n;
  }

 private:
  struct Line {
    UInt<1> level;
    UInt<8> stable;
  };
  // Line I: a sample equal to the filtered level restarts the count; the
  // N-th consecutive differing one (N <= 1: the first) is taken.
  template <std::size_t I>
  [[nodiscard]] Line filter_line(UInt<8> filter_clocks) const {
    const auto sample = UInt<1>::truncate(r_.sync2.value() >> I);
    const auto level = UInt<1>::truncate(r_.filtered.value() >> I);
    if (sample == level)
      return {level, UInt<8>{}};
    const UInt<9> seen = r_.stable[I] + UInt<1>{1};
    if (seen >= filter_clocks)
      return {sample, UInt<8>{}};
    return {level, seen.template wrap<8>()};  // seen < N <= 255
  }
};

}  // namespace odoloc::rtl
