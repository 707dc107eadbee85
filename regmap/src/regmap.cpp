#include "odoloc/regmap/regmap.hpp"

#include <algorithm>
#include <fstream>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include "names.hpp"
#include "odoloc/yaml/one_document.hpp"
#include "text.hpp"

namespace odoloc::regmap {

namespace {

[[noreturn]] void fail(const YAML::Node& at, const std::string& what) {
  throw RegmapError("line " + std::to_string(at.Mark().line + 1) + ": " + what);
}

YAML::Node required(const YAML::Node& node, const char* key, const std::string& where) {
  YAML::Node found = node[key];
  if (!found)
    fail(node, where + ": missing '" + key + "'");
  return found;
}

template <class T>
T scalar(const YAML::Node& node, const std::string& what) {
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    fail(node, what + ": not a valid value");
  }
}

// The length of the UTF-8 sequence starting at s[i], 0 when invalid.
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  std::size_t n = 0;
  std::uint32_t cp = 0;
  if (c < 0x80)
    return 1;
  if ((c & 0xE0U) == 0xC0U) {
    n = 2;
    cp = c & 0x1FU;
  } else if ((c & 0xF0U) == 0xE0U) {
    n = 3;
    cp = c & 0x0FU;
  } else if ((c & 0xF8U) == 0xF0U) {
    n = 4;
    cp = c & 0x07U;
  } else {
    return 0;
  }
  if (i + n > s.size())
    return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0U) != 0x80U)
      return 0;
    cp = (cp << 6) | (byte(i + k) & 0x3FU);
  }
  const std::uint32_t min = n == 2 ? 0x80U : n == 3 ? 0x800U : 0x10000U;
  if (cp < min || cp > 0x10FFFFU || (cp >= 0xD800U && cp <= 0xDFFFU))
    return 0;
  if (cp >= 0x80U && cp < 0xA0U)  // C1 control characters
    return 0;
  return n;
}

// A description: one paragraph of UTF-8 text. Line breaks (a YAML block
// scalar) and tabs become single spaces; other control characters and
// invalid UTF-8 are refused. The emitters escape what each language needs.
std::string text(const YAML::Node& node, const char* key, const std::string& where) {
  if (!node[key])
    return {};
  const auto raw = scalar<std::string>(node[key], where + " " + key);
  std::string out;
  bool space = false;
  for (std::size_t i = 0; i < raw.size();) {
    const char c = raw[i];
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      space = !out.empty();
      ++i;
      continue;
    }
    const std::size_t n = utf8_length(raw, i);
    if (n == 0 || static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
      fail(node[key], where + ": the " + std::string(key) +
                          " holds a control character or invalid UTF-8 at byte " +
                          std::to_string(i));
    }
    if (space)
      out += ' ';
    space = false;
    out.append(raw, i, n);
    i += n;
  }
  return out;
}

// a-z first, then a-z, 0-9 and single underscores, not at the end: joined
// with '_' (C macros, SystemRDL instances) a name never makes "__".
bool is_identifier(const std::string& s) {
  if (s.empty() || std::islower(static_cast<unsigned char>(s[0])) == 0 || s.back() == '_' ||
      s.find("__") != std::string::npos)
    return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::islower(static_cast<unsigned char>(c)) != 0 ||
           std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '_';
  });
}

void check_name(const YAML::Node& at, const std::string& name, const std::string& what) {
  if (!is_identifier(name)) {
    fail(at, what + " '" + name +
                 "': names are lower_snake_case identifiers (a-z first, then a-z, 0-9 and single "
                 "underscores, not at the end)");
  }
}

void check_unique(std::set<std::string>& seen, const YAML::Node& at, const std::string& name,
                  const std::string& what, const std::string& where = {}) {
  if (!seen.insert(name).second) {
    fail(at, "duplicate " + what + " '" + name + "'" + (where.empty() ? "" : " in " + where));
  }
}

