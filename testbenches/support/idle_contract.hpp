// The leaf-block contract every gated block keeps: idle(in) implies
// eval(in) == regs(). check_idle_contract drives a block with random inputs
// (and a random register set every 1000 clocks) and checks it at every clock;
// it returns the share of idle clocks, so a test can tell the check was not
// vacuous. Plus the small random helpers the gating testbenches share.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <random>

#include "odoloc/rtl/bits.hpp"
#include "register_dump.hpp"
#include "test_scale.hpp"

namespace odoloc::tb {

using Rng = std::mt19937_64;

inline bool one_in(Rng& rng, std::uint64_t n) {
  return rng() % n == 0;
}
template <int W>
rtl::UInt<W> random_uint(Rng& rng) {
  return rtl::UInt<W>::truncate(rng());
}
template <int W>
rtl::SInt<W> random_sint(Rng& rng) {
  return rtl::SInt<W>::truncate(static_cast<std::int64_t>(rng()));
}
template <int W, std::size_t N>
rtl::UInt<W> pick(Rng& rng, const std::array<std::uint32_t, N>& values) {
  return rtl::UInt<W>::truncate(values[rng() % N]);
}

template <class Block, class RandomRegs, class RandomIn>
double check_idle_contract(std::uint64_t seed, RandomRegs random_regs, RandomIn random_in) {
  const std::uint64_t clocks = scaled(200'000);
  Rng rng(seed);
  Block block;
  std::uint64_t idle_clocks = 0;
  for (std::uint64_t k = 0; k < clocks; ++k) {
    if (k % 1000 == 0)
      block.commit(random_regs(rng));
    const typename Block::In in = random_in(rng);
    const typename Block::Regs next = block.eval(in);
    if (block.idle(in)) {
      ++idle_clocks;
      if (!(next == block.regs())) {
        Block stepped = block;
        stepped.commit(next);
        ADD_FAILURE() << "idle but eval changes state, seed " << seed << " step " << k << ": "
                      << first_difference(block, stepped);
        return 0;
      }
    }
    block.commit(next);
  }
  return static_cast<double>(idle_clocks) / static_cast<double>(clocks);
}

}  // namespace odoloc::tb
