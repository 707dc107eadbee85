// rtl::SpiSlave and rtl::FabricRegisters, wired as in rtl::OdolocChip, behind
// the register file kernel's ports (hls/regfile_kernel.hpp): one call = one
// SPI transaction, driven at pin level by board::SpiPinMaster, the fabric's
// status held for the whole frame. The model's results are read back the way
// the fabric sees them: the MISO bits the master sampled, the one-clock
// pulses (ports::Pulses) seen in any clock of the transaction, the stored
// configuration words, the slave's status and top.spi_status/frame_errors.
//
// Nothing here comes from the kernel's tables: the column lists are built from
// odoloc/regs.hpp, and the status and pulse words from the generated
// ports.hpp coders, probed bit by bit (ports.hpp has encode_status and
// decode_pulses, not their inverses).
//
// Stimulus, per call:
// - 1 in 512 a reset (no frame).
// - 1 in 4 a new fabric status: every status port at random, 1/8 of them 0
//   and 1/8 all ones; else the previous one.
// - 45 % reads, 55 % writes. Start address: 50 % a mapped register (writes: one
//   that takes writes), 10 % an rpop FIFO's first word (writes: any mapped
//   register), 10 % the top block (ctrl, spi_status, frame_errors), 3 % near
//   1023 (bursts wrap to 0), 27 % any of the 1024 (unmapped, reserved). Burst:
//   1 word (55 %), 2-4 (30 %), 5-32 (15 %): long bursts cost the most clocks.
// - Data: random, 0, all ones or single bits (w1c clears, w1p commands);
//   words past the burst random (ignored). A write over top.ctrl keeps its
//   value 7 times in 8 (CRC framing and SPI mode change rarely).
// - Frame: 79 % well formed (with a good CRC when crc_enable); 5 % cut short
//   anywhere, 2 % inside the command, 3 % too long, 4 % a corrupted CRC (when
//   crc_enable), 3 % the length of the other CRC setting, 4 % too fast (SCLK
//   levels of 3 fabric clocks: overrun), cut short half the time.
#include <algorithm>
#include <cstdint>
#include <iterator>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "odoloc/board/spi_pin_master.hpp"
#include "odoloc/ports.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/fabric_registers.hpp"
#include "odoloc/rtl/spi_slave.hpp"
#include "odoloc/verification/reference.hpp"

