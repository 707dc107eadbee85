// Text and JSON renderings of registers, fields and the values read from
// them. Field values are decoded through the generated register map: enum
// names for enumerated fields, signed decimals for signed fields.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>

#include "odoloc/cli/names.hpp"
#include "odoloc/regs.hpp"

namespace odoloc::cli {

// One JSON Lines record of `doc`, on one line: control characters escaped
// (\u001b), and bytes that are not well-formed UTF-8 (a name from a file or
// a log may hold any) replaced by U+FFFD instead of failing the command.
[[nodiscard]] std::string json_line(const nlohmann::json& doc);

[[nodiscard]] std::string_view access_name(regs::Access access);
// "31:16", or "0" for a one-bit field.
[[nodiscard]] std::string bit_range(const regs::Field& field);
[[nodiscard]] unsigned msb(const regs::Field& field);

// A signed field's value, sign-extended in 64 bits. (The generated
// Field::get_signed subtracts INT32_MIN in int arithmetic, which overflows
// for negative values of a 32-bit field.)
[[nodiscard]] std::int64_t field_signed(const regs::Field& field, std::uint32_t word);

// The enumerator name, the signed decimal or the unsigned decimal; an enum
// value without a name stays a number.
[[nodiscard]] std::string field_compact(const regs::Field& field, std::uint32_t word);
// field_compact plus the raw bits: "x2 (1)", "-5 (0xffffb)", "3329 (0x0d01)", "1".
[[nodiscard]] std::string field_text(const regs::Field& field, std::uint32_t word);
// "x2", -5 or 3329.
[[nodiscard]] nlohmann::json field_json(const regs::Field& field, std::uint32_t word);

// `reg list`: the register and its fields (no value).
[[nodiscard]] nlohmann::json describe_json(const regs::Register& reg);
[[nodiscard]] std::string list_text(std::span<const regs::Register* const> registers);

// A value read at a location. Register: {"path","address","value","fields":
// {name: decoded}}; field: {"path","register","address","word","raw","value"}.
[[nodiscard]] nlohmann::json value_json(const Location& loc, std::uint32_t word);
// `reg read`: "top.id @ 0x000 = 0x0d010001" and one line per field, or
// "eppm.left_rear.cfg.decode_mode = x2 (1)" for a field.
[[nodiscard]] std::string value_text(const Location& loc, std::uint32_t word);
// `reg watch`: "top.id=0x0d010001(magic=3329,version=1)" or "path=x2".
[[nodiscard]] std::string value_compact(const Location& loc, std::uint32_t word);
// `reg dump`: "0x000  top.id  0x0d010001  magic=3329 version=1".
[[nodiscard]] std::string dump_line(const regs::Register& reg, std::uint32_t word,
                                    std::size_t path_width);

}  // namespace odoloc::cli
