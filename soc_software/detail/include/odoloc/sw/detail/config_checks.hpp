// Configuration checks shared by the SoC software's option and config
// structs: one message form, "<Owner>: <what>", thrown as
// std::invalid_argument. Private to soc_software/src.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>

namespace odoloc::sw::detail {

inline void require(bool ok, std::string_view owner, std::string_view what) {
  if (!ok)
    throw std::invalid_argument(std::string(owner) + ": " + std::string(what));
}
inline bool finite_positive(double v) {
  return std::isfinite(v) && v > 0;
}
inline bool finite_non_negative(double v) {
  return std::isfinite(v) && v >= 0;
}

}  // namespace odoloc::sw::detail
