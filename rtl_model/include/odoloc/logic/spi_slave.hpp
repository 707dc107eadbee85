// The SPI slave's logic, written once (docs/spi.md; docs/hls.md, "One source
// per block"): pins in, narrow wires to the register file out. The cycle
// model (rtl/spi_slave.hpp) runs it with the model's types, the register
// interface's HLS kernel (hls/regfile_kernel.hpp, through
// logic/register_interface.hpp) with the vendor's.
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
// its wires from the current registers; regfile::Port carries them):
//   snapshot       one clock, in the clock the cs_n fall is seen: capture the
//                  snapshot registers.
//   read_strobe,   one clock: request word read_address. In the NEXT clock the
//   read_address   composite must drive SlaveIn::read_data = the register
//                  file's read(read_address) (from the current registers); the
//                  slave latches it. Word 0 is requested after command bit 15
//                  (rising edge 16), word k+1 when word k starts shifting out,
//                  so data is fetched just in time (after the snapshot).
//   commit,        one clock, in the clock the cs_n rise is seen, only for a
//   commit_write,  frame of exactly the expected length with no overrun and
//   commit_address,(writes with CRC on) a good CRC. commit_write = 1: the words
//   commit_count   are the write buffer's words[0..commit_count-1], for
//                  commit_address onwards; commit_write = 0: a read frame
//                  completed (e.g. for read-to-clear registers).
//   frame_end      one clock, at every seen cs_n rise of a frame; `status`
//                  then holds that frame's flags.
//   write_refused  the register side drives it in the commit clock (or
//                  later); it is merged into the status of the frame just ended.
//   status         kStatus* flags of the last completed frame (MISO byte 0 of
//                  the next frame).
//
// Three leaves, so that a clock between SCLK edges costs the synchroniser
// alone in the model (the engine and the write buffer are idle then): the
// synchroniser (clocked every clock), the protocol engine (moves on a seen
// edge, a strobe to clear, a read word to latch or a refused write) and the
// write buffer (one write port). Each is Regs, In and next(); Slave computes
// every wire that crosses them from the current registers.
// C++14, no heap, no containers, static loop bounds (int_family.hpp).
#pragma once

#include <cstdint>

#include "odoloc/logic/int_family.hpp"
#include "odoloc/logic/regfile_map.hpp"

