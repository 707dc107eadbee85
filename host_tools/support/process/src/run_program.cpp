#include "odoloc/process/run_program.hpp"

#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

extern char** environ;  // NOLINT: POSIX

namespace odoloc::process {

ProgramResult run_program(const std::string& program, const std::vector<std::string>& args,
                          const std::filesystem::path& working_dir, const std::atomic<bool>* stop) {
  ProgramResult result;
  std::array<int, 2> err{};
  if (pipe(err.data()) != 0) {
    result.message = std::string("cannot create a pipe: ") + std::strerror(errno);
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, working_dir.c_str());
  posix_spawn_file_actions_adddup2(&actions, err[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, err[0]);
  posix_spawn_file_actions_addclose(&actions, err[1]);
  std::vector<std::string> argv_text{program};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(err[1]);
  if (spawned != 0) {
    close(err[0]);
    result.message = program + ": " + std::strerror(spawned);
    return result;
  }
  std::array<char, 4096> buffer{};
  constexpr int kStopPollMs = 10;
  for (;;) {
    if (stop != nullptr && stop->load() && !result.interrupted) {
      result.interrupted = true;
      kill(pid, SIGTERM);
    }
    pollfd readable{.fd = err[0], .events = POLLIN, .revents = 0};
    if (poll(&readable, 1, kStopPollMs) <= 0)
      continue;  // a timeout or a signal: look at the flag again
    const ssize_t n = read(err[0], buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0)
      break;  // the end: every writer (the program, its children) closed it
    result.message.append(buffer.data(), static_cast<std::size_t>(n));
  }
  close(err[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.launched = true;
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

std::string one_line(std::string_view message) {
  std::string out;
  for (std::size_t start = 0; start < message.size();) {
    std::size_t end = message.find('\n', start);
    if (end == std::string_view::npos)
      end = message.size();
    const std::string_view line = message.substr(start, end - start);
    start = end + 1;
    if (line.find_first_not_of(" ^\t") != std::string_view::npos)
      out += (out.empty() ? "" : "; ") + std::string{line};
  }
  return out;
}

ProgramResult run_shell(const std::string& command, const std::filesystem::path& working_dir) {
  return run_program("/bin/sh", {"-c", command}, working_dir);
}

}  // namespace odoloc::process
