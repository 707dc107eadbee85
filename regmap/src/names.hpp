// The identifiers the emitters write, built in one place: the emitters use
// these functions, and check_generated_names() (names.cpp) builds every
// identifier of every output from the same functions and refuses reserved
// words and collisions before anything is written.
#pragma once

#include <map>
#include <string>
#include <string_view>

#include "odoloc/regmap/regmap.hpp"
#include "text.hpp"

namespace odoloc::regmap {

// ---- C (odoloc_regs.h): one namespace, macros upper case ------------------

// "ODOLOC_": the prefix of every macro.
inline std::string c_prefix(const RegisterMap& m) {
  return upper(m.name) + "_";
}
// "ODOLOC_EPPM": a block's macros (BASE, STRIDE, INSTANCES, RESERVED_*).
inline std::string c_block(const RegisterMap& m, const Block& b) {
  return c_prefix(m) + upper(b.name);
}
// "ODOLOC_EPPM_CFG": a register's macros (OFFSET, RESET).
inline std::string c_register(const RegisterMap& m, const Block& b, const Register& r) {
  return c_block(m, b) + "_" + upper(r.name);
}
// "ODOLOC_TOF_CHANNEL_ENTRY": a register array's macros (OFFSET, COUNT, WORDS).
inline std::string c_array(const RegisterMap& m, const Block& b, const Register& r) {
  return c_block(m, b) + "_" + upper(r.array);
}
// "ODOLOC_EPPM_CFG_DECODE_MODE": a field's macros (SHIFT, MASK, enumerators).
inline std::string c_field(const RegisterMap& m, const Block& b, const Register& r,
                           const Field& f) {
  return c_register(m, b, r) + "_" + upper(f.name);
}
// "ODOLOC_EPPM_CFG_DECODE_MODE_X2": an enumerator.
inline std::string c_enumerator(const RegisterMap& m, const Block& b, const Register& r,
                                const Field& f, const std::string& e) {
  return c_field(m, b, r, f) + "_" + upper(e);
}
// "ODOLOC_EPPM_LEFT_REAR_CFG_ADDR": a register instance's address.
inline std::string c_address(const RegisterMap& m, const RegisterInstance& ri) {
  return c_prefix(m) + ri.macro + "_ADDR";
}
// "odoloc_eppm_cfg_decode_mode": the field's _get/_set functions.
inline std::string c_function(const RegisterMap& m, const Block& b, const Register& r,
                              const Field& f) {
  return m.name + "_" + b.name + "_" + r.name + "_" + f.name;
}

// ---- C++ (odoloc/regs.hpp, odoloc/ports.hpp) ------------------------------

// A field's enum class in its register's namespace: "decode_mode" -> "DecodeMode".
inline std::string cpp_enum_type(const Field& f) {
  return camel(f.name);
}
// Its table of names: "kDecodeModeNames".
inline std::string cpp_enum_names(const Field& f) {
  std::string out = "k";  // (appends: GCC 12 -O3 warns falsely on "literal" + string)
  return out.append(camel(f.name)).append("Names");
}
// An enumerator: "x2" -> "kX2".
inline std::string cpp_enumerator(const std::string& e) {
  std::string out = "k";
  return out.append(camel(e));
}
// ports.hpp: a register's nested struct type, "cfg" -> "CfgReg".
inline std::string ports_register_type(const std::string& port_name) {
  return camel(port_name) + "Reg";
}
// ports.hpp: per field name, how many registers of the block give it an enum
// (a register array's elements count once, as element 0).
inline std::map<std::string, int> ports_enum_uses(const Block& b) {
  std::map<std::string, int> uses;
  for (const Register& r : b.registers) {
    if (r.element != 0)
      continue;
    for (const Field& f : r.fields)
      uses[f.name] += f.enums.empty() ? 0 : 1;
  }
  return uses;
}
// ports.hpp: a field enum's alias in the block namespace; `clash`: another
// field of the block with the same name has an enum too (then the register
// names it: a register array's elements by the array, "e3_lo" -> "ELo").
inline std::string ports_enum_alias(const Register& r, const Field& f, bool clash) {
  const std::string reg =
      r.array.empty() ? r.name
                      : r.array + r.name.substr(r.array.size() + std::to_string(r.element).size());
  return clash ? camel(reg) + camel(f.name) : camel(f.name);
}

// ---- SystemRDL (odoloc.rdl) -----------------------------------------------

inline std::string rdl_block_type(const Block& b) {
  return b.name + "_t";
}
inline std::string rdl_enum_type(const Register& r, const Field& f) {
  return r.name + "_" + f.name + "_e";
}
inline std::string rdl_instance(const Block& b, std::size_t instance) {
  return b.instances.empty() ? b.name : b.name + "_" + b.instances[instance];
}

// ---- Text ---------------------------------------------------------------

// Text inside a C or C++ /* */ comment: no "*/" or "/*" survive.
inline std::string comment_text(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    out += s[i];
    if (i + 1 < s.size() && ((s[i] == '*' && s[i + 1] == '/') || (s[i] == '/' && s[i + 1] == '*')))
      out += ' ';
  }
  return out;
}

// Text in a Markdown table cell or paragraph: `|` and `\` escaped (a row
// never splits), and a `<` that could open HTML (`<!--`, `<br>`) as &lt;.
inline std::string markdown_text(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    const char next = i + 1 < s.size() ? s[i + 1] : '\0';
    if (c == '<' && (std::isalpha(static_cast<unsigned char>(next)) != 0 || next == '!' ||
                     next == '/' || next == '?')) {
      out += "&lt;";
      continue;
    }
    if (c == '|' || c == '\\')
      out += '\\';
    out += c;
  }
  return out;
}

// The languages whose reserved words a generated identifier must avoid.
enum class Language : std::uint8_t { kC, kCpp, kRdl };
// Why `id` cannot be an identifier of `lang` (a keyword, a standard macro, a
// reserved prefix), or nullptr when it can. The word lists are in reserved.cpp.
const char* reserved_reason(Language lang, std::string_view id);

// Every identifier of every output, checked for reserved words and for
// collisions per namespace; throws RegmapError naming both YAML paths.
void check_generated_names(const RegisterMap& map);

}  // namespace odoloc::regmap
