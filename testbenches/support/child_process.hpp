// A program run as a child process, its standard streams in files, for the
// tests that run the host tool as users do: to send it signals, give it
// devices, FIFOs and hostile file names, and check its exit status.
#pragma once

#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "scratch_files.hpp"

extern char** environ;  // NOLINT: POSIX

namespace odoloc::tb {

struct ChildResult {
  int code = -1;   // the exit status; -1 when a signal ended it
  int signal = 0;  // the signal that ended it, 0 when it exited
  std::string out, err;
};

struct Child {
  pid_t pid = -1;
  std::string in_path, out_path, err_path;
  bool own_out = true;  // out_path is the test's file (not e.g. /dev/full)
};

// Starts `program` with `args` (no shell), `input` on its standard input,
// standard output into `stdout_path` (default: a file of the test's), in
// `working_dir` (default: the test's), with `environment` ("NAME=VALUE")
// added to the test's own.
inline Child spawn(const std::string& program, const std::vector<std::string>& args,
                   const std::string& input, const std::string& stdout_path = {},
                   const std::filesystem::path& working_dir = {},
                   const std::vector<std::string>& environment = {}) {
  static int serial = 0;
  const std::string base =
      fmt::format("{}odoloc_child_{}_{}", ::testing::TempDir(), ::getpid(), ++serial);
  Child c{-1, base + ".in", stdout_path.empty() ? base + ".out" : stdout_path, base + ".err",
          stdout_path.empty()};
  std::ofstream(c.in_path) << input;

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, c.in_path.c_str(), O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, c.out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  posix_spawn_file_actions_addopen(&actions, 2, c.err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  if (!working_dir.empty())
    posix_spawn_file_actions_addchdir_np(&actions, working_dir.c_str());
  std::vector<std::string> argv_strings{program};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_strings)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  // The test's environment without the names `environment` sets (a shell
  // would take the last of two).
  std::vector<std::string> env_strings = environment;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string_view entry{*e};
    const bool replaced = std::any_of(
        environment.begin(), environment.end(),
        [&](const std::string& n) { return entry.starts_with(n.substr(0, n.find('=') + 1)); });
    if (!replaced)
      env_strings.emplace_back(entry);
  }
  std::vector<char*> env;
  for (std::string& e : env_strings)
    env.push_back(e.data());
  env.push_back(nullptr);
  const int spawned =
      posix_spawnp(&c.pid, program.c_str(), &actions, nullptr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    ADD_FAILURE() << "cannot run " << program << ": " << std::strerror(spawned);
    c.pid = -1;
  }
  return c;
}

// Waits for the child, killing it after `timeout` (a test failure).
inline ChildResult finish(const Child& c,
                          std::chrono::milliseconds timeout = std::chrono::seconds{120}) {
  ChildResult r;
  if (c.pid < 0)
    return r;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  for (;;) {
    const pid_t done = waitpid(c.pid, &status, WNOHANG);
    if (done == c.pid)
      break;
    if (done < 0 && errno != EINTR) {
      ADD_FAILURE() << "waitpid: " << std::strerror(errno);
      return r;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      ADD_FAILURE() << "still running after " << timeout.count() << " ms: killed";
      ::kill(c.pid, SIGKILL);
      while (waitpid(c.pid, &status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds{5});
  }
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  if (c.own_out) {
    r.out = slurp(c.out_path);
    std::remove(c.out_path.c_str());
  }
  r.err = slurp(c.err_path);
  for (const std::string& p : {c.in_path, c.err_path})
    std::remove(p.c_str());
  return r;
}

}  // namespace odoloc::tb
