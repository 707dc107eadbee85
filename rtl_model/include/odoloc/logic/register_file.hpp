// The register file's logic, written once (docs/spi.md, docs/register-map.md;
// docs/hls.md, "One source per block"): regmap/odoloc.yaml made logic, one
// fabric clock at a time, behind the SPI slave (logic/spi_slave.hpp). The
// cycle model (rtl/fabric_registers.hpp) runs it with the model's types, the
// register interface's HLS kernel (hls/regfile_kernel.hpp) with the vendor's.
//
// Every address, mask and reset comes from the generated
// odoloc/logic/regfile_map.hpp; the tables below are derived from it at
// compile time. The fabric's side travels as register words in four banks:
//   stored    the rw bits of every rw register (the configuration; the
//             model decodes them into ports::Config, the kernel outputs them)
//   snapshot  the hardware-driven words of the `snapshot` registers, captured
//             in the clock the frame's cs_n fall is seen, so one burst reads
//             one instant and never tears
//   status    the words of every register the hardware drives (live status),
//             other than this block's own top.spi_status and top.frame_errors:
//             an input, read through a status source (Status::word(register
//             index), only the hw_mask bits count)
//   pulse     per register with w1c or w1p bits, the bits a write set: one
//             clock, to the blocks (w1c clears, w1p commands); per rpop
//             window, `pops`: the whole entries a completed read frame read in
//             order from its first word (the FIFO pops them the next clock)
//
// Access kinds: rw stored; ro from the status (snapshot registers from the
// snapshot bank; constants read their reset); w1c and w1p pulse for one
// clock (an event in the same clock wins in the block, so nothing is lost);
// rc: frame_errors, a completed read frame subtracts the value it returned,
// so errors counted while the frame ran are kept; rpop: see pulse. A write
// word to an ro or unmapped address is dropped and flags write_refused; the
// other words of its burst are written. top.spi_status: written clears act
// at once, then odometry.command.clear_flags, then the frame's flags are
// added; top.frame_errors counts the frames with any flag, saturating.
//
// Timing: the SPI slave's strobes are registers; this block decodes them in
// the clock they are high, and its one-clock outputs (pulse, pops) reach the
// fabric in the clock after. The slave latches read() in the clock after its
// read_strobe; write_refused() goes back to it in the commit clock.
// C++14, no heap, no containers, static loop bounds (int_family.hpp).
#pragma once

#include <cstdint>

#include "odoloc/logic/int_family.hpp"
#include "odoloc/logic/regfile_map.hpp"
#include "odoloc/logic/spi_slave.hpp"

