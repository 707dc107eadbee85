// A fuzz target's invariant: when it is broken, say which and show the input,
// then abort, so that libFuzzer keeps the input as a crash file.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace odoloc::tb {

inline void require(bool ok, const char* what, const std::string& text) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n----\n%s\n----\n", what, text.c_str());
    std::abort();
  }
}

}  // namespace odoloc::tb
