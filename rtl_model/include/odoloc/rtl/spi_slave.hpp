// SPI slave protocol engine: pins in, narrow wires to the register side out.
// The register file is not part of this block (docs/spi.md).
//
// Frame (MSB first; n = burst length 1..32; bytes counted from cs_n falling):
//
//   bytes      MOSI (master)                          MISO (slave)
//   0-1        command: [15] 1 read / 0 write,        status of the previous frame
//              [14:10] n-1, [9:0] start word address  (kStatus* bits), then 0x00
//   2..4n+1    write: n words; read: don't care       read: n words; write: 0x00
//   4n+2       CRC-8 over MOSI bytes 0..4n+1          CRC-8 over MISO bytes 0..4n+1
//              (only when crc_enable)                 (only when crc_enable; reads and writes)
//
// Addresses auto-increment within a burst, modulo 1024. crc_enable and
// spi_mode3 are latched at cs_n falling, so they take effect from the next frame.
//
// Timing. sclk, cs_n and mosi pass two synchroniser flops (meta, sync); an
// edge is seen when sync differs from the previous sync (prev), i.e. in the
// third fabric clock after the pin changed, and MISO (a register) changes at
// the end of that clock. Modes 0 and 3 alike: MOSI is sampled on rising SCLK,
// MISO changes after falling SCLK; in mode 3 the first falling edge after cs_n
// falls only arms the engine. The first MISO bit (status bit 7) is driven when
// the cs_n fall is seen.
//
// Maximum SCLK: every SCLK level, and cs_n low before the first SCLK edge,
// must last >= kMinLevelClocks = 4 fabric clocks (f_SCLK <= 50 MHz / 8 =
// 6.25 MHz): 2 to synchronise, 1 to detect, 1 for MISO to settle before the
// master samples it. A shorter level sets `overrun` and the frame commits
// nothing; pulses shorter than a fabric clock lose bits, so the frame has the
// wrong length and gets `bad_length`. Either way the engine never hangs: every
// cs_n fall starts a fresh frame.
//
// Register-side interface (all outputs are registers, so a composite derives
// its wires from the current registers):
//   snapshot       one clock, in the clock the cs_n fall is seen: capture the
//                  snapshot registers.
//   read_strobe,   one clock: request word read_address. In the NEXT clock the
//   read_address   composite must drive In.read_data = bus.read(read_address)
//                  (computed from the current registers); the slave latches it.
//                  Word 0 is requested after command bit 15 (rising edge 16),
//                  word k+1 when word k starts shifting out, so data is
//                  fetched just in time (after the snapshot).
//   commit,        one clock, in the clock the cs_n rise is seen, only for a
//   commit_write,  frame of exactly the expected length with no overrun and
//   commit_address,(writes with CRC on) a good CRC. commit_write = 1: the words
//   commit_count   are regs().words[0..commit_count-1], for commit_address
//                  onwards; commit_write = 0: a read frame completed (e.g. for
//                  read-to-clear registers).
//   frame_end      one clock, at every seen cs_n rise of a frame; `status`
//                  then holds that frame's flags.
//   In.write_refused  the register side drives it in the commit clock (or
//                  later); it is merged into the status of the frame just ended.
//   status         kStatus* flags of the last completed frame (MISO byte 0 of
//                  the next frame).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

#include "odoloc/regs.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"

