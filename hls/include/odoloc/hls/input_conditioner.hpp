// The input conditioner of asynchronous pins (rtl/input_conditioner.hpp,
// docs/eppm.md "Input conditioning and latency") in odoloc::hls types: two
// synchroniser flops, then per line a level filter. One piece of logic for
// the EPPM's A/B pair and the TOF unit's comparators and sync input, as in
// the model. C++14.
//
// Per line, a count of consecutive samples differing from the filtered level;
// the new level is taken on the N-th such sample (N = max(filter_clocks, 1))
// and a sample equal to the filtered level restarts the count.
#pragma once

#include "odoloc/hls/types.hpp"

// Loop labels name the loops in the HLS tools' reports; GCC calls them unused.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-label"

namespace odoloc {
namespace hls {

// rtl::InputConditionerRegs<Lines>: lines packed, line i in bit i.
template <int Lines, int FilterBits>
struct InputConditioner {
  using Pins = uint<Lines>;
  using FilterClocks = uint<FilterBits>;
  struct Line {
    uint<FilterBits> stable = 0;  // consecutive samples differing from `filtered`
  };
  uint<Lines> sync1 = 0, sync2 = 0, filtered = 0;
  Line line[Lines];  // a struct per line: `= {}` would not zero ap_int elements
};

// One clock: the next conditioner `n` from the current `r` and the pins.
template <int Lines, int FilterBits>
inline void condition(
    InputConditioner<Lines, FilterBits>& n, const InputConditioner<Lines, FilterBits>& r,
    const typename InputConditioner<Lines, FilterBits>::Pins& pins,
    const typename InputConditioner<Lines, FilterBits>::FilterClocks& filter_clocks) {
#pragma HLS inline
  n.sync1 = pins;
  n.sync2 = r.sync1;
  uint<Lines> filtered = 0;
line_loop:
  for (int l = 0; l < Lines; ++l) {
#pragma HLS unroll
    const bool sample = bit(r.sync2, l);
    bool level = bit(r.filtered, l);
    if (sample == level) {
      n.line[l].stable = 0;
    } else {
      const uint<FilterBits + 1> seen = r.line[l].stable + 1;
      if (seen >= filter_clocks) {
        level = sample;
        n.line[l].stable = 0;
      } else {
        n.line[l].stable = seen;  // seen < N <= 2^FilterBits - 1
      }
    }
    const uint<Lines> one = 1;
    if (level)
      filtered = filtered | (one << l);
  }
  n.filtered = filtered;
}

}  // namespace hls
}  // namespace odoloc

#pragma GCC diagnostic pop
