// sw::SpiLink over a Linux spidev device: one SPI_IOC_MESSAGE(1) per frame,
// full duplex, chip select held for the whole frame, 8-bit words, MSB first.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::cli {

class SpidevLink final : public sw::SpiLink {
 public:
  // Opens and configures the device (mode 0, 8 bits per word, speed_hz);
  // UsageError when it cannot be opened or configured.
  SpidevLink(std::string device, std::uint32_t speed_hz);
  ~SpidevLink() override;

  // sw::BusError when the transfer fails.
  void transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override;
  void set_mode3(bool mode3) override;

 private:
  void configure(unsigned long request, const void* value, const char* what);

  std::string device_;
  std::uint32_t speed_hz_;
  int fd_ = -1;
};

}  // namespace odoloc::cli
