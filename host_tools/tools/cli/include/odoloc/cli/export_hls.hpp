// `odoloc export-hls` (docs/hls.md#export): the HLS kernels as standalone
// trees for Vitis HLS, Catapult or Intel HLS. No target: it writes files only.
#pragma once

#include <atomic>
#include <iosfwd>
#include <string>
#include <vector>

#include "odoloc/hls_export/export.hpp"

namespace odoloc::cli {

struct ExportHlsCommand {
  hls_export::ExportRequest request;
};

// The --tool value; UsageError for an unknown tool.
[[nodiscard]] hls_export::HlsTool parse_hls_tool(const std::string& name);

// Writes the trees and one line (or JSON object) per tree. A bad request is a
// UsageError, a failed write a FileError, a signal (`stop`) Interrupted;
// either way nothing is left behind.
void run_export_hls(const ExportHlsCommand& command, std::ostream& out, bool json,
                    const std::atomic<bool>* stop);

}  // namespace odoloc::cli
