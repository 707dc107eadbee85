#include "odoloc/hls_export/kernels.hpp"

#include <algorithm>
#include <array>

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
                      .make_reference = verification::make_cordic_reference},
    KernelDescription{.name = "tof",
                      .top = "odoloc_tof",
                      .header = "odoloc/hls/tof_kernel.hpp",
                      .top_source = "tof_top.cpp",
                      .space = "odoloc::hls::tof",
                      .call = "one fabric clock",
                      .summary = "ultrasonic time-of-flight capture unit: 8 comparator channels "
                                 "and a sync input, timestamps into 16-entry event FIFOs",
                      .golden_calls = 5000,  // 404 columns: 4.4 MB
                      .make_reference = verification::make_tof_reference},
    KernelDescription{.name = "odometry",
                      .top = "odoloc_odometry",
                      .header = "odoloc/hls/odometry_kernel.hpp",
                      .top_source = "odometry_top.cpp",
                      .space = "odoloc::hls::odometry",
                      .call = "one fabric clock",
                      .summary = "odometry datapath: sequencer, shared CORDIC, rear and front "
                                 "units, min-select, pose integrator and report",
                      .golden_calls = 20000,
                      .make_reference = verification::make_odometry_reference},
    KernelDescription{.name = "regfile",
                      .top = "odoloc_regfile",
                      .header = "odoloc/hls/regfile_kernel.hpp",
                      .top_source = "regfile_top.cpp",
                      .space = "odoloc::hls::regfile",
                      .call = "one fabric clock",
                      .summary = "register interface: SPI slave (synchroniser, protocol "
                                 "engine, CRC-8, write buffer) and register file (configuration "
                                 "words, status reads with snapshot, w1c/w1p strobes, rc and rpop)",
                      .golden_calls = 6000,  // 304 columns, 206 of them status words: 14 MB
                      .make_reference = verification::make_regfile_reference},
    KernelDescription{.name = "eppm",
                      .top = "odoloc_eppm",
                      .header = "odoloc/hls/eppm_kernel.hpp",
                      .top_source = "eppm_top.cpp",
                      .space = "odoloc::hls::eppm",
                      .call = "one fabric clock",
                      .summary = "encoder pulse processing module: input conditioner, x4/x2/x1 "
                                 "quadrature decoder, 20-bit position counter, pulse and period "
                                 "speed meters",
                      .golden_calls = 20000,
                      .make_reference = verification::make_eppm_reference},
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
