// Verification of the HLS kernels (docs/hls.md): for each kernel, the cycle
// model behind its ports and a seeded constrained-random stimulus. The
// bit-identity tests (testbenches/hls) replay it through the kernels, and
// `odoloc export-hls` writes its calls as each exported tree's golden vectors.
// Host side (C++20): it runs rtl_model/, which the kernels never include.
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

namespace odoloc::verification {

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

// Each kernel's reference (one source file each, src/<kernel>_reference.cpp).
std::unique_ptr<Reference> make_cordic_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_tof_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_odometry_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_regfile_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_eppm_reference(std::uint64_t seed);

}  // namespace odoloc::verification
