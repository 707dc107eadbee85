// The sequential rotation-mode CORDIC as an HLS kernel: one call = one fabric
// clock of rtl::SequentialCordic (docs/cordic.md), in odoloc::hls integer
// types (types.hpp: ap_int.h, ac_int.h or the project's own).
//
// Ports (per call): load, angle (16-bit binary angle), clear_flags, reset in;
// the registers out through `regs` (busy, ready, load_ignored, sin, cos with
// 14 fractional bits). A LOAD while idle starts 16 micro-rotations, one per
// call; the result is valid from the call after the last (ready).
//
// The formats, the arctangent table and x0 are the model's own constants
// (rtl/cordic_core.hpp, generated at compile time), so the kernel cannot
// drift from them; test_hls_cordic_* proves the datapath bit-identical over
// all 65536 angles and clock by clock under random stimulus, per type family.
// No heap, no containers, no floating point, static loop bounds.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/rtl/cordic_core.hpp"

namespace odoloc::hls::cordic {

namespace core = rtl::cordic;

using Angle = uint<core::kAngleBits>;
using Xy = sint<core::Xy::width>;
using Z = sint<core::Z::width>;
using Output = sint<core::Output::width>;

struct Registers {
  Xy x = 0, y = 0;
  Z z = 0;
  uint<2> quadrant = 0;
  uint<4> iteration = 0;  // the next micro-rotation
  uint<1> busy = 0, ready = 0, load_ignored = 0;
  Output sin = 0, cos = 0;
};

// Quadrant pre-rotation: angle = quadrant * 90 deg + residual in [-45, 45).
inline void load(Registers& n, Angle angle) {
  constexpr int kEighth = 1 << (core::kAngleBits - 3);
  const Angle shifted = angle + kEighth;
  n.quadrant = bits<core::kAngleBits - 1, core::kAngleBits - 2>(shifted);
  const sint<core::kAngleBits> residual = bits<core::kAngleBits - 3, 0>(shifted) - kEighth;
  const Z widened = residual;  // ap_int and ac_int shift within the operand's width
  n.z = widened << core::kAngleGuardBits;
  n.x = core::kX0.value();
  n.y = 0;
}

// Micro-rotation k (shift kFirstShift + k) toward z = 0.
inline void iterate(Registers& n, const Registers& r) {
  const auto k = static_cast<int>(to_s64(r.iteration));
  const int shift = core::kFirstShift + k;
  const Xy dx = r.y >> shift;
  const Xy dy = r.x >> shift;
  const Z angle = core::kAtan.units[k];
  if (r.z < 0) {
    n.x = r.x + dx;
    n.y = r.y - dy;
    n.z = r.z + angle;
  } else {
    n.x = r.x - dx;
    n.y = r.y + dy;
    n.z = r.z - angle;
  }
}

// Round to nearest (half up) into 14 fractional bits, undo the pre-rotation.
inline void finish(Registers& n) {
  constexpr int kHalf = 1 << (core::kGuardBits - 1);
  const Output c = (n.x + kHalf) >> core::kGuardBits;
  const Output v = (n.y + kHalf) >> core::kGuardBits;
  const Output minus_c = -c;
  const Output minus_v = -v;
  switch (to_s64(n.quadrant)) {
    case 1:
      n.sin = c;
      n.cos = minus_v;
      break;
    case 2:
      n.sin = minus_v;
      n.cos = minus_c;
      break;
    case 3:
      n.sin = minus_c;
      n.cos = v;
      break;
    default:
      n.sin = v;
      n.cos = c;
      break;
  }
}

// One fabric clock: the next registers from the current ones and the
// inputs, then the commit (`regs` is the register bank).
inline void sequential_cordic(Registers& regs, bool load_in, Angle angle, bool clear_flags,
                              bool reset) {
#pragma HLS pipeline II = 1
#pragma HLS inline
  const Registers r = regs;
  Registers n = r;
  if (reset) {
    n = Registers{};
  } else {
    if (clear_flags)
      n.load_ignored = 0;
    if (r.busy == 1) {
      if (load_in)
        n.load_ignored = 1;
      iterate(n, r);
      n.iteration = r.iteration + 1;
      if (to_s64(r.iteration) == core::kIterations - 1) {
        n.busy = 0;
        n.ready = 1;
        finish(n);
      }
    } else if (load_in) {
      load(n, angle);
      n.iteration = 0;
      n.busy = 1;
      n.ready = 0;
    }
  }
  regs = n;
}

}  // namespace odoloc::hls::cordic
