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

enum class Access : std::uint8_t { kRo, kRw, kW1c, kRc, kW1p };
const char* to_string(Access a);

struct Field {
  std::string name;
  int msb = 0, lsb = 0;
  Access access = Access::kRo;
  std::uint32_t reset = 0;  // the field's raw bits
  bool is_signed = false;
  std::string description;
  std::vector<std::pair<std::string, std::uint32_t>> enums;
  [[nodiscard]] int width() const { return msb - lsb + 1; }
  [[nodiscard]] std::uint32_t mask() const;  // in the register
};

struct Register {
  std::string name;
  std::uint32_t offset = 0;
  Access access = Access::kRo;
  bool snapshot = false;
  std::string description;
  std::vector<Field> fields;
  [[nodiscard]] std::uint32_t reset() const;
  [[nodiscard]] std::uint32_t mask(Access a) const;  // the bits of fields with access a
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

struct RegisterMap {
  std::string name, description;
  int address_bits = 0;
  int data_bits = 0;
  std::vector<Block> blocks;
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

// Parses and checks: duplicate names, overlapping addresses or fields, fields
// outside the data width, resets and enum values that do not fit their field.
RegisterMap parse(const std::string& yaml_text);
RegisterMap load(const std::string& path);
// Every register instance, by address.
std::vector<RegisterInstance> flatten(const RegisterMap& map);

// The generated artefacts.
std::string emit_cpp(const RegisterMap& map);
std::string emit_c(const RegisterMap& map);
std::string emit_systemrdl(const RegisterMap& map);
std::string emit_markdown(const RegisterMap& map);

}  // namespace odoloc::regmap