// Rejects keys the schema does not know: a typo, or an unquoted comma in a
// flow-style value, which YAML reads as the start of another key.
void check_keys(const YAML::Node& n, std::initializer_list<std::string_view> known,
                const std::string& where) {
  if (!n.IsMap())
    fail(n, where + ": expected a mapping");
  std::set<std::string> seen;
  for (const auto& kv : n) {
    const auto key = scalar<std::string>(kv.first, where + " key");
    if (std::find(known.begin(), known.end(), key) == known.end())
      fail(kv.first,
           where + ": unknown key '" + key + "' (quote values that contain a comma or a colon)");
    if (!seen.insert(key).second)
      fail(kv.first, where + ": key '" + key + "' given twice");
  }
}

Access access_of(const YAML::Node& node, const std::string& where) {
  const auto name = scalar<std::string>(node, where);
  for (const Access a :
       {Access::kRo, Access::kRw, Access::kW1c, Access::kRc, Access::kW1p, Access::kRpop}) {
    if (name == to_string(a))
      return a;
  }
  fail(node, where + ": unknown access '" + name + "'");
}

Hw hw_of(const YAML::Node& node, const std::string& where) {
  const auto name = scalar<std::string>(node, where);
  for (const Hw h : {Hw::kR, Hw::kW, Hw::kSet, Hw::kCount, Hw::kNone}) {
    if (name == to_string(h))
      return h;
  }
  fail(node, where + ": unknown hw '" + name + "' (r, w, set, count or none)");
}

// The hardware behaviours that make sense for each software access.
bool legal(Access a, Hw h) {
  switch (a) {
    case Access::kRw:
      return h == Hw::kR || h == Hw::kNone;
    case Access::kRo:
      return h == Hw::kW || h == Hw::kNone;
    case Access::kW1c:
      return h == Hw::kSet;
    case Access::kRc:
      return h == Hw::kCount;
    case Access::kW1p:
      return h == Hw::kR;
    case Access::kRpop:
      return h == Hw::kW;
  }
  return false;
}

// Why an (access, hw) pair was refused.
std::string illegal_pair(Access a, Hw h) {
  return "access " + std::string(to_string(a)) + " cannot have hw " + to_string(h) +
         " (legal: rw: r or none; ro: w or none; w1c: set; rc: count; w1p: r; rpop: w)";
}

std::uint64_t ones(int width) {
  return width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
}

// A field of a register `width` bits wide (64 for a `words: 2` register).
Field parse_field(const YAML::Node& n, Access default_access, Hw default_hw, int width,
                  const std::string& where) {
  Field f;
  f.name = scalar<std::string>(required(n, "name", where), "name");
  const std::string at = where + "." + f.name;
  check_keys(n, {"name", "bits", "access", "hw", "signed", "reset", "description", "enum"}, at);
  check_name(n, f.name, "field");
  const YAML::Node& bits = required(n, "bits", at);
  if (!bits.IsSequence() || bits.size() != 2)
    fail(bits, at + ": bits must be [msb, lsb]");
  f.msb = scalar<int>(bits[0], at + " msb");
  f.lsb = scalar<int>(bits[1], at + " lsb");
  if (f.lsb < 0 || f.msb < f.lsb)
    fail(bits, at + ": bits must be [msb, lsb] with msb >= lsb >= 0");
  if (f.msb >= width)
    fail(bits, at + ": field is wider than the " + std::to_string(width) + "-bit register");
  f.access = n["access"] ? access_of(n["access"], at) : default_access;
  f.hw = n["hw"] ? hw_of(n["hw"], at) : default_hw;
  if (!legal(f.access, f.hw))
    fail(n, at + ": " + illegal_pair(f.access, f.hw));
  f.is_signed = n["signed"] && scalar<bool>(n["signed"], at + " signed");
  if (f.is_signed && f.width() < 2)
    fail(n, at + ": a signed field needs at least 2 bits");
  f.description = text(n, "description", at);
  const std::uint64_t limit = ones(f.width());
  const auto reset = n["reset"] ? scalar<std::uint64_t>(n["reset"], at + " reset") : 0;
  if (reset > limit)
    fail(n["reset"], at + ": reset value does not fit the field");
  f.port_width = f.width();
  f.port_signed = f.is_signed;
  f.port_reset = reset;
  f.reset = static_cast<std::uint32_t>(reset);
  if (const YAML::Node& e = n["enum"]) {
    if (!e.IsMap())
      fail(e, at + ": enum must be a mapping {name: value}");
    std::set<std::string> names;
    std::set<std::uint64_t> values;
    for (const auto& kv : e) {
      const auto name = scalar<std::string>(kv.first, at + " enum");
      const auto value = scalar<std::uint64_t>(kv.second, at + " enum " + name);
      check_name(kv.first, name, "enum");
      check_unique(names, kv.first, name, "enum name", at);
      if (!values.insert(value).second)
        fail(kv.second, at + ": duplicate enum value");
      if (value > limit || value > 0xFFFFFFFFU)
        fail(kv.second, at + ": enum value does not fit the field");
      f.enums.emplace_back(name, static_cast<std::uint32_t>(value));
    }
  }
  return f;
}

