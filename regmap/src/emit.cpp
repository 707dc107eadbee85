// The four artefacts generated from one register description.
#include <algorithm>
#include <sstream>

#include "c_helpers.hpp"
#include "names.hpp"
#include "odoloc/regmap/regmap.hpp"
#include "text.hpp"

namespace odoloc::regmap {

namespace {

// A SystemRDL string literal (its only escapes: \" and \\).
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\')
      out += '\\';
    out += c;
  }
  return out + "\"";
}

// A C++ string literal: also "??" written "?\?", never read as a trigraph.
std::string cpp_quoted(const std::string& s) {
  std::string out = "\"";
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '"' || c == '\\' || (c == '?' && i > 0 && s[i - 1] == '?'))
      out += '\\';
    out += c;
  }
  return out + "\"";
}

// The generated enumerator: "ro" -> "Access::kRo".
std::string cpp_access(Access a) {
  return "Access::k" + camel(to_string(a));
}

// "set" -> "HwAccess::kSet".
std::string cpp_hw(Hw h) {
  return "HwAccess::k" + camel(to_string(h));
}

// A 32-bit unsigned constant of the C header, on any C99 compiler (unsigned
// int may have 16 bits: AVR, MSP430).
std::string u32(std::uint32_t v, int digits = 0) {
  return "UINT32_C(" + (digits == 0 ? std::to_string(v) : hex(v, digits)) + ")";
}

// A constant of the C header in a 32- or 64-bit unsigned type.
std::string c_constant(std::uint64_t v, bool wide) {
  std::ostringstream s;
  s << (wide ? "UINT64_C(0x" : "UINT32_C(0x") << std::hex << v << ")";
  return s.str();
}

// The C99 expression for the two's complement value of the `width`-bit
// unsigned variable `v` (uint32_t, or uint64_t when `wide`), as int32_t or
// int64_t. Portable where int has 16 bits and without implementation-defined
// or undefined behaviour: no signed shift, no conversion of a value that does
// not fit (a negative value is -(its magnitude - 1) - 1, the magnitude - 1
// being ~v's low width-1 bits), no overflow.
std::string c_sign_extend(const std::string& v, int width, bool wide) {
  const std::uint64_t sign = std::uint64_t{1} << (width - 1);
  const std::string type = wide ? "int64_t" : "int32_t";
  return "(" + v + " & " + c_constant(sign, wide) + ") != 0 ? -(" + type + ")(~" + v + " & " +
         c_constant(sign - 1, wide) + ") - 1 : (" + type + ")" + v;
}

// The join and split helpers of a field whose bits lie in both words of a
// `words: 2` register (or of each element of such a register array).
void emit_c_split_field(std::ostringstream& o, const RegisterMap& map, const SplitField& s) {
  const Block& b = *s.block;
  const Field& f = *s.hi;
  const bool wide = f.port_width > 32;
  const std::string value_type =
      std::string(f.port_signed ? "" : "u") + (wide ? "int64_t" : "int32_t");
  const std::string raw_type = wide ? "uint64_t" : "uint32_t";
  const std::string fn = c_split_function(map, s);
  const std::string lo_fn = c_function(map, b, *s.lo_reg, *s.lo);
  const std::string hi_fn = c_function(map, b, *s.hi_reg, f);
  const std::string shift = std::to_string(f.port_shift);  // the hi slice's first bit
  const std::string what = b.name + "." + s.hi_reg->port_name() + "." + f.name;
  o << "/* " << what << ", all " << f.port_width << " bits" << (f.port_signed ? " (signed)" : "")
    << ", from its slices in the words "
    << (s.hi_reg->array.empty()
            ? s.lo_reg->name + " and " + s.hi_reg->name
            : s.hi_reg->array + "k_lo and " + s.hi_reg->array + "k_hi of any element k")
    << (s.hi_reg->snapshot ? ", read in one burst" : "") << ". */\n"
    << "static inline " << value_type << " " << fn << "_join(uint32_t lo, uint32_t hi) {\n"
    << "  const " << raw_type << " v = ((" << raw_type << ")" << hi_fn << "_get(hi) << " << shift
    << ") | (" << raw_type << ")" << lo_fn << "_get(lo);\n"
    << "  return " << (f.port_signed ? c_sign_extend("v", f.port_width, wide) : std::string("v"))
    << ";\n}\n";
  if (!c_split_writable(s))
    return;
  o << "/* " << what << " written: its slices of `value` into the lo and hi words. */\n"
    << "static inline uint32_t " << fn << "_set_lo(uint32_t lo, " << value_type << " value) {\n"
    << "  return " << lo_fn << "_set(lo, (uint32_t)" << (wide ? "(uint64_t)" : "") << "value);\n}\n"
    << "static inline uint32_t " << fn << "_set_hi(uint32_t hi, " << value_type << " value) {\n"
    << "  return " << hi_fn << "_set(hi, (uint32_t)((" << raw_type << ")value >> " << shift
    << "));\n}\n";
}

