#include "odoloc/cli/commands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <ranges>
#include <utility>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/cli/locate_input.hpp"
#include "odoloc/cli/values.hpp"

namespace odoloc::cli {
namespace {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;  // clang 14 has no aggregate CTAD

bool has_rc_bits(const regs::Register& reg) {
  return reg.access == regs::Access::kRc ||
         std::ranges::any_of(reg.fields,
                             [](const regs::Field& f) { return f.access == regs::Access::kRc; });
}

void check_writable(regs::Access access, const std::string& path) {
  if (access == regs::Access::kRo)
    throw UsageError(fmt::format("{} is read-only (ro): nothing written", path));
  if (access == regs::Access::kRc)
    throw UsageError(fmt::format("{} is read-to-clear (rc), not writable: nothing written", path));
}

// Reads the registers under `addresses` (sorted, unique) in bursts of
// consecutive addresses: one frame per run, so snapshot registers read together
// are coherent.
std::map<std::uint16_t, std::uint32_t> read_runs(sw::RegisterBus& bus,
                                                 std::vector<std::uint16_t> addresses) {
  std::ranges::sort(addresses);
  addresses.erase(std::unique(addresses.begin(), addresses.end()), addresses.end());
  std::map<std::uint16_t, std::uint32_t> words;
  for (std::size_t i = 0; i < addresses.size();) {
    std::size_t j = i + 1;
    while (j < addresses.size() && addresses[j] == addresses[j - 1] + 1)
      ++j;
    std::vector<std::uint32_t> burst(j - i);
    bus.read(addresses[i], burst);
    for (std::size_t k = 0; k < burst.size(); ++k)
      words[addresses[i + k]] = burst[k];
    i = j;
  }
  return words;
}

std::map<std::uint16_t, std::uint32_t> read_locations(sw::RegisterBus& bus,
                                                      const std::vector<Location>& items) {
  std::vector<std::uint16_t> addresses;
  for (const Location& loc : items)
    addresses.push_back(loc.address());
  return read_runs(bus, std::move(addresses));
}

Target& need(Target* target) {
  if (target == nullptr)
    throw std::logic_error("this command needs a target");
  return *target;
}

void emit(std::ostream& out, const nlohmann::json& doc) {
  out << json_line(doc) << '\n' << std::flush;
}

void run_list(const ListCommand& cmd, std::ostream& out, bool json) {
  std::vector<const regs::Register*> selected;
  for (const regs::Register& r : regs::kRegisters) {
    if (register_matches(r, cmd.filter))
      selected.push_back(&r);
  }
  if (json) {
    nlohmann::json list = nlohmann::json::array();
    for (const regs::Register* r : selected)
      list.push_back(describe_json(*r));
    emit(out, {{"registers", std::move(list)}});
    return;
  }
  if (selected.empty()) {
    out << fmt::format("no register or field matches '{}'\n", cmd.filter);
    return;
  }
  out << list_text(selected);
}

void run_read(const ReadCommand& cmd, Target& target, std::ostream& out, bool json) {
  const auto words = read_locations(target.bus(), cmd.items);
  if (json) {
    nlohmann::json values = nlohmann::json::array();
    for (const Location& loc : cmd.items)
      values.push_back(value_json(loc, words.at(loc.address())));
    emit(out, {{"values", std::move(values)}});
    return;
  }
  for (const Location& loc : cmd.items)
    out << value_text(loc, words.at(loc.address()));
}

void run_write(const WriteCommand& cmd, Target& target, std::ostream& out, bool json) {
  sw::RegisterBus& bus = target.bus();
  nlohmann::json writes = nlohmann::json::array();
  for (const Assignment& a : cmd.items) {
    const regs::Register& reg = *a.target.reg;
    const regs::Field* field = a.target.field;
    std::uint32_t word = a.value;
    std::uint32_t before = 0;
    const WriteMode mode = a.mode();
    if (mode == WriteMode::kReadModifyWrite) {
      before = bus.read(reg.address);
      word = field->set(before & reg.rw_mask, a.value);
    } else if (mode == WriteMode::kFieldOnly) {
      word = field->set(0, a.value);
    }
    bus.write(reg.address, word);
    if (json) {
      nlohmann::json w = {{"path", a.target.path()},
                          {"register", reg.path},
                          {"address", reg.address},
                          {"word", word}};
      w["mode"] = mode == WriteMode::kWord              ? "word"
                  : mode == WriteMode::kReadModifyWrite ? "read-modify-write"
                                                        : "field-only";
      if (field != nullptr)
        w["value"] = field_json(*field, word);
      if (mode == WriteMode::kReadModifyWrite)
        w["read"] = before;
      writes.push_back(std::move(w));
      continue;
    }
    const std::string target_text =
        fmt::format("{} @ 0x{:03x} <- 0x{:08x}", reg.path, reg.address, word);
    if (mode == WriteMode::kWord)
      out << target_text << '\n';
    else if (mode == WriteMode::kReadModifyWrite)
      out << fmt::format("{} = {}: {} (read 0x{:08x})\n", a.target.path(), field_text(*field, word),
                         target_text, before);
    else
      out << fmt::format("{} = {}: {} (only this field's bits)\n", a.target.path(),
                         field_text(*field, word), target_text);
  }
  if (json)
    emit(out, {{"writes", std::move(writes)}});
}

std::vector<const regs::Register*> by_address() {
  std::vector<const regs::Register*> all;
  for (const regs::Register& r : regs::kRegisters)
    all.push_back(&r);
  std::ranges::sort(all, {}, &regs::Register::address);
  return all;
}

void run_dump(const DumpCommand& cmd, Target& target, std::ostream& out, bool json) {
  std::vector<const regs::Register*> all = by_address();
  std::erase_if(all, [&](const regs::Register* r) { return !register_matches(*r, cmd.filter); });
  if (all.empty() && !json) {
    out << fmt::format("no register or field matches '{}'\n", cmd.filter);
    return;
  }
  std::vector<std::uint16_t> addresses;
  std::size_t width = 0;
  for (const regs::Register* r : all) {
    addresses.push_back(r->address);
    width = std::max(width, r->path.size());
  }
  const auto words = read_runs(target.bus(), std::move(addresses));
  if (json) {
    nlohmann::json values = nlohmann::json::array();
    for (const regs::Register* r : all)
      values.push_back(value_json({r, nullptr}, words.at(r->address)));
    emit(out, {{"values", std::move(values)}});
    return;
  }
  for (const regs::Register* r : all)
    out << dump_line(*r, words.at(r->address), width);
}

void run_watch(const WatchCommand& cmd, Target& target, std::ostream& out, bool json,
               const std::atomic<bool>* stop) {
  const auto check_stop = [stop] {
    if (stop != nullptr && stop->load())
      throw Interrupted();
  };
  const std::chrono::nanoseconds t0 = target.elapsed();
  for (std::uint64_t sample = 0; cmd.count == 0 || sample < cmd.count; ++sample) {
    check_stop();
    if (sample > 0)
      target.wait(cmd.interval);  // throws Interrupted on Ctrl-C
    check_stop();
    const std::chrono::nanoseconds t = target.elapsed() - t0;
    const auto words = read_locations(target.bus(), cmd.items);
    if (json) {
      nlohmann::json values = nlohmann::json::array();
      for (const Location& loc : cmd.items)
        values.push_back(value_json(loc, words.at(loc.address())));
      emit(out, {{"sample", sample}, {"time_ns", t.count()}, {"values", std::move(values)}});
      continue;
    }
    std::string line = fmt::format("{:.6f} s", std::chrono::duration<double>(t).count());
    for (const Location& loc : cmd.items)
      line += fmt::format("  {}", value_compact(loc, words.at(loc.address())));
    out << line << '\n' << std::flush;
  }
}

void run_wait(const WaitCommand& cmd, Target& target, std::ostream& out, bool json,
              const std::atomic<bool>* stop) {
  if (stop != nullptr && stop->load())
    throw Interrupted();
  target.wait(cmd.duration);  // throws Interrupted on Ctrl-C
  if (json)
    emit(out, {{"waited_ns", cmd.duration.count()}});
}

}  // namespace

WriteMode Assignment::mode() const {
  if (target.field == nullptr)
    return WriteMode::kWord;
  return target.field->access == regs::Access::kRw ? WriteMode::kReadModifyWrite
                                                   : WriteMode::kFieldOnly;
}

Assignment parse_assignment(std::string_view text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string_view::npos)
    throw UsageError(fmt::format(
        "bad assignment '{}': expected NAME=VALUE or NAME.FIELD=VALUE (e.g. top.scratch=5)", text));
  const std::string_view name = text.substr(0, eq);
  const std::string_view value = text.substr(eq + 1);
  Assignment a{resolve(name)};
  const std::string path = a.target.path();
  if (value.empty())
    throw UsageError(fmt::format("missing value in '{}'", text));
  if (a.target.field == nullptr) {
    check_writable(a.target.reg->access, path);
    a.value = parse_register_value(*a.target.reg, value);
    return a;
  }
  check_writable(a.target.field->access, path);
  if (a.target.field->access == regs::Access::kRw && has_rc_bits(*a.target.reg))
    throw UsageError(fmt::format(
        "{} shares its register with read-to-clear bits; a read-modify-write would clear them: "
        "write the whole register",
        path));
  a.value = parse_field_value(*a.target.field, path, value);
  return a;
}

