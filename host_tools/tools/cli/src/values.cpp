#include "odoloc/cli/values.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <optional>
#include <span>
#include <string>

#include "odoloc/cli/errors.hpp"

namespace odoloc::cli {
namespace {

constexpr std::uint64_t kWordMax = (std::uint64_t{1} << regs::kDataBits) - 1;

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

int digit_value(char c) {
  if (is_digit(c))
    return c - '0';
  const char l = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (l >= 'a' && l <= 'f')
    return l - 'a' + 10;
  return 99;
}

bool iequal(std::string_view a, std::string_view b) {
  return std::ranges::equal(a, b, [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) ==
           std::tolower(static_cast<unsigned char>(y));
  });
}

std::string not_a_number(std::string_view text) {
  return fmt::format("'{}' is not a number (decimal, 0x hex or 0b binary)", text);
}

std::string enum_list(const regs::Field& f, bool with_values) {
  std::string out;
  for (std::size_t i = 0; i < f.enums.size(); ++i) {
    if (i > 0)
      out += i + 1 == f.enums.size() ? " or " : ", ";
    out += with_values ? fmt::format("{}={}", f.enums[i].name, f.enums[i].value)
                       : std::string{f.enums[i].name};
  }
  return out;
}

// A decimal with an optional fraction followed by a unit from `units`, as an
// integer count of the smallest unit. Every step is checked: a value that
// does not fit 64 bits is kOverflow, never wrapped, and a non-zero digit
// below the smallest unit is kTooFine, never dropped.
struct Unit {
  std::string_view suffix;
  std::uint64_t scale;
};

struct Scaled {
  enum Status : std::uint8_t { kOk, kSyntax, kOverflow, kTooFine };
  Status status = kSyntax;
  std::uint64_t value = 0;
};

Scaled parse_scaled(std::string_view text, std::span<const Unit> units, bool unit_required) {
  std::size_t i = 0;
  while (i < text.size() && is_digit(text[i]))
    ++i;
  const std::string_view whole = text.substr(0, i);
  std::string_view fraction;
  if (i < text.size() && text[i] == '.') {
    const std::size_t start = ++i;
    while (i < text.size() && is_digit(text[i]))
      ++i;
    fraction = text.substr(start, i - start);
  }
  if (whole.empty() && fraction.empty())
    return {};
  const std::string_view suffix = text.substr(i);
  std::uint64_t scale = 0;
  for (const Unit& u : units) {
    if (iequal(suffix, u.suffix))
      scale = u.scale;
  }
  if (scale == 0 && (unit_required || !suffix.empty()))
    return {};
  if (scale == 0)
    scale = 1;
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t value = 0;
  for (const char c : whole) {
    const auto d = static_cast<std::uint64_t>(c - '0');
    if (value > (kMax - d) / 10)
      return {Scaled::kOverflow};
    value = value * 10 + d;
  }
  if (value > kMax / scale)
    return {Scaled::kOverflow};
  value *= scale;
  std::uint64_t place = scale;
  for (const char c : fraction) {
    const auto d = static_cast<std::uint64_t>(c - '0');
    if (place < 10) {
      if (d != 0)
        return {Scaled::kTooFine};
      continue;
    }
    place /= 10;
    if (value > kMax - d * place)
      return {Scaled::kOverflow};
    value += d * place;
  }
  return {Scaled::kOk, value};
}

}  // namespace

bool looks_numeric(std::string_view text) {
  if (!text.empty() && (text.front() == '-' || text.front() == '+'))
    text.remove_prefix(1);
  return !text.empty() && is_digit(text.front());
}