// The part of a wide field that lies in word `word` (data_bits bits each),
// renumbered within that word; nullopt when the field has no bit there.
std::optional<Field> slice(const Field& f, int word, int data_bits, const std::string& at) {
  const int lo = word * data_bits, hi = lo + data_bits - 1;
  if (f.msb < lo || f.lsb > hi)
    return std::nullopt;
  Field s = f;
  s.msb = std::min(f.msb, hi) - lo;
  s.lsb = std::max(f.lsb, lo) - lo;
  s.port_shift = std::max(f.lsb, lo) - f.lsb;
  s.is_signed = f.is_signed && f.msb <= hi;  // only the slice holding the sign bit
  s.reset = static_cast<std::uint32_t>((f.port_reset >> s.port_shift) & ones(s.width()));
  if (s.width() != f.width()) {
    s.description = f.description + (f.description.empty() ? "" : " ") + "Bits " +
                    std::to_string(s.port_shift + s.width() - 1) + ":" +
                    std::to_string(s.port_shift) + ".";
  }
  if (!f.enums.empty() && s.width() != f.width())
    throw RegmapError(at + "." + f.name + ": an enum field cannot span two words");
  return s;
}

// The word registers of a `words: 2` register: <name>_lo (bits 31:0, at
// offset) and <name>_hi (the rest, at offset + 1), each with its slice of
// every field.
std::vector<Register> split_words(const Register& r, const YAML::Node& fields, int data_bits,
                                  const std::string& at) {
  std::vector<Register> out;
  for (int w = 0; w < 2; ++w) {
    const int lo = w * data_bits;
    Register wr = r;
    wr.name = r.name + (w == 0 ? "_lo" : "_hi");
    wr.offset = r.offset + static_cast<std::uint32_t>(w);
    wr.wide = r.name;
    wr.wide_description = r.description;
    wr.word = w;
    wr.fields.clear();
    int top = lo;
    for (const Field& f : r.fields) {
      if (auto s = slice(f, w, data_bits, at)) {
        top = std::max(top, std::min(f.msb, lo + data_bits - 1));
        wr.fields.push_back(std::move(*s));
      }
    }
    if (wr.fields.empty()) {
      fail(fields, at + ": words: 2 but no field has a bit in " +
                       (w == 0 ? std::string("bits 31:0") : std::string("bits 63:32")));
    }
    wr.description = r.description + (r.description.empty() ? "" : " ") + "Bits " +
                     std::to_string(w == 0 ? lo + data_bits - 1 : top) + ":" + std::to_string(lo) +
                     ".";
    out.push_back(std::move(wr));
  }
  return out;
}

