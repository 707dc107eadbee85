#include "odoloc/output/output_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <stdlib.h>  // mkstemp, mkdtemp
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

namespace odoloc::output {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void refuse(const fs::path& path, std::string_view why) {
  throw OutputError(true, fmt::format("cannot write {}: {}", path.string(), why));
}

[[noreturn]] void fail(const fs::path& path, std::string_view why) {
  throw OutputError(false, fmt::format("writing {} failed: {}", path.string(), why));
}

std::string errno_text(int error) {
  return error == EINTR ? std::string{"interrupted"} : std::string{std::strerror(error)};
}

mode_t new_file_mode() {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return 0666 & ~mask;
}

// What stat() (following links) says of `path`, or nullopt-like false with
// errno set.
bool status_of(const fs::path& path, struct stat& st) {
  return ::stat(path.c_str(), &st) == 0;
}

bool is_link(const fs::path& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode);
}

// A link to nothing: writing through it would create a file wherever it
// points (or fail), and replacing it would lose the link.
[[noreturn]] void refuse_dangling(const fs::path& path) {
  std::error_code ec;
  refuse(path, fmt::format("it is a symbolic link to {}, which does not exist",
                           fs::read_symlink(path, ec).string()));
}

}  // namespace

OutputFile::OutputFile(fs::path path) : path_(std::move(path)) {
  if (path_.empty())
    throw OutputError(true, "cannot write to an empty path");
  struct stat st {};
  mode_t mode = 0;
  if (status_of(path_, st)) {
    if (S_ISDIR(st.st_mode))
      refuse(path_, "it is a folder");
    if (!S_ISREG(st.st_mode)) {
      stream_ = true;
      return;
    }
    std::error_code ec;
    target_ = fs::canonical(path_, ec);
    if (ec)
      refuse(path_, ec.message());
    mode = st.st_mode & 07777;
  } else if (errno == ENOENT) {
    if (is_link(path_))
      refuse_dangling(path_);
    target_ = path_;
    mode = new_file_mode();
  } else {
    refuse(path_, errno_text(errno));
  }
  const fs::path dir = target_.has_parent_path() ? target_.parent_path() : fs::path{"."};
  std::string name = (dir / fmt::format(".{}.XXXXXX", target_.filename().string())).string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0 && errno == ENOENT)
    refuse(path_, fmt::format("the folder {} does not exist", dir.string()));
  if (fd < 0)
    refuse(path_, errno_text(errno));
  const int mode_set = ::fchmod(fd, mode);
  ::close(fd);
  temporary_ = name;
  file_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (mode_set != 0 || !file_) {
    std::error_code ec;
    fs::remove(temporary_, ec);
    refuse(path_, "cannot create a temporary file next to it");
  }
}

OutputFile::~OutputFile() {
  if (committed_ || temporary_.empty())
    return;
  file_.close();
  std::error_code ec;
  fs::remove(temporary_, ec);
}

std::ostream& OutputFile::out() {
  if (stream_)
    return buffer_;
  return file_;
}

void OutputFile::commit() {
  if (stream_) {
    std::istringstream content(std::move(buffer_).str());
    write_stream(content);
  } else {
    file_.close();
    if (!file_)
      fail(path_, "the temporary file could not be written");
    rename_into_place(temporary_);
  }
  committed_ = true;
}

void OutputFile::commit_from(const fs::path& staged) {
  std::ifstream in(staged, std::ios::binary);
  if (!in)
    fail(path_, fmt::format("cannot read {}", staged.string()));
  if (stream_) {
    write_stream(in);
    committed_ = true;
    return;
  }
  struct stat st {};
  if (::stat(temporary_.c_str(), &st) != 0)
    fail(path_, errno_text(errno));
  // The staged file takes the temporary's permissions and, on the same
  // file system, its place (no copy); elsewhere its bytes are copied.
  std::error_code ec;
  if (::chmod(staged.c_str(), st.st_mode & 07777) == 0 &&
      ::rename(staged.c_str(), target_.c_str()) == 0) {
    file_.close();
    fs::remove(temporary_, ec);
    temporary_.clear();
    committed_ = true;
    return;
  }
  file_ << in.rdbuf();
  commit();
}

void OutputFile::write_stream(std::istream& content) {
  // No O_CREAT: if the device or FIFO went away meanwhile, nothing is made
  // in its place.
  const int fd = ::open(path_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
  if (fd < 0)
    fail(path_, errno_text(errno));
  std::array<char, 1 << 16> chunk{};
  int error = 0;
  while (error == 0 && content) {
    content.read(chunk.data(), chunk.size());
    for (std::streamsize done = 0, n = content.gcount(); done < n;) {
      const ssize_t wrote = ::write(fd, chunk.data() + done, static_cast<std::size_t>(n - done));
      if (wrote < 0) {
        error = errno;
        break;
      }
      done += wrote;
    }
  }
  if (::close(fd) != 0 && error == 0)
    error = errno;
  if (error != 0)
    fail(path_, errno_text(error));
}

void OutputFile::rename_into_place(const fs::path& from) {
  if (::rename(from.c_str(), target_.c_str()) != 0) {
    const int error = errno;
    std::error_code ec;
    fs::remove(from, ec);
    fail(path_, errno_text(error));
  }
}

void write_file(const fs::path& path, std::string_view content) {
  OutputFile file(path);
  file.out() << content;
  file.commit();
}

OutputFolder::OutputFolder(fs::path path, Create create) : path_(std::move(path)) {
  if (path_.empty())
    throw OutputError(true, "cannot write to an empty folder name");
  // The missing folders, innermost first; the first existing one must be a
  // folder (or a link to one).
  std::vector<fs::path> missing;
  for (fs::path p = path_; !p.empty(); p = p.parent_path()) {
    struct stat st {};
    if (status_of(p, st)) {
      if (!S_ISDIR(st.st_mode))
        refuse(path_, p == path_ ? std::string{"it exists and is not a folder"}
                                 : fmt::format("{} is not a folder", p.string()));
      break;
    }
    if (errno != ENOENT)
      refuse(path_, errno_text(errno));
    if (is_link(p))
      refuse_dangling(p);
    missing.push_back(p);
    if (create == Create::kFolder)
      break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0) {
      const int error = errno;
      remove_created();
      refuse(path_, fmt::format("cannot create the folder: {}", errno_text(error)));
    }
    created_.push_back(*it);
  }
}

OutputFolder::~OutputFolder() {
  if (!kept_)
    remove_created();
}

void OutputFolder::remove_created() {
  // Only when empty: what a run delivered stays.
  for (auto it = created_.rbegin(); it != created_.rend(); ++it)
    ::rmdir(it->c_str());
  created_.clear();
}

Staging::Staging(const fs::path& parent, std::string_view purpose) {
  std::string name = (parent / fmt::format(".odoloc-{}-XXXXXX", purpose)).string();
  if (::mkdtemp(name.data()) == nullptr)
    throw OutputError(true, fmt::format("cannot create a staging folder in {}: {}", parent.string(),
                                        errno_text(errno)));
  dir_ = name;
}

Staging::~Staging() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace odoloc::output
