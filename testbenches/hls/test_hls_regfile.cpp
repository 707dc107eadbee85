// The register interface kernel (hls/regfile_kernel.hpp: the SPI slave and
// the register file, one call per fabric clock) against the cycle model
// (rtl::RegisterInterface), compiled once per type family:
// - under the reference's seeded stimulus (hls/verification/src/
//   regfile_reference.cpp: reads, writes and bursts everywhere, refused
//   writes, w1c/w1p strobes, rc and rpop reads, cut, long, too fast and
//   CRC-corrupted frames, resets) every output of every clock equals the
//   model's, and every register of the kernel equals the model's;
// - directed frames, driven at pin level by board::SpiPinMaster, check the
//   documented behaviour (docs/spi.md, docs/register-map.md) against values
//   written out from the docs and the generated register map, not from the
//   model.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "hls_kernel_check.hpp"
#include "odoloc/board/spi_pin_master.hpp"
#include "odoloc/hls/regfile_kernel.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/register_interface.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace {

namespace hr = odoloc::hls::regfile;
namespace rf = odoloc::logic::regfile;
namespace regs = odoloc::regs;
using odoloc::hls::to_s64;
using odoloc::rtl::UInt;

constexpr int kHeader = 16;
constexpr int kWord = 32;
constexpr int kCrc = 8;

int slot(int bank, unsigned address) {
  return rf::kLayout.slot[bank][rf::kLayout.register_at[address]];
}

using Model = odoloc::rtl::RegisterInterface<rf::StatusWords<odoloc::rtl::Family>>;

// f(name, kernel register, model register) for every register of the interface.
template <class F>
void walk(const hr::Registers& k, const Model& m, F&& f) {
  const auto& ks = k.slave.synchroniser;
  const auto& ms = m.spi().synchroniser();
  f("synchroniser.sclk_meta", ks.sclk_meta, ms.sclk_meta);
  f("synchroniser.sclk_sync", ks.sclk_sync, ms.sclk_sync);
  f("synchroniser.sclk_prev", ks.sclk_prev, ms.sclk_prev);
  f("synchroniser.cs_meta", ks.cs_meta, ms.cs_meta);
  f("synchroniser.cs_sync", ks.cs_sync, ms.cs_sync);
  f("synchroniser.cs_prev", ks.cs_prev, ms.cs_prev);
  f("synchroniser.mosi_meta", ks.mosi_meta, ms.mosi_meta);
  f("synchroniser.mosi_sync", ks.mosi_sync, ms.mosi_sync);
  f("synchroniser.level_clocks", ks.level_clocks, ms.level_clocks);
  const auto& ke = k.slave.engine;
  const auto& me = m.spi().engine();
  f("engine.active", ke.active, me.active);
  f("engine.crc_on", ke.crc_on, me.crc_on);
  f("engine.fall_armed", ke.fall_armed, me.fall_armed);
  f("engine.frame_overrun", ke.frame_overrun, me.frame_overrun);
  f("engine.rx_count", ke.rx_count, me.rx_count);
  f("engine.rx_shift", ke.rx_shift, me.rx_shift);
  f("engine.rx_crc", ke.rx_crc, me.rx_crc);
  f("engine.command", ke.command, me.command);
  f("engine.tx_count", ke.tx_count, me.tx_count);
  f("engine.tx_shift", ke.tx_shift, me.tx_shift);
  f("engine.tx_crc", ke.tx_crc, me.tx_crc);
  f("engine.read_word", ke.read_word, me.read_word);
  f("engine.miso", ke.miso, me.miso);
  f("engine.snapshot", ke.snapshot, me.snapshot);
  f("engine.read_strobe", ke.read_strobe, me.read_strobe);
  f("engine.read_address", ke.read_address, me.read_address);
  f("engine.commit", ke.commit, me.commit);
  f("engine.commit_write", ke.commit_write, me.commit_write);
  f("engine.frame_end", ke.frame_end, me.frame_end);
  f("engine.commit_address", ke.commit_address, me.commit_address);
  f("engine.commit_count", ke.commit_count, me.commit_count);
  f("engine.status", ke.status, me.status);
  for (int w = 0; w < rf::kMaxBurst; ++w)
    f("buffer.words", k.slave.buffer.words[w].value, m.spi().buffer().words[w].value);
  const auto& kr = k.registers;
  const auto& mr = m.registers().regs();
  for (int s = 0; s < rf::kStoredWords; ++s)
    f("registers.stored", kr.stored.word[s].value, mr.stored.word[s].value);
  for (int s = 0; s < rf::kSnapshotWords; ++s)
    f("registers.snapshot", kr.snapshot[s].value, mr.snapshot[s].value);
  f("registers.spi_status", kr.spi_status, mr.spi_status);
  f("registers.frame_errors", kr.frame_errors, mr.frame_errors);
  f("registers.frame_errors_returned", kr.frame_errors_returned, mr.frame_errors_returned);
  for (int w = 0; w < rf::kPopWindows; ++w) {
    f("registers.pop_words", kr.pop_words[w].value, mr.pop_words[w].value);
    f("registers.pops", kr.pops[w].value, mr.pops[w].value);
  }
  for (int s = 0; s < rf::kPulseWords; ++s)
    f("registers.pulse", kr.pulse[s].value, mr.pulse[s].value);
  f("registers.pulsing", kr.pulsing, mr.pulsing);
}

