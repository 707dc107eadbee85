// Whole numbers as the spec and --shard take them (private to the library).
#pragma once

#include <charconv>
#include <cstdint>
#include <optional>
#include <string_view>

namespace odoloc::sweep {

// Decimal digits only, 0 .. 2^64 - 1: no sign, space, base prefix or fraction.
inline std::optional<std::uint64_t> whole_number(std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size())
    return std::nullopt;
  return value;
}

}  // namespace odoloc::sweep