// The elements <array>0 .. <array>N-1 of a `count: N` register array: element
// k is `words` (the word registers of one element, named <array>...) moved
// by k times their number.
std::vector<Register> split_elements(const std::vector<Register>& words, const std::string& array,
                                     int count) {
  std::vector<Register> out;
  const auto stride = static_cast<int>(words.size());
  for (int k = 0; k < count; ++k) {
    const std::string element = array + std::to_string(k);
    const std::string note =
        "Element " + std::to_string(k) + " of " + array + "[" + std::to_string(count) + "].";
    for (const Register& w : words) {
      Register e = w;
      e.name = element + w.name.substr(array.size());  // entry_lo -> entry5_lo
      e.offset = w.offset + static_cast<std::uint32_t>(k * stride);
      if (!w.wide.empty()) {
        e.wide = element;
        e.wide_description = w.wide_description + (w.wide_description.empty() ? "" : " ") + note;
      }
      e.array = array;
      e.array_description = w.description;
      e.count = count;
      e.element = k;
      e.array_words = stride;
      e.description = w.description + (w.description.empty() ? "" : " ") + note;
      out.push_back(std::move(e));
    }
  }
  return out;
}

// One register; the two word registers of a `words: 2` register; the
// elements of a `count: N` register array (each one or two words).
std::vector<Register> parse_register(const YAML::Node& n, int data_bits, const std::string& block) {
  Register r;
  r.name = scalar<std::string>(required(n, "name", block), "name");
  const std::string at = block + "." + r.name;
  check_keys(
      n, {"name", "offset", "access", "hw", "words", "count", "snapshot", "description", "fields"},
      at);
  check_name(n, r.name, "register");
  r.offset = scalar<std::uint32_t>(required(n, "offset", at), at + " offset");
  if (r.offset > 0xFFFFU)
    fail(n["offset"], at + ": offset is outside the 16-bit address space");
  r.access = access_of(required(n, "access", at), at);
  r.hw = hw_of(required(n, "hw", at), at);
  if (!legal(r.access, r.hw))
    fail(n["hw"], at + ": " + illegal_pair(r.access, r.hw));
  const int words = n["words"] ? scalar<int>(n["words"], at + " words") : 1;
  if (words != 1 && words != 2)
    fail(n["words"], at + ": words must be 1 or 2");
  if (words == 2 && r.access != Access::kRo && r.access != Access::kRw && r.access != Access::kRpop)
    fail(n["words"], at + ": a words: 2 register must be ro, rw or rpop");
  const int count = n["count"] ? scalar<int>(n["count"], at + " count") : 0;
  if (n["count"] && (count < 1 || count > 64))
    fail(n["count"], at + ": count must be 1..64 (the elements of the register array)");
  r.snapshot = n["snapshot"] && scalar<bool>(n["snapshot"], at + " snapshot");
  if (r.access == Access::kRpop && !r.snapshot) {
    fail(n, at + ": an rpop register must be snapshot: true (the frame pops the values it read, "
                 "captured when it started)");
  }
  if (r.access == Access::kRpop && count == 0) {
    fail(n, at + ": an rpop register needs count: N (it reads a FIFO as an array, element 0 "
                 "the oldest entry)");
  }
  r.description = text(n, "description", at);
  const YAML::Node& fields = required(n, "fields", at);
  if (!fields.IsSequence() || fields.size() == 0)
    fail(fields, at + ": needs at least one field");
  std::set<std::string> names;
  std::uint64_t used = 0;
  for (const auto& fn : fields) {
    Field f = parse_field(fn, r.access, r.hw, words * data_bits, at);
    check_unique(names, fn, f.name, "field", at);
    const std::uint64_t mask = ones(f.width()) << f.lsb;
    if ((used & mask) != 0)
      fail(fn, at + "." + f.name + ": overlaps another field");
    used |= mask;
    if (words == 2 && f.access != r.access)
      fail(fn, at + "." + f.name + ": fields of a words: 2 register keep its access");
    if (r.access == Access::kRpop && f.access != Access::kRpop)
      fail(fn, at + "." + f.name +
                   ": every field of an rpop register is rpop (a read pops the "
                   "whole element)");
    if (r.access != Access::kRpop && f.access == Access::kRpop)
      fail(fn, at + "." + f.name +
                   ": only the fields of an rpop register can be rpop (give the "
                   "register access: rpop)");
    r.fields.push_back(std::move(f));
  }
  std::vector<Register> out =
      words == 1 ? std::vector<Register>{r} : split_words(r, fields, data_bits, at);
  return count == 0 ? out : split_elements(out, r.name, count);
}

