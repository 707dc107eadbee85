// The sequential rotation-mode CORDIC as an HLS kernel: the block's logic
// (logic/cordic.hpp, the file the cycle model runs) in the selected vendor
// types (types.hpp). One call = one fabric clock (docs/cordic.md).
//
// Ports (Inputs, per call): load, angle (16-bit binary angle, 65536 = one
// turn), clear_flags (clears load_ignored), reset (synchronous). Outputs, the
// registers after this clock's edge: busy, ready, load_ignored, sin and cos
// (16 bits, 14 fractional, round to nearest). A LOAD while idle starts 16
// micro-rotations, one per call; ready and the result come with the 16th call
// after it. A LOAD while busy sets load_ignored.
// No heap, no containers, no floating point, static loop bounds.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/logic/cordic.hpp"

namespace odoloc {
namespace hls {
namespace cordic {

using Logic = logic::cordic::Cordic<Family>;
using Inputs = logic::cordic::In<Family>;
using Outputs = logic::cordic::Out<Family>;
using Registers = logic::cordic::Regs<Family>;

// One fabric clock: the registers after this clock's edge (`regs` is the
// register bank), and the outputs.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  regs = Logic::next(regs, in);
  out = Logic::outputs(regs);
}

}  // namespace cordic
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/cordic_top.cpp): one call = one clock, the
// registers held in the function's static state.
void odoloc_cordic(const odoloc::hls::cordic::Inputs& in, odoloc::hls::cordic::Outputs& out);
