// The TOF capture unit through the whole chip and the pin-level SPI master:
// registers reached by name (the generated map), comparator pulses on the
// chip's pins coming out of FIFO bursts, and the pop-on-read transaction: a
// completed read frame pops exactly the whole entries it read, an aborted or
// CRC-failed frame pops nothing, so no event is lost to a bad frame.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "register_by_path.hpp"

namespace {

namespace regs = odoloc::regs;
using odoloc::board::ChipLink;
using odoloc::board::SpiPinMaster;
using odoloc::rtl::UInt;
using odoloc::sw::SpiOp;
using odoloc::sw::SpiRegisterBus;
using Words = std::vector<std::uint32_t>;

using odoloc::tb::reg;
std::string channel_reg(unsigned channel, std::string_view name) {
  return "tof_channel." + std::string{regs::tof_channel::kInstanceNames[channel]} + "." +
         std::string{name};
}

// Pulses on the comparator pins: [rise, fall) in fabric clocks, per channel.
struct Pulse {
  unsigned channel;
  std::uint64_t rise, fall;
};

struct TofBench {
  std::vector<Pulse> pulses;
  std::uint64_t clock = 0;
  ChipLink link{{.half_period = 4}, [this](odoloc::rtl::ChipPins& pins) {
                  std::uint64_t levels = 0;
                  for (const Pulse& p : pulses)
                    if (clock >= p.rise && clock < p.fall)
                      levels |= std::uint64_t{1} << p.channel;
                  pins.comparators = decltype(pins.comparators)::truncate(levels);
                  ++clock;
                }};
  SpiRegisterBus bus{link, {.crc = false, .confirm_writes = true}};

