#include "odoloc/cli/commands.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <ranges>
#include <sstream>
#include <utility>

#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/cli/locate_input.hpp"
#include "odoloc/cli/values.hpp"
#include "odoloc/hls_export/reference.hpp"

namespace odoloc::cli {
namespace {

constexpr std::string_view kFooter =
    "Global options, before or after the command: -t/--target SPEC, --json, --crc, --vcd FILE,\n"
    "--vcd-pins FILE.\n"
    "Targets: sim (default), sim:SCENARIO, spidev:/dev/spidevB.C[@HZ], lcm[:URL].\n"
    "Addresses are word addresses (w:0x10); b:0x40 is a byte address as in odoloc.rdl.\n"
    "Exit codes: 0 done, 1 bus, link or file error, 2 bad command, name, value, address or\n"
    "target, 130 Ctrl-C.\n"
    "Every run of `--target sim` starts a fresh simulated chip; `odoloc script` runs many\n"
    "commands on one. Reading an rc register (reg read, dump, watch) clears it.\n"
    "`odoloc locate` and `odoloc plot` read files only, `odoloc export-hls` writes files only\n"
    "and `odoloc sweep` runs its own simulations: none opens a target. `odoloc watch pose`\n"
    "listens to a simulator on LCM (--lcm-url) and opens none either.\n"
    "Manual: docs/host-tool.md.";

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;  // clang 14 has no aggregate CTAD

std::string one_line(std::string text) {
  std::ranges::replace(text, '\n', ' ');
  while (!text.empty() && text.back() == ' ')
    text.pop_back();
  return text;
}

std::vector<Location> resolve_all(const std::vector<std::string>& names) {
  std::vector<Location> out;
  out.reserve(names.size());
  for (const std::string& n : names)
    out.push_back(resolve(n));
  return out;
}

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

// A mistyped command word gets a better message than CLI11's: the first
// words that are not options must name a command and a reg subcommand.
// With `for_help`, only words that are there are checked (`odoloc --help`
// and `odoloc reg --help` are fine, `odoloc frobnicate --help` is not).
void check_command_words(std::span<const std::string> args, bool for_help = false) {
  static const std::vector<std::string> kCommands{"reg",    "script",     "wait",  "watch", "sim",
                                                  "locate", "export-hls", "sweep", "plot"};
  static const std::vector<std::string> kRegCommands{"list", "read", "write", "dump", "watch"};
  static const std::vector<std::string> kSweepCommands{"run", "merge"};
  static const std::vector<std::string> kWatchCommands{"pose"};
  std::vector<std::string> words;
  for (std::size_t i = 0; i < args.size() && words.size() < 2; ++i) {
    const std::string& a = args[i];
    if (a == "-t" || a == "--target" || a == "--vcd" || a == "--vcd-pins") {
      ++i;  // its value
      continue;
    }
    if (a.starts_with("-"))
      continue;
    words.push_back(a);
    if (a != "reg" && a != "sweep" && a != "watch")
      break;
  }
  const auto check = [](const std::string& word, const std::vector<std::string>& known,
                        std::string_view what) {
    if (std::ranges::find(known, word) != known.end())
      return;
    // `odoloc read top.id`: a reg command without "reg".
    if (&known == &kCommands && std::ranges::find(kRegCommands, word) != kRegCommands.end())
      throw UsageError(fmt::format("unknown command '{}'; did you mean reg {}?", word, word));
    std::string expected;
    for (std::size_t i = 0; i < known.size(); ++i)
      expected += (i == 0 ? "" : i + 1 == known.size() ? " or " : ", ") + known[i];
    const auto best = std::ranges::min_element(
        known, {}, [&](const std::string& k) { return edit_distance(word, k); });
    const std::string hint =
        edit_distance(word, *best) <= 2 ? fmt::format("; did you mean {}?", *best) : std::string{};
    throw UsageError(fmt::format("unknown {} '{}'{} (expected {})", what, word, hint, expected));
  };
  if (words.empty() && for_help)
    return;
  if (words.empty())
    throw UsageError(
        "no command given; expected reg, script, wait, watch, sim, locate, export-hls, sweep or "
        "plot (odoloc --help for usage)");
  check(words[0], kCommands, "command");
  if (words[0] == "reg" && words.size() == 1 && !for_help)
    throw UsageError("reg needs a command: list, read, write, dump or watch");
  if (words[0] == "sweep" && words.size() == 1 && !for_help)
    throw UsageError("sweep needs a command: run or merge");
  if (words[0] == "watch" && words.size() == 1 && !for_help)
    throw UsageError("watch needs a command: pose (registers: reg watch)");
  // `odoloc watch top.id`: a register watch without "reg".
  const auto names_a_register = [](const std::string& word) {
    try {
      (void)resolve(word);
      return true;
    } catch (const UsageError&) {
      return false;
    }
  };
  if (words[0] == "watch" && words.size() == 2 && words[1] != "pose" && names_a_register(words[1]))
    throw UsageError(
        fmt::format("unknown watch command '{}'; did you mean reg watch {}?", words[1], words[1]));
  if (words.size() == 2)
    check(words[1],
          words[0] == "reg"     ? kRegCommands
          : words[0] == "sweep" ? kSweepCommands
                                : kWatchCommands,
          fmt::format("{} command", words[0]));
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

Invocation parse_invocation(std::span<const std::string> args) {
  Invocation inv;
  struct {
    std::string filter, dump_filter, interval = "100ms", count, duration, file;
    std::vector<std::string> names, assignments;
    std::string solver = "gauss-newton", temperature, triple;
    std::string hls_out, hls_tool = "vitis";
    std::vector<std::string> hls_kernels;
    bool hls_force = false;
    std::string sweep_shard = "1/1";
  } raw;
  LocateCommand locate_command;
  SweepRunCommand sweep_run_command;
  SweepMergeCommand sweep_merge_command;
  PlotCommand plot_command;
  SimCommand sim_command;
  std::string sim_laps, sim_speed, sim_seed, sim_duration;
  std::string plot_ellipse_every;
  WatchPoseCommand watch_pose_command;
  std::string watch_pose_count;

  CLI::App app{
      "Register access to the odoloc FPGA fabric over SPI (simulated or real), beacon fixes "
      "from recorded arrivals, and Monte Carlo and parameter sweeps.",
      "odoloc"};
  app.footer(std::string{kFooter});
  app.fallthrough();
  app.require_subcommand(1);
  auto* target_opt =
      app.add_option("-t,--target", inv.target,
                     "sim (default), sim:SCENARIO, spidev:/dev/spidevB.C[@HZ] or lcm[:URL]");
  app.add_flag("--json", inv.json, "machine-readable output: one JSON document per line");
  app.add_flag("--crc", inv.crc, "switch the fabric's SPI CRC-8 on (top.ctrl.crc_enable) first");
  app.add_option("--vcd", inv.vcd,
                 "sim target: write the chip's waveform of every SPI frame to this VCD file");
  app.add_option("--vcd-pins", inv.vcd_pins,
                 "sim target: write only the four SPI pins of every frame to this VCD file "
                 "(for sigrok-cli and other logic-analyser software)");
  app.add_flag("--cycle-step", inv.cycle_step,
               "sim target: step the chip every clock instead of fast-forwarding between "
               "events (same results, slower; for comparison)");
  app.set_version_flag("--version", version_text());

  CLI::App* reg = app.add_subcommand("reg", "list, read, write, dump and watch registers");
  reg->require_subcommand(1);
  reg->fallthrough();
  CLI::App* list = reg->add_subcommand("list", "every register (path, address, access, reset)");
  list->add_option("--filter", raw.filter,
                   "substring, or glob (* ? [..]), of register/field paths");
  CLI::App* read = reg->add_subcommand("read", "read registers or fields, decoded");
  read->add_option("NAME", raw.names, "register path, field path or word address (0x12, 18)")
      ->required();
  CLI::App* write = reg->add_subcommand("write", "write registers or fields");
  write
      ->add_option("ASSIGNMENT", raw.assignments,
                   "NAME=VALUE or NAME.FIELD=VALUE: decimal, 0x hex, 0b binary, negative for "
                   "signed fields, enumerator names")
      ->required();
  CLI::App* dump = reg->add_subcommand(
      "dump", "read every mapped register in contiguous bursts (clears rc registers)");
  dump->add_option("--filter", raw.dump_filter,
                   "only the registers reg list --filter would list: substring or glob");
  CLI::App* watch = reg->add_subcommand("watch", "sample registers or fields, one line per sample");
  watch->add_option("NAME", raw.names, "register path, field path or word address")->required();
  watch->add_option("--interval", raw.interval,
                    "time between samples: 100ms (default), 1s, 250us; simulated time on sim");
  watch->add_option("--count", raw.count, "number of samples (default: until Ctrl-C)");
  for (CLI::App* sub : {list, read, write, dump, watch})
    sub->fallthrough();
  CLI::App* script = app.add_subcommand(
      "script", "run commands from FILE (or - for stdin), one per line, on one target");
  script->add_option("FILE", raw.file, "script file, or - for standard input")->required();
  script->fallthrough();
  CLI::App* wait = app.add_subcommand("wait", "let time pass (simulated on sim): 100ms, 1s");
  wait->add_option("DURATION", raw.duration, "how long")->required();
  wait->fallthrough();
  CLI::App* locate = app.add_subcommand(
      "locate", "beacon fixes from a beacon layout and recorded arrivals (files only, no target)");
  locate->add_option("--layout", locate_command.layout, "the beacons: YAML (id, x, y, height)")
      ->type_name("FILE")
      ->required();
  locate
      ->add_option("--arrivals", locate_command.arrivals,
                   "CSV with a header: cycle,beacon,distance_m[,sd_m][,candidate] or "
                   "cycle,beacon,time_s[,sd_s][,candidate]")
      ->type_name("FILE")
      ->required();
  locate->add_option("--solver", raw.solver, "gauss-newton (default), longsolve or kleeman")
      ->type_name("NAME");
  locate
      ->add_option("--triple", raw.triple,
                   "kleeman: the three beacons, ID,ID,ID (default: per cycle the usable triple "
                   "with the least predicted error)")
      ->type_name("ID,ID,ID");
  locate
      ->add_option("--temperature", raw.temperature,
                   "air temperature, degrees Celsius: the solvers assume c = 331.3 sqrt(1 + "
                   "T/273.15) (overrides the layout's)")
      ->type_name("C");
  locate->add_flag("--calibrate-c", locate_command.calibrate_c,
                   "gauss-newton: estimate the speed of sound too (5 or more beacons used)");
  locate
      ->add_option("--plot", locate_command.plot,
                   "draw beacons, fixes and 2-sigma error ellipses with gnuplot: OUT.png or "
                   "OUT.svg")
      ->type_name("OUT");
  locate->fallthrough();
  CLI::App* export_hls = app.add_subcommand(
      "export-hls",
      "write the HLS kernels as standalone Vitis HLS, Catapult or Intel HLS trees (files only, "
      "no target)");
  export_hls
      ->add_option("--out", raw.hls_out,
                   "the folder to write, one subfolder per kernel; it must be absent or empty "
                   "unless --force")
      ->type_name("DIR")
      ->required();
  export_hls
      ->add_option(
          "--kernel", raw.hls_kernels,
          fmt::format("a kernel to export (repeatable; default: all): {}",
                      fmt::join(hls_export::kernels() |
                                    std::views::transform(&hls_export::KernelDescription::name),
                                ", ")))
      ->type_name("NAME");
  export_hls->add_option("--tool", raw.hls_tool, "vitis (default), catapult or intel")
      ->type_name("TOOL");
  export_hls->add_flag("--force", raw.hls_force,
                       "OUT may hold files: replace the exported kernels' folders in it");
  export_hls->fallthrough();

  CLI::App* sweep = app.add_subcommand(
      "sweep",
      "Monte Carlo and parameter sweeps: run a shard of a YAML spec, merge the shards' files "
      "(docs/sweep.md; no target)");
  sweep->require_subcommand(1);
  sweep->fallthrough();
  CLI::App* sweep_run = sweep->add_subcommand(
      "run", "run shard K of N of a sweep and write its result file (JSON Lines)");
  sweep_run->add_option("SPEC", sweep_run_command.spec, "the sweep: YAML (docs/sweep.md)")
      ->required();
  sweep_run
      ->add_option("--shard", raw.sweep_shard,
                   "run the jobs j with j % N == K - 1 (default 1/1: every job)")
      ->type_name("K/N");
  sweep_run->add_option("--out", sweep_run_command.out, "the result file to write")
      ->type_name("FILE")
      ->required();
  CLI::App* sweep_merge = sweep->add_subcommand(
      "merge", "check the shard files of one run and write its table, summary and plots");
  sweep_merge->add_option("FILE", sweep_merge_command.files, "every shard file of the run")
      ->required();
  sweep_merge
      ->add_option("--out", sweep_merge_command.out,
                   "the folder for jobs.csv, points.csv, summary.md, plots.gp and the PNGs "
                   "(created; its parent must exist)")
      ->type_name("DIR")
      ->required();
  sweep_merge->add_flag("--no-plot{false}", sweep_merge_command.plot,
                        "write plots.gp but do not run gnuplot");
  for (CLI::App* sub : {sweep_run, sweep_merge})
    sub->fallthrough();

  CLI::App* plot = app.add_subcommand(
      "plot",
      "trajectories and errors of an LCM event log (truth, pose sources, fixes) as a PNG drawn "
      "with gnuplot, and a summary per source (no target)");
  plot->add_option("LOG", plot_command.log, "the LCM event log (odoloc sim, lcm-logger)")
      ->required();
  plot->add_option("--out", plot_command.out, "the PNG to write (default: LOG with extension .png)")
      ->type_name("FILE.png");
  plot->add_option("--ellipse-every", plot_ellipse_every,
                   "seconds between the fused estimate's drawn 95 % error ellipses (default 1)")
      ->type_name("SECONDS");
  plot->add_flag("--keep-script", plot_command.keep_script,
                 "keep the gnuplot script (its data inline) next to the PNG, as FILE.gp");
  plot->fallthrough();

  CLI::App* sim = app.add_subcommand(
      "sim",
      "the whole localisation system (world, chip at the pin level, SoC software over the "
      "register bus) on its room tour: LCM, CSV, plot and the table of errors (no target; "
      "docs/simulator.md)");
  sim->add_option("--laps", sim_laps, "laps of the 6 m square (default 2)")->type_name("N");
  sim->add_option("--speed", sim_speed, "m/s (default 0.5)")->type_name("M/S");
  sim->add_option("--seed", sim_seed, "the acoustic world's random draws (default 1)")
      ->type_name("N");
  sim->add_option("--duration", sim_duration,
                  "stop after this much simulated time (default: the whole tour)")
      ->type_name("SECONDS");
  sim->add_option("--out", sim_command.out,
                  "write DIR/odoloc.lcmlog, trajectories.csv, fixes.csv and localisation.png")
      ->type_name("DIR");
  sim->add_option(
         "--lcm-url", sim_command.lcm_url,
         fmt::format("publish live here (default {} when there is no --out)", lcm::kDefaultUrl))
      ->type_name("URL");
  sim->add_flag("--realtime", sim_command.realtime,
                "pace to the wall clock (default: as fast as the machine can)");
  sim->add_flag("--allow-write", sim_command.allow_write,
                "let the register bridge write registers (LCM has no authentication)");
  sim->add_flag("--no-plot", sim_command.no_plot, "with --out: no localisation.png");
  sim->add_flag("--no-beacon-ranges", sim_command.no_beacon_ranges,
                "Kleeman's beacons only initialise the filter; Liu's base station alone "
                "corrects it after");
  sim->fallthrough();

  CLI::App* watch_top = app.add_subcommand(
      "watch", "print what a simulator publishes on LCM as it comes (no target)");
  watch_top->require_subcommand(1);
  watch_top->fallthrough();
  CLI::App* watch_pose =
      watch_top->add_subcommand("pose",
                                "pose estimates from ODOLOC_POSE_<SOURCE> (truth: ODOLOC_TRUTH), "
                                "one line each: time, source, x, "
                                "y, heading, standard deviations");
  watch_pose
      ->add_option("--source", watch_pose_command.source,
                   "fused (default), odometry, rear, front, truth or all")
      ->type_name("SOURCE");
  watch_pose->add_option("--count", watch_pose_count, "estimates to print (default: until Ctrl-C)")
      ->type_name("N");
  watch_pose
      ->add_option("--lcm-url", watch_pose_command.url,
                   fmt::format("where to listen (default {})", lcm::kDefaultUrl))
      ->type_name("URL");
  watch_pose->fallthrough();

  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForVersion& e) {
    inv.help = version_text() + "\n";
    return inv;
  } catch (const CLI::CallForHelp& e) {
    check_command_words(args, true);
    std::ostringstream help;
    (void)app.exit(e, help, help);
    inv.help = help.str();
    return inv;
  } catch (const CLI::CallForAllHelp& e) {
    check_command_words(args, true);
    std::ostringstream help;
    (void)app.exit(e, help, help);
    inv.help = help.str();
    return inv;
  } catch (const CLI::ParseError& e) {
    check_command_words(args);
    throw UsageError(fmt::format("{} (odoloc --help for usage)", one_line(e.what())));
  }
  inv.target_given = target_opt->count() > 0;
  // The file-only commands open no target: board options given with them are
  // a mistake, not a no-op.
  const auto refuse_board_options = [&](std::string_view command, std::string_view does) {
    for (const auto& [given, option] :
         {std::pair{target_opt->count() > 0, "--target"}, std::pair{inv.crc, "--crc"},
          std::pair{!inv.vcd.empty(), "--vcd"}, std::pair{!inv.vcd_pins.empty(), "--vcd-pins"},
          std::pair{inv.cycle_step, "--cycle-step"}})
      if (given)
        throw UsageError(fmt::format("{} does not apply to {}: it {} and opens no target", option,
                                     command, does));
  };

  if (list->parsed()) {
    inv.command = ListCommand{raw.filter};
  } else if (read->parsed()) {
    inv.command = ReadCommand{resolve_all(raw.names)};
  } else if (write->parsed()) {
    WriteCommand w;
    for (const std::string& a : raw.assignments)
      w.items.push_back(parse_assignment(a));
    inv.command = std::move(w);
  } else if (dump->parsed()) {
    inv.command = DumpCommand{raw.dump_filter};
  } else if (watch->parsed()) {
    WatchCommand w{resolve_all(raw.names), parse_interval(raw.interval), 0};
    if (!raw.count.empty())
      w.count = parse_count(raw.count);
    inv.command = std::move(w);
  } else if (script->parsed()) {
    inv.command = ScriptCommand{raw.file};
  } else if (wait->parsed()) {
    inv.command = WaitCommand{parse_interval(raw.duration)};
  } else if (locate->parsed()) {
    refuse_board_options("locate", "reads files");
    locate_command.solver = parse_solver(raw.solver);
    if (!raw.temperature.empty())
      locate_command.temperature_c = parse_temperature(raw.temperature);
    if (!raw.triple.empty())
      locate_command.triple = parse_triple(raw.triple);
    check_locate(locate_command);
    inv.command = std::move(locate_command);
  } else if (export_hls->parsed()) {
    refuse_board_options("export-hls", "writes files");
    ExportHlsCommand command;
    command.request.out = raw.hls_out;
    command.request.kernels = raw.hls_kernels;
    command.request.tool = parse_hls_tool(raw.hls_tool);
    command.request.force = raw.hls_force;
    inv.command = std::move(command);
  } else if (sweep_run->parsed()) {
    refuse_board_options("sweep run", "simulates in process");
    sweep_run_command.shard = parse_shard_option(raw.sweep_shard);
    inv.command = std::move(sweep_run_command);
  } else if (sim->parsed()) {
    // --cycle-step applies: the simulator's chip is a simulated board.
    sim_command.cycle_step = std::exchange(inv.cycle_step, false);
    refuse_board_options("sim", "simulates its own board");
    if (!sim_laps.empty())
      sim_command.laps = parse_count(sim_laps);
    if (!sim_seed.empty())
      sim_command.seed = parse_count(sim_seed);
    const auto real = [](const std::string& text, std::string_view option) {
      const std::optional<double> value = parse_real(text);
      if (!value)
        throw UsageError(fmt::format("{}: '{}' is not a number", option, text));
      return *value;
    };
    if (!sim_speed.empty())
      sim_command.speed_mps = real(sim_speed, "--speed");
    if (!sim_duration.empty())
      sim_command.duration_s = real(sim_duration, "--duration");
    inv.command = std::move(sim_command);
  } else if (plot->parsed()) {
    refuse_board_options("plot", "reads a log file");
    if (!plot_ellipse_every.empty())
      plot_command.ellipse_every_s = parse_ellipse_every(plot_ellipse_every);
    inv.command = std::move(plot_command);
  } else if (sweep_merge->parsed()) {
    refuse_board_options("sweep merge", "reads and writes files");
    inv.command = std::move(sweep_merge_command);
  } else if (watch_pose->parsed()) {
    refuse_board_options("watch pose", "listens on LCM (--lcm-url)");
    watch_pose_command.source = parse_pose_source(watch_pose_command.source);
    if (!watch_pose_count.empty())
      watch_pose_command.count = parse_count(watch_pose_count);
    inv.command = std::move(watch_pose_command);
  } else {
    throw UsageError("no command given (odoloc --help for usage)");
  }
  return inv;
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
