// Bit-level SPI master bus-functional model for testbenches.
//
// It produces the pin levels one fabric clock at a time and hands them to a
// step callback that clocks the DUT once and returns the MISO pin after that
// clock:
//
//   SpiMasterBfm master({.half_period = 4, .mode3 = false});
//   const auto miso = master.transfer(spi_frame(SpiOp::kWrite, 0x004, words, true),
//                                     [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
//                                       return bench.step(sclk, cs_n, mosi);
//                                     });
//
// Timing per bit: SCLK low for half_period clocks (MOSI changes at its start,
// i.e. after the falling edge), then high for half_period clocks. MISO is
// sampled on the rising edge: the value the pin had in the clock before SCLK
// rose. cs_n falls half_period clocks before the first SCLK edge and rises
// half_period clocks after the last; then cs_n stays high for idle_clocks.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace odoloc::tb {

using rtl::UInt;

struct SpiMasterConfig {
  unsigned half_period = 4;  // fabric clocks per SCLK level
  bool mode3 = false;        // SCLK idles high
  unsigned idle_clocks = 8;  // cs_n high after a frame (the slave needs 3 to see the rise)
};

enum class SpiOp : bool { kWrite = false, kRead = true };

// The MOSI bytes of one frame. For a read, words.size() sets the burst length
// and the words are sent as the don't-care data.
inline std::vector<std::uint8_t> spi_frame(SpiOp op, unsigned address,
                                           std::span<const std::uint32_t> words, bool crc) {
  const auto command =
      static_cast<std::uint16_t>((op == SpiOp::kRead ? 0x8000U : 0U) |
                                 ((words.size() - 1U) & 0x1FU) << 10U | (address & 0x3FFU));
  std::vector<std::uint8_t> bytes{static_cast<std::uint8_t>(command >> 8U),
                                  static_cast<std::uint8_t>(command)};
  for (const std::uint32_t w : words)
    for (int shift = 24; shift >= 0; shift -= 8)
      bytes.push_back(static_cast<std::uint8_t>(w >> shift));
  if (crc)
    bytes.push_back(rtl::crc8_j1850(bytes));
  return bytes;
}

class SpiMasterBfm {
 public:
  static constexpr std::size_t kNoAbort = std::numeric_limits<std::size_t>::max();

  explicit SpiMasterBfm(SpiMasterConfig config) : config_(config) {}

  // Runs one frame: bytes MSB first, cut after abort_after_bits rising edges
  // if given. Returns the MISO bits sampled, packed MSB first (a partial last
  // byte is left-aligned).
  template <class Step>
  std::vector<std::uint8_t> transfer(std::span<const std::uint8_t> bytes, Step&& step,
                                     std::size_t abort_after_bits = kNoAbort) {
    const std::size_t bits = std::min(bytes.size() * 8, abort_after_bits);
    const UInt<1> idle_sclk = UInt<1>::truncate(config_.mode3 ? 1 : 0);
    std::vector<std::uint8_t> miso_bytes((bits + 7) / 8, 0);
    UInt<1> miso{};
    const auto hold = [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi, unsigned clocks) {
      for (unsigned c = 0; c < clocks; ++c)
        miso = step(sclk, cs_n, mosi);
    };
    const auto mosi_bit = [&](std::size_t i) {
      return UInt<1>::truncate(static_cast<std::uint64_t>(bytes[i / 8] >> (7 - i % 8)));
    };
    hold(idle_sclk, UInt<1>{1}, UInt<1>{}, 1);
    hold(idle_sclk, UInt<1>{}, bits > 0 ? mosi_bit(0) : UInt<1>{}, config_.half_period);
    for (std::size_t i = 0; i < bits; ++i) {
      if (i > 0 || config_.mode3)
        hold(UInt<1>{}, UInt<1>{}, mosi_bit(i), config_.half_period);
      if (miso)
        miso_bytes[i / 8] = static_cast<std::uint8_t>(miso_bytes[i / 8] | 0x80U >> (i % 8));
      hold(UInt<1>{1}, UInt<1>{}, mosi_bit(i), config_.half_period);
    }
    hold(idle_sclk, UInt<1>{}, UInt<1>{}, config_.half_period);
    hold(idle_sclk, UInt<1>{1}, UInt<1>{}, config_.idle_clocks);
    return miso_bytes;
  }

  [[nodiscard]] const SpiMasterConfig& config() const { return config_; }

 private:
  SpiMasterConfig config_;
};

}  // namespace odoloc::tb
