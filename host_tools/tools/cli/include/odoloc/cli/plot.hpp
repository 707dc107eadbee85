// `odoloc plot` (docs/host-tool.md#plots-of-an-lcm-log-plot): the
// trajectories and errors of an LCM event log (a simulator's run, ODOLOC_TRUTH
// against every pose source and the beacon fixes) as one PNG drawn by
// gnuplot, and a summary per source. No target: it reads a file only.
#pragma once

#include <atomic>
#include <iosfwd>
#include <string>
#include <string_view>

namespace odoloc::cli {

struct PlotCommand {
  std::string log;             // the LCM event log
  std::string out;             // the PNG; empty: the log with extension .png
  double ellipse_every_s = 1;  // s between the fused estimate's drawn ellipses
  bool keep_script = false;    // keep the gnuplot script next to the PNG (.gp)
};

// The --ellipse-every value: a positive finite number of seconds; UsageError
// otherwise.
[[nodiscard]] double parse_ellipse_every(std::string_view text);

// Reads the log and prints its summary (a table, or with `json` one JSON
// object after drawing), then draws the picture and says where it is. A log
// that is missing or not a log, or a picture that would replace it, is a
// UsageError; a script that cannot be written or gnuplot missing or failing
// is a FileError; Interrupted when `stop` is set while gnuplot draws
// (nothing is written).
void run_plot(const PlotCommand& command, std::ostream& out, bool json,
              const std::atomic<bool>* stop);

}  // namespace odoloc::cli
