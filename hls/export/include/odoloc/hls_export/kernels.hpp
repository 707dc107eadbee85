// The HLS kernels as `odoloc export-hls` and the tests know them: names,
// headers, top functions, and each one's reference (the model and stimulus
// of odoloc/verification/, whose calls are the golden vectors).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "odoloc/verification/reference.hpp"

namespace odoloc::hls_export {

using verification::Reference;

// What a kernel is: the names the export and the tests use.
struct KernelDescription {
  std::string_view name;        // --kernel NAME, and the tree's folder name
  std::string_view top;         // the top function (global namespace)
  std::string_view header;      // the kernel header, as included: odoloc/hls/..._kernel.hpp
  std::string_view top_source;  // the top function's source in hls/src/
  std::string_view space;       // the kernel's namespace: Inputs, Outputs, Registers, step
  std::string_view call;        // "one fabric clock" or "one SPI transaction"
  std::string_view summary;     // one line for the README
  std::int64_t golden_calls;    // calls in the exported golden vectors
  std::unique_ptr<Reference> (*make_reference)(std::uint64_t seed);
};

// Every kernel, in export order.
[[nodiscard]] std::span<const KernelDescription> kernels();
// The kernel of this name, or nullptr.
[[nodiscard]] const KernelDescription* find_kernel(std::string_view name);

}  // namespace odoloc::hls_export
