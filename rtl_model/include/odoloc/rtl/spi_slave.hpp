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
//   commit_count   are the write buffer's words[0..commit_count-1], for commit_address
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

// ---- pin synchroniser ---------------------------------------------------------
// The two synchroniser flops of each pin, the previous synchronised SCLK and
// cs_n (edge detection) and the clocks since the last SCLK edge. Clocked every
// clock; the protocol engine sees its edges (Seen) and moves only on them.
struct SpiSynchroniserRegs {
  UInt<1> sclk_meta, sclk_sync, sclk_prev;
  UInt<1> cs_meta, cs_sync, cs_prev;
  UInt<1> mosi_meta, mosi_sync;
  UInt<3> level_clocks;  // clocks since the last SCLK edge of a frame (or cs_n fall), saturating
  bool operator==(const SpiSynchroniserRegs&) const = default;
  ODOLOC_FIELDS(sclk_meta, sclk_sync, sclk_prev, cs_meta, cs_sync, cs_prev, mosi_meta, mosi_sync,
                level_clocks)
};

class SpiSynchroniser : public Registers<SpiSynchroniserRegs> {
 public:
  struct In {
    UInt<1> sclk, cs_n, mosi;  // pins, asynchronous
    UInt<1> active;            // the engine is in a frame: its SCLK edges restart level_clocks
    UInt<1> reset;
  };
  // What the engine sees in this clock, from the current registers.
  struct Seen {
    bool cs_fall, cs_rise;  // cs_n edges
    bool rise, fall;        // SCLK edges
    UInt<1> mosi;
    UInt<3> level_clocks;
  };
  [[nodiscard]] Seen seen() const {
    return {.cs_fall = !r_.cs_sync && r_.cs_prev,
            .cs_rise = r_.cs_sync && !r_.cs_prev,
            .rise = r_.sclk_sync && !r_.sclk_prev,
            .fall = !r_.sclk_sync && r_.sclk_prev,
            .mosi = r_.mosi_sync,
            .level_clocks = r_.level_clocks};
  }

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    const Seen s = seen();
    const bool restart = s.cs_fall || (in.active && (s.rise || s.fall));
    return {.sclk_meta = in.sclk,
            .sclk_sync = r_.sclk_meta,
            .sclk_prev = r_.sclk_sync,
            .cs_meta = in.cs_n,
            .cs_sync = r_.cs_meta,
            .cs_prev = r_.cs_sync,
            .mosi_meta = in.mosi,
            .mosi_sync = r_.mosi_meta,
            .level_clocks = restart ? UInt<3>{1} : (r_.level_clocks + UInt<1>{1}).sat<3>()};
  }
  // Every pin held through both flops, no edge pending, the level count saturated.
  [[nodiscard]] bool idle(const In& in) const {
    const auto held = [](UInt<1> pin, UInt<1> meta, UInt<1> sync) {
      return pin == meta && meta == sync;
    };
    return in.reset.is_zero() && held(in.sclk, r_.sclk_meta, r_.sclk_sync) &&
           r_.sclk_sync == r_.sclk_prev && held(in.cs_n, r_.cs_meta, r_.cs_sync) &&
           r_.cs_sync == r_.cs_prev && held(in.mosi, r_.mosi_meta, r_.mosi_sync) &&
           r_.level_clocks.value() == UInt<3>::max_value;
  }
};

