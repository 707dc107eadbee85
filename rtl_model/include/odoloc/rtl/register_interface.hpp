// The register interface: the SPI slave and the register file on one clock,
// SPI pins and the fabric's status in, MISO, the configuration ports and the
// one-clock pulses out (docs/spi.md). The wiring between the two:
// logic/register_interface.hpp (the one source, also the HLS kernel's).
// Here: the composite the chip composes, with what only a simulator needs
// (activity gating, the quiet path of a bus at rest, the fast-forward
// horizon, the waveform).
#pragma once

#include <cstdint>

#include "odoloc/logic/register_interface.hpp"
#include "odoloc/ports.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/fabric_registers.hpp"
#include "odoloc/rtl/family.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace odoloc::rtl {

// Status: where the register file's status words come from (fabric_registers.hpp).
template <class Status = EncodedStatus>
class RegisterInterface {
  using Logic = logic::register_interface::RegisterInterface<Family>;

 public:
  using In = logic::register_interface::Pins<Family>;
  using Registers = FabricRegisters<Status>;

  // The wires into both children, from the current registers only.
  struct Wires {
    SpiSlave::In spi;
    typename Registers::In registers;
  };
  [[nodiscard]] Wires wires(const In& pins, const Status& status) const {
    const SpiRegisterPort port = spi_.port();
    const UInt<32> data = Logic::read_data(registers_.regs(), port, status);
    return {.spi = Logic::slave_in(registers_.regs(), pins, data,
                                   Logic::RegisterFile::write_refused(port)),
            .registers = Logic::registers_in(port, pins, data, status)};
  }

  // The register file reads the fabric's status only in a clock with a
  // snapshot or a read strobe; `status` is not read in any other.
  [[nodiscard]] bool samples_status() const {
    return !(spi_.engine().snapshot | spi_.engine().read_strobe).is_zero();
  }
  // No strobe from the slave, no pulse pending and no reset: the register
  // file is idle and drives nothing, and only the slave's pins matter.
  [[nodiscard]] bool quiet(UInt<1> reset) const { return registers_.quiet(spi_.strobing(), reset); }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& pins, const Status& status, const Order& order = {}) {
    if (G == Gating::kOn && quiet(pins.reset)) {
      step_quiet<G>(pins, order);
      return;
    }
    step_all<G>(pins, status, order);
  }
  // One clock with quiet(pins.reset): the slave alone (nothing at all when
  // it is settled on these pins, the common case: checked before its inputs
  // are built).
  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step_quiet(const In& pins, const Order& order = {}) {
    if (G == Gating::kOn && spi_.settled_on(pins.sclk, pins.cs_n, pins.mosi, pins.reset))
      return;
    spi_.step<G>(quiet_spi_in(pins), order);
  }
  [[nodiscard]] bool idle(const In& pins, const Status& status) const {
    const Wires w = wires(pins, status);
    return spi_.idle(w.spi) && registers_.idle(w.registers);
  }
  // Fast-forward (clocked.hpp): nothing happens on its own while quiet and
  // the slave is idle on held pins; else step this clock.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& pins) const {
    return quiet(pins.reset) && spi_.idle(quiet_spi_in(pins)) ? kNoEvent : 0;
  }
  void reset_now() {
    spi_.reset_now();
    registers_.reset_now();
  }

  [[nodiscard]] UInt<1> miso() const { return spi_.miso(); }
  // The snapshot strobe (the capture unit freezes its FIFO levels with it).
  [[nodiscard]] UInt<1> snapshot() const { return spi_.engine().snapshot; }
  [[nodiscard]] const ports::Config& config() const { return registers_.config(); }
  [[nodiscard]] const ports::Pulses& pulses() const { return registers_.pulses(); }
  [[nodiscard]] const SpiSlave& spi() const { return spi_; }
  [[nodiscard]] const Registers& registers() const { return registers_; }

  template <class V>
  void trace(V& v) const {
    trace_scope(v, "spi", spi_);
    trace_scope(v, "registers", registers_);
  }

 private:
  [[nodiscard]] SpiSlave::In quiet_spi_in(const In& pins) const {
    return Logic::slave_in(registers_.regs(), pins, UInt<32>{}, UInt<1>{});
  }
  // A clock with a strobe or pulse: out of line, so the quiet clocks do not
  // pay for its large frame.
  template <Gating G, class Order>
  [[gnu::noinline]] void step_all(const In& pins, const Status& status, const Order& order) {
    const Wires w = wires(pins, status);
    order([&] { spi_.step<G>(w.spi, order); }, [&] { clock_block<G>(registers_, w.registers); });
  }

  SpiSlave spi_;
  Registers registers_;
};

}  // namespace odoloc::rtl
