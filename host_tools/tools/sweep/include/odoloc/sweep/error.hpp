// The one error kind of the sweep library.
#pragma once

#include <stdexcept>
#include <string>

#include "odoloc/output/output_file.hpp"

namespace odoloc::sweep {

// What went wrong, in one line that names the file and, where there is one,
// the line and key ("bump.yaml:7: grid: bump_height_m: ..."). usage(): the
// input is wrong (a spec, a shard file, a --shard value, a set of shard
// files that do not make one run, an output that cannot be created), which
// the host tool reports with exit status 2; otherwise a write failed midway
// (exit 1). Either way no partial output file is left behind.
class SweepError : public std::runtime_error {
 public:
  SweepError(bool usage, const std::string& what) : std::runtime_error(what), usage_(usage) {}
  [[nodiscard]] bool usage() const { return usage_; }

 private:
  bool usage_;
};

// Runs `body`, turning the output layer's errors (output::OutputError: a
// path that cannot be written, a write that failed) into SweepError.
template <class F>
auto writing(F&& body) {
  try {
    return body();
  } catch (const output::OutputError& e) {
    throw SweepError(e.usage(), e.what());
  }
}

}  // namespace odoloc::sweep