std::vector<std::string> split_line(std::string_view line) {
  std::vector<std::string> words;
  std::string current;
  bool in_word = false;
  char quote = 0;
  for (const char c : line) {
    if (quote != 0) {
      if (c == quote)
        quote = 0;
      else
        current += c;
      continue;
    }
    if (c == '#' && !in_word)
      break;
    if (std::isspace(static_cast<unsigned char>(c)) != 0) {
      if (in_word)
        words.push_back(std::exchange(current, {}));
      in_word = false;
      continue;
    }
    in_word = true;
    if (c == '"' || c == '\'')
      quote = c;
    else
      current += c;
  }
  if (quote != 0)
    throw UsageError(fmt::format("unterminated {} quote", quote));
  if (in_word)
    words.push_back(std::move(current));
  return words;
}

std::string version_text() {
  return fmt::format("odoloc {} (register map: top.id reset 0x{:08x})", ODOLOC_VERSION,
                     regs::top::id::kReset);
}

void check_simulated(const Command& command, const SimulatedLimit& limit) {
  using std::chrono::nanoseconds;
  const std::string at_most = fmt::format("at most {} s per command{}, about {} s of CPU",
                                          limit.max.count(), limit.mode, limit.cpu.count());
  const auto refuse = [&](std::string_view what, nanoseconds asked) {
    throw UsageError(fmt::format(
        "{} of {} s of simulated time is more than the simulated board runs in reasonable time "
        "({}); split it, or use a shorter interval",
        what, std::chrono::duration<double>(asked).count(), at_most));
  };
  if (const auto* wait = std::get_if<WaitCommand>(&command); wait != nullptr) {
    if (wait->duration > limit.max)
      refuse("wait", wait->duration);
  } else if (const auto* watch = std::get_if<WatchCommand>(&command); watch != nullptr) {
    if (watch->interval > limit.max)
      refuse("a watch interval", watch->interval);
    // interval × (count − 1), without overflow.
    if (watch->count > 1 &&
        static_cast<std::uint64_t>(watch->interval.count()) >
            static_cast<std::uint64_t>(nanoseconds{limit.max}.count()) / (watch->count - 1))
      throw UsageError(fmt::format(
          "a watch of {} samples {} s apart is more simulated time than the simulated board "
          "runs in reasonable time ({}); use fewer samples or a shorter interval",
          watch->count, std::chrono::duration<double>(watch->interval).count(), at_most));
  }
}