namespace odoloc::verification {

namespace {

using rtl::UInt;

constexpr unsigned kMaxBurst = regs::spi::kMaxBurst;
constexpr unsigned kAddressSpace = 1U << regs::kAddressBits;
// The command (docs/spi.md): [15] read, [14:10] burst length - 1, [9:0] address.
constexpr unsigned kReadBit = 15;
constexpr unsigned kBurstMask = (1U << (kReadBit - regs::kAddressBits)) - 1;
constexpr unsigned kHeaderBits = 16;
constexpr unsigned kWordBits = 32;
constexpr unsigned kCrcBits = 8;
constexpr unsigned kNormalHalfPeriod = regs::spi::kMinLevelClocks;
constexpr unsigned kFastHalfPeriod = regs::spi::kMinLevelClocks - 1;  // seen, but an overrun
constexpr unsigned kSettleClocks = 4;  // after a reset: the synchronisers see the idle pins
// cs_n high after a frame: the slave sees the rise in the 3rd clock, the
// register file commits in the 4th and its pulses show in the 5th.
constexpr unsigned kIdleClocks = 8;

// A port of a ports:: struct (UInt<W> or SInt<W>) as raw bits, and back.
template <class P>
std::uint64_t raw(const P& port) {
  if constexpr (requires { port.raw_bits(); })
    return port.raw_bits();
  else
    return port.value();
}
template <class P>
void set_raw(P& port, std::uint64_t bits) {
  if constexpr (requires { port.raw_bits(); })
    port = P::truncate(static_cast<std::int64_t>(bits));
  else
    port = P::truncate(bits);
}
// f(index, port) for every port of a whole-map ports:: struct, in order.
template <class S, class F>
void each_port(S& s, F&& f) {
  std::size_t i = 0;
  std::remove_const_t<S>::for_each_port(s, [&](std::string_view, int, std::string_view, int,
                                               std::string_view, auto& port) { f(i++, port); });
}

// Bits `width` of port `port` from bit `port_lsb` sit in word `word` from bit
// `word_lsb`.
struct Segment {
  std::size_t port;
  int port_lsb;
  std::size_t word;
  int word_lsb, width;
};

// Merges single-bit links into runs.
void add_bit(std::vector<Segment>& segments, std::size_t port, int port_bit, std::size_t word,
             int word_bit) {
  if (!segments.empty()) {
    Segment& s = segments.back();
    if (s.port == port && s.word == word && s.port_lsb + s.width == port_bit &&
        s.word_lsb + s.width == word_bit) {
      ++s.width;
      return;
    }
  }
  segments.push_back({port, port_bit, word, word_bit, 1});
}

std::uint64_t low_bits(int width) {
  return width >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << width) - 1;
}

std::string_view path_of(unsigned address) {
  for (const regs::Register& r : regs::kRegisters)
    if (r.address == address)
      return r.path;
  return {};
}

std::string column(std::string_view path) {
  std::string name(path);
  for (char& c : name)
    c = c == '.' ? '_' : c;
  return name;
}

class RegfileReference final : public Reference {
 public:
  explicit RegfileReference(std::uint64_t seed) : rng_(seed) {
    map_status();
    map_pulses();
    for (const regs::Register& r : regs::kRegisters)
      if (r.rw_mask != 0)
        stored_.push_back(r.address);
    for (const regs::Register& r : regs::kRegisters)
      if ((r.w1c_mask | r.w1p_mask) != 0)
        pulsed_.push_back(r.address);
    for (const regs::Register& r : regs::kRegisters) {
      mapped_.push_back(r.address);
      if ((r.rw_mask | r.w1c_mask | r.w1p_mask) != 0)
        writable_.push_back(r.address);
    }
    name_columns();
    status_words_.assign(status_regs_.size(), 0);
    draw_status();
  }

  [[nodiscard]] std::span<const std::string_view> input_names() const override { return in_; }
  [[nodiscard]] std::span<const std::string_view> output_names() const override { return out_; }

  void stimulus(std::span<std::int64_t> in) override {
    std::fill(in.begin(), in.end(), 0);
    if (chance(512)) {
      in[kReset] = 1;
      return;
    }
    if (chance(4))
      draw_status();
    std::copy(status_words_.begin(), status_words_.end(),
              in.begin() + static_cast<std::ptrdiff_t>(kStatus));
    const bool read = draw(100) < 45;
    const unsigned count = burst();
    const unsigned start = start_address(read);
    const std::uint32_t command =
        (read ? 1U : 0U) << kReadBit | (count - 1) << regs::kAddressBits | start;
    in[kCommand] = command;
    std::vector<std::uint8_t> bytes{static_cast<std::uint8_t>(command >> 8),
                                    static_cast<std::uint8_t>(command)};
    const std::uint32_t ctrl = stored_word(regs::top::ctrl::kAddress);
    for (unsigned k = 0; k < kMaxBurst; ++k) {
      std::uint32_t word = data_word();
      if (!read && k < count && (start + k) % kAddressSpace == regs::top::ctrl::kAddress &&
          !chance(8))
        word = ctrl;
      in[kData + k] = word;
      if (k < count)
        for (int b = 24; b >= 0; b -= 8)
          bytes.push_back(static_cast<std::uint8_t>(word >> b));
    }
    const bool crc_on = regs::top::ctrl::crc_enable.get(ctrl) != 0;
    const std::uint8_t good_crc = rtl::crc8_j1850(bytes);
    in[kCrc] = crc_on ? good_crc : static_cast<std::uint8_t>(rng_());
    const unsigned end = kHeaderBits + kWordBits * count;
    const unsigned expected = end + (crc_on ? kCrcBits : 0);
    unsigned bits = expected;
    const unsigned form = draw(100);
    if (form < 5) {
      bits = draw(expected);  // cs_n raised early
    } else if (form < 7) {
      bits = draw(kHeaderBits + 1);
    } else if (form < 10) {
      bits = expected + 1 + draw(40);
    } else if (form < 14) {
      if (crc_on)
        in[kCrc] = good_crc ^ (1U + draw(255));
    } else if (form < 17) {
      bits = crc_on ? end : end + kCrcBits;
    } else if (form < 21) {
      in[kOverrun] = 1;
      if (chance(2))
        bits = 1 + draw(expected);  // at least one SCLK edge: the short level is seen
    }
    in[kBits] = bits;
  }

