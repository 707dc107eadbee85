// Exit codes and the error kinds of the `odoloc` host tool.
#pragma once

#include <stdexcept>

namespace odoloc::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBus = 1;            // the bus or the link failed (sw::BusError)
inline constexpr int kExitUsage = 2;          // bad command line, name, value, address or target
inline constexpr int kExitInterrupted = 130;  // ended by Ctrl-C (SIGINT), as a shell reports it

// Anything the user can fix on the command line; detected before any bus
// traffic whenever possible. The message is one line, without "odoloc: ".
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file the tool writes (a waveform, standard output redirected to a file)
// lost data: a failed write or close. Exit kExitBus, never a silent loss.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Runs `body` (a call into one of the tool's libraries) and returns what it
// returns, turning the library's one error kind (sweep::SweepError,
// hls_export::ExportError, plot::PlotError: a what() and usage(), true when
// the input is at fault) into the tool's: UsageError (exit 2) or FileError
// (exit 1).
template <class LibraryError, class F>
auto translated(F&& body) {
  try {
    return body();
  } catch (const LibraryError& e) {
    if (e.usage())
      throw UsageError(e.what());
    throw FileError(e.what());
  }
}

// Ctrl-C: thrown by long-running loops (simulated time, watch, wait) when the
// stop flag is set; the tool exits kExitInterrupted without a message.
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted") {}
};

}  // namespace odoloc::cli
