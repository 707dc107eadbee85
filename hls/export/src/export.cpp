#include "odoloc/hls_export/export.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <functional>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <system_error>

#include "odoloc/hls_export/embedded.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/process/run_program.hpp"

namespace odoloc::hls_export {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kGoldenSeed = 12;
constexpr std::string_view kGoldenVectors = "golden_vectors.txt";
constexpr std::string_view kVitisPart = "xc7z020clg400-1";  // Zynq-7020 (PYNQ-Z2, ZedBoard)
constexpr int kClockNs = 20;  // the 50 MHz fabric clock, in every tool's flow
constexpr std::array kToolNames{std::string_view{"vitis"}, std::string_view{"catapult"},
                                std::string_view{"intel"}};

[[noreturn]] void usage_error(const std::string& what) {
  throw ExportError(true, what);
}
[[noreturn]] void file_error(const std::string& what) {
  throw ExportError(false, what);
}

std::string_view source(std::string_view key) {
  for (const EmbeddedFile& file : hls_sources())
    if (file.key == key)
      return file.text;
  file_error(fmt::format("export-hls: the tool carries no source {} (rebuild it)", key));
}

// `#include "odoloc/..."`: the project's; anything else stays as written.
// The preprocessor directive of a line ("include \"x\"", "pragma once"),
// spaces after '#' removed; empty when the line is not a directive.
std::string directive(std::string_view line) {
  const auto hash = line.find_first_not_of(" \t");
  if (hash == std::string_view::npos || line[hash] != '#')
    return {};
  line.remove_prefix(hash + 1);
  const auto start = line.find_first_not_of(" \t");
  return start == std::string_view::npos ? std::string{} : std::string(line.substr(start));
}

// `#include "odoloc/..."`: the header named, for the project's includes;
// nullopt for anything else, which stays as written.
std::optional<std::string> project_include(std::string_view line) {
  const std::string d = directive(line);
  if (!d.starts_with("include"))
    return std::nullopt;
  const auto open = d.find('"');
  const auto close = open == std::string::npos ? open : d.find('"', open + 1);
  if (close == std::string::npos || d.compare(open + 1, 7, "odoloc/") != 0)
    return std::nullopt;
  return d.substr(open + 1, close - open - 1);
}

bool is_pragma_once(std::string_view line) {
  std::istringstream words(directive(line));
  std::string pragma, once, rest;
  words >> pragma >> once >> rest;
  return pragma == "pragma" && once == "once" && rest.empty();
}

void flatten_into(std::string_view key, std::set<std::string, std::less<>>& done,
                  std::string& out) {
  done.emplace(key);
  std::istringstream lines{std::string(source(key))};
  out += fmt::format("// ---- {} ----\n", key);
  for (std::string line; std::getline(lines, line);) {
    if (is_pragma_once(line))
      continue;
    if (const auto header = project_include(line)) {
      if (!done.contains(*header))
        flatten_into(*header, done, out);
      continue;
    }
    out += line;
    out += '\n';
  }
}

std::string banner(const KernelDescription& kernel, std::string_view file) {
  return fmt::format(
      "// {}: the odoloc {} kernel ({}).\n"
      "// Written by `odoloc export-hls` from the project's HLS sources (hls/); edit those,\n"
      "// not this file. Details: README.md.\n",
      file, kernel.name, kernel.summary);
}

std::string kernel_header(const KernelDescription& kernel) {
  std::string guard = fmt::format("ODOLOC_{}_KERNEL_H", kernel.name);
  std::ranges::transform(guard, guard.begin(), [](unsigned char c) { return std::toupper(c); });
  return banner(kernel, "kernel.h") + fmt::format("#ifndef {0}\n#define {0}\n\n", guard) +
         flatten(kernel.header) + fmt::format("\n#endif  // {}\n", guard);
}

std::string kernel_source(const KernelDescription& kernel) {
  const std::string own = fmt::format("#include \"{}\"", kernel.header);
  std::string text(source(fmt::format("src/{}", kernel.top_source)));
  const auto at = text.find(own);
  if (at == std::string::npos)
    file_error(fmt::format("export-hls: {} does not include {}", kernel.top_source, kernel.header));
  text.replace(at, own.size(), "#include \"kernel.h\"");
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (project_include(line))
      file_error(fmt::format("export-hls: {} includes another odoloc header", kernel.top_source));
  return banner(kernel, "kernel.cpp") + text;
}

std::string kernel_test(const KernelDescription& kernel) {
  std::string testbench = flatten("testbench/golden_testbench.hpp");
  return banner(kernel, "kernel_test.cpp") +
         fmt::format(
             "// Usage: kernel_test [golden_vectors.txt]; exit status 0 when every output of\n"
             "// every call equals the cycle model's.\n"
             "#include \"kernel.h\"\n\n"
             "{0}\n"
             "int main(int argc, char** argv) {{\n"
             "  return odoloc::hls::golden::run_golden<{1}::Inputs, {1}::Outputs>(\n"
             "      argc > 1 ? argv[1] : \"golden_vectors.txt\", {2});\n"
             "}}\n",
             testbench, kernel.space, kernel.top);
}

std::string golden_vectors(const KernelDescription& kernel) {
  const auto reference = kernel.make_reference(kGoldenSeed);
  const auto in_names = reference->input_names();
  const auto out_names = reference->output_names();
  std::vector<std::int64_t> in(in_names.size()), out(out_names.size());
  std::string text = fmt::format(
      "# odoloc {} kernel: {} calls of seeded random stimulus (seed {}), each followed by the\n"
      "# outputs of the cycle model (rtl_model/) after that call; one call = {}.\n"
      "# in: {}\n# out: {}\n",
      kernel.name, kernel.golden_calls, kGoldenSeed, kernel.call, fmt::join(in_names, " "),
      fmt::join(out_names, " "));
  for (std::int64_t call = 0; call < kernel.golden_calls; ++call) {
    reference->stimulus(in);
    reference->step(in, out);
    text += fmt::format("{} {}\n", fmt::join(in, " "), fmt::join(out, " "));
  }
  return text;
}

// The header's leading comment: the interface as the kernel documents it.
std::string interface_text(const KernelDescription& kernel) {
  std::istringstream lines{std::string(source(kernel.header))};
  std::string text;
  for (std::string line; std::getline(lines, line) && line.starts_with("//");)
    text += (line.size() > 3 ? line.substr(3) : std::string()) + "\n";
  return text;
}

// The Vitis HLS project of a tree. Both flows are written from it: the
// classic Tcl script (vitis_hls -f run_hls.tcl) and the Vitis Unified config
// file (v++ / vitis-run --config hls_config.cfg), so they cannot drift apart.
struct VitisProject {
  std::string_view kernel;
  std::string_view top;
  std::vector<std::string_view> sources;     // synthesised
  std::vector<std::string_view> tb_sources;  // C simulation only
  std::vector<std::string_view> tb_data;     // read by the testbench
  std::string_view cflags;                   // of every source, kernel and testbench
  std::string_view tb_args;                  // C simulation and co-simulation
  std::string_view flow_target;
  std::string_view part;
  int clock_ns;
  std::string_view package_format;
};

VitisProject vitis_project(const KernelDescription& kernel) {
  return {.kernel = kernel.name,
          .top = kernel.top,
          .sources = {"kernel.cpp"},
          .tb_sources = {"kernel_test.cpp"},
          .tb_data = {kGoldenVectors},
          .cflags = "-std=c++14",
          .tb_args = kGoldenVectors,
          .flow_target = "vivado",
          .part = kVitisPart,
          .clock_ns = kClockNs,
          .package_format = "ip_catalog"};
}

std::string vitis_script(const VitisProject& p) {
  std::string files;
  for (std::string_view file : p.sources)
    files += fmt::format("add_files {} -cflags \"{}\"\n", file, p.cflags);
  for (std::string_view file : p.tb_sources)
    files += fmt::format("add_files -tb {} -cflags \"{}\"\n", file, p.cflags);
  for (std::string_view file : p.tb_data)
    files += fmt::format("add_files -tb {}\n", file);
  return fmt::format(
      "# Vitis HLS: vitis_hls -f run_hls.tcl   (odoloc {0} kernel, top {1})\n"
      "# C simulation replays {2}; co-simulation replays it against the RTL.\n"
      "# Vitis Unified (2023.2 and later) takes the same project from hls_config.cfg.\n"
      "open_project -reset {0}_prj\n"
      "set_top {1}\n"
      "{3}"
      "open_solution -reset solution1 -flow_target {4}\n"
      "set_part {{{5}}}\n"
      "create_clock -period {6} -name default\n"
      "csim_design -argv {2}\n"
      "csynth_design\n"
      "cosim_design -argv {2}\n"
      "export_design -format {7}\n"
      "exit\n",
      p.kernel, p.top, p.tb_args, files, p.flow_target, p.part, p.clock_ns, p.package_format);
}

// The Vitis Unified commands, in the order they must run: co-simulation and
// packaging need the synthesised component in the work folder.
std::string vitis_unified_commands(const VitisProject& p) {
  const std::string tail = fmt::format("--config hls_config.cfg --work_dir {}_component", p.kernel);
  return fmt::format(
      "vitis-run --mode hls --csim {0}\n"
      "v++ --compile --mode hls {0}\n"
      "vitis-run --mode hls --cosim {0}\n"
      "vitis-run --mode hls --package {0}\n",
      tail);
}

// The layout of Xilinx's Vitis-HLS-Introductory-Examples: the part before
// any section, the rest under [hls]; repeated keys list several files.
// Relative paths are taken from this file's folder.
std::string vitis_config(const VitisProject& p) {
  std::string text = fmt::format(
      "# Vitis Unified (2023.2 and later), odoloc {} kernel, top {}: the project of\n"
      "# run_hls.tcl. Paths are relative to this file's folder. Run from here:\n",
      p.kernel, p.top);
  std::istringstream commands(vitis_unified_commands(p));
  for (std::string line; std::getline(commands, line);)
    text += fmt::format("#   {}\n", line);
  text += fmt::format("part={}\n\n[hls]\nflow_target={}\nclock={}ns\nsyn.top={}\n", p.part,
                      p.flow_target, p.clock_ns, p.top);
  for (std::string_view file : p.sources)
    text += fmt::format("syn.file={}\n", file);
  text += fmt::format("syn.cflags={}\n", p.cflags);
  for (std::string_view file : p.tb_sources)
    text += fmt::format("tb.file={}\n", file);
  for (std::string_view file : p.tb_data)
    text += fmt::format("tb.file={}\n", file);
  text += fmt::format("tb.cflags={0}\ncsim.argv={1}\ncosim.argv={1}\npackage.output.format={2}\n",
                      p.cflags, p.tb_args, p.package_format);
  return text;
}

std::string catapult_script(const KernelDescription& kernel) {
  return fmt::format(
      "# Catapult: catapult -shell -file run_catapult.tcl   (odoloc {0} kernel, top {1})\n"
      "# ac_int types (ODOLOC_HLS_TYPES=2); the top carries #pragma hls_design top.\n"
      "# SCVerify replays golden_vectors.txt through kernel_test.cpp before and after\n"
      "# synthesis. Pick the technology library of your target below.\n"
      "options set Input/CppStandard c++14\n"
      "options set Input/CompilerFlags {{-DODOLOC_HLS_TYPES=2}}\n"
      "options set Flows/SCVerify/USE_CCS_BLOCK true\n"
      "project new -name {0}_prj\n"
      "flow package require /SCVerify\n"
      "solution file add ./kernel.h -type CHEADER\n"
      "solution file add ./kernel.cpp -type C++\n"
      "solution file add ./kernel_test.cpp -type C++ -exclude true\n"
      "solution design set {1} -top\n"
      "go analyze\n"
      "go compile\n"
      "solution library add mgc_Xilinx-ARTIX-7-1_beh -- -rtlsyntool Vivado -manufacturer Xilinx "
      "-family ARTIX-7 -speed -1 -part xc7a100tcsg324-1\n"
      "go libraries\n"
      "directive set -CLOCKS {{clk {{-CLOCK_PERIOD {2}.0}}}}\n"
      "go assembly\n"
      "go architect\n"
      "go allocate\n"
      "go extract\n"
      "flow run /SCVerify/launch_make ./scverify/Verify_orig_cxx_osci.mk {{}} SIMTOOL=osci sim\n"
      "flow run /SCVerify/launch_make ./scverify/Verify_rtl_v_msim.mk {{}} SIMTOOL=msim sim\n"
      "project save\n",
      kernel.name, kernel.top, kClockNs);
}

std::string intel_makefile(const KernelDescription& kernel) {
  return fmt::format(
      "# Intel HLS Compiler (i++), odoloc {0} kernel: the top {1} is a component\n"
      "# (ODOLOC_HLS_TOP expands to `component` under i++, whose HLS/ac_int.h it uses).\n"
      "#   make run        emulation on the host, replays golden_vectors.txt\n"
      "#   make fpga       the component for DEVICE at 50 MHz, with its co-simulation\n"
      "DEVICE ?= Agilex7\n"
      "SOURCES := kernel.cpp kernel_test.cpp\n"
      "FLAGS := -std=c++14 --component {1}\n\n"
      "test-x86-64: $(SOURCES) kernel.h\n"
      "\ti++ $(FLAGS) -march=x86-64 $(SOURCES) -o $@\n\n"
      "run: test-x86-64\n"
      "\t./test-x86-64 golden_vectors.txt\n\n"
      "test-fpga: $(SOURCES) kernel.h\n"
      "\ti++ $(FLAGS) -march=$(DEVICE) --clock {2}ns $(SOURCES) -o $@\n\n"
      "fpga: test-fpga\n"
      "\t./test-fpga golden_vectors.txt\n\n"
      ".PHONY: run fpga\n",
      kernel.name, kernel.top, kClockNs);
}

// A file of the tool's flow, with its row in the README's file table.
struct FlowFile {
  std::string_view name;
  std::string text;
  std::string_view what;
};

struct ToolFiles {
  std::vector<FlowFile> files;
  std::string how;  // the README's commands
};

ToolFiles tool_files(const KernelDescription& kernel, HlsTool tool) {
  switch (tool) {
    case HlsTool::kCatapult:
      return {{{"run_catapult.tcl", catapult_script(kernel), "the Catapult flow"}},
              "catapult -shell -file run_catapult.tcl\n"};
    case HlsTool::kIntel:
      return {{{"Makefile", intel_makefile(kernel), "the Intel HLS flow"}},
              "make run   # then: make fpga\n"};
    case HlsTool::kVitis:
      break;
  }
  const VitisProject project = vitis_project(kernel);
  return {{{"run_hls.tcl", vitis_script(project), "the classic Vitis HLS flow (Tcl)"},
           {"hls_config.cfg", vitis_config(project),
            "the same project for Vitis Unified (2023.2 and later)"}},
          "vitis_hls -f run_hls.tcl   # classic Vitis HLS\n"
          "# Vitis Unified (2023.2 and later), from hls_config.cfg:\n" +
              vitis_unified_commands(project)};
}

// The host builds of the C simulation, one per type family, under the
// warnings a project's CI uses. GCC knows no `#pragma HLS` (nor Catapult's
// `#pragma hls_design`), hence -Wno-unknown-pragmas; GCC 12 -O2 reports a
// false uninitialised use inside Xilinx's ap_private.h, hence the two
// -Wno- of the ap_int.h line. docs/hls.md shows the same lines, and
// test_export_hls runs them.
constexpr std::string_view kHostBuilds =
    "g++ -std=c++14 -pedantic-errors -Wall -Wextra -Werror -Wno-unknown-pragmas -O2 "
    "-DODOLOC_HLS_TYPES=0 kernel.cpp kernel_test.cpp -o kernel_test\n"
    "g++ -std=c++14 -pedantic-errors -Wall -Wextra -Werror -Wno-unknown-pragmas -O2 "
    "-DODOLOC_HLS_TYPES=1 -isystem AP_TYPES/include -Wno-uninitialized -Wno-maybe-uninitialized "
    "kernel.cpp kernel_test.cpp -o kernel_test\n"
    "g++ -std=c++14 -pedantic-errors -Wall -Wextra -Werror -Wno-unknown-pragmas -O2 "
    "-DODOLOC_HLS_TYPES=2 -isystem AC_TYPES/include kernel.cpp kernel_test.cpp -o kernel_test\n";

std::string readme(const KernelDescription& kernel, HlsTool tool, const ToolFiles& flow) {
  std::string flow_rows;
  for (const FlowFile& file : flow.files)
    flow_rows += fmt::format("| `{}` | {} |\n", file.name, file.what);
  return fmt::format(
      "# odoloc HLS kernel `{0}`\n\n"
      "{1}. Top function `{2}`; one call = {3}. Bit-identical to the project's cycle model\n"
      "(rtl_model/), which made `golden_vectors.txt` ({4} calls).\n\n"
      "Written by `odoloc export-hls --tool {5}`; the sources are the project's `hls/`\n"
      "(docs/hls.md). Edit those and export again rather than editing this tree.\n\n"
      "## Files\n\n"
      "| file | what |\n|---|---|\n"
      "| `kernel.h` | the kernel: types, ports, registers, `step()`, the top's prototype |\n"
      "| `kernel.cpp` | the top function `{2}` with its interface pragmas |\n"
      "| `kernel_test.cpp` | C-simulation testbench: replays the golden vectors, returns 0 on "
      "success |\n"
      "| `golden_vectors.txt` | per call: the inputs, then the model's outputs |\n"
      "{6}\n"
      "## C simulation with a plain compiler\n\n"
      "`ODOLOC_HLS_TYPES` picks the integer types: 0 the project's own (in `kernel.h`, no\n"
      "other header needed), 1 Xilinx `ap_int.h`, 2 `ac_int.h`. Unset: the first found.\n"
      "AP_TYPES and AC_TYPES stand for your checkouts of the vendors' type headers.\n"
      "`-Wno-unknown-pragmas`: GCC does not know `#pragma HLS`. The ap_int.h line turns\n"
      "off a false uninitialised-use warning of GCC 12 inside `ap_private.h`.\n\n"
      "```sh\n"
      "{7}"
      "./kernel_test golden_vectors.txt   # PASS: ... calls, exit status 0\n"
      "```\n\n"
      "## {5}\n\n"
      "```sh\n{8}```\n\n"
      "## Interface (from the kernel's header)\n\n"
      "```text\n{9}```\n",
      kernel.name, kernel.summary, kernel.top, kernel.call, kernel.golden_calls, tool_name(tool),
      flow_rows, kHostBuilds, flow.how, interface_text(kernel));
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out)
    file_error(fmt::format("export-hls: cannot write {}", path.string()));
}