  void step(std::span<const std::int64_t> in, std::span<std::int64_t> out) override {
    std::fill(out.begin(), out.end(), 0);
    pulse_words_.assign(pulsed_.size(), 0);
    pops_.assign(std::size(regs::kPopWindows), 0);
    if (in[kReset] != 0) {
      clock(UInt<1>{}, UInt<1>{1}, UInt<1>{}, UInt<1>{1});
      for (unsigned c = 0; c < kSettleClocks; ++c)
        clock(UInt<1>{}, UInt<1>{1}, UInt<1>{}, UInt<1>{});
    } else {
      set_status(in.subspan(kStatus, status_regs_.size()));
      transfer(in, out);
    }
    out[kFrameStatus] = static_cast<std::int64_t>(spi_.engine().status.value());
    out[kSpiStatus] = static_cast<std::int64_t>(registers_.regs().spi_status.value());
    out[kFrameErrors] = static_cast<std::int64_t>(registers_.regs().frame_errors.value());
    std::size_t o = kConfig;
    for (const unsigned address : stored_)
      out[o++] = static_cast<std::int64_t>(stored_word(address));
    for (const std::uint32_t word : pulse_words_)
      out[o++] = word;
    for (const unsigned pops : pops_)
      out[o++] = pops;
  }

 private:
  // Column indices.
  static constexpr std::size_t kReset = 0, kCommand = 1, kData = 2, kCrc = kData + kMaxBurst,
                               kBits = kCrc + 1, kOverrun = kBits + 1, kStatus = kOverrun + 1;
  static constexpr std::size_t kMisoHeader = 0, kMisoData = 1, kMisoCrc = kMisoData + kMaxBurst,
                               kFrameStatus = kMisoCrc + 1, kSpiStatus = kFrameStatus + 1,
                               kFrameErrors = kSpiStatus + 1, kConfig = kFrameErrors + 1;

  // ---- stimulus ----
  unsigned draw(std::size_t n) { return static_cast<unsigned>(rng_() % n); }
  bool chance(unsigned one_in) { return draw(one_in) == 0; }

  unsigned burst() {
    const unsigned kind = draw(20);
    if (kind < 11)
      return 1;
    return kind < 17 ? 2 + draw(3) : 5 + draw(kMaxBurst - 4);
  }
  unsigned start_address(bool read) {
    const unsigned kind = draw(100);
    if (kind < 50)  // writes: one that takes the write (rw, w1c, w1p)
      return read ? pick(mapped_) : pick(writable_);
    if (kind < 60)
      return read ? regs::kPopWindows[draw(std::size(regs::kPopWindows))].first : pick(mapped_);
    if (kind < 70)
      return draw(regs::top::scratch::kAddress + 1);
    if (kind < 73)
      return kAddressSpace - 1 - draw(kMaxBurst);  // bursts that wrap to address 0
    return draw(kAddressSpace);
  }
  unsigned pick(const std::vector<unsigned>& addresses) {
    return addresses[draw(addresses.size())];
  }
  std::uint32_t data_word() {
    const auto r = static_cast<std::uint32_t>(rng_());
    switch (draw(8)) {
      case 0:
        return 0;
      case 1:
        return 0xFFFFFFFFU;
      case 2:
      case 3:
        return std::uint32_t{1} << draw(32);
      case 4:
        return r & static_cast<std::uint32_t>(rng_()) & static_cast<std::uint32_t>(rng_());
      default:
        return r;
    }
  }
  // Every status port at random, as the fabric could drive it.
  void draw_status() {
    ports::Status s;
    each_port(s, [&](std::size_t, auto& port) {
      const unsigned kind = draw(8);
      set_raw(port, kind == 0 ? 0 : kind == 1 ? ~std::uint64_t{0} : rng_());
    });
    for (std::size_t w = 0; w < status_regs_.size(); ++w)
      status_words_[w] = ports::encode_status(static_cast<std::uint16_t>(status_regs_[w]), s);
  }