Number parse_number(std::string_view text) {
  Number n;
  std::string_view s = text;
  if (!s.empty() && (s.front() == '-' || s.front() == '+')) {
    n.negative = s.front() == '-';
    s.remove_prefix(1);
  }
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    n.base = 16;
    s.remove_prefix(2);
  } else if (s.size() > 2 && s[0] == '0' && (s[1] == 'b' || s[1] == 'B')) {
    n.base = 2;
    s.remove_prefix(2);
  }
  if (s.empty() || s.front() == '_' || s.back() == '_')
    throw UsageError(not_a_number(text));
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '_') {
      if (s[i - 1] == '_')
        throw UsageError(not_a_number(text));
      continue;
    }
    const int d = digit_value(s[i]);
    if (d >= static_cast<int>(n.base))
      throw UsageError(not_a_number(text));
    const auto du = static_cast<std::uint64_t>(d);
    if (n.magnitude > (std::numeric_limits<std::uint64_t>::max() - du) / n.base)
      throw UsageError(fmt::format("'{}' is too large", text));
    n.magnitude = n.magnitude * n.base + du;
  }
  return n;
}

std::uint32_t parse_field_value(const regs::Field& field, std::string_view path,
                                std::string_view text) {
  const unsigned w = field.width;
  const std::uint64_t max_raw = (std::uint64_t{1} << w) - 1;
  if (!field.enums.empty()) {
    for (const regs::Enumerator& e : field.enums) {
      if (iequal(e.name, text))
        return e.value;
    }
    if (!looks_numeric(text))
      throw UsageError(fmt::format("unknown value '{}' for {}; expected {}", text, path,
                                   enum_list(field, false)));
    const Number n = parse_number(text);
    for (const regs::Enumerator& e : field.enums) {
      if (!(n.negative && n.magnitude != 0) && n.magnitude == e.value)
        return e.value;
    }
    throw UsageError(
        fmt::format("value {} is not a valid {} ({})", text, path, enum_list(field, true)));
  }
  if (!looks_numeric(text))
    throw UsageError(fmt::format("bad value '{}' for {}: {}", text, path, not_a_number(text)));
  const Number n = parse_number(text);
  if (field.is_signed) {
    const std::int64_t min = -(std::int64_t{1} << (w - 1));
    const std::int64_t max = (std::int64_t{1} << (w - 1)) - 1;
    if (n.base == 10 || n.negative) {
      const std::uint64_t limit =
          n.negative ? static_cast<std::uint64_t>(-min) : static_cast<std::uint64_t>(max);
      if (n.magnitude > limit)
        throw UsageError(fmt::format(
            "value {} out of range for {} ({}-bit signed: {}..{}, or a 0x/0b bit pattern up to "
            "0x{:x})",
            text, path, w, min, max, max_raw));
      const std::int64_t v = n.negative ? -static_cast<std::int64_t>(n.magnitude)
                                        : static_cast<std::int64_t>(n.magnitude);
      return static_cast<std::uint32_t>(static_cast<std::uint64_t>(v) & max_raw);
    }
    if (n.magnitude > max_raw)
      throw UsageError(fmt::format("bit pattern {} does not fit {} ({} bits: 0x0..0x{:x})", text,
                                   path, w, max_raw));
    return static_cast<std::uint32_t>(n.magnitude);
  }
  if (n.negative && n.magnitude != 0)
    throw UsageError(fmt::format("value {} out of range for {} (unsigned, {} bits: 0..{})", text,
                                 path, w, max_raw));
  if (n.magnitude > max_raw)
    throw UsageError(fmt::format("value {} out of range for {} ({}-bit unsigned: 0..{})", text,
                                 path, w, max_raw));
  return static_cast<std::uint32_t>(n.magnitude);
}