// The first register in which kernel and model differ, or "".
std::string first_difference(const hr::Registers& kernel, const Model& model) {
  return odoloc::tb::first_difference([&](const auto& f) { walk(kernel, model, f); });
}

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

// What a frame did, as the master and the fabric see it.
struct Result {
  std::vector<std::uint8_t> miso;  // the bits the master clocked, MSB first
  std::vector<std::uint32_t> pulse = std::vector<std::uint32_t>(rf::kPulseWords);  // any clock
  std::vector<long long> pops = std::vector<long long>(rf::kPopWindows);           // any clock
  // MISO byte i (0 where the master clocked none).
  [[nodiscard]] std::uint32_t byte(std::size_t i) const { return i < miso.size() ? miso[i] : 0; }
  [[nodiscard]] std::uint32_t word(std::size_t k) const {
    std::uint32_t w = 0;
    for (std::size_t b = 0; b < 4; ++b)
      w = w << 8 | byte(2 + 4 * k + b);
    return w;
  }
  [[nodiscard]] std::uint32_t status_byte() const { return byte(0); }
  [[nodiscard]] std::uint32_t pulse_of(unsigned address) const {
    return pulse[static_cast<std::size_t>(slot(rf::kPulse, address))];
  }
};

// The kernel, clocked at pin level, with the fabric's status all 0 unless set.
struct Bench {
  hr::Registers regs;
  hr::Inputs in;
  hr::Outputs out;

  Bench() { settle(); }

  UInt<1> clock(UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi, Result* result = nullptr) {
    in.sclk = static_cast<unsigned>(sclk.value());
    in.cs_n = static_cast<unsigned>(cs_n.value());
    in.mosi = static_cast<unsigned>(mosi.value());
    hr::step(regs, in, out);
    if (result != nullptr) {
      for (int k = 0; k < rf::kPulseWords; ++k)
        result->pulse[static_cast<std::size_t>(k)] |=
            static_cast<std::uint32_t>(to_s64(out.pulse[k].value));
      for (int w = 0; w < rf::kPopWindows; ++w)
        result->pops[static_cast<std::size_t>(w)] |= to_s64(out.pops[w].value);
    }
    return UInt<1>::truncate(static_cast<std::uint64_t>(to_s64(out.miso)));
  }
  void settle() {
    for (int c = 0; c < 8; ++c)
      clock(UInt<1>{}, UInt<1>{1}, UInt<1>{});
  }
  void reset() {
    in.reset = 1;
    clock(UInt<1>{}, UInt<1>{1}, UInt<1>{});
    in.reset = 0;
    settle();
  }