namespace odoloc {
namespace logic {
namespace spi {

namespace map = regfile_map;

constexpr int kHeaderBits = 16;  // the command: read bit, burst length - 1, start address
constexpr int kWordBits = map::kDataBits;
constexpr int kCrcBits = 8;
constexpr int kMaxBurst = map::spi::kMaxBurst;
constexpr int kAddressBits = map::kAddressBits;
constexpr int kCountBits = 11;      // SCLK edges of a frame, saturating
constexpr int kLevelBits = 3;       // clocks since the last SCLK edge, saturating
constexpr int kFlagBits = 4;        // the status flags
constexpr int kIndexBits = 5;       // a word of the burst, 0..kMaxBurst-1
constexpr int kBurstCountBits = 6;  // words of a burst, 1..kMaxBurst
constexpr int kMinLevelClocks = map::spi::kMinLevelClocks;
constexpr long long kCountMax = (1LL << kCountBits) - 1;
static_assert(kWordBits == 32 && kAddressBits == 10, "the frame format's word and address");
static_assert((1 << kIndexBits) == kMaxBurst && (1 << (kBurstCountBits - 1)) == kMaxBurst,
              "the burst field holds n - 1");
static_assert(kHeaderBits + kWordBits * kMaxBurst + kCrcBits < kCountMax,
              "the edge count holds a frame");
static_assert(kMinLevelClocks < (1 << kLevelBits), "the level count reaches the minimum");

// The status flags: top.spi_status's fields, one bit each in the low nibble.
constexpr std::uint32_t kCrcError = map::top::spi_status::crc_error.mask();
constexpr std::uint32_t kBadLength = map::top::spi_status::bad_length.mask();
constexpr std::uint32_t kWriteRefused = map::top::spi_status::write_refused.mask();
constexpr std::uint32_t kOverrun = map::top::spi_status::overrun.mask();
static_assert((kCrcError | kBadLength | kWriteRefused | kOverrun) == (1U << kFlagBits) - 1,
              "the flags fill top.spi_status's low nibble");

template <class F>
using Word = uint<F, kWordBits>;
template <class F>
using Address = uint<F, kAddressBits>;
template <class F>
using Crc = uint<F, kCrcBits>;
template <class F>
using Flags = uint<F, kFlagBits>;
template <class F>
using EdgeCount = uint<F, kCountBits>;

// CRC-8 as in SAE J1850 (regmap/odoloc.yaml, spi.crc): polynomial 0x1D,
// init 0xFF, no reflection, final XOR 0xFF. One message bit into the CRC
// shift register, as the hardware does per SCLK.
template <class F>
inline Crc<F> crc8_step(const Crc<F>& crc, const uint<F, 1>& message_bit) {
  const Crc<F> shifted = wrap<Crc<F> >(shl<1>(crc));
  if (bit<7>(crc) != message_bit)
    return wrap<Crc<F> >(shifted ^ Crc<F>(map::spi::kCrcPolynomial));
  return shifted;
}

// ---- pin synchroniser ---------------------------------------------------------
// The two synchroniser flops of each pin, the previous synchronised SCLK and
// cs_n (edge detection) and the clocks since the last SCLK edge.
template <class F>
struct SynchroniserRegs {
  uint<F, 1> sclk_meta{0}, sclk_sync{0}, sclk_prev{0};
  uint<F, 1> cs_meta{0}, cs_sync{0}, cs_prev{0};
  uint<F, 1> mosi_meta{0}, mosi_sync{0};
  uint<F, kLevelBits> level_clocks{0};  // since the last SCLK edge of a frame (or cs_n fall)
};
template <class F>
struct SynchroniserIn {
  uint<F, 1> sclk{0}, cs_n{0}, mosi{0};  // pins, asynchronous
  uint<F, 1> active{0};  // the engine is in a frame: its SCLK edges restart level_clocks
  uint<F, 1> reset{0};
};
// What the engine sees in this clock, from the synchroniser's registers.
template <class F>
struct Seen {
  bool cs_fall = false, cs_rise = false;  // cs_n edges
  bool rise = false, fall = false;        // SCLK edges
  uint<F, 1> mosi{0};
  uint<F, kLevelBits> level_clocks{0};
};

template <class F>
struct Synchroniser {
  using R = SynchroniserRegs<F>;

  static Seen<F> seen(const R& r) {
    Seen<F> s;
    s.cs_fall = is_zero(r.cs_sync) && !is_zero(r.cs_prev);
    s.cs_rise = !is_zero(r.cs_sync) && is_zero(r.cs_prev);
    s.rise = !is_zero(r.sclk_sync) && is_zero(r.sclk_prev);
    s.fall = is_zero(r.sclk_sync) && !is_zero(r.sclk_prev);
    s.mosi = r.mosi_sync;
    s.level_clocks = r.level_clocks;
    return s;
  }

