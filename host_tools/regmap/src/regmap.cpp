#include "odoloc/regmap/regmap.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <initializer_list>
#include <map>
#include <set>
#include <sstream>
#include <string_view>

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

std::string text(const YAML::Node& node, const char* key) {
  return node[key] ? scalar<std::string>(node[key], key) : std::string{};
}

bool is_identifier(const std::string& s) {
  return !s.empty() && (std::islower(static_cast<unsigned char>(s[0])) != 0) &&
         std::all_of(s.begin(), s.end(), [](char c) {
           return std::islower(static_cast<unsigned char>(c)) != 0 ||
                  std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '_';
         });
}

void check_name(const YAML::Node& at, const std::string& name, const std::string& what) {
  if (!is_identifier(name)) {
    fail(at, what + " '" + name + "': names are lower_snake_case identifiers");
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
  for (const auto& kv : n) {
    const auto key = kv.first.as<std::string>();
    if (std::find(known.begin(), known.end(), key) == known.end())
      fail(kv.first,
           where + ": unknown key '" + key + "' (quote values that contain a comma or a colon)");
  }
}

Access access_of(const YAML::Node& node, const std::string& where) {
  const auto name = scalar<std::string>(node, where);
  for (const Access a : {Access::kRo, Access::kRw, Access::kW1c, Access::kRc, Access::kW1p}) {
    if (name == to_string(a))
      return a;
  }
  fail(node, where + ": unknown access '" + name + "'");
}

Field parse_field(const YAML::Node& n, Access default_access, int data_bits,
                  const std::string& where) {
  Field f;
  f.name = scalar<std::string>(required(n, "name", where), "name");
  const std::string at = where + "." + f.name;
  check_keys(n, {"name", "bits", "access", "signed", "reset", "description", "enum"}, at);
  check_name(n, f.name, "field");
  const YAML::Node& bits = required(n, "bits", at);
  if (!bits.IsSequence() || bits.size() != 2)
    fail(bits, at + ": bits must be [msb, lsb]");
  f.msb = scalar<int>(bits[0], at + " msb");
  f.lsb = scalar<int>(bits[1], at + " lsb");
  if (f.lsb < 0 || f.msb < f.lsb)
    fail(bits, at + ": bits must be [msb, lsb] with msb >= lsb >= 0");
  if (f.msb >= data_bits) {
    fail(bits, at + ": field is wider than the " + std::to_string(data_bits) + "-bit register");
  }
  f.access = n["access"] ? access_of(n["access"], at) : default_access;
  f.is_signed = n["signed"] && scalar<bool>(n["signed"], at + " signed");
  f.description = text(n, "description");
  const std::uint64_t limit = (std::uint64_t{1} << f.width()) - 1;
  const auto reset = n["reset"] ? scalar<std::uint64_t>(n["reset"], at + " reset") : 0;
  if (reset > limit)
    fail(n["reset"], at + ": reset value does not fit the field");
  f.reset = static_cast<std::uint32_t>(reset);
  if (const YAML::Node& e = n["enum"]) {
    std::set<std::string> names;
    std::set<std::uint64_t> values;
    for (const auto& kv : e) {
      const auto name = scalar<std::string>(kv.first, at + " enum");
      const auto value = scalar<std::uint64_t>(kv.second, at + " enum " + name);
      check_name(kv.first, name, "enum");
      check_unique(names, kv.first, name, "enum name", at);
      if (!values.insert(value).second)
        fail(kv.second, at + ": duplicate enum value");
      if (value > limit)
        fail(kv.second, at + ": enum value does not fit the field");
      f.enums.emplace_back(name, static_cast<std::uint32_t>(value));
    }
  }
  return f;
}

Register parse_register(const YAML::Node& n, int data_bits, const std::string& block) {
  Register r;
  r.name = scalar<std::string>(required(n, "name", block), "name");
  const std::string at = block + "." + r.name;
  check_keys(n, {"name", "offset", "access", "snapshot", "description", "fields"}, at);
  check_name(n, r.name, "register");
  r.offset = scalar<std::uint32_t>(required(n, "offset", at), at + " offset");
  r.access = access_of(required(n, "access", at), at);
  r.snapshot = n["snapshot"] && scalar<bool>(n["snapshot"], at + " snapshot");
  r.description = text(n, "description");
  const YAML::Node& fields = required(n, "fields", at);
  if (!fields.IsSequence() || fields.size() == 0)
    fail(fields, at + ": needs at least one field");
  std::set<std::string> names;
  std::uint32_t used = 0;
  for (const auto& fn : fields) {
    Field f = parse_field(fn, r.access, data_bits, at);
    check_unique(names, fn, f.name, "field", at);
    if ((used & f.mask()) != 0)
      fail(fn, at + "." + f.name + ": overlaps another field");
    used |= f.mask();
    r.fields.push_back(std::move(f));
  }
  return r;
}

Block parse_block(const YAML::Node& n, int data_bits) {
  Block b;
  b.name = scalar<std::string>(required(n, "name", "block"), "block name");
  check_keys(
      n, {"name", "base", "description", "reserved", "size", "instances", "stride", "registers"},
      b.name);
  check_name(n, b.name, "block");
  b.base = scalar<std::uint32_t>(required(n, "base", b.name), b.name + " base");
  b.description = text(n, "description");
  b.reserved = n["reserved"] && scalar<bool>(n["reserved"], b.name + " reserved");
  if (b.reserved) {
    b.size = scalar<std::uint32_t>(required(n, "size", b.name), b.name + " size");
    return b;
  }
  if (const YAML::Node& inst = n["instances"]) {
    std::set<std::string> names;
    for (const auto& i : inst) {
      const auto name = scalar<std::string>(i, b.name + " instance");
      check_name(i, name, "instance");
      check_unique(names, i, name, "instance", b.name);
      b.instances.push_back(name);
    }
    b.stride = scalar<std::uint32_t>(required(n, "stride", b.name), b.name + " stride");
  }
  std::set<std::string> names;
  for (const auto& rn : required(n, "registers", b.name)) {
    Register r = parse_register(rn, data_bits, b.name);
    check_unique(names, rn, r.name, "register", b.name);
    if (!b.instances.empty() && r.offset >= b.stride) {
      fail(rn, b.name + "." + r.name + ": offset is outside the instance stride");
    }
    b.registers.push_back(std::move(r));
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

RegisterMap parse(const std::string& yaml_text) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw RegmapError(std::string("YAML: ") + e.what());
  }
  if (!root.IsMap())
    throw RegmapError("the description must be a YAML mapping");
  RegisterMap map;
  const YAML::Node& m = required(root, "map", "top level");
  map.name = scalar<std::string>(required(m, "name", "map"), "map name");
  check_keys(m, {"name", "description", "address_bits", "data_bits"}, "map");
  check_name(m, map.name, "map");
  map.description = text(m, "description");
  map.address_bits = scalar<int>(required(m, "address_bits", "map"), "address_bits");
  map.data_bits = scalar<int>(required(m, "data_bits", "map"), "data_bits");
  if (map.address_bits < 1 || map.address_bits > 16)
    fail(m, "address_bits must be 1..16");
  if (map.data_bits < 8 || map.data_bits > 32)
    fail(m, "data_bits must be 8..32");
  std::set<std::string> names;
  for (const auto& bn : required(root, "blocks", "top level")) {
    Block b = parse_block(bn, map.data_bits);
    check_unique(names, bn, b.name, "block");
    map.blocks.push_back(std::move(b));
  }
  check_addresses(map);
  return map;
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

}  // namespace odoloc::regmap