void check_stop(const std::atomic<bool>* stop) {
  if (stop != nullptr && stop->load())
    throw process::Interrupted();
}

ExportedTree write_tree(const KernelDescription& kernel, HlsTool tool, const fs::path& folder,
                        const std::atomic<bool>* stop) {
  std::error_code error;
  fs::create_directory(folder, error);
  if (error)
    file_error(fmt::format("export-hls: cannot create {}: {}", folder.string(), error.message()));
  const ToolFiles flow = tool_files(kernel, tool);
  std::vector<std::pair<std::string_view, std::function<std::string()>>> contents{
      {"kernel.h", [&] { return kernel_header(kernel); }},
      {"kernel.cpp", [&] { return kernel_source(kernel); }},
      {"kernel_test.cpp", [&] { return kernel_test(kernel); }},
      {kGoldenVectors, [&] { return golden_vectors(kernel); }},
  };
  for (const FlowFile& file : flow.files)
    contents.emplace_back(file.name, [&file] { return file.text; });
  contents.emplace_back("README.md", [&] { return readme(kernel, tool, flow); });
  ExportedTree tree{std::string(kernel.name), folder, {}, kernel.golden_calls};
  for (const auto& [name, text] : contents) {
    check_stop(stop);
    write_file(folder / name, text());
    tree.files.emplace_back(name);
  }
  return tree;
}