  static R next(const R& r, const SynchroniserIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    const Seen<F> s = seen(r);
    const bool restart = s.cs_fall || (!is_zero(in.active) && (s.rise || s.fall));
    const long long saturated = (1LL << kLevelBits) - 1;
    R n;
    n.sclk_meta = in.sclk;
    n.sclk_sync = r.sclk_meta;
    n.sclk_prev = r.sclk_sync;
    n.cs_meta = in.cs_n;
    n.cs_sync = r.cs_meta;
    n.cs_prev = r.cs_sync;
    n.mosi_meta = in.mosi;
    n.mosi_sync = r.mosi_meta;
    if (restart)
      n.level_clocks = uint<F, kLevelBits>(1);
    else if (to_s64(r.level_clocks) != saturated)
      n.level_clocks = wrap<uint<F, kLevelBits> >(r.level_clocks + uint<F, 1>(1));
    else
      n.level_clocks = r.level_clocks;
    return n;
  }
};

// ---- write buffer -----------------------------------------------------------------
// The words of a write frame, one write port: a word is stored in the clock
// its last bit is received. Valid while the engine's commit is high.
// A struct per word, not an array of integers: `= {}` leaves ap_int elements
// undefined, a member initialiser does not.
template <class F>
struct BufferWord {
  Word<F> value{0};
};
template <class F>
struct WriteBufferRegs {
  BufferWord<F> words[kMaxBurst];
};
template <class F>
struct WriteBufferIn {
  uint<F, 1> write{0};
  uint<F, kIndexBits> index{0};
  Word<F> word{0};
  uint<F, 1> reset{0};
};

template <class F>
struct WriteBuffer {
  using R = WriteBufferRegs<F>;
  static R next(const R& r, const WriteBufferIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    if (!is_zero(in.write))
      n.words[to_s64(in.index)].value = in.word;
    return n;
  }
};

// ---- protocol engine ------------------------------------------------------------
// The frame state, the shift registers, the CRCs and every output to the
// register side.
template <class F>
struct EngineRegs {
  uint<F, 1> active{0};      // between a seen cs_n fall and rise
  uint<F, 1> crc_on{0};      // crc_enable latched at cs_n fall
  uint<F, 1> fall_armed{0};  // 0 in mode 3 until the first falling edge
  uint<F, 1> frame_overrun{0};
  EdgeCount<F> rx_count{0};  // rising edges in this frame, saturating
  Word<F> rx_shift{0};
  Crc<F> rx_crc{0};
  uint<F, kHeaderBits> command{0};
  EdgeCount<F> tx_count{0};  // index of the MISO bit on the pin, saturating
  Word<F> tx_shift{0};       // the bits after it
  Crc<F> tx_crc{0};
  Word<F> read_word{0};  // the next word to shift out, fetched ahead
  // outputs
  uint<F, 1> miso{0};
  uint<F, 1> snapshot{0};
  uint<F, 1> read_strobe{0};
  Address<F> read_address{0};
  uint<F, 1> commit{0}, commit_write{0};
  uint<F, 1> frame_end{0};  // one clock: a frame ended; `status` holds its flags
  Address<F> commit_address{0};
  uint<F, kBurstCountBits> commit_count{0};
  Flags<F> status{0};
};
template <class F>
struct EngineIn {
  Seen<F> seen;
  uint<F, 1> crc_enable{0}, spi_mode3{0};
  Word<F> read_data{0};  // the register file's read(read_address), the clock after read_strobe
  uint<F, 1> write_refused{0};
  uint<F, 1> reset{0};
};

template <class F>
struct Engine {
  using R = EngineRegs<F>;

  static R next(const R& r, const EngineIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    n.snapshot = n.read_strobe = n.commit = n.frame_end = uint<F, 1>(0);
    if (!is_zero(r.read_strobe))
      n.read_word = in.read_data;
    if (!is_zero(in.write_refused))
      n.status = wrap<Flags<F> >(r.status | Flags<F>(kWriteRefused));

    if (in.seen.cs_fall) {
      start_frame(n, in);  // an SCLK edge seen in the same clock is dropped
      return n;
    }
    if (is_zero(r.active))
      return n;
    if ((in.seen.rise || in.seen.fall) && to_s64(in.seen.level_clocks) < kMinLevelClocks)
      n.frame_overrun = uint<F, 1>(1);
    if (in.seen.rise)
      receive_bit(r, n, in.seen.mosi);
    if (in.seen.fall)
      drive_next_bit(r, n);
    if (in.seen.cs_rise)
      end_frame(r, n);
    return n;
  }

  // Any strobe the register side acts on.
  static bool strobing(const R& r) {
    return !is_zero(r.snapshot | r.read_strobe | r.commit | r.frame_end);
  }

