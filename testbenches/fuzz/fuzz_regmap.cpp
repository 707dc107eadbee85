// libFuzzer target: the register-map generator on arbitrary YAML (the file
// users write). Seeded with testbenches/tools/regmap_corpus/.
//
// Invariants: parse() either returns a map or throws RegmapError (never
// another exception, never a crash, a hang or a sanitizer finding); for an
// accepted map every emitter runs, and the outputs are well-formed at the
// lexical level: no control characters but newlines; in C and C++ every
// comment closes where it should and no string literal spans a line;
// braces balance outside comments and strings; in SystemRDL strings close
// and braces balance; every Markdown table row has its table's cell count.
// Register arrays (count) and rpop FIFOs (the corpus seeds both): every
// element is where its array says, and the pop windows are the rpop arrays,
// in address order, each inside the map and apart from the others.
// (test_regmap_corpus compiles the outputs of its corpus for real.)
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz_require.hpp"
#include "markdown_table.hpp"
#include "odoloc/regmap/regmap.hpp"

namespace {

namespace rm = odoloc::regmap;

using odoloc::tb::require;

void no_control_characters(const std::string& s) {
  for (const char c : s) {
    require(c == '\n' || static_cast<unsigned char>(c) >= 0x20, "control character in an output",
            s);
    require(c != 0x7F, "DEL in an output", s);
  }
}

// C and C++: comments close, strings stay on their line, braces balance.
void c_like(const std::string& s, bool line_comments) {
  long depth = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    const char next = i + 1 < s.size() ? s[i + 1] : '\0';
    if (c == '/' && next == '*') {
      const auto end = s.find("*/", i + 2);
      require(end != std::string::npos, "unterminated /* comment", s);
      require(s.substr(i + 2, end - i - 2).find("/*") == std::string::npos, "/* inside a comment",
              s);
      i = end + 1;
    } else if (c == '/' && next == '/') {
      require(line_comments, "// comment in C", s);
      const auto end = s.find('\n', i);
      require(end == std::string::npos || s[end - 1] != '\\', "// comment continues", s);
      i = end == std::string::npos ? s.size() : end;
    } else if (c == '"') {
      for (++i; i < s.size() && s[i] != '"'; ++i) {
        require(s[i] != '\n', "string literal spans a line", s);
        if (s[i] == '\\')
          ++i;
      }
      require(i < s.size(), "unterminated string literal", s);
    } else if (c == '{' || c == '}') {
      depth += c == '{' ? 1 : -1;
      require(depth >= 0, "unbalanced braces", s);
    }
  }
  require(depth == 0, "unbalanced braces", s);
}

void rdl(const std::string& s) {
  long depth = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '/' && i + 1 < s.size() && s[i + 1] == '/') {
      i = s.find('\n', i);
      if (i == std::string::npos)
        break;
    } else if (c == '"') {
      for (++i; i < s.size() && s[i] != '"'; ++i) {
        if (s[i] == '\\')
          ++i;
      }
      require(i < s.size(), "unterminated SystemRDL string", s);
    } else if (c == '{' || c == '}') {
      depth += c == '{' ? 1 : -1;
      require(depth >= 0, "unbalanced SystemRDL braces", s);
    }
  }
  require(depth == 0, "unbalanced SystemRDL braces", s);
}

// The elements of every register array, and the rpop windows.
void arrays(const rm::RegisterMap& map) {
  for (const rm::Block& b : map.blocks) {
    for (const rm::Register& r : b.registers) {
      if (r.array.empty()) {
        require(r.access != rm::Access::kRpop, "an rpop register outside an array", r.name);
        continue;
      }
      require(r.count >= 1 && r.count <= 64 && r.element < r.count, "array bounds", r.name);
      require(r.name == r.array + std::to_string(r.element) +
                            (r.wide.empty() ? ""
                             : r.word == 0  ? "_lo"
                                            : "_hi"),
              "an element's name", r.name);
      require(r.offset ==
                  r.array_offset() + static_cast<std::uint32_t>(r.element * r.array_words + r.word),
              "an element's offset", r.name);
      require(r.access != rm::Access::kRpop || r.snapshot, "an rpop register without snapshot",
              r.name);
    }
  }
  std::uint32_t next = 0;
  for (const rm::PopWindow& w : rm::pop_windows(map)) {
    require(w.head != nullptr && w.head->access == rm::Access::kRpop && w.head->array_head(),
            "a pop window's head", w.path);
    require(w.first >= next, "pop windows out of order or overlapping", w.path);
    next = w.first + static_cast<std::uint32_t>(w.entries * w.words);
    require(next <= (std::uint32_t{1} << map.address_bits), "a pop window outside the map", w.path);
  }
}

std::size_t cells(const std::string& row) {
  return odoloc::tb::unescaped_pipes(row);
}

void markdown(const std::string& s) {
  std::istringstream in(s);
  std::size_t want = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind('|', 0) != 0) {
      want = 0;
      continue;
    }
    if (want == 0)
      want = cells(line);
    require(cells(line) == want, "a Markdown row with the wrong number of cells", line);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string yaml(reinterpret_cast<const char*>(data), size);
  rm::RegisterMap map;
  try {
    map = rm::parse(yaml);
  } catch (const rm::RegmapError&) {
    return 0;
  }
  const std::string cpp = rm::emit_cpp(map), ports = rm::emit_ports(map), c = rm::emit_c(map),
                    r = rm::emit_systemrdl(map), md = rm::emit_markdown(map);
  for (const std::string* s : {&cpp, &ports, &c, &r, &md})
    no_control_characters(*s);
  c_like(cpp, true);
  c_like(ports, true);
  c_like(c, false);
  rdl(r);
  markdown(md);
  arrays(map);
  return 0;
}
