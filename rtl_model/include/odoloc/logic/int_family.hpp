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
  return wrap<Result>(shl<IntTraits<L>::width>(high) |
                      wrap<Result>(bits<IntTraits<L>::width - 1, 0>(low)));
}

// (v + 2^(N-1)) >> N in W + 1 - N bits (W: v's width): round half up, the
// fixed-point "round to nearest" of the datapaths (rtl::round_shr).
template <int N, class T>
inline sint<typename IntTraits<T>::family, IntTraits<T>::width + 1 - N> round_shr(const T& v) {
  using F = typename IntTraits<T>::family;
  using Biased = sint<F, IntTraits<T>::width + 1>;
  const Biased biased = wrap<Biased>(v + sint<F, N + 1>(1LL << (N - 1)));
  return wrap<sint<F, IntTraits<T>::width + 1 - N> >(shr<N>(biased));
}

// v clamped to R's two's complement range (R signed; rtl's sat<N>).
template <class R, class T>
inline R saturate(const T& v) {
  const long long most = (1LL << (IntTraits<R>::width - 1)) - 1;
  if (v > R(most))
    return R(most);
  if (v < R(-most - 1))
    return R(-most - 1);
  return wrap<R>(v);
}

// A 64-bit register as two 32-bit words, high word signed (a 64-bit
// two's complement value) or not: one integer of a family holds at most 63
// bits (hls/own_int.hpp), and a 64-bit accumulator is two 32-bit adders with
// a carry in the fabric too. The register map's 64-bit fields are Words in
// logic/ports.hpp.
template <class F, bool Signed>
struct HighWord {
  typedef sint<F, 32> type;
};
template <class F>
struct HighWord<F, false> {
  typedef uint<F, 32> type;
};
template <class F, bool Signed = true>
struct Words {
  typename HighWord<F, Signed>::type hi{0};
  uint<F, 32> lo{0};
};

// A 64-bit value (a Words, or a 64-bit integer of a family that has one)
// as Words.
template <class F, bool Signed>
inline Words<F, Signed> to_words(const Words<F, Signed>& w) {
  return w;
}
template <class T>
inline Words<typename IntTraits<T>::family> to_words(const T& v) {
  using F = typename IntTraits<T>::family;
  static_assert(IntTraits<T>::width == 64, "to_words takes a 64-bit value");
  Words<F> w;
  w.hi = wrap<sint<F, 32> >(shr<32>(v));
  w.lo = wrap<uint<F, 32> >(v);
  return w;
}
// Stores Words into a 64-bit port (a Words, or a 64-bit integer).
template <class F, bool Signed>
inline void from_words(Words<F, Signed>& port, const Words<F, Signed>& w) {
  port = w;
}
template <class T, class F, bool Signed>
inline void from_words(T& port, const Words<F, Signed>& w) {
  static_assert(IntTraits<T>::width == 64, "from_words fills a 64-bit value");
  port = wrap<T>(cat(w.hi, w.lo));
}

}  // namespace logic
}  // namespace odoloc