// The SPI frame of docs/spi.md: command word, CRC-8, frame encode and decode.
void emit_c_spi(std::ostringstream& o, const RegisterMap& map) {
  const std::string p = c_prefix(map);
  const std::string n = map.name + "_spi_";
  const auto max_bytes =
      static_cast<std::uint32_t>(kSpiHeaderBytes + kSpiWordBytes * map.spi.max_burst + 1);
  o << "\n/* SPI frames (docs/spi.md). MOSI: the command word (2 bytes, MSB first), n data words\n"
    << " * (4 bytes each, MSB first; a read sends zeros), the CRC-8 of every byte before it\n"
    << " * when top.ctrl.crc_enable is on. MISO: the status byte of the previous frame\n"
    << " * (top.spi_status bits), 0x00, n words (reads; zeros for writes), the CRC-8 of every\n"
    << " * byte before it when CRC is on. Command: bit 15 read, bits 14:10 n - 1, bits 9:0 the\n"
    << " * start word address (auto-incrementing modulo 1024). */\n"
    << "#define " << p << "SPI_COMMAND_READ " << u32(1U << kSpiCommandReadBit, 4) << "\n"
    << "#define " << p << "SPI_COMMAND_BURST_SHIFT " << u32(kSpiCommandBurstShift) << "\n"
    << "#define " << p << "SPI_COMMAND_BURST_MASK "
    << u32(((1U << kSpiCommandBurstBits) - 1U) << kSpiCommandBurstShift, 4) << "\n"
    << "#define " << p << "SPI_COMMAND_ADDRESS_MASK " << u32((1U << kSpiCommandAddressBits) - 1U, 4)
    << "\n"
    << "#define " << p << "SPI_HEADER_BYTES " << u32(kSpiHeaderBytes) << "\n"
    << "#define " << p << "SPI_WORD_BYTES " << u32(kSpiWordBytes) << "\n"
    << "#define " << p << "SPI_FRAME_MAX_BYTES " << u32(max_bytes) << "\n"
    << "/* The command word of a frame of `count` words (1.." << map.spi.max_burst
    << ") from word `address`\n * (0..0x3ff): false, and *command untouched, when the frame "
       "cannot carry them. */\n"
    << "static inline bool " << n
    << "command(uint16_t *command, bool read, uint32_t address, uint32_t count) {\n"
    << "  if (count < UINT32_C(1) || count > " << p << "SPI_MAX_BURST || address > " << p
    << "SPI_COMMAND_ADDRESS_MASK)\n    return false;\n"
    << "  *command = (uint16_t)((read ? " << p << "SPI_COMMAND_READ : UINT32_C(0)) |\n"
    << "                        ((count - UINT32_C(1)) << " << p
    << "SPI_COMMAND_BURST_SHIFT) | "
       "address);\n  return true;\n}\n"
    << "/* CRC-8 (spi.crc: polynomial " << hex(map.spi.crc_polynomial, 2) << ", init "
    << hex(map.spi.crc_init, 2) << ", MSB first, final XOR " << hex(map.spi.crc_xor_out, 2)
    << "), one byte at a time:\n * start from (uint8_t)" << p
    << "SPI_CRC_INIT, finish with ^ (uint8_t)" << p << "SPI_CRC_XOR_OUT. */\n"
    << "static inline uint8_t " << n << "crc8_update(uint8_t crc, uint8_t byte) {\n"
    << "  uint8_t c = (uint8_t)(crc ^ byte);\n  uint8_t bit;\n"
    << "  for (bit = 0; bit < 8u; ++bit)\n"
    << "    c = (uint8_t)(((unsigned)c << 1) ^ ((c & 0x80u) != 0 ? (unsigned)" << p
    << "SPI_CRC_POLYNOMIAL : 0u));\n"
    << "  return c;\n}\n"
    << "/* The CRC-8 of bytes[0 .. count-1]. */\n"
    << "static inline uint8_t " << n << "crc8(const uint8_t *bytes, uint32_t count) {\n"
    << "  uint8_t crc = (uint8_t)" << p << "SPI_CRC_INIT;\n  uint32_t i;\n"
    << "  for (i = 0; i < count; ++i)\n    crc = " << n << "crc8_update(crc, bytes[i]);\n"
    << "  return (uint8_t)(crc ^ (uint8_t)" << p << "SPI_CRC_XOR_OUT);\n}\n"
    << "/* A data word as its 4 frame bytes, MSB first, and back. */\n"
    << "static inline void " << n << "put_word(uint8_t *bytes, uint32_t word) {\n"
    << "  bytes[0] = (uint8_t)(word >> 24);\n  bytes[1] = (uint8_t)(word >> 16);\n"
    << "  bytes[2] = (uint8_t)(word >> 8);\n  bytes[3] = (uint8_t)word;\n}\n"
    << "static inline uint32_t " << n << "get_word(const uint8_t *bytes) {\n"
    << "  return ((uint32_t)bytes[0] << 24) | ((uint32_t)bytes[1] << 16) | ((uint32_t)bytes[2] << "
       "8) |\n         (uint32_t)bytes[3];\n}\n"
    << "/* The bytes of a frame of `count` words, in each direction. */\n"
    << "static inline uint32_t " << n << "frame_bytes(uint32_t count, bool crc) {\n"
    << "  return " << p << "SPI_HEADER_BYTES + " << p << "SPI_WORD_BYTES * count + (crc ? "
    << "UINT32_C(1) : UINT32_C(0));\n}\n"
    << "/* The MOSI bytes of a frame into frame[0 .. n-1], n = " << n
    << "frame_bytes(count, crc)\n * (at most " << p
    << "SPI_FRAME_MAX_BYTES): the command, a write's `count` words (a read ignores\n"
    << " * `words` and sends zeros), the CRC-8 when `crc`. Returns n; 0, with nothing written, "
       "when\n * the command cannot carry count and address. */\n"
    << "static inline uint32_t " << n
    << "encode(uint8_t *frame, bool read, uint32_t address, uint32_t count, "
       "const uint32_t *words, bool crc) {\n"
    << "  uint16_t command;\n  uint32_t k;\n  uint32_t at = " << p << "SPI_HEADER_BYTES;\n"
    << "  if (!" << n << "command(&command, read, address, count))\n    return 0;\n"
    << "  frame[0] = (uint8_t)(command >> 8);\n  frame[1] = (uint8_t)command;\n"
    << "  for (k = 0; k < count; ++k, at += " << p << "SPI_WORD_BYTES)\n"
    << "    " << n << "put_word(&frame[at], read ? UINT32_C(0) : words[k]);\n"
    << "  if (crc) {\n    frame[at] = " << n << "crc8(frame, at);\n    ++at;\n  }\n"
    << "  return at;\n}\n"
    << "/* The MISO bytes of a frame of `count` words (" << n
    << "frame_bytes(count, crc) of "
       "them):\n * *status = the previous frame's status byte, words[0 .. count-1] = the words "
       "(a\n * write's zeros; `words` may be 0 then). False, with nothing stored, for a bad "
       "count or\n * a CRC mismatch. */\n"
    << "static inline bool " << n
    << "decode(const uint8_t *frame, uint32_t count, bool crc, uint8_t *status, "
       "uint32_t *words) {\n"
    << "  const uint32_t body = " << p << "SPI_HEADER_BYTES + " << p << "SPI_WORD_BYTES * count;\n"
    << "  uint32_t k;\n"
    << "  if (count < UINT32_C(1) || count > " << p << "SPI_MAX_BURST)\n    return false;\n"
    << "  if (crc && " << n << "crc8(frame, body) != frame[body])\n    return false;\n"
    << "  *status = frame[0];\n"
    << "  for (k = 0; words != 0 && k < count; ++k)\n"
    << "    words[k] = " << n << "get_word(&frame[" << p << "SPI_HEADER_BYTES + " << p
    << "SPI_WORD_BYTES * k]);\n"
    << "  return true;\n}\n";
}

