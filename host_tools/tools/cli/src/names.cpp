#include "odoloc/cli/names.hpp"

#include <fmt/format.h>
#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <tuple>
#include <utility>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/values.hpp"

namespace odoloc::cli {
namespace {

constexpr std::uint32_t kAddressSpace = std::uint32_t{1} << regs::kAddressBits;

char lower(char c) {
  return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
}

bool iequal(std::string_view a, std::string_view b) {
  return std::ranges::equal(a, b, [](char x, char y) { return lower(x) == lower(y); });
}

// `needle` is a (case-insensitive) subsequence of `hay`: "cnt" in "count".
bool is_subsequence(std::string_view needle, std::string_view hay) {
  std::size_t i = 0;
  for (const char c : hay) {
    if (i < needle.size() && lower(needle[i]) == lower(c))
      ++i;
  }
  return i == needle.size();
}

std::size_t components(std::string_view s) {
  return static_cast<std::size_t>(std::ranges::count(s, '.')) + 1;
}

// The last `n` dot-separated components of `path`.
std::string_view tail(std::string_view path, std::size_t n) {
  std::size_t start = path.size();
  for (std::size_t k = 0; k < n; ++k) {
    if (start == 0)
      return path;
    const std::size_t dot = path.rfind('.', start - 1);
    if (dot == std::string_view::npos)
      return path;
    start = dot;
  }
  return path.substr(start + 1);
}

// Distance of a typed name to a path: the whole path, or its tail with as
// many components as the name (one more edit for the missing prefix), so
// "scratch" is near "top.scratch".
std::size_t name_distance(std::string_view name, std::string_view path) {
  std::size_t d = edit_distance(name, path);
  const std::size_t n = components(name);
  if (n < components(path))
    d = std::min(d, edit_distance(name, tail(path, n)) + 1);
  return d;
}

std::string join_alternatives(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0)
      out += i + 1 == items.size() ? " or " : ", ";
    out += items[i];
  }
  return out;
}

std::string field_names(const regs::Register& reg) {
  std::string out;
  for (const regs::Field& f : reg.fields)
    out += fmt::format("{}{}", out.empty() ? "" : ", ", f.name);
  return out;
}

// The fields of `reg` near a mistyped field name (close in spelling, or
// starting with it), else the list of its fields.
std::string field_hint(const regs::Register& reg, std::string_view typed) {
  std::vector<std::pair<std::size_t, std::string>> near;
  const std::size_t threshold = std::max<std::size_t>(2, typed.size() / 3);
  for (const regs::Field& f : reg.fields) {
    const std::size_t d = edit_distance(typed, f.name);
    if (d <= threshold || (!typed.empty() && f.name.starts_with(typed)))
      near.emplace_back(d, Location{&reg, &f}.path());
  }
  std::ranges::sort(near);
  if (near.empty())
    return fmt::format("; {} has the fields {}", reg.path, field_names(reg));
  std::vector<std::string> paths;
  for (auto& [d, p] : near)
    paths.push_back(std::move(p));
  return fmt::format("; did you mean {}?", join_alternatives(paths));
}

// The spelling of a path in the other artefacts generated from the same
// YAML, reduced to one key: odoloc.rdl and PeakRDL (eppm_left_rear.cfg,
// odoloc.eppm_left_rear.cfg.decode_mode), the C header
// (ODOLOC_EPPM_LEFT_REAR_CFG_ADDR) and the tool's own paths all become
// "eppm_left_rear_cfg[_decode_mode]".
std::string artefact_key(std::string_view name) {
  std::string key;
  for (const char c : name) {
    const char l = c == '.' ? '_' : lower(c);
    if (l == '_' && (key.empty() || key.back() == '_'))
      continue;  // PeakRDL's "__" separators, leading '_'
    key += l;
  }
  if (key.starts_with("odoloc_"))
    key.erase(0, std::string_view{"odoloc_"}.size());
  if (key.ends_with("_addr"))
    key.erase(key.size() - std::string_view{"_addr"}.size());
  return key;
}

// Every register and field whose artefact key is `key`.
std::vector<Location> by_artefact_key(const std::string& key) {
  std::vector<Location> out;
  for (const regs::Register& r : regs::kRegisters) {
    if (artefact_key(r.path) == key)
      out.push_back({&r, nullptr});
    for (const regs::Field& f : r.fields) {
      if (artefact_key(Location{&r, &f}.path()) == key)
        out.push_back({&r, &f});
    }
  }
  return out;
}

std::string hex_address(std::uint64_t a) {
  return fmt::format("0x{:03x}", a);
}

