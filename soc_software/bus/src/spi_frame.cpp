#include "odoloc/sw/spi_frame.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "odoloc/regs.hpp"

namespace odoloc::sw {
namespace {

constexpr std::uint8_t kPoly = regs::spi::kCrcPolynomial, kInit = regs::spi::kCrcInit,
                       kXorOut = regs::spi::kCrcXorOut;
constexpr unsigned kWordBytes = 4;
constexpr std::uint16_t kReadBit = 0x8000;
constexpr unsigned kBurstShift = 10;
constexpr std::uint16_t kAddressMask = (1U << regs::kAddressBits) - 1U;

std::size_t frame_bytes(unsigned count, bool crc) {
  return kSpiHeaderBytes + kWordBytes * count + (crc ? 1U : 0U);
}

void check_count(unsigned count) {
  if (count < 1 || count > kSpiMaxBurst)
    throw BusError("SPI burst of " + std::to_string(count) + " words: must be 1.." +
                   std::to_string(kSpiMaxBurst));
}

}  // namespace

std::uint8_t crc8_j1850(std::span<const std::uint8_t> bytes) {
  std::uint8_t crc = kInit;
  for (const std::uint8_t byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit)
      crc = static_cast<std::uint8_t>((crc & 0x80U) != 0 ? (crc << 1U) ^ kPoly : crc << 1U);
  }
  return static_cast<std::uint8_t>(crc ^ kXorOut);
}

std::vector<std::uint8_t> encode_frame(SpiOp op, std::uint16_t address, unsigned count,
                                       std::span<const std::uint32_t> words, bool crc) {
  check_count(count);
  if (op == SpiOp::kWrite && words.size() != count)
    throw BusError("SPI write frame of " + std::to_string(count) + " words given " +
                   std::to_string(words.size()));
  const auto command =
      static_cast<std::uint16_t>((op == SpiOp::kRead ? kReadBit : 0U) |
                                 (count - 1U) << kBurstShift | (address & kAddressMask));
  std::vector<std::uint8_t> bytes;
  bytes.reserve(frame_bytes(count, crc));
  bytes.push_back(static_cast<std::uint8_t>(command >> 8U));
  bytes.push_back(static_cast<std::uint8_t>(command));
  for (unsigned k = 0; k < count; ++k) {
    const std::uint32_t w = op == SpiOp::kWrite ? words[k] : 0U;
    for (int shift = 24; shift >= 0; shift -= 8)
      bytes.push_back(static_cast<std::uint8_t>(w >> static_cast<unsigned>(shift)));
  }
  if (crc)
    bytes.push_back(crc8_j1850(bytes));
  return bytes;
}

FrameReply decode_reply(std::span<const std::uint8_t> miso, unsigned count, bool crc) {
  check_count(count);
  if (miso.size() != frame_bytes(count, crc))
    throw BusError("SPI reply of " + std::to_string(miso.size()) + " bytes, expected " +
                   std::to_string(frame_bytes(count, crc)));
  const std::size_t body = miso.size() - (crc ? 1U : 0U);
  if (crc && crc8_j1850(miso.first(body)) != miso[body])
    throw BusError("SPI reply CRC mismatch: the read data is corrupt");
  FrameReply reply{miso[0], {}};
  reply.words.reserve(count);
  for (std::size_t i = kSpiHeaderBytes; i < body; i += kWordBytes) {
    std::uint32_t w = 0;
    for (std::size_t b = 0; b < kWordBytes; ++b)
      w = w << 8U | miso[i + b];
    reply.words.push_back(w);
  }
  return reply;
}

std::string describe_status(std::uint8_t status) {
  std::string out;
  for (const regs::Field& f : regs::top::spi_status::kFields) {
    if (f.get(status) == 0)
      continue;
    if (!out.empty())
      out += '|';
    out += f.name;
  }
  return out.empty() ? "none" : out;
}

SpiRegisterBus::SpiRegisterBus(SpiLink& link, Options options)
    : link_(link), confirm_writes_(options.confirm_writes) {
  // Adopt the slave's framing: a read without CRC returns its data even when
  // the slave expects a CRC (that frame is then flagged bad_length).
  const std::uint32_t ctrl = read(regs::top::ctrl::kAddress);
  crc_ = regs::top::ctrl::crc_enable.get(ctrl) != 0;
  if (options.crc && !crc_)
    write(regs::top::ctrl::kAddress, regs::top::ctrl::crc_enable.set(ctrl, 1));
}

FrameReply SpiRegisterBus::frame(SpiOp op, std::uint16_t address, unsigned count,
                                 std::span<const std::uint32_t> words) {
  const std::vector<std::uint8_t> mosi = encode_frame(op, address, count, words, crc_);
  std::vector<std::uint8_t> miso(mosi.size());
  link_.transfer(mosi, miso);
  FrameReply reply = decode_reply(miso, count, crc_);
  last_status_ = reply.status;
  return reply;
}

void SpiRegisterBus::read(std::uint16_t address, std::span<std::uint32_t> words) {
  for (std::size_t done = 0; done < words.size();) {
    const auto count =
        static_cast<unsigned>(std::min<std::size_t>(kSpiMaxBurst, words.size() - done));
    const FrameReply reply =
        frame(SpiOp::kRead, static_cast<std::uint16_t>(address + done), count, {});
    std::ranges::copy(reply.words, words.begin() + static_cast<std::ptrdiff_t>(done));
    done += count;
  }
}

void SpiRegisterBus::write(std::uint16_t address, std::span<const std::uint32_t> words) {
  for (std::size_t done = 0; done < words.size();) {
    const auto count =
        static_cast<unsigned>(std::min<std::size_t>(kSpiMaxBurst, words.size() - done));
    const auto start = static_cast<std::uint16_t>(address + done);
    const std::span<const std::uint32_t> burst = words.subspan(done, count);
    frame(SpiOp::kWrite, start, count, burst);
    const bool crc_before = crc_;
    follow_ctrl(start, burst);
    if (confirm_writes_) {
      const FrameReply probe = frame(SpiOp::kRead, regs::top::id::kAddress, 1, {});
      if (probe.status != 0 || probe.words[0] != regs::top::id::kReset) {
        crc_ = crc_before;
        throw BusError(fmt::format(
            "SPI write of {} word(s) at 0x{:03x} failed: {}", count, start,
            probe.status != 0 ? describe_status(probe.status) : "top.id does not read back"));
      }
    }
    done += count;
  }
}

void SpiRegisterBus::follow_ctrl(std::uint16_t address, std::span<const std::uint32_t> words) {
  const std::size_t ctrl = static_cast<std::uint16_t>(regs::top::ctrl::kAddress - address);
  if (ctrl >= words.size())
    return;
  crc_ = regs::top::ctrl::crc_enable.get(words[ctrl]) != 0;
  link_.set_mode3(regs::top::ctrl::spi_mode3.get(words[ctrl]) != 0);
}

}  // namespace odoloc::sw
