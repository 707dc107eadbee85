// The cycle model behind each HLS kernel's ports: what the golden vectors of
// `odoloc export-hls` are made of and what the bit-identity tests compare the
// kernels with (docs/hls.md). Host side (C++20): it runs rtl_model/, which
// the kernels themselves never include.
//
// A kernel's ports are its Inputs and Outputs structs (hls/include/odoloc/
// hls/<name>_kernel.hpp, field lists in visit_fields order). Here a call's
// ports travel as rows of int64, one value per field in that order: unsigned
// fields as their value, signed ones as their two's-complement value.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

namespace odoloc::hls_export {

// One kernel's model and its seeded random stimulus.
class Reference {
 public:
  virtual ~Reference() = default;
  // Field names, in the kernel's visit_fields order.
  [[nodiscard]] virtual std::span<const std::string_view> input_names() const = 0;
  [[nodiscard]] virtual std::span<const std::string_view> output_names() const = 0;
  // The next call's inputs, drawn from the stimulus (deterministic per seed).
  virtual void stimulus(std::span<std::int64_t> inputs) = 0;
  // One call of the model with these inputs (as the kernel would see them);
  // the outputs the kernel must produce for it.
  virtual void step(std::span<const std::int64_t> inputs, std::span<std::int64_t> outputs) = 0;
};

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
