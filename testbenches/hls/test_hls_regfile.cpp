// The SPI register file kernel (hls/regfile_kernel.hpp) against the cycle
// model (rtl::SpiSlave + rtl::FabricRegisters driven at pin level), compiled
// once per type family:
// - under the reference's seeded stimulus (host_tools/verification/src/
//   regfile_reference.cpp: reads, writes and bursts everywhere, refused
//   writes, w1c/w1p strobes, rc and rpop reads, cut, long, too fast and
//   CRC-corrupted frames, resets) every output of every transaction equals
//   the model's; every kernel register is an output (config words, the
//   slave's status, top.spi_status, top.frame_errors), so this covers them;
// - directed transactions check the documented behaviour (docs/spi.md,
//   docs/register-map.md) against values written out from the docs and the
//   generated register map, not from the model.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "hls_kernel_check.hpp"
#include "odoloc/hls/regfile_kernel.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace {

namespace hr = odoloc::hls::regfile;
namespace regs = odoloc::regs;
using odoloc::hls::to_s64;

constexpr int kHeader = 16;
constexpr int kWord = 32;
constexpr int kCrc = 8;

// A frame as the master sends it; `bits` < 0: the exact length (with the CRC
// byte when `crc`).
struct Frame {
  bool read = false;
  unsigned address = 0;
  std::vector<std::uint32_t> words;  // writes: the data; reads: one 0 per word
  bool crc = false;
  int bits = -1;
  bool corrupt_crc = false;
  bool overrun = false;
};

hr::Inputs inputs(const Frame& f) {
  hr::Inputs in;
  const auto count = static_cast<unsigned>(f.words.size());
  const std::uint32_t command = (f.read ? 0x8000U : 0U) | (count - 1) << 10 | f.address;
  in.command = command;
  std::vector<std::uint8_t> bytes{static_cast<std::uint8_t>(command >> 8),
                                  static_cast<std::uint8_t>(command)};
  for (unsigned k = 0; k < count; ++k) {
    in.data[k].value = f.words[k];
    for (int b = 24; b >= 0; b -= 8)
      bytes.push_back(static_cast<std::uint8_t>(f.words[k] >> b));
  }
  const std::uint8_t crc = odoloc::rtl::crc8_j1850(bytes);
  in.crc = f.corrupt_crc ? crc ^ 0x01U : crc;
  in.bits = f.bits >= 0 ? f.bits : kHeader + kWord * static_cast<int>(count) + (f.crc ? kCrc : 0);
  in.overrun = f.overrun ? 1 : 0;
  return in;
}

// The kernel with the fabric's status all 0 unless set.
struct Bench {
  hr::Registers regs;
  hr::Outputs out;
  hr::Inputs status_only;  // only its status words are used
  const hr::Outputs& run(const Frame& f) {
    hr::Inputs in = inputs(f);
    for (int k = 0; k < hr::kStatusWords; ++k)
      in.status[k] = status_only.status[k];
    hr::step(regs, in, out);
    return out;
  }
  std::uint32_t read(unsigned address, bool crc = false) {
    return static_cast<std::uint32_t>(to_s64(
        run({.read = true, .address = address, .words = {0}, .crc = crc}).miso_data[0].value));
  }
  void write(unsigned address, std::uint32_t word, bool crc = false) {
    run({.address = address, .words = {word}, .crc = crc});
  }
};

int slot(int bank, unsigned address) {
  return hr::kLayout.slot[bank][hr::kLayout.register_at[address]];
}
std::uint32_t config(const hr::Outputs& out, unsigned address) {
  return static_cast<std::uint32_t>(to_s64(out.config[slot(hr::kStored, address)].value));
}
std::uint32_t pulse(const hr::Outputs& out, unsigned address) {
  return static_cast<std::uint32_t>(to_s64(out.pulse[slot(hr::kPulse, address)].value));
}
long long status_byte(const hr::Outputs& out) {
  return to_s64(out.miso_header) >> 8;
}

constexpr unsigned kRefused = regs::top::spi_status::write_refused.mask();
constexpr unsigned kBadLength = regs::top::spi_status::bad_length.mask();
constexpr unsigned kCrcError = regs::top::spi_status::crc_error.mask();
constexpr unsigned kOverrunFlag = regs::top::spi_status::overrun.mask();

TEST(HlsRegfile, EveryOutputEqualsTheModelEveryTransaction) {
  const auto check = odoloc::tb::check_kernel<hr::Inputs, hr::Outputs, hr::Registers>(
      "regfile", 12, odoloc::tb::hls_calls(30000), hr::step);
  EXPECT_EQ(check.names_error, "");
  EXPECT_GT(check.calls, 0U);
  EXPECT_EQ(check.mismatches, 0U) << check.first_mismatch;
}

