// Exit codes and the error kinds of the `odoloc` host tool.
#pragma once

#include <stdexcept>

#include "odoloc/process/run_program.hpp"

namespace odoloc::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBus = 1;    // the bus or the link failed (sw::BusError)
inline constexpr int kExitUsage = 2;  // bad command line, name, value, address or target
// Ended by a signal: run_cli returns 130 (128 + SIGINT); main returns 128 +
// the number of the signal that came (SIGTERM 143, SIGHUP 129), as a shell
// reports a process that signal ended.
inline constexpr int kExitInterrupted = 130;

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

// Ctrl-C, SIGTERM, SIGHUP: thrown by long-running loops (simulated time,
// watch, wait) and the libraries when the stop flag is set; the tool exits
// 128 + the signal's number without a message.
using Interrupted = process::Interrupted;

}  // namespace odoloc::cli
