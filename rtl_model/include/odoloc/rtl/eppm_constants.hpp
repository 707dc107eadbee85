// The EPPM's register widths and port encodings, in one place for the cycle
// model (eppm.hpp, which static_asserts its register types and the register
// map's enumerations against them) and the HLS kernel (hls/eppm_kernel.hpp).
// Plain C++14 with integer results only, because HLS front ends accept C++14
// and the kernel may not include the model's other headers.
#pragma once

namespace odoloc {
namespace rtl {
namespace eppm {

constexpr int kLines = 2;  // the conditioner's lines: A in bit 1, B in bit 0
constexpr int kLineA = 1;
constexpr int kLineB = 0;
constexpr int kFilterBits = 8;       // eppm.cfg.filter_clocks and the filter's per-line counter
constexpr int kErrorCountBits = 16;  // illegal transitions, saturating
constexpr int kCountBits = 20;       // position count and latched increment, two's complement
constexpr int kWindowBits = 23;      // eppm.window.clocks and the window timer
constexpr int kPrescaleBits = 16;    // eppm.prescale.divider and the prescaler
constexpr int kPulseBits = 24;       // signed edges per window, and the speed word's value
constexpr int kPeriodBits = 23;      // reference ticks, saturating; stall_ticks, thresholds
constexpr int kModeBits = 2;         // eppm.cfg.decode_mode and speed_mode_select

// eppm.cfg.decode_mode (3 behaves as x4).
constexpr int kDecodeX4 = 0;
constexpr int kDecodeX2 = 1;
constexpr int kDecodeX1 = 2;
// eppm.cfg.speed_mode_select (0 and 3: automatic).
constexpr int kSelectPulse = 1;
constexpr int kSelectPeriod = 2;
// eppm.speed.mode.
constexpr int kModePeriod = 0;
constexpr int kModePulse = 1;

}  // namespace eppm
}  // namespace rtl
}  // namespace odoloc
