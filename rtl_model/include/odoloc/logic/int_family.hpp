// The integer-type families the blocks' logic is written over (docs/hls.md,
// "One source per block").
//
// Each block's next-state logic (odoloc/logic/<block>.hpp) is written once,
// as templates over a family F, and instantiated twice:
//   - by the cycle model with the model's own types (rtl::Family:
//     rtl::UInt<W>, rtl::SInt<W>, rtl/family.hpp), whose narrowing does not
//     compile, so the logic states every wrap;
//   - by the HLS top functions with the vendor's types (hls::Family:
//     ap_int.h, ac_int.h, or own_int.hpp; hls/types.hpp), which wrap on
//     assignment.
// A family is a struct with the member templates uint<W> and sint<W>, and an
// IntTraits<T> specialisation for each of its named types. The logic uses
// only what both kinds of type agree on:
//   - +, -, * between operands of the same signedness (the result grows:
//     max(Wa, Wb) + 1 bits, Wa + Wb for *), unary minus (W + 1), &, |, ^ of
//     unsigned operands, comparisons between the same signedness; a
//     difference of unsigned values is wrapped before it is compared (its
//     type differs between families: unsigned in the model, signed in ap_int);
//   - the functions below for everything else: wrap<T> (the low bits, two's
//     complement), bits<Hi, Lo> and bit<I>, shl<N> (grows), shr<N> and
//     shr_by (a barrel shifter), both the same width, to_s64 and is_zero, cat;
//   - literals as T(value), in range; a value known only at run time (a bool,
//     a table entry) through wrap<T>, since T(value) checks its range at run
//     time in the model's family.
// C++14, header-only, no heap, no containers: the HLS front ends compile it.
#pragma once

namespace odoloc {
namespace logic {

template <class F, int W>
using uint = typename F::template uint<W>;
template <class F, int W>
using sint = typename F::template sint<W>;

// Specialised by each family for its named types:
//   family                           the family struct
//   width                            W
//   static T wrap(const From& v)     the low W bits of v (any integer of the
//                                    family, or a host integer)
//   static long long to_s64(T v)     the value
//   template <int Hi, int Lo> static uint<family, Hi - Lo + 1> bits(T v)
//   static T shr_by(T v, A amount)   v >> amount, arithmetic for signed
//   template <int N> static T shr(T v)      v >> N, same width
//   template <int N> static auto shl(T v)   v << N in W + N bits
//   template <class L> static auto cat(T high, L low)   {high, low}
//                                    (generic_cat unless the family has a
//                                    faster way)
template <class T>
struct IntTraits;

template <class To, class From>
inline To wrap(const From& v) {
  return IntTraits<To>::wrap(v);
}
template <class T>
inline long long to_s64(const T& v) {
  return IntTraits<T>::to_s64(v);
}
template <class T>
inline bool is_zero(const T& v) {
  return IntTraits<T>::to_s64(v) == 0;
}
template <int Hi, int Lo, class T>
inline uint<typename IntTraits<T>::family, Hi - Lo + 1> bits(const T& v) {
  return IntTraits<T>::template bits<Hi, Lo>(v);
}
template <int I, class T>
inline uint<typename IntTraits<T>::family, 1> bit(const T& v) {
  return IntTraits<T>::template bits<I, I>(v);
}
template <int N, class T>
inline auto shl(const T& v) {
  return IntTraits<T>::template shl<N>(v);
}
template <int N, class T>
inline T shr(const T& v) {
  return IntTraits<T>::template shr<N>(v);
}
template <class T, class A>
inline T shr_by(const T& v, const A& amount) {
  return IntTraits<T>::shr_by(v, amount);
}
// {high, low}: high in the upper bits. A family may spell it itself
// (IntTraits<H>::cat, the model's: one shift and one or).
template <class H, class L>
inline uint<typename IntTraits<H>::family, IntTraits<H>::width + IntTraits<L>::width> cat(
    const H& high, const L& low) {
  return IntTraits<H>::cat(high, low);
}
// cat() of a family without its own: the bits of both through wrap and shl.
template <class H, class L>
inline uint<typename IntTraits<H>::family, IntTraits<H>::width + IntTraits<L>::width> generic_cat(
    const H& high, const L& low) {
  using Result = uint<typename IntTraits<H>::family, IntTraits<H>::width + IntTraits<L>::width>;
  return wrap<Result>(shl<IntTraits<L>::width>(high) | wrap<Result>(low));
}

}  // namespace logic
}  // namespace odoloc