constexpr const char* kGeneratedBanner =
    "Generated by odoloc_regmap_gen from regmap/odoloc.yaml. Do not edit.";

}  // namespace

std::string emit_cpp(const RegisterMap& map) {
  std::ostringstream o;
  o << "// " << kGeneratedBanner << "\n"
    << "/* " << comment_text(map.description) << " */\n"
    << "#pragma once\n\n#include <array>\n#include <cstdint>\n#include <optional>\n#include "
       "<span>\n#include <string_view>\n\n"
    << "namespace odoloc::regs {\n\n"
    << "inline constexpr unsigned kAddressBits = " << map.address_bits << ";\n"
    << "inline constexpr unsigned kDataBits = " << map.data_bits << ";\n"
    << "inline constexpr std::uint32_t kFabricClockHz = " << map.clock_hz << ";\n"
    << "inline constexpr std::uint32_t kFabricClockPeriodNs = " << map.clock_period_ns() << ";\n\n"
    << "// The SPI interface.\nnamespace spi {\n"
    << "inline constexpr unsigned kMaxBurst = " << map.spi.max_burst
    << ";  // registers per frame\n"
    << "inline constexpr unsigned kMinLevelClocks = " << map.spi.min_level_clocks
    << ";  // fabric clocks per SCLK level, at least\n"
    << "inline constexpr std::uint32_t kMaxSclkHz = " << map.max_sclk_hz() << ";\n"
    << "inline constexpr std::uint8_t kCrcPolynomial = " << hex(map.spi.crc_polynomial, 2)
    << ";  // CRC-8\n"
    << "inline constexpr std::uint8_t kCrcInit = " << hex(map.spi.crc_init, 2) << ";\n"
    << "inline constexpr std::uint8_t kCrcXorOut = " << hex(map.spi.crc_xor_out, 2) << ";\n"
    << "// The command word: read bit, burst length - 1 above the start word address.\n"
    << "inline constexpr unsigned kCommandReadBit = " << kSpiCommandReadBit << ";\n"
    << "inline constexpr unsigned kCommandBurstShift = " << kSpiCommandBurstShift << ";\n"
    << "inline constexpr unsigned kCommandBurstBits = " << kSpiCommandBurstBits << ";\n"
    << "inline constexpr unsigned kCommandAddressBits = " << kSpiCommandAddressBits << ";\n"
    << "}  // namespace spi\n\n"
    << "// What software may do. kRpop (read pops): read only; a read frame that\n"
    << "// completes without error pops off the hardware's FIFO the elements of the\n"
    << "// register array it read whole, in order from element 0 (kPopWindows).\n"
    << "enum class Access : std::uint8_t { kRo, kRw, kW1c, kRc, kW1p, kRpop };\n"
    << "// What the hardware does with a field: reads it (configuration, pulses),\n"
    << "// drives it (status), sets it (sticky flags), counts it, or nothing\n"
    << "// (scratch, constants).\n"
    << "enum class HwAccess : std::uint8_t { kR, kW, kSet, kCount, kNone };\n\n"
    << "struct Enumerator {\n  std::string_view name;\n  std::uint32_t value;\n};\n\n"
    << "// Mask-based field helpers: get() and set() never shift by hand.\n"
    << "struct Field {\n  std::string_view name;\n  std::uint8_t lsb, width;\n  Access access;\n"
    << "  HwAccess hw;\n"
    << "  bool is_signed;\n  std::uint32_t reset;\n  std::string_view description;\n"
    << "  std::span<const Enumerator> enums;\n"
    << "  [[nodiscard]] constexpr std::uint32_t mask() const {\n"
    << "    return static_cast<std::uint32_t>(((std::uint64_t{1} << width) - 1) << lsb);\n  }\n"
    << "  [[nodiscard]] constexpr std::uint32_t get(std::uint32_t word) const {\n"
    << "    return (word & mask()) >> lsb;\n  }\n"
    << "  [[nodiscard]] constexpr std::int32_t get_signed(std::uint32_t word) const {\n"
    << "    const std::uint32_t v = get(word), sign = std::uint32_t{1} << (width - 1);\n"
    << "    return static_cast<std::int32_t>(static_cast<std::int64_t>(v ^ sign) - "
       "std::int64_t{sign});\n  }\n"
    << "  [[nodiscard]] constexpr std::uint32_t set(std::uint32_t word, std::uint32_t value) const "
       "{\n"
    << "    return (word & ~mask()) | ((value << lsb) & mask());\n  }\n};\n\n"
    << "struct Register {\n  std::string_view path;\n  std::uint16_t address;\n  Access access;\n"
    << "  bool snapshot;\n  std::uint32_t reset;\n"
    << "  std::uint32_t rw_mask, w1c_mask, w1p_mask;  // which bits a write changes, and how\n"
    << "  std::uint32_t const_mask;  // ro fields without hardware: they read their reset\n"
    << "  std::string_view description;\n  std::span<const Field> fields;\n"
    << "  std::int8_t element;      // its index in a register array; -1: not an element\n"
    << "  std::int16_t pop_window;  // rpop: its FIFO's index in kPopWindows; -1: none\n};\n\n"
    << "// An rpop register array of one block instance: the FIFO it reads, `entries`\n"
    << "// elements of `words` words each from word address `first`,\n"
    << "// element 0 the oldest entry. A read frame that completes without error\n"
    << "// pops the longest run of whole elements it read in order from element 0\n"
    << "// (each element's words lo then hi); a frame that ends in an error pops\n"
    << "// nothing.\n"
    << "struct PopWindow {\n  std::string_view path;\n  std::uint16_t first;  // element 0's first "
       "word\n"
    << "  std::uint8_t entries, words;\n};\n\n"
    << "// A word address in a pop window: the window's index in kPopWindows and the\n"
    << "// word's index from its element 0's first word (element = word / words).\n"
    << "struct PopWord {\n  std::uint16_t window, word;\n};\n\n"
    << "struct Reserved {\n  std::string_view name;\n  std::uint16_t base, size;\n};\n\n";

  // Per block: a namespace with its layout, and one namespace per register.
  for (const Block& b : map.blocks) {
    if (b.reserved)
      continue;
    o << "/* " << comment_text(b.description) << " */\nnamespace " << b.name << " {\n"
      << "inline constexpr std::uint16_t kBase = " << hex(b.base) << ";\n";
    if (!b.instances.empty()) {
      o << "inline constexpr std::uint16_t kStride = " << hex(b.stride) << ";\n"
        << "inline constexpr unsigned kInstances = " << b.instances.size() << ";\n"
        << "inline constexpr std::string_view kInstanceNames[] = {";
      for (std::size_t i = 0; i < b.instances.size(); ++i)
        o << (i ? ", " : "") << cpp_quoted(b.instances[i]);
      o << "};\n";
    }
    for (const Register& r : b.registers) {
      if (r.array_head()) {
        o << "// The register array " << r.array << "0 .. " << r.array << r.count - 1
          << ": element k's words from kOffset + k * kWords.\n"
          << "namespace " << r.array << " {\n"
          << "inline constexpr std::uint16_t kOffset = " << hex(r.offset) << ";  // element 0\n"
          << "inline constexpr unsigned kCount = " << r.count << ";\n"
          << "inline constexpr unsigned kWords = " << r.array_words
          << ";  // per element: the element stride\n";
        if (b.instances.empty()) {
          o << "constexpr std::uint16_t address(unsigned element) {\n"
            << "  return static_cast<std::uint16_t>(kBase + kOffset + element * kWords);\n}\n";
        } else {
          o << "constexpr std::uint16_t address(unsigned instance, unsigned element) {\n"
            << "  return static_cast<std::uint16_t>(kBase + instance * kStride + kOffset + element "
               "* kWords);\n}\n";
        }
        o << "}  // namespace " << r.array << "\n";
      }
      o << "namespace " << r.name << " {\n"
        << "inline constexpr std::uint16_t kOffset = " << hex(r.offset) << ";\n";
      if (b.instances.empty()) {
        o << "inline constexpr std::uint16_t kAddress = kBase + kOffset;\n";
      } else {
        o << "constexpr std::uint16_t address(unsigned instance) {\n"
          << "  return static_cast<std::uint16_t>(kBase + instance * kStride + kOffset);\n}\n";
      }
      o << "inline constexpr std::uint32_t kReset = " << hex(r.reset(), 8) << ";\n";
      for (const Field& f : r.fields) {
        if (!f.enums.empty()) {
          o << "enum class " << cpp_enum_type(f) << " : std::uint32_t {";
          for (std::size_t i = 0; i < f.enums.size(); ++i) {
            o << (i ? ", " : " ") << cpp_enumerator(f.enums[i].first) << " = " << f.enums[i].second;
          }
          o << " };\ninline constexpr Enumerator " << cpp_enum_names(f) << "[] = {";
          for (std::size_t i = 0; i < f.enums.size(); ++i) {
            o << (i ? ", " : "") << "{" << cpp_quoted(f.enums[i].first) << ", " << f.enums[i].second
              << "}";
          }
          o << "};\n";
        }
        o << "inline constexpr Field " << f.name << "{" << cpp_quoted(f.name) << ", " << f.lsb
          << ", " << f.width() << ", " << cpp_access(f.access) << ", " << cpp_hw(f.hw) << ", "
          << (f.is_signed ? "true" : "false") << ", " << f.reset << ", "
          << cpp_quoted(f.description) << ", ";
        if (f.enums.empty()) {
          o << "{}";
        } else {
          o << cpp_enum_names(f);
        }
        o << "};\n";
      }
      o << "inline constexpr Field kFields[] = {";
      for (std::size_t i = 0; i < r.fields.size(); ++i)
        o << (i ? ", " : "") << r.fields[i].name;
      o << "};\n}  // namespace " << r.name << "\n";
    }
    o << "}  // namespace " << b.name << "\n\n";
  }

  // The rpop FIFOs, by address.
  const std::vector<PopWindow> windows = pop_windows(map);
  if (windows.empty()) {  // no zero-size array
    o << "inline constexpr std::array<PopWindow, 0> kPopWindows{};\n\n";
  } else {
    o << "inline constexpr PopWindow kPopWindows[] = {\n";
    for (const PopWindow& w : windows) {
      o << "    {" << cpp_quoted(w.path) << ", " << hex(w.first, 3) << ", " << w.entries << ", "
        << w.words << "},\n";
    }
    o << "};\n\n";
  }
  // The pop window a word address lies in, -1 for none.
  const auto window_of = [&](std::uint32_t address) {
    for (std::size_t i = 0; i < windows.size(); ++i) {
      const PopWindow& w = windows[i];
      if (address >= w.first && address - w.first < static_cast<std::uint32_t>(w.entries * w.words))
        return static_cast<int>(i);
    }
    return -1;
  };

  o << "// Every register instance, by address.\ninline constexpr Register kRegisters[] = {\n";
  for (const RegisterInstance& ri : flatten(map)) {
    const Register& r = *ri.reg;
    o << "    {" << cpp_quoted(ri.path) << ", " << hex(ri.address, 3) << ", "
      << cpp_access(r.access) << ", " << (r.snapshot ? "true" : "false") << ", "
      << hex(r.reset(), 8) << ", " << hex(r.mask(Access::kRw), 8) << ", "
      << hex(r.mask(Access::kW1c), 8) << ", " << hex(r.mask(Access::kW1p), 8) << ", "
      << hex(r.const_mask(), 8) << ", " << cpp_quoted(r.description) << ", " << ri.block->name
      << "::" << r.name << "::kFields, " << (r.array.empty() ? -1 : r.element) << ", "
      << window_of(ri.address) << "},\n";
  }
  o << "};\n\n";
  bool any = false;
  for (const Block& b : map.blocks)
    any = any || b.reserved;
  if (any) {
    o << "inline constexpr Reserved kReserved[] = {";
    const char* sep = "";
    for (const Block& b : map.blocks) {
      if (!b.reserved)
        continue;
      o << sep << "{" << cpp_quoted(b.name) << ", " << hex(b.base) << ", " << hex(b.size) << "}";
      sep = ", ";
    }
    o << "};\n\n";
  } else {  // no zero-size array
    o << "inline constexpr std::array<Reserved, 0> kReserved{};\n\n";
  }
  o << "// The register at an address; nullptr when unmapped.\n"
    << "constexpr const Register* find(std::uint32_t address) {\n"
    << "  for (const Register& r : kRegisters) {\n"
    << "    if (r.address == address) return &r;\n  }\n  return nullptr;\n}\n"
    << "// The register with a dotted path (\"eppm.left_rear.cfg\"); nullptr when unknown.\n"
    << "constexpr const Register* find(std::string_view path) {\n"
    << "  for (const Register& r : kRegisters) {\n"
    << "    if (r.path == path) return &r;\n  }\n  return nullptr;\n}\n"
    << "// Where a word address lies in the rpop FIFOs; nullopt outside them.\n"
    << "constexpr std::optional<PopWord> find_pop_word(std::uint32_t address) {\n"
    << "  for (std::size_t i = 0; i < std::size(kPopWindows); ++i) {\n"
    << "    const PopWindow& w = kPopWindows[i];\n"
    << "    if (address >= w.first && address - w.first < std::uint32_t{w.entries} * w.words)\n"
    << "      return PopWord{static_cast<std::uint16_t>(i), static_cast<std::uint16_t>(address - "
       "w.first)};\n"
    << "  }\n  return std::nullopt;\n}\n\n"
    << "}  // namespace odoloc::regs\n";
  return o.str();
}

