#include "odoloc/process/gnuplot.hpp"

#include <fmt/format.h>

#include <optional>

#include "odoloc/output/output_file.hpp"
#include "odoloc/output/printable.hpp"

namespace odoloc::process {

namespace fs = std::filesystem;

std::string gnuplot_string(std::string_view text) {
  std::string out = "'";
  for (const char c : output::printable(text)) {
    if (c == '\'')
      out += '\'';
    out += c;
  }
  return out + '\'';
}

std::string gnuplot_output(std::string_view file_name) {
  return fmt::format("if (!exists(\"picture\")) picture = {}\nset output picture\n",
                     gnuplot_string(file_name));
}

ProgramResult draw_with_gnuplot(const std::string& script, const fs::path& picture,
                                const fs::path& keep_script, const std::atomic<bool>* stop) {
  // The outputs are checked first: a folder or a link to nothing is refused
  // before gnuplot runs.
  output::OutputFile picture_file(picture);
  std::optional<output::OutputFile> script_file;
  if (!keep_script.empty())
    script_file.emplace(keep_script);
  const output::Staging staging(fs::temp_directory_path(), "gnuplot");
  // The staged picture keeps the extension: some scripts choose the
  // terminal by it.
  const std::string staged = "picture" + picture.extension().string();
  output::write_file(staging.dir() / "script.gp", script);
  ProgramResult result = run_program(
      "gnuplot", {"-e", fmt::format("picture = {}", gnuplot_string(staged)), "script.gp"},
      staging.dir(), stop);
  if (!result.ok())
    return result;
  std::error_code ec;
  if (!fs::is_regular_file(staging.dir() / staged, ec)) {
    result.exit_status = 1;
    result.message = "gnuplot exited 0 without drawing the picture";
    return result;
  }
  picture_file.commit_from(staging.dir() / staged);
  if (script_file) {
    script_file->out() << script;
    script_file->commit();
  }
  return result;
}

}  // namespace odoloc::process
