// What the register bridge's two sides agree on beyond the message types
// (register_request_t, register_response_t; docs/lcm.md, "Register bridge"):
// the size limit of one request and the extent of a DUMP, both from the
// generated register map.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <limits>

#include "odoloc/regs.hpp"

namespace odoloc::bridge {

// Words one READ or WRITE may carry: 2 KiB of values, a few UDP fragments.
// Longer transfers are split by the client (LcmRegisterBus).
inline constexpr std::int32_t kMaxWords = 256;

// How long a client waits for the simulator's answer by default.
inline constexpr std::chrono::milliseconds kDefaultTimeout{2000};

// The largest register word, in the int64_t the messages carry words in.
inline constexpr std::int64_t kMaxWord = std::numeric_limits<std::uint32_t>::max();

// kMapped[a]: word address a is a register of the map.
inline constexpr std::array<bool, std::size_t{1} << regs::kAddressBits> kMapped = [] {
  std::array<bool, std::size_t{1} << regs::kAddressBits> mapped{};
  for (const regs::Register& r : regs::kRegisters)
    mapped[r.address] = true;
  return mapped;
}();

// A DUMP answers the words at addresses 0 … kDumpWords − 1: up to the
// highest register, unmapped addresses 0.
inline constexpr std::int32_t kDumpWords = [] {
  std::int32_t words = 0;
  for (const regs::Register& r : regs::kRegisters)
    words = r.address + 1 > words ? r.address + 1 : words;
  return words;
}();

}  // namespace odoloc::bridge