std::string emit_c(const RegisterMap& map) {
  const std::string p = c_prefix(map);
  std::ostringstream o;
  o << "/* " << kGeneratedBanner << " */\n/* " << comment_text(map.description) << " */\n"
    << "/* C99 or later (stdint.h: uint32_t, UINT32_C); C++ too. Every constant is\n"
    << " * a 32-bit unsigned (UINT32_C) and every helper computes in uint32_t (uint64_t\n"
    << " * for values of two words), also where unsigned int has 16 bits (AVR, MSP430).\n"
    << " * Freestanding: no library function is called. */\n"
    << "#ifndef " << p << "REGS_H\n#define " << p << "REGS_H\n\n#include <stdbool.h>\n"
    << "#include <stdint.h>\n\n"
    << "#define " << p << "ADDRESS_BITS " << u32(static_cast<std::uint32_t>(map.address_bits))
    << "\n"
    << "#define " << p << "DATA_BITS " << u32(static_cast<std::uint32_t>(map.data_bits)) << "\n"
    << "#define " << p << "REGISTER_COUNT " << u32(static_cast<std::uint32_t>(flatten(map).size()))
    << "\n"
    << "#define " << p << "FABRIC_CLOCK_HZ " << u32(map.clock_hz) << "\n"
    << "#define " << p << "FABRIC_CLOCK_PERIOD_NS " << u32(map.clock_period_ns()) << "\n"
    << "#define " << p << "SPI_MAX_BURST " << u32(static_cast<std::uint32_t>(map.spi.max_burst))
    << "\n"
    << "#define " << p << "SPI_MIN_LEVEL_CLOCKS "
    << u32(static_cast<std::uint32_t>(map.spi.min_level_clocks)) << "\n"
    << "#define " << p << "SPI_MAX_SCLK_HZ " << u32(map.max_sclk_hz()) << "\n"
    << "#define " << p << "SPI_CRC_POLYNOMIAL " << u32(map.spi.crc_polynomial, 2) << "\n"
    << "#define " << p << "SPI_CRC_INIT " << u32(map.spi.crc_init, 2) << "\n"
    << "#define " << p << "SPI_CRC_XOR_OUT " << u32(map.spi.crc_xor_out, 2) << "\n\n";
  for (const RegisterInstance& ri : flatten(map)) {
    o << "#define " << c_address(map, ri) << " " << u32(ri.address, 3) << "\n";
  }
  for (const Block& b : map.blocks) {
    const std::string blk = c_block(map, b);
    if (b.reserved) {
      o << "\n/* " << b.name << ": reserved " << hex(b.base, 3) << ".."
        << hex(b.base + b.size - 1, 3) << " */\n#define " << blk << "_RESERVED_BASE "
        << u32(b.base, 3) << "\n"
        << "#define " << blk << "_RESERVED_SIZE " << u32(b.size, 3) << "\n";
      continue;
    }
    o << "\n/* " << b.name << ": " << comment_text(b.description) << " */\n";
    if (!b.instances.empty()) {
      o << "#define " << blk << "_BASE " << u32(b.base, 3) << "\n"
        << "#define " << blk << "_STRIDE " << u32(b.stride, 3) << "\n"
        << "#define " << blk << "_INSTANCES " << u32(static_cast<std::uint32_t>(b.instances.size()))
        << "\n";
    }
    for (const Register& r : b.registers) {
      if (r.array_head()) {  // element k's words from OFFSET + k * WORDS
        const std::string arr = c_array(map, b, r);
        o << "#define " << arr << "_OFFSET " << u32(r.offset, 1) << "\n"
          << "#define " << arr << "_COUNT " << u32(static_cast<std::uint32_t>(r.count)) << "\n"
          << "#define " << arr << "_WORDS " << u32(static_cast<std::uint32_t>(r.array_words))
          << "\n";
      }
      const std::string reg = c_register(map, b, r);
      o << "#define " << reg << "_OFFSET " << u32(r.offset, 1) << "\n"
        << "#define " << reg << "_RESET " << u32(r.reset(), 8) << "\n";
      for (const Field& f : r.fields) {
        const std::string fld = c_field(map, b, r, f);
        o << "#define " << fld << "_SHIFT " << u32(static_cast<std::uint32_t>(f.lsb)) << "\n"
          << "#define " << fld << "_MASK " << u32(f.mask(), 8) << "\n";
        for (const auto& [name, value] : f.enums)
          o << "#define " << c_enumerator(map, b, r, f, name) << " " << u32(value) << "\n";
        const std::string fn = c_function(map, b, r, f);
        o << "static inline uint32_t " << fn << "_get(uint32_t word) {\n"
          << "  return (uint32_t)((word & " << fld << "_MASK) >> " << fld << "_SHIFT);\n}\n"
          << "static inline uint32_t " << fn << "_set(uint32_t word, uint32_t value) {\n"
          << "  return (uint32_t)((word & (uint32_t)~" << fld << "_MASK) | (((uint32_t)value << "
          << fld << "_SHIFT) & " << fld << "_MASK));\n}\n";
        if (f.is_signed) {  // two's complement: the field's value with its sign
          o << "static inline int32_t " << c_get_signed(map, b, r, f) << "(uint32_t word) {\n"
            << "  const uint32_t v = " << fn << "_get(word);\n"
            << "  return " << c_sign_extend("v", f.width(), false) << ";\n}\n";
        }
      }
    }
  }
  const std::vector<SplitField> split = split_fields(map);
  if (!split.empty())
    o << "\n/* Fields in both words of a two-word register. */\n";
  for (const SplitField& s : split)
    emit_c_split_field(o, map, s);
  emit_c_spi(o, map);
  o << "\n#endif /* " << p << "REGS_H */\n";
  return o.str();
}