namespace odoloc {
namespace logic {
namespace regfile {

namespace map = regfile_map;
using spi::Address;
using spi::BufferWord;
using spi::Flags;
using spi::kMaxBurst;
using spi::Word;

// ---- the tables, from the map at compile time -------------------------------------
enum Bank { kStored, kSnapshot, kStatus, kPulse, kBanks };

constexpr bool is_own(const map::Register& r) {
  return r.address == map::top::spi_status::kAddress ||
         r.address == map::top::frame_errors::kAddress;
}
constexpr bool in_bank(int bank, const map::Register& r) {
  return bank == kStored     ? r.rw_mask != 0
         : bank == kSnapshot ? r.snapshot
         : bank == kStatus   ? r.hw_mask != 0 && !is_own(r)
                             : (r.w1c_mask | r.w1p_mask) != 0;
}
constexpr int bank_size(int bank) {
  int n = 0;
  for (int i = 0; i < map::kRegisterCount; ++i)
    n += in_bank(bank, map::kRegisters[i]) ? 1 : 0;
  return n;
}
constexpr int kStoredWords = bank_size(kStored);
constexpr int kSnapshotWords = bank_size(kSnapshot);
constexpr int kStatusWords = bank_size(kStatus);
constexpr int kPulseWords = bank_size(kPulse);
constexpr int kPopWindows = map::kPopWindowCount;
static_assert(kStoredWords > 0 && kSnapshotWords > 0 && kStatusWords > 0 && kPulseWords > 0 &&
                  kPopWindows > 0,
              "the map has configuration, snapshots, status, strobes and FIFOs");

constexpr int bits_of(int value) {
  int bits = 0;
  for (int b = 0; b < 31; ++b)
    bits = (value >> b) != 0 ? b + 1 : bits;
  return bits;
}
constexpr int largest_window(bool words) {
  int most = 0;
  for (int w = 0; w < kPopWindows; ++w) {
    const map::PopWindow& window = map::kPopWindows[w];
    const int n = words ? window.entries * window.words : window.entries;
    most = n > most ? n : most;
  }
  return most;
}
constexpr int kPopBits = bits_of(largest_window(false));  // entries popped at once
constexpr int kPopWordBits = 7;                           // words read in order, per window
static_assert(largest_window(true) < (1 << kPopWordBits), "the word count holds a window");
constexpr int kErrorBits = map::top::frame_errors::count.width;
static_assert(map::top::frame_errors::count.lsb == 0, "frame_errors' count is its word's low bits");

struct Layout {
  short register_at[map::kAddressSpace];          // address -> register index, -1: unmapped
  signed char pop_window_at[map::kAddressSpace];  // address -> rpop window, -1: none
  short slot[kBanks][map::kRegisterCount];        // register -> its word in a bank, -1: none
  short member[kBanks][map::kRegisterCount];      // a bank's word -> its register
  std::uint32_t stored_reset[kStoredWords];       // reset & rw_mask
};
constexpr Layout make_layout() {
  Layout t = {};
  for (int a = 0; a < map::kAddressSpace; ++a) {
    t.register_at[a] = -1;
    t.pop_window_at[a] = -1;
  }
  int next[kBanks] = {0, 0, 0, 0};
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
  for (int w = 0; w < kPopWindows; ++w) {
    const map::PopWindow& window = map::kPopWindows[w];
    for (int k = 0; k < window.entries * window.words; ++k)
      t.pop_window_at[window.first + k] = static_cast<signed char>(w);
  }
  return t;
}
constexpr Layout kLayout = make_layout();

// The registers the block treats by name.
constexpr int kSpiStatus = kLayout.register_at[map::top::spi_status::kAddress];
constexpr int kFrameErrors = kLayout.register_at[map::top::frame_errors::kAddress];
constexpr int kCtrl = kLayout.register_at[map::top::ctrl::kAddress];
constexpr int kCtrlWord = kLayout.slot[kStored][kCtrl];
constexpr int kSpiStatusPulse = kLayout.slot[kPulse][kSpiStatus];
constexpr int kCommandPulse =
    kLayout.slot[kPulse][kLayout.register_at[map::odometry::command::kAddress]];
static_assert(kCtrlWord >= 0 && kSpiStatusPulse >= 0 && kCommandPulse >= 0,
              "top.ctrl is rw, top.spi_status w1c, odometry.command w1p");
static_assert(map::top::spi_status::crc_error.mask() == spi::kCrcError &&
                  map::top::spi_status::overrun.mask() == spi::kOverrun,
              "top.spi_status's fields are the slave's flags");

// ---- registers ----------------------------------------------------------------------
template <class F, int W>
struct Cell {
  uint<F, W> value{0};
};
// The stored words start at the map's reset values.
template <class F>
struct StoredWords {
  BufferWord<F> word[kStoredWords];
};
template <class F>
inline StoredWords<F> stored_resets() {
  StoredWords<F> s;
  for (int i = 0; i < kStoredWords; ++i)
    s.word[i].value = wrap<Word<F> >(kLayout.stored_reset[i]);
  return s;
}

template <class F>
struct Regs {
  StoredWords<F> stored = stored_resets<F>();  // rw bits
  BufferWord<F> snapshot[kSnapshotWords];
  Flags<F> spi_status{0};                        // sticky top.spi_status
  uint<F, kErrorBits> frame_errors{0};           // top.frame_errors, saturating
  uint<F, kErrorBits> frame_errors_returned{0};  // what this frame's read of frame_errors returned
  Cell<F, kPopWordBits> pop_words[kPopWindows];  // per rpop window: words read in order
  BufferWord<F> pulse[kPulseWords];              // one clock: the w1c and w1p bits written
  Cell<F, kPopBits> pops[kPopWindows];           // one clock: entries to pop
  uint<F, 1> pulsing{0};  // any of pulse and pops is not 0 (registered with them)
};

// The slave's wires to the register side (logic/spi_slave.hpp); words[0..
// commit_count-1] are valid while commit is high.
template <class F>
struct Port {
  uint<F, 1> snapshot{0}, read_strobe{0};
  Address<F> read_address{0};
  uint<F, 1> commit{0}, commit_write{0}, frame_end{0};
  Address<F> commit_address{0};
  uint<F, spi::kBurstCountBits> commit_count{0};
  Flags<F> status{0};
  BufferWord<F> words[kMaxBurst];
};
template <class F>
inline Port<F> port(const spi::EngineRegs<F>& e, const spi::WriteBufferRegs<F>& buffer) {
  Port<F> p;
  p.snapshot = e.snapshot;
  p.read_strobe = e.read_strobe;
  p.read_address = e.read_address;
  p.commit = e.commit;
  p.commit_write = e.commit_write;
  p.frame_end = e.frame_end;
  p.commit_address = e.commit_address;
  p.commit_count = e.commit_count;
  p.status = e.status;
  for (int k = 0; k < kMaxBurst; ++k)
    p.words[k] = buffer.words[k];
  return p;
}

// Status: the fabric's live status, `Word<F> word(int register_index) const`
// for every register of the status bank (hw_mask bits; others ignored).
template <class F, class Status>
struct In {
  Port<F> spi;
  Word<F> read_data{0};  // read(spi.read_address) while spi.read_strobe is high
  Status status;
  uint<F, 1> reset{0};
};

// The status bank as words, a Status for the HLS kernel's ports.
template <class F>
struct StatusWords {
  BufferWord<F> bank[kStatusWords];  // in address order
  Word<F> word(int reg) const { return bank[kLayout.slot[kStatus][reg]].value; }
};

template <class F>
struct RegisterFile {
  using R = Regs<F>;

