// The host tool's one-line UsageError message of a call, for tests that
// compare messages word for word.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "odoloc/cli/errors.hpp"

namespace odoloc::tb {

// What `f` throws as a UsageError; a test failure when it throws none.
inline std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const cli::UsageError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no UsageError";
  return {};
}

}  // namespace odoloc::tb
