// The run-time switch of the fast-forward mutant build
// (testbenches/rtl/fast_forward_mutants.cmake): ODOLOC_MUTANT=<name> turns on
// the mutant of that name; unset or empty, none. Only the mutant copies of
// the model's headers include this.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <string_view>
#include <type_traits>

#include "fast_forward_mutant_names.hpp"

namespace odoloc::tb {

// The index of the mutant ODOLOC_MUTANT names, -1 for none; an unknown name
// ends the program with status 2 (so no mutant test can pass on a typo).
inline int active_mutant() {
  static const int active = [] {
    const char* name = std::getenv("ODOLOC_MUTANT");  // NOLINT(concurrency-mt-unsafe)
    if (name == nullptr || *name == '\0')
      return -1;
    for (int k = 0; k < static_cast<int>(std::size(kFastForwardMutants)); ++k)
      if (std::string_view{name} == kFastForwardMutants[k])
        return k;
    std::fprintf(stderr, "ODOLOC_MUTANT=%s: no such mutant (testbenches/rtl/fast_forward_mutants.txt)\n",
                 name);
    std::exit(2);  // NOLINT(concurrency-mt-unsafe)
  }();
  return active;
}

// Whether mutant k is on. Never during constant evaluation, so the model's
// constexpr rules stay constant expressions.
constexpr bool mutant(int k) {
  if (std::is_constant_evaluated())
    return false;
  return active_mutant() == k;
}

}  // namespace odoloc::tb
