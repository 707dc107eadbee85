// The register file of the fabric: regmap/odoloc.yaml made logic. Every
// address, mask and reset comes from the generated odoloc/regs.hpp; the
// mapping between register words and the fabric's ports (configuration,
// clear strobes and commands, status) is the generated odoloc/ports.hpp.
//
// Address map (32-bit words; docs/register-map.md lists every field):
//   0x000-0x004  top        id, ctrl, spi_status, frame_errors, scratch
//   0x010-0x04C  eppm[4]    stride 0x010: cfg..stall_ticks (rw), count..period_last
//                           (snapshot), status (w1c), error_count
//   0x060-0x086  odometry   cfg and scales (rw), status (w1c), updates, pose and the
//                           last update's increments (snapshot), set_* (rw), command (w1p)
//   0x100-0x10F  tof        cfg, info, command (w1p), timestamp, sync FIFO (rpop window)
//   0x110-0x1CF  tof_channel[8]  stride 0x018: cfg, listening window (rw), status,
//                           events (snapshot), event FIFO window entry0..7 (rpop)
//   0x1D0-0x1FF  reserved
//
// Access kinds:
//   rw   stored here; config() decodes the stored words into ports::Config.
//   ro   the fabric's ports::Status; `snapshot` registers come from the bank
//        captured in the clock the frame's cs_n fall is seen, so one burst
//        reads one instant and never tears. Constants read their reset.
//   w1c  a 1 pulses that flag's clear strobe for one clock (an event in the
//        same clock wins, so nothing is lost).
//   w1p  a 1 pulses the command for one clock; reads 0.
//   rc   frame_errors: a completed read frame subtracts the value it
//        returned, so errors counted while the frame ran are kept.
//   rpop a FIFO window (snapshot): a completed read frame pops the whole
//        entries it read in order from the window's first word
//        (ports::Pulses <array>.pops, the next clock); a frame with any error
//        pops nothing. The block bounds the pops by its level at the frame's
//        start, so an entry pushed while the frame ran is never popped unread.
// The top block (spi_status, frame_errors) is this block's own hardware.
// A write word to an ro or unmapped address is dropped and flags
// write_refused; the other words of its burst are written.
//
// Timing: the SPI slave's strobes are registers; this block decodes them in
// the clock they are high, and its own one-clock outputs (ports::Pulses)
// reach the fabric in the clock after. The slave latches read_data in the
// clock read_strobe is high; write_refused goes back to it in the commit clock.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "odoloc/ports.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace odoloc::rtl {

namespace regfile {

inline constexpr std::size_t kAddressSpace = std::size_t{1} << regs::kAddressBits;
static_assert(regs::kDataBits == 32);

constexpr bool is_stored(const regs::Register& r) {
  return r.rw_mask != 0;
}
constexpr bool is_snapshot(const regs::Register& r) {
  return r.snapshot;
}

template <auto Pred>
constexpr std::size_t slot_count() {
  std::size_t n = 0;
  for (const regs::Register& r : regs::kRegisters)
    n += Pred(r) ? 1 : 0;
  return n;
}

// Address -> slot of the registers Pred selects, -1 elsewhere.
template <auto Pred>
constexpr std::array<std::int16_t, kAddressSpace> slot_table() {
  std::array<std::int16_t, kAddressSpace> table{};
  table.fill(-1);
  std::int16_t next = 0;
  for (const regs::Register& r : regs::kRegisters)
    if (Pred(r))
      table[r.address] = next++;
  return table;
}

// Address -> rpop window holding it, -1 elsewhere.
constexpr std::array<std::int8_t, kAddressSpace> pop_window_table() {
  std::array<std::int8_t, kAddressSpace> table{};
  table.fill(-1);
  for (std::size_t w = 0; w < std::size(regs::kPopWindows); ++w) {
    const regs::PopWindow& window = regs::kPopWindows[w];
    for (unsigned k = 0; k < window.entries * window.words; ++k)
      table[window.first + k] = static_cast<std::int8_t>(w);
  }
  return table;
}

inline constexpr std::size_t kPopWindowCount = std::size(regs::kPopWindows);
inline constexpr auto kPopWindow = pop_window_table();
inline constexpr std::size_t kStoredWords = slot_count<is_stored>();
inline constexpr std::size_t kSnapshotWords = slot_count<is_snapshot>();
inline constexpr auto kStoredSlot = slot_table<is_stored>();
inline constexpr auto kSnapshotSlot = slot_table<is_snapshot>();

constexpr std::array<UInt<32>, kStoredWords> stored_resets() {
  std::array<UInt<32>, kStoredWords> words{};
  for (const regs::Register& r : regs::kRegisters)
    if (is_stored(r))
      words[static_cast<std::size_t>(kStoredSlot[r.address])] = UInt<32>{r.reset & r.rw_mask};
  return words;
}

// A field as a typed wire: its width is the type's, so a field that does not
// fit its port does not compile.
template <const regs::Field& F>
constexpr UInt<F.width> field(UInt<32> word) {
  return UInt<F.width>::truncate(F.get(static_cast<std::uint32_t>(word.value())));
}

}  // namespace regfile

