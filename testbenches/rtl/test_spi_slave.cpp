// SPI slave protocol engine driven at pin level by the bit-level master BFM,
// with a tiny in-test register side (1024 words, the top quarter read-only).
// The expected memory and status bytes come from a frame-level reference, the
// CRC from polynomial long division.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/rtl/spi_slave.hpp"
#include "odoloc/rtl/vcd.hpp"
#include "spi_master_bfm.hpp"
#include "vcd_check.hpp"

namespace {

using odoloc::rtl::crc8_j1850;
using odoloc::rtl::Gating;
using odoloc::rtl::SpiRegisterPort;
using odoloc::rtl::SpiSlave;
using odoloc::rtl::UInt;
using odoloc::tb::spi_frame;
using odoloc::tb::SpiMasterBfm;
using odoloc::tb::SpiMasterConfig;
using odoloc::tb::SpiOp;
using Bytes = std::vector<std::uint8_t>;
using Words = std::vector<std::uint32_t>;

constexpr unsigned kReadOnlyFirst = 0x300;

// The slave plus a register side composed per the clocked conventions: every
// wire into the slave and every register-side action derive from the current
// registers, then one edge.
struct Bench {
  SpiSlave slave;
  SpiSlave ungated;
  std::array<std::uint32_t, 1024> mem{};
  bool crc_enable = false;
  bool mode3 = false;
  UInt<1> refused{};  // register side: write_refused pulse register
  unsigned snapshots = 0;
  unsigned commits = 0;
  std::vector<unsigned> read_addresses;
  std::uint64_t clock = 0;
  std::uint64_t last_snapshot_clock = 0;

  Bench() {
    for (unsigned a = 0; a < mem.size(); ++a)
      mem[a] = 0xA5000000U | a;
  }

  UInt<1> step(UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
    const SpiRegisterPort r = slave.port();
    const SpiSlave::In in{.sclk = sclk,
                          .cs_n = cs_n,
                          .mosi = mosi,
                          .crc_enable = UInt<1>::truncate(crc_enable ? 1 : 0),
                          .spi_mode3 = UInt<1>::truncate(mode3 ? 1 : 0),
                          .read_data = UInt<32>{mem[r.read_address.value()]},
                          .write_refused = refused,
                          .reset = {}};
    bool refuse = false;
    if (r.snapshot) {
      ++snapshots;
      last_snapshot_clock = clock;
    }
    if (r.read_strobe)
      read_addresses.push_back(static_cast<unsigned>(r.read_address.value()));
    if (r.commit) {
      ++commits;
      for (unsigned k = 0; r.commit_write && k < r.commit_count.value(); ++k) {
        const auto a = static_cast<unsigned>((r.commit_address.value() + k) % mem.size());
        if (a >= kReadOnlyFirst)
          refuse = true;
        else
          mem[a] = static_cast<std::uint32_t>(r.words[k].value.value());
      }
    }
    // Activity gating: the gated slave and an ungated twin agree every clock.
    const bool idle = slave.idle(in);
    const SpiSlave before = slave;
    slave.step<Gating::kOn>(in);
    ungated.step<Gating::kOff>(in);
    EXPECT_TRUE(slave == ungated) << "gated and ungated slaves differ at clock " << clock;
    if (idle) {
      EXPECT_TRUE(slave == before) << "idle() promised no change at clock " << clock;
    }
    refused = UInt<1>::truncate(refuse ? 1 : 0);
    ++clock;
    return slave.miso();
  }

  void settle() {
    for (int i = 0; i < 8; ++i)
      step(UInt<1>::truncate(mode3 ? 1 : 0), UInt<1>{1}, UInt<1>{});
  }
};

struct Harness {
  Bench bench;
  SpiMasterBfm master;

