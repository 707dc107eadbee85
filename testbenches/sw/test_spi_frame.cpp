// The SoC-side SPI frame codec and register bus, against the slave model's
// bit-serial CRC and against the frame layout of docs/spi.md.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "odoloc/regs.hpp"
#include "odoloc/rtl/spi_slave.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace {

using odoloc::sw::BusError;
using odoloc::sw::decode_reply;
using odoloc::sw::encode_frame;
using odoloc::sw::SpiOp;
using Bytes = std::vector<std::uint8_t>;
using Words = std::vector<std::uint32_t>;

TEST(SpiFrame, ByteWiseCrcMatchesTheSlavesBitSerialCrc) {
  const Bytes check{'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(odoloc::sw::crc8_j1850(check), 0x4B);  // the catalogued check value
  for (unsigned a = 0; a < 256; ++a) {
    const Bytes one{static_cast<std::uint8_t>(a)};
    ASSERT_EQ(odoloc::sw::crc8_j1850(one), odoloc::rtl::crc8_j1850(one)) << a;
    for (unsigned b = 0; b < 256; ++b) {
      const Bytes two{static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b)};
      ASSERT_EQ(odoloc::sw::crc8_j1850(two), odoloc::rtl::crc8_j1850(two)) << a << " " << b;
    }
  }
}

TEST(SpiFrame, CommandAndDataLayout) {
  const Words words{0x01234567U, 0x89ABCDEFU};
  const Bytes w = encode_frame(SpiOp::kWrite, 0x3A5, 2, words, false);
  // [15] write=0, [14:10] n-1 = 1, [9:0] 0x3A5
  EXPECT_EQ(w, (Bytes{0x07, 0xA5, 0x01, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD, 0xEF}));
  const Bytes r = encode_frame(SpiOp::kRead, 0x010, 32, {}, true);
  ASSERT_EQ(r.size(), 2U + 4U * 32U + 1U);
  EXPECT_EQ(r[0], 0x80 | 31 << 2);
  EXPECT_EQ(r[1], 0x10);
  EXPECT_EQ(r.back(), odoloc::sw::crc8_j1850(std::span(r).first(r.size() - 1)));
}

TEST(SpiFrame, BadBurstsAreRejected) {
  EXPECT_THROW((void)encode_frame(SpiOp::kRead, 0, 0, {}, false), BusError);
  EXPECT_THROW((void)encode_frame(SpiOp::kRead, 0, 33, {}, false), BusError);
  const Words one{1};
  EXPECT_THROW((void)encode_frame(SpiOp::kWrite, 0, 2, one, false), BusError);
  EXPECT_THROW((void)decode_reply(Bytes(5), 1, false), BusError);  // short
  EXPECT_THROW((void)decode_reply(Bytes(7), 1, false), BusError);  // long
}

// A reply with every single-bit error is caught by the CRC.
TEST(SpiFrame, RepliesDecodeAndEveryBitFlipIsCaught) {
  std::mt19937 rng(3);
  for (int round = 0; round < 20; ++round) {
    const unsigned n = 1 + rng() % 32;
    Bytes miso{static_cast<std::uint8_t>(rng() % 16), 0};
    Words words(n);
    for (auto& w : words) {
      w = static_cast<std::uint32_t>(rng());
      for (int shift = 24; shift >= 0; shift -= 8)
        miso.push_back(static_cast<std::uint8_t>(w >> shift));
    }
    miso.push_back(odoloc::sw::crc8_j1850(miso));
    const auto reply = decode_reply(miso, n, true);
    EXPECT_EQ(reply.words, words);
    EXPECT_EQ(reply.status, miso[0]);
    for (std::size_t bit = 0; bit < miso.size() * 8; ++bit) {
      Bytes bad = miso;
      bad[bit / 8] = static_cast<std::uint8_t>(bad[bit / 8] ^ (0x80U >> (bit % 8)));
      EXPECT_THROW((void)decode_reply(bad, n, true), BusError) << bit;
    }
  }
}

TEST(SpiFrame, StatusNamesComeFromTheRegisterMap) {
  namespace s = odoloc::regs::top::spi_status;
  EXPECT_EQ(odoloc::sw::describe_status(0), "none");
  EXPECT_EQ(odoloc::sw::describe_status(
                static_cast<std::uint8_t>(s::crc_error.mask() | s::overrun.mask())),
            "crc_error|overrun");
}

// Records frames and answers with zeros: shows how the bus splits bursts.
class RecordingLink final : public odoloc::sw::SpiLink {
 public:
  std::vector<Bytes> frames;
  void transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override {
    frames.emplace_back(mosi.begin(), mosi.end());
    std::fill(miso.begin(), miso.end(), 0);
  }
  void set_mode3(bool) override {}
};

TEST(SpiRegisterBus, LongTransfersSplitIntoBurstsOf32) {
  RecordingLink link;
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = false});
  ASSERT_EQ(link.frames.size(), 1U);  // the constructor reads top.ctrl
  EXPECT_EQ(link.frames[0][0] << 8 | link.frames[0][1], 0x8000 | odoloc::regs::top::ctrl::kAddress);
  link.frames.clear();
  Words words(70);
  bus.read(0x100, words);
  ASSERT_EQ(link.frames.size(), 3U);
  const auto command = [](const Bytes& f) { return f[0] << 8 | f[1]; };
  EXPECT_EQ(command(link.frames[0]), 0x8000 | 31 << 10 | 0x100);
  EXPECT_EQ(command(link.frames[1]), 0x8000 | 31 << 10 | 0x120);
  EXPECT_EQ(command(link.frames[2]), 0x8000 | 5 << 10 | 0x140);
  link.frames.clear();
  bus.write(0x010, words);
  ASSERT_EQ(link.frames.size(), 3U);
  EXPECT_EQ(command(link.frames[2]), 5 << 10 | 0x050);
}

// With confirmation the bus insists that top.id reads back.
TEST(SpiRegisterBus, ConfirmationNoticesABrokenLink) {
  RecordingLink link;  // answers zeros: top.id reads 0
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = true});
  EXPECT_THROW(bus.write(odoloc::regs::top::scratch::kAddress, 1), BusError);
}

}  // namespace
