// odoloc: the host tool. See docs/host-tool.md.
#include <signal.h>

#include <atomic>
#include <iostream>
#include <string>
#include <vector>

#include "odoloc/cli/app.hpp"

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_interrupt(int /*signal*/) {
  g_stop.store(true);
}

}  // namespace

int main(int argc, char** argv) {
  // The first Ctrl-C sets the flag that every long-running loop polls
  // (simulated time in slices of 1 ms, sleeps in 10 ms, watch samples, script
  // lines): the command ends within milliseconds and the tool exits 130.
  // SA_RESETHAND makes a second one kill the process.
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);

  const std::vector<std::string> args(argv + 1, argv + argc);
  return odoloc::cli::run_cli(args, {std::cin, std::cout, std::cerr}, odoloc::cli::open_target,
                              &g_stop);
}