  explicit Harness(SpiMasterConfig config, bool crc = false) : master(config) {
    bench.crc_enable = crc;
    bench.mode3 = config.mode3;
    bench.settle();
  }
  Bytes run(std::span<const std::uint8_t> mosi, std::size_t abort = SpiMasterBfm::kNoAbort) {
    return master.transfer(
        mosi, [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> d) { return bench.step(sclk, cs_n, d); },
        abort);
  }
  Bytes write(unsigned address, const Words& words) {
    return run(spi_frame(SpiOp::kWrite, address, words, bench.crc_enable));
  }
  Bytes read_raw(unsigned address, std::size_t n) {
    return run(spi_frame(SpiOp::kRead, address, Words(n, 0), bench.crc_enable));
  }
  // Reads n words; checks the reply's byte 1 and (CRC on) its CRC.
  Words read(unsigned address, std::size_t n) {
    const Bytes miso = read_raw(address, n);
    EXPECT_EQ(miso[1], 0);
    if (bench.crc_enable) {
      EXPECT_EQ(miso[4 * n + 2], crc8_j1850(std::span(miso).first(4 * n + 2)));
    }
    Words words(n);
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t b = 0; b < 4; ++b)
        words[k] = words[k] << 8U | miso[2 + 4 * k + b];
    return words;
  }
  std::uint8_t status() { return read_raw(0, 1)[0]; }
};

Words random_words(std::mt19937& rng, std::size_t n) {
  Words w(n);
  for (auto& x : w)
    x = static_cast<std::uint32_t>(rng());
  return w;
}

// ---- CRC-8 ------------------------------------------------------------------

// Polynomial long division of the augmented message, init folded into the
// first byte: independent of the shift-register formulation in the header.
std::uint8_t crc8_reference(std::span<const std::uint8_t> bytes) {
  std::vector<int> bits;
  for (std::size_t i = 0; i < bytes.size(); ++i)
    for (int b = 7; b >= 0; --b)
      bits.push_back(((bytes[i] ^ (i == 0 ? 0xFF : 0)) >> b) & 1);
  bits.resize(bits.size() + 8, 0);
  constexpr std::array<int, 9> kPoly = {1, 0, 0, 0, 1, 1, 1, 0, 1};  // x^8+x^4+x^3+x^2+1
  for (std::size_t i = 0; i + 8 < bits.size(); ++i)
    if (bits[i] != 0)
      for (std::size_t j = 0; j < kPoly.size(); ++j)
        bits[i + j] ^= kPoly[j];
  unsigned rem = 0;
  for (std::size_t i = bits.size() - 8; i < bits.size(); ++i)
    rem = rem << 1U | static_cast<unsigned>(bits[i]);
  return static_cast<std::uint8_t>(rem ^ 0xFFU);
}

// The catalogue's check value of CRC-8/SAE-J1850: the CRC of "123456789".
TEST(SpiCrc8, CheckValue) {
  const std::string_view check = "123456789";
  std::array<std::uint8_t, 9> b{};
  for (std::size_t i = 0; i < b.size(); ++i)
    b[i] = static_cast<std::uint8_t>(check[i]);
  EXPECT_EQ(crc8_j1850(b), 0x4B);
}

TEST(SpiCrc8, AllSingleBytesMatchLongDivision) {
  for (unsigned b = 0; b < 256; ++b) {
    const std::array<std::uint8_t, 1> msg{static_cast<std::uint8_t>(b)};
    EXPECT_EQ(crc8_j1850(msg), crc8_reference(msg)) << b;
  }
}

TEST(SpiCrc8, MultiByteVectorsMatchLongDivision) {
  EXPECT_EQ(crc8_j1850(std::span<const std::uint8_t>{}), 0x00);  // init ^ xorout
  std::mt19937 rng(8);
  for (int t = 0; t < 2000; ++t) {
    Bytes msg(1 + rng() % 131);
    for (auto& b : msg)
      b = static_cast<std::uint8_t>(rng());
    ASSERT_EQ(crc8_j1850(msg), crc8_reference(msg)) << t;
  }
  for (unsigned a = 0; a < 256; ++a)
    for (unsigned b = 0; b < 256; b += 7) {
      const std::array<std::uint8_t, 2> msg{static_cast<std::uint8_t>(a),
                                            static_cast<std::uint8_t>(b)};
      ASSERT_EQ(crc8_j1850(msg), crc8_reference(msg));
    }
}

// ---- frames -----------------------------------------------------------------

struct Speed {
  unsigned half_period;
  bool mode3;
  bool crc;
};

class SpiReadBack : public ::testing::TestWithParam<Speed> {};

