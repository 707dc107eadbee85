// Master side of the fabric's SPI frame (docs/spi.md), independent of the
// slave model: it is what firmware or a host runs over any full-duplex link.
//
//   MOSI: command[15:0] = {read, burst-1 [4:0], word address [9:0]}, n data
//         words (write data; don't care for reads), CRC-8 when enabled.
//   MISO: status byte of the previous frame, 0x00, n words (reads), CRC-8
//         over every MISO byte before it when enabled.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "odoloc/regs.hpp"
#include "odoloc/sw/register_bus.hpp"

namespace odoloc::sw {

inline constexpr unsigned kSpiMaxBurst = regs::spi::kMaxBurst;
inline constexpr unsigned kSpiHeaderBytes = 2;

// SAE J1850 CRC-8 (regs::spi: poly 0x1D, init 0xFF, final XOR 0xFF), byte-wise.
std::uint8_t crc8_j1850(std::span<const std::uint8_t> bytes);

enum class SpiOp : bool { kWrite = false, kRead = true };

// The MOSI bytes of one frame of `count` words (1..32). For a write `words`
// holds them; for a read it is ignored and zeros are sent.
std::vector<std::uint8_t> encode_frame(SpiOp op, std::uint16_t address, unsigned count,
                                       std::span<const std::uint32_t> words, bool crc);

struct FrameReply {
  std::uint8_t status = 0;  // error flags of the previous frame (top.spi_status bits)
  std::vector<std::uint32_t> words;
};

// Parses the MISO bytes of a frame of `count` words; throws BusError on a
// short reply or a CRC mismatch.
FrameReply decode_reply(std::span<const std::uint8_t> miso, unsigned count, bool crc);

// "crc_error|write_refused", or "none".
std::string describe_status(std::uint8_t status);

// One chip-select assertion, full duplex: miso.size() == mosi.size().
class SpiLink {
 public:
  SpiLink() = default;
  SpiLink(const SpiLink&) = delete;
  SpiLink& operator=(const SpiLink&) = delete;
  virtual ~SpiLink() = default;
  virtual void transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) = 0;
  // SPI mode 0 or 3 for the following frames.
  virtual void set_mode3(bool mode3) = 0;
};

// RegisterBus over SpiLink frames: bursts of at most 32 words, CRC when
// top.ctrl.crc_enable is on. The constructor reads top.ctrl to adopt the
// slave's CRC setting (a board may keep it from an earlier session), and
// writes to top.ctrl are followed, so the bus frames the way the slave
// expects from the next frame on. The SPI mode cannot be discovered: the
// link starts in mode 0. With
// confirm_writes, each write is followed by a one-word read of top.id whose
// status byte reports the write's fate; a refused or discarded write throws.
class SpiRegisterBus final : public RegisterBus {
 public:
  struct Options {
    bool crc = false;  // switch the slave's CRC on at construction if it is off
    bool confirm_writes = true;
  };
  SpiRegisterBus(SpiLink& link, Options options);
  using RegisterBus::read;
  using RegisterBus::write;
  void read(std::uint16_t address, std::span<std::uint32_t> words) override;
  void write(std::uint16_t address, std::span<const std::uint32_t> words) override;

  [[nodiscard]] bool crc() const { return crc_; }
  // Status byte of the last frame's reply (the frame before it).
  [[nodiscard]] std::uint8_t last_status() const { return last_status_; }

 private:
  FrameReply frame(SpiOp op, std::uint16_t address, unsigned count,
                   std::span<const std::uint32_t> words);
  void follow_ctrl(std::uint16_t address, std::span<const std::uint32_t> words);

  SpiLink& link_;
  bool crc_ = false;
  bool confirm_writes_;
  std::uint8_t last_status_ = 0;
};

}  // namespace odoloc::sw
