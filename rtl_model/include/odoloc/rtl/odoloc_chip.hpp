// The whole FPGA: the odometry fabric, its register file and the SPI slave on
// one 50 MHz clock. Pins in, MISO out; the only door is SPI (docs/spi.md).
#pragma once

#include <array>

#include "odoloc/rtl/fabric_registers.hpp"
#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/rtl/spi_slave.hpp"

namespace odoloc::rtl {

struct ChipPins {
  std::array<UInt<2>, kWheelCount> encoders{};  // A/B per encoder, A in bit 1
  UInt<1> sclk;
  UInt<1> cs_n{1};
  UInt<1> mosi;
  UInt<1> reset;
};

class OdolocChip {
 public:
  OdolocChip() { reset_now(); }

  template <Gating G = Gating::kOn>
  void step(const ChipPins& pins) {
    // Wires from the current registers.
    const SpiSlave::Regs& spi = spi_.regs();
    const UInt<32> read_data =
        spi.read_strobe ? registers_.read(spi.read_address, fabric_, config_) : UInt<32>{};
    const FabricRegisters::In registers_in{spi, read_data, fabric_, config_, pins.reset};
    const SpiSlave::In spi_in{pins.sclk,
                              pins.cs_n,
                              pins.mosi,
                              registers_.crc_enable(),
                              registers_.spi_mode3(),
                              read_data,
                              FabricRegisters::write_refused(spi),
                              pins.reset};
    fabric_in_.pins = pins.encoders;
    fabric_in_.reset = pins.reset;
    spi_pins_ = pins;

    if (G == Gating::kOn && registers_.idle(registers_in)) {  // no SPI traffic: the common case
      fabric_.step<G>(fabric_in_, config_);
      clock_block<G>(spi_, spi_in);
      return;
    }
    const bool writes = (spi.commit & spi.commit_write) == UInt<1>{1};
    const FabricRegisters::Regs registers_next = registers_.eval(registers_in);
    fabric_.step<G>(fabric_in_, config_);
    clock_block<G>(spi_, spi_in);
    registers_.commit(registers_next);
    registers_.drive(fabric_in_);
    if (writes || pins.reset)  // the configuration ports decode the stored words
      config_ = registers_.config();
  }

  void reset_now() {
    fabric_.reset_now();
    spi_.reset_now();
    registers_.reset_now();
    config_ = registers_.config();
    registers_.drive(fabric_in_);
  }

  [[nodiscard]] UInt<1> miso() const { return spi_.regs().miso; }
  [[nodiscard]] const OdometryFabric& fabric() const { return fabric_; }
  [[nodiscard]] const SpiSlave& spi() const { return spi_; }
  [[nodiscard]] const FabricRegisters& registers() const { return registers_; }
  [[nodiscard]] const OdometryFabricConfig& config() const { return config_; }

  template <class V>
  void trace(V& v) const {
    v.signal("sclk", spi_pins_.sclk);
    v.signal("cs_n", spi_pins_.cs_n);
    v.signal("mosi", spi_pins_.mosi);
    v.signal("miso", miso());
    trace_scope(v, "spi", spi_);
    trace_scope(v, "registers", registers_);
    trace_scope(v, "fabric", fabric_);
  }

 private:
  OdometryFabric fabric_;
  SpiSlave spi_;
  FabricRegisters registers_;
  // registers_.config() and the fabric inputs registers_ drives, refreshed
  // whenever registers_ changes: pure functions of its registers, kept
  // decoded for simulation speed.
  OdometryFabricConfig config_;
  OdometryFabric::Inputs fabric_in_;
  ChipPins spi_pins_;  // the pins of the last clock, for waveforms
};

}  // namespace odoloc::rtl