TEST_P(SpiReadBack, WriteThenReadBursts) {
  const Speed s = GetParam();
  Harness h({.half_period = s.half_period, .mode3 = s.mode3}, s.crc);
  std::mt19937 rng(s.half_period * 4U + (s.mode3 ? 2U : 0U) + (s.crc ? 1U : 0U));
  unsigned expected_commits = 0;
  for (const auto& [address, n] :
       {std::pair{0x004U, 1U}, {0x010U, 2U}, {0x100U, 32U}, {0x2FFU, 1U}}) {
    const Words words = random_words(rng, n);
    const Bytes miso = h.write(address, words);
    EXPECT_EQ(miso[0], 0) << "status";
    for (std::size_t i = 1; i < 4 * n + 2; ++i)
      EXPECT_EQ(miso[i], 0) << i;
    if (s.crc) {
      EXPECT_EQ(miso[4 * n + 2], crc8_j1850(std::span(miso).first(4 * n + 2)));
    }
    EXPECT_EQ(h.bench.commits, ++expected_commits);
    EXPECT_EQ(h.read(address, n), words);
    EXPECT_EQ(h.bench.commits, ++expected_commits);  // a complete read commits too
  }
  EXPECT_EQ(h.bench.mem[0x005], 0xA5000005U) << "neighbour untouched";
}

std::string speed_name(const ::testing::TestParamInfo<Speed>& info) {
  std::array<char, 32> name{};
  std::snprintf(name.data(), name.size(), "h%u_mode%d%s", info.param.half_period,
                info.param.mode3 ? 3 : 0, info.param.crc ? "_crc" : "");
  return name.data();
}

INSTANTIATE_TEST_SUITE_P(ModesAndSpeeds, SpiReadBack,
                         ::testing::Values(Speed{4, false, false}, Speed{4, true, false},
                                           Speed{4, false, true}, Speed{4, true, true},
                                           Speed{5, false, true}, Speed{7, true, false},
                                           Speed{16, false, false}, Speed{16, true, true}),
                         speed_name);

TEST(SpiSlave, BurstReadsAddressesStartToStartPlusNMinus1) {
  Harness h({.half_period = 4});
  for (const auto& [address, n] : {std::pair{0x020U, 32U}, {0x3FEU, 4U}}) {
    h.bench.read_addresses.clear();
    const Words got = h.read(address, n);
    ASSERT_EQ(h.bench.read_addresses.size(), n);
    for (unsigned k = 0; k < n; ++k) {
      const unsigned a = (address + k) % 1024;
      EXPECT_EQ(h.bench.read_addresses[k], a);
      EXPECT_EQ(got[k], 0xA5000000U | a);
    }
  }
}

TEST(SpiSlave, StatusByteCarriesPreviousFrameErrors) {
  Harness h({.half_period = 4}, true);
  EXPECT_EQ(h.status(), 0);
  Bytes bad = spi_frame(SpiOp::kWrite, 0x001, Words{0x12345678U}, true);
  bad.back() ^= 0x01;
  EXPECT_EQ(h.run(bad)[0], 0);
  EXPECT_EQ(h.bench.mem[0x001], 0xA5000001U) << "bad CRC discards the write";
  EXPECT_EQ(h.status(), SpiSlave::kStatusCrcError);
  EXPECT_EQ(h.status(), 0) << "errors are per frame";
  h.run(spi_frame(SpiOp::kWrite, 0x001, Words{1, 2}, true), 40);
  EXPECT_EQ(h.status(), SpiSlave::kStatusBadLength);
  h.write(kReadOnlyFirst - 1, Words{7, 8});
  EXPECT_EQ(h.bench.mem[kReadOnlyFirst - 1], 7U) << "the writable word lands";
  EXPECT_EQ(h.bench.mem[kReadOnlyFirst], 0xA5000000U | kReadOnlyFirst);
  EXPECT_EQ(h.status(), SpiSlave::kStatusWriteRefused);
  EXPECT_EQ(h.bench.slave.engine().status, UInt<4>{}) << "status output after a clean frame";
}