// ---- protocol engine ------------------------------------------------------------
// The frame state, the shift registers, the CRCs and every output to the
// register side. Moves only on a seen edge, a strobe to clear, a read word to
// latch or a refused write: between SCLK edges it is idle.
struct SpiEngineRegs {
  UInt<1> active;      // between a seen cs_n fall and rise
  UInt<1> crc_on;      // crc_enable latched at cs_n fall
  UInt<1> fall_armed;  // 0 in mode 3 until the first falling edge
  UInt<1> frame_overrun;
  UInt<11> rx_count;  // rising edges in this frame, saturating
  UInt<32> rx_shift;
  UInt<8> rx_crc;
  UInt<16> command;
  UInt<11> tx_count;  // index of the MISO bit on the pin, saturating
  UInt<32> tx_shift;  // the bits after it
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
  bool operator==(const SpiEngineRegs&) const = default;
  ODOLOC_FIELDS(active, crc_on, fall_armed, frame_overrun, rx_count, rx_shift, rx_crc, command,
                tx_count, tx_shift, tx_crc, read_word, miso, snapshot, read_strobe, read_address,
                commit, commit_write, frame_end, commit_address, commit_count, status)
};

// ---- write buffer -----------------------------------------------------------------
// The words of a write frame, one write port: a word is stored in the clock
// its last bit is received. Valid while the engine's commit is high.
struct SpiWriteBufferRegs {
  std::array<UInt<32>, kSpiMaxBurst> words;
  bool operator==(const SpiWriteBufferRegs&) const = default;
  ODOLOC_FIELDS(words)
};

class SpiWriteBuffer : public Registers<SpiWriteBufferRegs> {
 public:
  struct In {
    UInt<1> write;
    UInt<5> index;
    UInt<32> word;
    UInt<1> reset;
  };
  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    if (in.write)
      n.words[in.index.value()] = in.word;
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const { return (in.write | in.reset).is_zero(); }
};

class SpiEngine : public Registers<SpiEngineRegs> {
 public:
  static constexpr unsigned kMinLevelClocks = regs::spi::kMinLevelClocks;
  // status bits: the top.spi_status fields
  static constexpr std::uint8_t kStatusCrcError = regs::top::spi_status::crc_error.mask();
  static constexpr std::uint8_t kStatusBadLength = regs::top::spi_status::bad_length.mask();
  static constexpr std::uint8_t kStatusWriteRefused = regs::top::spi_status::write_refused.mask();
  static constexpr std::uint8_t kStatusOverrun = regs::top::spi_status::overrun.mask();

  struct In {
    SpiSynchroniser::Seen seen;
    UInt<1> crc_enable, spi_mode3;
    UInt<32> read_data;  // bus.read(read_address), the clock after read_strobe
    UInt<1> write_refused;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    n.snapshot = n.read_strobe = n.commit = n.frame_end = UInt<1>{};
    if (r_.read_strobe)
      n.read_word = in.read_data;
    if (in.write_refused)
      n.status = r_.status | UInt<4>{kStatusWriteRefused};

    if (in.seen.cs_fall) {
      start_frame(n, in);  // an SCLK edge seen in the same clock is dropped
      return n;
    }
    if (!r_.active)
      return n;
    if ((in.seen.rise || in.seen.fall) && in.seen.level_clocks.value() < kMinLevelClocks)
      n.frame_overrun = UInt<1>{1};
    if (in.seen.rise)
      receive_bit(n, in.seen.mosi);
    if (in.seen.fall)
      drive_next_bit(n);
    if (in.seen.cs_rise)
      end_frame(n);
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    const SpiSynchroniser::Seen& s = in.seen;
    return !(s.cs_fall || s.cs_rise || s.rise || s.fall) &&
           (in.reset | in.write_refused | r_.read_strobe).is_zero() && !strobing();
  }

  // The write buffer's port in this clock: a write frame's word whose last
  // bit the rising edge of this clock brings in.
  [[nodiscard]] SpiWriteBuffer::In word_write(const In& in) const {
    SpiWriteBuffer::In w{
        .write = {}, .index = {}, .word = received(in.seen.mosi), .reset = in.reset};
    if (in.reset || in.seen.cs_fall || !r_.active || !in.seen.rise || is_read(r_.command))
      return w;
    // The command is stored at bit 16, before any data bit.
    const unsigned c = static_cast<unsigned>(saturating_count(r_.rx_count).value());
    if (c > kHeaderBits && c <= data_end(r_.command) && (c - kHeaderBits) % kWordBits == 0) {
      w.write = UInt<1>{1};
      w.index = UInt<5>::truncate((c - kHeaderBits) / kWordBits - 1);
    }
    return w;
  }