// The SystemRDL properties that give a field its hardware semantics.
std::string rdl_properties(const Field& f) {
  switch (f.access) {
    case Access::kRo:  // a constant reads its reset value; status is a wire
      return f.hw == Hw::kNone ? "sw = r; hw = na;" : "sw = r; hw = w;";
    case Access::kRw:  // configuration, or scratch storage
      return f.hw == Hw::kR ? "sw = rw; hw = r;" : "sw = rw; hw = na;";
    case Access::kW1c:  // sticky: a hardware event sets it, beating a clear in the same clock
      return "sw = rw; hw = r; hwset; onwrite = woclr; precedence = hw;";
    case Access::kRc:  // a saturating event counter, cleared by reading it
      return "sw = r; hw = r; counter; incrsaturate; onread = rclr;";
    case Access::kW1p:  // one-clock pulse, reads 0; SystemRDL's singlepulse is 1 bit wide, so
                        // wider fields pulse the written bits while swmod strobes
      return f.width() == 1 ? "sw = w; hw = r; singlepulse;" : "sw = w; hw = r; swmod = true;";
    case Access::kRpop:  // the head of a FIFO: a wire, and a strobe when software reads it
      return "sw = r; hw = w; swacc = true;";
  }
  return "";
}

// What an rpop register does, in the outputs' prose.
constexpr const char* kRpopText =
    "Read pops (rpop): a read frame that completes without error pops off the hardware's FIFO "
    "one entry per whole element of this array it read in order from element 0 (the oldest "
    "entry), each element's words lo then hi; a frame that ends in an error pops nothing. "
    "Writes are refused.";