// Reset: every configuration word holds the map's reset, every register reads
// its stored and constant bits (the status all 0), top.id its constant.
TEST(HlsRegfile, ResetValuesAreTheMapsAndReadBack) {
  Bench b;
  b.run({.address = regs::top::scratch::kAddress, .words = {0x12345678U}});
  hr::Inputs reset;
  reset.reset = 1;
  hr::step(b.regs, reset, b.out);
  for (const regs::Register& r : regs::kRegisters) {
    if (r.rw_mask != 0) {
      EXPECT_EQ(config(b.out, r.address), r.reset & r.rw_mask) << r.path;
    }
  }
  for (unsigned start = 0; start < 1024; start += 32) {
    const hr::Outputs& out =
        b.run({.read = true, .address = start, .words = std::vector<std::uint32_t>(32)});
    for (unsigned k = 0; k < 32; ++k) {
      const regs::Register* r = regs::find(start + k);
      const std::uint32_t want =
          r == nullptr || r->snapshot ? 0 : r->reset & (r->rw_mask | r->const_mask);
      EXPECT_EQ(to_s64(out.miso_data[k].value), want) << start + k;
    }
  }
  EXPECT_EQ(b.read(regs::top::id::kAddress), regs::top::id::kReset);
}

// A write burst over a read-only register lands its other words and sets
// write_refused, reported in the next frame's status byte and counted.
TEST(HlsRegfile, RefusedWordsAreDroppedTheOthersLand) {
  Bench b;
  const unsigned scratch = regs::top::scratch::kAddress;
  const hr::Outputs& out = b.run({.address = regs::top::frame_errors::kAddress,
                                  .words = {0xFFFFU, 0xCAFEF00DU, 0x1U}});  // rc, rw, unmapped
  EXPECT_EQ(to_s64(out.frame_status), kRefused);
  EXPECT_EQ(to_s64(out.spi_status), kRefused);
  EXPECT_EQ(to_s64(out.frame_errors), 1);
  EXPECT_EQ(config(out, scratch), 0xCAFEF00DU);
  const hr::Outputs& next = b.run({.read = true, .address = scratch, .words = {0}});
  EXPECT_EQ(status_byte(next), kRefused);
  EXPECT_EQ(to_s64(next.miso_data[0].value), 0xCAFEF00DU);
  EXPECT_EQ(to_s64(next.frame_status), 0);
  EXPECT_EQ(to_s64(next.spi_status), kRefused);  // sticky
}

// CRC on: a corrupted CRC, a frame cut short, a frame too long and one too
// fast commit nothing and are counted; reading frame_errors returns the
// count and clears it (rc); writing 1s clears the sticky flags (w1c).
TEST(HlsRegfile, BadFramesCommitNothingAndAreCounted) {
  Bench b;
  const unsigned scratch = regs::top::scratch::kAddress;
  b.write(regs::top::ctrl::kAddress, regs::top::ctrl::crc_enable.mask());
  b.write(scratch, 1, true);
  const std::uint32_t before = config(b.out, scratch);
  EXPECT_EQ(before, 1U);
  b.run({.address = scratch, .words = {2}, .crc = true, .corrupt_crc = true});
  EXPECT_EQ(to_s64(b.out.frame_status), kCrcError);
  b.run({.address = scratch, .words = {3}, .crc = true, .bits = kHeader + kWord});  // no CRC byte
  EXPECT_EQ(to_s64(b.out.frame_status), kBadLength);
  b.run({.address = scratch, .words = {4}, .crc = true, .bits = 10});  // cut inside the command
  EXPECT_EQ(to_s64(b.out.frame_status), kBadLength);
  b.run({.address = scratch, .words = {5}, .crc = true, .bits = kHeader + kWord + kCrc + 1});
  EXPECT_EQ(to_s64(b.out.frame_status), kBadLength);
  b.run({.address = scratch, .words = {6}, .crc = true, .overrun = true});
  EXPECT_EQ(to_s64(b.out.frame_status), kOverrunFlag);
  EXPECT_EQ(config(b.out, scratch), before);
  EXPECT_EQ(to_s64(b.out.spi_status), kCrcError | kBadLength | kOverrunFlag);
  EXPECT_EQ(to_s64(b.out.frame_errors), 5);
  EXPECT_EQ(b.read(regs::top::frame_errors::kAddress, true), 5U);
  EXPECT_EQ(to_s64(b.out.frame_errors), 0);
  b.write(regs::top::spi_status::kAddress, kCrcError | kOverrunFlag, true);
  EXPECT_EQ(to_s64(b.out.spi_status), kBadLength);
  EXPECT_EQ(pulse(b.out, regs::top::spi_status::kAddress), kCrcError | kOverrunFlag);
}

// top.frame_errors saturates at its maximum instead of wrapping.
TEST(HlsRegfile, FrameErrorsSaturate) {
  Bench b;
  const long long max = (1LL << regs::top::frame_errors::count.width) - 1;
  b.regs.frame_errors = max - 1;
  b.run({.address = regs::top::scratch::kAddress, .words = {1}, .bits = 3});
  EXPECT_EQ(to_s64(b.out.frame_errors), max);
  b.run({.address = regs::top::scratch::kAddress, .words = {1}, .bits = 3});
  EXPECT_EQ(to_s64(b.out.frame_errors), max);
  EXPECT_EQ(b.read(regs::top::frame_errors::kAddress), static_cast<std::uint32_t>(max));
  EXPECT_EQ(to_s64(b.out.frame_errors), 0);
}

