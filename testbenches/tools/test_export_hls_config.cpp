// The Vitis Unified config file (hls_config.cfg) of every exported tree,
// checked without Vitis, which is not available here:
//  - it parses as the INI-like format Vitis reads (UG1702 "Vitis Compiler
//    Configuration File"): `#` comments, `[section]` heads, `key=value`
//    lines, keys before any section global (part=), syn.file and tb.file
//    repeated to list several files. Python's configparser cannot read it:
//    it refuses keys before a section and keeps only the last of repeated
//    keys (strict=False), so the parser is here;
//  - every key is one whose meaning we checked in the Vitis docs, and a key
//    that must not repeat does not (Vitis would take the first silently);
//  - every file it names is a file of the tree, relative to the cfg;
//  - it says what run_hls.tcl says: top, files, cflags, part, clock, flow
//    target, testbench arguments, export format;
//  - syn.top is a function the syn.file sources define (nm on the objects);
//  - what C simulation does: the syn.file sources built with syn.cflags,
//    the tb.file sources with tb.cflags, linked, run in a folder holding the
//    other tb.file files with csim.argv, must pass the golden vectors; once
//    with exactly those flags (the project's own types), once with Xilinx's
//    ap_int.h on the include path as Vitis has it, where ../shared/vendor
//    holds it.
// Each check is also shown to fail on a cfg broken the way it guards against.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "export_hls_support.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/process/run_program.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::hls_export::KernelDescription;
using odoloc::process::run_program;
using odoloc::process::run_shell;
using odoloc::tb::slurp;
using odoloc::tb::export_hls::families;
using odoloc::tb::export_hls::Family;
using odoloc::tb::export_hls::fresh_folder;
using odoloc::tb::export_hls::odoloc_cli;

std::string trimmed(std::string_view text) {
  const auto start = text.find_first_not_of(" \t\r");
  if (start == std::string_view::npos)
    return {};
  const auto end = text.find_last_not_of(" \t\r");
  return std::string(text.substr(start, end + 1 - start));
}

std::vector<std::string> words(std::string_view text) {
  std::istringstream in{std::string(text)};
  std::vector<std::string> list;
  for (std::string word; in >> word;)
    list.push_back(word);
  return list;
}

// ---- the config file --------------------------------------------------

struct Entry {
  std::string section;  // empty: before any section head
  std::string key;
  std::string value;
  int line = 0;
};

struct Config {
  std::vector<Entry> entries;
  std::vector<std::string> errors;  // lines that are none of the forms

  [[nodiscard]] std::vector<std::string> all(std::string_view section, std::string_view key) const {
    std::vector<std::string> values;
    for (const Entry& e : entries)
      if (e.section == section && e.key == key)
        values.push_back(e.value);
    return values;
  }
  // The value of a key that appears once; empty when it does not.
  [[nodiscard]] std::string one(std::string_view key) const {
    const std::vector<std::string> values = all(key == "part" ? "" : "hls", key);
    return values.size() == 1 ? values.front() : std::string();
  }
};

Config parse_config(std::string_view text) {
  Config config;
  std::string section;
  std::istringstream lines{std::string(text)};
  int n = 0;
  for (std::string raw; std::getline(lines, raw);) {
    ++n;
    const std::string line = trimmed(raw);
    if (line.empty() || line.starts_with('#'))
      continue;
    if (line.starts_with('[')) {
      const std::string name = line.size() > 2 && line.ends_with(']')
                                   ? trimmed(std::string_view(line).substr(1, line.size() - 2))
                                   : std::string();
      if (name.empty() || name.find_first_of("[] \t") != std::string::npos)
        config.errors.push_back(fmt::format("line {}: a malformed section head: {}", n, line));
      else
        section = name;
      continue;
    }
    const auto equals = line.find('=');
    const std::string key =
        equals == std::string::npos ? std::string() : trimmed(line.substr(0, equals));
    if (key.empty() || key.find_first_of(" \t") != std::string::npos) {
      config.errors.push_back(fmt::format("line {}: not a key=value line: {}", n, line));
      continue;
    }
    config.entries.push_back({section, key, trimmed(line.substr(equals + 1)), n});
  }
  return config;
}