std::string emit_systemrdl(const RegisterMap& map) {
  std::ostringstream o;
  o << "// " << kGeneratedBanner << "\n"
    << "// SystemRDL is byte addressed: every 32-bit register at word address a\n"
    << "// sits at byte address 4a. Blocks are regfiles, one instance per block\n"
    << "// instance (eppm_left_rear, ...).\n"
    << "addrmap " << map.name << " {\n  name = " << quoted(map.name) << ";\n  desc = "
    << quoted(map.description + ". Fabric clock " + std::to_string(map.clock_hz) + " Hz.")
    << ";\n  default regwidth = " << map.data_bits << ";\n"
    << "  default accesswidth = " << map.data_bits << ";\n";
  for (const Block& b : map.blocks) {
    if (b.reserved)
      continue;
    o << "\n  regfile " << rdl_block_type(b) << " {\n    desc = " << quoted(b.description) << ";\n";
    for (const Register& r : b.registers) {
      for (const Field& f : r.fields) {
        if (f.enums.empty())
          continue;
        o << "    enum " << rdl_enum_type(r, f) << " {";
        for (const auto& [name, value] : f.enums)
          o << " " << name << " = " << f.width() << "'d" << value << ";";
        o << " };\n";
      }
    }
    for (const Register& r : b.registers) {
      std::string desc = r.description;
      if (r.snapshot) {
        desc +=
            " Snapshot: captured with every other snapshot register when a read frame "
            "starts, so a burst over them never tears.";
      }
      if (r.access == Access::kRpop)
        desc += std::string(" ") + kRpopText + " swacc strobes each read word.";
      o << "    reg {\n      desc = " << quoted(desc) << ";\n";
      for (const Field& f : r.fields) {
        const std::string kind =
            std::string(f.access == Access::kRpop ? "Read pops. " : "") +
            (f.access == Access::kW1p && f.width() > 1
                 ? "Write 1s for a one-clock pulse on those bits: the written value, valid while "
                   "swmod strobes. "
                 : "") +
            (f.is_signed ? "Signed. " : "");
        o << "      field { desc = " << quoted(kind + f.description) << "; " << rdl_properties(f);
        if (!f.enums.empty())
          o << " encode = " << rdl_enum_type(r, f) << ";";
        o << " } " << f.name << "[" << f.msb << ":" << f.lsb << "] = " << hex(f.reset) << ";\n";
      }
      o << "    } " << r.name << " @ " << hex(4 * r.offset) << ";\n";
    }
    o << "  };\n";
    if (b.instances.empty()) {
      o << "  " << rdl_block_type(b) << " " << rdl_instance(b, 0) << " @ " << hex(4 * b.base)
        << ";\n";
    } else {
      for (std::size_t i = 0; i < b.instances.size(); ++i) {
        o << "  " << rdl_block_type(b) << " " << rdl_instance(b, i) << " @ "
          << hex(4 * (b.base + static_cast<std::uint32_t>(i) * b.stride)) << ";\n";
      }
    }
  }
  o << "};\n";
  return o.str();
}