TEST(SpiSlave, CrcGoodWritesLandBadOnesAreFlagged) {
  Harness h({.half_period = 5, .mode3 = true}, true);
  h.write(0x040, Words{0xDEADBEEFU, 0x01020304U});
  EXPECT_EQ(h.bench.mem[0x040], 0xDEADBEEFU);
  EXPECT_EQ(h.bench.mem[0x041], 0x01020304U);
  for (unsigned flip = 8; flip < 8 * 11; flip += 5) {  // address, data or CRC bits
    Bytes frame = spi_frame(SpiOp::kWrite, 0x040, Words{1, 2}, true);
    frame[flip / 8] = static_cast<std::uint8_t>(frame[flip / 8] ^ (1U << (flip % 8)));
    const unsigned commits = h.bench.commits;
    h.run(frame);
    EXPECT_EQ(h.bench.commits, commits) << flip;
    EXPECT_EQ(h.bench.mem[0x040], 0xDEADBEEFU) << flip;
    EXPECT_EQ(h.status(), SpiSlave::kStatusCrcError) << flip;
  }
  Bytes longer = spi_frame(SpiOp::kWrite, 0x040, Words{1, 2}, true);
  longer[0] ^= 0x04;  // burst length 2 -> 3: the frame is now short
  h.run(longer);
  EXPECT_EQ(h.status(), SpiSlave::kStatusBadLength);
  EXPECT_EQ(h.read(0x040, 2), (Words{0xDEADBEEFU, 0x01020304U}));
}

TEST(SpiSlave, AbortedFramesCommitNothingAndTheNextFrameWorks) {
  for (const bool crc : {false, true}) {
    Harness h({.half_period = 4}, crc);
    const Bytes frame = spi_frame(SpiOp::kWrite, 0x0AA, Words{0x11111111U, 0x22222222U}, crc);
    for (std::size_t k = 0; k < frame.size() * 8; ++k) {
      const unsigned commits = h.bench.commits;
      h.run(frame, k);
      EXPECT_EQ(h.bench.commits, commits) << k;
      EXPECT_EQ(h.bench.mem[0x0AA], 0xA50000AAU) << k;
      EXPECT_EQ(h.status(), SpiSlave::kStatusBadLength) << k;
    }
    Bytes longer = frame;
    longer.push_back(0);
    h.run(longer);
    EXPECT_EQ(h.status(), SpiSlave::kStatusBadLength) << "one byte too many";
    h.run(frame);
    EXPECT_EQ(h.read(0x0AA, 2), (Words{0x11111111U, 0x22222222U}));
  }
}

TEST(SpiSlave, SclkTooFastIsFlaggedNeverHangs) {
  for (const bool mode3 : {false, true})
    for (unsigned half = 1; half < SpiSlave::kMinLevelClocks; ++half) {
      Harness h({.half_period = half, .mode3 = mode3});
      h.write(0x030, Words{0x0BADF00DU});
      EXPECT_EQ(h.bench.commits, 0U) << half;
      EXPECT_EQ(h.bench.mem[0x030], 0xA5000030U) << half;
      EXPECT_EQ(h.bench.slave.engine().active, UInt<1>{}) << "frame closed at cs_n rise";
      h.master = SpiMasterBfm({.half_period = SpiSlave::kMinLevelClocks, .mode3 = mode3});
      EXPECT_EQ(h.status(), SpiSlave::kStatusOverrun) << half;
      h.write(0x030, Words{0x600DF00DU});
      EXPECT_EQ(h.read(0x030, 1), Words{0x600DF00DU});
    }
}

TEST(SpiSlave, SnapshotOncePerFrameAtCsFall) {
  Harness h({.half_period = 6});
  const Bytes frame = spi_frame(SpiOp::kRead, 0x010, Words(3, 0), false);
  unsigned frames = 0;
  for (const std::size_t abort : {SpiMasterBfm::kNoAbort, std::size_t{0}, std::size_t{17}}) {
    h.bench.read_addresses.clear();
    const std::uint64_t start = h.bench.clock;
    h.run(frame, abort);
    EXPECT_EQ(h.bench.snapshots, ++frames);
    // cs_n falls in the BFM's 2nd clock; 2 synchroniser clocks + 1 to detect,
    // and the register side sees the strobe one clock later.
    EXPECT_EQ(h.bench.last_snapshot_clock, start + 4);
  }
}