// "w:ADDR" and "b:ADDR", or a bare number: see resolve().
const regs::Register& register_at_text(std::string_view text) {
  if (text.starts_with("w:") || text.starts_with("W:"))
    return register_at(parse_address(text.substr(2)));
  if (text.starts_with("b:") || text.starts_with("B:"))
    return register_at(parse_byte_address(text.substr(2)));
  const Number n = parse_number(text);
  const bool as_byte = !n.negative && n.magnitude != 0 && n.magnitude % 4 == 0 &&
                       n.magnitude / 4 < kAddressSpace &&
                       regs::find(static_cast<std::uint32_t>(n.magnitude / 4)) != nullptr;
  if (!as_byte)
    return register_at(parse_address(text));
  // A bare number that is also the byte address (odoloc.rdl, PeakRDL: 4 × the
  // word address) of a different register: which one was meant is unknowable.
  const regs::Register& byte_reg = *regs::find(static_cast<std::uint32_t>(n.magnitude / 4));
  const regs::Register* word_reg =
      n.magnitude < kAddressSpace ? regs::find(static_cast<std::uint32_t>(n.magnitude)) : nullptr;
  if (word_reg == &byte_reg)
    return byte_reg;
  const std::string as_word =
      word_reg != nullptr
          ? fmt::format("word address {} is {}", hex_address(n.magnitude), word_reg->path)
      : n.magnitude < kAddressSpace
          ? fmt::format("word address {} is unmapped", hex_address(n.magnitude))
          : fmt::format("it is beyond the word addresses 0x000..{}",
                        hex_address(kAddressSpace - 1));
  throw UsageError(fmt::format(
      "address {} is ambiguous: {} (odoloc's addresses, as in docs/spi.md and odoloc_regs.h), "
      "byte address {} (odoloc.rdl, PeakRDL) is {} at word {}; write w:{} or b:{}, or the name",
      text, as_word, hex_address(n.magnitude), byte_reg.path, hex_address(byte_reg.address), text,
      text));
}

}  // namespace

std::string Location::path() const {
  std::string p{reg->path};
  if (field != nullptr) {
    p += '.';
    p += field->name;
  }
  return p;
}

std::uint16_t parse_address(std::string_view text) {
  const Number n = parse_number(text);
  if (n.negative && n.magnitude != 0)
    throw UsageError(fmt::format("address {} is negative", text));
  if (n.magnitude >= kAddressSpace)
    throw UsageError(fmt::format("address {} is out of range (word addresses 0x000..0x{:03x})",
                                 text, kAddressSpace - 1));
  return static_cast<std::uint16_t>(n.magnitude);
}

std::uint16_t parse_byte_address(std::string_view text) {
  const Number n = parse_number(text);
  if (n.negative && n.magnitude != 0)
    throw UsageError(fmt::format("byte address {} is negative", text));
  if (n.magnitude % 4 != 0)
    throw UsageError(fmt::format(
        "byte address {} is not a multiple of 4 (registers are 32-bit words at 4 × the word "
        "address)",
        text));
  if (n.magnitude / 4 >= kAddressSpace)
    throw UsageError(fmt::format("byte address {} is out of range (byte addresses 0x000..0x{:03x})",
                                 text, (kAddressSpace - 1) * 4));
  return static_cast<std::uint16_t>(n.magnitude / 4);
}

const regs::Register& register_at(std::uint16_t address) {
  if (const regs::Register* r = regs::find(std::uint32_t{address}))
    return *r;
  for (const regs::Reserved& block : regs::kReserved) {
    if (address >= block.base && address - block.base < block.size)
      throw UsageError(
          fmt::format("address 0x{:03x} is unmapped (reserved block {}, 0x{:03x}..0x{:03x})",
                      address, block.name, block.base, block.base + block.size - 1));
  }
  const regs::Register* below = nullptr;
  const regs::Register* above = nullptr;
  for (const regs::Register& r : regs::kRegisters) {
    if (r.address < address && (below == nullptr || r.address > below->address))
      below = &r;
    if (r.address > address && (above == nullptr || r.address < above->address))
      above = &r;
  }
  std::string near;
  for (const regs::Register* r : {below, above}) {
    if (r != nullptr)
      near += fmt::format("{}{} at 0x{:03x}", near.empty() ? "" : ", ", r->path, r->address);
  }
  throw UsageError(fmt::format("address 0x{:03x} is unmapped{}", address,
                               near.empty() ? std::string{} : fmt::format(" (nearest: {})", near)));
}