// The keys the trees use, each looked up in the Vitis docs (UG1399 "Tcl to
// Config File Command Map", UG1702 "HLS General Options", "C-Simulation
// Configuration", "Co-Simulation Configuration", "Package Options"); true:
// may repeat (one file per line).
const std::map<std::string, bool, std::less<>> kHlsKeys{
    {"flow_target", false}, {"clock", false},
    {"syn.top", false},     {"syn.file", true},
    {"syn.cflags", false},  {"tb.file", true},
    {"tb.cflags", false},   {"csim.argv", false},
    {"cosim.argv", false},  {"package.output.format", false}};

// What is wrong with the cfg in `folder`; empty when nothing is.
std::vector<std::string> format_problems(const Config& config, const fs::path& folder) {
  std::vector<std::string> problems = config.errors;
  std::map<std::string, int, std::less<>> seen;
  for (const Entry& e : config.entries) {
    const std::string where = fmt::format("line {}: {}", e.line, e.key);
    if (e.section.empty()) {
      if (e.key != "part")
        problems.push_back(where + " outside [hls]");
    } else if (e.section != "hls") {
      problems.push_back(fmt::format("line {}: section [{}]", e.line, e.section));
    } else if (const auto known = kHlsKeys.find(e.key); known == kHlsKeys.end()) {
      problems.push_back(where + " is not a key we know the meaning of");
    } else if (!known->second && ++seen[e.key] > 1) {
      problems.push_back(where + " again (Vitis takes the first)");
    }
    if (e.value.empty())
      problems.push_back(where + " has no value");
  }
  for (const char* key : {"part", "flow_target", "clock", "syn.top", "syn.file", "tb.file"})
    if (config.all(std::string_view(key) == "part" ? "" : "hls", key).empty())
      problems.push_back(fmt::format("no {}", key));
  for (const char* key : {"syn.file", "tb.file"}) {
    for (const std::string& file : config.all("hls", key)) {
      const fs::path relative = fs::path(file).lexically_normal();
      if (relative.is_absolute() || relative.begin() == relative.end() || *relative.begin() == "..")
        problems.push_back(fmt::format("{}={} is not inside the tree", key, file));
      else if (!fs::is_regular_file(folder / relative))
        problems.push_back(fmt::format("{}={}: no such file next to the cfg", key, file));
    }
  }
  return problems;
}

// ---- run_hls.tcl --------------------------------------------------------

// A Tcl command's words: "..." and {...} are one word each, without the
// quotes or braces (enough for the script the exporter writes).
std::vector<std::string> tcl_words(std::string_view line) {
  std::vector<std::string> list;
  std::size_t i = 0;
  while (i < line.size()) {
    if (line[i] == ' ' || line[i] == '\t') {
      ++i;
      continue;
    }
    const char close = line[i] == '"' ? '"' : line[i] == '{' ? '}' : ' ';
    const std::size_t start = close == ' ' ? i : i + 1;
    const std::size_t end = std::min(line.find(close, start), line.size());
    list.emplace_back(line.substr(start, end - start));
    i = end + 1;
  }
  return list;
}

struct TclFile {
  std::string file;
  std::string cflags;
};

struct TclProject {
  std::string top, part, period, flow_target, csim_argv, cosim_argv, format;
  std::vector<TclFile> sources, tb_files;
};

TclProject parse_tcl(std::string_view text) {
  TclProject p;
  std::istringstream lines{std::string(text)};
  for (std::string line; std::getline(lines, line);) {
    const std::vector<std::string> w = tcl_words(line);
    if (w.empty() || w[0].starts_with('#'))
      continue;
    const auto option = [&](std::string_view name) {
      const auto it = std::ranges::find(w, name);
      return it != w.end() && it + 1 != w.end() ? *(it + 1) : std::string();
    };
    if (w[0] == "set_top" && w.size() == 2) {
      p.top = w[1];
    } else if (w[0] == "set_part" && w.size() == 2) {
      p.part = w[1];
    } else if (w[0] == "create_clock") {
      p.period = option("-period");
    } else if (w[0] == "open_solution") {
      p.flow_target = option("-flow_target");
    } else if (w[0] == "csim_design") {
      p.csim_argv = option("-argv");
    } else if (w[0] == "cosim_design") {
      p.cosim_argv = option("-argv");
    } else if (w[0] == "export_design") {
      p.format = option("-format");
    } else if (w[0] == "add_files") {
      const bool tb = std::ranges::find(w, "-tb") != w.end();
      for (std::size_t i = 1; i < w.size(); ++i) {
        if (w[i] == "-tb")
          continue;
        if (w[i].starts_with('-')) {
          ++i;  // an option's value
          continue;
        }
        for (const std::string& file : words(w[i]))
          (tb ? p.tb_files : p.sources).push_back({file, option("-cflags")});
      }
    }
  }
  return p;
}

