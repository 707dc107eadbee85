// odoloc: the host tool. See docs/host-tool.md.
#include <signal.h>

#include <atomic>
#include <iostream>
#include <string>
#include <vector>

#include "odoloc/cli/app.hpp"
#include "odoloc/cli/errors.hpp"

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" void on_stop_signal(int signal) {
  g_signal.store(signal);
  g_stop.store(true);
}

}  // namespace

int main(int argc, char** argv) {
  // Ctrl-C (SIGINT), SIGTERM (kill, Slurm, GNU parallel --halt) and SIGHUP
  // (a closed terminal) set the flag that every long-running loop polls
  // (simulated time in slices of 1 ms, sleeps in 10 ms, watch samples,
  // script lines, jobs, files, kernels, gnuplot every 10 ms): the command
  // removes what it had begun to write and the tool exits 128 + the
  // signal's number (130, 143, 129), as a shell reports a process the
  // signal ended. Not SA_RESTART, so that a blocking open or read ends too;
  // SA_RESETHAND makes a second signal end the process at once.
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  for (const int signal : {SIGINT, SIGTERM, SIGHUP})
    sigaction(signal, &action, nullptr);

  const std::vector<std::string> args(argv + 1, argv + argc);
  const int code = odoloc::cli::run_cli(args, {std::cin, std::cout, std::cerr},
                                        odoloc::cli::open_target, &g_stop);
  if (code == odoloc::cli::kExitInterrupted && g_signal.load() != 0)
    return 128 + g_signal.load();
  return code;
}
