// `odoloc export-hls` end to end: the real binary writes every kernel's tree
// into a temporary folder; each tree alone (no include path but the vendor's)
// is built with the g++ lines docs/hls.md documents, against the project's
// own types and, where ../shared/vendor has them, ap_int.h and ac_int.h, and
// its testbench must pass on the golden vectors. Without
// -Wno-unknown-pragmas those builds fail on the HLS pragmas and on nothing
// else. Then the bad requests: each gets a clear message and leaves the file
// system as it was. (hls_config.cfg: test_export_hls_config.)
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "export_hls_support.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/process/run_program.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::process::run_program;
using odoloc::process::run_shell;
using odoloc::tb::slurp;
using odoloc::tb::export_hls::documented_host_build;
using odoloc::tb::export_hls::documented_host_builds;
using odoloc::tb::export_hls::families;
using odoloc::tb::export_hls::Family;
using odoloc::tb::export_hls::fresh_folder;
using odoloc::tb::export_hls::odoloc_cli;

std::set<std::string> entries(const fs::path& folder) {
  const std::vector<std::string> names = odoloc::tb::entries(folder);
  return {names.begin(), names.end()};
}

// Every #include of the tree's sources names a file of the tree, the
// vendor's type header or a C/C++ standard header.
void expect_self_contained(const fs::path& tree) {
  // The standard headers: lower case, digits and '_', C's with ".h".
  const auto standard = [](std::string name) {
    if (name.ends_with(".h"))
      name.resize(name.size() - 2);
    return !name.empty() && std::ranges::all_of(name, [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
  };
  for (const char* file : {"kernel.h", "kernel.cpp", "kernel_test.cpp"}) {
    std::istringstream lines(slurp(tree / file));
    for (std::string line; std::getline(lines, line);) {
      std::istringstream words(line);
      std::string hash, include;
      words >> hash;
      if (hash == "#")
        words >> include;
      else if (hash.starts_with('#'))
        include = hash.substr(1);
      if (!include.starts_with("include"))
        continue;
      const auto open = line.find_first_of("<\"", line.find("include"));
      ASSERT_NE(open, std::string::npos) << line;
      const auto close = line.find(line[open] == '<' ? '>' : '"', open + 1);
      ASSERT_NE(close, std::string::npos) << line;
      const std::string header = line.substr(open + 1, close - open - 1);
      const bool local = line[open] == '"' && fs::exists(tree / header);
      const bool vendor = header == "ap_int.h" || header == "ac_int.h" ||
                          header == "HLS/ac_int.h" || header == "HLS/hls.h";
      const bool std_header = line[open] == '<' && standard(header);
      EXPECT_TRUE(local || vendor || std_header) << tree / file << ": " << line;
    }
  }
}

TEST(ExportHls, EveryTreeBuildsAloneAndPassesItsTestbenchInEveryTypeFamily) {
  const fs::path out = fresh_folder("all") / "trees";
  const auto run = odoloc_cli({"export-hls", "--out", out.string()}, out.parent_path());
  ASSERT_TRUE(run.ok()) << run.message;
  const auto kernels = odoloc::hls_export::kernels();
  ASSERT_FALSE(kernels.empty());
  EXPECT_EQ(entries(out).size(), kernels.size());  // one folder per kernel, no staging left
  for (const auto& kernel : kernels) {
    const fs::path tree = out / std::string(kernel.name);
    EXPECT_EQ(entries(tree), (std::set<std::string>{"kernel.h", "kernel.cpp", "kernel_test.cpp",
                                                    "golden_vectors.txt", "run_hls.tcl",
                                                    "hls_config.cfg", "README.md"}))
        << tree;
    expect_self_contained(tree);
    const std::string tcl = slurp(tree / "run_hls.tcl");
    for (const std::string& command : std::vector<std::string>{
             "open_project", "open_solution", "add_files kernel.cpp",
             "add_files -tb kernel_test.cpp", "add_files -tb golden_vectors.txt",
             fmt::format("set_top {}", kernel.top), "set_part", "create_clock -period 20",
             "csim_design", "csynth_design", "cosim_design", "export_design"})
      EXPECT_NE(tcl.find(command), std::string::npos) << kernel.name << ": " << command;
    // The tree's README shows the builds docs/hls.md shows.
    const std::string readme = slurp(tree / "README.md");
    for (const std::string& line : documented_host_builds())
      EXPECT_NE(readme.find(line + "\n"), std::string::npos) << kernel.name << ": " << line;
    for (const Family& family : families()) {
      const std::string build_line = documented_host_build(family);
      const auto build = run_shell(build_line, tree);
      ASSERT_TRUE(build.ok()) << kernel.name << ": " << build_line << ": " << build.message;
      const auto test = run_program((tree / "kernel_test").string(), {"golden_vectors.txt"}, tree);
      EXPECT_TRUE(test.ok()) << kernel.name << " (" << family.name << "): " << test.message;
      EXPECT_NE(test.message.find(fmt::format("PASS: {} calls", kernel.golden_calls)),
                std::string::npos)
          << test.message;
      fs::remove(tree / "kernel_test");  // the next family's build must make its own
    }
  }
}

TEST(ExportHls, TheDocumentedBuildsAreOnePerFamily) {
  const std::vector<std::string> lines = documented_host_builds();
  EXPECT_EQ(lines.size(), 3U);
  for (int value = 0; value <= 2; ++value)
    EXPECT_EQ(std::ranges::count_if(lines,
                                    [&](const std::string& line) {
                                      return line.find(fmt::format("-DODOLOC_HLS_TYPES={} ",
                                                                   value)) != std::string::npos;
                                    }),
              1)
        << value;
}

// What -Wno-unknown-pragmas of the documented builds is for: without it every
// tree fails -Werror, and every error is GCC ignoring an HLS tool's pragma
// (`#pragma HLS ...`, and Catapult's `#pragma hls_design top`) on a line
// that holds that pragma. The front end is enough to see it: -fsyntax-only.
TEST(ExportHls, WithoutNoUnknownPragmasOnlyTheHlsPragmasFailTheBuild) {
  const fs::path out = fresh_folder("pragmas") / "trees";
  ASSERT_TRUE(odoloc_cli({"export-hls", "--out", out.string()}, out.parent_path()).ok());
  std::string command = documented_host_build(families().front());
  const std::string flag = " -Wno-unknown-pragmas";
  const auto at = command.find(flag);
  ASSERT_NE(at, std::string::npos) << command;
  command.erase(at, flag.size());
  command = fmt::format("LC_ALL=C {} -fsyntax-only -fdiagnostics-plain-output", command);
  for (const auto& kernel : odoloc::hls_export::kernels()) {
    const fs::path tree = out / std::string(kernel.name);
    const auto build = run_shell(command, tree);
    EXPECT_TRUE(build.launched);
    EXPECT_NE(build.exit_status, 0) << kernel.name << ": " << command;
    int hls_pragmas = 0;
    std::istringstream lines(build.message);
    for (std::string line; std::getline(lines, line);) {
      if (line.find("error: ") == std::string::npos)
        continue;
      // FILE:LINE: error: ignoring '#pragma NAME ...' [-Werror=unknown-pragmas]
      const auto colon = line.find(':');
      const auto colon2 = line.find(':', colon + 1);
      const auto quote = line.find("'#pragma ");
      const auto unquote = line.find('\'', quote + 1);
      ASSERT_TRUE(colon2 != std::string::npos && quote != std::string::npos &&
                  unquote != std::string::npos)
          << kernel.name << ": " << line;
      EXPECT_TRUE(line.ends_with("[-Werror=unknown-pragmas]")) << kernel.name << ": " << line;
      const std::string pragma = line.substr(quote + 1, unquote - quote - 1);
      EXPECT_TRUE(pragma.starts_with("#pragma HLS ") || pragma == "#pragma hls_design top")
          << kernel.name << ": " << line;
      hls_pragmas += pragma.starts_with("#pragma HLS ") ? 1 : 0;
      // The line GCC names holds that pragma.
      std::istringstream source(slurp(tree / line.substr(0, colon)));
      std::string text;
      for (int n = std::stoi(line.substr(colon + 1, colon2 - colon - 1)); n > 0; --n)
        std::getline(source, text);
      const auto start = text.find_first_not_of(" \t");
      EXPECT_TRUE(start != std::string::npos && text.compare(start, pragma.size(), pragma) == 0)
          << kernel.name << ": " << line << " names the line '" << text << "'";
    }
    EXPECT_GT(hls_pragmas, 0) << kernel.name << ": " << build.message;
  }
}

TEST(ExportHls, ATestbenchFailsOnAGoldenValueChanged) {
  const fs::path out = fresh_folder("tamper") / "trees";
  ASSERT_TRUE(
      odoloc_cli({"export-hls", "--out", out.string(), "--kernel", "cordic"}, out.parent_path())
          .ok());
  const fs::path tree = out / "cordic";
  ASSERT_TRUE(run_shell(documented_host_build(families().front()), tree).ok());
  // The last column of the last row (cos) off by one.
  std::string text = slurp(tree / "golden_vectors.txt");
  const auto end = text.find_last_not_of('\n');
  const auto start = text.find_last_of(' ', end) + 1;
  const long long cos = std::stoll(text.substr(start, end + 1 - start));
  text.replace(start, end + 1 - start, std::to_string(cos + 1));
  std::ofstream(tree / "golden_vectors.txt") << text;
  const auto test = run_program((tree / "kernel_test").string(), {}, tree);
  EXPECT_TRUE(test.launched);
  EXPECT_EQ(test.exit_status, 1);
  EXPECT_NE(test.message.find("MISMATCH call 19999, cos"), std::string::npos) << test.message;
}

TEST(ExportHls, EachToolGetsItsScript) {
  for (const auto& [tool, script, words] :
       {std::tuple{"catapult", "run_catapult.tcl",
                   std::vector<std::string>{"solution file add ./kernel.cpp",
                                            "solution design set odoloc_cordic -top",
                                            "CLOCK_PERIOD 20", "go extract", "SCVerify"}},
        std::tuple{"intel", "Makefile",
                   std::vector<std::string>{"i++", "--component odoloc_cordic", "--clock 20ns",
                                            "-march=x86-64", "golden_vectors.txt"}}}) {
    const fs::path out = fresh_folder(tool) / "trees";
    const auto run =
        odoloc_cli({"export-hls", "--out", out.string(), "--kernel", "cordic", "--tool", tool},
                   out.parent_path());
    ASSERT_TRUE(run.ok()) << run.message;
    const std::string text = slurp(out / "cordic" / script);
    for (const std::string& word : words)
      EXPECT_NE(text.find(word), std::string::npos) << tool << ": " << word;
    EXPECT_FALSE(fs::exists(out / "cordic" / "run_hls.tcl"));
  }
}

// A refused request: exit status 2, the message, and the parent folder as before.
void expect_refused(const std::vector<std::string>& args, const fs::path& parent,
                    const std::string& message) {
  const std::set<std::string> before = entries(parent);
  const auto run = odoloc_cli(args, parent);
  EXPECT_TRUE(run.launched);
  EXPECT_EQ(run.exit_status, 2) << run.message;
  EXPECT_NE(run.message.find(message), std::string::npos) << run.message;
  EXPECT_EQ(entries(parent), before);
}

TEST(ExportHls, BadRequestsAreRefusedAndWriteNothing) {
  const fs::path parent = fresh_folder("bad");
  const std::string out = (parent / "trees").string();
  expect_refused({"export-hls", "--out", out, "--kernel", "cordic", "--kernel", "fft"}, parent,
                 "unknown kernel 'fft'; the kernels are cordic");
  expect_refused({"export-hls", "--out", out, "--tool", "quartus"}, parent,
                 "unknown --tool 'quartus'; expected vitis, catapult or intel");
  expect_refused({"export-hls"}, parent, "--out is required");
  expect_refused({"export-hls", "--out", (parent / "missing" / "trees").string()}, parent,
                 "does not exist");
  expect_refused({"export-hls", "--out", out, "--target", "sim"}, parent,
                 "--target does not apply to export-hls");
  // A folder nobody may write in, root included.
  const auto proc = odoloc_cli({"export-hls", "--out", "/proc/odoloc-export"}, parent);
  EXPECT_EQ(proc.exit_status, 2) << proc.message;
  EXPECT_NE(proc.message.find("cannot write in /proc"), std::string::npos) << proc.message;
  EXPECT_FALSE(fs::exists("/proc/odoloc-export"));

  // An existing, non-empty folder: refused without --force; with it, the
  // kernel's folder is replaced and nothing else is touched.
  fs::create_directories(parent / "trees" / "cordic");
  std::ofstream(parent / "trees" / "notes.txt") << "mine\n";
  std::ofstream(parent / "trees" / "cordic" / "stale.txt") << "old\n";
  const std::set<std::string> before = entries(parent / "trees");
  expect_refused({"export-hls", "--out", out, "--kernel", "cordic"}, parent / "trees",
                 "is not empty; pass --force");
  EXPECT_TRUE(fs::exists(parent / "trees" / "cordic" / "stale.txt"));
  const auto forced =
      odoloc_cli({"export-hls", "--out", out, "--kernel", "cordic", "--force"}, parent);
  ASSERT_TRUE(forced.ok()) << forced.message;
  EXPECT_EQ(entries(parent / "trees"), before);  // no staging folder left behind
  EXPECT_EQ(slurp(parent / "trees" / "notes.txt"), "mine\n");
  EXPECT_FALSE(fs::exists(parent / "trees" / "cordic" / "stale.txt"));
  EXPECT_TRUE(fs::exists(parent / "trees" / "cordic" / "kernel.h"));
  // OUT is a file.
  expect_refused({"export-hls", "--out", (parent / "trees" / "notes.txt").string()},
                 parent / "trees", "exists and is not a folder");
}

}  // namespace
