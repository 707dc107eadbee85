// Parsing of the values the user types: numbers in every base, field values
// (signed, enumerated, range-checked against the field width), register
// words, durations, counts and frequencies. Every function throws UsageError
// with a one-line message naming what was wrong.
#pragma once

#include <chrono>
#include <cstdint>
#include <string_view>

#include "odoloc/regs.hpp"

namespace odoloc::cli {

struct Number {
  bool negative = false;
  std::uint64_t magnitude = 0;
  unsigned base = 10;  // 10, 16 (0x) or 2 (0b)
};

// [+-] then decimal digits, 0x hex or 0b binary digits; '_' may separate
// digits (0b1010_0101). Leading zeros are decimal, never octal.
[[nodiscard]] bool looks_numeric(std::string_view text);
[[nodiscard]] Number parse_number(std::string_view text);

// The field's raw bits (right-aligned, width bits) for `text`: an enumerator
// name of an enumerated field (or a number that is one of its values); for a
// signed field a signed decimal in [-2^(w-1), 2^(w-1)) or a hex/binary bit
// pattern in [0, 2^w); for an unsigned field a number in [0, 2^w). `path`
// names the field in messages.
[[nodiscard]] std::uint32_t parse_field_value(const regs::Field& field, std::string_view path,
                                              std::string_view text);

// A whole register word: 0 .. 0xffffffff, with no bit set outside the
// register's fields.
[[nodiscard]] std::uint32_t parse_register_value(const regs::Register& reg, std::string_view text);

// "100ms", "1s", "250us", "20ns", "1.5s": a positive duration with its unit.
[[nodiscard]] std::chrono::nanoseconds parse_interval(std::string_view text);

// A positive sample count.
[[nodiscard]] std::uint64_t parse_count(std::string_view text);

// An SPI clock: "1000000", "500k", "2M", optionally followed by "Hz".
[[nodiscard]] std::uint32_t parse_frequency(std::string_view text);

}  // namespace odoloc::cli
