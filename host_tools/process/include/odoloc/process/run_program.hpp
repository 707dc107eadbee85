// Runs another program the way the project's tools and tests need it: no
// shell (no quoting of paths), in a given working directory, with what the
// program printed kept for the error message.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace odoloc::process {

// What running a program gave: `launched` false when it could not be started
// (`message` says why, e.g. not installed); else its exit status and what it
// printed (stdout and stderr).
struct ProgramResult {
  bool launched = false;
  int exit_status = -1;
  std::string message;
  [[nodiscard]] bool ok() const { return launched && exit_status == 0; }
};

// Runs `program` (looked up in PATH) with `args` in `working_dir`, without a
// shell, capturing its output.
ProgramResult run_program(const std::string& program, const std::vector<std::string>& args,
                          const std::filesystem::path& working_dir);

// Runs a command line with /bin/sh -c in `working_dir` (for tests that
// compose compiler command lines); quote paths in it.
ProgramResult run_shell(const std::string& command, const std::filesystem::path& working_dir);

}  // namespace odoloc::process
