// The one door from the SoC software to the fabric: word reads and writes at
// register addresses (odoloc/regs.hpp). A simulator, a Linux spidev device or
// a remote link implements it; nothing above it knows which.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

namespace odoloc::sw {

// A transfer the fabric or the link reported as failed; nothing was written.
class BusError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RegisterBus {
 public:
  RegisterBus() = default;
  RegisterBus(const RegisterBus&) = delete;
  RegisterBus& operator=(const RegisterBus&) = delete;
  virtual ~RegisterBus() = default;

  // words.size() consecutive words from `address` on (auto-increment).
  virtual void read(std::uint16_t address, std::span<std::uint32_t> words) = 0;
  // Throws BusError if the fabric refused or discarded any of the words.
  virtual void write(std::uint16_t address, std::span<const std::uint32_t> words) = 0;

  std::uint32_t read(std::uint16_t address) {
    std::uint32_t word = 0;
    read(address, std::span{&word, 1});
    return word;
  }
  void write(std::uint16_t address, std::uint32_t word) { write(address, std::span{&word, 1}); }
};

}  // namespace odoloc::sw
