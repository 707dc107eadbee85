// ODOLOC_TEST_SCALE multiplies the clock budgets of the long randomised
// testbenches (e.g. 0.1 for a quick run, 3 for a soak); default 1.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>

namespace odoloc::tb {

inline std::uint64_t scaled(std::uint64_t clocks) {
  const char* env = std::getenv("ODOLOC_TEST_SCALE");  // NOLINT(concurrency-mt-unsafe)
  const double scale = env != nullptr ? std::strtod(env, nullptr) : 1.0;
  if (!(scale > 0))
    return clocks;
  return std::max<std::uint64_t>(1000,
                                 static_cast<std::uint64_t>(static_cast<double>(clocks) * scale));
}

}  // namespace odoloc::tb