struct FabricRegistersRegs {
  std::array<UInt<32>, regfile::kStoredWords> stored = regfile::stored_resets();  // rw bits
  std::array<UInt<32>, regfile::kSnapshotWords> snapshot{};
  UInt<4> spi_status;              // sticky top.spi_status
  UInt<16> frame_errors;           // top.frame_errors, saturating
  UInt<16> frame_errors_returned;  // what this frame's read of frame_errors returned
  // Per rpop window: words this frame has read in order from its first word.
  std::array<UInt<7>, regfile::kPopWindowCount> pop_words{};
  ports::Pulses pulses;  // one clock: w1c clears, w1p commands and rpop pops to the fabric
  UInt<1> pulsing;       // any of `pulses` is high (their OR, registered with them)
  bool operator==(const FabricRegistersRegs&) const = default;
  ODOLOC_FIELDS(stored, snapshot, spi_status, frame_errors, frame_errors_returned, pop_words,
                pulses, pulsing)
};

class FabricRegisters : public Registers<FabricRegistersRegs> {
 public:
  struct In {
    SpiRegisterPort spi;
    UInt<32> read_data;    // read(spi.read_address, status) while spi.read_strobe is high
    ports::Status status;  // the fabric's, while spi.snapshot is high
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    n.pulses = {};
    const SpiRegisterPort& spi = in.spi;
    if (spi.snapshot) {
      for (const regs::Register& r : regs::kRegisters)
        if (r.snapshot)
          n.snapshot[snapshot_slot(r.address)] =
              UInt<32>{ports::encode_status(r.address, in.status)};
      n.frame_errors_returned = UInt<16>{};
      n.pop_words = {};
    }
    if (spi.read_strobe && spi.read_address.value() == regs::top::frame_errors::kAddress)
      n.frame_errors_returned = regfile::field<regs::top::frame_errors::count>(in.read_data);
    if (spi.read_strobe)
      count_pop_word(n, spi.read_address);
    bool refused = false;
    if (spi.commit && spi.commit_write) {
      for (unsigned k = 0; k < spi.commit_count.value(); ++k)
        refused |= !write_word(n, word_address(spi.commit_address, k), spi.words[k]);
    } else if (spi.commit) {
      n.frame_errors =
          UInt<16>::truncate(n.frame_errors.value() - r_.frame_errors_returned.value());
      pop_read_entries(n);
    }
    // top.spi_status is this block's own: written clears act at once, before
    // the flags of the frame that wrote them are added.
    n.spi_status = n.spi_status & ~UInt<4>::truncate(ports::encode_status(
                                      regs::top::spi_status::kAddress, as_status(n.pulses.top)));
    if (n.pulses.odometry.command.clear_flags)
      n.spi_status = UInt<4>{};
    if (spi.frame_end) {
      const UInt<4> errors = spi.status | (refused ? kRefused : UInt<4>{});
      n.spi_status = n.spi_status | errors;
      if (!errors.is_zero())
        n.frame_errors = (n.frame_errors + UInt<1>{1}).sat<16>();
    }
    n.pulsing = UInt<1>::truncate(any_set(n.pulses));
    return n;
  }

  // Cheap: no strobe from the slave, no reset, none of this block's own
  // one-clock outputs pending.
  [[nodiscard]] bool quiet(bool spi_strobing, UInt<1> reset) const {
    return !spi_strobing && (reset | r_.pulsing).is_zero();
  }
  [[nodiscard]] bool idle(const In& in) const { return quiet(in.spi.active(), in.reset); }

  // The write_refused wire of the commit clock.
  [[nodiscard]] static UInt<1> write_refused(const SpiRegisterPort& spi) {
    bool refused = false;
    if (spi.commit && spi.commit_write)
      for (unsigned k = 0; k < spi.commit_count.value(); ++k)
        refused |= !writable(word_address(spi.commit_address, k));
    return UInt<1>::truncate(refused);
  }

