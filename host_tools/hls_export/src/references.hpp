// The per-kernel references (one source file each), for the registry in
// kernels.cpp.
#pragma once

#include <cstdint>
#include <memory>

#include "odoloc/hls_export/reference.hpp"

namespace odoloc::hls_export {

std::unique_ptr<Reference> make_cordic_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_tof_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_odometry_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_regfile_reference(std::uint64_t seed);
std::unique_ptr<Reference> make_eppm_reference(std::uint64_t seed);

}  // namespace odoloc::hls_export
