// The model's types as an integer-type family of the blocks' logic
// (logic/int_family.hpp): rtl::Family is UInt<W> and SInt<W> (bits.hpp).
// Narrowing does not compile in this family, so the logic instantiated with
// it states every wrap; the HLS families (hls/types.hpp) accept the same
// source.
//
// ODOLOC_LOGIC_FIELDS(Type, members...) gives a logic struct instantiated
// with rtl::Family its field list (fields.hpp: waveforms, comparisons,
// messages) and ==, outside the C++14 logic header; the list must name every
// member, in order, or it does not compile.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "odoloc/logic/int_family.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/fields.hpp"

namespace odoloc::rtl {

struct Family {
  template <int W>
  using uint = UInt<W>;
  template <int W>
  using sint = SInt<W>;
};

namespace detail {
template <class T>
struct is_rtl_int : std::false_type {};
template <int W>
struct is_rtl_int<UInt<W>> : std::true_type {};
template <int W>
struct is_rtl_int<SInt<W>> : std::true_type {};

// The two's complement bits of any model integer or host integer, extended
// to 64 bits by its sign: wrapping a signed value into a wider type keeps
// its value, as ap_int and ac_int do.
template <class From>
constexpr std::uint64_t raw_bits(const From& v) {
  if constexpr (std::integral<From>)
    return static_cast<std::uint64_t>(v);
  else
    return static_cast<std::uint64_t>(v.value());
}

// ==, element by element for C arrays (the logic's register banks).
template <class T>
constexpr bool equal_value(const T& a, const T& b) {
  if constexpr (std::is_array_v<T>) {
    for (std::size_t i = 0; i < std::extent_v<T>; ++i)
      if (!equal_value(a[i], b[i]))
        return false;
    return true;
  } else {
    return a == b;
  }
}
}  // namespace detail

}  // namespace odoloc::rtl

namespace odoloc::logic {

// UInt<W> and SInt<W> alike: the value through its two's complement bits.
template <class T>
struct ModelIntTraits {
  using family = rtl::Family;
  static constexpr int width = T::width;
  // Every value of From is one of T: the same signedness and no wider, or
  // unsigned into a wider signed type.
  template <class From>
  static constexpr bool fits() {
    if constexpr (std::integral<From>) {
      return false;
    } else {
      constexpr bool from_signed = std::is_same_v<From, rtl::SInt<From::width>>;
      constexpr bool to_signed = std::is_same_v<T, rtl::SInt<T::width>>;
      return from_signed == to_signed ? From::width <= T::width
                                      : !from_signed && From::width < T::width;
    }
  }
  template <class From>
  requires(std::integral<From> || rtl::detail::is_rtl_int<From>::value)
      [[gnu::always_inline]] static constexpr T wrap(const From& v) {
    if constexpr (fits<From>())
      return T::exact(v.value());
    else
      return T::truncate(static_cast<decltype(T{}.value())>(rtl::detail::raw_bits(v)));
  }
  [[gnu::always_inline]] static constexpr long long to_s64(T v) {
    return static_cast<long long>(v.value());
  }
  template <int Hi, int Lo>
  [[gnu::always_inline]] static constexpr rtl::UInt<Hi - Lo + 1> bits(T v) {
    return rtl::UInt<width>::truncate(rtl::detail::raw_bits(v)).template bits<Hi, Lo>();
  }
  template <int N>
  [[gnu::always_inline]] static constexpr auto shl(T v) {
    return v.template shl<N>();
  }
  template <int N>
  [[gnu::always_inline]] static constexpr T shr(T v) {
    return T::exact(v.value() >> N);
  }
  template <int K>
  [[gnu::always_inline]] static constexpr T shr_by(T v, rtl::UInt<K> amount) {
    return v.dshr(amount);
  }
  template <class L>
  [[gnu::always_inline]] static constexpr rtl::UInt<width + L::width> cat(T high, L low) {
    return rtl::cat(rtl::UInt<width>::truncate(rtl::detail::raw_bits(high)),
                    rtl::UInt<L::width>::truncate(rtl::detail::raw_bits(low)));
  }
};

template <int W>
struct IntTraits<rtl::UInt<W>> : ModelIntTraits<rtl::UInt<W>> {};
template <int W>
struct IntTraits<rtl::SInt<W>> : ModelIntTraits<rtl::SInt<W>> {};

}  // namespace odoloc::logic

// Field list and == of a logic struct instantiated with rtl::Family, in
// namespace odoloc::rtl (found by argument-dependent lookup through the
// family). TYPE is the template, e.g. logic::cordic::State.
// ODOLOC_LOGIC_FIELDS_OF((PARAMETERS), (TYPE), members...) does the same for
// a template with more parameters: ((int Lines), (logic::conditioner::Regs<
// Family, Lines>), ...).
#define ODOLOC_UNPAREN(...) __VA_ARGS__
#define ODOLOC_LOGIC_VISIT(name) f(#name, s.name);
#define ODOLOC_LOGIC_EQUAL(name) &&::odoloc::rtl::detail::equal_value(a.name, b.name)
#define ODOLOC_LOGIC_FIELDS_BODY(TYPE, ...)                                             \
  constexpr void for_each_field(const TYPE& s, F&& f) {                                 \
    [[maybe_unused]] const auto& [ODOLOC_BINDINGS(__VA_ARGS__)] = s; /* every member */ \
    ODOLOC_FOR_EACH(ODOLOC_LOGIC_VISIT, __VA_ARGS__)                                    \
  }
#define ODOLOC_LOGIC_EQUAL_BODY(TYPE, ...)                        \
  constexpr bool operator==(const TYPE& a, const TYPE& b) {       \
    return true ODOLOC_FOR_EACH(ODOLOC_LOGIC_EQUAL, __VA_ARGS__); \
  }
#define ODOLOC_LOGIC_FIELDS(TYPE, ...)                               \
  template <class F>                                                 \
  ODOLOC_LOGIC_FIELDS_BODY(TYPE<::odoloc::rtl::Family>, __VA_ARGS__) \
  ODOLOC_LOGIC_EQUAL_BODY(TYPE<::odoloc::rtl::Family>, __VA_ARGS__)
#define ODOLOC_LOGIC_FIELDS_OF(PARAMETERS, TYPE, ...)        \
  template <ODOLOC_UNPAREN PARAMETERS, class F>              \
  ODOLOC_LOGIC_FIELDS_BODY(ODOLOC_UNPAREN TYPE, __VA_ARGS__) \
  template <ODOLOC_UNPAREN PARAMETERS>                       \
  ODOLOC_LOGIC_EQUAL_BODY(ODOLOC_UNPAREN TYPE, __VA_ARGS__)

namespace odoloc::rtl {
ODOLOC_LOGIC_FIELDS_OF((bool Signed), (logic::Words<Family, Signed>), hi, lo)
}  // namespace odoloc::rtl