TEST(SpiSlave, TraceMakesAWellFormedWaveform) {
  Harness h({.half_period = 4});
  std::stringstream out;
  odoloc::rtl::VcdWriter vcd(out);
  vcd.declare(h.bench.slave);
  std::uint64_t commit_clock = 0;
  h.master.transfer(spi_frame(SpiOp::kWrite, 0x008, Words{42}, false),
                    [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
                      const UInt<1> miso = h.bench.step(sclk, cs_n, mosi);
                      vcd.sample(h.bench.slave, h.bench.clock);
                      if (h.bench.slave.engine().commit)
                        commit_clock = h.bench.clock;
                      return miso;
                    });
  const auto wave = odoloc::tb::check_vcd(out);
  ASSERT_TRUE(wave.ok()) << wave.error_text();
  ASSERT_NE(commit_clock, 0U);
  EXPECT_EQ(wave.value_at("odoloc.engine.commit", commit_clock * odoloc::rtl::kFabricClockPeriodNs),
            1U);
  EXPECT_EQ(wave.value_at("odoloc.engine.commit_address",
                          commit_clock * odoloc::rtl::kFabricClockPeriodNs),
            8U);
}

// Random frames against a frame-level reference of memory and status.
TEST(SpiSlave, RandomFramesSeeded) {
  std::mt19937 rng(20261123);
  for (const bool mode3 : {false, true}) {
    Harness h({.half_period = 4, .mode3 = mode3}, false);
    std::array<std::uint32_t, 1024> ref = h.bench.mem;
    std::uint8_t expected_status = 0;
    for (int frame = 0; frame < 150; ++frame) {
      h.bench.crc_enable = rng() % 2 == 0;
      h.master =
          SpiMasterBfm({.half_period = 4 + static_cast<unsigned>(rng() % 6), .mode3 = mode3});
      const bool read = rng() % 2 == 0;
      const unsigned address = static_cast<unsigned>(rng() % 1024);
      const std::size_t n = 1 + rng() % 32;
      const Words words = random_words(rng, n);
      Bytes mosi =
          spi_frame(read ? SpiOp::kRead : SpiOp::kWrite, address, words, h.bench.crc_enable);
      const bool corrupt = h.bench.crc_enable && rng() % 8 == 0;
      if (corrupt)
        mosi.back() ^= 0x80;
      const std::size_t abort = rng() % 8 == 0 ? rng() % (mosi.size() * 8) : SpiMasterBfm::kNoAbort;
      const Bytes miso = h.run(mosi, abort);
      const std::size_t status_bits = std::min<std::size_t>(abort, 8);  // a cut frame samples fewer
      if (status_bits > 0) {
        const auto mask = static_cast<std::uint8_t>(0xFF00U >> status_bits);
        ASSERT_EQ(miso[0] & mask, expected_status & mask) << frame;
      }
      if (abort != SpiMasterBfm::kNoAbort) {
        expected_status = SpiSlave::kStatusBadLength;
        continue;
      }
      expected_status = 0;
      if (read) {
        for (std::size_t k = 0; k < n; ++k) {
          std::uint32_t got = 0;
          for (std::size_t b = 0; b < 4; ++b)
            got = got << 8U | miso[2 + 4 * k + b];
          ASSERT_EQ(got, ref[(address + k) % 1024]) << frame << " word " << k;
        }
        if (h.bench.crc_enable) {
          ASSERT_EQ(miso[4 * n + 2], crc8_j1850(std::span(miso).first(4 * n + 2)));
        }
      }
      if (corrupt) {  // reads too: a corrupted command must not count as read
        expected_status = SpiSlave::kStatusCrcError;
      } else if (!read) {
        for (std::size_t k = 0; k < n; ++k) {
          const std::size_t a = (address + k) % 1024;
          if (a >= kReadOnlyFirst)
            expected_status = SpiSlave::kStatusWriteRefused;
          else
            ref[a] = words[k];
        }
      }
      ASSERT_EQ(h.bench.mem, ref) << frame;
    }
  }
}

}  // namespace
