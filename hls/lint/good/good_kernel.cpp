// Rule sample for hls_lint.py: a kernel every rule accepts (no `expect:`
// line, so the lint must report nothing). One call is one clock of an 8-tap
// FIR filter with a peak detector, in the shapes the lint accepts:
// fixed-width types, bounded labelled loops, a coefficient table generated
// at compile time in long double.
#include "odoloc/hls/types.hpp"

namespace odoloc {
namespace hls {
namespace lint_sample {

constexpr int kTaps = 8;
constexpr int kCoefficientBits = 12;

// Floating point and a while loop, run by the compiler only: allowed.
struct Coefficients {
  int q[kTaps];
};
constexpr long double kDecay = 0.75L;
constexpr Coefficients make_coefficients() {
  Coefficients c{};
  long double weight = 1.0L;
  int k = 0;
  while (k < kTaps) {
    c.q[k] = static_cast<int>(weight * (1 << (kCoefficientBits - 1)) + 0.5L);
    weight *= kDecay;
    ++k;
  }
  return c;
}
constexpr Coefficients kCoefficients = make_coefficients();

struct State {
  sint<16> taps[kTaps] = {};
};

// The trip count is a template parameter: a compile-time constant.
template <int N>
inline sint<32> dot(const sint<16> (&x)[N]) {
  sint<32> acc = 0;
mac:
  for (int k = 0; k < N; ++k) {
#pragma HLS unroll
    acc += x[k] * kCoefficients.q[k];
  }
  return acc;
}

inline void clear(State& state) {
  for (sint<16>& tap : state.taps)  // a range-for over a fixed-size array
    tap = 0;
}

inline sint<32> fir(State& state, sint<16> sample, sint<16>& peak) {
#pragma HLS pipeline II = 1
shift:
  for (int k = kTaps - 1; k > 0; --k) {
#pragma HLS unroll
    state.taps[k] = state.taps[k - 1];
  }
  state.taps[0] = sample;
  sint<16> largest = state.taps[0];
scan:
  for (uint<4> k = 1; k < kTaps; ++k) {  // a fixed-width counter
    const sint<16> tap = state.taps[to_s64(k)];
    if (tap > largest)
      largest = tap;
  }
  peak = largest;
  return dot(state.taps);
}

}  // namespace lint_sample
}  // namespace hls
}  // namespace odoloc

ODOLOC_HLS_TOP void good_kernel_top(odoloc::hls::sint<16> sample, bool reset,
                                    odoloc::hls::sint<32>& out, odoloc::hls::sint<16>& peak) {
#pragma HLS interface mode = ap_ctrl_none port = return
#pragma HLS pipeline II = 1
  static odoloc::hls::lint_sample::State state;
  if (reset)
    odoloc::hls::lint_sample::clear(state);
  out = odoloc::hls::lint_sample::fir(state, sample, peak);
}
