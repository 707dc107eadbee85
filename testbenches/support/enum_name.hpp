// The name the register map gives a field's value; a test failure when the
// value is no enumerator of the field.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "odoloc/regs.hpp"

namespace odoloc::tb {

inline std::string enum_name(const regs::Field& f, std::uint32_t value) {
  for (const regs::Enumerator& e : f.enums) {
    if (e.value == value)
      return std::string{e.name};
  }
  ADD_FAILURE() << "no enumerator " << value << " in " << f.name;
  return {};
}

}  // namespace odoloc::tb
