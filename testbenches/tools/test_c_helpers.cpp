// The C header's firmware helpers (docs/register-generator.md, "Firmware
// helpers"), compiled as C99 (c_helpers_tables.c, c_firmware.c), against
// references that share nothing with the generator:
//   - which fields are signed or split over two words: regmap/odoloc.yaml read
//     here with yaml-cpp, not through the generator's parser;
//   - sign extension: v >= 2^(w-1) ? v - 2^w : v in 128-bit arithmetic,
//     exhaustively for every signed field of at most 24 bits;
//   - CRC-8: polynomial long division of the augmented message (SAE J1850's
//     0x11D, init and final XOR 0xFF, check value 0x4B), and the C++ codecs
//     of the host (sw::crc8_j1850) and of the model (rtl::crc8_j1850);
//   - the command word and whole frames: docs/spi.md's layout, the host's
//     sw::encode_frame/decode_reply for every (op, count, address), and the
//     model's SPI slave, which must decode and accept them;
//   - the firmware driver of c_firmware.c on the simulated board (the host
//     tool's sim transport board::ChipLink: the chip model behind the
//     bit-level master), against the model's own count, speed and pose.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "c_helpers.h"
#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/board/spi_pin_master.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/spi_slave.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc/world/quadrature_source.hpp"

