// Exit codes and the error kinds of the `odoloc` host tool.
#pragma once

#include <stdexcept>

namespace odoloc::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBus = 1;    // the bus or the link failed (sw::BusError)
inline constexpr int kExitUsage = 2;  // bad command line, name, value, address or target

// Anything the user can fix on the command line; detected before any bus
// traffic whenever possible. The message is one line, without "odoloc: ".
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace odoloc::cli
