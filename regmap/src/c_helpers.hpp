// The C header's firmware helpers beyond _get/_set (docs/register-generator.md,
// "Firmware helpers"): the SPI frame layout they encode, which fields get
// which helper, and their names. emit.cpp writes them; check_generated_names()
// (names.cpp) claims the same names, so a map whose helpers would clash is
// refused before anything is written.
#pragma once

#include <string>
#include <vector>

#include "names.hpp"
#include "odoloc/regmap/regmap.hpp"

namespace odoloc::regmap {

// ---- The SPI frame (docs/spi.md) ------------------------------------------
// The command word: bit 15 read (1) / write (0), bits 14:10 burst length - 1,
// bits 9:0 the start word address. The generator is the one definition: the C
// header's ODOLOC_SPI_COMMAND_* macros and odoloc_spi_command(), and
// regs.hpp's regs::spi::kCommand* constants, are all written from these.
inline constexpr unsigned kSpiCommandAddressBits = 10;
inline constexpr unsigned kSpiCommandBurstShift = kSpiCommandAddressBits;
inline constexpr unsigned kSpiCommandBurstBits = 5;  // spi.max_burst 1..32
inline constexpr unsigned kSpiCommandReadBit = kSpiCommandBurstShift + kSpiCommandBurstBits;
inline constexpr unsigned kSpiHeaderBytes = 2;  // the command, MSB first
inline constexpr unsigned kSpiWordBytes = 4;    // each data word, MSB first
static_assert(kSpiCommandReadBit == 15, "the command is one 16-bit word");
static_assert(kSpiHeaderBytes * 8 == kSpiCommandReadBit + 1, "the header is the command");

// The C header's global helpers: macros (after the map's prefix, "ODOLOC_")
// and functions (after the map's name and '_', "odoloc_").
inline constexpr const char* kCSpiMacros[] = {"SPI_COMMAND_READ",       "SPI_COMMAND_BURST_SHIFT",
                                              "SPI_COMMAND_BURST_MASK", "SPI_COMMAND_ADDRESS_MASK",
                                              "SPI_HEADER_BYTES",       "SPI_WORD_BYTES",
                                              "SPI_FRAME_MAX_BYTES"};
inline constexpr const char* kCSpiFunctions[] = {
    "spi_command",  "spi_crc8_update", "spi_crc8",   "spi_put_word",
    "spi_get_word", "spi_frame_bytes", "spi_encode", "spi_decode"};

// ---- Per field ------------------------------------------------------------

// "odoloc_eppm_count_value_get_signed": the two's complement value of a
// signed field (the slice holding the sign bit, for a wide one).
inline std::string c_get_signed(const RegisterMap& m, const Block& b, const Register& r,
                                const Field& f) {
  return c_function(m, b, r, f) + "_get_signed";
}

// A field of a `words: 2` register with bits in both words: its slices in the
// lo and hi word registers (element 0's for a register array: every element
// has the same layout, so the array has one set of helpers).
struct SplitField {
  const Block* block = nullptr;
  const Register* lo_reg = nullptr;
  const Field* lo = nullptr;
  const Register* hi_reg = nullptr;
  const Field* hi = nullptr;
};

// Every split field of the map, in declaration order.
inline std::vector<SplitField> split_fields(const RegisterMap& m) {
  std::vector<SplitField> out;
  for (const Block& b : m.blocks) {
    for (std::size_t i = 1; i < b.registers.size(); ++i) {
      const Register& hi = b.registers[i];
      // split_words() puts a wide register's hi word right after its lo word.
      if (hi.wide.empty() || hi.word != 1 || hi.element != 0)
        continue;
      const Register& lo = b.registers[i - 1];
      for (const Field& f : hi.fields) {
        if (f.port_shift == 0)  // no bit in the lo word
          continue;
        for (const Field& l : lo.fields) {
          if (l.name == f.name)
            out.push_back({&b, &lo, &l, &hi, &f});
        }
      }
    }
  }
  return out;
}

// "odoloc_odometry_pose_x_bits" (the wide register's or the array's name):
// the stem of a split field's _join, _set_lo and _set_hi.
inline std::string c_split_function(const RegisterMap& m, const SplitField& s) {
  return m.name + "_" + s.block->name + "_" + s.hi_reg->port_name() + "_" + s.hi->name;
}

// Only writable split fields get _set_lo and _set_hi.
inline bool c_split_writable(const SplitField& s) {
  return s.hi->access == Access::kRw;
}

}  // namespace odoloc::regmap
