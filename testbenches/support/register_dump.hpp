// Every register of a block, flattened through its trace() (which is derived
// from the register structs' field lists, so it names every register): for
// comparing two models clock by clock and for naming the first difference.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/rtl/bits.hpp"

namespace odoloc::tb {

struct RegisterDump {
  std::vector<std::string> names;  // dotted paths; filled only when asked for
  std::vector<std::uint64_t> values;
  bool with_names = false;

  std::string scope;
  void enter(std::string_view name) {
    if (with_names)
      scope += std::string(name) + ".";
  }
  void leave() {
    if (!with_names)
      return;
    scope.pop_back();
    scope.erase(scope.rfind('.') == std::string::npos ? 0 : scope.rfind('.') + 1);
  }
  template <int W>
  void signal(std::string_view name, rtl::UInt<W> v) {
    record(name, v.value());
  }
  template <int W>
  void signal(std::string_view name, rtl::SInt<W> v) {
    record(name, v.raw_bits());
  }
  void record(std::string_view name, std::uint64_t bits) {
    if (with_names)
      names.push_back(scope + std::string(name));
    values.push_back(bits);
  }
};

template <class Block>
RegisterDump dump_registers(const Block& block, bool with_names = false) {
  RegisterDump d;
  d.with_names = with_names;
  block.trace(d);
  return d;
}

// "" when equal, else the first differing register's path and both values.
template <class Block>
std::string first_difference(const Block& a, const Block& b) {
  const RegisterDump da = dump_registers(a), db = dump_registers(b);
  if (da.values == db.values)
    return {};
  const RegisterDump named = dump_registers(a, true);
  for (std::size_t i = 0; i < da.values.size(); ++i)
    if (da.values[i] != db.values[i])
      return named.names[i] + ": " + std::to_string(da.values[i]) + " vs " +
             std::to_string(db.values[i]);
  return "different register counts";
}

}  // namespace odoloc::tb