// Where the cfg says something else than run_hls.tcl.
std::vector<std::string> tcl_differences(const Config& cfg, const TclProject& tcl) {
  std::vector<std::string> differences;
  const auto expect = [&](std::string_view what, const std::string& in_cfg,
                          const std::string& in_tcl) {
    if (in_cfg != in_tcl || in_tcl.empty())
      differences.push_back(
          fmt::format("{}: '{}' in hls_config.cfg, '{}' in run_hls.tcl", what, in_cfg, in_tcl));
  };
  expect("top", cfg.one("syn.top"), tcl.top);
  expect("part", cfg.one("part"), tcl.part);
  expect("clock", cfg.one("clock"), tcl.period + "ns");
  expect("flow target", cfg.one("flow_target"), tcl.flow_target);
  expect("csim arguments", cfg.one("csim.argv"), tcl.csim_argv);
  expect("cosim arguments", cfg.one("cosim.argv"), tcl.cosim_argv);
  expect("export format", cfg.one("package.output.format"), tcl.format);
  const auto names = [](const std::vector<TclFile>& files) {
    std::vector<std::string> list;
    for (const TclFile& f : files)
      list.push_back(f.file);
    return fmt::format("{}", fmt::join(list, " "));
  };
  expect("sources", fmt::format("{}", fmt::join(cfg.all("hls", "syn.file"), " ")),
         names(tcl.sources));
  expect("testbench files", fmt::format("{}", fmt::join(cfg.all("hls", "tb.file"), " ")),
         names(tcl.tb_files));
  for (const TclFile& f : tcl.sources)
    expect(fmt::format("cflags of {}", f.file), cfg.one("syn.cflags"), f.cflags);
  for (const TclFile& f : tcl.tb_files)
    if (!f.cflags.empty())  // data files have none
      expect(fmt::format("cflags of {}", f.file), cfg.one("tb.cflags"), f.cflags);
  return differences;
}

// ---- building as C simulation does -----------------------------------

bool is_cxx_source(const std::string& file) {
  const std::string ext = fs::path(file).extension().string();
  return ext == ".cpp" || ext == ".cc" || ext == ".cxx" || ext == ".c";
}

struct CsimBuild {
  bool ok = false;
  std::string log;                    // the commands and what they printed
  std::vector<fs::path> syn_objects;  // of the syn.file sources
  fs::path run_folder;                // holds the binary and the tb data files
};

// Builds the tree in `folder` as C simulation does, in `work`, each
// syn.file with syn.cflags and each tb.file source with tb.cflags;
// `tool_flags` stands for what Vitis adds itself (its include path).
CsimBuild build_like_csim(const Config& cfg, const fs::path& folder, const fs::path& work,
                          const std::string& tool_flags) {
  CsimBuild build;
  build.run_folder = work / "csim";
  fs::create_directories(build.run_folder);
  std::vector<std::string> objects;
  const auto compile = [&](const std::string& file, const std::string& cflags) {
    const fs::path object = work / fmt::format("{}.o", objects.size());
    const std::string command = fmt::format("g++ {} {} -c '{}' -o '{}'", cflags, tool_flags,
                                            (folder / file).string(), object.string());
    const auto result = run_shell(command, work);
    build.log += fmt::format("$ {}\n{}", command, result.message);
    objects.push_back(fmt::format("'{}'", object.string()));
    return result.ok() ? std::optional<fs::path>(object) : std::nullopt;
  };
  for (const std::string& file : cfg.all("hls", "syn.file")) {
    const auto object = compile(file, cfg.one("syn.cflags"));
    if (!object)
      return build;
    build.syn_objects.push_back(*object);
  }
  for (const std::string& file : cfg.all("hls", "tb.file")) {
    if (is_cxx_source(file)) {
      if (!compile(file, cfg.one("tb.cflags")))
        return build;
    } else {
      fs::copy_file(folder / file, build.run_folder / fs::path(file).filename());
    }
  }
  const std::string link = fmt::format("g++ {} -o '{}'", fmt::join(objects, " "),
                                       (build.run_folder / "csim.exe").string());
  const auto linked = run_shell(link, work);
  build.log += fmt::format("$ {}\n{}", link, linked.message);
  build.ok = linked.ok();
  return build;
}