  template <class Status>
  static R next(const R& r, const In<F, Status>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    for (int k = 0; k < kPulseWords; ++k)
      n.pulse[k].value = Word<F>(0);
    for (int w = 0; w < kPopWindows; ++w)
      n.pops[w].value = uint<F, kPopBits>(0);
    const Port<F>& spi = in.spi;
    if (!is_zero(spi.snapshot)) {
      for (int s = 0; s < kSnapshotWords; ++s)
        n.snapshot[s].value = hardware_word(in.status, kLayout.member[kSnapshot][s]);
      n.frame_errors_returned = uint<F, kErrorBits>(0);
      for (int w = 0; w < kPopWindows; ++w)
        n.pop_words[w].value = uint<F, kPopWordBits>(0);
    }
    if (!is_zero(spi.read_strobe)) {
      if (to_s64(spi.read_address) == map::top::frame_errors::kAddress)
        n.frame_errors_returned = bits<kErrorBits - 1, 0>(in.read_data);
      count_pop_word(n, spi.read_address);
    }
    bool refused = false;
    if (!is_zero(spi.commit) && !is_zero(spi.commit_write)) {
      for (int k = 0; k < kMaxBurst; ++k)
        if (k < to_s64(spi.commit_count) &&
            !write_word(n, word_address(spi.commit_address, k), spi.words[k].value))
          refused = true;
    } else if (!is_zero(spi.commit)) {
      n.frame_errors = wrap<uint<F, kErrorBits> >(n.frame_errors - r.frame_errors_returned);
      pop_read_entries(n);
    }
    // top.spi_status is this block's own: written clears act at once, before
    // the flags of the frame that wrote them are added.
    n.spi_status = wrap<Flags<F> >(n.spi_status &
                                   ~bits<spi::kFlagBits - 1, 0>(n.pulse[kSpiStatusPulse].value));
    if ((to_s64(n.pulse[kCommandPulse].value) & map::odometry::command::clear_flags.mask()) != 0)
      n.spi_status = Flags<F>(0);
    if (!is_zero(spi.frame_end)) {
      const Flags<F> errors =
          wrap<Flags<F> >(spi.status | Flags<F>(refused ? spi::kWriteRefused : 0U));
      n.spi_status = wrap<Flags<F> >(n.spi_status | errors);
      const long long most = (1LL << kErrorBits) - 1;
      if (!is_zero(errors) && to_s64(n.frame_errors) != most)
        n.frame_errors = wrap<uint<F, kErrorBits> >(n.frame_errors + uint<F, 1>(1));
    }
    n.pulsing = wrap<uint<F, 1> >(any_pulse(n) ? 1 : 0);
    return n;
  }

  // What a read frame returns for `address`: the snapshot, else the stored
  // bits, constants and hardware-driven bits; unmapped or reserved: 0.
  template <class Status>
  static Word<F> read(const R& r, const Address<F>& address, const Status& status) {
    const int reg = kLayout.register_at[to_s64(address)];
    if (reg < 0)
      return Word<F>(0);
    const int snapshot = kLayout.slot[kSnapshot][reg];
    if (snapshot >= 0)
      return r.snapshot[snapshot].value;
    const map::Register& d = map::kRegisters[reg];
    Word<F> hw = hardware_word(status, reg);
    if (reg == kSpiStatus)
      hw = wrap<Word<F> >(r.spi_status);
    if (reg == kFrameErrors)
      hw = wrap<Word<F> >(r.frame_errors);
    const int stored = kLayout.slot[kStored][reg];
    const Word<F> rw = stored >= 0 ? r.stored.word[stored].value : Word<F>(0);
    return wrap<Word<F> >((rw & wrap<Word<F> >(d.rw_mask)) |
                          wrap<Word<F> >(d.reset & d.const_mask) | hw);
  }

