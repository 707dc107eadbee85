// The register description (regmap/odoloc.yaml) as data: parsed, checked and
// flattened into one entry per register instance. The generator emits the
// C++ header, the C header, SystemRDL and the Markdown documentation from it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace odoloc::regmap {

// A description that cannot be generated: says where and why.
class RegmapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What software may do: ro, rw, w1c (write 1 to clear), rc (read to clear),
// w1p (write 1 for a one-clock pulse), rpop (read pops: read only, and a read
// frame that completes without error pops the elements of the register array
// it read in order from element 0 off the hardware's FIFO).
enum class Access : std::uint8_t { kRo, kRw, kW1c, kRc, kW1p, kRpop };
const char* to_string(Access a);

// What the hardware does with a field (OpenTitan hwaccess, SystemRDL hw):
//   r      reads the stored value (configuration) or the pulse (w1p)
//   w      drives the value (live status)
//   set    sets a sticky flag on an event; software clears it (w1c)
//   count  increments a counter (rc)
//   none   no connection: scratch storage, or a constant (ro: the reset value)
// Legal with each access: rw {r, none}, ro {w, none}, w1c {set}, rc {count},
// w1p {r}, rpop {w}.
enum class Hw : std::uint8_t { kR, kW, kSet, kCount, kNone };
const char* to_string(Hw h);

struct Field {
  std::string name;
  int msb = 0, lsb = 0;
  Access access = Access::kRo;
  Hw hw = Hw::kNone;
  std::uint32_t reset = 0;  // the field's raw bits
  bool is_signed = false;
  std::string description;
  std::vector<std::pair<std::string, std::uint32_t>> enums;
  // The hardware port this field (or slice of a wide field) belongs to: its
  // width and signedness, which bit of the port the field's lsb carries, and
  // the port's reset. For a field of a one-word register: the field itself.
  int port_width = 0, port_shift = 0;
  bool port_signed = false;
  std::uint64_t port_reset = 0;
  [[nodiscard]] int width() const { return msb - lsb + 1; }
  [[nodiscard]] std::uint32_t mask() const;  // in the register
};

struct Register {
  std::string name;
  std::uint32_t offset = 0;
  Access access = Access::kRo;
  Hw hw = Hw::kNone;  // the fields' default
  bool snapshot = false;
  std::string description;
  std::vector<Field> fields;
  // A word of a `words: 2` register: the wide register's name, its
  // description, and which word this is (0: bits 31:0, 1: bits 63:32).
  std::string wide;
  std::string wide_description;
  int word = 0;
  // A word of element `element` of a `count: N` register array (the element
  // registers <array>0 .. <array>N-1 at offset + k * array_words): the
  // array's name, this word's description without the element, N, and the
  // words per element (the element stride). Empty `array`: not an element.
  std::string array;
  std::string array_description;
  int count = 0, element = 0, array_words = 0;
  [[nodiscard]] std::uint32_t reset() const;
  [[nodiscard]] std::uint32_t mask(Access a) const;  // the bits of fields with access a
  [[nodiscard]] std::uint32_t mask(Hw h) const;      // the bits of fields with hw h
  [[nodiscard]] std::uint32_t const_mask() const;    // ro fields with hw none: constants
  // The name of the hardware port group: the array name for an element, the
  // wide name for a word register.
  [[nodiscard]] const std::string& port_name() const {
    return !array.empty() ? array : wide.empty() ? name : wide;
  }
  // The port group as a member expression: "entry[5]" for an element.
  [[nodiscard]] std::string port_member() const {
    return array.empty() ? port_name() : array + "[" + std::to_string(element) + "]";
  }
  // The first word of element 0: where an array is declared once.
  [[nodiscard]] bool array_head() const { return !array.empty() && element == 0 && word == 0; }
  // The offset of element 0's first word.
  [[nodiscard]] std::uint32_t array_offset() const {
    return offset - static_cast<std::uint32_t>(element * array_words + word);
  }
};

struct Block {
  std::string name;
  std::uint32_t base = 0;
  std::uint32_t stride = 0;
  std::uint32_t size = 0;  // reserved blocks only
  bool reserved = false;
  std::vector<std::string> instances;  // empty: a single instance
  std::string description;
  std::vector<Register> registers;
};

// The SPI interface's global facts.
struct Spi {
  int max_burst = 0;         // registers per frame (the frame's 5-bit burst field: 1..32)
  int min_level_clocks = 0;  // fabric clocks SCLK must stay at each level
  std::uint8_t crc_polynomial = 0, crc_init = 0, crc_xor_out = 0;  // CRC-8
};

struct RegisterMap {
  std::string name, description;
  int address_bits = 0;
  int data_bits = 0;
  std::uint32_t clock_hz = 0;  // the fabric clock
  Spi spi;
  std::vector<Block> blocks;
  [[nodiscard]] std::uint32_t clock_period_ns() const { return 1000000000U / clock_hz; }
  [[nodiscard]] std::uint32_t max_sclk_hz() const {
    return clock_hz / (2U * static_cast<std::uint32_t>(spi.min_level_clocks));
  }
};

// One register at one address.
struct RegisterInstance {
  std::string path;   // "eppm.left_rear.cfg", "top.id"
  std::string macro;  // "EPPM_LEFT_REAR_CFG"
  std::uint32_t address = 0;
  const Block* block = nullptr;
  const Register* reg = nullptr;
  int instance = -1;  // index into block->instances, -1 for single blocks
};

// The FIFO behind one rpop register array in one block instance: `entries`
// elements of `words` words from word address `first` (element 0's first word).
struct PopWindow {
  std::string path;  // "tof_channel.rx3.entry"
  std::uint32_t first = 0;
  int entries = 0, words = 0;
  const Block* block = nullptr;
  const Register* head = nullptr;  // element 0's first word
  int instance = -1;
};

// Parses and checks: duplicate names, overlapping addresses or fields, fields
// outside the data width, resets and enum values that do not fit their field,
// illegal (access, hw) pairs, bad clock or SPI facts, rpop rules. Expands
// every `count: N` register into its elements <name>0 .. <name>N-1, and
// every `words: 2` register (or element) into its `_lo` and `_hi` words.
RegisterMap parse(const std::string& yaml_text);
RegisterMap load(const std::string& path);
// Every register instance, by address.
std::vector<RegisterInstance> flatten(const RegisterMap& map);
// Every rpop array of every block instance, by address.
std::vector<PopWindow> pop_windows(const RegisterMap& map);

// The generated artefacts.
std::string emit_cpp(const RegisterMap& map);
// odoloc/ports.hpp: typed register <-> hardware port structs, decode/encode.
std::string emit_ports(const RegisterMap& map);
// odoloc/logic/ports.hpp: the same port structs over an integer-type family,
// C++14, for the blocks' logic and the HLS kernels.
std::string emit_logic_ports(const RegisterMap& map);
// odoloc/logic/regfile_map.hpp: the same facts as emit_cpp in plain C++14, for the
// HLS kernels (constexpr integers and tables).
std::string emit_hls(const RegisterMap& map);
std::string emit_c(const RegisterMap& map);
std::string emit_systemrdl(const RegisterMap& map);
std::string emit_markdown(const RegisterMap& map);

}  // namespace odoloc::regmap
