// Name resolution over the generated register map (odoloc/regs.hpp): register
// paths ("eppm.left_rear.count"), field paths ("eppm.left_rear.cfg.decode_mode")
// and word addresses ("0x16", "22"), with closest-match suggestions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/regs.hpp"

namespace odoloc::cli {

// A register, or one field of it.
struct Location {
  const regs::Register* reg = nullptr;
  const regs::Field* field = nullptr;  // nullptr: the whole register

  [[nodiscard]] std::string path() const;
  [[nodiscard]] std::uint16_t address() const { return reg->address; }
};

// A word address in 0 .. 2^kAddressBits - 1 (not necessarily mapped).
[[nodiscard]] std::uint16_t parse_address(std::string_view text);
// "b:ADDR": a byte address as in odoloc.rdl and PeakRDL's outputs (4 × the
// word address), returned as the word address; UsageError unless a multiple
// of 4 in range.
[[nodiscard]] std::uint16_t parse_byte_address(std::string_view text);
// The register at a word address; UsageError when unmapped or reserved.
[[nodiscard]] const regs::Register& register_at(std::uint16_t address);
// NAME or ADDR; UsageError naming the closest paths when unknown.
//  - NAME: a register or field path ("eppm.left_rear.cfg.decode_mode"), or
//    the same register or field as spelt in odoloc.rdl / PeakRDL
//    ("eppm_left_rear.cfg", "odoloc.eppm_left_rear.cfg") or the C header
//    ("ODOLOC_EPPM_LEFT_REAR_CFG_ADDR"), case-insensitive.
//  - ADDR: "w:N" a word address (as in docs/spi.md, odoloc_regs.h and
//    `reg list`), "b:N" a byte address (odoloc.rdl: 4 × the word address),
//    or a bare N, taken as a word address; a bare N that is also the byte
//    address of a different register is refused naming both.
[[nodiscard]] Location resolve(std::string_view name);

// Every register path, then every field path ("reg.field").
[[nodiscard]] std::vector<std::string> all_paths();
// Optimal-string-alignment distance (insertions, deletions, substitutions,
// adjacent transpositions), case-insensitive.
[[nodiscard]] std::size_t edit_distance(std::string_view a, std::string_view b);
// Up to `max` register or field paths nearest to `name`, best first; empty
// when nothing is reasonably close.
[[nodiscard]] std::vector<std::string> closest_paths(std::string_view name, std::size_t max = 3);

// `filter` with a glob character (* ? [) matches the whole path as a glob
// whose * and ? stay within one dot-separated component ("eppm.*.count");
// otherwise it matches any path containing it. Empty matches everything.
[[nodiscard]] bool path_matches(std::string_view path, std::string_view filter);
// A register matches when its path or one of its field paths matches.
[[nodiscard]] bool register_matches(const regs::Register& reg, std::string_view filter);

}  // namespace odoloc::cli