std::string emit_markdown(const RegisterMap& map) {
  std::ostringstream o;
  o << "# Register map\n\n<!-- " << kGeneratedBanner << " -->\n\n"
    << markdown_text(map.description) << ". " << map.data_bits << "-bit registers at "
    << map.address_bits
    << "-bit word addresses. Access: `ro` read only, `rw` read/write, `w1c` write 1 to "
       "clear, `rc` read to clear, `w1p` write 1 for a one-clock pulse, `rpop` read pops (read "
       "only: a read frame that completes without error pops off the hardware's FIFO the "
       "elements of the register array it read whole, in order from element 0, the oldest "
       "entry; a frame that ends in an error pops nothing). Registers marked "
       "*snapshot* are captured together when a read frame starts. Hardware (`hw`): `r` the "
       "fabric reads the value (configuration) or the pulse, `w` the fabric drives it (live "
       "status), `set` a fabric event sets the sticky flag (it wins over a clear in the same "
       "clock), `count` the fabric counts events (saturating), `none` no connection (scratch "
       "storage, or a constant that reads its reset value). Registers ending in `_lo`/`_hi` "
       "are the two words of one wide value. A register array `name[N]` is the registers "
       "`name0` … `nameN-1` (element k of name[N]), element k at the array's offset + k × "
       "its words per element.\n\n"
    << "Fabric clock " << map.clock_hz << " Hz (" << map.clock_period_ns() << " ns). SPI: at most "
    << map.spi.max_burst << " registers per frame, SCLK levels of at "
    << "least " << map.spi.min_level_clocks << " fabric clocks (SCLK up to " << map.max_sclk_hz()
    << " Hz), CRC-8 polynomial " << hex(map.spi.crc_polynomial, 2) << ", init "
    << hex(map.spi.crc_init, 2) << ", final XOR " << hex(map.spi.crc_xor_out, 2) << ".\n\n"
    << "| address | register | access | reset | description |\n|---|---|---|---|---|\n";
  for (const RegisterInstance& ri : flatten(map)) {
    o << "| " << hex(ri.address, 3) << " | `" << ri.path << "` | " << to_string(ri.reg->access)
      << (ri.reg->snapshot ? ", snapshot" : "") << " | " << hex(ri.reg->reset(), 8) << " | "
      << markdown_text(ri.reg->description) << " |\n";
  }
  for (const Block& b : map.blocks) {
    if (b.reserved) {
      o << "| " << hex(b.base, 3) << "–" << hex(b.base + b.size - 1, 3) << " | *" << b.name
        << "* | reserved | | " << markdown_text(b.description) << " |\n";
    }
  }
  for (const Block& b : map.blocks) {
    if (b.reserved)
      continue;
    o << "\n## " << b.name << "\n\n" << markdown_text(b.description) << " Base " << hex(b.base, 3);
    if (!b.instances.empty()) {
      o << ", " << b.instances.size() << " instances every " << hex(b.stride) << " words: ";
      for (std::size_t i = 0; i < b.instances.size(); ++i)
        o << (i ? ", " : "") << "`" << b.instances[i] << "`";
    }
    o << ".\n";
    for (const Register& r : b.registers) {
      if (r.array.empty()) {
        o << "\n### " << b.name << "." << r.name << " (offset " << hex(r.offset) << ")\n\n"
          << markdown_text(r.description);
      } else if (r.element == 0) {  // one section for every element's word
        const std::string word = r.name.substr(r.array.size() + 1);  // "_lo", "" (after '0')
        o << "\n### " << b.name << "." << r.name << " … " << r.array << r.count - 1 << word
          << " (offset " << hex(r.offset) << " + "
          << (r.array_words == 1 ? std::string() : std::to_string(r.array_words)) << "k, k = 0.."
          << r.count - 1 << ")\n\n"
          << markdown_text(r.array_description) << (r.array_description.empty() ? "" : " ")
          << "Element k of the register array " << r.array << "[" << r.count << "]."
          << (r.access == Access::kRpop ? std::string(" ") + kRpopText : "");
      } else {
        continue;
      }
      o << "\n\n| bits | field | access | hw | reset | description |\n|---|---|---|---|---|---|\n";
      for (const Field& f : r.fields) {
        o << "| " << f.msb;
        if (f.msb != f.lsb)
          o << ":" << f.lsb;
        o << " | `" << f.name << "` | " << to_string(f.access) << " | " << to_string(f.hw) << " | "
          << f.reset << " | " << (f.is_signed ? "Signed. " : "") << markdown_text(f.description);
        if (!f.enums.empty()) {
          o << " Values:";
          for (const auto& [name, value] : f.enums)
            o << " `" << name << "` = " << value << ";";
        }
        o << " |\n";
      }
    }
  }
  return o.str();
}

}  // namespace odoloc::regmap
