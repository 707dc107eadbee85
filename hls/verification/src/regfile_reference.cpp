// rtl::RegisterInterface (the SPI slave and the register file, as
// rtl::OdolocChip composes them) behind the register interface kernel's
// ports (hls/regfile_kernel.hpp): one call = one fabric clock. The pins come
// from board::SpiPinMaster running seeded random frames; the fabric's status
// arrives as the kernel's status words (logic::regfile::StatusWords, the
// model's status source for word ports). The outputs are the model's
// registers after the clock: MISO, the snapshot strobe, the stored
// configuration words, the pulse words and the pops.
//
// Stimulus, per frame:
// - 1 in 256 a reset (one clock, then the pins idle for a few clocks).
// - 1 in 4 a new fabric status before the frame, and 1 in 4096 per clock
//   within it: every status word at random, 1/8 of them 0 and 1/8 all ones.
// - 45 % reads, 55 % writes. Start address: 50 % a mapped register (writes: one
//   that takes writes), 10 % an rpop FIFO's first word (writes: any mapped
//   register), 10 % the top block (ctrl, spi_status, frame_errors), 3 % near
//   1023 (bursts wrap to 0), 27 % any of the 1024 (unmapped, reserved). Burst:
//   1 word (60 %), 2-4 (30 %), 5-32 (10 %): long bursts cost the most clocks.
// - Data: random, 0, all ones or single bits (w1c clears, w1p commands).
//   A write over top.ctrl keeps its value 7 times in 8 (CRC framing and SPI
//   mode change rarely).
// - Frame: 79 % well formed (with a good CRC when crc_enable); 5 % cut short
//   anywhere, 2 % inside the command, 3 % too long, 4 % a corrupted CRC (when
//   crc_enable), 3 % the length of the other CRC setting, 4 % too fast (SCLK
//   levels of 3 fabric clocks: overrun), cut short half the time.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <iterator>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/board/spi_pin_master.hpp"
#include "odoloc/logic/register_file.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/register_interface.hpp"
#include "odoloc/verification/reference.hpp"

namespace odoloc::verification {

namespace {

using rtl::UInt;
namespace rf = logic::regfile;

constexpr unsigned kMaxBurst = regs::spi::kMaxBurst;
constexpr unsigned kAddressSpace = 1U << regs::kAddressBits;
// The command (docs/spi.md): [15] read, [14:10] burst length - 1, [9:0] address.
constexpr unsigned kReadBit = 15;
constexpr unsigned kHeaderBits = 16;
constexpr unsigned kWordBits = 32;
constexpr unsigned kCrcBits = 8;
constexpr unsigned kNormalHalfPeriod = regs::spi::kMinLevelClocks;
constexpr unsigned kFastHalfPeriod = regs::spi::kMinLevelClocks - 1;  // seen, but an overrun
constexpr unsigned kSettleClocks = 4;  // after a reset: the synchronisers see the idle pins
// cs_n high after a frame: the slave sees the rise in the 3rd clock, the
// register file commits in the 4th and its pulses show in the 5th.
constexpr unsigned kIdleClocks = 8;

using Model = rtl::RegisterInterface<rf::StatusWords<rtl::Family>>;

struct Clock {
  UInt<1> sclk, cs_n{1}, mosi, reset;
  bool new_status = false;  // draw the status words before this clock
};

std::string column(std::string_view path) {
  std::string name(path);
  for (char& c : name)
    c = c == '.' ? '_' : c;
  return name;
}

class RegfileReference final : public Reference {
 public:
  explicit RegfileReference(std::uint64_t seed) : rng_(seed) {
    for (const regs::Register& r : regs::kRegisters) {
      mapped_.push_back(r.address);
      if ((r.rw_mask | r.w1c_mask | r.w1p_mask) != 0)
        writable_.push_back(r.address);
    }
    name_columns();
    status_.assign(status_names_.size(), 0);
    draw_status();
  }

  [[nodiscard]] std::span<const std::string_view> input_names() const override { return in_; }
  [[nodiscard]] std::span<const std::string_view> output_names() const override { return out_; }