// Where an expanded register came from, for a duplicate name; "" when it
// was declared as it is.
std::string origin(const Register& r) {
  if (!r.array.empty())
    return "element " + std::to_string(r.element) + " of the register array '" + r.array + "'";
  if (!r.wide.empty())
    return "a word of the wide register '" + r.wide + "'";
  return {};
}

Block parse_block(const YAML::Node& n, int data_bits) {
  Block b;
  b.name = scalar<std::string>(required(n, "name", "block"), "block name");
  check_keys(
      n, {"name", "base", "description", "reserved", "size", "instances", "stride", "registers"},
      b.name);
  check_name(n, b.name, "block");
  b.base = scalar<std::uint32_t>(required(n, "base", b.name), b.name + " base");
  if (b.base > 0xFFFFU)
    fail(n["base"], b.name + ": base is outside the 16-bit address space");
  b.description = text(n, "description", b.name);
  b.reserved = n["reserved"] && scalar<bool>(n["reserved"], b.name + " reserved");
  if (b.reserved) {
    b.size = scalar<std::uint32_t>(required(n, "size", b.name), b.name + " size");
    if (b.size == 0 || b.size > 0xFFFFU)
      fail(n["size"], b.name + ": size must be 1..0xffff words");
    return b;
  }
  if (const YAML::Node& inst = n["instances"]) {
    if (!inst.IsSequence() || inst.size() == 0)
      fail(inst, b.name + ": instances must be a list of names");
    std::set<std::string> names;
    for (const auto& i : inst) {
      const auto name = scalar<std::string>(i, b.name + " instance");
      check_name(i, name, "instance");
      check_unique(names, i, name, "instance", b.name);
      b.instances.push_back(name);
    }
    b.stride = scalar<std::uint32_t>(required(n, "stride", b.name), b.name + " stride");
    if (b.stride == 0 || b.stride > 0xFFFFU)
      fail(n["stride"], b.name + ": stride must be 1..0xffff words");
  }
  std::map<std::string, std::string> names;  // register -> where it came from
  const YAML::Node& registers = required(n, "registers", b.name);
  if (!registers.IsSequence())
    fail(registers, b.name + ": registers must be a list");
  for (const auto& rn : registers) {
    for (Register& r : parse_register(rn, data_bits, b.name)) {
      const auto [it, fresh] = names.emplace(r.name, origin(r));
      if (!fresh) {
        const std::string both =
            it->second + (it->second.empty() || origin(r).empty() ? "" : "; ") + origin(r);
        fail(rn, "duplicate register '" + r.name + "' in " + b.name +
                     (both.empty() ? "" : " (" + both + ")"));
      }
      if (!b.instances.empty() && r.offset >= b.stride) {
        fail(rn, b.name + "." + r.name + ": offset is outside the instance stride");
      }
      b.registers.push_back(std::move(r));
    }
  }
  return b;
}

// Every address the map occupies, reserved ranges included, must be unique.
void check_addresses(const RegisterMap& map) {
  std::map<std::uint32_t, std::string> owner;
  const std::uint32_t limit = std::uint32_t{1} << map.address_bits;
  const auto claim = [&](std::uint32_t address, const std::string& who) {
    if (address >= limit) {
      throw RegmapError(who + ": address " + hex(address) + " is outside the " +
                        std::to_string(map.address_bits) + "-bit space");
    }
    const auto [it, fresh] = owner.emplace(address, who);
    if (!fresh)
      throw RegmapError(who + " overlaps " + it->second + " at " + hex(address));
  };
  for (const RegisterInstance& r : flatten(map))
    claim(r.address, r.path);
  for (const Block& b : map.blocks) {
    if (!b.reserved)
      continue;
    for (std::uint32_t a = b.base; a < b.base + b.size; ++a)
      claim(a, b.name + " (reserved)");
  }
}

}  // namespace

