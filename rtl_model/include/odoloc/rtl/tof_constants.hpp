// The TOF capture unit's parameters and register widths, in one place for the
// cycle model (tof_capture.hpp, which static_asserts its register types
// against them) and the HLS kernel (hls/tof_kernel.hpp). Plain C++14 with
// integer results only, because HLS front ends accept C++14 and the kernel
// may not include the model's other headers.
#pragma once

namespace odoloc {
namespace rtl {
namespace tof_capture {

constexpr int kChannels = 8;   // receivers of the chip's unit (tof_channel.rx0..rx7)
constexpr int kDepthBits = 4;  // the chip's event FIFOs: 16 entries each
constexpr int kDepth = 1 << kDepthBits;
constexpr int kWindow = 8;     // entries the register window shows (entry0..entry7)
constexpr int kHeadBits = 5;   // FIFO head register (oldest entry, mod kDepth)
constexpr int kLevelBits = 6;  // FIFO level and snapshot level (0..32)
constexpr int kPopBits = 4;    // entries one read frame pops (the register file's port)
constexpr int kTimestampBits = 32;
constexpr int kPrescaleBits = 16;
constexpr int kEpochBits = 23;      // the epoch strobe: timestamp bits 22:0 roll over
constexpr int kEpochCountBits = 2;  // epochs seen by a pulse in progress, saturating at 3
constexpr int kWidthBits = 24;      // pulse width in ticks, saturating
constexpr int kEdgeIndexBits = 7;   // carrier entry: edges recorded before this one, saturating
constexpr int kEdgeCountBits = 8;   // carrier mode: edges recorded since arming, saturating
constexpr int kCounterBits = 16;    // events.dropped, events.ignored: saturating
constexpr int kFilterBits = 8;      // tof.cfg.filter_clocks and the filter's per-line counter
constexpr int kModeEnvelope = 0;    // tof_channel.rxI.cfg.mode encodings
constexpr int kModeCarrier = 1;

}  // namespace tof_capture
}  // namespace rtl
}  // namespace odoloc
