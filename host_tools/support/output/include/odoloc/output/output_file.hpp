// The files the tools write, whatever their path names:
// - a regular file, or a path that does not exist yet, appears whole or not
//   at all: the content goes to a temporary next to it, renamed over it on
//   commit() (the file keeps its permissions; a new one gets 0666 less the
//   umask);
// - a symbolic link is followed: the file it names is written as above and
//   the link stays; a link to nothing is refused;
// - a FIFO, a character or block device or a socket is written as a stream
//   at commit(), opened without O_CREAT: never replaced, never unlinked;
// - a folder is refused.
// Nothing is written to the path before commit(), so an error or an
// interruption (the object destroyed uncommitted) leaves it as it was.
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace odoloc::output {

// What went wrong, one line naming the path. usage(): the path cannot be
// written at all (a folder, a missing folder, no permission, a link to
// nothing), which the host tool reports with exit status 2; otherwise a
// write failed midway (exit 1).
class OutputError : public std::runtime_error {
 public:
  OutputError(bool usage, const std::string& what) : std::runtime_error(what), usage_(usage) {}
  [[nodiscard]] bool usage() const { return usage_; }

 private:
  bool usage_;
};

class OutputFile {
 public:
  // Decides what `path` is and, for a file, creates the temporary
  // (".NAME.XXXXXX" next to the file the path names). Throws OutputError
  // (usage) when the path cannot be written.
  explicit OutputFile(std::filesystem::path path);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  // Uncommitted: the temporary is removed, the path is untouched.
  ~OutputFile();

  [[nodiscard]] std::ostream& out();
  // A file: flushes the temporary and renames it over the file. A stream:
  // opens the path for writing and writes the content. Throws OutputError
  // (not usage) when a write, the rename or the open failed (a FIFO's open
  // waits for a reader; a signal ends the wait with this error).
  void commit();
  // Commits the content of the finished file `staged` (which is moved when
  // it can be, else copied) instead of what out() received.
  void commit_from(const std::filesystem::path& staged);
  // True when the path is a stream (FIFO, device, socket), not a file.
  [[nodiscard]] bool is_stream() const { return stream_; }

 private:
  void write_stream(std::istream& content);
  void rename_into_place(const std::filesystem::path& from);

  std::filesystem::path path_;    // as given, for messages
  std::filesystem::path target_;  // a file: the one the path names, links resolved
  std::filesystem::path temporary_;
  std::ofstream file_;
  std::ostringstream buffer_;  // a stream's content until commit()
  bool stream_ = false;
  bool committed_ = false;
};

// `content` into `path` through an OutputFile.
void write_file(const std::filesystem::path& path, std::string_view content);

// The folder an output's files go in (`--out DIR`): created when missing
// (with kParents its missing parents too, else the parent must exist),
// followed when a symbolic link to a folder; anything else there (a file, a
// device, a link to nothing) is refused with OutputError (usage). The
// folders it created are removed again when it is destroyed before keep()
// and they are still empty, so an interrupted run leaves no trace.
class OutputFolder {
 public:
  enum class Create { kFolder, kParents };
  explicit OutputFolder(std::filesystem::path path, Create create = Create::kFolder);
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  ~OutputFolder();
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  void keep() { kept_ = true; }

 private:
  void remove_created();

  std::filesystem::path path_;
  std::vector<std::filesystem::path> created_;  // outermost first
  bool kept_ = false;
};

// A private folder for files that are made first and delivered to their
// outputs at the end (by OutputFile::commit_from), created by mkdtemp as
// PARENT/.odoloc-PURPOSE-XXXXXX (mode 0700) and removed with all it holds
// when destroyed. Throws OutputError (usage) when it cannot be created.
class Staging {
 public:
  Staging(const std::filesystem::path& parent, std::string_view purpose);
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;
  ~Staging();
  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

}  // namespace odoloc::output
