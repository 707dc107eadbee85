// One field list per register struct, and everything derived from it.
//
//   struct CounterRegs {
//     SInt<20> count, latched;
//     UInt<1> carry;
//     ODOLOC_FIELDS(count, latched, carry)
//   };
//
// ODOLOC_FIELDS(...) defines `for_each_field(f)`, which calls f(name, member)
// for every listed member in order, the name being the member's own
// identifier. The list cannot fall behind the struct: a member missing from
// it is a compile error (the list is also a structured binding of the whole
// struct, which must name every member). Waveforms (trace_fields), register
// comparisons in tests and failure messages all walk this one list.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <string_view>
#include <tuple>
#include <type_traits>

#include "odoloc/rtl/bits.hpp"

// Preprocessor iteration (C++20 __VA_OPT__): up to 256 list elements.
#define ODOLOC_PARENS ()
#define ODOLOC_EXPAND(...) \
  ODOLOC_EXPAND4(ODOLOC_EXPAND4(ODOLOC_EXPAND4(ODOLOC_EXPAND4(__VA_ARGS__))))
#define ODOLOC_EXPAND4(...) \
  ODOLOC_EXPAND3(ODOLOC_EXPAND3(ODOLOC_EXPAND3(ODOLOC_EXPAND3(__VA_ARGS__))))
#define ODOLOC_EXPAND3(...) \
  ODOLOC_EXPAND2(ODOLOC_EXPAND2(ODOLOC_EXPAND2(ODOLOC_EXPAND2(__VA_ARGS__))))
#define ODOLOC_EXPAND2(...) \
  ODOLOC_EXPAND1(ODOLOC_EXPAND1(ODOLOC_EXPAND1(ODOLOC_EXPAND1(__VA_ARGS__))))
#define ODOLOC_EXPAND1(...) __VA_ARGS__

#define ODOLOC_VISIT_FIELD(name) f(#name, name);
#define ODOLOC_FOR_EACH(macro, ...) \
  __VA_OPT__(ODOLOC_EXPAND(ODOLOC_FOR_EACH_STEP(macro, __VA_ARGS__)))
#define ODOLOC_FOR_EACH_STEP(macro, first, ...) \
  macro(first) __VA_OPT__(ODOLOC_FOR_EACH_AGAIN ODOLOC_PARENS(macro, __VA_ARGS__))
#define ODOLOC_FOR_EACH_AGAIN() ODOLOC_FOR_EACH_STEP

#define ODOLOC_BINDING_NAME(name) odoloc_field_##name
#define ODOLOC_BINDINGS(first, ...) \
  ODOLOC_BINDING_NAME(first) __VA_OPT__(ODOLOC_EXPAND(ODOLOC_BINDINGS_REST(__VA_ARGS__)))
#define ODOLOC_BINDINGS_REST(first, ...) \
  , ODOLOC_BINDING_NAME(first) __VA_OPT__(ODOLOC_BINDINGS_AGAIN ODOLOC_PARENS(__VA_ARGS__))
#define ODOLOC_BINDINGS_AGAIN() ODOLOC_BINDINGS_REST

#define ODOLOC_FIELDS(...)                                               \
  template <class F>                                                     \
  constexpr void for_each_field(F&& f) const {                           \
    ODOLOC_FOR_EACH(ODOLOC_VISIT_FIELD, __VA_ARGS__)                     \
  }                                                                      \
  /* Does not compile unless the list names every member, in order. */   \
  void odoloc_fields_are_complete() const {                              \
    [[maybe_unused]] const auto& [ODOLOC_BINDINGS(__VA_ARGS__)] = *this; \
  }                                                                      \
  static constexpr std::size_t kFieldCount = std::array{ODOLOC_FIELD_NAMES(__VA_ARGS__)}.size();

#define ODOLOC_FIELD_NAME(name) std::string_view{#name},
#define ODOLOC_FIELD_NAMES(...) ODOLOC_FOR_EACH(ODOLOC_FIELD_NAME, __VA_ARGS__)

