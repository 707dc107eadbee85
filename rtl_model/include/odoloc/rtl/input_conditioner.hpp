// Input conditioning of asynchronous pins: two synchroniser flops, then a
// level filter per line, for every pin bank of the fabric (the EPPM's A/B
// pair, the TOF capture unit's comparators and sync input). The logic:
// logic/input_conditioner.hpp (the one source, also the HLS kernels'). Here:
// what only a simulator needs around it (field lists, settled, idle, the
// fast-forward).
#pragma once

#include <cstddef>
#include <cstdint>

#include "odoloc/logic/input_conditioner.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/family.hpp"

namespace odoloc::rtl {

ODOLOC_LOGIC_FIELDS(logic::conditioner::Line, stable)
ODOLOC_LOGIC_FIELDS_OF((int Lines), (logic::conditioner::Regs<Family, Lines>), sync1, sync2,
                       filtered, line)

// Lines travel packed, line i in bit i.
template <int Lines>
using InputConditionerRegs = logic::conditioner::Regs<Family, Lines>;

template <int Lines>
class InputConditioner : public Registers<InputConditionerRegs<Lines>> {
  using Base = Registers<InputConditionerRegs<Lines>>;
  using Base::r_;
  using Logic = logic::conditioner::InputConditioner<Family, Lines>;

 public:
  using Regs = typename Base::Regs;
  using In = logic::conditioner::In<Family, Lines>;

  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  // Every stage holds the pins and no filter count runs.
  [[nodiscard]] bool settled() const {
    bool counting = false;
    for (const auto& line : r_.line)
      counting |= !line.stable.is_zero();
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
          n.line[i].stable = UInt<8>::truncate(k - 2);  // k - 2 < N <= 255
    }
    return n;
  }
};

}  // namespace odoloc::rtl
