// The commands of `odoloc`: parsed and resolved against the register map
// first (names, values, access rights: every mistake is a UsageError before
// any bus traffic), then executed on a Target.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "odoloc/cli/export_hls.hpp"
#include "odoloc/cli/locate.hpp"
#include "odoloc/cli/names.hpp"
#include "odoloc/cli/plot.hpp"
#include "odoloc/cli/sim_command.hpp"
#include "odoloc/cli/sweep.hpp"
#include "odoloc/cli/target.hpp"
#include "odoloc/cli/watch_pose.hpp"

namespace odoloc::cli {

struct ListCommand {
  std::string filter;  // substring or glob over register and field paths
};
struct ReadCommand {
  std::vector<Location> items;
};

enum class WriteMode : std::uint8_t {
  kWord,             // a whole register: the word as given
  kReadModifyWrite,  // an rw field: read, keep the other rw bits, write (w1c/w1p bits written 0)
  kFieldOnly,        // a w1c or w1p field: only this field's bits, the rest 0, no read
};
struct Assignment {
  Location target;
  std::uint32_t value = 0;  // the field's raw bits, or the whole word
  [[nodiscard]] WriteMode mode() const;
};
struct WriteCommand {
  std::vector<Assignment> items;
};
struct DumpCommand {
  std::string filter;  // as ListCommand's
};
struct WatchCommand {
  std::vector<Location> items;
  std::chrono::nanoseconds interval = std::chrono::milliseconds{100};
  std::uint64_t count = 0;  // 0: until stopped
};
struct WaitCommand {
  std::chrono::nanoseconds duration{};
};
struct ScriptCommand {
  std::string file;  // "-": standard input
};
using Command =
    std::variant<ListCommand, ReadCommand, WriteCommand, DumpCommand, WatchCommand, WaitCommand,
                 ScriptCommand, LocateCommand, ExportHlsCommand, SweepRunCommand, SweepMergeCommand,
                 PlotCommand, WatchPoseCommand, SimCommand>;

// One command line (the words after "odoloc").
struct Invocation {
  std::string target = "sim";
  bool target_given = false;
  bool json = false;
  bool crc = false;
  std::string vcd;          // sim target: waveform file
  std::string vcd_pins;     // sim target: SPI pins only
  bool cycle_step = false;  // sim target: no fast-forward
  Command command;
  std::string help;  // not empty: --help or --version was asked for; print it, run nothing
};

// Throws UsageError (one line) for anything wrong.
[[nodiscard]] Invocation parse_invocation(std::span<const std::string> args);
// "NAME=VALUE", "NAME.FIELD=VALUE" or "ADDR=VALUE", checked for access and range.
[[nodiscard]] Assignment parse_assignment(std::string_view text);
// A script line's words: whitespace-separated, '...' or "..." quoting, and a
// '#' at the start of a word begins a comment.
[[nodiscard]] std::vector<std::string> split_line(std::string_view line);

[[nodiscard]] bool needs_target(const Command& command);

// "odoloc 0.1.0 (register map: ...)": --version.
[[nodiscard]] std::string version_text();

// On the simulated board: UsageError for a command that asks for more
// simulated time than limit.max (a wait, a watch's interval or its
// interval × (count − 1)). A watch without --count is bounded by Ctrl-C.
void check_simulated(const Command& command, const SimulatedLimit& limit);

// Runs one command other than ScriptCommand. `target` may be null for
// commands that need none. With `json`, prints exactly one JSON document per
// line (watch: one per sample). `stop` set (Ctrl-C) ends a watch or a wait
// promptly by throwing Interrupted.
void execute(const Command& command, Target* target, std::ostream& out, bool json,
             const std::atomic<bool>* stop = nullptr);

}  // namespace odoloc::cli