  Result run(const Frame& f) {
    const auto count = static_cast<unsigned>(f.words.size());
    const std::uint32_t command = (f.read ? 0x8000U : 0U) | (count - 1) << 10 | f.address;
    std::vector<std::uint8_t> bytes{static_cast<std::uint8_t>(command >> 8),
                                    static_cast<std::uint8_t>(command)};
    for (const std::uint32_t w : f.words)
      for (int b = 24; b >= 0; b -= 8)
        bytes.push_back(static_cast<std::uint8_t>(w >> b));
    const std::uint8_t crc = odoloc::rtl::crc8_j1850(bytes);
    if (f.crc)
      bytes.push_back(f.corrupt_crc ? crc ^ 0x01U : crc);
    const std::size_t bits = f.bits >= 0 ? static_cast<std::size_t>(f.bits) : bytes.size() * 8;
    bytes.resize(std::max(bytes.size(), (bits + 7) / 8), 0);  // a frame held too long
    odoloc::board::SpiPinMaster master(
        {.half_period = f.overrun ? regs::spi::kMinLevelClocks - 1 : regs::spi::kMinLevelClocks,
         .mode3 = false,
         .idle_clocks = 8});
    Result result;
    result.miso = master.transfer(
        bytes,
        [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) { return clock(sclk, cs_n, mosi, &result); },
        bits);
    return result;
  }
  std::uint32_t read(unsigned address, bool crc = false) {
    return run({.read = true, .address = address, .words = {0}, .crc = crc}).word(0);
  }
  Result write(unsigned address, std::uint32_t word, bool crc = false) {
    return run({.address = address, .words = {word}, .crc = crc});
  }

  [[nodiscard]] std::uint32_t config(unsigned address) const {
    return static_cast<std::uint32_t>(to_s64(out.config[slot(rf::kStored, address)].value));
  }
  // The slave's flags of the last frame (the next frame's status byte).
  [[nodiscard]] long long frame_status() const { return to_s64(regs.slave.engine.status); }
  [[nodiscard]] long long spi_status() const { return to_s64(regs.registers.spi_status); }
  [[nodiscard]] long long frame_errors() const { return to_s64(regs.registers.frame_errors); }
};

constexpr unsigned kRefused = regs::top::spi_status::write_refused.mask();
constexpr unsigned kBadLength = regs::top::spi_status::bad_length.mask();
constexpr unsigned kCrcError = regs::top::spi_status::crc_error.mask();
constexpr unsigned kOverrunFlag = regs::top::spi_status::overrun.mask();

TEST(HlsRegfile, EveryOutputEqualsTheModelEveryClock) {
  const auto check = odoloc::tb::check_kernel<hr::Inputs, hr::Outputs, hr::Registers>(
      "regfile", 12, odoloc::tb::hls_calls(400000), hr::step);
  EXPECT_EQ(check.names_error, "");
  EXPECT_GT(check.calls, 0U);
  EXPECT_EQ(check.mismatches, 0U) << check.first_mismatch;
}

