// Composites are two-phase by construction: every composite computes all the
// wires into its children from the current registers, then clocks the
// children, so the order it clocks them in cannot matter. Proof: the whole
// chip (chip -> fabric -> encoders -> EPPM -> leaves, chip -> SPI slave,
// register file) is run with its children clocked in a fresh random
// permutation at every level and every clock, and in reverse order, against
// declaration order, under moving encoders, random SPI frames (writes that
// configure, clear flags, set the pose; reads) and rare resets. Every
// register of every block is compared after every clock.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <random>
#include <vector>

#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/odoloc_chip.hpp"
#include "odoloc/world/quadrature_source.hpp"
#include "random_frames.hpp"
#include "register_dump.hpp"
#include "spi_master_bfm.hpp"

namespace {

using odoloc::rtl::ChipPins;
using odoloc::rtl::Gating;
using odoloc::rtl::OdolocChip;
using odoloc::rtl::UInt;

// Clocks the children in a random permutation, drawn anew at every call.
struct ShuffledOrder {
  std::mt19937_64* rng;
  template <class... Clock>
  void operator()(Clock&&... clock) const {
    std::array<std::function<void()>, sizeof...(Clock)> calls{
        std::function<void()>(std::ref(clock))...};
    std::shuffle(calls.begin(), calls.end(), *rng);
    for (auto& c : calls)
      c();
  }
};

struct ReverseOrder {
  template <class... Clock>
  void operator()(Clock&&... clock) const {
    std::array<std::function<void()>, sizeof...(Clock)> calls{
        std::function<void()>(std::ref(clock))...};
    std::reverse(calls.begin(), calls.end());
    for (auto& c : calls)
      c();
  }
};

TEST(CommitOrder, EveryPermutationOfEveryCompositeGivesTheSameRegisters) {
  std::mt19937_64 rng(8);
  std::mt19937_64 order_rng(88);
  OdolocChip reference, shuffled, shuffled_ungated, reversed;
  std::array<odoloc::world::QuadratureSource, 4> sources{};
  std::uniform_real_distribution<double> rate(-0.03, 0.03);
  ChipPins pins;
  std::uint64_t clock = 0;
  std::uint64_t updates = 0;
  odoloc::tb::SpiMasterBfm master({.half_period = 4, .mode3 = false});

  const auto step = [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
    if (clock % 15'000 == 0)
      for (auto& s : sources)
        s.set_rate(rng() % 4 == 0 ? 0.0 : rate(rng));
    for (std::size_t w = 0; w < sources.size(); ++w) {
      pins.encoders[w] = odoloc::board::encoder_pins(sources[w].tick());
    }
    pins.sclk = sclk;
    pins.cs_n = cs_n;
    pins.mosi = mosi;
    pins.reset = UInt<1>::truncate(rng() % 150'000 == 0);
    reference.step(pins);
    shuffled.step<Gating::kOn>(pins, ShuffledOrder{&order_rng});
    shuffled_ungated.step<Gating::kOff>(pins, ShuffledOrder{&order_rng});
    reversed.step<Gating::kOn>(pins, ReverseOrder{});
    for (const OdolocChip* other : {&shuffled, &shuffled_ungated, &reversed}) {
      const std::string diff = odoloc::tb::first_difference(reference, *other);
      if (!diff.empty())
        ADD_FAILURE() << "clock " << clock << ": " << diff;
    }
    ++clock;
    return reference.miso();
  };
  std::uint64_t last = 0;
  while (clock < 400'000 && !HasFailure()) {
    master.transfer(odoloc::tb::random_frame(rng), step);
    const std::uint64_t now = reference.fabric().sequencer().updates.value();
    updates += now > last ? now - last : 0;
    last = now;
  }
  EXPECT_GT(updates, 200U);  // many complete updates were compared
}

}  // namespace