  // What a read frame returns for `address`, given the fabric's status:
  // the snapshot, else the stored bits, constants and hardware-driven bits.
  [[nodiscard]] UInt<32> read(UInt<10> address, ports::Status status) const {
    const auto a = static_cast<std::size_t>(address.value());
    if (regfile::kSnapshotSlot[a] >= 0)
      return r_.snapshot[static_cast<std::size_t>(regfile::kSnapshotSlot[a])];
    const regs::Register* r = regs::find(static_cast<std::uint32_t>(a));
    if (r == nullptr)
      return UInt<32>{};  // unmapped or reserved: reads 0
    status.top = top_status();
    const std::uint32_t stored =
        regfile::kStoredSlot[a] >= 0 ? static_cast<std::uint32_t>(stored_word(a).value()) : 0;
    return UInt<32>{(stored & r->rw_mask) | (r->reset & r->const_mask) |
                    ports::encode_status(static_cast<std::uint16_t>(a), status)};
  }

  // The configuration ports: the stored words, decoded (generated decoder).
  [[nodiscard]] ports::Config config() const {
    ports::Config c;
    for (const regs::Register& r : regs::kRegisters)
      if (regfile::is_stored(r))
        ports::decode_config(r.address, static_cast<std::uint32_t>(stored_word(r.address).value()),
                             c);
    return c;
  }

 private:
  static constexpr UInt<4> kRefused{SpiSlave::kStatusWriteRefused};

  // This block's own top.* status fields.
  [[nodiscard]] ports::top::Status top_status() const {
    return as_status(r_.spi_status, r_.frame_errors);
  }
  // top.spi_status flags from their register bits (through the generated
  // pulse decoder, which places each field the way the map says).
  static ports::top::Status as_status(UInt<4> spi_status, UInt<16> frame_errors) {
    ports::Pulses p;
    ports::decode_pulses(regs::top::spi_status::kAddress,
                         static_cast<std::uint32_t>(spi_status.value()), p);
    ports::top::Status s = as_status(p.top).top;
    s.frame_errors.count = frame_errors;
    return s;
  }
  static ports::Status as_status(const ports::top::Pulses& clears) {
    ports::Status s;
    s.top.spi_status = {.crc_error = clears.spi_status.crc_error,
                        .bad_length = clears.spi_status.bad_length,
                        .write_refused = clears.spi_status.write_refused,
                        .overrun = clears.spi_status.overrun};
    return s;
  }

  static std::size_t word_address(UInt<10> start, unsigned k) {
    return static_cast<std::size_t>((start.value() + k) % regfile::kAddressSpace);
  }
  static std::size_t snapshot_slot(std::size_t address) {
    return static_cast<std::size_t>(regfile::kSnapshotSlot[address]);
  }
  static bool writable(std::size_t address) {
    const regs::Register* r = regs::find(static_cast<std::uint32_t>(address));
    return r != nullptr && (r->rw_mask | r->w1c_mask | r->w1p_mask) != 0;
  }
  [[nodiscard]] UInt<32> stored_word(std::size_t address) const {
    return r_.stored[static_cast<std::size_t>(regfile::kStoredSlot[address])];
  }

  // A read of the next word of an rpop window, in order from its first word.
  static void count_pop_word(Regs& n, UInt<10> address) {
    const auto a = static_cast<std::size_t>(address.value());
    const int w = regfile::kPopWindow[a];
    if (w < 0)
      return;
    UInt<7>& words = n.pop_words[static_cast<std::size_t>(w)];
    if (a == regs::kPopWindows[w].first + words.value())
      words = (words + UInt<1>{1}).wrap<7>();
  }
  // A completed read frame: each window pops the whole entries it read.
  static void pop_read_entries(Regs& n) {
    for (std::size_t w = 0; w < regfile::kPopWindowCount; ++w) {
      const regs::PopWindow& window = regs::kPopWindows[w];
      const unsigned entries = static_cast<unsigned>(n.pop_words[w].value()) / window.words;
      if (entries != 0)
        ports::decode_pops(window.first, entries, n.pulses);
      n.pop_words[w] = UInt<7>{};
    }
  }

  // Applies one written word; false when the address takes no write.
  static bool write_word(Regs& n, std::size_t address, UInt<32> word) {
    const regs::Register* r = regs::find(static_cast<std::uint32_t>(address));
    if (r == nullptr || (r->rw_mask | r->w1c_mask | r->w1p_mask) == 0)
      return false;
    const auto data = static_cast<std::uint32_t>(word.value());
    if (r->rw_mask != 0) {
      UInt<32>& s = n.stored[static_cast<std::size_t>(regfile::kStoredSlot[address])];
      s = UInt<32>{(static_cast<std::uint32_t>(s.value()) & ~r->rw_mask) | (data & r->rw_mask)};
    }
    ports::decode_pulses(r->address, data & (r->w1c_mask | r->w1p_mask), n.pulses);
    return true;
  }
};

}  // namespace odoloc::rtl