bool needs_target(const Command& command) {
  return !std::holds_alternative<ListCommand>(command) &&
         !std::holds_alternative<LocateCommand>(command) &&
         !std::holds_alternative<ExportHlsCommand>(command) &&
         !std::holds_alternative<SweepRunCommand>(command) &&
         !std::holds_alternative<SweepMergeCommand>(command) &&
         !std::holds_alternative<PlotCommand>(command) &&
         !std::holds_alternative<WatchPoseCommand>(command) &&
         !std::holds_alternative<SimCommand>(command);
}

void execute(const Command& command, Target* target, std::ostream& out, bool json,
             const std::atomic<bool>* stop) {
  std::visit(
      Overloaded{
          [&](const ListCommand& c) { run_list(c, out, json); },
          [&](const ReadCommand& c) { run_read(c, need(target), out, json); },
          [&](const WriteCommand& c) { run_write(c, need(target), out, json); },
          [&](const DumpCommand& c) { run_dump(c, need(target), out, json); },
          [&](const WatchCommand& c) { run_watch(c, need(target), out, json, stop); },
          [&](const WaitCommand& c) { run_wait(c, need(target), out, json, stop); },
          [&](const ScriptCommand&) { throw UsageError("a script cannot run another script"); },
          [&](const LocateCommand& c) { run_locate(c, out, json, stop); },
          [&](const ExportHlsCommand& c) { run_export_hls(c, out, json, stop); },
          [&](const SweepRunCommand& c) { run_sweep_run(c, out, json, stop); },
          [&](const SweepMergeCommand& c) { run_sweep_merge(c, out, json, stop); },
          [&](const PlotCommand& c) { run_plot(c, out, json, stop); },
          [&](const WatchPoseCommand& c) { run_watch_pose(c, out, json, stop); },
          [&](const SimCommand& c) { run_sim(c, out, json, stop); },
      },
      command);
}

}  // namespace odoloc::cli
