// The command line of `odoloc`: every subcommand registers its own options
// on CLI11 (one function per command, below) together with what turns them
// into a Command once CLI11 parsed that subcommand; parse_invocation adds the
// global options, parses, and asks the parsed subcommand for its Command.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <functional>
#include <memory>
#include <optional>
#include <ranges>
#include <sstream>
#include <utility>

#include "odoloc/cli/commands.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/cli/format.hpp"
#include "odoloc/cli/locate_input.hpp"
#include "odoloc/cli/values.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/yaml/reader.hpp"

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

// The names of a CLI11 app's subcommands, in registration order.
std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}
// "a, b or c".
std::string alternatives(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

// A mistyped command word gets a better message than CLI11's: the first
// words that are not options must name a command and, in a group (reg,
// sweep, watch), one of its commands; both lists are the app's own. With
// `for_help`, only words that are there are checked (`odoloc --help` and
// `odoloc reg --help` are fine, `odoloc frobnicate --help` is not).
void check_command_words(const CLI::App& app, std::span<const std::string> args,
                         bool for_help = false) {
  // The global options that take a value: skip it too.
  std::vector<std::string> valued;
  for (const CLI::Option* o : app.get_options()) {
    if (o->get_items_expected_max() == 0)
      continue;
    for (const std::string& n : o->get_lnames())
      valued.push_back("--" + n);
    for (const std::string& n : o->get_snames())
      valued.push_back("-" + n);
  }
  std::vector<std::string> words;
  const CLI::App* group = nullptr;
  for (std::size_t i = 0; i < args.size() && words.size() < 2; ++i) {
    const std::string& a = args[i];
    if (std::ranges::find(valued, a) != valued.end()) {
      ++i;  // its value
      continue;
    }
    if (a.starts_with("-"))
      continue;
    words.push_back(a);
    if (words.size() == 2)
      break;
    const std::vector<std::string> top = subcommand_names(app);
    if (std::ranges::find(top, a) == top.end())
      break;
    group = app.get_subcommand(a);
    if (subcommand_names(*group).empty())
      break;
  }
  const std::vector<std::string> commands = subcommand_names(app);
  const std::vector<std::string> reg_commands = subcommand_names(*app.get_subcommand("reg"));
  const auto check = [&](const std::string& word, const std::vector<std::string>& known,
                         std::string_view what) {
    if (std::ranges::find(known, word) != known.end())
      return;
    // `odoloc read top.id`: a reg command without "reg".
    if (&known == &commands && std::ranges::find(reg_commands, word) != reg_commands.end())
      throw UsageError(fmt::format("unknown command '{}'; did you mean reg {}?", word, word));
    const auto best = std::ranges::min_element(
        known, {}, [&](const std::string& k) { return edit_distance(word, k); });
    const std::string hint =
        edit_distance(word, *best) <= 2 ? fmt::format("; did you mean {}?", *best) : std::string{};
    throw UsageError(
        fmt::format("unknown {} '{}'{} (expected {})", what, word, hint, alternatives(known)));
  };
  if (words.empty() && for_help)
    return;
  if (words.empty())
    throw UsageError(fmt::format("no command given; expected {} (odoloc --help for usage)",
                                 alternatives(commands)));
  check(words[0], commands, "command");
  const std::vector<std::string> group_commands =
      group != nullptr ? subcommand_names(*group) : std::vector<std::string>{};
  if (!group_commands.empty() && words.size() == 1 && !for_help)
    throw UsageError(fmt::format("{} needs a command: {}{}", words[0], alternatives(group_commands),
                                 words[0] == "watch" ? " (registers: reg watch)" : ""));
  // `odoloc watch top.id`: a register watch without "reg".
  const auto names_a_register = [](const std::string& word) {
    try {
      (void)resolve(word);
      return true;
    } catch (const UsageError&) {
      return false;
    }
  };
  if (words[0] == "watch" && words.size() == 2 &&
      std::ranges::find(group_commands, words[1]) == group_commands.end() &&
      names_a_register(words[1]))
    throw UsageError(
        fmt::format("unknown watch command '{}'; did you mean reg watch {}?", words[1], words[1]));
  if (words.size() == 2 && !group_commands.empty())
    check(words[1], group_commands, fmt::format("{} command", words[0]));
}

// The global options a subcommand's Command may take over or refuse.
struct Globals {
  Invocation& inv;
  const CLI::Option* target;
  // The file-only commands open no target: board options given with them
  // are a mistake, not a no-op.
  void refuse_board_options(std::string_view command, std::string_view does) const {
    for (const auto& [given, option] :
         {std::pair{target->count() > 0, "--target"}, std::pair{inv.crc, "--crc"},
          std::pair{!inv.vcd.empty(), "--vcd"}, std::pair{!inv.vcd_pins.empty(), "--vcd-pins"},
          std::pair{inv.cycle_step, "--cycle-step"}})
      if (given)
        throw UsageError(fmt::format("{} does not apply to {}: it {} and opens no target", option,
                                     command, does));
  }
};

// A registered subcommand: its CLI11 app and, once CLI11 parsed it, its
// Command (UsageError for a value CLI11 cannot judge).
struct Registered {
  CLI::App* app;
  std::function<Command(Globals&)> command;
};

// Adds subcommand `name` to `parent` with the options `add` registers into an
// Options, and `finish` to turn those into the Command.
template <class Options, class Add, class Finish>
Registered subcommand(CLI::App& parent, const std::string& name, const std::string& description,
                      Add&& add, Finish&& finish) {
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(name, description);
  add(*app, *options);
  app->fallthrough();
  return {app, [options, finish = std::forward<Finish>(finish)](Globals& globals) -> Command {
            return finish(*options, globals);
          }};
}

// A group of subcommands (reg, sweep, watch): one of them is required.
CLI::App* group(CLI::App& app, const std::string& name, const std::string& description) {
  CLI::App* g = app.add_subcommand(name, description);
  g->require_subcommand(1);
  g->fallthrough();
  return g;
}

double real_option(const std::string& text, std::string_view option) {
  const std::optional<double> value = yaml::finite_number(text);
  if (!value)
    throw UsageError(fmt::format("{}: '{}' is not a number", option, text));
  return *value;
}

// A count option's value; its errors name the option ("--laps: bad count '0': ...").
std::uint64_t count_option(const std::string& text, std::string_view option) {
  try {
    return parse_count(text);
  } catch (const UsageError& e) {
    throw UsageError(fmt::format("{}: {}", option, e.what()));
  }
}

// ---- reg list, read, write, dump, watch ----------------------------------------------
struct FilterOptions {
  std::string filter;
};
struct NamesOptions {
  std::vector<std::string> names;
};
struct WatchOptions {
  std::vector<std::string> names;
  std::string interval = "100ms", count;
};

void add_reg(CLI::App& app, std::vector<Registered>& out) {
  CLI::App& reg = *group(app, "reg", "list, read, write, dump and watch registers");
  out.push_back(subcommand<FilterOptions>(
      reg, "list", "every register (path, address, access, reset)",
      [](CLI::App& c, FilterOptions& o) {
        c.add_option("--filter", o.filter,
                     "substring, or glob (* ? [..]), of register/field paths");
      },
      [](const FilterOptions& o, Globals&) -> Command { return ListCommand{o.filter}; }));
  out.push_back(subcommand<NamesOptions>(
      reg, "read", "read registers or fields, decoded",
      [](CLI::App& c, NamesOptions& o) {
        c.add_option("NAME", o.names, "register path, field path or word address (0x12, 18)")
            ->required();
      },
      [](const NamesOptions& o, Globals&) -> Command {
        return ReadCommand{resolve_all(o.names)};
      }));
  out.push_back(subcommand<NamesOptions>(
      reg, "write", "write registers or fields",
      [](CLI::App& c, NamesOptions& o) {
        c.add_option("ASSIGNMENT", o.names,
                     "NAME=VALUE or NAME.FIELD=VALUE: decimal, 0x hex, 0b binary, negative for "
                     "signed fields, enumerator names")
            ->required();
      },
      [](const NamesOptions& o, Globals&) -> Command {
        WriteCommand w;
        for (const std::string& a : o.names)
          w.items.push_back(parse_assignment(a));
        return w;
      }));
  out.push_back(subcommand<FilterOptions>(
      reg, "dump", "read every mapped register in contiguous bursts (clears rc registers)",
      [](CLI::App& c, FilterOptions& o) {
        c.add_option("--filter", o.filter,
                     "only the registers reg list --filter would list: substring or glob");
      },
      [](const FilterOptions& o, Globals&) -> Command { return DumpCommand{o.filter}; }));
  out.push_back(subcommand<WatchOptions>(
      reg, "watch", "sample registers or fields, one line per sample",
      [](CLI::App& c, WatchOptions& o) {
        c.add_option("NAME", o.names, "register path, field path or word address")->required();
        c.add_option("--interval", o.interval,
                     "time between samples: 100ms (default), 1s, 250us; simulated time on sim");
        c.add_option("--count", o.count, "number of samples (default: until Ctrl-C)");
      },
      [](const WatchOptions& o, Globals&) -> Command {
        WatchCommand w{resolve_all(o.names), parse_interval(o.interval), 0};
        if (!o.count.empty())
          w.count = count_option(o.count, "--count");
        return w;
      }));
}

// ---- script, wait -----------------------------------------------------------------------
struct TextOptions {
  std::string text;
};

void add_script_and_wait(CLI::App& app, std::vector<Registered>& out) {
  out.push_back(subcommand<TextOptions>(
      app, "script", "run commands from FILE (or - for stdin), one per line, on one target",
      [](CLI::App& c, TextOptions& o) {
        c.add_option("FILE", o.text, "script file, or - for standard input")->required();
      },
      [](const TextOptions& o, Globals&) -> Command { return ScriptCommand{o.text}; }));
  out.push_back(subcommand<TextOptions>(
      app, "wait", "let time pass (simulated on sim): 100ms, 1s",
      [](CLI::App& c, TextOptions& o) { c.add_option("DURATION", o.text, "how long")->required(); },
      [](const TextOptions& o, Globals&) -> Command {
        return WaitCommand{parse_interval(o.text)};
      }));
}

// ---- locate -------------------------------------------------------------------------------
struct LocateOptions {
  LocateCommand command;
  std::string solver = "gauss-newton", temperature, triple;
};

Registered add_locate(CLI::App& app) {
  return subcommand<LocateOptions>(
      app, "locate",
      "beacon fixes from a beacon layout and recorded arrivals (files only, no target)",
      [](CLI::App& c, LocateOptions& o) {
        c.add_option("--layout", o.command.layout, "the beacons: YAML (id, x, y, height)")
            ->type_name("FILE")
            ->required();
        c.add_option("--arrivals", o.command.arrivals,
                     "CSV with a header: cycle,beacon,distance_m[,sd_m][,candidate] or "
                     "cycle,beacon,time_s[,sd_s][,candidate]")
            ->type_name("FILE")
            ->required();
        c.add_option("--solver", o.solver, "gauss-newton (default), longsolve or kleeman")
            ->type_name("NAME");
        c.add_option("--triple", o.triple,
                     "kleeman: the three beacons, ID,ID,ID (default: per cycle the usable triple "
                     "with the least predicted error)")
            ->type_name("ID,ID,ID");
        c.add_option("--temperature", o.temperature,
                     "air temperature, degrees Celsius: the solvers assume c = 331.3 sqrt(1 + "
                     "T/273.15) (overrides the layout's)")
            ->type_name("C");
        c.add_flag("--calibrate-c", o.command.calibrate_c,
                   "gauss-newton: estimate the speed of sound too (5 or more beacons used)");
        c.add_option("--plot", o.command.plot,
                     "draw beacons, fixes and 2-sigma error ellipses with gnuplot: OUT.png or "
                     "OUT.svg")
            ->type_name("OUT");
      },
      [](const LocateOptions& o, Globals& globals) -> Command {
        globals.refuse_board_options("locate", "reads files");
        LocateCommand command = o.command;
        command.solver = parse_solver(o.solver);
        if (!o.temperature.empty())
          command.temperature_c = parse_temperature(o.temperature);
        if (!o.triple.empty())
          command.triple = parse_triple(o.triple);
        check_locate(command);
        return command;
      });
}

// ---- export-hls ---------------------------------------------------------------------------
struct ExportHlsOptions {
  std::string out, tool = "vitis";
  std::vector<std::string> kernels;
  bool force = false;
};

Registered add_export_hls(CLI::App& app) {
  return subcommand<ExportHlsOptions>(
      app, "export-hls",
      "write the HLS kernels as standalone Vitis HLS, Catapult or Intel HLS trees (files only, "
      "no target)",
      [](CLI::App& c, ExportHlsOptions& o) {
        c.add_option("--out", o.out,
                     "the folder to write, one subfolder per kernel; it must be absent or empty "
                     "unless --force")
            ->type_name("DIR")
            ->required();
        c.add_option(
             "--kernel", o.kernels,
             fmt::format("a kernel to export (repeatable; default: all): {}",
                         fmt::join(hls_export::kernels() |
                                       std::views::transform(&hls_export::KernelDescription::name),
                                   ", ")))
            ->type_name("NAME");
        c.add_option("--tool", o.tool, "vitis (default), catapult or intel")->type_name("TOOL");
        c.add_flag("--force", o.force,
                   "OUT may hold files: replace the exported kernels' folders in it");
      },
      [](const ExportHlsOptions& o, Globals& globals) -> Command {
        globals.refuse_board_options("export-hls", "writes files");
        ExportHlsCommand command;
        command.request.out = o.out;
        command.request.kernels = o.kernels;
        command.request.tool = parse_hls_tool(o.tool);
        command.request.force = o.force;
        return command;
      });
}

// ---- sweep run, merge ----------------------------------------------------------------------
struct SweepRunOptions {
  SweepRunCommand command;
  std::string shard = "1/1";
};

void add_sweep(CLI::App& app, std::vector<Registered>& out) {
  CLI::App& sweep = *group(app, "sweep",
                           "Monte Carlo and parameter sweeps: run a shard of a YAML spec, merge "
                           "the shards' files (docs/sweep.md; no target)");
  out.push_back(subcommand<SweepRunOptions>(
      sweep, "run", "run shard K of N of a sweep and write its result file (JSON Lines)",
      [](CLI::App& c, SweepRunOptions& o) {
        c.add_option("SPEC", o.command.spec, "the sweep: YAML (docs/sweep.md)")->required();
        c.add_option("--shard", o.shard,
                     "run the jobs j with j % N == K - 1 (default 1/1: every job)")
            ->type_name("K/N");
        c.add_option("--out", o.command.out, "the result file to write")
            ->type_name("FILE")
            ->required();
      },
      [](const SweepRunOptions& o, Globals& globals) -> Command {
        globals.refuse_board_options("sweep run", "simulates in process");
        SweepRunCommand command = o.command;
        command.shard = parse_shard_option(o.shard);
        return command;
      }));
  out.push_back(subcommand<SweepMergeCommand>(
      sweep, "merge", "check the shard files of one run and write its table, summary and plots",
      [](CLI::App& c, SweepMergeCommand& o) {
        c.add_option("FILE", o.files, "every shard file of the run")->required();
        c.add_option("--out", o.out,
                     "the folder for jobs.csv, points.csv, summary.md, plots.gp and the PNGs "
                     "(created; its parent must exist)")
            ->type_name("DIR")
            ->required();
        c.add_flag("--no-plot{false}", o.plot, "write plots.gp but do not run gnuplot");
      },
      [](const SweepMergeCommand& o, Globals& globals) -> Command {
        globals.refuse_board_options("sweep merge", "reads and writes files");
        return o;
      }));
}

// ---- plot ------------------------------------------------------------------------------------
struct PlotOptions {
  PlotCommand command;
  std::string ellipse_every;
};

Registered add_plot(CLI::App& app) {
  return subcommand<PlotOptions>(
      app, "plot",
      "trajectories and errors of an LCM event log (truth, pose sources, fixes) as a PNG drawn "
      "with gnuplot, and a summary per source (no target)",
      [](CLI::App& c, PlotOptions& o) {
        c.add_option("LOG", o.command.log, "the LCM event log (odoloc sim, lcm-logger)")
            ->required();
        c.add_option("--out", o.command.out, "the PNG to write (default: LOG with extension .png)")
            ->type_name("FILE.png");
        c.add_option("--ellipse-every", o.ellipse_every,
                     "seconds between the fused estimate's drawn 95 % error ellipses (default 1)")
            ->type_name("SECONDS");
        c.add_flag("--keep-script", o.command.keep_script,
                   "keep the gnuplot script (its data inline) next to the PNG, as FILE.gp");
      },
      [](const PlotOptions& o, Globals& globals) -> Command {
        globals.refuse_board_options("plot", "reads a log file");
        PlotCommand command = o.command;
        if (!o.ellipse_every.empty())
          command.ellipse_every_s = parse_ellipse_every(o.ellipse_every);
        return command;
      });
}

// ---- sim ---------------------------------------------------------------------------------------
struct SimOptions {
  SimCommand command;
  std::string laps, speed, seed, duration;
};

Registered add_sim(CLI::App& app) {
  return subcommand<SimOptions>(
      app, "sim",
      "the whole localisation system (world, chip at the pin level, SoC software over the "
      "register bus) in a scenario (default: the room tour): LCM, CSV, plot and the table of "
      "errors (no target; docs/simulator.md)",
      [](CLI::App& c, SimOptions& o) {
        c.add_option("--scenario", o.command.scenario,
                     "a scenario file (docs/scenarios.md) or a built-in one's name (default "
                     "room-tour.yaml)")
            ->type_name("FILE");
        c.add_option("--laps", o.laps, "the path's laps (the scenario's; the room tour: 2)")
            ->type_name("N");
        c.add_option("--speed", o.speed, "a square path's speed, m/s (the room tour: 0.5)")
            ->type_name("M/S");
        c.add_option("--seed", o.seed, "the acoustic world's random draws (the scenario's)")
            ->type_name("N");
        c.add_option("--duration", o.duration,
                     "stop after this much simulated time (default: the whole tour)")
            ->type_name("SECONDS");
        c.add_option("--out", o.command.out,
                     "write DIR/odoloc.lcmlog, trajectories.csv, fixes.csv and localisation.png")
            ->type_name("DIR");
        c.add_option(
             "--lcm-url", o.command.lcm_url,
             fmt::format("publish live here (default {} when there is no --out)", lcm::kDefaultUrl))
            ->type_name("URL");
        c.add_flag("--realtime", o.command.realtime,
                   "pace to the wall clock (default: as fast as the machine can)");
        c.add_flag("--allow-write", o.command.allow_write,
                   "let the register bridge write registers (LCM has no authentication)");
        c.add_flag("--no-plot", o.command.no_plot, "with --out: no localisation.png");
        c.add_flag("--no-beacon-ranges", o.command.no_beacon_ranges,
                   "Kleeman's beacons only initialise the filter; Liu's base station alone "
                   "corrects it after");
      },
      [](const SimOptions& o, Globals& globals) -> Command {
        SimCommand command = o.command;
        // --cycle-step applies: the simulator's chip is a simulated board.
        command.cycle_step = std::exchange(globals.inv.cycle_step, false);
        globals.refuse_board_options("sim", "simulates its own board");
        if (!o.laps.empty())
          command.laps = count_option(o.laps, "--laps");
        if (!o.seed.empty())
          command.seed = count_option(o.seed, "--seed");
        if (!o.speed.empty())
          command.speed_mps = real_option(o.speed, "--speed");
        if (!o.duration.empty())
          command.duration_s = real_option(o.duration, "--duration");
        return command;
      });
}

// ---- watch pose --------------------------------------------------------------------------------
struct WatchPoseOptions {
  WatchPoseCommand command;
  std::string count;
};

Registered add_watch_pose(CLI::App& app) {
  CLI::App& watch =
      *group(app, "watch", "print what a simulator publishes on LCM as it comes (no target)");
  return subcommand<WatchPoseOptions>(
      watch, "pose",
      "pose estimates from ODOLOC_POSE_<SOURCE> (truth: ODOLOC_TRUTH), one line each: time, "
      "source, x, y, heading, standard deviations",
      [](CLI::App& c, WatchPoseOptions& o) {
        c.add_option("--source", o.command.source,
                     "fused (default), odometry, rear, front, liu, truth or all")
            ->type_name("SOURCE");
        c.add_option("--count", o.count, "estimates to print (default: until Ctrl-C)")
            ->type_name("N");
        c.add_option("--lcm-url", o.command.url,
                     fmt::format("where to listen (default {})", lcm::kDefaultUrl))
            ->type_name("URL");
      },
      [](const WatchPoseOptions& o, Globals& globals) -> Command {
        globals.refuse_board_options("watch pose", "listens on LCM (--lcm-url)");
        WatchPoseCommand command = o.command;
        command.source = parse_pose_source(o.command.source);
        if (!o.count.empty())
          command.count = count_option(o.count, "--count");
        return command;
      });
}

// The help text of a --help or --all-help request.
std::string help_text(const CLI::App& app, const CLI::Error& e) {
  std::ostringstream help;
  (void)app.exit(e, help, help);
  return help.str();
}

}  // namespace

