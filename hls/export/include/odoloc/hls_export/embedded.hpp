// The HLS sources built into the tool (cmake/EmbedFiles.cmake), keyed as a
// kernel includes them: "odoloc/hls/types.hpp", "odoloc/rtl/cordic_constants.hpp",
// plus "src/<kernel>_top.cpp" and "testbench/golden_testbench.hpp".
#pragma once

#include <span>
#include <string_view>

namespace odoloc::hls_export {

struct EmbeddedFile {
  std::string_view key;
  std::string_view text;
};

[[nodiscard]] std::span<const EmbeddedFile> hls_sources();

}  // namespace odoloc::hls_export
