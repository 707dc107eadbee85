#include <algorithm>
#include <array>

#include "odoloc/hls_export/reference.hpp"
#include "references.hpp"

namespace odoloc::hls_export {

namespace {
constexpr std::array kKernels{
    KernelDescription{.name = "cordic",
                      .top = "odoloc_cordic",
                      .header = "odoloc/hls/cordic_kernel.hpp",
                      .top_source = "cordic_top.cpp",
                      .space = "odoloc::hls::cordic",
                      .call = "one fabric clock",
                      .summary = "sequential rotation-mode CORDIC, 16 iterations, sin/cos of a "
                                 "16-bit binary angle",
                      .golden_calls = 20000,
                      .make_reference = make_cordic_reference},
};
}  // namespace

std::span<const KernelDescription> kernels() {
  return kKernels;
}

const KernelDescription* find_kernel(std::string_view name) {
  const auto* it = std::ranges::find(kKernels, name, &KernelDescription::name);
  return it == kKernels.end() ? nullptr : it;
}

}  // namespace odoloc::hls_export
