// The sequential rotation-mode CORDIC as an HLS kernel: one call = one fabric
// clock of rtl::SequentialCordic (docs/cordic.md), in odoloc::hls integer
// types (types.hpp: ap_int.h, ac_int.h or the project's own). C++14.
//
// Ports (Inputs, per call): load, angle (16-bit binary angle, 65536 = one
// turn), clear_flags (clears load_ignored), reset (synchronous). Outputs, the
// registers after this clock's edge: busy, ready, load_ignored, sin and cos
// (16 bits, 14 fractional, round to nearest). A LOAD while idle starts 16
// micro-rotations, one per call; ready and the result come with the 16th call
// after it. A LOAD while busy sets load_ignored.
//
// The formats, the arctangent table and x0 are the model's own constants
// (rtl/cordic_constants.hpp, generated at compile time), so the kernel cannot
// drift from them; test_hls_cordic_* proves the datapath bit-identical over
// all 65536 angles and clock by clock under random stimulus, per type family.
// No heap, no containers, no floating point, static loop bounds.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/rtl/cordic_constants.hpp"

namespace odoloc {
namespace hls {
namespace cordic {

namespace core = rtl::cordic;

using Angle = uint<core::kAngleBits>;
using Xy = sint<core::kXyFractionBits + 2>;  // sign, one integer bit
using Z = sint<core::kZUnitsBits - 1>;       // |z| < 2^20 units of 2^-22 turn
using Output = sint<core::kOutputFractionBits + 2>;

// Every field starts at 0: ap_int's default constructor leaves the value
// undefined, so a port struct without initialisers differs between families.
struct Inputs {
  uint<1> load = 0;
  Angle angle = 0;
  uint<1> clear_flags = 0;
  uint<1> reset = 0;
};

struct Outputs {
  uint<1> busy = 0, ready = 0, load_ignored = 0;
  Output sin = 0, cos = 0;
};

struct Registers {
  Xy x = 0, y = 0;
  Z z = 0;
  uint<2> quadrant = 0;
  uint<4> iteration = 0;  // the next micro-rotation
  uint<1> busy = 0, ready = 0, load_ignored = 0;
  Output sin = 0, cos = 0;
};

// The ports by name, in the golden vectors' column order (testbenches only).
template <class Visit>
void visit_fields(Inputs& s, Visit&& v) {
  v("load", s.load);
  v("angle", s.angle);
  v("clear_flags", s.clear_flags);
  v("reset", s.reset);
}
template <class Visit>
void visit_fields(Outputs& s, Visit&& v) {
  v("busy", s.busy);
  v("ready", s.ready);
  v("load_ignored", s.load_ignored);
  v("sin", s.sin);
  v("cos", s.cos);
}

// Quadrant pre-rotation: angle = quadrant * 90 deg + residual in [-45, 45).
inline void load(Registers& n, Angle angle) {
  const int kEighth = 1 << (core::kAngleBits - 3);
  const Angle shifted = angle + kEighth;
  n.quadrant = bits<core::kAngleBits - 1, core::kAngleBits - 2>(shifted);
  const sint<core::kAngleBits> residual = bits<core::kAngleBits - 3, 0>(shifted) - kEighth;
  const Z widened = residual;  // ap_int and ac_int shift within the operand's width
  n.z = widened << core::kAngleGuardBits;
  n.x = core::kX0Units;
  n.y = 0;
}

// Micro-rotation k (shift kFirstShift + k) toward z = 0.
inline void iterate(Registers& n, const Registers& r) {
  const int k = static_cast<int>(to_s64(r.iteration));
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
  const int kHalf = 1 << (core::kGuardBits - 1);
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

// One fabric clock: the next registers from the current ones and the inputs,
// then the commit (`regs` is the register bank) and the outputs.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  const Registers r = regs;
  Registers n = r;
  if (in.reset == 1) {
    n = Registers();
  } else {
    if (in.clear_flags == 1)
      n.load_ignored = 0;
    if (r.busy == 1) {
      if (in.load == 1)
        n.load_ignored = 1;
      iterate(n, r);
      n.iteration = r.iteration + 1;
      if (r.iteration == core::kIterations - 1) {
        n.busy = 0;
        n.ready = 1;
        finish(n);
      }
    } else if (in.load == 1) {
      load(n, in.angle);
      n.iteration = 0;
      n.busy = 1;
      n.ready = 0;
    }
  }
  regs = n;
  out.busy = n.busy;
  out.ready = n.ready;
  out.load_ignored = n.load_ignored;
  out.sin = n.sin;
  out.cos = n.cos;
}

}  // namespace cordic
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/cordic_top.cpp): one call = one clock, the
// registers held in the function's static state.
void odoloc_cordic(const odoloc::hls::cordic::Inputs& in, odoloc::hls::cordic::Outputs& out);