const char* to_string(Access a) {
  switch (a) {
    case Access::kRo:
      return "ro";
    case Access::kRw:
      return "rw";
    case Access::kW1c:
      return "w1c";
    case Access::kRc:
      return "rc";
    case Access::kW1p:
      return "w1p";
    case Access::kRpop:
      return "rpop";
  }
  return "?";
}

const char* to_string(Hw h) {
  switch (h) {
    case Hw::kR:
      return "r";
    case Hw::kW:
      return "w";
    case Hw::kSet:
      return "set";
    case Hw::kCount:
      return "count";
    case Hw::kNone:
      return "none";
  }
  return "?";
}

std::uint32_t Field::mask() const {
  const std::uint64_t ones = (std::uint64_t{1} << width()) - 1;
  return static_cast<std::uint32_t>(ones << lsb);
}

std::uint32_t Register::reset() const {
  std::uint32_t value = 0;
  for (const Field& f : fields)
    value |= f.reset << f.lsb;
  return value;
}

std::uint32_t Register::mask(Access a) const {
  std::uint32_t m = 0;
  for (const Field& f : fields) {
    if (f.access == a)
      m |= f.mask();
  }
  return m;
}

std::uint32_t Register::mask(Hw h) const {
  std::uint32_t m = 0;
  for (const Field& f : fields) {
    if (f.hw == h)
      m |= f.mask();
  }
  return m;
}

std::uint32_t Register::const_mask() const {
  std::uint32_t m = 0;
  for (const Field& f : fields) {
    if (f.access == Access::kRo && f.hw == Hw::kNone)
      m |= f.mask();
  }
  return m;
}

namespace {

Spi parse_spi(const YAML::Node& n) {
  check_keys(n, {"max_burst", "min_level_clocks", "crc"}, "spi");
  Spi s;
  s.max_burst = scalar<int>(required(n, "max_burst", "spi"), "spi max_burst");
  if (s.max_burst < 1 || s.max_burst > 32)
    fail(n["max_burst"], "spi: max_burst must be 1..32 (the frame's 5-bit burst field)");
  s.min_level_clocks = scalar<int>(required(n, "min_level_clocks", "spi"), "spi min_level_clocks");
  if (s.min_level_clocks < 1 || s.min_level_clocks > 1000)
    fail(n["min_level_clocks"], "spi: min_level_clocks must be 1..1000");
  const YAML::Node& crc = required(n, "crc", "spi");
  check_keys(crc, {"polynomial", "init", "xor_out"}, "spi.crc");
  const auto byte = [&](const char* key) {
    const auto v =
        scalar<std::uint32_t>(required(crc, key, "spi.crc"), std::string("spi.crc ") + key);
    if (v > 0xFF)
      fail(crc[key], std::string("spi.crc: ") + key + " must fit 8 bits (CRC-8)");
    return static_cast<std::uint8_t>(v);
  };
  s.crc_polynomial = byte("polynomial");
  s.crc_init = byte("init");
  s.crc_xor_out = byte("xor_out");
  return s;
}

}  // namespace