  // The write buffer's port in this clock: a write frame's word whose last
  // bit the rising edge of this clock brings in.
  static WriteBufferIn<F> word_write(const R& r, const EngineIn<F>& in) {
    WriteBufferIn<F> w;
    w.word = received(r, in.seen.mosi);
    w.reset = in.reset;
    if (!is_zero(in.reset) || in.seen.cs_fall || is_zero(r.active) || !in.seen.rise ||
        is_read(r.command))
      return w;
    // The command is stored at bit 16, before any data bit.
    const long long c = next_count(r.rx_count);
    if (c > kHeaderBits && c <= data_end(r.command) && (c - kHeaderBits) % kWordBits == 0) {
      w.write = uint<F, 1>(1);
      w.index = wrap<uint<F, kIndexBits> >((c - kHeaderBits) / kWordBits - 1);
    }
    return w;
  }

 private:
  static bool is_read(const uint<F, kHeaderBits>& command) {
    return !is_zero(bit<kHeaderBits - 1>(command));
  }
  static long long burst(const uint<F, kHeaderBits>& command) {
    return to_s64(bits<kHeaderBits - 2, kAddressBits>(command)) + 1;
  }
  // Bit index where the CRC byte starts (= data bits end).
  static long long data_end(const uint<F, kHeaderBits>& command) {
    return kHeaderBits + kWordBits * burst(command);
  }
  static Address<F> word_address(const uint<F, kHeaderBits>& command, long long k) {
    return wrap<Address<F> >(to_s64(bits<kAddressBits - 1, 0>(command)) + k);
  }
  // A count after one more edge, saturating.
  static long long next_count(const EdgeCount<F>& count) {
    const long long c = to_s64(count) + 1;
    return c < kCountMax ? c : kCountMax;
  }
  // The receive shift register after a rising edge samples `mosi`.
  static Word<F> received(const R& r, const uint<F, 1>& mosi) {
    return cat(bits<kWordBits - 2, 0>(r.rx_shift), mosi);
  }
  // Puts w's MSB on the pin and keeps the rest.
  static void shift_out(R& n, const Word<F>& w) {
    n.miso = bit<kWordBits - 1>(w);
    n.tx_shift = wrap<Word<F> >(shl<1>(w));
  }

  static void start_frame(R& n, const EngineIn<F>& in) {
    n.active = uint<F, 1>(1);
    n.crc_on = in.crc_enable;
    n.fall_armed = wrap<uint<F, 1> >(is_zero(in.spi_mode3) ? 1 : 0);
    n.frame_overrun = uint<F, 1>(0);
    n.rx_count = EdgeCount<F>(0);
    n.rx_crc = Crc<F>(map::spi::kCrcInit);
    n.command = uint<F, kHeaderBits>(0);  // a frame cut before bit 16 then expects >= 48 bits
    n.tx_count = EdgeCount<F>(0);
    n.snapshot = uint<F, 1>(1);
    // The status byte, then 0x00, then the first word.
    shift_out(n, wrap<Word<F> >(shl<kWordBits - 8>(wrap<uint<F, 8> >(n.status))));
    n.tx_crc = crc8_step<F>(Crc<F>(map::spi::kCrcInit), n.miso);
  }

  static void receive_bit(const R& r, R& n, const uint<F, 1>& mosi) {
    const long long c = next_count(r.rx_count);
    n.rx_count = wrap<EdgeCount<F> >(c);
    n.rx_shift = received(r, mosi);
    if (c == kHeaderBits) {
      n.command = bits<kHeaderBits - 1, 0>(n.rx_shift);
      if (is_read(n.command)) {
        n.read_strobe = uint<F, 1>(1);
        n.read_address = word_address(n.command, 0);
      }
    }
    const long long end = c <= kHeaderBits ? kHeaderBits : data_end(n.command);
    if (c <= end)
      n.rx_crc = crc8_step<F>(r.rx_crc, mosi);
  }