Invocation parse_invocation(std::span<const std::string> args) {
  Invocation inv;
  CLI::App app{
      "Register access to the odoloc FPGA fabric over SPI (simulated or real), beacon fixes "
      "from recorded arrivals, and Monte Carlo and parameter sweeps.",
      "odoloc"};
  app.footer(std::string{kFooter});
  app.fallthrough();
  app.require_subcommand(1);
  const CLI::Option* target =
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

  std::vector<Registered> commands;
  add_reg(app, commands);
  add_script_and_wait(app, commands);
  commands.push_back(add_locate(app));
  commands.push_back(add_export_hls(app));
  add_sweep(app, commands);
  commands.push_back(add_plot(app));
  commands.push_back(add_sim(app));
  commands.push_back(add_watch_pose(app));

  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForVersion&) {
    inv.help = version_text() + "\n";
    return inv;
  } catch (const CLI::CallForHelp& e) {
    check_command_words(app, args, true);
    inv.help = help_text(app, e);
    return inv;
  } catch (const CLI::CallForAllHelp& e) {
    check_command_words(app, args, true);
    inv.help = help_text(app, e);
    return inv;
  } catch (const CLI::ParseError& e) {
    check_command_words(app, args);
    throw UsageError(fmt::format("{} (odoloc --help for usage)", one_line(e.what())));
  }
  inv.target_given = target->count() > 0;
  Globals globals{inv, target};
  for (const Registered& r : commands) {
    if (r.app->parsed()) {
      inv.command = r.command(globals);
      return inv;
    }
  }
  throw UsageError("no command given (odoloc --help for usage)");
}

}  // namespace odoloc::cli
