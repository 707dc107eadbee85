#include "odoloc/sweep/atomic_file.hpp"

#include <fmt/format.h>
#include <stdlib.h>  // mkstemp
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "odoloc/sweep/error.hpp"

namespace odoloc::sweep {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)) {
  std::error_code ec;
  if (fs::is_directory(path_, ec))
    throw SweepError(true, fmt::format("cannot write {}: it is a directory", path_.string()));
  const fs::path dir = path_.has_parent_path() ? path_.parent_path() : fs::path{"."};
  std::string name = (dir / fmt::format(".{}.XXXXXX", path_.filename().string())).string();
  const int fd = ::mkstemp(name.data());
  if (fd < 0)
    throw SweepError(true,
                     fmt::format("cannot write {}: {}", path_.string(), std::strerror(errno)));
  // mkstemp makes the file 0600; the result should look like any new file.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  const int mode_set = ::fchmod(fd, 0666 & ~mask);
  ::close(fd);
  temporary_ = name;
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (mode_set != 0 || !out_) {
    fs::remove(temporary_, ec);
    throw SweepError(true, fmt::format("cannot write {}", path_.string()));
  }
}

AtomicFile::~AtomicFile() {
  if (committed_)
    return;
  out_.close();
  std::error_code ec;
  fs::remove(temporary_, ec);
}

void AtomicFile::commit() {
  out_.close();
  std::error_code ec;
  if (!out_) {
    fs::remove(temporary_, ec);
    throw SweepError(false, fmt::format("writing {} failed", path_.string()));
  }
  fs::rename(temporary_, path_, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(temporary_, ec);
    throw SweepError(false, fmt::format("cannot write {}: {}", path_.string(), why));
  }
  committed_ = true;
}

void write_file(const fs::path& path, std::string_view content) {
  AtomicFile file(path);
  file.out() << content;
  file.commit();
}

}  // namespace odoloc::sweep
