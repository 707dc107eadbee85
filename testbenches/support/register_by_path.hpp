// A register of the generated map by its path ("tof_channel.rx0.status"):
// testbenches name registers as users do, and a typo fails loudly.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "odoloc/regs.hpp"

namespace odoloc::tb {

inline const regs::Register& reg(std::string_view path) {
  const regs::Register* r = regs::find(path);
  if (r == nullptr)
    throw std::invalid_argument("no register " + std::string{path});
  return *r;
}

}  // namespace odoloc::tb