  // ---- the model ----
  // One fabric clock of the slave and the register file (rtl::OdolocChip's
  // wires): MISO after it.
  UInt<1> clock(UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi, UInt<1> reset) {
    rtl::SpiSlave::In spi_in{.sclk = sclk,
                             .cs_n = cs_n,
                             .mosi = mosi,
                             .crc_enable = config_.top.ctrl.crc_enable,
                             .spi_mode3 = config_.top.ctrl.spi_mode3,
                             .read_data = UInt<32>{},
                             .write_refused = UInt<1>{},
                             .reset = reset};
    // Most clocks: no strobe from the slave and no pulse pending, so the
    // register file keeps its registers and drives nothing (the chip's
    // quiet path, FabricRegisters::quiet).
    if (registers_.quiet(spi_.strobing(), reset)) {
      spi_.step(spi_in);
      return spi_.miso();
    }
    const rtl::SpiRegisterPort port = spi_.port();
    const UInt<32> read_data =
        port.read_strobe ? registers_.read(port.read_address, fabric_status_) : UInt<32>{};
    const bool writes = (port.commit & port.commit_write) == UInt<1>{1};
    spi_in.read_data = read_data;
    spi_in.write_refused = rtl::FabricRegisters::write_refused(port);
    const rtl::FabricRegisters::In reg_in{
        .spi = port, .read_data = read_data, .status = fabric_status_, .reset = reset};
    registers_.commit(registers_.eval(reg_in));
    spi_.step(spi_in);
    if (writes || reset == UInt<1>{1})
      config_ = registers_.config();
    if (registers_.regs().pulsing == UInt<1>{1})
      collect_pulses(registers_.regs().pulses);
    return spi_.miso();
  }

  void transfer(std::span<const std::int64_t> in, std::span<std::int64_t> out) {
    const auto command = static_cast<std::uint32_t>(in[kCommand]);
    const unsigned count = (command >> regs::kAddressBits & kBurstMask) + 1;
    const auto bits = static_cast<std::size_t>(in[kBits]);
    std::vector<std::uint8_t> bytes{static_cast<std::uint8_t>(command >> 8),
                                    static_cast<std::uint8_t>(command)};
    for (unsigned k = 0; k < count; ++k)
      for (int b = 24; b >= 0; b -= 8)
        bytes.push_back(static_cast<std::uint8_t>(in[kData + k] >> b));
    bytes.push_back(static_cast<std::uint8_t>(in[kCrc]));
    bytes.resize(std::max(bytes.size(), (bits + 7) / 8), 0);  // a frame held too long
    board::SpiPinMaster master(
        {.half_period = in[kOverrun] != 0 ? kFastHalfPeriod : kNormalHalfPeriod,
         .mode3 = config_.top.ctrl.spi_mode3 == UInt<1>{1},
         .idle_clocks = kIdleClocks});
    const std::vector<std::uint8_t> miso = master.transfer(
        bytes,
        [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
          return clock(sclk, cs_n, mosi, UInt<1>{});
        },
        bits);
    // The MISO stream, MSB first: bits the master did not clock are 0.
    const auto stream = [&](std::size_t from, unsigned width) {
      std::uint64_t v = 0;
      for (std::size_t i = from; i < from + width; ++i) {
        const unsigned b = i < bits ? miso[i / 8] >> (7 - i % 8) & 1U : 0U;
        v = v << 1 | b;
      }
      return static_cast<std::int64_t>(v);
    };
    out[kMisoHeader] = stream(0, kHeaderBits);
    for (unsigned k = 0; k < count; ++k)
      out[kMisoData + k] = stream(kHeaderBits + kWordBits * k, kWordBits);
    out[kMisoCrc] = stream(kHeaderBits + kWordBits * count, kCrcBits);
  }

