// Scratch folders and whole-file reads for tests that run tools on files.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

namespace odoloc::tb {

// An empty folder under the test's temporary directory, named after the
// process, `prefix` and `tag` (removed first if a former run left it).
inline std::filesystem::path fresh_dir(std::string_view prefix, std::string_view tag) {
  const std::filesystem::path dir = std::filesystem::path{::testing::TempDir()} /
                                    fmt::format("{}_{}_{}", prefix, ::getpid(), tag);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The file's bytes; empty when it cannot be read.
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace odoloc::tb