// The reference's stimulus through the kernel and a model of this test's
// own, clock by clock: every register equal, and the stimulus reaches the
// frames' corners (commits, refused writes, every error flag, pops, resets).
TEST(HlsRegfile, EveryRegisterEqualsTheModelAndTheStimulusReachesTheCorners) {
  const auto reference = odoloc::hls_export::find_kernel("regfile")->make_reference(13);
  std::vector<std::int64_t> row(reference->input_names().size()),
      want(reference->output_names().size());
  Model model;
  hr::Registers regs;
  hr::Inputs in;
  hr::Outputs out;
  std::uint64_t differing = 0, commits = 0, writes = 0, pops = 0, resets = 0;
  unsigned flags = 0;
  std::string first;
  const std::uint64_t clocks = odoloc::tb::scaled(1000000);
  for (std::uint64_t clock = 0; clock < clocks; ++clock) {
    reference->stimulus(row);
    reference->step(row, want);
    std::size_t at = 0;
    hr::visit_fields(in, [&](const char*, auto& field) { field = row[at++]; });
    hr::step(regs, in, out);
    rf::StatusWords<odoloc::rtl::Family> status;
    for (int k = 0; k < rf::kStatusWords; ++k)
      status.bank[k].value =
          UInt<32>::truncate(static_cast<std::uint64_t>(to_s64(in.status.bank[k].value)));
    const auto pin = [](const auto& p) {
      return UInt<1>::truncate(static_cast<std::uint64_t>(to_s64(p)));
    };
    model.step(
        {.sclk = pin(in.sclk), .cs_n = pin(in.cs_n), .mosi = pin(in.mosi), .reset = pin(in.reset)},
        status);
    const std::string d = first_difference(regs, model);
    if (!d.empty() && differing++ == 0)
      first = "clock " + std::to_string(clock) + ": " + d;
    const auto& e = model.spi().engine();
    commits += e.commit.value();
    writes += (e.commit & e.commit_write).value();
    flags |= static_cast<unsigned>(model.registers().regs().spi_status.value());
    pops += model.registers().regs().pops[0].value.value() != 0 ? 1 : 0;
    resets += to_s64(in.reset) != 0 ? 1 : 0;
  }
  EXPECT_EQ(differing, 0U) << first;
  EXPECT_GT(commits, 20U);
  EXPECT_GT(writes, 10U);
  EXPECT_EQ(flags, kCrcError | kBadLength | kRefused | kOverrunFlag);
  EXPECT_GT(resets, 0U);
  std::printf("%llu clocks: %llu commits (%llu writes), pops of FIFO 0 in %llu, %llu resets\n",
              static_cast<unsigned long long>(clocks), static_cast<unsigned long long>(commits),
              static_cast<unsigned long long>(writes), static_cast<unsigned long long>(pops),
              static_cast<unsigned long long>(resets));
}

// Reset: every configuration word holds the map's reset, every register reads
// its stored and constant bits (the status all 0), top.id its constant.
TEST(HlsRegfile, ResetValuesAreTheMapsAndReadBack) {
  Bench b;
  b.write(regs::top::scratch::kAddress, 0x12345678U);
  EXPECT_EQ(b.config(regs::top::scratch::kAddress), 0x12345678U);
  b.reset();
  for (const regs::Register& r : regs::kRegisters)
    if (r.rw_mask != 0) {
      EXPECT_EQ(b.config(r.address), r.reset & r.rw_mask) << r.path;
    }
  for (unsigned start = 0; start < 1024; start += 32) {
    const Result out =
        b.run({.read = true, .address = start, .words = std::vector<std::uint32_t>(32)});
    for (unsigned k = 0; k < 32; ++k) {
      const regs::Register* r = regs::find(start + k);
      const std::uint32_t want =
          r == nullptr || r->snapshot ? 0 : r->reset & (r->rw_mask | r->const_mask);
      EXPECT_EQ(out.word(k), want) << start + k;
    }
  }
  EXPECT_EQ(b.read(regs::top::id::kAddress), regs::top::id::kReset);
}

// A write burst over a read-only register lands its other words and sets
// write_refused, reported in the next frame's status byte and counted.
TEST(HlsRegfile, RefusedWordsAreDroppedTheOthersLand) {
  Bench b;
  const unsigned scratch = regs::top::scratch::kAddress;
  b.run({.address = regs::top::frame_errors::kAddress,
         .words = {0xFFFFU, 0xCAFEF00DU, 0x1U}});  // rc, rw, unmapped
  EXPECT_EQ(b.frame_status(), kRefused);
  EXPECT_EQ(b.spi_status(), kRefused);
  EXPECT_EQ(b.frame_errors(), 1);
  EXPECT_EQ(b.config(scratch), 0xCAFEF00DU);
  const Result next = b.run({.read = true, .address = scratch, .words = {0}});
  EXPECT_EQ(next.status_byte(), kRefused);
  EXPECT_EQ(next.word(0), 0xCAFEF00DU);
  EXPECT_EQ(b.frame_status(), 0);
  EXPECT_EQ(b.spi_status(), kRefused);  // sticky
}