  [[nodiscard]] std::uint32_t stored_word(unsigned address) const {
    return static_cast<std::uint32_t>(
        registers_.regs()
            .stored[static_cast<std::size_t>(rtl::regfile::kStoredSlot[address])]
            .value());
  }

  // ---- the fabric's ports as register words ----
  // The status words: per status register, which status port bits make it.
  void map_status() {
    ports::Status probe;
    std::size_t ports = 0;
    each_port(probe, [&](std::size_t, auto&) { ++ports; });
    status_ports_ = ports;
    // Per port: all ones shows the words it reaches, one bit at a time where.
    std::vector<std::vector<unsigned>> reaches(ports);
    for (std::size_t p = 0; p < ports; ++p) {
      set_port(probe, p, ~std::uint64_t{0});
      for (const regs::Register& r : regs::kRegisters)
        if (ports::encode_status(r.address, probe) != 0)
          reaches[p].push_back(r.address);
      set_port(probe, p, 0);
    }
    // The register file's own registers are not fabric status.
    const auto own = [](unsigned a) {
      return a == regs::top::spi_status::kAddress || a == regs::top::frame_errors::kAddress;
    };
    for (const regs::Register& r : regs::kRegisters) {
      bool driven = false;
      for (const auto& words : reaches)
        driven = driven || std::ranges::find(words, r.address) != words.end();
      if (driven && !own(r.address))
        status_regs_.push_back(r.address);
    }
    for (std::size_t p = 0; p < ports; ++p) {
      int width = 0;
      each_port(probe, [&](std::size_t i, auto& port) {
        if (i == p)
          width = std::remove_cvref_t<decltype(port)>::width;
      });
      for (int b = 0; b < width; ++b) {
        set_port(probe, p, std::uint64_t{1} << b);
        for (std::size_t w = 0; w < status_regs_.size(); ++w) {
          if (std::ranges::find(reaches[p], status_regs_[w]) == reaches[p].end())
            continue;
          const std::uint32_t word =
              ports::encode_status(static_cast<std::uint16_t>(status_regs_[w]), probe);
          for (int wb = 0; wb < 32; ++wb)
            if ((word >> wb & 1U) != 0)
              add_bit(status_segments_, p, b, w, wb);
        }
      }
      set_port(probe, p, 0);
    }
  }

  // The pulse words and pops: which pulse port bit a written 1 raises.
  void map_pulses() {
    ports::Pulses probe;
    std::size_t pulse_count = 0;
    for (const regs::Register& r : regs::kRegisters) {
      const std::uint32_t mask = r.w1c_mask | r.w1p_mask;
      if (mask == 0)
        continue;
      const std::size_t w = pulse_count++;
      for (int b = 0; b < 32; ++b) {
        if ((mask >> b & 1U) == 0)
          continue;
        probe = {};
        ports::decode_pulses(r.address, std::uint32_t{1} << b, probe);
        each_port(probe, [&](std::size_t p, auto& port) {
          const std::uint64_t v = raw(port);
          for (int pb = 0; pb < 64; ++pb)
            if ((v >> pb & 1U) != 0)
              add_bit(pulse_segments_, p, pb, w, b);
        });
      }
    }
    for (std::size_t w = 0; w < std::size(regs::kPopWindows); ++w) {
      probe = {};
      ports::decode_pops(regs::kPopWindows[w].first, 1, probe);
      each_port(probe, [&](std::size_t p, auto& port) {
        if (raw(port) != 0)
          pop_ports_.push_back({p, w});
      });
    }
  }

