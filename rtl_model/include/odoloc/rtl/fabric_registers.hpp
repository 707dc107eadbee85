// The register file of the fabric: regmap/odoloc.yaml made logic. The logic
// (banks, access kinds, timing): logic/register_file.hpp (the one source,
// also the HLS kernel's). Here: what only a simulator needs around it (field
// lists, the quiet condition, and the fabric's side of the map decoded into
// the typed ports of the generated odoloc/ports.hpp: ports::Config from the
// stored words, ports::Pulses from the pulse words and pops, ports::Status
// encoded into words when the logic reads them).
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
#pragma once

#include <cstddef>
#include <cstdint>

#include "odoloc/logic/register_file.hpp"
#include "odoloc/ports.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/family.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace odoloc::rtl {

namespace regfile = logic::regfile;

ODOLOC_LOGIC_FIELDS_OF((int W), (regfile::Cell<Family, W>), value)
ODOLOC_LOGIC_FIELDS(regfile::StoredWords, word)
ODOLOC_LOGIC_FIELDS(regfile::Regs, stored, snapshot, spi_status, frame_errors,
                    frame_errors_returned, pop_words, pulse, pops, pulsing)

using FabricRegistersRegs = regfile::Regs<Family>;

// The fabric's status as the register file reads it: the typed ports,
// encoded into a register's word when the logic asks for it (a snapshot or
// a read), through the generated encoder.
struct EncodedStatus {
  ports::Status status;
  [[nodiscard]] UInt<32> word(int reg) const {
    return UInt<32>{ports::encode_status(
        static_cast<std::uint16_t>(regfile::map::kRegisters[reg].address), status)};
  }
};

// Status: where the status words come from (EncodedStatus in the chip;
// logic::regfile::StatusWords for the kernel's ports, in the verification).
template <class Status = EncodedStatus>
class FabricRegisters : public Registers<FabricRegistersRegs> {
  using Logic = regfile::RegisterFile<Family>;

 public:
  using In = regfile::In<Family, Status>;

  FabricRegisters() { decode(); }

  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  // The clock edge, and the decoded ports of the new registers.
  void commit(const Regs& next) {
    const bool stored_changed = !(next.stored == r_.stored);
    const bool pulsed = !(next.pulsing | r_.pulsing).is_zero();
    r_ = next;
    if (stored_changed)
      decode_config();
    if (pulsed)
      decode_pulses();
  }
  void reset_now() {
    Registers::reset_now();
    decode();
  }

  // Cheap: no strobe from the slave, no reset, none of this block's own
  // one-clock outputs pending.
  [[nodiscard]] bool quiet(bool spi_strobing, UInt<1> reset) const {
    return !spi_strobing && (reset | r_.pulsing).is_zero();
  }
  [[nodiscard]] bool idle(const In& in) const {
    return quiet(
        !(in.spi.snapshot | in.spi.read_strobe | in.spi.commit | in.spi.frame_end).is_zero(),
        in.reset);
  }

  // What a read frame returns for `address`, given the fabric's status.
  [[nodiscard]] UInt<32> read(UInt<10> address, const Status& status) const {
    return Logic::read(r_, address, status);
  }
  // The stored word of the rw register at `address` (0 for any other).
  [[nodiscard]] UInt<32> stored_word(unsigned address) const {
    const int reg = regfile::kLayout.register_at[address % regfile::map::kAddressSpace];
    const int slot = reg < 0 ? -1 : regfile::kLayout.slot[regfile::kStored][reg];
    return slot < 0 ? UInt<32>{} : r_.stored.word[slot].value;
  }

  // The configuration ports: the stored words, decoded (generated decoder).
  [[nodiscard]] const ports::Config& config() const { return config_; }
  // The one-clock strobes to the fabric: the pulse words and pops, decoded.
  [[nodiscard]] const ports::Pulses& pulses() const { return pulses_; }

 private:
  void decode() {
    decode_config();
    decode_pulses();
  }
  void decode_config() {
    config_ = {};
    for (int s = 0; s < regfile::kStoredWords; ++s)
      ports::decode_config(address_of(regfile::kStored, s),
                           static_cast<std::uint32_t>(r_.stored.word[s].value.value()), config_);
  }
  void decode_pulses() {
    pulses_ = {};
    if (r_.pulsing.is_zero())
      return;
    for (int s = 0; s < regfile::kPulseWords; ++s)
      if (!r_.pulse[s].value.is_zero())
        ports::decode_pulses(address_of(regfile::kPulse, s),
                             static_cast<std::uint32_t>(r_.pulse[s].value.value()), pulses_);
    for (int w = 0; w < regfile::kPopWindows; ++w)
      if (!r_.pops[w].value.is_zero())
        ports::decode_pops(static_cast<std::uint16_t>(regfile::map::kPopWindows[w].first),
                           static_cast<unsigned>(r_.pops[w].value.value()), pulses_);
  }
  static std::uint16_t address_of(regfile::Bank bank, int slot) {
    return static_cast<std::uint16_t>(
        regfile::map::kRegisters[regfile::kLayout.member[bank][slot]].address);
  }

  // Pure functions of the registers, kept decoded for simulation speed.
  ports::Config config_;
  ports::Pulses pulses_;
};

}  // namespace odoloc::rtl
