// check_generated_names(): every identifier the emitters write, per output
// and per namespace of that output, built with the same functions the
// emitters use (names.hpp). A reserved word or two YAML paths that end up as
// one identifier refuse the map, naming both paths.
#include "names.hpp"

#include <map>
#include <set>

#include "c_helpers.hpp"

namespace odoloc::regmap {

namespace {

class Names {
 public:
  // Claims `id` in `scope` (one namespace of one output) for `path`.
  void claim(Language lang, const std::string& scope, const std::string& id,
             const std::string& path) {
    if (const char* why = reserved_reason(lang, id))
      throw RegmapError(path + ": '" + id + "' in " + scope + " is " + why);
    const auto [it, fresh] = scopes_[scope].emplace(id, path);
    if (!fresh && it->second != path) {
      throw RegmapError(path + " and " + it->second + " both become '" + id + "' in " + scope +
                        ": rename one");
    }
  }
  // Names the generated code itself declares or uses unqualified in `scope`.
  void fixed(Language lang, const std::string& scope, std::initializer_list<const char*> ids) {
    for (const char* id : ids)
      claim(lang, scope, id, std::string("the generated '") + id + "'");
  }

 private:
  std::map<std::string, std::map<std::string, std::string>> scopes_;
};

std::string register_path(const Block& b, const Register& r) {
  if (!r.array.empty()) {
    return b.name + "." + r.array + "[" + std::to_string(r.element) + "] (" +
           (r.wide.empty() ? "register " : "word register ") + r.name + ")";
  }
  return b.name + "." + (r.wide.empty() ? r.name : r.wide + " (word register " + r.name + ")");
}

std::string array_path(const Block& b, const Register& r) {
  return b.name + "." + r.array + " (register array)";
}

std::string field_path(const Block& b, const Register& r, const Field& f) {
  return b.name + "." + r.port_name() + "." + f.name;
}

void c_names(const RegisterMap& map, Names& n) {
  const std::string scope = "the C header";
  const std::string p = c_prefix(map);
  const auto c = [&](const std::string& id, const std::string& path) {
    n.claim(Language::kC, scope, id, path);
  };
  for (const char* g : {"REGS_H", "ADDRESS_BITS", "DATA_BITS", "REGISTER_COUNT", "FABRIC_CLOCK_HZ",
                        "FABRIC_CLOCK_PERIOD_NS", "SPI_MAX_BURST", "SPI_MIN_LEVEL_CLOCKS",
                        "SPI_MAX_SCLK_HZ", "SPI_CRC_POLYNOMIAL", "SPI_CRC_INIT", "SPI_CRC_XOR_OUT"})
    c(p + g, "map.name (the generated " + p + g + ")");
  for (const char* g : kCSpiMacros)
    c(p + g, "map.name (the generated " + p + g + ")");
  for (const char* g : kCSpiFunctions)
    c(map.name + "_" + g, "map.name (the generated " + map.name + "_" + g + ")");
  for (const RegisterInstance& ri : flatten(map)) {
    std::string path = register_path(*ri.block, *ri.reg);
    if (ri.instance >= 0)
      path += " of instance " + ri.block->instances[static_cast<std::size_t>(ri.instance)];
    c(c_address(map, ri), path);
  }
  for (const Block& b : map.blocks) {
    if (b.reserved) {
      c(c_block(map, b) + "_RESERVED_BASE", b.name);
      c(c_block(map, b) + "_RESERVED_SIZE", b.name);
      continue;
    }
    if (!b.instances.empty()) {
      for (const char* s : {"_BASE", "_STRIDE", "_INSTANCES"})
        c(c_block(map, b) + s, b.name);
    }
    for (const Register& r : b.registers) {
      if (r.array_head()) {
        for (const char* s : {"_OFFSET", "_COUNT", "_WORDS"})
          c(c_array(map, b, r) + s, array_path(b, r));
      }
      c(c_register(map, b, r) + "_OFFSET", register_path(b, r));
      c(c_register(map, b, r) + "_RESET", register_path(b, r));
      for (const Field& f : r.fields) {
        const std::string fp = register_path(b, r) + "." + f.name;
        c(c_field(map, b, r, f) + "_SHIFT", fp);
        c(c_field(map, b, r, f) + "_MASK", fp);
        for (const auto& e : f.enums)
          c(c_enumerator(map, b, r, f, e.first), fp + " enum " + e.first);
        c(c_function(map, b, r, f) + "_get", fp);
        c(c_function(map, b, r, f) + "_set", fp);
        if (f.is_signed)
          c(c_get_signed(map, b, r, f), fp);
      }
    }
  }
  for (const SplitField& s : split_fields(map)) {
    const std::string fp = field_path(*s.block, *s.hi_reg, *s.hi);
    c(c_split_function(map, s) + "_join", fp);
    if (c_split_writable(s)) {
      c(c_split_function(map, s) + "_set_lo", fp);
      c(c_split_function(map, s) + "_set_hi", fp);
    }
  }
}

void cpp_names(const RegisterMap& map, Names& n) {
  const auto cpp = [&](const std::string& scope, const std::string& id, const std::string& path) {
    n.claim(Language::kCpp, scope, id, path);
  };
  const std::string regs = "C++ namespace odoloc::regs";
  n.fixed(Language::kCpp, regs,
          {"kAddressBits", "kDataBits", "kFabricClockHz", "kFabricClockPeriodNs", "spi", "Access",
           "HwAccess", "Enumerator", "Field", "Register", "Reserved", "kRegisters", "kReserved",
           "find", "std", "odoloc", "regs", "ports", "rtl"});
  n.fixed(Language::kCpp, regs, {"PopWindow", "PopWord", "kPopWindows", "find_pop_word"});
  const std::string ports = "C++ namespace odoloc::ports";
  n.fixed(Language::kCpp, ports,
          {"SInt", "UInt", "rtl", "regs", "std", "odoloc", "ports", "Config", "Pulses", "Status",
           "decode_config", "decode_pulses", "encode_status", "decode_pops"});
  for (const char* s : {"Config", "Pulses", "Status"}) {
    n.fixed(Language::kCpp, std::string("C++ struct odoloc::ports::") + s,
            {"for_each_field", "for_each_port", "std"});
  }
  for (const Block& b : map.blocks) {
    if (b.reserved)
      continue;
    cpp(regs, b.name, b.name);
    cpp(ports, b.name, b.name);
    for (const char* s : {"Config", "Pulses", "Status"})
      cpp(std::string("C++ struct odoloc::ports::") + s, b.name, b.name);
    const std::string bs = regs + "::" + b.name;
    n.fixed(Language::kCpp, bs, {"kBase", "kStride", "kInstances", "kInstanceNames", "std"});
    const std::string pb = ports + "::" + b.name;
    n.fixed(Language::kCpp, pb,
            {"Config", "Pulses", "Status", "decode_config", "decode_pulses", "encode_status",
             "decode_pops", "UInt", "SInt", "regs", "std"});
    std::map<std::string, int> enum_uses = ports_enum_uses(b);
    for (const Register& r : b.registers) {
      const std::string rp = register_path(b, r);
      if (r.array_head()) {  // regs.hpp: the array's namespace next to its registers'
        cpp(bs, r.array, array_path(b, r));
        n.fixed(Language::kCpp, bs + "::" + r.array,
                {"kOffset", "kCount", "kWords", "address", "std"});
      }
      cpp(bs, r.name, rp);
      const std::string rs = bs + "::" + r.name;
      n.fixed(Language::kCpp, rs,
              {"kOffset", b.instances.empty() ? "kAddress" : "address", "kReset", "kFields", "std",
               "Field", "Enumerator", "Access", "HwAccess"});
      for (const Field& f : r.fields) {
        const std::string fp = rp + "." + f.name;
        cpp(rs, f.name, fp);
        if (f.enums.empty())
          continue;
        cpp(rs, cpp_enum_type(f), fp + " (its enum)");
        cpp(rs, cpp_enum_names(f), fp + " (its enum names)");
        for (const auto& e : f.enums)
          cpp(rs + "::" + cpp_enum_type(f), cpp_enumerator(e.first), fp + " enum " + e.first);
        cpp(pb, ports_enum_alias(r, f, enum_uses[f.name] > 1), field_path(b, r, f) + " (its enum)");
      }
      // ports.hpp: one member and one nested type per register (wide
      // registers once), one member per field.
      for (const char* s : {"Config", "Pulses", "Status"}) {
        const std::string ss = pb + "::" + s;
        const std::string group = b.name + "." + r.port_name();
        n.fixed(Language::kCpp, ss, {"for_each_field", "for_each_port", "std"});
        cpp(ss, r.port_name(), group);
        cpp(ss, ports_register_type(r.port_name()), group + " (its port struct)");
        const std::string gs = ss + "::" + ports_register_type(r.port_name());
        n.fixed(Language::kCpp, gs, {"for_each_field", "std", "UInt", "SInt"});
        if (r.access == Access::kRpop && std::string(s) == "Pulses") {  // one strobe
          cpp(gs, "pops", group + " (its pops)");
        } else {
          for (const Field& f : r.fields)
            cpp(gs, f.name, field_path(b, r, f));
        }
      }
    }
  }
}

void rdl_names(const RegisterMap& map, Names& n) {
  const auto rdl = [&](const std::string& scope, const std::string& id, const std::string& path) {
    n.claim(Language::kRdl, scope, id, path);
  };
  rdl("SystemRDL (the addrmap)", map.name, "map.name");
  const std::string types = "SystemRDL types of addrmap " + map.name;
  const std::string elements = "SystemRDL instances of addrmap " + map.name;
  for (const Block& b : map.blocks) {
    if (b.reserved)
      continue;
    rdl(types, rdl_block_type(b), b.name);
    for (std::size_t i = 0; i < std::max<std::size_t>(1, b.instances.size()); ++i)
      rdl(elements, rdl_instance(b, i),
          b.instances.empty() ? b.name : b.name + " instance " + b.instances[i]);
    const std::string bt = "SystemRDL types of regfile " + rdl_block_type(b);
    const std::string be = "SystemRDL instances of regfile " + rdl_block_type(b);
    for (const Register& r : b.registers) {
      const std::string rp = register_path(b, r);
      rdl(be, r.name, rp);
      for (const Field& f : r.fields) {
        const std::string fp = rp + "." + f.name;
        rdl("SystemRDL fields of " + b.name + "." + r.name, f.name, fp);
        if (f.enums.empty())
          continue;
        rdl(bt, rdl_enum_type(r, f), fp + " (its enum)");
        for (const auto& e : f.enums)
          rdl("SystemRDL enum " + rdl_enum_type(r, f), e.first, fp + " enum " + e.first);
      }
    }
  }
}

}  // namespace

void check_generated_names(const RegisterMap& map) {
  Names n;
  c_names(map, n);
  cpp_names(map, n);
  rdl_names(map, n);
}

}  // namespace odoloc::regmap