namespace {

namespace regs = odoloc::regs;
using odoloc::rtl::UInt;
using Bytes = std::vector<std::uint8_t>;
using Words = std::vector<std::uint32_t>;
__extension__ using Int128 = __int128;  // the reference's headroom over 64-bit values

// A 64-bit generator whose sequence is the same everywhere (std::mt19937_64).
struct Random {
  std::mt19937_64 engine{20240607};
  std::uint64_t operator()() { return engine(); }
  std::uint32_t word() { return static_cast<std::uint32_t>(engine()); }
};

std::uint64_t ones(int width) {
  return width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
}

// The value of `width` bits `raw` as two's complement, or unsigned.
Int128 reference_value(std::uint64_t raw, int width, bool is_signed) {
  const Int128 v = raw;
  if (is_signed && v >= (Int128{1} << (width - 1)))
    return v - (Int128{1} << width);
  return v;
}

// ---- The map, read straight from the YAML -----------------------------------

struct YamlField {
  std::string stem;  // the C helper's name between "odoloc_" and its suffix
  int lsb = 0, width = 0;
  bool is_signed = false, writable = false;
};

struct YamlFields {
  std::vector<YamlField> signed_words;  // one word's field or slice with the sign bit
  std::vector<YamlField> split;         // bits in both words of a words: 2 register
};

// The map's signed fields as the C header names their _get_signed (the
// slice holding the sign bit, lsb and width in that word) and its fields of
// two-word registers that have bits in both words (lsb in the 64-bit value).
YamlFields yaml_fields() {
  const YAML::Node root = YAML::LoadFile(ODOLOC_REGMAP_YAML);
  YamlFields out;
  for (const YAML::Node& b : root["blocks"]) {
    if (b["reserved"] && b["reserved"].as<bool>())
      continue;
    const auto block = b["name"].as<std::string>();
    for (const YAML::Node& r : b["registers"]) {
      const auto name = r["name"].as<std::string>();
      const bool wide = r["words"] && r["words"].as<int>() == 2;
      const int count = r["count"] ? r["count"].as<int>() : 0;
      for (const YAML::Node& f : r["fields"]) {
        const auto field = f["name"].as<std::string>();
        const int msb = f["bits"][0].as<int>(), lsb = f["bits"][1].as<int>();
        const bool is_signed = f["signed"] && f["signed"].as<bool>();
        const auto access = (f["access"] ? f["access"] : r["access"]).as<std::string>();
        if (wide && lsb < 32 && msb >= 32) {  // an array's elements share one set
          out.split.push_back(
              {block + "_" + name + "_" + field, lsb, msb - lsb + 1, is_signed, access == "rw"});
        }
        if (!is_signed)
          continue;
        const int first = wide && msb >= 32 ? std::max(lsb, 32) : lsb;
        const std::string word = wide ? (msb >= 32 ? "_hi" : "_lo") : "";
        for (int k = 0; k < std::max(count, 1); ++k) {
          const std::string element = count == 0 ? name : name + std::to_string(k);
          out.signed_words.push_back({block + "_" + element + word + "_" + field, first % 32,
                                      msb - first + 1, true, access == "rw"});
        }
      }
    }
  }
  return out;
}

template <class T>
std::set<std::string> names(std::span<const T> table) {
  std::set<std::string> out;
  for (const T& t : table)
    out.insert(t.name);
  return out;
}
template <class T>
const T& by_name(std::span<const T> table, const std::string& name) {
  for (const T& t : table) {
    if (t.name == name)
      return t;
  }
  throw std::invalid_argument("no C helper for " + name);
}

std::span<const tb_signed_field> signed_table() {
  return {tb_signed_fields, tb_signed_field_count};
}
std::span<const tb_split_field> split_table() {
  return {tb_split_fields, tb_split_field_count};
}

TEST(CHelpers, TheTablesNameEverySignedAndSplitFieldOfTheMap) {
  const YamlFields y = yaml_fields();
  std::set<std::string> want_signed, want_split;
  for (const YamlField& f : y.signed_words)
    want_signed.insert(f.stem);
  for (const YamlField& f : y.split)
    want_split.insert(f.stem);
  EXPECT_EQ(names(signed_table()), want_signed);
  EXPECT_EQ(names(split_table()), want_split);
  EXPECT_EQ(want_signed.size(), 16U);  // eppm count/latched/speed/pulse_last, odometry's
  EXPECT_EQ(want_split.size(), 13U);   // the pose, increments, steer_phi, set_*
  for (const YamlField& f : y.split) {
    const tb_split_field& c = by_name(split_table(), f.stem);
    EXPECT_EQ(c.join_signed != nullptr, f.is_signed) << f.stem;
    EXPECT_EQ(c.join_unsigned != nullptr, !f.is_signed) << f.stem;
    EXPECT_EQ(c.set_lo_signed != nullptr || c.set_lo_unsigned != nullptr, f.writable) << f.stem;
  }
}

// ---- (a) sign extension ---------------------------------------------------------

TEST(CHelpers, SignExtensionOfEverySignedField) {
  Random rng;
  std::uint64_t exhaustive = 0, sampled = 0, wrong = 0;
  for (const YamlField& f : yaml_fields().signed_words) {
    SCOPED_TRACE(f.stem);
    const tb_signed_field& c = by_name(signed_table(), f.stem);
    const std::uint32_t mask = static_cast<std::uint32_t>(ones(f.width) << f.lsb);
    const std::uint64_t salt = rng();
    const auto check = [&](std::uint64_t v) {
      // The word's other bits are noise the helper must ignore (a multiplicative
      // hash of v: cheaper than the generator, over 1e8 values).
      const auto noise = static_cast<std::uint32_t>((v + salt) * 0x9E3779B97F4A7C15U >> 32U);
      const std::uint32_t word = static_cast<std::uint32_t>(v << f.lsb) | (noise & ~mask);
      const std::int32_t got = c.get_signed(word);
      if (Int128{got} != reference_value(v, f.width, true) && wrong++ < 5) {
        ADD_FAILURE() << "word 0x" << std::hex << word << " gives " << std::dec << got;
      }
    };
    if (f.width <= 24) {
      for (std::uint64_t v = 0; v <= ones(f.width); ++v)
        check(v);
      exhaustive += ones(f.width) + 1;
    } else {  // the edges, every power of two and its neighbours, 2^20 random values
      const std::uint64_t sign = std::uint64_t{1} << (f.width - 1);
      std::vector<std::uint64_t> values{
          0, 1, 2, sign - 1, sign, sign + 1, ones(f.width) - 1, ones(f.width)};
      for (int k = 0; k < f.width; ++k) {
        for (const std::uint64_t d : {std::uint64_t{0}, std::uint64_t{1}, ones(f.width)})
          values.push_back(((std::uint64_t{1} << k) + d) & ones(f.width));
      }
      for (int i = 0; i < (1 << 20); ++i)
        values.push_back(rng() & ones(f.width));
      for (const std::uint64_t v : values)
        check(v);
      sampled += values.size();
    }
  }
  EXPECT_EQ(wrong, 0U);
  EXPECT_GT(exhaustive, 100'000'000U);  // six 24-bit fields alone are 1e8 values
  std::printf("sign extension: %llu values exhaustively (fields <= 24 bits), %llu sampled\n",
              static_cast<unsigned long long>(exhaustive),
              static_cast<unsigned long long>(sampled));
}

// ---- (b) joins and splits of two-word fields -------------------------------------

// The edge values of a `width`-bit field, as the bits they occupy.
std::vector<std::uint64_t> edge_values(int width, bool is_signed, Random& rng) {
  const std::uint64_t all = ones(width), sign = std::uint64_t{1} << (width - 1);
  std::vector<std::uint64_t> v{0,
                               1,
                               all,
                               all - 1,
                               sign,
                               sign - 1,
                               sign + 1,
                               0x80000000U,
                               0x7FFFFFFFU,
                               0xFFFFFFFFU,
                               std::uint64_t{1} << 32};
  if (is_signed)  // -123456789012345 where it fits (the pose test's x)
    v.push_back(static_cast<std::uint64_t>(-123'456'789'012'345) & all);
  for (int i = 0; i < 200; ++i)
    v.push_back(rng() & all);
  for (std::uint64_t& x : v)
    x &= all;
  return v;
}

TEST(CHelpers, SplitFieldsJoinTheirWordsAndSplitValuesBack) {
  Random rng;
  std::uint64_t joins = 0, splits = 0;
  const std::vector<std::uint32_t> edge_words{0,           1,           0x7FFFFFFFU, 0x80000000U,
                                              0x80000001U, 0xFFFFFFFEU, 0xFFFFFFFFU, 0x000000FFU,
                                              0x00000080U, 0x00008000U, 0x00800000U};
  for (const YamlField& f : yaml_fields().split) {
    SCOPED_TRACE(f.stem);
    const tb_split_field& c = by_name(split_table(), f.stem);
    const auto join = [&](std::uint32_t lo, std::uint32_t hi) {
      return f.is_signed ? Int128{c.join_signed(lo, hi)} : Int128{c.join_unsigned(lo, hi)};
    };
    // Every pair of edge words and random words: the field's bits of hi:lo.
    std::vector<std::uint32_t> words = edge_words;
    for (int i = 0; i < 64; ++i)
      words.push_back(rng.word());
    for (const std::uint32_t lo : words) {
      for (const std::uint32_t hi : words) {
        const std::uint64_t raw = ((std::uint64_t{hi} << 32 | lo) >> f.lsb) & ones(f.width);
        ASSERT_EQ(join(lo, hi), reference_value(raw, f.width, f.is_signed))
            << std::hex << "lo 0x" << lo << " hi 0x" << hi;
        ++joins;
      }
    }
    if (!f.writable)
      continue;
    // Written: the field's bits land where the map says, the others are kept.
    const std::uint64_t field_mask = ones(f.width) << f.lsb;
    for (const std::uint64_t bits : edge_values(f.width, f.is_signed, rng)) {
      const std::uint32_t lo0 = rng.word(), hi0 = rng.word();
      const Int128 value = reference_value(bits, f.width, f.is_signed);
      std::uint32_t lo = 0, hi = 0;
      if (f.is_signed) {
        lo = c.set_lo_signed(lo0, static_cast<std::int64_t>(value));
        hi = c.set_hi_signed(hi0, static_cast<std::int64_t>(value));
      } else {
        lo = c.set_lo_unsigned(lo0, static_cast<std::uint64_t>(value));
        hi = c.set_hi_unsigned(hi0, static_cast<std::uint64_t>(value));
      }
      const std::uint64_t before = std::uint64_t{hi0} << 32 | lo0;
      const std::uint64_t want = (before & ~field_mask) | (bits << f.lsb);
      ASSERT_EQ(std::uint64_t{hi} << 32 | lo, want) << std::hex << "value bits 0x" << bits;
      ASSERT_EQ(join(lo, hi), value);
      ++splits;
    }
  }
  std::printf("two-word fields: %llu joins, %llu split writes checked\n",
              static_cast<unsigned long long>(joins), static_cast<unsigned long long>(splits));
}

// ---- (c) CRC-8 ----------------------------------------------------------------

// SAE J1850 by polynomial long division: init 0xFF XORed into the first 8 bits
// of the message followed by 8 zero bits, divided by x^8+x^4+x^3+x^2+1
// (0x11D); the remainder XOR 0xFF. A different algorithm from every codec.
std::uint8_t crc8_long_division(std::span<const std::uint8_t> bytes) {
  std::vector<int> bits;
  for (const std::uint8_t b : bytes) {
    for (int i = 7; i >= 0; --i)
      bits.push_back((b >> i) & 1);
  }
  bits.insert(bits.end(), 8, 0);
  for (int i = 0; i < 8; ++i)
    bits[static_cast<std::size_t>(i)] ^= 1;  // init 0xFF
  constexpr unsigned kPoly = 0x11D;
  for (std::size_t i = 0; i + 8 < bits.size(); ++i) {
    if (bits[i] == 0)
      continue;
    for (int k = 0; k <= 8; ++k)
      bits[i + static_cast<std::size_t>(k)] ^= static_cast<int>((kPoly >> (8 - k)) & 1U);
  }
  unsigned rem = 0;
  for (std::size_t i = bits.size() - 8; i < bits.size(); ++i)
    rem = rem << 1U | static_cast<unsigned>(bits[i]);
  return static_cast<std::uint8_t>(rem ^ 0xFFU);
}

std::uint8_t c_crc(std::span<const std::uint8_t> bytes) {
  return tb_spi_crc8(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
}

TEST(CHelpers, Crc8IsSaeJ1850AsTheHostAndTheModelComputeIt) {
  // The catalogue's check value, and the parameters of docs/spi.md.
  const Bytes check{'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(c_crc(check), 0x4B);
  EXPECT_EQ(crc8_long_division(check), 0x4B);
  EXPECT_EQ(tb_spi.crc_polynomial, 0x1DU);
  EXPECT_EQ(tb_spi.crc_init, 0xFFU);
  EXPECT_EQ(tb_spi.crc_xor_out, 0xFFU);
  EXPECT_EQ(tb_spi.crc_polynomial, regs::spi::kCrcPolynomial);  // one source: spi.crc
  EXPECT_EQ(tb_spi.crc_init, regs::spi::kCrcInit);
  EXPECT_EQ(tb_spi.crc_xor_out, regs::spi::kCrcXorOut);
  // Every message of 0, 1 and 2 bytes.
  std::uint64_t messages = 0;
  EXPECT_EQ(c_crc({}), crc8_long_division({}));
  for (unsigned a = 0; a < 256; ++a) {
    const Bytes one{static_cast<std::uint8_t>(a)};
    ASSERT_EQ(c_crc(one), crc8_long_division(one)) << a;
    for (unsigned b = 0; b < 256; ++b) {
      const Bytes two{static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b)};
      ASSERT_EQ(c_crc(two), crc8_long_division(two)) << a << " " << b;
    }
    messages += 257;
  }
  // Random messages of every frame length, through all four implementations
  // and byte by byte through crc8_update.
  Random rng;
  for (std::size_t n = 0; n <= tb_spi.frame_max_bytes; ++n) {
    for (int i = 0; i < 20; ++i, ++messages) {
      Bytes m(n);
      for (std::uint8_t& b : m)
        b = static_cast<std::uint8_t>(rng());
      const std::uint8_t want = crc8_long_division(m);
      ASSERT_EQ(c_crc(m), want) << n;
      ASSERT_EQ(odoloc::sw::crc8_j1850(m), want) << n;
      ASSERT_EQ(odoloc::rtl::crc8_j1850(m), want) << n;
      auto crc = static_cast<std::uint8_t>(tb_spi.crc_init);
      for (const std::uint8_t b : m)
        crc = tb_spi_crc8_update(crc, b);
      ASSERT_EQ(crc ^ tb_spi.crc_xor_out, want) << n;
    }
  }
  std::printf("CRC-8: %llu messages against long division\n",
              static_cast<unsigned long long>(messages + 1));
}

// ---- (d) the command word and whole frames --------------------------------------

Bytes c_encode(bool read, std::uint32_t address, std::uint32_t count, const Words& words,
               bool crc) {
  Bytes frame(tb_spi.frame_max_bytes + 1, 0xA5);
  const std::uint32_t n = tb_spi_encode(frame.data(), read, address, count,
                                        words.empty() ? nullptr : words.data(), crc);
  frame.resize(n);
  return frame;
}

TEST(CHelpers, CommandWordAndFramesAreTheHostsForEveryCommand) {
  // One definition: the generator's layout in regs.hpp and in the C header.
  EXPECT_EQ(tb_spi.command_read, 1U << regs::spi::kCommandReadBit);
  EXPECT_EQ(tb_spi.burst_shift, regs::spi::kCommandBurstShift);
  EXPECT_EQ(tb_spi.burst_mask, ((1U << regs::spi::kCommandBurstBits) - 1)
                                   << regs::spi::kCommandBurstShift);
  EXPECT_EQ(tb_spi.address_mask, (1U << regs::spi::kCommandAddressBits) - 1);
  EXPECT_EQ(tb_spi.max_burst, regs::spi::kMaxBurst);
  EXPECT_EQ(tb_spi.frame_max_bytes, 2 + 4 * regs::spi::kMaxBurst + 1);
  Random rng;
  std::uint64_t commands = 0;
  for (const bool read : {false, true}) {
    for (std::uint32_t count = 1; count <= 32; ++count) {
      for (std::uint32_t address = 0; address < 1024; ++address, ++commands) {
        // docs/spi.md: bit 15 read, bits 14:10 count - 1, bits 9:0 the address.
        std::uint16_t command = 0;
        ASSERT_TRUE(tb_spi_command(&command, read, address, count));
        ASSERT_EQ(command, (read ? 0x8000U : 0U) | (count - 1) << 10 | address);
        Words words(count);
        for (std::uint32_t& w : words)
          w = rng.word();
        const bool crc = (address & 1U) != 0;
        const auto op = read ? odoloc::sw::SpiOp::kRead : odoloc::sw::SpiOp::kWrite;
        ASSERT_EQ(
            c_encode(read, address, count, words, crc),
            odoloc::sw::encode_frame(op, static_cast<std::uint16_t>(address), count, words, crc))
            << read << " " << count << " " << address;
        ASSERT_EQ(tb_spi_frame_bytes(count, crc), 2 + 4 * count + (crc ? 1U : 0U));
      }
    }
  }
  EXPECT_EQ(commands, 65536U);
  // What no frame can carry: refused, nothing written.
  for (const auto& [address, count] : std::vector<std::pair<std::uint32_t, std::uint32_t>>{
           {0, 0}, {0, 33}, {0, 0xFFFFFFFFU}, {0x400, 1}, {0xFFFFFFFFU, 1}, {0x3FF, 0}}) {
    std::uint16_t command = 0x1234;
    EXPECT_FALSE(tb_spi_command(&command, true, address, count)) << address << " " << count;
    EXPECT_EQ(command, 0x1234U);
    Bytes frame(8, 0xA5);
    EXPECT_EQ(tb_spi_encode(frame.data(), false, address, count, nullptr, true), 0U);
    EXPECT_EQ(frame, Bytes(8, 0xA5));
  }
}

TEST(CHelpers, ReplyDecodingIsTheHostsAndRefusesEveryCorruptedBit) {
  Random rng;
  for (std::uint32_t count = 1; count <= 32; ++count) {
    for (const bool crc : {false, true}) {
      Bytes miso(tb_spi_frame_bytes(count, crc));
      for (std::uint8_t& b : miso)
        b = static_cast<std::uint8_t>(rng());
      if (crc)
        miso.back() = odoloc::sw::crc8_j1850(std::span(miso).first(miso.size() - 1));
      const odoloc::sw::FrameReply want = odoloc::sw::decode_reply(miso, count, crc);
      Words words(count);
      std::uint8_t status = 0;
      ASSERT_TRUE(tb_spi_decode(miso.data(), count, crc, &status, words.data()));
      EXPECT_EQ(status, want.status);
      EXPECT_EQ(words, want.words);
      if (!crc)
        continue;
      for (std::size_t bit = 0; bit < miso.size() * 8; ++bit) {
        Bytes bad = miso;
        bad[bit / 8] = static_cast<std::uint8_t>(bad[bit / 8] ^ (0x80U >> (bit % 8)));
        Words untouched(count, 0x5A5A5A5AU);
        std::uint8_t s = 0x77;
        ASSERT_FALSE(tb_spi_decode(bad.data(), count, crc, &s, untouched.data())) << bit;
        EXPECT_EQ(s, 0x77);
        EXPECT_EQ(untouched, Words(count, 0x5A5A5A5AU));
      }
    }
  }
  std::uint8_t status = 0;
  const Bytes zeros(200, 0);
  EXPECT_FALSE(tb_spi_decode(zeros.data(), 0, false, &status, nullptr));
  EXPECT_FALSE(tb_spi_decode(zeros.data(), 33, false, &status, nullptr));
}

// The model's SPI slave alone, with a 1024-word register side: what its own
// decoder makes of the C header's frames.
struct SlaveBench {
  odoloc::rtl::SpiSlave slave;
  std::array<std::uint32_t, 1024> mem{};
  bool crc = false;
  struct Commit {
    bool write;
    unsigned address, count;
  };
  std::vector<Commit> commits;
  std::vector<unsigned> reads;  // the words the slave fetched, in order
  odoloc::board::SpiPinMaster master{{.half_period = 4}};

  SlaveBench() {
    for (unsigned a = 0; a < mem.size(); ++a)
      mem[a] = 0xC0DE0000U | a;
  }
  UInt<1> step(UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
    const odoloc::rtl::SpiRegisterPort r = slave.port();
    if (r.read_strobe)
      reads.push_back(static_cast<unsigned>(r.read_address.value()));
    if (r.commit) {
      commits.push_back({r.commit_write.value() != 0,
                         static_cast<unsigned>(r.commit_address.value()),
                         static_cast<unsigned>(r.commit_count.value())});
      for (unsigned k = 0; r.commit_write && k < r.commit_count.value(); ++k)
        mem[(r.commit_address.value() + k) % mem.size()] =
            static_cast<std::uint32_t>(r.words[k].value.value());
    }
    slave.step({.sclk = sclk,
                .cs_n = cs_n,
                .mosi = mosi,
                .crc_enable = UInt<1>::truncate(crc ? 1 : 0),
                .spi_mode3 = {},
                .read_data = UInt<32>{mem[r.read_address.value()]},
                .write_refused = {},
                .reset = {}});
    return slave.miso();
  }
  Bytes transfer(const Bytes& mosi) {
    commits.clear();
    reads.clear();
    return master.transfer(mosi, [this](UInt<1> s, UInt<1> c, UInt<1> m) { return step(s, c, m); });
  }
};

TEST(CHelpers, TheModelsSlaveDecodesTheCommandWordAndChecksTheCrc) {
  SlaveBench b;
  Random rng;
  unsigned frames = 0;
  // Every burst length at the edges of the address space (the last ones wrap)
  // and a random address; every address with one word.
  std::vector<std::tuple<bool, std::uint32_t, std::uint32_t>> cases;
  for (const bool read : {false, true}) {
    for (std::uint32_t count = 1; count <= 32; ++count) {
      for (const std::uint32_t address :
           {0U, 0x155U, 0x3FFU - count / 2, 0x3FFU, rng.word() % 1024})
        cases.emplace_back(read, address, count);
    }
    for (std::uint32_t address = 0; address < 1024; ++address)
      cases.emplace_back(read, address, 1);
  }
  for (const bool crc : {false, true}) {
    b.crc = crc;
    for (const auto& [read, address, count] : cases) {
      SCOPED_TRACE(std::to_string(read) + " " + std::to_string(address) + " " +
                   std::to_string(count) + " crc " + std::to_string(crc));
      Words words(count);
      for (std::uint32_t& w : words)
        w = rng.word();
      const auto before = b.mem;
      const Bytes miso = b.transfer(c_encode(read, address, count, words, crc));
      ++frames;
      ASSERT_EQ(b.commits.size(), 1U);
      EXPECT_EQ(b.commits[0].write, !read);
      EXPECT_EQ(b.commits[0].address, address);
      EXPECT_EQ(b.commits[0].count, count);
      Words got(count);
      std::uint8_t status = 0xFF;
      ASSERT_TRUE(tb_spi_decode(miso.data(), count, crc, &status, got.data()));  // MISO CRC
      EXPECT_EQ(status, 0U);  // the previous frame was good too
      for (std::uint32_t k = 0; k < count; ++k) {
        const std::size_t a = (address + k) % 1024;
        if (read) {
          ASSERT_EQ(b.reads.at(k), a);
          EXPECT_EQ(got[k], before[a]);
        } else {
          EXPECT_EQ(b.mem[a], words[k]);
        }
      }
    }
  }
  // A frame whose CRC byte is off by one bit commits nothing, and the next
  // frame's status byte says why.
  b.crc = true;
  for (int bit = 0; bit < 8; ++bit) {
    Bytes bad = c_encode(false, 0x10, 1, Words{0xBADC0DEU}, true);
    bad.back() = static_cast<std::uint8_t>(bad.back() ^ (1U << bit));
    const std::uint32_t kept = b.mem[0x10];
    b.transfer(bad);
    EXPECT_TRUE(b.commits.empty()) << bit;
    EXPECT_EQ(b.mem[0x10], kept);
    const Bytes next = b.transfer(c_encode(true, 0, 1, {}, true));
    EXPECT_EQ(next[0], regs::top::spi_status::crc_error.mask()) << bit;
    frames += 2;
  }
  std::printf("model's slave: %u frames built by the C helpers\n", frames);
}

// ---- The firmware driver on the simulated board ---------------------------------

// The host tool's sim transport: the chip model behind the bit-level master,
// one quadrature source per encoder pin pair. The C firmware's frames go
// through it as bytes; `corrupt_next` flips one bit of the next frame's CRC.
struct SimBoard {
  std::array<odoloc::world::QuadratureSource, 4> sources;
  odoloc::board::ChipLink link{{.half_period = 4}, [this](odoloc::rtl::ChipPins& pins) {
                                 for (std::size_t w = 0; w < sources.size(); ++w)
                                   pins.encoders[w] =
                                       odoloc::board::encoder_pins(sources[w].tick());
                               }};
  bool corrupt_next = false;
  tb_firmware fw{&SimBoard::transfer, this, false, 0};

  static void transfer(void* self, const std::uint8_t* mosi, std::uint8_t* miso,
                       std::uint32_t bytes) {
    auto& b = *static_cast<SimBoard*>(self);
    Bytes out(mosi, mosi + bytes);
    if (std::exchange(b.corrupt_next, false))
      out.back() = static_cast<std::uint8_t>(out.back() ^ 1U);
    b.link.transfer(out, std::span(miso, bytes));
  }
  [[nodiscard]] const odoloc::rtl::Eppm& left_rear() const {
    return link.chip().fabric().encoders().eppm(odoloc::rtl::Encoder::kLeftRear);
  }
};

TEST(CFirmwareOnTheSimulatedBoard, ReadsTheCountBackwardsAndANegativePose) {
  static_assert(regs::eppm::kInstanceNames[0] == "left_rear");
  constexpr std::uint32_t kLeftRear = 0;  // eppm instance 0 = encoder pins 0
  static_assert(static_cast<std::size_t>(odoloc::rtl::Encoder::kLeftRear) == kLeftRear);
  SimBoard b;
  ASSERT_TRUE(tb_fw_enable_crc(&b.fw));  // from here on every frame carries the C CRC-8
  ASSERT_TRUE(b.link.chip().config().top.ctrl.crc_enable);
  ASSERT_TRUE(tb_fw_stop_odometry(&b.fw));  // no latch-and-clear of the count
  EXPECT_EQ(b.fw.last_status, 0U);

  // Backwards at 0.05 edges per clock: 2500 edges per 50000-clock window.
  b.sources[kLeftRear].set_rate(-0.05);
  b.link.advance(200'000);
  std::int32_t speed = 0;
  bool pulse = false;
  const auto model_speed = [&] {
    return b.left_rear().status(b.link.chip().config().eppm[kLeftRear]).speed.value.value();
  };
  const std::int64_t speed_before = model_speed();
  ASSERT_TRUE(tb_fw_read_speed(&b.fw, kLeftRear, &speed, &pulse));
  ASSERT_EQ(model_speed(), speed_before);  // no window ended during the frame
  EXPECT_TRUE(pulse);
  EXPECT_EQ(speed, speed_before);
  EXPECT_NEAR(speed, -2500, 1);

  b.sources[kLeftRear].set_rate(0.0);
  b.link.advance(1000);  // the last edges through the input filter
  std::int32_t count = 0;
  ASSERT_TRUE(tb_fw_read_count(&b.fw, kLeftRear, &count));
  EXPECT_EQ(count, b.left_rear().count().value());
  EXPECT_EQ(count, b.sources[kLeftRear].edges());  // every edge the pins made, signed
  EXPECT_LT(count, -9000);
  EXPECT_EQ(b.fw.last_status, 0U);

  // set_pose with a negative x, y = -1 (all ones) and a 40-bit theta.
  const std::int64_t x = -123'456'789'012'345, y = -1;
  const std::uint64_t theta = 0xAB'1234'5678;
  ASSERT_TRUE(tb_fw_set_pose(&b.fw, x, y, theta));
  std::int64_t gx = 0, gy = 0;
  std::uint64_t gtheta = 0;
  ASSERT_TRUE(tb_fw_read_pose(&b.fw, &gx, &gy, &gtheta));
  EXPECT_EQ(b.fw.last_status, 0U);  // the set_pose command frame was good
  const auto& pose = b.link.chip().fabric().pose();
  EXPECT_EQ(odoloc::rtl::pose_coordinate(pose.x).value(), x);
  EXPECT_EQ(odoloc::rtl::pose_coordinate(pose.y).value(), y);
  EXPECT_EQ(pose.theta.value(), theta);
  EXPECT_EQ(gx, x);
  EXPECT_EQ(gy, y);
  EXPECT_EQ(gtheta, theta);

  // A write whose CRC the link corrupts is discarded and flagged in the next
  // frame's status; the same write with the C CRC lands.
  const std::uint32_t scratch = 0x600DF00DU;
  b.corrupt_next = true;
  ASSERT_TRUE(tb_fw_write(&b.fw, regs::top::scratch::kAddress, 1, &scratch));
  std::uint32_t read_back = 1;
  ASSERT_TRUE(tb_fw_read(&b.fw, regs::top::scratch::kAddress, 1, &read_back));
  EXPECT_EQ(b.fw.last_status, regs::top::spi_status::crc_error.mask());
  EXPECT_EQ(read_back, 0U);
  ASSERT_TRUE(tb_fw_write(&b.fw, regs::top::scratch::kAddress, 1, &scratch));
  ASSERT_TRUE(tb_fw_read(&b.fw, regs::top::scratch::kAddress, 1, &read_back));
  EXPECT_EQ(b.fw.last_status, 0U);
  EXPECT_EQ(read_back, scratch);
}

}  // namespace