namespace odoloc::rtl {

// CRC-8 as in SAE J1850 (regmap/odoloc.yaml, spi.crc): polynomial 0x1D,
// init 0xFF, no reflection, final XOR 0xFF.
inline constexpr std::uint8_t kCrc8Poly = regs::spi::kCrcPolynomial;
inline constexpr std::uint8_t kCrc8Init = regs::spi::kCrcInit;
inline constexpr std::uint8_t kCrc8XorOut = regs::spi::kCrcXorOut;

// One message bit into the CRC shift register (what the hardware does per SCLK).
constexpr UInt<8> crc8_step(UInt<8> crc, UInt<1> bit) {
  const UInt<8> shifted = crc.shl<1>().wrap<8>();
  return (crc.bit<7>() ^ bit) ? shifted ^ UInt<8>{kCrc8Poly} : shifted;
}

constexpr std::uint8_t crc8_j1850(std::span<const std::uint8_t> bytes) {
  UInt<8> crc{kCrc8Init};
  for (const std::uint8_t b : bytes)
    for (int i = 7; i >= 0; --i)
      crc = crc8_step(crc, UInt<1>::truncate(static_cast<std::uint64_t>(b >> i)));
  return static_cast<std::uint8_t>(crc.value() ^ kCrc8XorOut);
}

inline constexpr unsigned kSpiMaxBurst = regs::spi::kMaxBurst;

struct SpiSlaveRegs {
  UInt<1> sclk_meta, sclk_sync, sclk_prev;
  UInt<1> cs_meta, cs_sync, cs_prev;
  UInt<1> mosi_meta, mosi_sync;
  UInt<1> active;        // between a seen cs_n fall and rise
  UInt<1> crc_on;        // crc_enable latched at cs_n fall
  UInt<1> fall_armed;    // 0 in mode 3 until the first falling edge
  UInt<3> level_clocks;  // clocks since the last SCLK edge (or cs_n fall), saturating
  UInt<1> frame_overrun;
  UInt<11> rx_count;  // rising edges in this frame, saturating
  UInt<32> rx_shift;
  UInt<8> rx_crc;
  UInt<16> command;
  std::array<UInt<32>, kSpiMaxBurst> words;  // write data, valid while commit is high
  UInt<11> tx_count;                         // index of the MISO bit on the pin, saturating
  UInt<32> tx_shift;                         // the bits after it
  UInt<8> tx_crc;
  UInt<32> read_word;  // the next word to shift out, fetched ahead
  // outputs
  UInt<1> miso;
  UInt<1> snapshot;
  UInt<1> read_strobe;
  UInt<10> read_address;
  UInt<1> commit, commit_write;
  UInt<1> frame_end;  // one clock: a frame ended; `status` holds its flags
  UInt<10> commit_address;
  UInt<6> commit_count;
  UInt<4> status;
  bool operator==(const SpiSlaveRegs&) const = default;
  ODOLOC_FIELDS(sclk_meta, sclk_sync, sclk_prev, cs_meta, cs_sync, cs_prev, mosi_meta, mosi_sync,
                active, crc_on, fall_armed, level_clocks, frame_overrun, rx_count, rx_shift, rx_crc,
                command, words, tx_count, tx_shift, tx_crc, read_word, miso, snapshot, read_strobe,
                read_address, commit, commit_write, frame_end, commit_address, commit_count, status)
};

// The register side's wires from the slave, as values (see the interface
// above); words[0..commit_count-1] are valid while commit is high.
struct SpiRegisterPort {
  UInt<1> snapshot, read_strobe;
  UInt<10> read_address;
  UInt<1> commit, commit_write, frame_end;
  UInt<10> commit_address;
  UInt<6> commit_count;
  UInt<4> status;
  std::array<UInt<32>, kSpiMaxBurst> words;
  // Any strobe the register side acts on.
  [[nodiscard]] bool active() const {
    return !(snapshot | read_strobe | commit | frame_end).is_zero();
  }
};

class SpiSlave : public Registers<SpiSlaveRegs> {
 public:
  static constexpr unsigned kMinLevelClocks = regs::spi::kMinLevelClocks;
  // status bits: the top.spi_status fields
  static constexpr std::uint8_t kStatusCrcError = regs::top::spi_status::crc_error.mask();
  static constexpr std::uint8_t kStatusBadLength = regs::top::spi_status::bad_length.mask();
  static constexpr std::uint8_t kStatusWriteRefused = regs::top::spi_status::write_refused.mask();
  static constexpr std::uint8_t kStatusOverrun = regs::top::spi_status::overrun.mask();

