#include "odoloc/cli/app.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <istream>
#include <optional>
#include <ostream>
#include <vector>

#include "odoloc/cli/commands.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/sw/register_bus.hpp"

namespace odoloc::cli {
namespace {

constexpr int kExitInterrupted = 130;

struct ScriptStep {
  std::size_t line;
  Invocation invocation;
};

int report(const Io& io, std::string_view where, std::string_view message, int code) {
  io.err << "odoloc: " << where << message << '\n' << std::flush;
  return code;
}

// Runs `body`, mapping its exceptions to exit codes and one-line messages.
template <class F>
int guarded(const Io& io, std::string_view where, F&& body) {
  try {
    body();
    return kExitOk;
  } catch (const UsageError& e) {
    return report(io, where, e.what(), kExitUsage);
  } catch (const sw::BusError& e) {
    return report(io, where, fmt::format("bus error: {}", e.what()), kExitBus);
  } catch (const std::exception& e) {
    return report(io, where, e.what(), kExitBus);
  }
}

// Every line parsed and resolved before anything runs, so a typo on line 9
// does not leave lines 1-8 applied.
std::vector<ScriptStep> parse_script(std::istream& in, const std::string& name) {
  std::vector<ScriptStep> steps;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    try {
      const std::vector<std::string> words = split_line(text);
      if (words.empty())
        continue;
      Invocation inv = parse_invocation(words);
      if (inv.target_given || inv.crc || !inv.vcd.empty())
        throw UsageError(
            "--target, --crc and --vcd choose the transport once, on the odoloc command line, "
            "for the whole script");
      if (std::holds_alternative<ScriptCommand>(inv.command) && inv.help.empty())
        throw UsageError("a script cannot run another script");
      steps.push_back({line, std::move(inv)});
    } catch (const UsageError& e) {
      throw UsageError(fmt::format("{}:{}: {}", name, line, e.what()));
    }
  }
  return steps;
}

int run_script(const Invocation& outer, const ScriptCommand& cmd, const Io& io,
               const TargetOpener& open, const std::atomic<bool>* stop) {
  const std::string name = cmd.file == "-" ? "<stdin>" : cmd.file;
  std::vector<ScriptStep> steps;
  int code = guarded(io, "", [&] {
    if (cmd.file == "-") {
      steps = parse_script(io.in, name);
      return;
    }
    std::ifstream file(cmd.file);
    if (!file)
      throw UsageError(fmt::format("cannot open script {}: {}", cmd.file, std::strerror(errno)));
    steps = parse_script(file, name);
  });
  if (code != kExitOk)
    return code;

  std::unique_ptr<Target> target;
  const bool any_target = std::ranges::any_of(steps, [](const ScriptStep& s) {
    return s.invocation.help.empty() && needs_target(s.invocation.command);
  });
  if (any_target) {
    code =
        guarded(io, "", [&] { target = open(outer.target, {.crc = outer.crc, .vcd = outer.vcd}); });
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
    code = guarded(io, fmt::format("{}:{}: ", name, step.line), [&] {
      execute(step.invocation.command, target.get(), io.out, outer.json || step.invocation.json,
              stop);
    });
    if (code != kExitOk)
      return code;
  }
  return kExitOk;
}

}  // namespace

int run_cli(std::span<const std::string> args, const Io& io, const TargetOpener& open,
            const std::atomic<bool>* stop) {
  Invocation inv;
  int code = guarded(io, "", [&] {
    inv = parse_invocation(args);
    check_target_spec(inv.target);
  });
  if (code != kExitOk)
    return code;
  if (!inv.help.empty()) {
    io.out << inv.help;
    return kExitOk;
  }
  if (const auto* script = std::get_if<ScriptCommand>(&inv.command))
    return run_script(inv, *script, io, open, stop);
  return guarded(io, "", [&] {
    std::unique_ptr<Target> target;
    if (needs_target(inv.command))
      target = open(inv.target, {.crc = inv.crc, .vcd = inv.vcd});
    execute(inv.command, target.get(), io.out, inv.json, stop);
  });
}

}  // namespace odoloc::cli
