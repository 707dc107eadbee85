// The HLS kernels' fixed-width integers: odoloc::hls::uint<W> and sint<W>.
//
// ODOLOC_HLS_TYPES picks the family:
//   1  Xilinx ap_int.h   (Vitis HLS):            ap_uint<W>, ap_int<W>
//   2  ac_int.h          (Catapult, Intel HLS):  ac_int<W, false>, ac_int<W, true>
//   0  the project's own (own_int.hpp)
// Unset: ap_int.h when the include path has it, else ac_int.h, else the own.
// One rule the kernels keep because the families differ there: a left shift
// stays within its operand's width in ap_int and ac_int (it grows in the
// own type), so a value is assigned to its wider type before shifting left.
// C++14 throughout, the newest standard every HLS front end accepts.
// The three give the same results on the kernels (test_hls_types, and the
// export test builds every kernel with each). Bit access and the value as a
// host integer go through bits<Hi, Lo>(x), bit(x, i) and to_s64(x), which each
// family spells differently.
#pragma once

#ifndef ODOLOC_HLS_TYPES
#if defined(__INTELFPGA_COMPILER__)
#define ODOLOC_HLS_TYPES 2
#elif __has_include(<ap_int.h>)
#define ODOLOC_HLS_TYPES 1
#elif __has_include(<ac_int.h>)
#define ODOLOC_HLS_TYPES 2
#else
#define ODOLOC_HLS_TYPES 0
#endif
#endif

#include <type_traits>

#include "odoloc/logic/int_family.hpp"

#if ODOLOC_HLS_TYPES == 1
#include <ap_int.h>
#elif ODOLOC_HLS_TYPES == 2 && defined(__INTELFPGA_COMPILER__)
#include "HLS/ac_int.h"
#elif ODOLOC_HLS_TYPES == 2
#include <ac_int.h>
#elif ODOLOC_HLS_TYPES == 0
#include "odoloc/hls/own_int.hpp"
#else
#error "ODOLOC_HLS_TYPES must be 0 (own), 1 (ap_int.h) or 2 (ac_int.h)"
#endif

// A top function is an Intel HLS `component`; Vitis HLS and Catapult take
// theirs from the script (set_top) or a pragma (hls_design top).
#if defined(__INTELFPGA_COMPILER__)
#include "HLS/hls.h"
#define ODOLOC_HLS_TOP component
#else
#define ODOLOC_HLS_TOP
#endif

namespace odoloc {
namespace hls {

#if ODOLOC_HLS_TYPES == 1
constexpr const char* kTypeFamily = "ap_int.h";
template <int W>
using uint = ap_uint<W>;
template <int W>
using sint = ap_int<W>;
template <int Hi, int Lo, int W, bool S>
inline uint<Hi - Lo + 1> bits(const ap_int_base<W, S>& x) {
  return x.range(Hi, Lo);
}
template <int W, bool S>
inline bool bit(const ap_int_base<W, S>& x, int i) {
  return x[i];
}
template <int W, bool S>
inline long long to_s64(const ap_int_base<W, S>& x) {
  return x.to_int64();
}
#elif ODOLOC_HLS_TYPES == 2
constexpr const char* kTypeFamily = "ac_int.h";
template <int W>
using uint = ac_int<W, false>;
template <int W>
using sint = ac_int<W, true>;
template <int Hi, int Lo, int W, bool S>
inline uint<Hi - Lo + 1> bits(const ac_int<W, S>& x) {
  return x.template slc<Hi - Lo + 1>(Lo);
}
template <int W, bool S>
inline bool bit(const ac_int<W, S>& x, int i) {
  return x[i];
}
template <int W, bool S>
inline long long to_s64(const ac_int<W, S>& x) {
  return x.to_int64();
}
#else
constexpr const char* kTypeFamily = "own_int.hpp";
template <int W>
using uint = own::uint<W>;
template <int W>
using sint = own::sint<W>;
using own::bit;
using own::bits;
using own::to_s64;
#endif

// The selected family for the blocks' logic (logic/int_family.hpp).
struct Family {
  template <int W>
  using uint = hls::uint<W>;
  template <int W>
  using sint = hls::sint<W>;
};

namespace detail {
// What logic/int_family.hpp asks of each named type, in this family's terms.
template <class T, int W, bool Signed>
struct VendorTraits {
  using family = Family;
  static const int width = W;
  template <class From>
  static T wrap(const From& v) {
    return T(v);  // every family wraps on construction
  }
  static long long to_s64(const T& v) { return hls::to_s64(v); }
  template <int Hi, int Lo>
  static uint<Hi - Lo + 1> bits(const T& v) {
    return hls::bits<Hi, Lo>(v);
  }
  template <int N>
  static typename std::conditional<Signed, sint<W + N>, uint<W + N> >::type shl(const T& v) {
    typedef typename std::conditional<Signed, sint<W + N>, uint<W + N> >::type Wider;
    const Wider widened = v;  // ap_int and ac_int shift within the operand's width
    return Wider(widened * (1LL << N));
  }
  template <int N>
  static T shr(const T& v) {
    return T(v >> N);
  }
  template <class A>
  static T shr_by(const T& v, const A& amount) {
    return T(v >> amount);
  }
  template <class L>
  static uint<W + logic::IntTraits<L>::width> cat(const T& high, const L& low) {
    return logic::generic_cat(high, low);
  }
};
}  // namespace detail

}  // namespace hls

namespace logic {
template <int W>
struct IntTraits<hls::uint<W> > : hls::detail::VendorTraits<hls::uint<W>, W, false> {};
template <int W>
struct IntTraits<hls::sint<W> > : hls::detail::VendorTraits<hls::sint<W>, W, true> {};
}  // namespace logic

}  // namespace odoloc
