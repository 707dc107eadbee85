// Runs another program the way the project's tools and tests need it: no
// shell (no quoting of paths), in a given working directory, with what the
// program printed kept for the error message.
#pragma once

#include <atomic>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace odoloc::process {

// A stop flag (SIGINT, SIGTERM, SIGHUP: the host tool's main) ended the
// work; thrown by the tools' libraries after they removed what they had
// begun to write. The host tool exits 128 + the signal's number, silently.
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted") {}
};

// What running a program gave: `launched` false when it could not be started
// (`message` says why, e.g. not installed); else its exit status and what it
// printed (stdout and stderr); `interrupted` when the stop flag ended it.
struct ProgramResult {
  bool launched = false;
  bool interrupted = false;
  int exit_status = -1;
  std::string message;
  [[nodiscard]] bool ok() const { return launched && !interrupted && exit_status == 0; }
};

// Runs `program` (looked up in PATH) with `args` in `working_dir`, without a
// shell, capturing its output. When `stop` is set meanwhile (a signal), the
// program is sent SIGTERM within 10 ms and waited for.
ProgramResult run_program(const std::string& program, const std::vector<std::string>& args,
                          const std::filesystem::path& working_dir,
                          const std::atomic<bool>* stop = nullptr);

// A program's message on one line, for an error message: its lines joined
// by "; ", without blank lines and without the caret lines (" ^") that
// gnuplot prints under an echoed command.
std::string one_line(std::string_view message);

// Runs a command line with /bin/sh -c in `working_dir` (for tests that
// compose compiler command lines); quote paths in it.
ProgramResult run_shell(const std::string& command, const std::filesystem::path& working_dir);

}  // namespace odoloc::process