  template <class S>
  static void set_port(S& s, std::size_t index, std::uint64_t bits) {
    each_port(s, [&](std::size_t i, auto& port) {
      if (i == index)
        set_raw(port, bits);
    });
  }

  // The status words of a call as the model's ports::Status.
  void set_status(std::span<const std::int64_t> words) {
    if (std::equal(words.begin(), words.end(), decoded_.begin(), decoded_.end()))
      return;
    decoded_.assign(words.begin(), words.end());
    std::vector<std::uint64_t> values(status_ports_, 0);
    for (const Segment& s : status_segments_) {
      const std::uint64_t bits =
          static_cast<std::uint64_t>(words[s.word]) >> s.word_lsb & low_bits(s.width);
      values[s.port] |= bits << s.port_lsb;
    }
    each_port(fabric_status_, [&](std::size_t i, auto& port) { set_raw(port, values[i]); });
  }

  void collect_pulses(const ports::Pulses& pulses) {
    std::vector<std::uint64_t> values;
    each_port(pulses, [&](std::size_t, auto& port) { values.push_back(raw(port)); });
    for (const Segment& s : pulse_segments_)
      pulse_words_[s.word] |= static_cast<std::uint32_t>(
          (values[s.port] >> s.port_lsb & low_bits(s.width)) << s.word_lsb);
    for (const auto& [port, window] : pop_ports_)
      pops_[window] |= static_cast<unsigned>(values[port]);
  }

  void name_columns() {
    names_.emplace_back("reset");
    names_.emplace_back("command");
    for (unsigned k = 0; k < kMaxBurst; ++k)
      names_.push_back("data_" + std::to_string(k));
    names_.emplace_back("crc");
    names_.emplace_back("bits");
    names_.emplace_back("overrun");
    for (const unsigned a : status_regs_)
      names_.push_back(column(path_of(a)));
    const std::size_t inputs = names_.size();
    names_.emplace_back("miso_header");
    for (unsigned k = 0; k < kMaxBurst; ++k)
      names_.push_back("miso_data_" + std::to_string(k));
    for (const char* n : {"miso_crc", "frame_status", "spi_status", "frame_errors"})
      names_.emplace_back(n);
    for (const unsigned a : stored_)
      names_.push_back("config_" + column(path_of(a)));
    for (const unsigned a : pulsed_)
      names_.push_back("pulse_" + column(path_of(a)));
    for (const regs::PopWindow& w : regs::kPopWindows)
      names_.push_back("pops_" + column(w.path));
    for (std::size_t i = 0; i < names_.size(); ++i)
      (i < inputs ? in_ : out_).emplace_back(names_[i]);
  }

  std::mt19937_64 rng_;
  rtl::SpiSlave spi_;
  rtl::FabricRegisters registers_;
  ports::Config config_ = rtl::FabricRegisters{}.config();
  ports::Status fabric_status_;  // held for the whole frame
  std::size_t status_ports_ = 0;
  // Addresses: the status words (kernel inputs), the stored words and the
  // pulse words (outputs), every mapped and every writable register (stimulus).
  std::vector<unsigned> status_regs_, stored_, pulsed_, mapped_, writable_;
  std::vector<Segment> status_segments_, pulse_segments_;
  std::vector<std::pair<std::size_t, std::size_t>> pop_ports_;  // pops port, window
  std::vector<std::int64_t> status_words_, decoded_;
  std::vector<std::uint32_t> pulse_words_;
  std::vector<unsigned> pops_;
  std::vector<std::string> names_;
  std::vector<std::string_view> in_, out_;
};

}  // namespace

std::unique_ptr<Reference> make_regfile_reference(std::uint64_t seed) {
  return std::make_unique<RegfileReference>(seed);
}

}  // namespace odoloc::verification