  // Any strobe the register side acts on.
  [[nodiscard]] bool strobing() const {
    return !(r_.snapshot | r_.read_strobe | r_.commit | r_.frame_end).is_zero();
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
  // The receive shift register after a rising edge samples `mosi`.
  [[nodiscard]] UInt<32> received(UInt<1> mosi) const {
    return cat(r_.rx_shift.bits<30, 0>(), mosi);
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
    n.frame_overrun = UInt<1>{};
    n.rx_count = UInt<11>{};
    n.rx_crc = UInt<8>{kCrc8Init};
    n.command = UInt<16>{};  // a frame cut before bit 16 then expects >= 48 bits: bad_length
    n.tx_count = UInt<11>{};
    n.snapshot = UInt<1>{1};
    shift_out(n, cat(cat(UInt<8>{n.status}, UInt<8>{}), UInt<16>{}));
    n.tx_crc = crc8_step(UInt<8>{kCrc8Init}, n.miso);
  }

  void receive_bit(Regs& n, UInt<1> mosi) const {
    const unsigned c = static_cast<unsigned>(saturating_count(r_.rx_count).value());
    n.rx_count = saturating_count(r_.rx_count);
    n.rx_shift = received(mosi);
    if (c == kHeaderBits) {
      n.command = n.rx_shift.bits<15, 0>();
      if (is_read(n.command)) {
        n.read_strobe = UInt<1>{1};
        n.read_address = word_address(n.command, 0);
      }
    }
    const unsigned end = c <= kHeaderBits ? kHeaderBits : data_end(n.command);
    if (c <= end)
      n.rx_crc = crc8_step(r_.rx_crc, mosi);
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

// ---- the slave ----------------------------------------------------------------------
// Three blocks, so that a clock between SCLK edges costs the synchroniser
// alone: the engine and the write buffer are idle then (activity gating).
class SpiSlave {
 public:
  static constexpr unsigned kMinLevelClocks = SpiEngine::kMinLevelClocks;
  static constexpr std::uint8_t kStatusCrcError = SpiEngine::kStatusCrcError;
  static constexpr std::uint8_t kStatusBadLength = SpiEngine::kStatusBadLength;
  static constexpr std::uint8_t kStatusWriteRefused = SpiEngine::kStatusWriteRefused;
  static constexpr std::uint8_t kStatusOverrun = SpiEngine::kStatusOverrun;

  struct In {
    UInt<1> sclk, cs_n, mosi;  // pins, asynchronous
    UInt<1> crc_enable, spi_mode3;
    UInt<32> read_data;  // bus.read(read_address), the clock after read_strobe
    UInt<1> write_refused;
    UInt<1> reset;
  };

  // The wires into every child, from the current registers only.
  struct Wires {
    SpiSynchroniser::In synchroniser;
    SpiEngine::In engine;
    SpiWriteBuffer::In buffer;
  };
  [[nodiscard]] Wires wires(const In& in) const {
    const SpiEngine::In engine = engine_in(in);
    return {.synchroniser = synchroniser_in(in),
            .engine = engine,
            .buffer = engine_.word_write(engine)};
  }
  [[nodiscard]] SpiSynchroniser::In synchroniser_in(const In& in) const {
    return {.sclk = in.sclk,
            .cs_n = in.cs_n,
            .mosi = in.mosi,
            .active = engine_.regs().active,
            .reset = in.reset};
  }
  [[nodiscard]] SpiEngine::In engine_in(const In& in) const {
    return {.seen = synchroniser_.seen(),
            .crc_enable = in.crc_enable,
            .spi_mode3 = in.spi_mode3,
            .read_data = in.read_data,
            .write_refused = in.write_refused,
            .reset = in.reset};
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Order& order = {}) {
    if (G == Gating::kOn && quiet(in))
      return;
    step_blocks<G>(in, order);
  }
  [[nodiscard]] bool idle(const In& in) const {
    const Wires w = wires(in);
    return synchroniser_.idle(w.synchroniser) && engine_.idle(w.engine) && buffer_.idle(w.buffer);
  }
  void reset_now() {
    synchroniser_.reset_now();
    engine_.reset_now();
    buffer_.reset_now();
    settled_ = false;
  }

  // Any strobe the register side acts on (SpiRegisterPort::active, without the copy).
  [[nodiscard]] bool strobing() const { return engine_.strobing(); }
  [[nodiscard]] SpiRegisterPort port() const {
    const SpiEngineRegs& e = engine_.regs();
    return {.snapshot = e.snapshot,
            .read_strobe = e.read_strobe,
            .read_address = e.read_address,
            .commit = e.commit,
            .commit_write = e.commit_write,
            .frame_end = e.frame_end,
            .commit_address = e.commit_address,
            .commit_count = e.commit_count,
            .status = e.status,
            .words = buffer_.regs().words};
  }
  [[nodiscard]] UInt<1> miso() const { return engine_.regs().miso; }

  [[nodiscard]] const SpiSynchroniserRegs& synchroniser() const { return synchroniser_.regs(); }
  [[nodiscard]] const SpiEngineRegs& engine() const { return engine_.regs(); }
  [[nodiscard]] const SpiWriteBufferRegs& buffer() const { return buffer_.regs(); }
  bool operator==(const SpiSlave& o) const {
    return synchroniser() == o.synchroniser() && engine() == o.engine() && buffer() == o.buffer();
  }

  template <class V>
  void trace(V& v) const {
    trace_scope(v, "synchroniser", synchroniser_);
    trace_scope(v, "engine", engine_);
    trace_scope(v, "buffer", buffer_);
  }

 private:
  // Out of line: a bus at rest (the common case) costs quiet() alone.
  template <Gating G, class Order>
  [[gnu::noinline]] void step_blocks(const In& in, const Order& order) {
    // Between SCLK edges the engine is idle, and with it the write buffer
    // (written only on an edge): only the synchroniser moves.
    if (G == Gating::kOn && engine_.idle(engine_in(in))) {
      clock_block<G>(synchroniser_, synchroniser_in(in));
    } else {
      const Wires w = wires(in);
      order([&] { clock_block<G>(synchroniser_, w.synchroniser); },
            [&] { clock_block<G>(engine_, w.engine); }, [&] { clock_block<G>(buffer_, w.buffer); });
    }
    settled_ = G == Gating::kOn && settled();  // only the gated step reads it
  }
  // The synchroniser idle on the pins it last took and no strobe out: then
  // the whole slave is idle for the same pins, no reset and no refused write.
  [[nodiscard]] bool settled() const {
    const SpiSynchroniserRegs& s = synchroniser_.regs();
    return synchroniser_.idle({.sclk = s.sclk_meta,
                               .cs_n = s.cs_meta,
                               .mosi = s.mosi_meta,
                               .active = engine_.regs().active,
                               .reset = {}}) &&
           !engine_.strobing();
  }
  [[nodiscard]] bool quiet(const In& in) const {
    const SpiSynchroniserRegs& s = synchroniser_.regs();
    return settled_ && in.sclk == s.sclk_meta && in.cs_n == s.cs_meta && in.mosi == s.mosi_meta &&
           (in.reset | in.write_refused).is_zero();
  }

  SpiSynchroniser synchroniser_;
  SpiEngine engine_;
  SpiWriteBuffer buffer_;
  bool settled_ = false;  // simulator bookkeeping, not a register: settled() after the last clock
};

}  // namespace odoloc::rtl
