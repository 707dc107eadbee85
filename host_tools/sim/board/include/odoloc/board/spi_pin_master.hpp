// Bit-level SPI master: drives the chip's SPI pins one fabric clock at a
// time. The sim target's link and the testbenches' bus-functional model.
//
// It produces the pin levels one fabric clock at a time and hands them to a
// step callback that clocks the DUT once and returns the MISO pin after that
// clock:
//
//   SpiPinMaster master({.half_period = 4, .mode3 = false});
//   const auto miso = master.transfer(sw::encode_frame(sw::SpiOp::kWrite, 0x004, 1, words, true),
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

namespace odoloc::board {

using rtl::UInt;

struct SpiMasterConfig {
  unsigned half_period = 4;  // fabric clocks per SCLK level
  bool mode3 = false;        // SCLK idles high
  unsigned idle_clocks = 8;  // cs_n high after a frame (the slave needs 3 to see the rise)
};

class SpiPinMaster {
 public:
  static constexpr std::size_t kNoAbort = std::numeric_limits<std::size_t>::max();

  explicit SpiPinMaster(SpiMasterConfig config) : config_(config) {}

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
  void set_mode3(bool mode3) { config_.mode3 = mode3; }

 private:
  SpiMasterConfig config_;
};

}  // namespace odoloc::board