// True when an object defines the function `top` (nm: T, the C++ name).
bool defines_function(const std::vector<fs::path>& objects, const std::string& top,
                      std::string& listing) {
  for (const fs::path& object : objects) {
    const auto nm =
        run_program("nm", {"-C", "--defined-only", object.string()}, object.parent_path());
    listing += nm.message;
    std::istringstream lines(nm.message);
    for (std::string line; std::getline(lines, line);) {
      const std::vector<std::string> w = words(line);
      if (w.size() >= 3 && w[1] == "T" && w[2].starts_with(top + "("))
        return true;
    }
  }
  return false;
}

// ---- the tests ----------------------------------------------------------

class HlsConfig : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    out_ = fresh_folder("cfg") / "trees";
    const auto run = odoloc_cli({"export-hls", "--out", out_.string()}, out_.parent_path());
    ASSERT_TRUE(run.ok()) << run.message;
  }
  static fs::path tree(std::string_view kernel) { return out_ / std::string(kernel); }
  static Config config(std::string_view kernel) {
    return parse_config(slurp(tree(kernel) / "hls_config.cfg"));
  }
  // The cordic tree's cfg with `from` replaced by `to` (a broken cfg).
  static Config broken(std::string_view from, std::string_view to) {
    std::string text = slurp(tree("cordic") / "hls_config.cfg");
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos)
      text.replace(at, from.size(), to);
    return parse_config(text);
  }
  static bool mentions(const std::vector<std::string>& problems, std::string_view what) {
    return std::ranges::any_of(
        problems, [&](const std::string& p) { return p.find(what) != std::string::npos; });
  }

 private:
  static inline fs::path out_;
};

TEST_F(HlsConfig, TheParserReadsTheFormVitisReads) {
  const Config c = parse_config(
      "# comment\npart=xc7z020clg400-1\n\n[hls]\n  syn.file = a.cpp\nsyn.file=b.cpp\n"
      "syn.cflags=-std=c++14 -DX=1\n");
  EXPECT_TRUE(c.errors.empty()) << fmt::format("{}", fmt::join(c.errors, "; "));
  EXPECT_EQ(c.one("part"), "xc7z020clg400-1");
  EXPECT_EQ(c.all("hls", "syn.file"), (std::vector<std::string>{"a.cpp", "b.cpp"}));
  EXPECT_EQ(c.one("syn.cflags"), "-std=c++14 -DX=1");  // the value is the rest of the line
  EXPECT_TRUE(c.one("syn.file").empty());              // repeated: no single value
  const Config bad = parse_config("[hls\nsyn.file a.cpp\n=x\nsyn file=y\n");
  ASSERT_EQ(bad.errors.size(), 4U) << fmt::format("{}", fmt::join(bad.errors, "; "));
  EXPECT_NE(bad.errors[0].find("line 1: a malformed section head"), std::string::npos);
  EXPECT_NE(bad.errors[1].find("line 2: not a key=value line"), std::string::npos);
  EXPECT_NE(bad.errors[3].find("line 4:"), std::string::npos);
}

TEST_F(HlsConfig, EveryTreeHasOneThatParsesAndNamesItsOwnFiles) {
  int files = 0;
  for (const auto& kernel : odoloc::hls_export::kernels()) {
    const Config cfg = config(kernel.name);
    const std::vector<std::string> problems = format_problems(cfg, tree(kernel.name));
    EXPECT_TRUE(problems.empty()) << kernel.name << ": "
                                  << fmt::format("{}", fmt::join(problems, "; "));
    files += static_cast<int>(cfg.all("hls", "syn.file").size() + cfg.all("hls", "tb.file").size());
    // Every file of the tree the flow needs is named: all but the scripts and the README.
    std::set<std::string> named;
    for (const char* key : {"syn.file", "tb.file"})
      for (const std::string& file : cfg.all("hls", key))
        named.insert(file);
    EXPECT_EQ(named, (std::set<std::string>{"kernel.cpp", "kernel_test.cpp", "golden_vectors.txt"}))
        << kernel.name;
    // kernel.cpp includes kernel.h from its own folder, as Vitis compiles it.
    EXPECT_NE(slurp(tree(kernel.name) / "kernel.cpp").find("#include \"kernel.h\""),
              std::string::npos);
  }
  // The figures docs/hls.md quotes.
  std::printf("hls_config.cfg of %zu trees: %d files named, each present\n",
              odoloc::hls_export::kernels().size(), files);
}