  struct In {
    UInt<1> sclk, cs_n, mosi;  // pins, asynchronous
    UInt<1> crc_enable, spi_mode3;
    UInt<32> read_data;  // bus.read(read_address), the clock after read_strobe
    UInt<1> write_refused;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    n.sclk_meta = in.sclk;
    n.sclk_sync = r_.sclk_meta;
    n.sclk_prev = r_.sclk_sync;
    n.cs_meta = in.cs_n;
    n.cs_sync = r_.cs_meta;
    n.cs_prev = r_.cs_sync;
    n.mosi_meta = in.mosi;
    n.mosi_sync = r_.mosi_meta;
    n.snapshot = n.read_strobe = n.commit = n.frame_end = UInt<1>{};
    n.level_clocks = (r_.level_clocks + UInt<1>{1}).sat<3>();
    if (r_.read_strobe)
      n.read_word = in.read_data;
    if (in.write_refused)
      n.status = r_.status | UInt<4>{kStatusWriteRefused};

    if (!r_.cs_sync && r_.cs_prev) {
      start_frame(n, in);  // an SCLK edge seen in the same clock is dropped
      return n;
    }
    if (!r_.active)
      return n;
    const bool rise = r_.sclk_sync && !r_.sclk_prev;
    const bool fall = !r_.sclk_sync && r_.sclk_prev;
    if (rise || fall) {
      if (r_.level_clocks.value() < kMinLevelClocks)
        n.frame_overrun = UInt<1>{1};
      n.level_clocks = UInt<3>{1};
    }
    if (rise)
      receive_bit(n);
    if (fall)
      drive_next_bit(n);
    if (r_.cs_sync && !r_.cs_prev)
      end_frame(n);
    return n;
  }

  [[nodiscard]] bool idle(const In& in) const {
    const auto settled = [](UInt<1> pin, UInt<1> a, UInt<1> b) { return pin == a && a == b; };
    return (in.reset | in.write_refused | r_.snapshot | r_.read_strobe | r_.commit | r_.frame_end)
               .is_zero() &&
           settled(in.sclk, r_.sclk_meta, r_.sclk_sync) && r_.sclk_sync == r_.sclk_prev &&
           settled(in.cs_n, r_.cs_meta, r_.cs_sync) && r_.cs_sync == r_.cs_prev &&
           settled(in.mosi, r_.mosi_meta, r_.mosi_sync) &&
           r_.level_clocks.value() == UInt<3>::max_value;
  }

  // Any strobe the register side acts on (SpiRegisterPort::active, without the copy).
  [[nodiscard]] bool strobing() const {
    return !(r_.snapshot | r_.read_strobe | r_.commit | r_.frame_end).is_zero();
  }
  [[nodiscard]] SpiRegisterPort port() const {
    return {.snapshot = r_.snapshot,
            .read_strobe = r_.read_strobe,
            .read_address = r_.read_address,
            .commit = r_.commit,
            .commit_write = r_.commit_write,
            .frame_end = r_.frame_end,
            .commit_address = r_.commit_address,
            .commit_count = r_.commit_count,
            .status = r_.status,
            .words = r_.words};
  }

 private:
  static constexpr unsigned kHeaderBits = 16;
  static constexpr unsigned kWordBits = 32;
  static constexpr unsigned kCountMax = UInt<11>::max_value;

  static bool is_read(UInt<16> command) { return command.bit<15>() == UInt<1>{1}; }
  static unsigned burst(UInt<16> command) {
    return static_cast<unsigned>(command.bits<14, 10>().value()) + 1;
  }
  // Bit index where the CRC byte starts (= data bits end).
  static unsigned data_end(UInt<16> command) { return kHeaderBits + kWordBits * burst(command); }
  static UInt<10> word_address(UInt<16> command, unsigned k) {
    return UInt<10>::truncate(command.bits<9, 0>().value() + k);
  }
  static UInt<11> saturating_count(UInt<11> count) {
    return UInt<11>::truncate(std::min<std::uint64_t>(count.value() + 1, kCountMax));
  }
  // Puts w's MSB on the pin and keeps the rest.
  static void shift_out(Regs& n, UInt<32> w) {
    n.miso = w.bit<31>();
    n.tx_shift = w.shl<1>().wrap<32>();
  }

