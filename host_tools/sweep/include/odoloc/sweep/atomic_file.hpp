// An output file that appears whole or not at all: written to a temporary
// file in the same directory, renamed over the path on commit().
#pragma once

#include <filesystem>
#include <fstream>
#include <string_view>

namespace odoloc::sweep {

class AtomicFile {
 public:
  // Creates the temporary (".NAME.XXXXXX" next to `path`). Throws
  // SweepError (usage) when it cannot: a missing or read-only directory,
  // `path` a directory.
  explicit AtomicFile(std::filesystem::path path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Removes the temporary unless committed.
  ~AtomicFile();

  [[nodiscard]] std::ostream& out() { return out_; }
  // Flushes and closes the temporary and renames it to the path, with the
  // permissions a new file gets (0666 less the umask). Throws SweepError
  // (not usage) when a write or the rename failed; the temporary is removed.
  void commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

// `content` into `path` through an AtomicFile.
void write_file(const std::filesystem::path& path, std::string_view content);

}  // namespace odoloc::sweep