  void stimulus(std::span<std::int64_t> in) override {
    if (clocks_.empty())
      next_frame();
    const Clock c = clocks_.front();
    clocks_.pop_front();
    if (c.new_status || chance(4096))
      draw_status();
    in[kSclk] = static_cast<std::int64_t>(c.sclk.value());
    in[kCsN] = static_cast<std::int64_t>(c.cs_n.value());
    in[kMosi] = static_cast<std::int64_t>(c.mosi.value());
    in[kReset] = static_cast<std::int64_t>(c.reset.value());
    std::copy(status_.begin(), status_.end(), in.begin() + kStatus);
  }

  void step(std::span<const std::int64_t> in, std::span<std::int64_t> out) override {
    rf::StatusWords<rtl::Family> status;
    for (int k = 0; k < rf::kStatusWords; ++k)
      status.bank[k].value = UInt<32>::truncate(static_cast<std::uint64_t>(in[kStatus + k]));
    const auto pin = [&](std::size_t i) { return UInt<1>::truncate(in[i] != 0 ? 1U : 0U); };
    model_.step({.sclk = pin(kSclk), .cs_n = pin(kCsN), .mosi = pin(kMosi), .reset = pin(kReset)},
                status);
    const rtl::FabricRegistersRegs& r = model_.registers().regs();
    std::size_t o = 0;
    out[o++] = static_cast<std::int64_t>(model_.miso().value());
    out[o++] = static_cast<std::int64_t>(model_.snapshot().value());
    for (const auto& word : r.stored.word)
      out[o++] = static_cast<std::int64_t>(word.value.value());
    for (const auto& word : r.pulse)
      out[o++] = static_cast<std::int64_t>(word.value.value());
    for (const auto& pops : r.pops)
      out[o++] = static_cast<std::int64_t>(pops.value.value());
  }

 private:
  // Column indices of the inputs.
  static constexpr std::size_t kSclk = 0, kCsN = 1, kMosi = 2, kReset = 3, kStatus = 4;

  // ---- stimulus ----
  unsigned draw(std::size_t n) { return static_cast<unsigned>(rng_() % n); }
  bool chance(unsigned one_in) { return draw(one_in) == 0; }