Location resolve(std::string_view name) {
  if (name.empty())
    throw UsageError("empty register name");
  if (looks_numeric(name) || name.starts_with("w:") || name.starts_with("W:") ||
      name.starts_with("b:") || name.starts_with("B:"))
    return {&register_at_text(name), nullptr};
  if (const regs::Register* r = regs::find(name))
    return {r, nullptr};
  if (const std::size_t dot = name.rfind('.'); dot != std::string_view::npos) {
    if (const regs::Register* r = regs::find(name.substr(0, dot))) {
      const std::string_view field_name = name.substr(dot + 1);
      for (const regs::Field& f : r->fields) {
        if (f.name == field_name)
          return {r, &f};
      }
      throw UsageError(fmt::format("unknown field '{}'{}", name, field_hint(*r, field_name)));
    }
  }
  // The same register as spelt in odoloc.rdl, PeakRDL's outputs or the C
  // header: the same register here.
  const std::vector<Location> same = by_artefact_key(artefact_key(name));
  if (same.size() == 1)
    return same.front();
  if (same.size() > 1) {
    std::vector<std::string> paths;
    for (const Location& l : same)
      paths.push_back(l.path());
    throw UsageError(
        fmt::format("'{}' is ambiguous: it could be {}", name, join_alternatives(paths)));
  }
  const std::vector<std::string> near = closest_paths(name);
  throw UsageError(fmt::format("unknown register '{}'{}", name,
                               near.empty()
                                   ? std::string{" ('odoloc reg list' shows every register)"}
                                   : fmt::format("; did you mean {}?", join_alternatives(near))));
}

std::vector<std::string> all_paths() {
  std::vector<std::string> paths;
  for (const regs::Register& r : regs::kRegisters)
    paths.emplace_back(r.path);
  for (const regs::Register& r : regs::kRegisters) {
    for (const regs::Field& f : r.fields)
      paths.push_back(Location{&r, &f}.path());
  }
  return paths;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  // Three rows: i-2, i-1, i.
  std::vector<std::size_t> prev2(m + 1), prev(m + 1), cur(m + 1);
  for (std::size_t j = 0; j <= m; ++j)
    prev[j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= m; ++j) {
      const bool same = lower(a[i - 1]) == lower(b[j - 1]);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0U : 1U)});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1]))
        cur[j] = std::min(cur[j], prev2[j - 2] + 1);
    }
    std::swap(prev2, prev);
    std::swap(prev, cur);
  }
  return prev[m];
}

std::vector<std::string> closest_paths(std::string_view name, std::size_t max) {
  struct Scored {
    std::size_t distance;
    bool subsequence;
    std::size_t length_gap;
    std::string path;
  };
  std::vector<Scored> scored;
  for (std::string& p : all_paths()) {
    const std::size_t gap =
        p.size() > name.size() ? p.size() - name.size() : name.size() - p.size();
    scored.push_back({name_distance(name, p), is_subsequence(name, p), gap, std::move(p)});
  }
  std::ranges::sort(scored, [](const Scored& x, const Scored& y) {
    return std::tie(x.distance, y.subsequence, x.length_gap, x.path) <
           std::tie(y.distance, x.subsequence, y.length_gap, y.path);
  });
  std::vector<std::string> out;
  if (scored.empty())
    return out;
  const std::size_t best = scored.front().distance;
  const std::size_t threshold = std::max<std::size_t>(2, name.size() / 3);
  if (best > threshold)
    return out;
  for (const Scored& s : scored) {
    if (s.distance != best || out.size() == max)
      break;
    if (!iequal(s.path, name))
      out.push_back(s.path);
  }
  return out;
}

bool path_matches(std::string_view path, std::string_view filter) {
  if (filter.empty())
    return true;
  if (filter.find_first_of("*?[") == std::string_view::npos)
    return path.find(filter) != std::string_view::npos;
  // Globs work per component: '.' plays the part of '/' under FNM_PATHNAME,
  // so "eppm.*.count" matches the four count registers and nothing deeper.
  std::string pattern{filter}, subject{path};
  std::ranges::replace(pattern, '.', '/');
  std::ranges::replace(subject, '.', '/');
  return fnmatch(pattern.c_str(), subject.c_str(), FNM_PATHNAME) == 0;
}

bool register_matches(const regs::Register& reg, std::string_view filter) {
  if (path_matches(reg.path, filter))
    return true;
  return std::ranges::any_of(reg.fields, [&](const regs::Field& f) {
    return path_matches(Location{&reg, &f}.path(), filter);
  });
}

}  // namespace odoloc::cli
