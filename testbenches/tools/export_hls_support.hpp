// What test_export_hls and test_export_hls_config share: a per-process
// scratch folder, the real `odoloc` binary, the type families the vendor
// folder offers, and the host build lines of the C simulation as
// docs/hls.md documents them (the tests run the documented lines, so the
// documentation cannot drift from what was verified).
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "odoloc/process/run_program.hpp"
#include "scratch_files.hpp"

namespace odoloc::tb::export_hls {

namespace fs = std::filesystem;

// Per process (builds in other folders may run these tests at the same
// time), removed when the tests end.
inline fs::path scratch() {
  return fs::path(::testing::TempDir()) / fmt::format("odoloc_export_{}", ::getpid());
}
class RemoveScratch : public ::testing::Environment {
 public:
  void TearDown() override { fs::remove_all(scratch()); }
};
inline const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

inline fs::path fresh_folder(const std::string& name) {
  const fs::path folder = scratch() / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

inline process::ProgramResult odoloc_cli(const std::vector<std::string>& args,
                                         const fs::path& dir) {
  return process::run_program(ODOLOC_CLI, args, dir);
}

// A type family of the kernels (ODOLOC_HLS_TYPES) that can be built here.
struct Family {
  const char* name;
  int value;
  std::string placeholder;  // how docs/hls.md names the vendor's checkout
  std::string root;         // that checkout; empty for the project's own types
};

inline std::vector<Family> families() {
  std::vector<Family> list{{"own", 0, "", ""}};
  const fs::path vendor = ODOLOC_VENDOR_DIR;
  if (fs::exists(vendor / "ap_types/include/ap_int.h"))
    list.push_back({"ap", 1, "AP_TYPES", (vendor / "ap_types").string()});
  if (fs::exists(vendor / "ac_types/include/ac_int.h"))
    list.push_back({"ac", 2, "AC_TYPES", (vendor / "ac_types").string()});
  return list;
}

// The distinct lines of docs/hls.md that start with "g++ ": the host builds
// of a tree's C simulation, one per family (the example that test_cli_docs
// runs repeats the first).
inline std::vector<std::string> documented_host_builds() {
  std::istringstream lines(slurp(fs::path(ODOLOC_SOURCE_DIR) / "docs/hls.md"));
  std::vector<std::string> builds;
  for (std::string line; std::getline(lines, line);) {
    const auto start = line.find_first_not_of(' ');
    if (start != std::string::npos && line.compare(start, 4, "g++ ") == 0 &&
        std::ranges::find(builds, line.substr(start)) == builds.end())
      builds.push_back(line.substr(start));
  }
  return builds;
}

// The documented build of `family`, the vendor's checkout filled in; fails
// the test when docs/hls.md has none or several.
inline std::string documented_host_build(const Family& family) {
  const std::string types = fmt::format("-DODOLOC_HLS_TYPES={} ", family.value);
  std::vector<std::string> found;
  for (const std::string& line : documented_host_builds())
    if (line.find(types) != std::string::npos)
      found.push_back(line);
  EXPECT_EQ(found.size(), 1U) << "docs/hls.md: the g++ lines with " << types;
  if (found.empty())
    return "false";
  std::string command = found.front();
  if (!family.placeholder.empty()) {
    const auto at = command.find(family.placeholder);
    EXPECT_NE(at, std::string::npos) << command;
    if (at != std::string::npos)
      command.replace(at, family.placeholder.size(), fmt::format("'{}'", family.root));
  }
  return command;
}

}  // namespace odoloc::tb::export_hls
