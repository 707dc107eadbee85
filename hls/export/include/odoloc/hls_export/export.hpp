// `odoloc export-hls` (docs/hls.md#export): one standalone tree per kernel,
// the way vendor example folders look:
//
//   OUT/<kernel>/kernel.h            types and the top function's prototype
//                                    (the kernel header with every odoloc
//                                    header it includes, inlined)
//                kernel.cpp          the top function
//                kernel_test.cpp     C-simulation testbench: 0 on success
//                golden_vectors.txt  inputs and outputs per call, from the cycle model
//                run_hls.tcl + hls_config.cfg | run_catapult.tcl | Makefile   the tool's flow
//                README.md
//
// No file includes anything outside its tree except the vendor's type header
// (ap_int.h, ac_int.h) and the C/C++ standard library.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace odoloc::hls_export {

enum class HlsTool : std::uint8_t { kVitis, kCatapult, kIntel };

// "vitis", "catapult", "intel"; nullopt for anything else.
[[nodiscard]] std::optional<HlsTool> parse_tool(std::string_view name);
[[nodiscard]] std::string_view tool_name(HlsTool tool);

struct ExportRequest {
  std::filesystem::path out;         // its parent folder must exist
  std::vector<std::string> kernels;  // empty: every kernel
  HlsTool tool = HlsTool::kVitis;
  // OUT may already hold files: each exported kernel's folder is replaced,
  // anything else in OUT is left alone. Without it OUT must be absent or empty.
  bool force = false;
};

// What went wrong, in one line. usage: the request itself (unknown kernel,
// OUT not empty, OUT's parent missing, OUT not a folder); else a file system
// error while writing. Either way OUT is as it was before the call.
class ExportError : public std::runtime_error {
 public:
  ExportError(bool usage, const std::string& what) : std::runtime_error(what), usage_(usage) {}
  [[nodiscard]] bool usage() const { return usage_; }

 private:
  bool usage_;
};

struct ExportedTree {
  std::string kernel;
  std::filesystem::path folder;
  std::vector<std::string> files;
  std::int64_t golden_calls = 0;
};

// Writes every tree into a staging folder first and moves each into place
// only when all are complete. OUT may be a symbolic link to a folder (the
// trees go into the folder); a link to nothing, and with `force` a kernel's
// folder in OUT that is a link, are refused (replacing them would lose the
// link). Throws ExportError; process::Interrupted when `stop` is set
// (checked before each kernel and each file): OUT is then as it was.
std::vector<ExportedTree> export_hls(const ExportRequest& request,
                                     const std::atomic<bool>* stop = nullptr);

// The source under this key (embedded.hpp) with every "odoloc/..." include
// it makes inlined, each file once, in include order. Throws ExportError for
// an include of the project that is not embedded.
[[nodiscard]] std::string flatten(std::string_view key);

}  // namespace odoloc::hls_export
