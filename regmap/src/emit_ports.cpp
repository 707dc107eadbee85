// odoloc/ports.hpp: the register file's side of the fabric, typed. Per block,
// Config (what the hardware reads from rw registers), Pulses (one-clock
// strobes of software writes: w1p commands, w1c clears) and Status (what the
// hardware drives: live values, sticky flags, counters), with the generated
// decode/encode between them and register words.
#include <bit>
#include <map>
#include <sstream>

#include "names.hpp"
#include "odoloc/regmap/regmap.hpp"
#include "text.hpp"

namespace odoloc::regmap {

namespace {

enum class Port : std::uint8_t { kConfig, kPulses, kStatus };

bool in_port(const Field& f, Port p) {
  switch (p) {
    case Port::kConfig:
      return f.access == Access::kRw && f.hw == Hw::kR;
    case Port::kPulses:
      return (f.access == Access::kW1c && f.hw == Hw::kSet) ||
             (f.access == Access::kW1p && f.hw == Hw::kR);
    case Port::kStatus:
      return f.hw == Hw::kW || f.hw == Hw::kSet || f.hw == Hw::kCount;
  }
  return false;
}

const char* struct_name(Port p) {
  switch (p) {
    case Port::kConfig:
      return "Config";
    case Port::kPulses:
      return "Pulses";
    case Port::kStatus:
      return "Status";
  }
  return "?";
}

std::string hex64(std::uint64_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v << "ULL";
  return s.str();
}

std::uint64_t ones(int width) {
  return width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
}

std::int64_t sign_extended(std::uint64_t bits, int width) {
  const bool negative = width < 64 && ((bits >> (width - 1)) & 1U) != 0;
  return static_cast<std::int64_t>(negative ? bits | ~ones(width) : bits);
}

// How a port struct spells its integers: the model's (UInt<W>, SInt<W>,
// odoloc/ports.hpp) or a family's (uint<F, W>, sint<F, W>, the C++14
// odoloc/logic/ports.hpp that the blocks' logic and the HLS kernels take).
enum class Types : std::uint8_t { kModel, kFamily };

// (Streams, not "literal" + std::string: GCC 12 -O3 warns falsely on those.)
std::string int_type(bool is_signed, int width, Types types) {
  std::ostringstream o;
  if (types == Types::kModel)
    o << (is_signed ? "SInt<" : "UInt<") << width << ">";
  else
    o << (is_signed ? "sint<F, " : "uint<F, ") << width << ">";
  return o.str();
}
// A family integer holds at most 63 bits (hls/own_int.hpp): a wider port is
// logic::Words there, two 32-bit words (logic/int_family.hpp).
constexpr int kFamilyMaxBits = 63;
bool family_words(const Field& f, Types types) {
  return types == Types::kFamily && f.port_width > kFamilyMaxBits;
}
std::string port_type(const Field& f, Types types = Types::kModel) {
  if (family_words(f, types))
    return f.port_signed ? "Words<F, true>" : "Words<F, false>";
  return int_type(f.port_signed, f.port_width, types);
}

// The port's raw bits as a std::uint64_t.
std::string raw(const Field& f, const std::string& port) {
  return port + (f.port_signed ? ".raw_bits()" : ".value()");
}

// The default member initialiser: the reset value. A family's types take it
// as a host integer (each wraps on construction); ap_int's `{}` would leave
// the value undefined.
std::string initialiser(const Field& f, Types types) {
  std::ostringstream o;
  const std::uint64_t bits = f.port_reset;
  if (family_words(f, types)) {
    const std::uint64_t high = bits >> 32;
    o << "{{" << (f.port_signed ? sign_extended(high, 32) : static_cast<std::int64_t>(high))
      << (f.port_signed ? "LL" : "ULL") << "}, {" << (bits & 0xFFFFFFFFU) << "ULL}}";
    return o.str();
  }
  if (types == Types::kFamily) {
    if (f.port_signed)
      o << "{" << sign_extended(bits, f.port_width) << "LL}";
    else
      o << "{" << bits << "ULL}";
    return o.str();
  }
  if (!f.port_signed) {
    o << "{" << bits << "U}";
  } else if (((bits >> (f.port_width - 1)) & 1U) == 0) {
    o << "{" << bits << "}";
  } else {
    o << "{" << port_type(f) << "::truncate(static_cast<std::int64_t>("
      << hex64(bits | ~ones(f.port_width)) << "))}";
  }
  return o.str();
}

// One register as the hardware sees it: a one-word register, or both words
// of a wide one, or a register array (element 0's words standing for every
// element); `ports` holds one slice per port (the first found).
struct Group {
  std::string name;
  int count = 0;      // the elements of a register array; 0: not an array
  bool pops = false;  // an rpop array: its FIFO pops
  std::vector<const Register*> words;
  std::vector<const Field*> ports;
};

std::vector<Group> groups(const Block& b) {
  std::vector<Group> out;
  for (const Register& r : b.registers) {
    if (r.element != 0)
      continue;
    if (r.word == 0)
      out.push_back({r.port_name(), r.count, r.access == Access::kRpop, {}, {}});
    Group& g = out.back();
    g.words.push_back(&r);
    for (const Field& f : r.fields) {
      bool seen = false;
      for (const Field* p : g.ports)
        seen = seen || p->name == f.name;
      if (!seen)
        g.ports.push_back(&f);
    }
  }
  return out;
}

bool has(const Register& r, Port p) {
  for (const Field& f : r.fields) {
    if (in_port(f, p))
      return true;
  }
  return false;
}

// A member of a port struct: its type, name and default member initialiser.
struct Member {
  std::string type, name, init;
};
// A register's member of a block's port struct: a struct of its ports, or an
// array of them (one per element of a register array).
struct PortGroup {
  std::string name;
  int count = 0;
  std::vector<Member> members;
};

// The pops of an rpop array: how many whole elements (0..N) a read frame popped.
std::string pops_type(int count, Types types = Types::kModel) {
  return int_type(false, static_cast<int>(std::bit_width(static_cast<unsigned>(count))), types);
}

// The members of a block's Config, Pulses or Status. Pulses carries one
// `pops` per rpop array (a strobe for the array, not per element).
std::vector<PortGroup> port_groups(const Block& b, Port p, Types types = Types::kModel) {
  const std::string zero = types == Types::kModel ? "{}" : "{0}";
  std::vector<PortGroup> out;
  for (const Group& g : groups(b)) {
    PortGroup pg{g.name, g.count, {}};
    for (const Field* f : g.ports) {
      if (in_port(*f, p))
        pg.members.push_back(
            {port_type(*f, types), f->name, p == Port::kPulses ? zero : initialiser(*f, types)});
    }
    if (p == Port::kPulses && g.pops) {  // (rpop fields are in Status only)
      pg.count = 0;
      pg.members.push_back({pops_type(g.count, types), "pops", zero});
    }
    if (!pg.members.empty())
      out.push_back(std::move(pg));
  }
  return out;
}

void emit_struct(std::ostringstream& o, const Block& b, Port p) {
  const std::string name = struct_name(p);
  o << "struct " << name << " {\n";
  const auto gs = port_groups(b, p);
  for (const PortGroup& g : gs) {
    const std::string type = ports_register_type(g.name);
    o << "  struct " << type << " {\n";
    for (const Member& m : g.members)
      o << "    " << m.type << " " << m.name << m.init << ";\n";
    o << "    bool operator==(const " << type << "&) const = default;\n"
      << "    template <class F>\n    constexpr void for_each_field(F&& f_) const {\n";
    for (const Member& m : g.members)
      o << "      f_(std::string_view{\"" << m.name << "\"}, " << m.name << ");\n";
    o << "    }\n  }";
    if (g.count == 0)
      o << " " << g.name << ";\n";
    else
      o << ";\n  std::array<" << type << ", " << g.count << "> " << g.name << ";\n";
  }
  o << "  bool operator==(const " << name << "&) const = default;\n"
    << "  // Calls f(name, member) for every register (rtl/fields.hpp's field list).\n"
    << "  template <class F>\n  constexpr void for_each_field([[maybe_unused]] F&& f_) const {\n";
  for (const PortGroup& g : gs)
    o << "    f_(std::string_view{\"" << g.name << "\"}, " << g.name << ");\n";
  o << "  }\n"
    << "  // Calls v(register, element, field, port) for every port; element: the\n"
    << "  // index in a register array, -1 for other registers.\n"
    << "  template <class Self, class V>\n"
    << "  static constexpr void for_each_port([[maybe_unused]] Self& self_, "
       "[[maybe_unused]] V&& v_) {\n";
  for (const PortGroup& g : gs) {
    const bool array = g.count != 0;
    if (array)
      o << "    for (std::size_t k_ = 0; k_ < " << g.count << "; ++k_) {\n";
    for (const Member& m : g.members) {
      o << (array ? "      " : "    ") << "v_(std::string_view{\"" << g.name << "\"}, "
        << (array ? "static_cast<int>(k_)" : "-1") << ", std::string_view{\"" << m.name
        << "\"}, self_." << g.name << (array ? "[k_]." : ".") << m.name << ");\n";
    }
    if (array)
      o << "    }\n";
  }
  o << "  }\n};\n\n";
}

// A block's Config, Pulses or Status over an integer-type family, C++14: the
// same members, names and reset values as emit_struct's; a register array is
// a C array.
void emit_family_struct(std::ostringstream& o, const Block& b, Port p) {
  o << "template <class F>\nstruct " << struct_name(p) << " {\n";
  for (const PortGroup& g : port_groups(b, p, Types::kFamily)) {
    const std::string type = ports_register_type(g.name);
    o << "  struct " << type << " {\n";
    for (const Member& m : g.members)
      o << "    " << m.type << " " << m.name << m.init << ";\n";
    o << "  } " << g.name;
    if (g.count != 0)
      o << "[" << g.count << "]";
    o << ";\n";
  }
  o << "};\n\n";
}

// One `case` per register with fields in `port`: `open` writes the case's
// first statements, `field` one statement per field, `close` the last.
template <class PerField, class Close>
void emit_cases(std::ostringstream& o, const Block& b, Port port, const std::string& open,
                PerField&& field, Close&& close) {
  for (const Register& r : b.registers) {
    if (!has(r, port))
      continue;
    o << "    case regs::" << b.name << "::" << r.name << "::kOffset:" << open;
    for (const auto& f : r.fields)
      if (in_port(f, port))
        field(r, f);
    o << close;
  }
}

void emit_block_functions(std::ostringstream& o, const Block& b) {
  const std::string ns = "regs::" + b.name + "::";
  o << "// Sets the Config ports of the rw register at `offset` from its stored word.\n"
    << "constexpr void decode_config(std::uint16_t offset, [[maybe_unused]] std::uint32_t word,\n"
    << "                             [[maybe_unused]] Config& c) {\n  switch (offset) {\n";
  emit_cases(
      o, b, Port::kConfig, "\n",
      [&](const Register& r, const Field& f) {
        const std::string port = "c." + r.port_member() + "." + f.name;
        const std::string get = ns + r.name + "::" + f.name + ".get(word)";
        o << "      " << port << " = UInt<" << f.port_width << ">::truncate(";
        if (r.wide.empty()) {
          o << get;
        } else {
          const std::uint64_t mask = ones(f.width()) << f.port_shift;
          o << "(" << raw(f, port) << " & " << hex64(~mask & ones(f.port_width))
            << ") | (std::uint64_t{" << get << "}";
          if (f.port_shift != 0)
            o << " << " << f.port_shift;
          o << ")";
        }
        o << ")" << (f.port_signed ? ".as_sint()" : "") << ";\n";
      },
      "      return;\n");
  o << "    default:\n      return;\n  }\n}\n\n";

  o << "// Raises the Pulses of the register at `offset` for the 1 bits of a written\n"
    << "// word (w1p commands, w1c clears); leaves the other pulses as they are.\n"
    << "constexpr void decode_pulses(std::uint16_t offset, [[maybe_unused]] std::uint32_t ones,\n"
    << "                             [[maybe_unused]] Pulses& p) {\n  switch (offset) {\n";
  emit_cases(
      o, b, Port::kPulses, "\n",
      [&](const Register& r, const Field& f) {
        const std::string port = "p." + r.port_member() + "." + f.name;
        o << "      " << port << " = " << port << " | UInt<" << f.width() << ">::truncate(" << ns
          << r.name << "::" << f.name << ".get(ones));\n";
      },
      "      return;\n");
  o << "    default:\n      return;\n  }\n}\n\n";

  o << "// The bits of the register word at `offset` that the hardware drives; 0\n"
    << "// elsewhere.\n"
    << "constexpr std::uint32_t encode_status(std::uint16_t offset, "
       "[[maybe_unused]] const Status& s) {\n  switch (offset) {\n";
  emit_cases(
      o, b, Port::kStatus, " {\n      std::uint32_t w = 0;\n",
      [&](const Register& r, const Field& f) {
        const std::string port = "s." + r.port_member() + "." + f.name;
        o << "      w = " << ns << r.name << "::" << f.name << ".set(w, static_cast<std::uint32_t>("
          << raw(f, port);
        if (f.port_shift != 0)
          o << " >> " << f.port_shift;
        o << "));\n";
      },
      "      return w;\n    }\n");
  o << "    default:\n      return 0;\n  }\n}\n\n";

  o << "// A read frame that completed without error popped `entries` whole elements\n"
    << "// (0..N; more count as N) off the FIFO of the rpop array whose element 0 is\n"
    << "// at `offset`: sets its pops. Other offsets: no effect.\n"
    << "constexpr void decode_pops(std::uint16_t offset, [[maybe_unused]] unsigned entries,\n"
    << "                           [[maybe_unused]] Pulses& p) {\n  switch (offset) {\n";
  for (const Group& g : groups(b)) {
    if (!g.pops)
      continue;
    o << "    case " << ns << g.name << "::kOffset:\n      p." << g.name
      << ".pops = " << pops_type(g.count) << "::truncate(entries < " << g.count
      << "U ? entries : " << g.count << "U);\n      return;\n";
  }
  o << "    default:\n      return;\n  }\n}\n\n";
}

}  // namespace

std::string emit_logic_ports(const RegisterMap& map) {
  std::ostringstream o;
  o << "// Generated by odoloc_regmap_gen from regmap/odoloc.yaml. Do not edit.\n"
    << "// The fabric's side of the register map over an integer-type family\n"
    << "// (logic/int_family.hpp), for the blocks' logic and the HLS kernels, in\n"
    << "// C++14: per block, Config (rw fields the hardware reads, reset values as\n"
    << "// member initialisers), Pulses (one-clock strobes of software writes) and\n"
    << "// Status (fields the hardware drives). The same members as odoloc/ports.hpp's\n"
    << "// structs of the model's types; a register array is a C array, and a\n"
    << "// 64-bit port is a logic::Words (two 32-bit words: a family integer holds\n"
    << "// at most 63 bits).\n"
    << "#pragma once\n\n#include \"odoloc/logic/int_family.hpp\"\n\n"
    << "namespace odoloc {\nnamespace logic {\nnamespace ports {\n\n";
  for (const Block& b : map.blocks) {
    if (b.reserved)
      continue;
    o << "/* " << comment_text(b.description) << " */\nnamespace " << b.name << " {\n\n";
    for (const Port p : {Port::kConfig, Port::kPulses, Port::kStatus})
      emit_family_struct(o, b, p);
    o << "}  // namespace " << b.name << "\n\n";
  }
  o << "}  // namespace ports\n}  // namespace logic\n}  // namespace odoloc\n";
  return o.str();
}

std::string emit_ports(const RegisterMap& map) {
  std::ostringstream o;
  o << "// Generated by odoloc_regmap_gen from regmap/odoloc.yaml. Do not edit.\n"
    << "// The fabric's side of the register map, typed with the model's integers:\n"
    << "// per block, Config (rw fields the hardware reads, reset values as default\n"
    << "// initialisers), Pulses (one-clock strobes of software writes: w1p commands\n"
    << "// and the clears of w1c flags) and Status (fields the hardware drives: live\n"
    << "// values, sticky flags, counters); wide registers appear once, at full\n"
    << "// width, and a register array once, as a std::array of its elements. An\n"
    << "// rpop array's Pulses member holds `pops`: the whole elements a completed\n"
    << "// read frame popped off its FIFO. decode_config/decode_pulses/encode_status/\n"
    << "// decode_pops convert between them and register words, by block offset (per\n"
    << "// block) or by word address (whole map).\n"
    << "#pragma once\n\n#include <array>\n#include <cstdint>\n#include <string_view>\n\n"
    << "#include \"odoloc/regs.hpp\"\n#include \"odoloc/rtl/bits.hpp\"\n\n"
    << "namespace odoloc::ports {\n\nusing rtl::SInt;\nusing rtl::UInt;\n\n";
  std::vector<const Block*> blocks;
  for (const Block& b : map.blocks) {
    if (!b.reserved)
      blocks.push_back(&b);
  }
  for (const Block* bp : blocks) {
    const Block& b = *bp;
    o << "/* " << comment_text(b.description) << " */\nnamespace " << b.name << " {\n\n";
    // The register map's enums, by field name (register + field on a clash);
    // a register array's by its element 0.
    std::map<std::string, int> uses = ports_enum_uses(b);
    bool any = false;
    for (const Register& r : b.registers) {
      if (r.element != 0)
        continue;
      for (const Field& f : r.fields) {
        if (f.enums.empty())
          continue;
        const std::string alias = ports_enum_alias(r, f, uses[f.name] > 1);
        o << "using " << alias << " = regs::" << b.name << "::" << r.name
          << "::" << cpp_enum_type(f) << ";\n";
        any = true;
      }
    }
    if (any)
      o << "\n";
    for (const Port p : {Port::kConfig, Port::kPulses, Port::kStatus})
      emit_struct(o, b, p);
    emit_block_functions(o, b);
    o << "}  // namespace " << b.name << "\n\n";
  }

  // Whole-map aggregates.
  for (const Port p : {Port::kConfig, Port::kPulses, Port::kStatus}) {
    const std::string name = struct_name(p);
    o << "struct " << name << " {\n";
    for (const Block* b : blocks) {
      const std::string type = "::odoloc::ports::" + b->name + "::" + name;
      if (b->instances.empty()) {
        o << "  " << type << " " << b->name << ";\n";
      } else {
        o << "  std::array<" << type << ", regs::" << b->name << "::kInstances> " << b->name
          << ";\n";
      }
    }
    o << "  bool operator==(const " << name << "&) const = default;\n"
      << "  // Calls f(name, member) for every block (rtl/fields.hpp's field list).\n"
      << "  template <class F>\n  constexpr void for_each_field(F&& f_) const {\n";
    for (const Block* b : blocks)
      o << "    f_(std::string_view{\"" << b->name << "\"}, " << b->name << ");\n";
    o << "  }\n"
      << "  // Calls v(block, instance (-1: a single block), register, element (-1: not\n"
      << "  // in a register array), field, port).\n"
      << "  template <class Self, class V>\n"
      << "  static constexpr void for_each_port([[maybe_unused]] Self& self_, [[maybe_unused]] V&& "
         "v_) {\n";
    for (const Block* b : blocks) {
      const std::string type = "::odoloc::ports::" + b->name + "::" + name;
      const auto call = [&](const std::string& member, const std::string& instance) {
        o << "    " << type << "::for_each_port(" << member
          << ", [&](std::string_view r_, int e_, std::string_view f_, auto& port_) { "
             "v_(std::string_view{\""
          << b->name << "\"}, " << instance << ", r_, e_, f_, port_); });\n";
      };
      if (b->instances.empty()) {
        call("self_." + b->name, "-1");
      } else {
        for (std::size_t i = 0; i < b->instances.size(); ++i)
          call("self_." + b->name + "[" + std::to_string(i) + "]", std::to_string(i));
      }
    }
    o << "  }\n};\n\n";
  }

  // Whole-map functions: dispatch by word address to the block functions.
  struct Target {
    std::uint32_t address, offset;
    std::string path;
    const Block* block;
    int instance;
  };
  const auto targets = [&](Port p) {
    std::vector<Target> out;
    for (const RegisterInstance& ri : flatten(map)) {
      if (has(*ri.reg, p))
        out.push_back({ri.address, ri.reg->offset, ri.path, ri.block, ri.instance});
    }
    return out;
  };
  // `signature` declares the function, switching on `selector`, a word address.
  const auto dispatch = [&](const std::vector<Target>& cases, Port p, const std::string& signature,
                            const std::string& selector, const std::string& call,
                            const std::string& arg, const std::string& fallback) {
    o << signature << " {\n  switch (" << selector << ") {\n";
    for (const Target& t : cases) {
      const std::string member =
          t.instance < 0 ? t.block->name : t.block->name + "[" + std::to_string(t.instance) + "]";
      o << "    case " << hex(t.address, 3) << ":  // " << t.path << "\n      "
        << (fallback.empty() ? "" : "return ") << t.block->name << "::" << call << "("
        << hex(t.offset) << ", " << (arg.empty() ? "" : arg + ", ")
        << (p == Port::kConfig   ? "c."
            : p == Port::kPulses ? "p."
                                 : "s.")
        << member << ");\n"
        << (fallback.empty() ? "      return;\n" : "");
    }
    o << "    default:\n      return" << (fallback.empty() ? "" : " " + fallback)
      << ";\n  }\n}\n\n";
  };
  o << "// Sets the Config ports of the rw register at a word address from its stored\n"
    << "// word (a wide register's _lo word sets bits 31:0, its _hi word the rest);\n"
    << "// other addresses: no effect.\n";
  dispatch(
      targets(Port::kConfig), Port::kConfig,
      "constexpr void decode_config(std::uint16_t address, [[maybe_unused]] std::uint32_t word,\n"
      "                             [[maybe_unused]] Config& c)",
      "address", "decode_config", "word", "");
  o << "// Raises the Pulses of a written register for the 1 bits of the written word\n"
    << "// (w1c clear strobes, w1p pulses); leaves the others as they are.\n";
  dispatch(
      targets(Port::kPulses), Port::kPulses,
      "constexpr void decode_pulses(std::uint16_t address, [[maybe_unused]] std::uint32_t ones,\n"
      "                             [[maybe_unused]] Pulses& p)",
      "address", "decode_pulses", "ones", "");
  o << "// The bits of the register word at a word address that the hardware drives\n"
    << "// (hw w, set and count fields); 0 elsewhere.\n";
  dispatch(targets(Port::kStatus), Port::kStatus,
           "constexpr std::uint32_t encode_status(std::uint16_t address,\n"
           "                                      [[maybe_unused]] const Status& s)",
           "address", "encode_status", "", "0");
  o << "// A read frame that completed without error popped `entries` whole elements\n"
    << "// (0..N; more count as N) off the FIFO of the rpop array whose element 0\n"
    << "// starts at `first_address` (regs::kPopWindows): sets that array's pops in\n"
    << "// its block instance. Other addresses: no effect.\n";
  std::vector<Target> windows;
  for (const PopWindow& w : pop_windows(map))
    windows.push_back({w.first, w.head->offset, w.path, w.block, w.instance});
  dispatch(windows, Port::kPulses,
           "constexpr void decode_pops(std::uint16_t first_address, [[maybe_unused]] unsigned "
           "entries,\n"
           "                           [[maybe_unused]] Pulses& p)",
           "first_address", "decode_pops", "entries", "");
  o << "}  // namespace odoloc::ports\n";
  return o.str();
}

}  // namespace odoloc::regmap