  static void drive_next_bit(const R& r, R& n) {
    if (is_zero(r.fall_armed)) {
      n.fall_armed = uint<F, 1>(1);
      return;
    }
    const long long i = next_count(r.tx_count);
    n.tx_count = wrap<EdgeCount<F> >(i);
    const long long end = data_end(r.command);
    if (i >= kHeaderBits && i < end && (i - kHeaderBits) % kWordBits == 0) {
      const long long k = (i - kHeaderBits) / kWordBits;
      const bool read = is_read(r.command);
      shift_out(n, read ? r.read_word : Word<F>(0));
      if (read && k + 1 < burst(r.command)) {
        n.read_strobe = uint<F, 1>(1);
        n.read_address = word_address(r.command, k + 1);
      }
    } else if (i == end) {
      const Crc<F> sent = wrap<Crc<F> >(r.tx_crc ^ Crc<F>(map::spi::kCrcXorOut));
      shift_out(n,
                is_zero(r.crc_on) ? Word<F>(0) : wrap<Word<F> >(shl<kWordBits - kCrcBits>(sent)));
    } else {
      shift_out(n, r.tx_shift);
    }
    if (i < end)
      n.tx_crc = crc8_step<F>(r.tx_crc, n.miso);
  }

  static void end_frame(const R& r, R& n) {
    n.active = uint<F, 1>(0);
    n.frame_end = uint<F, 1>(1);
    n.miso = uint<F, 1>(0);
    const bool write = !is_read(n.command);
    const long long expected = data_end(n.command) + (is_zero(r.crc_on) ? 0 : kCrcBits);
    const bool bad_length = to_s64(n.rx_count) != expected;
    // Reads are checked too: a corrupted read command must not clear an rc register.
    const Crc<F> crc = wrap<Crc<F> >(n.rx_crc ^ Crc<F>(map::spi::kCrcXorOut));
    const bool crc_error = !bad_length && !is_zero(r.crc_on) && crc != bits<7, 0>(n.rx_shift);
    const bool overrun = !is_zero(n.frame_overrun);
    n.status = wrap<Flags<F> >((crc_error ? kCrcError : 0U) | (bad_length ? kBadLength : 0U) |
                               (overrun ? kOverrun : 0U));
    if (!bad_length && !crc_error && !overrun) {
      n.commit = uint<F, 1>(1);
      n.commit_write = wrap<uint<F, 1> >(write ? 1 : 0);
      n.commit_address = word_address(n.command, 0);
      n.commit_count = wrap<uint<F, kBurstCountBits> >(burst(n.command));
    }
  }
};

// ---- the slave ----------------------------------------------------------------------
template <class F>
struct SlaveRegs {
  SynchroniserRegs<F> synchroniser;
  EngineRegs<F> engine;
  WriteBufferRegs<F> buffer;
};
template <class F>
struct SlaveIn {
  uint<F, 1> sclk{0}, cs_n{0}, mosi{0};  // pins, asynchronous
  uint<F, 1> crc_enable{0}, spi_mode3{0};
  Word<F> read_data{0};  // the register file's read(read_address), the clock after read_strobe
  uint<F, 1> write_refused{0};
  uint<F, 1> reset{0};
};

// The wires that cross the leaves, each from the current registers only.
template <class F>
struct Slave {
  static SynchroniserIn<F> synchroniser_in(const EngineRegs<F>& engine, const SlaveIn<F>& in) {
    SynchroniserIn<F> s;
    s.sclk = in.sclk;
    s.cs_n = in.cs_n;
    s.mosi = in.mosi;
    s.active = engine.active;
    s.reset = in.reset;
    return s;
  }
  static EngineIn<F> engine_in(const SynchroniserRegs<F>& synchroniser, const SlaveIn<F>& in) {
    EngineIn<F> e;
    e.seen = Synchroniser<F>::seen(synchroniser);
    e.crc_enable = in.crc_enable;
    e.spi_mode3 = in.spi_mode3;
    e.read_data = in.read_data;
    e.write_refused = in.write_refused;
    e.reset = in.reset;
    return e;
  }
  // One fabric clock of the whole slave.
  static SlaveRegs<F> next(const SlaveRegs<F>& r, const SlaveIn<F>& in) {
    const EngineIn<F> engine = engine_in(r.synchroniser, in);
    SlaveRegs<F> n;
    n.synchroniser = Synchroniser<F>::next(r.synchroniser, synchroniser_in(r.engine, in));
    n.engine = Engine<F>::next(r.engine, engine);
    n.buffer = WriteBuffer<F>::next(r.buffer, Engine<F>::word_write(r.engine, engine));
    return n;
  }
};

}  // namespace spi
}  // namespace logic
}  // namespace odoloc
