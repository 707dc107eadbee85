// The SPI register file as an HLS kernel: one call = one SPI transaction of
// rtl::SpiSlave (its frame-level behaviour) and rtl::FabricRegisters together
// (docs/spi.md), in odoloc::hls integer types (types.hpp). C++14.
//
// Why a transaction and not a clock: the register file acts on whole frames
// (the snapshot when cs_n falls, the commit when it rises with a good length
// and CRC, the status byte of the next frame). In front of it the slave's
// bit-level part is a synchroniser and a serial-in shift register that only
// turns pins into the frame's bits; the model already has it
// (rtl::SpiSlave), and a call per clock would spend ~8 calls per frame bit on
// it. So a call takes the frame as the slave received it and returns
// everything the frame produced.
//
// Every address, mask, reset value and the CRC come from the register map
// (odoloc/hls/regfile_map.hpp, generated from regmap/odoloc.yaml); the kernel
// derives its tables from them at compile time, as FabricRegisters derives
// its own from odoloc/regs.hpp.
//
// Inputs (per call = per frame, cs_n fall to rise):
//   reset [1]          synchronous reset instead of a frame: every register to
//                      its reset value, no frame, all outputs of a quiet call
//   command [16]       MOSI bits 0..15: [15] 1 read / 0 write, [14:10] burst
//                      length n - 1, [9:0] start word address (auto-increments,
//                      modulo 1024)
//   data_0..data_31 [32]  MOSI words 0..n-1 (bits 16 + 32k ..); words k >= n are
//                      not part of the frame and are ignored; read frames send
//                      them too (don't care, but the CRC covers them)
//   crc [8]            the MOSI byte after the last word (the frame's CRC-8 when
//                      top.ctrl.crc_enable was set at cs_n fall)
//   bits [11]          SCLK rising edges the slave saw (rtl::SpiEngineRegs::
//                      rx_count): 16 + 32n (+ 8 with CRC) for a good frame, fewer
//                      for a chip select raised early, more for one held too long
//   overrun [1]        an SCLK level (or cs_n low before the first edge) lasted
//                      less than spi.min_level_clocks fabric clocks: the frame
//                      commits nothing
//   <register> [32]    the fabric's status: per register with bits the hardware
//                      drives (hw w, set, count) except the register file's own
//                      top.spi_status and top.frame_errors, the word those
//                      bits make (ports.hpp encode_status; other bits ignored),
//                      named after the register (eppm_left_rear_count, ...).
//                      Sampled once per call: it is the snapshot taken at cs_n
//                      fall, and the live value of the other status registers
//                      for the whole frame.
//
// Outputs:
//   miso_header [16]   MISO bits 0..15: the status byte of the previous frame
//                      (top.spi_status bits), then 0x00
//   miso_data_0..31 [32]  MISO words 0..n-1: the read data (snapshot registers:
//                      the sample; others: stored rw bits, constants, status
//                      bits; unmapped: 0); 0 in write frames and for k >= n
//   miso_crc [8]       the MISO byte after the last word: CRC-8 of MISO bytes
//                      0..4n+1 with crc_enable, else 0
//                      (MISO bits the master did not clock read 0: only the
//                      first `bits` bits of the MISO stream are ports)
//   frame_status [4]   this frame's flags (crc_error, bad_length, overrun,
//                      write_refused at their top.spi_status positions): the
//                      next frame's status byte
//   spi_status [4], frame_errors [16]  top.spi_status (sticky, w1c) and
//                      top.frame_errors (frames with any flag, saturating, rc)
//                      after the frame
//   config_<register> [32]  the stored rw bits of every rw register after the
//                      frame: the configuration ports are their fields
//   pulse_<register> [32]  per register with w1c or w1p bits: the bits this
//                      frame wrote 1 to (w1c clears, w1p commands), one-clock
//                      strobes to the blocks; 0 unless a write committed
//   pops_<fifo> [4]    per rpop FIFO: the whole entries a completed read frame
//                      read in order from its first word (the FIFO pops them)
//
// What a frame does (rtl::SpiSlave and rtl::FabricRegisters):
// - A frame commits only with exactly the expected number of bits, no overrun
//   and, with crc_enable, a matching MOSI CRC; else it sets bad_length,
//   overrun or crc_error and changes nothing but the flags.
// - A committed write stores the rw bits and pulses the w1c/w1p bits of every
//   word; a word to an unmapped or read-only address is dropped and sets
//   write_refused, the other words still land.
// - A committed read clears top.frame_errors if it read it (rc) and pops the
//   rpop FIFOs it read in order from their first word.
// - top.spi_status: the written w1c clears and odometry.command.clear_flags act
//   first, then the frame's flags are added; top.frame_errors counts the frames
//   with any flag. crc_enable is the stored top.ctrl at the frame's start.
//
// Timing in the fabric: the slave sees cs_n rise in the third fabric clock
// after the pin, the register file commits in the next one, and the
// configuration and the pulses reach the blocks in the clock after that; the
// kernel's ports carry those values per frame. The top (hls/src/
// regfile_top.cpp) is not II=1: the frame's end starts it (ap_ctrl_hs), and a
// call takes a few passes over the 32 burst words (CRCs, reads, writes), each
// pipelined with II=1, far less than a complete frame lasts (>= 48 SCLK
// periods).
// Reset: the registers' initialisers (stored words: the map's reset values).
// No heap, no containers, no floating point, static loop bounds.
#pragma once