namespace {

RegisterMap parse_checked(const std::string& yaml_text) {
  YAML::Node root;
  try {
    root = yaml::load_one_document(yaml_text);
  } catch (const YAML::Exception& e) {
    throw RegmapError(std::string("YAML: ") + e.what());
  }
  if (!root.IsMap())
    throw RegmapError("the description must be a YAML mapping");
  RegisterMap map;
  const YAML::Node& m = required(root, "map", "top level");
  map.name = scalar<std::string>(required(m, "name", "map"), "map name");
  check_keys(m, {"name", "description", "address_bits", "data_bits", "clock_hz"}, "map");
  check_name(m, map.name, "map");
  map.description = text(m, "description", "map");
  map.address_bits = scalar<int>(required(m, "address_bits", "map"), "address_bits");
  map.data_bits = scalar<int>(required(m, "data_bits", "map"), "data_bits");
  if (map.address_bits < 1 || map.address_bits > 16)
    fail(m, "address_bits must be 1..16");
  if (map.data_bits < 8 || map.data_bits > 32)
    fail(m, "data_bits must be 8..32");
  const YAML::Node& clock = required(m, "clock_hz", "map");
  map.clock_hz = scalar<std::uint32_t>(clock, "clock_hz");
  if (map.clock_hz == 0 || 1000000000U % map.clock_hz != 0)
    fail(clock, "clock_hz: the clock period must be a whole number of ns");
  for (const auto& kv : root) {
    const auto key = kv.first.as<std::string>();
    if (key != "map" && key != "spi" && key != "blocks")
      fail(kv.first, "top level: unknown key '" + key + "'");
  }
  map.spi = parse_spi(required(root, "spi", "top level"));
  std::set<std::string> names;
  const YAML::Node& blocks = required(root, "blocks", "top level");
  if (!blocks.IsSequence())
    fail(blocks, "blocks must be a list");
  for (const auto& bn : blocks) {
    Block b = parse_block(bn, map.data_bits);
    check_unique(names, bn, b.name, "block");
    map.blocks.push_back(std::move(b));
  }
  check_addresses(map);
  check_generated_names(map);
  return map;
}

}  // namespace

RegisterMap parse(const std::string& yaml_text) {
  try {
    return parse_checked(yaml_text);
  } catch (const YAML::Exception& e) {  // a node of the wrong kind, deep nesting, ...
    throw RegmapError(std::string("YAML: ") + e.what());
  }
}

RegisterMap load(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw RegmapError("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  try {
    return parse(s.str());
  } catch (const RegmapError& e) {
    throw RegmapError(path + ": " + e.what());
  }
}

std::vector<RegisterInstance> flatten(const RegisterMap& map) {
  std::vector<RegisterInstance> out;
  for (const Block& b : map.blocks) {
    if (b.reserved)
      continue;
    const int count = b.instances.empty() ? 1 : static_cast<int>(b.instances.size());
    for (int i = 0; i < count; ++i) {
      const std::string prefix =
          b.instances.empty() ? b.name : b.name + "." + b.instances[static_cast<std::size_t>(i)];
      for (const Register& r : b.registers) {
        RegisterInstance ri;
        ri.path = prefix + "." + r.name;
        std::string macro = ri.path;
        std::replace(macro.begin(), macro.end(), '.', '_');
        ri.macro = upper(macro);
        ri.address = b.base + static_cast<std::uint32_t>(i) * b.stride + r.offset;
        ri.block = &b;
        ri.reg = &r;
        ri.instance = b.instances.empty() ? -1 : i;
        out.push_back(std::move(ri));
      }
    }
  }
  std::sort(out.begin(), out.end(), [](const RegisterInstance& a, const RegisterInstance& b) {
    return a.address < b.address;
  });
  return out;
}

std::vector<PopWindow> pop_windows(const RegisterMap& map) {
  std::vector<PopWindow> out;
  for (const RegisterInstance& ri : flatten(map)) {
    const Register& r = *ri.reg;
    if (!r.array_head() || r.access != Access::kRpop)
      continue;
    PopWindow w;
    w.path = ri.path.substr(0, ri.path.size() - r.name.size()) + r.array;
    w.first = ri.address;
    w.entries = r.count;
    w.words = r.array_words;
    w.block = ri.block;
    w.head = &r;
    w.instance = ri.instance;
    out.push_back(std::move(w));
  }
  return out;
}

}  // namespace odoloc::regmap
