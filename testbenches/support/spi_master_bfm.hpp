// The testbenches' SPI bus-functional model: the sim target's pin-level
// master, with frames built by the SoC-side codec (an independent encoder).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "odoloc/board/spi_pin_master.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::tb {

using SpiMasterBfm = board::SpiPinMaster;
using board::SpiMasterConfig;
using sw::SpiOp;

// The MOSI bytes of one frame; for a read, words.size() sets the burst length.
inline std::vector<std::uint8_t> spi_frame(SpiOp op, unsigned address,
                                           std::span<const std::uint32_t> words, bool crc) {
  return sw::encode_frame(op, static_cast<std::uint16_t>(address),
                          static_cast<unsigned>(words.size()), words, crc);
}

}  // namespace odoloc::tb