#include <cstdint>

#include "odoloc/hls/regfile_map.hpp"
#include "odoloc/hls/types.hpp"

namespace odoloc {
namespace hls {
namespace regfile {

namespace map = regfile_map;

// Loop labels name the loops in the HLS tools' reports; no C++ jumps to them.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-label"
#endif

// ---- the frame (docs/spi.md) -------------------------------------------------------
constexpr int kMaxBurst = map::spi::kMaxBurst;
constexpr int kAddressBits = map::kAddressBits;
constexpr int kWordBits = map::kDataBits;
constexpr int kHeaderBits = 16;  // the command: read bit, burst length - 1, start address
constexpr int kBurstBits = kHeaderBits - 1 - kAddressBits;
constexpr int kCrcBits = 8;
static_assert(kBurstBits >= 1 && (1 << kBurstBits) >= kMaxBurst, "the burst field holds n - 1");
static_assert(kWordBits == 32, "the kernel's words are 32 bits");

using Command = uint<kHeaderBits>;
using Address = uint<kAddressBits>;
using Burst = uint<kBurstBits + 1>;  // 1..kMaxBurst words
using BitCount = uint<11>;           // rtl::SpiEngineRegs::rx_count (saturates at 2047)
using Crc = uint<kCrcBits>;
using Flags = uint<4>;  // rtl::SpiEngineRegs::status, FabricRegistersRegs::spi_status
using ErrorCount = uint<map::top::frame_errors::count.width>;
static_assert(kHeaderBits + kWordBits * kMaxBurst + kCrcBits < (1 << 11), "bits holds a frame");

// The status flags: top.spi_status's fields (rtl::SpiSlave::kStatus*).
constexpr std::uint32_t kCrcError = map::top::spi_status::crc_error.mask();
constexpr std::uint32_t kBadLength = map::top::spi_status::bad_length.mask();
constexpr std::uint32_t kWriteRefused = map::top::spi_status::write_refused.mask();
constexpr std::uint32_t kOverrun = map::top::spi_status::overrun.mask();
static_assert((kCrcError | kBadLength | kWriteRefused | kOverrun) < 16, "flags fit 4 bits");
static_assert(map::top::frame_errors::count.lsb == 0, "frame_errors' count is its word's low bits");

// ---- the register file's tables, from the map at compile time ----------------------
// Banks: the stored rw words (configuration), the status words (ports in),
// the pulse words (w1c/w1p strobes out). top.spi_status and top.frame_errors
// are this block's own registers, not fabric status.
enum Bank { kStored, kStatus, kPulse, kBanks };

constexpr bool is_own(const map::Register& r) {
  return r.address == map::top::spi_status::kAddress ||
         r.address == map::top::frame_errors::kAddress;
}
constexpr bool in_bank(int bank, const map::Register& r) {
  return bank == kStored   ? r.rw_mask != 0
         : bank == kStatus ? r.hw_mask != 0 && !is_own(r)
                           : (r.w1c_mask | r.w1p_mask) != 0;
}
constexpr int bank_size(int bank) {
  int n = 0;
  for (int i = 0; i < map::kRegisterCount; ++i)
    n += in_bank(bank, map::kRegisters[i]) ? 1 : 0;
  return n;
}
constexpr int kStoredWords = bank_size(kStored);
constexpr int kStatusWords = bank_size(kStatus);
constexpr int kPulseWords = bank_size(kPulse);
constexpr int kPopWindows = map::kPopWindowCount;
static_assert(kStoredWords > 0 && kStatusWords > 0 && kPulseWords > 0 && kPopWindows > 0,
              "the map has configuration, status, strobes and FIFOs");

// Bits of the largest FIFO's entry count (ports.hpp's pops width).
constexpr int pop_bits() {
  int entries = 0;
  for (int w = 0; w < kPopWindows; ++w)
    entries = map::kPopWindows[w].entries > entries ? map::kPopWindows[w].entries : entries;
  int bits = 0;
  for (int b = 0; b < 31; ++b)
    bits = (entries >> b) != 0 ? b + 1 : bits;
  return bits;
}
constexpr int kPopBits = pop_bits();

struct Layout {
  short register_at[map::kAddressSpace];      // address -> register index, -1: unmapped
  short slot[kBanks][map::kRegisterCount];    // register -> its word in a bank, -1: none
  short member[kBanks][map::kRegisterCount];  // a bank's word -> its register
  std::uint32_t stored_reset[kStoredWords];   // reset & rw_mask
};
constexpr Layout make_layout() {
  Layout t = {};
  for (int a = 0; a < map::kAddressSpace; ++a)
    t.register_at[a] = -1;
  int next[kBanks] = {0, 0, 0};
  for (int i = 0; i < map::kRegisterCount; ++i) {
    const map::Register& r = map::kRegisters[i];
    t.register_at[r.address] = static_cast<short>(i);
    for (int b = 0; b < kBanks; ++b) {
      t.slot[b][i] = -1;
      if (in_bank(b, r)) {
        t.slot[b][i] = static_cast<short>(next[b]);
        t.member[b][next[b]++] = static_cast<short>(i);
      }
    }
    if (in_bank(kStored, r))
      t.stored_reset[t.slot[kStored][i]] = r.reset & r.rw_mask;
  }
  return t;
}
constexpr Layout kLayout = make_layout();

// The registers the block treats by name, as FabricRegisters does.
constexpr int kCtrl = kLayout.register_at[map::top::ctrl::kAddress];
constexpr int kSpiStatus = kLayout.register_at[map::top::spi_status::kAddress];
constexpr int kFrameErrors = kLayout.register_at[map::top::frame_errors::kAddress];
constexpr int kCommand = kLayout.register_at[map::odometry::command::kAddress];
constexpr int kCtrlWord = kLayout.slot[kStored][kCtrl];
constexpr int kSpiStatusPulse = kLayout.slot[kPulse][kSpiStatus];
constexpr int kCommandPulse = kLayout.slot[kPulse][kCommand];
static_assert(kCtrlWord >= 0 && kSpiStatusPulse >= 0 && kCommandPulse >= 0,
              "top.ctrl is rw, top.spi_status w1c, odometry.command w1p");

// ---- ports -------------------------------------------------------------------------
// An element of a port or register array. The initialiser makes every element
// 0 under ap_int.h too, whose default constructor leaves the value undefined.
template <int W>
struct Cell {
  uint<W> value = 0;
};
using Word = Cell<kWordBits>;

struct Inputs {
  uint<1> reset = 0;
  Command command = 0;
  Word data[kMaxBurst];
  Crc crc = 0;
  BitCount bits = 0;
  uint<1> overrun = 0;
  Word status[kStatusWords];  // bank kStatus, in address order
};

struct Outputs {
  uint<kHeaderBits> miso_header = 0;
  Word miso_data[kMaxBurst];
  Crc miso_crc = 0;
  Flags frame_status = 0;
  Flags spi_status = 0;
  ErrorCount frame_errors = 0;
  Word config[kStoredWords];  // bank kStored
  Word pulse[kPulseWords];    // bank kPulse
  Cell<kPopBits> pops[kPopWindows];
};

// ---- registers (FabricRegistersRegs and the slave's status; the snapshot
// bank needs no register here: a call's status input is that snapshot) -------------
struct StoredWords {
  Word word[kStoredWords];
};
inline StoredWords stored_resets() {
  StoredWords s;
stored_reset_loop:
  for (int i = 0; i < kStoredWords; ++i)
    s.word[i].value = kLayout.stored_reset[i];
  return s;
}

struct Registers {
  StoredWords stored = stored_resets();  // rw bits of the rw registers
  Flags status = 0;                      // the last frame's flags (rtl::SpiEngineRegs::status)
  Flags spi_status = 0;                  // top.spi_status, sticky
  ErrorCount frame_errors = 0;           // top.frame_errors, saturating
};

// ---- port names (testbenches only: never synthesised) ------------------------------
// Column names built at compile time: "data_7", "config_eppm_left_rear_cfg".
constexpr int kNameChars = 48;
struct Name {
  char text[kNameChars];
};
template <int N>
struct Names {
  Name of[N];
};

// prefix + stem + the decimal index (left out when negative). Longer names are
// cut, which the testbenches' name check reports.
constexpr Name port_name(const char* prefix, const char* stem, int index) {
  Name name = {};
  int n = 0;
  for (const char* s = prefix; *s != '\0' && n < kNameChars - 1; ++s)
    name.text[n++] = *s;
  for (const char* s = stem; *s != '\0' && n < kNameChars - 1; ++s)
    name.text[n++] = *s;
  char digits[10] = {};
  int count = 0;
  for (int v = index; v > 0 || (count == 0 && index == 0); v /= 10)
    digits[count++] = static_cast<char>('0' + v % 10);
  while (count > 0 && n < kNameChars - 1)
    name.text[n++] = digits[--count];
  return name;
}
template <int N>
constexpr Names<N> indexed_names(const char* prefix) {
  Names<N> names = {};
  for (int k = 0; k < N; ++k)
    names.of[k] = port_name(prefix, "", k);
  return names;
}
// prefix + the register's name, for every word of a bank.
template <int N>
constexpr Names<N> bank_names(const char* prefix, int bank) {
  Names<N> names = {};
  for (int k = 0; k < N; ++k)
    names.of[k] = port_name(prefix, map::kRegisterNames[kLayout.member[bank][k]], -1);
  return names;
}
constexpr Names<kPopWindows> pop_names() {
  Names<kPopWindows> names = {};
  for (int w = 0; w < kPopWindows; ++w)
    names.of[w] = port_name("pops_", map::kPopWindowNames[w], -1);
  return names;
}

// The ports by name, in the golden vectors' column order (testbenches only).
template <class Visit>
void visit_fields(Inputs& s, Visit&& v) {
  static constexpr Names<kMaxBurst> kData = indexed_names<kMaxBurst>("data_");
  v("reset", s.reset);
  v("command", s.command);
data_names:
  for (int k = 0; k < kMaxBurst; ++k)
    v(kData.of[k].text, s.data[k].value);
  v("crc", s.crc);
  v("bits", s.bits);
  v("overrun", s.overrun);
status_names:
  for (int k = 0; k < kStatusWords; ++k)
    v(map::kRegisterNames[kLayout.member[kStatus][k]], s.status[k].value);
}
template <class Visit>
void visit_fields(Outputs& s, Visit&& v) {
  static constexpr Names<kMaxBurst> kMisoData = indexed_names<kMaxBurst>("miso_data_");
  static constexpr Names<kStoredWords> kConfig = bank_names<kStoredWords>("config_", kStored);
  static constexpr Names<kPulseWords> kPulses = bank_names<kPulseWords>("pulse_", kPulse);
  static constexpr Names<kPopWindows> kPops = pop_names();
  v("miso_header", s.miso_header);
miso_names:
  for (int k = 0; k < kMaxBurst; ++k)
    v(kMisoData.of[k].text, s.miso_data[k].value);
  v("miso_crc", s.miso_crc);
  v("frame_status", s.frame_status);
  v("spi_status", s.spi_status);
  v("frame_errors", s.frame_errors);
config_names:
  for (int k = 0; k < kStoredWords; ++k)
    v(kConfig.of[k].text, s.config[k].value);
pulse_names:
  for (int k = 0; k < kPulseWords; ++k)
    v(kPulses.of[k].text, s.pulse[k].value);
pop_names:
  for (int w = 0; w < kPopWindows; ++w)
    v(kPops.of[w].text, s.pops[w].value);
}

// ---- the logic ----------------------------------------------------------------------
// CRC-8 (spi.crc: MSB first, no reflection) over the W bits of `message`, one
// shift per bit as rtl::crc8_step; unrolled, the XORs fold into one level of
// parity trees.
template <int W>
inline Crc crc_update(Crc crc, uint<W> message) {
#pragma HLS inline
crc_bit_loop:
  for (int i = W - 1; i >= 0; --i) {
#pragma HLS unroll
    const Crc shifted = crc << 1;  // ap_int and ac_int keep 8 bits, the own type wraps here
    if (bit(crc, 7) != bit(message, i))
      crc = shifted ^ map::spi::kCrcPolynomial;
    else
      crc = shifted;
  }
  return crc;
}

// The first `received` bits (MSB first) of a W-bit piece of the MISO stream:
// the master clocks no more.
template <int W>
inline uint<W> clocked(uint<W> value, int received) {
#pragma HLS inline
  if (received <= 0)
    return 0;
  if (received >= W)
    return value;
  return (value >> (W - received)) << (W - received);
}

inline int register_at(Address a) {
  return kLayout.register_at[to_s64(a)];
}

// The frame as the slave received it. The command is latched at its 16th bit,
// so a frame cut shorter reads as command 0 (as in the model; such a frame has
// the wrong length whatever its command, and the master clocked no data).
struct Frame {
  uint<1> read;
  Burst count;  // words, 1..kMaxBurst
  Address start;
  uint<1> crc_on;     // top.ctrl.crc_enable, as the slave latched it at cs_n fall
  BitCount data_end;  // where the CRC byte starts
  uint<1> commit;     // exact length, no overrun, matching CRC
  Flags flags;        // crc_error, bad_length, overrun
};

// Word `a` as a read returns it while the frame runs (FabricRegisters::read).
inline uint<kWordBits> read_word(const Registers& r, const Inputs& in, Address a) {
#pragma HLS inline
  const int reg = register_at(a);
  if (reg < 0)
    return 0;  // unmapped or reserved
  const map::Register& d = map::kRegisters[reg];
  const int status = kLayout.slot[kStatus][reg];
  uint<kWordBits> hw = 0;
  if (status >= 0)
    hw = in.status[status].value & d.hw_mask;
  if (d.snapshot)
    return hw;  // the snapshot bank holds only what the fabric drives
  if (reg == kSpiStatus)
    hw = r.spi_status;
  if (reg == kFrameErrors)
    hw = r.frame_errors;
  const int stored = kLayout.slot[kStored][reg];
  const uint<kWordBits> rw = stored >= 0 ? r.stored.word[stored].value : uint<kWordBits>(0);
  return (rw & d.rw_mask) | (d.reset & d.const_mask) | hw;
}

// The MOSI side: command, length and CRC checks (rtl::SpiEngine::end_frame).
inline Frame receive(const Registers& r, const Inputs& in) {
#pragma HLS inline
  Frame f;
  const Command command = in.bits >= kHeaderBits ? in.command : Command(0);
  f.read = bit(command, kHeaderBits - 1) ? 1 : 0;
  f.count = bits<kHeaderBits - 2, kAddressBits>(command) + 1;
  f.start = bits<kAddressBits - 1, 0>(command);
  f.crc_on = bit(r.stored.word[kCtrlWord].value, map::top::ctrl::crc_enable.lsb) ? 1 : 0;
  f.data_end = kHeaderBits + f.count * kWordBits;
  const BitCount expected = f.data_end + (f.crc_on == 1 ? kCrcBits : 0);
  Crc crc = map::spi::kCrcInit;
  crc = crc_update<kHeaderBits>(crc, command);
mosi_crc_loop:
  for (int k = 0; k < kMaxBurst; ++k) {
#pragma HLS pipeline II = 1
    if (k < f.count)
      crc = crc_update<kWordBits>(crc, in.data[k].value);
  }
  const bool bad_length = in.bits != expected;
  const bool crc_error = !bad_length && f.crc_on == 1 && (crc ^ map::spi::kCrcXorOut) != in.crc;
  const bool overrun = in.overrun == 1;
  f.flags =
      (crc_error ? kCrcError : 0U) | (bad_length ? kBadLength : 0U) | (overrun ? kOverrun : 0U);
  f.commit = !bad_length && !crc_error && !overrun ? 1 : 0;
  return f;
}

// The MISO side, from the registers as the frame found them: the status byte,
// the words read (in order, each fetched just before it shifts out) and the
// CRC over them (rtl::SpiEngine::drive_next_bit).
inline void respond(const Registers& r, const Inputs& in, const Frame& f, Outputs& o) {
#pragma HLS inline
  const int received = static_cast<int>(to_s64(in.bits));
  const uint<kHeaderBits> status = r.status;  // widened before the shift
  const uint<kHeaderBits> header = status << 8;
  Crc crc = map::spi::kCrcInit;
  crc = crc_update<kHeaderBits>(crc, header);
  o.miso_header = clocked<kHeaderBits>(header, received);
miso_word_loop:
  for (int k = 0; k < kMaxBurst; ++k) {
#pragma HLS pipeline II = 1
    uint<kWordBits> word = 0;
    if (k < f.count) {
      if (f.read == 1) {
        const Address a = f.start + k;  // wraps, as the burst does
        word = read_word(r, in, a);
      }
      crc = crc_update<kWordBits>(crc, word);
    }
    o.miso_data[k].value = clocked<kWordBits>(word, received - kHeaderBits - kWordBits * k);
  }
  const Crc sent = f.crc_on == 1 ? Crc(crc ^ map::spi::kCrcXorOut) : Crc(0);
  o.miso_crc = clocked<kCrcBits>(sent, received - static_cast<int>(to_s64(f.data_end)));
}

// A word's write (FabricRegisters::write_word): false when refused.
inline bool write_word(Registers& n, const Registers& r, Outputs& o, Address a,
                       uint<kWordBits> data) {
#pragma HLS inline
  const int reg = register_at(a);
  if (reg < 0)
    return false;
  const map::Register& d = map::kRegisters[reg];
  if ((d.rw_mask | d.w1c_mask | d.w1p_mask) == 0)
    return false;
  const int stored = kLayout.slot[kStored][reg];
  if (stored >= 0)
    n.stored.word[stored].value = (r.stored.word[stored].value & ~d.rw_mask) | (data & d.rw_mask);
  const int pulse = kLayout.slot[kPulse][reg];
  if (pulse >= 0)
    o.pulse[pulse].value = data & (d.w1c_mask | d.w1p_mask);
  return true;
}

// A committed frame's effects, then the flags (FabricRegisters::eval at the
// commit, and the slave's status).
inline void commit(Registers& n, const Registers& r, const Inputs& in, const Frame& f, Outputs& o) {
#pragma HLS inline
  bool refused = false;
  if (f.commit == 1 && f.read == 0) {
  write_loop:
    for (int k = 0; k < kMaxBurst; ++k) {
#pragma HLS pipeline II = 1
      if (k < f.count) {
        const Address a = f.start + k;
        if (!write_word(n, r, o, a, in.data[k].value))
          refused = true;
      }
    }
  }
  if (f.commit == 1 && f.read == 1) {
    // rc: the model subtracts what the frame returned; nothing counts while a
    // frame runs, so a completed read of frame_errors clears it.
    const Address errors_at = map::top::frame_errors::kAddress - f.start;
    if (errors_at < f.count)
      n.frame_errors = 0;
  pop_loop:
    for (int w = 0; w < kPopWindows; ++w) {
#pragma HLS unroll
      // The window's first word's place in the burst; the words after it, up
      // to the window's end, are read in order.
      const map::PopWindow& window = map::kPopWindows[w];
      const Address first_at = window.first - f.start;
      if (first_at < f.count) {
        const Burst after = f.count - first_at;
        const int size = window.entries * window.words;
        const int words = after < size ? static_cast<int>(to_s64(after)) : size;
        o.pops[w].value = words / window.words;
      }
    }
  }
  const Flags flags = f.flags | (refused ? kWriteRefused : 0U);
  n.status = flags;
  // top.spi_status: written clears act at once, then clear_flags, then the
  // frame's flags; a frame with any flag counts.
  Flags sticky = r.spi_status & ~bits<3, 0>(o.pulse[kSpiStatusPulse].value);
  if ((o.pulse[kCommandPulse].value & map::odometry::command::clear_flags.mask()) != 0)
    sticky = 0;
  n.spi_status = sticky | flags;
  const int kMaxErrors = (1 << map::top::frame_errors::count.width) - 1;
  if (flags != 0 && n.frame_errors != kMaxErrors)
    n.frame_errors = n.frame_errors + 1;
}

// One SPI transaction: the next registers from the current ones and the
// frame, then the commit (`regs` is the register bank) and the outputs.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  const Registers r = regs;
  Registers n = r;
  Outputs o;  // MISO and strobes: 0 unless the frame drives them
  if (in.reset == 1) {
    n = Registers();
  } else {
    const Frame f = receive(r, in);
    respond(r, in, f, o);
    commit(n, r, in, f, o);
  }
  regs = n;
  o.frame_status = n.status;
  o.spi_status = n.spi_status;
  o.frame_errors = n.frame_errors;
config_loop:
  for (int k = 0; k < kStoredWords; ++k) {
#pragma HLS unroll
    o.config[k] = n.stored.word[k];
  }
  out = o;
}

#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

}  // namespace regfile
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/regfile_top.cpp): one call = one SPI transaction,
// the registers held in the function's static state.
void odoloc_regfile(const odoloc::hls::regfile::Inputs& in, odoloc::hls::regfile::Outputs& out);
