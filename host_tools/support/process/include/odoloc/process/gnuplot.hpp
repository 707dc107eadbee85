// Driving gnuplot with text it must take as data: file names, titles and
// labels from the command line, a log, a spec or the network.
#pragma once

#include <atomic>
#include <filesystem>
#include <string>
#include <string_view>

#include "odoloc/process/run_program.hpp"

namespace odoloc::process {

// A gnuplot string constant whose value shows `text` and that can do nothing
// else. Single-quoted: gnuplot runs backquoted commands inside double
// quotes, expands macros (@name) in neither, and takes a backslash in single
// quotes as itself; a single quote is doubled. The text is first made
// printable (output::printable), so a line break, which would end the
// command and start another, is shown as \x0a, as is any byte that is not
// well-formed UTF-8. Checked against gnuplot itself (test_gnuplot_text).
std::string gnuplot_string(std::string_view text);

// The script lines that send a picture to the gnuplot variable `picture`,
// defaulting to `file_name`: run alone in the picture's folder
// (`gnuplot SCRIPT`) the script draws `file_name` again; the tools set
// `picture` on gnuplot's command line to a fixed name in a staging folder,
// so the user's path reaches gnuplot only as that default's string.
std::string gnuplot_output(std::string_view file_name);

// Draws `script` (which sends its picture to gnuplot_output()) with gnuplot
// in a private staging folder, into the output `picture` (output::OutputFile:
// a file appears whole, a device or FIFO receives the picture as a stream, a
// symbolic link is followed) and, when `keep_script` is not empty, writes
// the script there too. Returns gnuplot's result: not launched, interrupted
// by `stop` (gnuplot is ended; nothing is written), failed, or, when gnuplot
// succeeded without drawing, a failure with that message. Throws
// output::OutputError when an output cannot be written.
ProgramResult draw_with_gnuplot(const std::string& script, const std::filesystem::path& picture,
                                const std::filesystem::path& keep_script,
                                const std::atomic<bool>* stop);

}  // namespace odoloc::process
