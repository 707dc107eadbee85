// Scratch folders and whole-file reads for tests that run tools on files.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

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

// True when `path` itself (not what a link names) is of `kind` (S_IFREG,
// S_IFLNK, S_IFIFO, S_IFCHR, ...).
inline bool is_kind(const std::filesystem::path& path, mode_t kind) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 && (st.st_mode & S_IFMT) == kind;
}

// The names in a folder, sorted: to show that nothing else was left there.
inline std::vector<std::string> entries(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const std::filesystem::directory_entry& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::ranges::sort(names);
  return names;
}

}  // namespace odoloc::tb