// The MISO CRC covers the status byte, 0x00 and the words read, and the
// master receives only the bits it clocks.
TEST(HlsRegfile, MisoCrcAndCutFrames) {
  Bench b;
  b.write(regs::top::ctrl::kAddress, regs::top::ctrl::crc_enable.mask());
  const hr::Outputs& out =
      b.run({.read = true, .address = regs::top::id::kAddress, .words = {0, 0}, .crc = true});
  const std::uint32_t id = regs::top::id::kReset;
  const std::uint8_t miso[] = {0,
                               0,
                               static_cast<std::uint8_t>(id >> 24),
                               static_cast<std::uint8_t>(id >> 16),
                               static_cast<std::uint8_t>(id >> 8),
                               static_cast<std::uint8_t>(id),
                               0,
                               0,
                               0,
                               regs::top::ctrl::crc_enable.mask()};
  EXPECT_EQ(to_s64(out.miso_data[0].value), id);
  EXPECT_EQ(to_s64(out.miso_crc), odoloc::rtl::crc8_j1850(miso));
  const hr::Outputs& cut = b.run({.read = true,
                                  .address = regs::top::id::kAddress,
                                  .words = {0, 0},
                                  .crc = true,
                                  .bits = kHeader + 12});
  EXPECT_EQ(to_s64(cut.miso_data[0].value), id & 0xFFF00000U);
  EXPECT_EQ(to_s64(cut.miso_data[1].value), 0);
  EXPECT_EQ(to_s64(cut.miso_crc), 0);
}

// w1c and w1p: the 1s written are one-call strobes; clear_flags also clears
// top.spi_status.
TEST(HlsRegfile, StrobesAreTheOnesWritten) {
  Bench b;
  const unsigned status = regs::eppm::status::address(2);
  const unsigned command = regs::odometry::command::kAddress;
  b.run({.address = regs::top::id::kAddress, .words = {1}});  // refused: a flag to clear
  EXPECT_EQ(to_s64(b.out.spi_status), kRefused);
  b.run({.address = status, .words = {0xFFFFFFFFU}});
  EXPECT_EQ(pulse(b.out, status),
            regs::eppm::status::phase_error.mask() | regs::eppm::status::carry.mask() |
                regs::eppm::status::borrow.mask() | regs::eppm::status::period_overflow.mask());
  b.run({.address = command, .words = {regs::odometry::command::clear_flags.mask()}});
  EXPECT_EQ(pulse(b.out, command), regs::odometry::command::clear_flags.mask());
  EXPECT_EQ(pulse(b.out, status), 0U);
  EXPECT_EQ(to_s64(b.out.spi_status), 0);
  b.run({.read = true, .address = command, .words = {0}});
  EXPECT_EQ(to_s64(b.out.miso_data[0].value), 0);  // w1p reads 0
  EXPECT_EQ(pulse(b.out, command), 0U);
}

// rpop: a completed read pops the whole entries it read in order from entry
// 0; from entry 1, or with a bad length, nothing.
TEST(HlsRegfile, ReadsPopWholeEntriesFromTheFirst) {
  Bench b;
  const unsigned entry0 = regs::tof_channel::entry::address(3, 0);
  const int window = regs::find(entry0)->pop_window;
  const auto pops = [&](const hr::Outputs& out) { return to_s64(out.pops[window].value); };
  EXPECT_EQ(
      pops(b.run({.read = true, .address = entry0 - 1, .words = std::vector<std::uint32_t>(6)})),
      2);  // unmapped, entry0 lo/hi, entry1 lo/hi, entry2 lo
  EXPECT_EQ(pops(b.run({.read = true, .address = entry0 + 2, .words = {0, 0}})), 0);
  EXPECT_EQ(pops(b.run({.read = true, .address = entry0, .words = std::vector<std::uint32_t>(32)})),
            regs::tof_channel::entry::kCount);
  EXPECT_EQ(pops(b.run({.read = true, .address = entry0, .words = {0, 0}, .bits = 40})), 0);
  EXPECT_EQ(pops(b.run({.address = entry0, .words = {0, 0}})), 0);  // a write: refused
  EXPECT_EQ(to_s64(b.out.frame_status), kRefused);
}

// Snapshot registers read the sampled status only; live ones add their
// stored and constant bits.
TEST(HlsRegfile, StatusWordsAreReadAsSampled) {
  Bench b;
  const unsigned count = regs::eppm::count::address(1);
  const unsigned info = regs::tof::info::kAddress;
  b.status_only.status[slot(hr::kStatus, count)].value = 0xFFFFFFFFU;
  b.status_only.status[slot(hr::kStatus, info)].value = 0x0000ABCDU;
  EXPECT_EQ(b.read(count), regs::eppm::count::value.mask());
  EXPECT_EQ(b.read(info), 0xABCDU);  // hw bits only: every field of tof.info is driven
}

}  // namespace