  unsigned burst() {
    const unsigned kind = draw(10);
    if (kind < 6)
      return 1;
    return kind < 9 ? 2 + draw(3) : 5 + draw(kMaxBurst - 4);
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
  // Every status word at random, as the fabric could drive it.
  void draw_status() {
    for (std::int64_t& word : status_) {
      const unsigned kind = draw(8);
      word = kind == 0 ? 0 : kind == 1 ? 0xFFFFFFFF : static_cast<std::uint32_t>(rng_());
    }
  }

  // The pins of the next frame, clock by clock.
  void next_frame() {
    if (chance(256)) {
      clocks_.push_back({.sclk = {}, .cs_n = UInt<1>{1}, .mosi = {}, .reset = UInt<1>{1}});
      for (unsigned c = 0; c < kSettleClocks; ++c)
        clocks_.push_back({});
      return;
    }
    const bool read = draw(100) < 45;
    const unsigned count = burst();
    const unsigned start = start_address(read);
    const std::uint32_t command =
        (read ? 1U : 0U) << kReadBit | (count - 1) << regs::kAddressBits | start;
    std::vector<std::uint8_t> bytes{static_cast<std::uint8_t>(command >> 8),
                                    static_cast<std::uint8_t>(command)};
    const std::uint32_t ctrl = static_cast<std::uint32_t>(
        model_.registers().stored_word(regs::top::ctrl::kAddress).value());
    for (unsigned k = 0; k < count; ++k) {
      std::uint32_t word = data_word();
      if (!read && (start + k) % kAddressSpace == regs::top::ctrl::kAddress && !chance(8))
        word = ctrl;
      for (int b = 24; b >= 0; b -= 8)
        bytes.push_back(static_cast<std::uint8_t>(word >> b));
    }
    const bool crc_on = regs::top::ctrl::crc_enable.get(ctrl) != 0;
    const std::uint8_t good_crc = rtl::crc8_j1850(bytes);
    std::uint8_t crc = crc_on ? good_crc : static_cast<std::uint8_t>(rng_());
    const unsigned end = kHeaderBits + kWordBits * count;
    const unsigned expected = end + (crc_on ? kCrcBits : 0);
    unsigned bits = expected;
    bool overrun = false;
    const unsigned form = draw(100);
    if (form < 5) {
      bits = draw(expected);  // cs_n raised early
    } else if (form < 7) {
      bits = draw(kHeaderBits + 1);
    } else if (form < 10) {
      bits = expected + 1 + draw(40);
    } else if (form < 14) {
      if (crc_on)
        crc = static_cast<std::uint8_t>(good_crc ^ (1U + draw(255)));
    } else if (form < 17) {
      bits = crc_on ? end : end + kCrcBits;
    } else if (form < 21) {
      overrun = true;
      if (chance(2))
        bits = 1 + draw(expected);  // at least one SCLK edge: the short level is seen
    }
    bytes.push_back(crc);
    bytes.resize(std::max<std::size_t>(bytes.size(), (bits + 7) / 8), 0);  // held too long
    board::SpiPinMaster master({.half_period = overrun ? kFastHalfPeriod : kNormalHalfPeriod,
                                .mode3 = regs::top::ctrl::spi_mode3.get(ctrl) != 0,
                                .idle_clocks = kIdleClocks});
    const bool new_status = chance(4);
    master.transfer(
        bytes,
        [&](UInt<1> sclk, UInt<1> cs_n, UInt<1> mosi) {
          clocks_.push_back({.sclk = sclk, .cs_n = cs_n, .mosi = mosi, .reset = {}});
          return UInt<1>{};  // the stimulus does not depend on MISO
        },
        bits);
    clocks_.front().new_status = new_status;
  }

  void name_columns() {
    for (const char* n : {"sclk", "cs_n", "mosi", "reset"})
      names_.emplace_back(n);
    // The registers the hardware drives, but for the register file's own.
    static_assert(std::size(regs::kRegisters) == logic::regfile_map::kRegisterCount);
    for (std::size_t i = 0; i < std::size(regs::kRegisters); ++i) {
      const auto& r = logic::regfile_map::kRegisters[i];  // the same register, with hw_mask
      if (r.hw_mask != 0 && r.address != regs::top::spi_status::kAddress &&
          r.address != regs::top::frame_errors::kAddress)
        status_names_.push_back(column(regs::kRegisters[i].path));
    }
    names_.insert(names_.end(), status_names_.begin(), status_names_.end());
    const std::size_t inputs = names_.size();
    names_.emplace_back("miso");
    names_.emplace_back("snapshot");
    for (const regs::Register& r : regs::kRegisters)
      if (r.rw_mask != 0)
        names_.push_back("config_" + column(r.path));
    for (const regs::Register& r : regs::kRegisters)
      if ((r.w1c_mask | r.w1p_mask) != 0)
        names_.push_back("pulse_" + column(r.path));
    for (const regs::PopWindow& w : regs::kPopWindows)
      names_.push_back("pops_" + column(w.path));
    for (std::size_t i = 0; i < names_.size(); ++i)
      (i < inputs ? in_ : out_).emplace_back(names_[i]);
  }

  std::mt19937_64 rng_;
  Model model_;
  std::deque<Clock> clocks_;
  std::vector<std::int64_t> status_;  // the status words, kernel input order
  // Addresses: every mapped and every writable register (stimulus).
  std::vector<unsigned> mapped_, writable_;
  std::vector<std::string> status_names_, names_;
  std::vector<std::string_view> in_, out_;
};

}  // namespace

std::unique_ptr<Reference> make_regfile_reference(std::uint64_t seed) {
  return std::make_unique<RegfileReference>(seed);
}

}  // namespace odoloc::verification