// CRC on: a corrupted CRC, a frame cut short, a frame too long and one too
// fast commit nothing and are counted; reading frame_errors returns the
// count and clears it (rc); writing 1s clears the sticky flags (w1c).
TEST(HlsRegfile, BadFramesCommitNothingAndAreCounted) {
  Bench b;
  const unsigned scratch = regs::top::scratch::kAddress;
  b.write(regs::top::ctrl::kAddress, regs::top::ctrl::crc_enable.mask());
  b.write(scratch, 1, true);
  EXPECT_EQ(b.config(scratch), 1U);
  b.run({.address = scratch, .words = {2}, .crc = true, .corrupt_crc = true});
  EXPECT_EQ(b.frame_status(), kCrcError);
  b.run({.address = scratch, .words = {3}, .crc = true, .bits = kHeader + kWord});  // no CRC byte
  EXPECT_EQ(b.frame_status(), kBadLength);
  b.run({.address = scratch, .words = {4}, .crc = true, .bits = 10});  // cut inside the command
  EXPECT_EQ(b.frame_status(), kBadLength);
  b.run({.address = scratch, .words = {5}, .crc = true, .bits = kHeader + kWord + kCrc + 1});
  EXPECT_EQ(b.frame_status(), kBadLength);
  b.run({.address = scratch, .words = {6}, .crc = true, .overrun = true});
  EXPECT_EQ(b.frame_status(), kOverrunFlag);
  EXPECT_EQ(b.config(scratch), 1U);
  EXPECT_EQ(b.spi_status(), kCrcError | kBadLength | kOverrunFlag);
  EXPECT_EQ(b.frame_errors(), 5);
  EXPECT_EQ(b.read(regs::top::frame_errors::kAddress, true), 5U);
  EXPECT_EQ(b.frame_errors(), 0);
  const Result clear = b.write(regs::top::spi_status::kAddress, kCrcError | kOverrunFlag, true);
  EXPECT_EQ(b.spi_status(), kBadLength);
  EXPECT_EQ(clear.pulse_of(regs::top::spi_status::kAddress), kCrcError | kOverrunFlag);
}

// top.frame_errors saturates at its maximum instead of wrapping.
TEST(HlsRegfile, FrameErrorsSaturate) {
  Bench b;
  const long long max = (1LL << regs::top::frame_errors::count.width) - 1;
  b.regs.registers.frame_errors = max - 1;
  b.run({.address = regs::top::scratch::kAddress, .words = {1}, .bits = 3});
  EXPECT_EQ(b.frame_errors(), max);
  b.run({.address = regs::top::scratch::kAddress, .words = {1}, .bits = 3});
  EXPECT_EQ(b.frame_errors(), max);
  EXPECT_EQ(b.read(regs::top::frame_errors::kAddress), static_cast<std::uint32_t>(max));
  EXPECT_EQ(b.frame_errors(), 0);
}

// The MISO CRC covers the status byte, 0x00 and the words read, and the
// master receives only the bits it clocks.
TEST(HlsRegfile, MisoCrcAndCutFrames) {
  Bench b;
  b.write(regs::top::ctrl::kAddress, regs::top::ctrl::crc_enable.mask());
  const Result out =
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
  EXPECT_EQ(out.word(0), id);
  EXPECT_EQ(out.byte(10), odoloc::rtl::crc8_j1850(miso));
  const Result cut = b.run({.read = true,
                            .address = regs::top::id::kAddress,
                            .words = {0, 0},
                            .crc = true,
                            .bits = kHeader + 12});
  EXPECT_EQ(cut.word(0), id & 0xFFF00000U);
  EXPECT_EQ(cut.word(1), 0U);
  EXPECT_EQ(cut.byte(10), 0U);
}