  std::uint32_t read(std::string_view path) { return bus.read(reg(path).address); }
  void write(std::string_view path, std::uint32_t value) { bus.write(reg(path).address, value); }
  void arm(std::uint32_t channels) {
    write("tof.command", regs::tof::command::arm.set(0, channels));
  }
  // Entries in the FIFO (status alone: a frame that reads no entry pops none).
  unsigned level(unsigned channel) {
    return regs::tof_channel::status::fill_level.get(read(channel_reg(channel, "status")));
  }
  // status, events, 3 spare words, then the whole entry window, in one frame:
  // pops every entry present.
  Words read_channel(unsigned channel) {
    const std::uint16_t status = reg(channel_reg(channel, "status")).address;
    Words words(5 + 16);
    bus.read(status, words);
    return words;
  }
};

unsigned level_of(const Words& channel_words) {
  return regs::tof_channel::status::fill_level.get(channel_words[0]);
}
// Entry k's rise timestamp and width from a read_channel() burst.
std::uint32_t entry_ticks(const Words& w, unsigned k) {
  return w[5 + 2 * k];
}
std::uint32_t entry_high(const Words& w, unsigned k) {
  return w[5 + 2 * k + 1];
}

TEST(TofRegisters, InfoTellsTheBuild) {
  TofBench b;
  const std::uint32_t info = b.read("tof.info");
  EXPECT_EQ(regs::tof::info::channels.get(info), regs::tof_channel::kInstances);
  EXPECT_EQ(regs::tof::info::fifo_depth.get(info), 16U);
}

// Envelope pulses on three channels come out of the FIFO windows with the
// rise timestamps and widths the pins had (minus the constant latency), and
// a burst over the whole window pops exactly the entries present.
TEST(TofRegisters, EnvelopePulsesComeOutOfBursts) {
  TofBench b;
  b.arm(0b1011);
  const std::uint64_t t0 = b.clock + 1000;
  for (unsigned ch : {0U, 1U, 3U})
    for (unsigned p = 0; p < 3; ++p)
      b.pulses.push_back({ch, t0 + 5000 * p + 37 * ch, t0 + 5000 * p + 37 * ch + 1200 + 100 * p});
  b.link.advance(t0 + 20'000 - b.clock);
  const std::uint64_t latency = 3 + 2;  // filter_clocks reset 3: N + 2 (docs/tof-capture.md)
  const std::uint64_t ts_before = b.read("tof.timestamp");
  // The timestamp counts clocks (prescale 0) from reset: the chip's clock count.
  EXPECT_NEAR(static_cast<double>(ts_before), static_cast<double>(b.link.clocks()), 2000.0);
  // Timestamps are the chip's clock numbers; the stimulus counter starts at 0
  // with the chip, so rise + latency is the expected timestamp.
  for (unsigned ch : {0U, 1U, 3U}) {
    const Words w = b.read_channel(ch);
    ASSERT_EQ(level_of(w), 3U) << ch;
    for (unsigned p = 0; p < 3; ++p) {
      const Pulse& pulse = b.pulses[(ch == 3 ? 2 : ch) * 3 + p];
      EXPECT_EQ(entry_ticks(w, p), pulse.rise + latency) << ch << " " << p;
      EXPECT_EQ(regs::tof_channel::entry0_hi::width.get(entry_high(w, p)), pulse.fall - pulse.rise)
          << ch << " " << p;
      EXPECT_EQ(regs::tof_channel::entry0_hi::valid.get(entry_high(w, p)), 1U);
    }
    EXPECT_EQ(regs::tof_channel::entry0_hi::valid.get(entry_high(w, 3)), 0U);
    EXPECT_EQ(b.level(ch), 0U) << "the burst popped what it read, " << ch;
  }
  EXPECT_EQ(b.level(2), 0U) << "channel 2 was not armed";
}

// Read frames over the first entry cut after every bit count, or with a
// corrupted CRC, pop nothing; the completed frame pops one entry.
TEST(TofRegisters, BadReadFramesPopNothing) {
  TofBench b;
  b.arm(0b1);
  b.pulses.push_back({0, b.clock + 100, b.clock + 300});
  b.pulses.push_back({0, b.clock + 500, b.clock + 900});
  b.link.advance(2000);
  const std::uint16_t first = reg(channel_reg(0, "entry0_lo")).address;
  const auto frame = odoloc::sw::encode_frame(SpiOp::kRead, first, 2, {}, false);
  for (std::size_t bits = 0; bits < frame.size() * 8; ++bits) {
    b.link.transfer_bits(frame, bits);
    ASSERT_EQ(b.level(0), 2U) << "aborted after " << bits << " bits";
  }
  b.write("top.spi_status", 0xF);
  b.write("top.ctrl", regs::top::ctrl::crc_enable.mask());
  auto bad = odoloc::sw::encode_frame(SpiOp::kRead, first, 2, {}, true);
  bad.back() ^= 0x01;
  b.link.transfer_bits(bad, SpiPinMaster::kNoAbort);
  EXPECT_EQ(b.level(0), 2U) << "a CRC-failed frame popped";
  EXPECT_NE(b.read("top.spi_status") & regs::top::spi_status::crc_error.mask(), 0U);
  Words one(2);
  b.bus.read(first, one);  // a good frame over entry 0 only
  EXPECT_EQ(one[0], b.pulses[0].rise + 5);
  const Words after = b.read_channel(0);
  ASSERT_EQ(level_of(after), 1U);
  EXPECT_EQ(entry_ticks(after, 0), b.pulses[1].rise + 5);
}

// A frame that starts in the middle of the window, or reads only the low
// word of an entry, pops nothing: pops are whole entries from entry 0 on.
TEST(TofRegisters, OnlyWholeEntriesFromTheFirstPop) {
  TofBench b;
  b.arm(0b1);
  for (unsigned p = 0; p < 4; ++p)
    b.pulses.push_back({0, b.clock + 100 + 400 * p, b.clock + 300 + 400 * p});
  b.link.advance(3000);
  const std::uint16_t first = reg(channel_reg(0, "entry0_lo")).address;
  Words w(3);
  b.bus.read(first + 2, w);  // entry 1 and half of entry 2
  EXPECT_EQ(b.level(0), 4U);
  b.bus.read(first, std::span{w.data(), 1});  // half an entry
  EXPECT_EQ(b.level(0), 4U);
  b.bus.read(first, w);  // entry 0 and half of entry 1
  EXPECT_EQ(b.level(0), 3U);
}

// FIFO overflow through the registers: sticky w1c flag, dropped counter, and
// odometry.command.clear_flags clears it like every sticky flag.
TEST(TofRegisters, OverflowFlagAndCounterThroughRegisters) {
  TofBench b;
  b.write(channel_reg(0, "cfg"),
          regs::tof_channel::cfg::mode.set(
              0, static_cast<std::uint32_t>(regs::tof_channel::cfg::Mode::kCarrier)));
  b.arm(0b1);
  for (unsigned p = 0; p < 20; ++p)
    b.pulses.push_back({0, b.clock + 100 + 50 * p, b.clock + 125 + 50 * p});
  b.link.advance(2000);
  const std::uint32_t status = b.read(channel_reg(0, "status"));
  EXPECT_EQ(regs::tof_channel::status::overflow.get(status), 1U);
  EXPECT_EQ(regs::tof_channel::status::fill_level.get(status), 16U);
  EXPECT_EQ(regs::tof_channel::events::dropped.get(b.read(channel_reg(0, "events"))), 4U);
  b.write(channel_reg(0, "status"), regs::tof_channel::status::overflow.mask());
  EXPECT_EQ(regs::tof_channel::status::overflow.get(b.read(channel_reg(0, "status"))), 0U);
  b.pulses.push_back({0, b.clock + 100, b.clock + 125});
  b.link.advance(500);
  EXPECT_EQ(regs::tof_channel::status::overflow.get(b.read(channel_reg(0, "status"))), 1U);
  b.write("odometry.command", regs::odometry::command::clear_flags.mask());
  EXPECT_EQ(regs::tof_channel::status::overflow.get(b.read(channel_reg(0, "status"))), 0U);
  b.write("tof.command", regs::tof::command::flush.set(0, 1));
  EXPECT_EQ(b.read(channel_reg(0, "events")), 0U);
  EXPECT_EQ(regs::tof_channel::status::fill_level.get(b.read(channel_reg(0, "status"))), 0U);
}

}  // namespace
