// `odoloc export-hls` end to end: the real binary writes every kernel's tree
// into a temporary folder; each tree alone (no include path but the vendor's)
// is built with g++ -std=c++14 against the project's own types and, where
// ../shared/vendor has them, ap_int.h and ac_int.h, and its testbench must
// pass on the golden vectors. Then the bad requests: each gets a clear
// message and leaves the file system as it was.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "odoloc/hls_export/reference.hpp"
#include "odoloc/process/run_program.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::process::run_program;
using odoloc::process::run_shell;

// Per process (builds in other folders may run this test at the same time),
// removed when the tests end.
fs::path scratch() {
  return fs::path(::testing::TempDir()) / fmt::format("odoloc_export_{}", ::getpid());
}
class RemoveScratch : public ::testing::Environment {
 public:
  void TearDown() override { fs::remove_all(scratch()); }
};
const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = scratch() / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::set<std::string> entries(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.insert(entry.path().filename().string());
  return names;
}

odoloc::process::ProgramResult odoloc_cli(const std::vector<std::string>& args,
                                          const fs::path& dir) {
  return run_program(ODOLOC_CLI, args, dir);
}

struct Family {
  const char* name;
  int value;
  std::string include;  // empty: the project's own types
};

std::vector<Family> families() {
  std::vector<Family> list{{"own", 0, ""}};
  const fs::path vendor = ODOLOC_VENDOR_DIR;
  if (fs::exists(vendor / "ap_types/include/ap_int.h"))
    list.push_back({"ap", 1, (vendor / "ap_types/include").string()});
  if (fs::exists(vendor / "ac_types/include/ac_int.h"))
    list.push_back({"ac", 2, (vendor / "ac_types/include").string()});
  return list;
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
    std::istringstream lines(read_text(tree / file));
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
    EXPECT_EQ(entries(tree),
              (std::set<std::string>{"kernel.h", "kernel.cpp", "kernel_test.cpp",
                                     "golden_vectors.txt", "run_hls.tcl", "README.md"}))
        << tree;
    expect_self_contained(tree);
    const std::string tcl = read_text(tree / "run_hls.tcl");
    for (const std::string& command : std::vector<std::string>{
             "open_project", "open_solution", "add_files kernel.cpp",
             "add_files -tb kernel_test.cpp", "add_files -tb golden_vectors.txt",
             fmt::format("set_top {}", kernel.top), "set_part", "create_clock -period 20",
             "csim_design", "csynth_design", "cosim_design", "export_design"})
      EXPECT_NE(tcl.find(command), std::string::npos) << kernel.name << ": " << command;
    for (const Family& family : families()) {
      const std::string binary = fmt::format("kernel_test_{}", family.name);
      // GCC 12 -O2 reports a false uninitialised use inside Xilinx's ap_private.h
      // (docs/hls.md), hence the two -Wno- for the vendor families.
      const std::string vendor =
          family.include.empty()
              ? ""
              : fmt::format("-isystem '{}' -Wno-uninitialized -Wno-maybe-uninitialized",
                            family.include);
      const auto build =
          run_shell(fmt::format("g++ -std=c++14 -pedantic-errors -Wall -Wextra -Werror "
                                "-Wno-unknown-pragmas -O2 -DODOLOC_HLS_TYPES={} {} kernel.cpp "
                                "kernel_test.cpp -o {}",
                                family.value, vendor, binary),
                    tree);
      ASSERT_TRUE(build.ok()) << kernel.name << " (" << family.name << "): " << build.message;
      const auto test = run_program((tree / binary).string(), {"golden_vectors.txt"}, tree);
      EXPECT_TRUE(test.ok()) << kernel.name << " (" << family.name << "): " << test.message;
      EXPECT_NE(test.message.find(fmt::format("PASS: {} calls", kernel.golden_calls)),
                std::string::npos)
          << test.message;
    }
  }
}

TEST(ExportHls, ATestbenchFailsOnAGoldenValueChanged) {
  const fs::path out = fresh_folder("tamper") / "trees";
  ASSERT_TRUE(
      odoloc_cli({"export-hls", "--out", out.string(), "--kernel", "cordic"}, out.parent_path())
          .ok());
  const fs::path tree = out / "cordic";
  ASSERT_TRUE(run_shell("g++ -std=c++14 -O1 -Wno-unknown-pragmas -DODOLOC_HLS_TYPES=0 kernel.cpp "
                        "kernel_test.cpp -o kernel_test",
                        tree)
                  .ok());
  // The last column of the last row (cos) off by one.
  std::string text = read_text(tree / "golden_vectors.txt");
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
    const std::string text = read_text(out / "cordic" / script);
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
  EXPECT_EQ(read_text(parent / "trees" / "notes.txt"), "mine\n");
  EXPECT_FALSE(fs::exists(parent / "trees" / "cordic" / "stale.txt"));
  EXPECT_TRUE(fs::exists(parent / "trees" / "cordic" / "kernel.h"));
  // OUT is a file.
  expect_refused({"export-hls", "--out", (parent / "trees" / "notes.txt").string()},
                 parent / "trees", "exists and is not a folder");
}

}  // namespace