  // The write_refused wire of the commit clock.
  static uint<F, 1> write_refused(const Port<F>& spi) {
    bool refused = false;
    if (!is_zero(spi.commit) && !is_zero(spi.commit_write)) {
      for (int k = 0; k < kMaxBurst; ++k)
        if (k < to_s64(spi.commit_count) && !writable(word_address(spi.commit_address, k)))
          refused = true;
    }
    return wrap<uint<F, 1> >(refused ? 1 : 0);
  }

  // top.ctrl's bits, for the slave (latched by it at cs_n fall).
  static uint<F, 1> crc_enable(const R& r) {
    return wrap<uint<F, 1> >(to_s64(r.stored.word[kCtrlWord].value) >>
                             map::top::ctrl::crc_enable.lsb);
  }
  static uint<F, 1> spi_mode3(const R& r) {
    return wrap<uint<F, 1> >(to_s64(r.stored.word[kCtrlWord].value) >>
                             map::top::ctrl::spi_mode3.lsb);
  }

 private:
  template <class Status>
  static Word<F> hardware_word(const Status& status, int reg) {
    if (kLayout.slot[kStatus][reg] < 0)
      return Word<F>(0);
    return wrap<Word<F> >(status.word(reg) & wrap<Word<F> >(map::kRegisters[reg].hw_mask));
  }
  static int word_address(const Address<F>& start, int k) {
    return static_cast<int>((to_s64(start) + k) % map::kAddressSpace);
  }
  static bool writable(int address) {
    const int reg = kLayout.register_at[address];
    if (reg < 0)
      return false;
    const map::Register& d = map::kRegisters[reg];
    return (d.rw_mask | d.w1c_mask | d.w1p_mask) != 0;
  }
  static bool any_pulse(const R& n) {
    bool any = false;
    for (int k = 0; k < kPulseWords; ++k)
      any = any || !is_zero(n.pulse[k].value);
    for (int w = 0; w < kPopWindows; ++w)
      any = any || !is_zero(n.pops[w].value);
    return any;
  }

  // A read of the next word of an rpop window, in order from its first word.
  static void count_pop_word(R& n, const Address<F>& address) {
    const long long a = to_s64(address);
    const int w = kLayout.pop_window_at[a];
    if (w < 0)
      return;
    uint<F, kPopWordBits>& words = n.pop_words[w].value;
    if (a == map::kPopWindows[w].first + to_s64(words))
      words = wrap<uint<F, kPopWordBits> >(words + uint<F, 1>(1));
  }
  // A completed read frame: each window pops the whole entries it read.
  static void pop_read_entries(R& n) {
    for (int w = 0; w < kPopWindows; ++w) {
      const map::PopWindow& window = map::kPopWindows[w];
      const long long entries = to_s64(n.pop_words[w].value) / window.words;
      n.pops[w].value =
          wrap<uint<F, kPopBits> >(entries < window.entries ? entries : window.entries);
      n.pop_words[w].value = uint<F, kPopWordBits>(0);
    }
  }

  // Applies one written word; false when the address takes no write.
  static bool write_word(R& n, int address, const Word<F>& data) {
    const int reg = kLayout.register_at[address];
    if (reg < 0)
      return false;
    const map::Register& d = map::kRegisters[reg];
    if ((d.rw_mask | d.w1c_mask | d.w1p_mask) == 0)
      return false;
    const int stored = kLayout.slot[kStored][reg];
    if (stored >= 0) {
      Word<F>& s = n.stored.word[stored].value;
      s = wrap<Word<F> >((s & wrap<Word<F> >(~d.rw_mask)) | (data & wrap<Word<F> >(d.rw_mask)));
    }
    const int pulse = kLayout.slot[kPulse][reg];
    if (pulse >= 0)
      n.pulse[pulse].value = wrap<Word<F> >(data & wrap<Word<F> >(d.w1c_mask | d.w1p_mask));
    return true;
  }
};

}  // namespace regfile
}  // namespace logic
}  // namespace odoloc