// w1c and w1p: the 1s written are one-clock strobes; clear_flags also clears
// top.spi_status.
TEST(HlsRegfile, StrobesAreTheOnesWrittenForOneClock) {
  Bench b;
  const unsigned status = regs::eppm::status::address(2);
  const unsigned command = regs::odometry::command::kAddress;
  b.write(regs::top::id::kAddress, 1);  // refused: a flag to clear
  EXPECT_EQ(b.spi_status(), kRefused);
  const Result clears = b.write(status, 0xFFFFFFFFU);
  EXPECT_EQ(clears.pulse_of(status),
            regs::eppm::status::phase_error.mask() | regs::eppm::status::carry.mask() |
                regs::eppm::status::borrow.mask() | regs::eppm::status::period_overflow.mask());
  const Result commands = b.write(command, regs::odometry::command::clear_flags.mask());
  EXPECT_EQ(commands.pulse_of(command), regs::odometry::command::clear_flags.mask());
  EXPECT_EQ(commands.pulse_of(status), 0U);
  EXPECT_EQ(b.spi_status(), 0);
  EXPECT_EQ(to_s64(b.out.pulse[slot(rf::kPulse, command)].value), 0);  // one clock only
  const Result read = b.run({.read = true, .address = command, .words = {0}});
  EXPECT_EQ(read.word(0), 0U);  // w1p reads 0
  EXPECT_EQ(read.pulse_of(command), 0U);
}

// rpop: a completed read pops the whole entries it read in order from entry
// 0; from entry 1, or with a bad length, nothing.
TEST(HlsRegfile, ReadsPopWholeEntriesFromTheFirst) {
  Bench b;
  const unsigned entry0 = regs::tof_channel::entry::address(3, 0);
  const auto window = static_cast<std::size_t>(regs::find(entry0)->pop_window);
  const auto pops = [&](const Result& out) { return out.pops[window]; };
  EXPECT_EQ(
      pops(b.run({.read = true, .address = entry0 - 1, .words = std::vector<std::uint32_t>(6)})),
      2);  // unmapped, entry0 lo/hi, entry1 lo/hi, entry2 lo
  EXPECT_EQ(pops(b.run({.read = true, .address = entry0 + 2, .words = {0, 0}})), 0);
  EXPECT_EQ(pops(b.run({.read = true, .address = entry0, .words = std::vector<std::uint32_t>(32)})),
            regs::tof_channel::entry::kCount);
  EXPECT_EQ(pops(b.run({.read = true, .address = entry0, .words = {0, 0}, .bits = 40})), 0);
  EXPECT_EQ(pops(b.run({.address = entry0, .words = {0, 0}})), 0);  // a write: refused
  EXPECT_EQ(b.frame_status(), kRefused);
}

// Snapshot registers read the status sampled when the frame started; live
// ones read it when the word is fetched and add their stored and constant
// bits.
TEST(HlsRegfile, StatusWordsAreReadAsSampled) {
  Bench b;
  const unsigned count = regs::eppm::count::address(1);
  const unsigned info = regs::tof::info::kAddress;
  b.in.status.bank[slot(rf::kStatus, count)].value = 0xFFFFFFFFU;
  b.in.status.bank[slot(rf::kStatus, info)].value = 0x0000ABCDU;
  EXPECT_EQ(b.read(count), regs::eppm::count::value.mask());
  EXPECT_EQ(b.read(info), 0xABCDU);  // hw bits only: every field of tof.info is driven
  // The status changes 20 clocks into a read of count, after the snapshot and
  // before the word is fetched: the frame still returns the sample.
  const std::uint8_t read_count[] = {
      static_cast<std::uint8_t>(0x80U | count >> 8), static_cast<std::uint8_t>(count), 0, 0, 0, 0};
  odoloc::board::SpiPinMaster master({.half_period = regs::spi::kMinLevelClocks});
  int clocks = 0;
  const auto miso = master.transfer(read_count, [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
    if (++clocks == 20)
      b.in.status.bank[slot(rf::kStatus, count)].value = 0;
    return b.clock(sclk, cs_n, mosi);
  });
  EXPECT_EQ(Result{.miso = miso}.word(0), regs::eppm::count::value.mask());
  EXPECT_EQ(b.read(count), 0U);  // the next frame samples the new status
}

}  // namespace
