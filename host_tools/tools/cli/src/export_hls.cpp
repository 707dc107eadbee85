#include "odoloc/cli/export_hls.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <ostream>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/output/printable.hpp"

namespace odoloc::cli {

hls_export::HlsTool parse_hls_tool(const std::string& name) {
  const auto tool = hls_export::parse_tool(name);
  if (!tool)
    throw UsageError(
        fmt::format("export-hls: unknown --tool '{}'; expected vitis, catapult or intel", name));
  return *tool;
}

void run_export_hls(const ExportHlsCommand& command, std::ostream& out, bool json,
                    const std::atomic<bool>* stop) {
  const std::vector<hls_export::ExportedTree> trees = translated<hls_export::ExportError>(
      [&] { return hls_export::export_hls(command.request, stop); });
  for (const hls_export::ExportedTree& tree : trees) {
    if (json) {
      out << json_line(nlohmann::json{{"kernel", tree.kernel},
                                      {"folder", tree.folder.string()},
                                      {"files", tree.files},
                                      {"golden_calls", tree.golden_calls}})
          << '\n';
    } else {
      out << fmt::format("{}: {} ({}, {} golden calls)\n", tree.kernel,
                         output::printable(tree.folder.string()), fmt::join(tree.files, " "),
                         tree.golden_calls);
    }
  }
}

}  // namespace odoloc::cli