  void start_frame(Regs& n, const In& in) const {
    n.active = UInt<1>{1};
    n.crc_on = in.crc_enable;
    n.fall_armed = ~in.spi_mode3;
    n.level_clocks = UInt<3>{1};
    n.frame_overrun = UInt<1>{};
    n.rx_count = UInt<11>{};
    n.rx_crc = UInt<8>{kCrc8Init};
    n.command = UInt<16>{};  // a frame cut before bit 16 then expects >= 48 bits: bad_length
    n.tx_count = UInt<11>{};
    n.snapshot = UInt<1>{1};
    shift_out(n, cat(cat(UInt<8>{n.status}, UInt<8>{}), UInt<16>{}));
    n.tx_crc = crc8_step(UInt<8>{kCrc8Init}, n.miso);
  }

  void receive_bit(Regs& n) const {
    const unsigned c = static_cast<unsigned>(saturating_count(r_.rx_count).value());
    n.rx_count = saturating_count(r_.rx_count);
    n.rx_shift = cat(r_.rx_shift.bits<30, 0>(), r_.mosi_sync);
    if (c == kHeaderBits) {
      n.command = n.rx_shift.bits<15, 0>();
      if (is_read(n.command)) {
        n.read_strobe = UInt<1>{1};
        n.read_address = word_address(n.command, 0);
      }
    }
    const unsigned end = c <= kHeaderBits ? kHeaderBits : data_end(n.command);
    if (c <= end)
      n.rx_crc = crc8_step(r_.rx_crc, r_.mosi_sync);
    if (c > kHeaderBits && c <= end && (c - kHeaderBits) % kWordBits == 0 && !is_read(n.command))
      n.words[(c - kHeaderBits) / kWordBits - 1] = n.rx_shift;
  }

  void drive_next_bit(Regs& n) const {
    if (!r_.fall_armed) {
      n.fall_armed = UInt<1>{1};
      return;
    }
    const unsigned i = static_cast<unsigned>(saturating_count(r_.tx_count).value());
    n.tx_count = saturating_count(r_.tx_count);
    const unsigned end = data_end(r_.command);
    if (i >= kHeaderBits && i < end && (i - kHeaderBits) % kWordBits == 0) {
      const unsigned k = (i - kHeaderBits) / kWordBits;
      const bool read = is_read(r_.command);
      shift_out(n, read ? r_.read_word : UInt<32>{});
      if (read && k + 1 < burst(r_.command)) {
        n.read_strobe = UInt<1>{1};
        n.read_address = word_address(r_.command, k + 1);
      }
    } else if (i == end) {
      shift_out(n, r_.crc_on ? cat(r_.tx_crc ^ UInt<8>{kCrc8XorOut}, UInt<24>{}) : UInt<32>{});
    } else {
      shift_out(n, r_.tx_shift);
    }
    if (i < end)
      n.tx_crc = crc8_step(r_.tx_crc, n.miso);
  }

  void end_frame(Regs& n) const {
    n.active = UInt<1>{};
    n.frame_end = UInt<1>{1};
    n.miso = UInt<1>{};
    const bool write = !is_read(n.command);
    const bool bad_length = n.rx_count.value() != data_end(n.command) + (r_.crc_on ? 8U : 0U);
    // Reads are checked too: a corrupted read command must not clear an rc register.
    const bool crc_error =
        !bad_length && r_.crc_on && (n.rx_crc ^ UInt<8>{kCrc8XorOut}) != n.rx_shift.bits<7, 0>();
    const bool overrun = n.frame_overrun == UInt<1>{1};
    n.status =
        UInt<4>::truncate((crc_error ? kStatusCrcError : 0U) |
                          (bad_length ? kStatusBadLength : 0U) | (overrun ? kStatusOverrun : 0U));
    if (!bad_length && !crc_error && !overrun) {
      n.commit = UInt<1>{1};
      n.commit_write = UInt<1>::truncate(write ? 1 : 0);
      n.commit_address = word_address(n.command, 0);
      n.commit_count = UInt<6>::truncate(burst(n.command));
    }
  }
};

}  // namespace odoloc::rtl