std::vector<const KernelDescription*> requested_kernels(const std::vector<std::string>& names) {
  std::vector<const KernelDescription*> chosen;
  if (names.empty()) {
    for (const KernelDescription& k : kernels())
      chosen.push_back(&k);
    return chosen;
  }
  for (const std::string& name : names) {
    const KernelDescription* k = find_kernel(name);
    if (k == nullptr) {
      std::vector<std::string_view> known;
      for (const KernelDescription& each : kernels())
        known.push_back(each.name);
      usage_error(fmt::format("export-hls: unknown kernel '{}'; the kernels are {}", name,
                              fmt::join(known, ", ")));
    }
    if (std::ranges::find(chosen, k) == chosen.end())
      chosen.push_back(k);
  }
  return chosen;
}

// A fresh folder next to (or, when OUT exists, inside) OUT, on the same file
// system, so moving a finished tree into place is a rename.
fs::path make_staging(const fs::path& out, bool out_exists) {
  const fs::path base = out_exists ? out : out.parent_path();
  std::random_device entropy;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const fs::path staging = base / fmt::format(".odoloc-export-{}-{:08x}", ::getpid(), entropy());
    std::error_code error;
    if (fs::create_directory(staging, error))
      return staging;
    if (error)
      usage_error(
          fmt::format("export-hls: cannot write in {}: {}", base.string(), error.message()));
  }
  file_error(fmt::format("export-hls: cannot create a staging folder in {}", base.string()));
}

}  // namespace