// The commands the cfg's header gives (its "#   " lines), in order.
std::vector<std::string> cfg_commands(const std::string& text) {
  std::vector<std::string> commands;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.starts_with("#   "))
      commands.push_back(line.substr(4));
  return commands;
}

// The README of every tree gives the cfg's commands; docs/hls.md shows the
// CORDIC's cfg as exported and the same commands.
TEST_F(HlsConfig, TheReadmeAndTheDocsShowItsCommands) {
  for (const auto& kernel : odoloc::hls_export::kernels()) {
    const std::vector<std::string> commands =
        cfg_commands(slurp(tree(kernel.name) / "hls_config.cfg"));
    ASSERT_EQ(commands.size(), 4U) << kernel.name;
    EXPECT_TRUE(commands[0].starts_with("vitis-run --mode hls --csim ")) << commands[0];
    EXPECT_TRUE(commands[1].starts_with("v++ --compile --mode hls ")) << commands[1];
    const std::string readme = slurp(tree(kernel.name) / "README.md");
    for (const std::string& command : commands)
      EXPECT_NE(readme.find("\n" + command + "\n"), std::string::npos)
          << kernel.name << ": " << command;
  }
  const std::string docs = slurp(fs::path(ODOLOC_SOURCE_DIR) / "docs/hls.md");
  const std::string cordic = slurp(tree("cordic") / "hls_config.cfg");
  EXPECT_NE(docs.find("```ini\n" + cordic + "```\n"), std::string::npos)
      << "docs/hls.md does not show the CORDIC's hls_config.cfg as exported:\n"
      << cordic;
  for (const std::string& command : cfg_commands(cordic))
    EXPECT_NE(docs.find("\n" + command + "\n"), std::string::npos) << command;
}

TEST_F(HlsConfig, TheFormatChecksFailOnABrokenCfg) {
  const fs::path folder = tree("cordic");
  EXPECT_TRUE(
      mentions(format_problems(broken("syn.file=kernel.cpp", "syn.file=kernal.cpp"), folder),
               "syn.file=kernal.cpp: no such file"));
  EXPECT_TRUE(mentions(
      format_problems(broken("tb.file=golden_vectors.txt", "tb.file=../cordic/golden_vectors.txt"),
                      folder),
      "is not inside the tree"));
  EXPECT_TRUE(mentions(
      format_problems(broken("syn.top=odoloc_cordic", "syn.top=odoloc_cordic\nsyn.top=x"), folder),
      "syn.top again"));
  EXPECT_TRUE(mentions(format_problems(broken("clock=", "clk="), folder), "clk is not a key"));
  EXPECT_TRUE(
      mentions(format_problems(broken("part=", "[vivado]\npart="), folder), "section [vivado]"));
  EXPECT_TRUE(
      mentions(format_problems(broken("[hls]\n", ""), folder), "flow_target outside [hls]"));
}

TEST_F(HlsConfig, ItSaysWhatRunHlsTclSays) {
  for (const auto& kernel : odoloc::hls_export::kernels()) {
    const TclProject tcl = parse_tcl(slurp(tree(kernel.name) / "run_hls.tcl"));
    EXPECT_EQ(tcl.top, kernel.top);  // the parser read the script
    ASSERT_EQ(tcl.sources.size(), 1U) << kernel.name;
    EXPECT_EQ(tcl.sources[0].cflags, "-std=c++14");
    const std::vector<std::string> differences = tcl_differences(config(kernel.name), tcl);
    EXPECT_TRUE(differences.empty())
        << kernel.name << ": " << fmt::format("{}", fmt::join(differences, "; "));
  }
  const TclProject tcl = parse_tcl(slurp(tree("cordic") / "run_hls.tcl"));
  EXPECT_TRUE(mentions(tcl_differences(broken("clock=20ns", "clock=10ns"), tcl), "clock"));
  EXPECT_TRUE(mentions(tcl_differences(broken("tb.cflags=-std=c++14", "tb.cflags=-std=c++17"), tcl),
                       "cflags of kernel_test.cpp"));
  EXPECT_TRUE(mentions(tcl_differences(broken("tb.file=golden_vectors.txt\n", ""), tcl),
                       "testbench files"));
}

