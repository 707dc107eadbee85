#include "odoloc/cli/format.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace odoloc::cli {

std::string json_line(const nlohmann::json& doc) {
  return doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

namespace {

const regs::Enumerator* enumerator(const regs::Field& f, std::uint32_t raw) {
  for (const regs::Enumerator& e : f.enums) {
    if (e.value == raw)
      return &e;
  }
  return nullptr;
}

std::string hex_bits(const regs::Field& f, std::uint32_t raw) {
  return fmt::format("0x{:0{}x}", raw, (f.width + 3U) / 4U);
}

std::string fields_joined(const regs::Register& reg, std::uint32_t word, std::string_view sep) {
  std::string out;
  for (const regs::Field& f : reg.fields)
    out += fmt::format("{}{}={}", out.empty() ? "" : sep, f.name, field_compact(f, word));
  return out;
}

}  // namespace

std::string_view access_name(regs::Access access) {
  switch (access) {
    case regs::Access::kRo:
      return "ro";
    case regs::Access::kRw:
      return "rw";
    case regs::Access::kW1c:
      return "w1c";
    case regs::Access::kRc:
      return "rc";
    case regs::Access::kW1p:
      return "w1p";
    case regs::Access::kRpop:
      return "rpop";
  }
  return "?";
}

unsigned msb(const regs::Field& field) {
  return field.lsb + field.width - 1U;
}

std::string bit_range(const regs::Field& field) {
  return field.width == 1 ? fmt::format("{}", field.lsb)
                          : fmt::format("{}:{}", msb(field), field.lsb);
}

std::int64_t field_signed(const regs::Field& field, std::uint32_t word) {
  return field.get_signed(word);
}

std::string field_compact(const regs::Field& field, std::uint32_t word) {
  const std::uint32_t raw = field.get(word);
  if (const regs::Enumerator* e = enumerator(field, raw))
    return std::string{e->name};
  if (field.is_signed)
    return fmt::format("{}", field_signed(field, word));
  return fmt::format("{}", raw);
}

std::string field_text(const regs::Field& field, std::uint32_t word) {
  const std::uint32_t raw = field.get(word);
  if (!field.enums.empty()) {
    const regs::Enumerator* e = enumerator(field, raw);
    return e != nullptr ? fmt::format("{} ({})", e->name, raw)
                        : fmt::format("{} (no enumerator)", raw);
  }
  if (field.is_signed)
    return fmt::format("{} ({})", field_signed(field, word), hex_bits(field, raw));
  if (field.width == 1)
    return fmt::format("{}", raw);
  return fmt::format("{} ({})", raw, hex_bits(field, raw));
}

nlohmann::json field_json(const regs::Field& field, std::uint32_t word) {
  const std::uint32_t raw = field.get(word);
  if (const regs::Enumerator* e = enumerator(field, raw))
    return std::string{e->name};
  if (field.is_signed)
    return field_signed(field, word);
  return raw;
}

nlohmann::json describe_json(const regs::Register& reg) {
  nlohmann::json fields = nlohmann::json::array();
  for (const regs::Field& f : reg.fields) {
    nlohmann::json enums = nlohmann::json::array();
    for (const regs::Enumerator& e : f.enums)
      enums.push_back({{"name", e.name}, {"value", e.value}});
    fields.push_back({{"name", f.name},
                      {"path", Location{&reg, &f}.path()},
                      {"bits", {msb(f), f.lsb}},
                      {"lsb", f.lsb},
                      {"width", f.width},
                      {"access", access_name(f.access)},
                      {"reset", f.reset},
                      {"signed", f.is_signed},
                      {"description", f.description},
                      {"enums", std::move(enums)}});
  }
  return {
      {"path", reg.path},           {"address", reg.address},   {"access", access_name(reg.access)},
      {"reset", reg.reset},         {"snapshot", reg.snapshot}, {"description", reg.description},
      {"fields", std::move(fields)}};
}

std::string list_text(std::span<const regs::Register* const> registers) {
  std::size_t width = std::string_view{"REGISTER"}.size();
  for (const regs::Register* r : registers)
    width = std::max(width, r->path.size());
  std::string out = fmt::format("{:<7}{:<8}{:<12}{:<{}}  {}\n", "ADDR", "ACCESS", "RESET",
                                "REGISTER", width, "DESCRIPTION");
  for (const regs::Register* r : registers) {
    out += fmt::format("0x{:03x}  {:<8}0x{:08x}  {:<{}}  {}\n", r->address, access_name(r->access),
                       r->reset, r->path, width, r->description);
  }
  return out;
}

nlohmann::json value_json(const Location& loc, std::uint32_t word) {
  if (loc.field != nullptr) {
    return {{"path", loc.path()},          {"register", loc.reg->path},
            {"address", loc.reg->address}, {"word", word},
            {"raw", loc.field->get(word)}, {"value", field_json(*loc.field, word)}};
  }
  nlohmann::json fields = nlohmann::json::object();
  for (const regs::Field& f : loc.reg->fields)
    fields[std::string{f.name}] = field_json(f, word);
  return {{"path", loc.reg->path},
          {"address", loc.reg->address},
          {"value", word},
          {"fields", std::move(fields)}};
}

std::string value_text(const Location& loc, std::uint32_t word) {
  if (loc.field != nullptr)
    return fmt::format("{} = {}\n", loc.path(), field_text(*loc.field, word));
  std::size_t width = 0;
  for (const regs::Field& f : loc.reg->fields)
    width = std::max(width, f.name.size());
  std::string out =
      fmt::format("{} @ 0x{:03x} = 0x{:08x}\n", loc.reg->path, loc.reg->address, word);
  for (const regs::Field& f : loc.reg->fields) {
    out += fmt::format("  {:<{}}  {:<8} {}\n", f.name, width, fmt::format("[{}]", bit_range(f)),
                       field_text(f, word));
  }
  return out;
}

std::string value_compact(const Location& loc, std::uint32_t word) {
  if (loc.field != nullptr)
    return fmt::format("{}={}", loc.path(), field_compact(*loc.field, word));
  return fmt::format("{}=0x{:08x}({})", loc.reg->path, word, fields_joined(*loc.reg, word, ","));
}

std::string dump_line(const regs::Register& reg, std::uint32_t word, std::size_t path_width) {
  return fmt::format("0x{:03x}  {:<{}}  0x{:08x}  {}\n", reg.address, reg.path, path_width, word,
                     fields_joined(reg, word, " "));
}

}  // namespace odoloc::cli
