// libFuzzer target: arbitrary SPI traffic into the whole chip, at the pins.
//
// Input: a sequence of operations, each chosen by one byte.
//   0xxx cxxx  a frame of arbitrary MOSI bytes through the pin-level master:
//              half period 1 + (op & 7) clocks (below 4 the slave must flag
//              overrun), SPI mode from bit 4 of the op, cut after a 16-bit bit
//              count when bit 3 is set; then a length byte and the bytes.
//   1xxx xxxx  raw pins for op & 0x3F steps: each byte holds sclk, cs_n,
//              mosi in bits 0-2 and 1 + (byte >> 3) clocks to hold them.
// The encoder pins never move, so the position registers must stay at 0
// whatever SPI does: read-only registers never change through SPI. After
// every operation the register file keeps only writable bits, and at the
// end a well-formed write and read at a legal speed must work.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace {

namespace regs = odoloc::regs;
using odoloc::board::ChipLink;
using odoloc::board::SpiPinMaster;
using odoloc::rtl::UInt;

void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n", what);
    std::abort();
  }
}

class Input {
 public:
  explicit Input(std::span<const std::uint8_t> data) : data_(data) {}
  [[nodiscard]] bool empty() const { return pos_ >= data_.size(); }
  std::uint8_t byte() { return empty() ? 0 : data_[pos_++]; }
  std::span<const std::uint8_t> bytes(std::size_t n) {
    n = std::min(n, data_.size() - std::min(pos_, data_.size()));
    const auto out = data_.subspan(pos_, n);
    pos_ += n;
    return out;
  }

 private:
  std::span<const std::uint8_t> data_;
  std::size_t pos_ = 0;
};

void check_invariants(const ChipLink& link) {
  const auto& fabric = link.chip().fabric();
  for (std::size_t w = 0; w < odoloc::rtl::kEncoderCount; ++w) {
    const auto& e = fabric.encoders().eppm(static_cast<odoloc::rtl::Encoder>(w));
    require(e.counter().count.is_zero() && e.counter().latched.is_zero(), "count moved");
    require((e.counter().carry | e.counter().borrow | e.decoder().phase_error).is_zero(),
            "position flags set");
    require(e.decoder().error_count.is_zero(), "error count moved");
  }
  for (const regs::Register& r : regs::kRegisters)
    require(
        (link.chip().registers().stored_word(r.address).value() & ~std::uint64_t{r.rw_mask}) == 0,
        "a stored word holds a non-writable bit");
}

// Back to a known framing, then a write and a read at a legal speed.
void check_next_frame_works(ChipLink& link) {
  const bool mode3 = link.chip().config().top.ctrl.spi_mode3.value() != 0;
  link.master() = SpiPinMaster({.half_period = 4, .mode3 = mode3});
  link.advance(16);
  const std::uint32_t plain = 0;
  const bool crc = link.chip().config().top.ctrl.crc_enable.value() != 0;
  link.transfer_bits(odoloc::sw::encode_frame(odoloc::sw::SpiOp::kWrite, regs::top::ctrl::kAddress,
                                              1, std::span{&plain, 1}, crc),
                     SpiPinMaster::kNoAbort);
  link.set_mode3(false);
  require(link.chip().config().top.ctrl.crc_enable.is_zero(), "ctrl write failed");
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = true});
  bus.write(regs::top::scratch::kAddress, 0x5EED1234U);  // throws (and aborts) on failure
  require(bus.read(regs::top::scratch::kAddress) == 0x5EED1234U, "scratch did not read back");
  require(bus.read(regs::top::id::kAddress) == regs::top::id::kReset, "id changed");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ChipLink link({.half_period = 4});
  Input in({data, size});
  while (!in.empty()) {
    const std::uint8_t op = in.byte();
    if ((op & 0x80U) == 0) {
      link.master() = SpiPinMaster({.half_period = 1U + (op & 7U), .mode3 = (op & 0x10U) != 0});
      std::size_t cut = SpiPinMaster::kNoAbort;
      if ((op & 0x08U) != 0)
        cut = static_cast<std::size_t>(in.byte()) << 8U | in.byte();
      const std::size_t length = in.byte() % 140U;
      const auto mosi = in.bytes(length);
      link.transfer_bits(std::vector<std::uint8_t>(mosi.begin(), mosi.end()), cut);
    } else {
      for (unsigned step = 0; step < (op & 0x3FU) && !in.empty(); ++step) {
        const std::uint8_t pins = in.byte();
        for (unsigned c = 0; c < 1U + (pins >> 3U); ++c)
          link.clock(UInt<1>::truncate(pins), UInt<1>::truncate(pins >> 1U),
                     UInt<1>::truncate(pins >> 2U));
      }
      link.advance(8);
    }
    check_invariants(link);
  }
  check_next_frame_works(link);
  check_invariants(link);
  return 0;
}
