#include "odoloc/cli/app.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <istream>
#include <optional>
#include <ostream>
#include <vector>

#include "odoloc/cli/commands.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/output/output_file.hpp"
#include "odoloc/output/printable.hpp"
#include "odoloc/sw/register_bus.hpp"

namespace odoloc::cli {
namespace {

TargetOptions options_of(const Invocation& inv, const std::atomic<bool>* stop) {
  return {.crc = inv.crc,
          .vcd = inv.vcd,
          .vcd_pins = inv.vcd_pins,
          .cycle_step = inv.cycle_step,
          .stop = stop};
}

struct ScriptStep {
  std::size_t line;
  Invocation invocation;
};

// Messages quote file names, file contents, log and network text: shown
// printable (no control sequence reaches the terminal) and on one line.
int report(const Io& io, std::string_view where, std::string_view message, int code) {
  io.err << "odoloc: " << output::printable(where) << output::printable(message) << '\n'
         << std::flush;
  return code;
}

// Runs `body`, mapping its exceptions to exit codes and one-line messages.
// Once `stop` is set any error is the interruption's (a FIFO's open or a
// read that the signal ended): exit kExitInterrupted, no message.
template <class F>
int guarded(const Io& io, std::string_view where, const std::atomic<bool>* stop, F&& body) {
  const auto failed = [&](std::string_view message, int code) {
    return stop != nullptr && stop->load() ? kExitInterrupted : report(io, where, message, code);
  };
  try {
    body();
    return kExitOk;
  } catch (const Interrupted&) {
    return kExitInterrupted;  // a signal: the shell's convention, no message
  } catch (const FileError& e) {
    return failed(e.what(), kExitBus);
  } catch (const UsageError& e) {
    return failed(e.what(), kExitUsage);
  } catch (const output::OutputError& e) {
    return failed(e.what(), e.usage() ? kExitUsage : kExitBus);
  } catch (const sw::BusError& e) {
    return failed(fmt::format("bus error: {}", e.what()), kExitBus);
  } catch (const std::exception& e) {
    return failed(e.what(), kExitBus);
  }
}

// Every line parsed and resolved before anything runs, so a typo on line 9
// does not leave lines 1-8 applied.
// limit: the simulated board's (check_simulated), null on other targets.
std::vector<ScriptStep> parse_script(std::istream& in, const std::string& name,
                                     const SimulatedLimit* limit) {
  std::vector<ScriptStep> steps;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    try {
      const std::vector<std::string> words = split_line(text);
      if (words.empty())
        continue;
      Invocation inv = parse_invocation(words);
      if (inv.target_given || inv.crc || !inv.vcd.empty() || !inv.vcd_pins.empty() ||
          inv.cycle_step)
        throw UsageError(
            "--target, --crc, --vcd, --vcd-pins and --cycle-step choose the transport once, on "
            "the odoloc command line, for the whole script");
      if (std::holds_alternative<ScriptCommand>(inv.command) && inv.help.empty())
        throw UsageError("a script cannot run another script");
      if (limit != nullptr && inv.help.empty())
        check_simulated(inv.command, *limit);
      steps.push_back({line, std::move(inv)});
    } catch (const UsageError& e) {
      throw UsageError(fmt::format("{}:{}: {}", name, line, e.what()));
    }
  }
  if (in.bad())  // a directory, an I/O error: never a silently empty script
    throw UsageError(fmt::format("cannot read script {}: {}", name, std::strerror(errno)));
  return steps;
}

int run_script(const Invocation& outer, const ScriptCommand& cmd, const Io& io,
               const TargetOpener& open, const std::atomic<bool>* stop) {
  const std::string name = cmd.file == "-" ? "<stdin>" : cmd.file;
  std::vector<ScriptStep> steps;
  int code = guarded(io, "", stop, [&] {
    const SimulatedLimit limit = simulated_limit(outer.cycle_step);
    const SimulatedLimit* simulated = is_sim_spec(outer.target) ? &limit : nullptr;
    if (cmd.file == "-") {
      steps = parse_script(io.in, name, simulated);
      return;
    }
    std::error_code ec;
    if (std::filesystem::is_directory(cmd.file, ec))
      throw UsageError(fmt::format("cannot read script {}: it is a directory", cmd.file));
    std::ifstream file(cmd.file);
    if (!file)
      throw UsageError(fmt::format("cannot open script {}: {}", cmd.file, std::strerror(errno)));
    steps = parse_script(file, name, simulated);
  });
  if (code != kExitOk)
    return code;

  std::unique_ptr<Target> target;
  const bool any_target = std::ranges::any_of(steps, [](const ScriptStep& s) {
    return s.invocation.help.empty() && needs_target(s.invocation.command);
  });
  if (any_target) {
    code = guarded(io, "", stop, [&] { target = open(outer.target, options_of(outer, stop)); });
    if (code != kExitOk)
      return code;
  }
  for (const ScriptStep& step : steps) {
    if (stop != nullptr && stop->load())
      return kExitInterrupted;
    if (!step.invocation.help.empty()) {
      io.out << step.invocation.help;
      continue;
    }
    code = guarded(io, fmt::format("{}:{}: ", name, step.line), stop, [&] {
      execute(step.invocation.command, target.get(), io.out, outer.json || step.invocation.json,
              stop);
    });
    if (code != kExitOk)
      break;
  }
  if (target) {
    const int closed = guarded(io, "", stop, [&] { target->finish(); });
    if (code == kExitOk)
      code = closed;
  }
  return code;
}

// Standard output redirected to a file is a file the tool writes too: a
// full disk is an error, not a silently short file.
int check_output(const Io& io, int code) {
  io.out.flush();
  if (!io.out.fail())
    return code;
  const int failed = report(io, "", "writing standard output failed", kExitBus);
  return code == kExitOk ? failed : code;
}

}  // namespace

int run_cli(std::span<const std::string> args, const Io& io, const TargetOpener& open,
            const std::atomic<bool>* stop) {
  Invocation inv;
  int code = guarded(io, "", stop, [&] {
    inv = parse_invocation(args);
    check_target_spec(inv.target);
    if (inv.help.empty() && is_sim_spec(inv.target))
      check_simulated(inv.command, simulated_limit(inv.cycle_step));
  });
  if (code != kExitOk)
    return code;
  if (!inv.help.empty()) {
    io.out << inv.help;
    return check_output(io, kExitOk);
  }
  if (const auto* script = std::get_if<ScriptCommand>(&inv.command))
    return check_output(io, run_script(inv, *script, io, open, stop));
  std::unique_ptr<Target> target;
  code = guarded(io, "", stop, [&] {
    if (needs_target(inv.command))
      target = open(inv.target, options_of(inv, stop));
    execute(inv.command, target.get(), io.out, inv.json, stop);
  });
  if (target) {
    const int closed = guarded(io, "", stop, [&] { target->finish(); });
    if (code == kExitOk)
      code = closed;
  }
  return check_output(io, code);
}

}  // namespace odoloc::cli