namespace odoloc::rtl {

// A struct has a field list as a member (ODOLOC_FIELDS), or, for structs
// that must stay free of this header (the HLS-shared cores), as a free
// function for_each_field(s, f) found by argument-dependent lookup.
template <class S>
concept HasMemberFields = requires(const S& s) {
  s.for_each_field([](std::string_view, const auto&) {});
};
template <class S>
concept HasFreeFields = requires(const S& s) {
  for_each_field(s, [](std::string_view, const auto&) {});
};
template <class S>
concept HasFields = HasMemberFields<S> || HasFreeFields<S>;

template <HasFields S, class F>
constexpr void visit_fields(const S& s, F&& f) {
  if constexpr (HasMemberFields<S>)
    s.for_each_field(f);
  else
    for_each_field(s, f);
}

namespace detail {
template <class T>
struct is_std_array : std::false_type {};
template <class T, std::size_t N>
struct is_std_array<std::array<T, N>> : std::true_type {};
// A register bank: a std::array or, in the HLS-style logic, a C array.
template <class T>
inline constexpr bool is_bank = is_std_array<T>::value || std::is_array_v<T>;
template <class T>
struct bank_extent : std::extent<T> {};
template <class T, std::size_t N>
struct bank_extent<std::array<T, N>> : std::integral_constant<std::size_t, N> {};
template <class T>
inline constexpr std::size_t bank_size = bank_extent<T>::value;

// "0", "1", ... "255": names of array elements inside the array's scope,
// built at compile time (the register file's word arrays are the longest).
inline constexpr std::size_t kMaxIndexNames = 256;
struct IndexNames {
  std::array<char, kMaxIndexNames * 4> text{};  // up to three digits and a NUL each
  constexpr IndexNames() {
    for (std::size_t i = 0; i < kMaxIndexNames; ++i) {
      char* p = &text[i * 4];
      if (i >= 100)
        *p++ = static_cast<char>('0' + i / 100);
      if (i >= 10)
        *p++ = static_cast<char>('0' + i / 10 % 10);
      *p = static_cast<char>('0' + i % 10);
    }
  }
  [[nodiscard]] constexpr std::string_view operator[](std::size_t i) const {
    return {&text[i * 4]};
  }
};
inline constexpr IndexNames kIndexNames{};
}  // namespace detail

// Names one value for a waveform: a UInt/SInt is a signal; a struct with a
// field list or an array is a scope of its members (array elements are
// named by their index).
template <class V, class T>
void trace_value(V& v, std::string_view name, const T& value) {
  if constexpr (HasFields<T>) {
    v.enter(name);
    visit_fields(value, [&](std::string_view n, const auto& m) { trace_value(v, n, m); });
    v.leave();
  } else if constexpr (detail::is_bank<T>) {
    static_assert(detail::bank_size<T> <= detail::kMaxIndexNames);
    v.enter(name);
    for (std::size_t i = 0; i < detail::bank_size<T>; ++i)
      trace_value(v, detail::kIndexNames[i], value[i]);
    v.leave();
  } else {
    v.signal(name, value);
  }
}

// True when any bit of any scalar in `value` is set (a strobe struct: any
// strobe high). Branch-free, so a struct of strobes is a few ORs.
template <class T>
[[gnu::always_inline]] constexpr bool any_set(const T& value) {
  if constexpr (HasFields<T>) {
    bool any = false;
    visit_fields(value, [&](std::string_view, const auto& m) { any |= any_set(m); });
    return any;
  } else if constexpr (detail::is_bank<T>) {
    bool any = false;
    for (const auto& element : value)
      any |= any_set(element);
    return any;
  } else {
    return !value.is_zero();
  }
}

// Every field of `s` at the current scope.
template <class V, HasFields S>
void trace_fields(V& v, const S& s) {
  visit_fields(s, [&](std::string_view n, const auto& m) { trace_value(v, n, m); });
}

}  // namespace odoloc::rtl
