// The whole `odoloc` command line as a function: parse, check, open the
// target, run, report. main() is a thin wrapper; tests call it in-process
// with their own target opener.
#pragma once

#include <atomic>
#include <functional>
#include <iosfwd>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "odoloc/cli/target.hpp"

namespace odoloc::cli {

struct Io {
  std::istream& in;  // `script -`
  std::ostream& out;
  std::ostream& err;  // one line "odoloc: ..." per error
};

using TargetOpener =
    std::function<std::unique_ptr<Target>(std::string_view spec, const TargetOptions& options)>;

// Exit code: kExitOk, kExitBus or kExitUsage (130 when a script is
// interrupted by `stop`). `args` excludes the program name.
int run_cli(std::span<const std::string> args, const Io& io, const TargetOpener& open = open_target,
            const std::atomic<bool>* stop = nullptr);

}  // namespace odoloc::cli