// The tree in `kernel` built as C simulation builds it, with `tool_flags`
// added: the kernel must take the type family `types`, its top must be
// defined and its testbench must pass.
void expect_csim_passes(const KernelDescription& kernel, const fs::path& folder,
                        std::string_view variant, const std::string& tool_flags, int types) {
  const Config cfg = parse_config(slurp(folder / "hls_config.cfg"));
  const std::string what = fmt::format("{} ({})", kernel.name, variant);
  const auto macros = run_shell(
      fmt::format("g++ {} {} -E -dM kernel.cpp", cfg.one("syn.cflags"), tool_flags), folder);
  EXPECT_NE(macros.message.find(fmt::format("#define ODOLOC_HLS_TYPES {}\n", types)),
            std::string::npos)
      << what;
  const fs::path work = fresh_folder(fmt::format("csim_{}_{}", kernel.name, variant));
  const CsimBuild build = build_like_csim(cfg, folder, work, tool_flags);
  ASSERT_TRUE(build.ok) << what << ":\n" << build.log;
  std::string listing;
  EXPECT_TRUE(defines_function(build.syn_objects, cfg.one("syn.top"), listing))
      << what << ": no " << cfg.one("syn.top") << " in\n"
      << listing;
  const auto run = run_program((build.run_folder / "csim.exe").string(),
                               words(cfg.one("csim.argv")), build.run_folder);
  EXPECT_TRUE(run.ok()) << what << ": " << run.message;
  EXPECT_NE(run.message.find(fmt::format("PASS: {} calls", kernel.golden_calls)), std::string::npos)
      << what << ": " << run.message;
}

// Exactly the cfg's flags, so the project's own types (no vendor header on
// the include path).
TEST_F(HlsConfig, ItsTopIsDefinedAndItsTestbenchPassesAsCSimulationBuildsIt) {
  for (const auto& kernel : odoloc::hls_export::kernels())
    expect_csim_passes(kernel, tree(kernel.name), "own", "", 0);
}

// As under Vitis, whose include path has ap_int.h: with no ODOLOC_HLS_TYPES
// the kernel takes it. One tree: the choice is types.hpp's, the same in
// every tree, and test_export_hls builds every tree against ap_int.h; a
// build against ap_int.h takes seconds, not tenths.
TEST_F(HlsConfig, WithApIntOnTheIncludePathAsUnderVitisCSimulationPassesToo) {
  const std::vector<Family> available = families();
  const auto ap = std::ranges::find(available, 1, &Family::value);
  if (ap == available.end())
    GTEST_SKIP() << "no ap_int.h in " << ODOLOC_VENDOR_DIR;
  expect_csim_passes(*odoloc::hls_export::find_kernel("cordic"), tree("cordic"), "ap",
                     fmt::format("-isystem '{}/include'", ap->root), 1);
}

TEST_F(HlsConfig, TheCsimChecksFailOnABrokenCfg) {
  const fs::path folder = tree("cordic");
  // A top the sources do not define.
  const Config renamed = broken("syn.top=odoloc_cordic", "syn.top=odoloc_cordik");
  const CsimBuild build = build_like_csim(renamed, folder, fresh_folder("csim_renamed"), "");
  ASSERT_TRUE(build.ok) << build.log;
  std::string listing;
  EXPECT_FALSE(defines_function(build.syn_objects, renamed.one("syn.top"), listing));
  // Without golden_vectors.txt among the tb.file files C simulation has no
  // vectors to replay.
  const Config no_vectors = broken("tb.file=golden_vectors.txt\n", "");
  const CsimBuild bare = build_like_csim(no_vectors, folder, fresh_folder("csim_bare"), "");
  ASSERT_TRUE(bare.ok) << bare.log;
  const auto run = run_program((bare.run_folder / "csim.exe").string(),
                               words(no_vectors.one("csim.argv")), bare.run_folder);
  EXPECT_TRUE(run.launched);
  EXPECT_NE(run.exit_status, 0) << run.message;
  // The testbench with cflags a C++14 front end refuses.
  const Config cxx98 = broken("tb.cflags=-std=c++14", "tb.cflags=-std=c++98 -pedantic-errors");
  EXPECT_FALSE(build_like_csim(cxx98, folder, fresh_folder("csim_98"), "").ok);
}

}  // namespace
