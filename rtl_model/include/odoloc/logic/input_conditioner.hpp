// Input conditioning of asynchronous pins, written once (docs/hls.md, "One
// source per block"): two synchroniser flops, then a level filter per line.
// One piece of logic for every pin bank of the fabric: the EPPM's A/B pair
// (docs/eppm.md) and the ultrasonic comparators and sync input of the TOF
// capture unit (docs/tof-capture.md). The cycle model (rtl/input_conditioner.hpp)
// runs it with the model's types, the EPPM and TOF kernels with the vendor's.
//
// Per line, a counter of consecutive samples whose level differs from the
// filtered level; the new level is taken on the N-th such sample (N =
// max(filter_clocks, 1)) and any sample equal to the filtered level restarts
// the count. A pulse of N clocks passes, one of N-1 clocks is rejected. A pin
// change first applied in clock t reaches `filtered` at the edge ending clock
// t+N+1 (docs/eppm.md, "Input conditioning and latency").
// C++14, no heap, no containers, static loop bounds (int_family.hpp).
#pragma once

#include "odoloc/logic/int_family.hpp"

namespace odoloc {
namespace logic {
namespace conditioner {

constexpr int kFilterBits = 8;  // filter_clocks and the per-line counter

// A struct per line, not an array of integers: `= {}` leaves ap_int
// elements undefined, a member initialiser does not.
template <class F>
struct Line {
  uint<F, kFilterBits> stable{0};  // consecutive samples differing from `filtered`
};

// Lines travel packed, line i in bit i.
template <class F, int Lines>
struct Regs {
  uint<F, Lines> sync1{0}, sync2{0}, filtered{0};
  Line<F> line[Lines];
};

template <class F, int Lines>
struct In {
  uint<F, Lines> pins{0};
  uint<F, kFilterBits> filter_clocks{0};
  uint<F, 1> reset{0};  // synchronous
};

template <class F, int Lines>
struct InputConditioner {
  using R = Regs<F, Lines>;
  using Stable = uint<F, kFilterBits>;

  // One fabric clock: the registers after this clock's edge.
  static R next(const R& r, const In<F, Lines>& in) {
    if (!is_zero(in.reset))
      return R();
    R n;
    n.sync1 = in.pins;
    n.sync2 = r.sync1;
    long long filtered = 0;
    // Unrolled by the HLS tools: a loop inside the pipelined top function.
    for (int l = 0; l < Lines; ++l) {
      const bool sample = (to_s64(r.sync2) >> l & 1) != 0;
      bool level = (to_s64(r.filtered) >> l & 1) != 0;
      // A sample equal to the filtered level restarts the count; the N-th
      // consecutive differing one (N <= 1: the first) is taken.
      if (sample == level) {
        n.line[l].stable = Stable(0);
      } else {
        const uint<F, kFilterBits + 1> seen = r.line[l].stable + uint<F, 1>(1);
        if (seen >= in.filter_clocks) {
          level = sample;
          n.line[l].stable = Stable(0);
        } else {
          n.line[l].stable = wrap<Stable>(seen);  // seen < N <= 255
        }
      }
      if (level)
        filtered |= 1LL << l;
    }
    n.filtered = wrap<uint<F, Lines> >(filtered);
    return n;
  }
};

}  // namespace conditioner
}  // namespace logic
}  // namespace odoloc