std::uint32_t parse_register_value(const regs::Register& reg, std::string_view text) {
  if (!looks_numeric(text))
    throw UsageError(fmt::format(
        "bad value '{}' for {}: {}; enumerator names go to a field ({}.{}=...)", text, reg.path,
        not_a_number(text), reg.path, reg.fields.empty() ? "FIELD" : reg.fields.front().name));
  const Number n = parse_number(text);
  if (n.negative && n.magnitude != 0) {
    // Point at the register's own signed writable fields, when it has any.
    std::string fields;
    for (const regs::Field& f : reg.fields) {
      if (f.is_signed && f.access == regs::Access::kRw)
        fields += fmt::format("{}{}.{}", fields.empty() ? "" : ", ", reg.path, f.name);
    }
    throw UsageError(fmt::format(
        "value {} out of range for {}: a register word is 0..0x{:x}{}", text, reg.path, kWordMax,
        fields.empty() ? std::string{"; give the bit pattern in hex"}
                       : fmt::format("; write a negative value to its signed field ({})", fields)));
  }
  if (n.magnitude > kWordMax)
    throw UsageError(fmt::format("value {} out of range for {} (a {}-bit word: 0..0x{:x})", text,
                                 reg.path, regs::kDataBits, kWordMax));
  const auto word = static_cast<std::uint32_t>(n.magnitude);
  std::uint32_t fields = 0;
  for (const regs::Field& f : reg.fields)
    fields |= f.mask();
  if ((word & ~fields) != 0)
    throw UsageError(fmt::format(
        "value 0x{:08x} sets bits 0x{:08x} outside the fields of {} (field bits: 0x{:08x})", word,
        word & ~fields, reg.path, fields));
  return word;
}

std::chrono::nanoseconds parse_interval(std::string_view text) {
  static constexpr Unit kUnits[] = {
      {"ns", 1}, {"us", 1'000}, {"\u00b5s", 1'000}, {"ms", 1'000'000}, {"s", 1'000'000'000}};
  const Scaled ns = parse_scaled(text, kUnits, true);
  constexpr auto kMax = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  if (ns.status == Scaled::kOverflow || (ns.status == Scaled::kOk && ns.value > kMax))
    throw UsageError(
        fmt::format("bad interval '{}': too long (at most {} ns, about 292 years)", text, kMax));
  if (ns.status == Scaled::kTooFine)
    throw UsageError(fmt::format("bad interval '{}': finer than the 1 ns resolution", text));
  if (ns.status != Scaled::kOk)
    throw UsageError(fmt::format(
        "bad interval '{}': expected a number with a unit ns, us, ms or s (e.g. 100ms, 1.5s)",
        text));
  if (ns.value == 0)
    throw UsageError(fmt::format("bad interval '{}': must be longer than 0", text));
  return std::chrono::nanoseconds{static_cast<std::int64_t>(ns.value)};
}

std::uint64_t parse_count(std::string_view text) {
  if (!looks_numeric(text))
    throw UsageError(fmt::format("bad count '{}': expected a positive number", text));
  const Number n = parse_number(text);
  if (n.negative || n.magnitude == 0)
    throw UsageError(fmt::format("bad count '{}': expected a positive number", text));
  return n.magnitude;
}

std::uint32_t parse_frequency(std::string_view text) {
  static constexpr Unit kUnits[] = {{"", 1},        {"hz", 1},        {"k", 1'000},
                                    {"khz", 1'000}, {"m", 1'000'000}, {"mhz", 1'000'000}};
  const Scaled hz = parse_scaled(text, kUnits, false);
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint32_t>::max();
  if (hz.status == Scaled::kOverflow || (hz.status == Scaled::kOk && hz.value > kMax))
    throw UsageError(fmt::format(
        "bad SPI clock '{}': too large (at most {} Hz can be asked of spidev)", text, kMax));
  if (hz.status == Scaled::kTooFine)
    throw UsageError(fmt::format("bad SPI clock '{}': finer than 1 Hz", text));
  if (hz.status != Scaled::kOk || hz.value == 0)
    throw UsageError(fmt::format(
        "bad SPI clock '{}': expected a frequency in Hz such as 1000000, 500k or 2M", text));
  return static_cast<std::uint32_t>(hz.value);
}

}  // namespace odoloc::cli
