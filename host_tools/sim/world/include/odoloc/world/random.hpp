// Portable random draws for the world's seeded simulations (the acoustic
// world, the sweeps of `odoloc sweep`): std::mt19937_64's output is fixed by
// the standard, and so is std::seed_seq; the transforms below are ours,
// because the standard distributions are not portable. A seed and a stream
// number give the same draws on every standard library.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace odoloc::world {

class Random {
 public:
  // One engine per (seed, stream): independent streams from one seed.
  Random(std::uint64_t seed, std::uint32_t stream) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32U),
                      stream};
    engine_.seed(seq);
  }
  double uniform() {  // [0, 1), 53 bits
    return std::ldexp(static_cast<double>(engine_() >> 11U), -53);
  }
  double normal() {                     // standard normal; Box-Muller, one value per call
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2);
  }
  double exponential(double rate) { return -std::log(1.0 - uniform()) / rate; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace odoloc::world