std::optional<HlsTool> parse_tool(std::string_view name) {
  for (std::size_t i = 0; i < kToolNames.size(); ++i)
    if (kToolNames[i] == name)
      return static_cast<HlsTool>(i);
  return std::nullopt;
}

std::string_view tool_name(HlsTool tool) {
  return kToolNames.at(static_cast<std::size_t>(tool));
}

std::string flatten(std::string_view key) {
  std::set<std::string, std::less<>> done;
  std::string out;
  flatten_into(key, done, out);
  return out;
}

std::vector<ExportedTree> export_hls(const ExportRequest& request, const std::atomic<bool>* stop) {
  const std::vector<const KernelDescription*> chosen = requested_kernels(request.kernels);
  if (request.out.empty())
    usage_error("export-hls: --out is empty");
  const fs::path out = fs::absolute(request.out).lexically_normal();
  std::error_code error;
  const fs::file_status status = fs::status(out, error);
  const bool out_exists = fs::exists(status);
  if (!out_exists && fs::is_symlink(fs::symlink_status(out, error)))
    usage_error(fmt::format("export-hls: {} is a symbolic link to {}, which does not exist",
                            out.string(), fs::read_symlink(out, error).string()));
  if (out_exists && !fs::is_directory(status))
    usage_error(fmt::format("export-hls: {} exists and is not a folder", out.string()));
  if (out_exists && !fs::is_empty(out, error) && !request.force)
    usage_error(fmt::format(
        "export-hls: {} is not empty; pass --force to replace the kernels' folders in it",
        out.string()));
  if (!out_exists && !fs::is_directory(out.parent_path(), error))
    usage_error(
        fmt::format("export-hls: the folder {} does not exist", out.parent_path().string()));

  if (out_exists && request.force) {
    for (const KernelDescription* kernel : chosen) {
      const fs::path target = out / std::string(kernel->name);
      if (fs::is_symlink(fs::symlink_status(target, error)))
        usage_error(fmt::format(
            "export-hls: {} is a symbolic link; --force replaces the kernels' folders, not what "
            "a link points at: remove the link or export elsewhere",
            target.string()));
    }
  }

  const fs::path staging = make_staging(out, out_exists);
  std::vector<ExportedTree> trees;
  try {
    for (const KernelDescription* kernel : chosen)
      trees.push_back(write_tree(*kernel, request.tool, staging / std::string(kernel->name), stop));
    check_stop(stop);
    if (!out_exists) {
      fs::rename(staging, out);
    } else {
      // Each finished tree replaces its old folder; the old ones go into the
      // staging folder, which is removed last.
      for (const KernelDescription* kernel : chosen) {
        const fs::path target = out / std::string(kernel->name);
        if (fs::exists(target))
          fs::rename(target, staging / fmt::format(".old-{}", kernel->name));
        fs::rename(staging / std::string(kernel->name), target);
      }
      fs::remove_all(staging);
    }
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(staging, error);
    file_error(fmt::format("export-hls: {}", e.what()));
  } catch (...) {
    fs::remove_all(staging, error);
    throw;
  }
  for (ExportedTree& tree : trees)
    tree.folder = out / tree.kernel;
  return trees;
}

}  // namespace odoloc::hls_export
