// The whole FPGA: the odometry fabric, the ultrasonic time-of-flight capture
// unit, the register file and the SPI slave on one 50 MHz clock. Pins in,
// MISO out; the only door is SPI (docs/spi.md).
#pragma once

#include <array>

#include "odoloc/rtl/fabric_registers.hpp"
#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/rtl/spi_slave.hpp"
#include "odoloc/rtl/tof_capture.hpp"

namespace odoloc::rtl {

using ChipTofCapture = TofCapture<>;  // every channel of the register map, 16-entry FIFOs
static_assert(ChipTofCapture::kDepth == regs::tof::info::fifo_depth.reset &&
                  ChipTofCapture::kChannels == regs::tof::info::channels.reset,
              "tof.info's reset documents the chip's build");

struct ChipPins {
  std::array<UInt<2>, kEncoderCount> encoders{};  // A/B per encoder, A in bit 1
  UInt<ChipTofCapture::kChannels> comparators;    // ultrasonic receivers, rx i in bit i
  UInt<1> tof_sync;                               // TOF sync input (RF trigger)
  UInt<1> sclk;
  UInt<1> cs_n{1};
  UInt<1> mosi;
  UInt<1> reset;
  ODOLOC_FIELDS(encoders, comparators, tof_sync, sclk, cs_n, mosi, reset)
};

class OdolocChip {
 public:
  using In = ChipPins;
  OdolocChip() { reset_now(); }

  // The wires into every child, from the current registers only.
  struct Wires {
    OdometryFabric::In fabric;
    ChipTofCapture::In tof;
    SpiSlave::In spi;
    FabricRegisters::In registers;
  };
  [[nodiscard]] Wires wires(const In& pins) const {
    const SpiRegisterPort port = spi_.port();
    // The fabric's status is needed only by a snapshot or a read.
    ports::Status status;
    if (port.snapshot | port.read_strobe) {
      status = fabric_.status(config_);
      tof_.status(status);
    }
    const UInt<32> read_data =
        port.read_strobe ? registers_.read(port.read_address, status) : UInt<32>{};
    const ports::Pulses& pulses = registers_.regs().pulses;
    return {
        .fabric = {.pins = pins.encoders,
                   .eppm = pulses.eppm,
                   .odometry = pulses.odometry,
                   .reset = pins.reset},
        .tof = {.comparators = pins.comparators,
                .sync = pins.tof_sync,
                .tof = pulses.tof,
                .channel = pulses.tof_channel,
                .snapshot = port.snapshot,
                .clear_all = pulses.odometry.command.clear_flags,
                .reset = pins.reset},
        .spi = {.sclk = pins.sclk,
                .cs_n = pins.cs_n,
                .mosi = pins.mosi,
                .crc_enable = config_.top.ctrl.crc_enable,
                .spi_mode3 = config_.top.ctrl.spi_mode3,
                .read_data = read_data,
                .write_refused = FabricRegisters::write_refused(port),
                .reset = pins.reset},
        .registers = {.spi = port, .read_data = read_data, .status = status, .reset = pins.reset},
    };
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& pins, const Order& order = {}) {
    record_pins(pins);
    // No SPI strobe and no pulse pending (the common case): the register
    // file is idle, the fabric's strobes are all 0 and the slave reads nothing.
    if (G == Gating::kOn && registers_.quiet(spi_.strobing(), pins.reset)) {
      set_sensor_pins(idle_fabric_in_, idle_tof_in_, pins);
      const SpiSlave::In spi_in = quiet_spi_in(pins);
      order([&] { fabric_.step<G>(idle_fabric_in_, config_, order); },
            [&] { tof_.step_pins<G>(idle_tof_in_, config_, order); },
            [&] { spi_.step<G>(spi_in, order); });
      return;
    }
    step_all<G>(pins, order);
  }

  // Fast-forward (clocked.hpp): how many of the next clocks, with `pins`
  // held, can be skipped: 0 while the SPI slave or the register file has
  // anything to do (a strobe, a frame, a reset), else until the odometry
  // period ends. In between, the capture unit and the fabric's EPPMs share
  // no signal with anything, so each advances on its own through its events.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& pins) const {
    if (!bus_quiet(pins) || !spi_.idle(quiet_spi_in(pins)))
      return 0;
    return sensor_clocks_until_event();
  }
  void skip(std::uint64_t n, const In& pins) {
    skip(n, pins, [&pins](std::size_t w, std::uint64_t clocks) {
      return PinRun{pins.encoders[w], clocks};
    });
  }
  // skip() with each encoder's pins following its own runs (runs(w, max):
  // encoder w's next PinRun, EncoderFabric::advance) and the other pins
  // held, n <= clocks_until_event(pins), which reads no encoder pin. The
  // fast path for moving wheels: a pin change costs its EPPM's events only.
  // It moves the sensor side only (the bus side is idle), so behind a frame
  // (step_bus) n <= sensor_clocks_until_event() suffices.
  template <class Runs>
  void skip(std::uint64_t n, const In& pins, Runs&& runs) {
    record_sensor_pins(pins);
    set_sensor_pins(idle_fabric_in_, idle_tof_in_, pins);
    const auto last = fabric_.skip(n, idle_fabric_in_, config_, runs);
    tof_.advance(n, idle_tof_in_, config_);
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      spi_pins_.encoders[w] = last[w];
  }
  // n clocks with `pins` held, bit-identical to n calls of step(pins);
  // returns how many were not stepped as a whole chip (inside them the EPPMs
  // and the capture unit still step through their own events).
  std::uint64_t advance(std::uint64_t n, const In& pins) { return fast_forward(*this, n, pins); }
  [[nodiscard]] bool idle(const In& pins) const {
    const Wires w = wires(pins);
    return fabric_.idle(w.fabric, config_) && tof_.idle(w.tof, config_) && spi_.idle(w.spi) &&
           registers_.idle(w.registers);
  }

  // ---- the sensor side behind the bus side (fast-forward inside frames) ----
  // While the register file is quiet (bus_quiet: no slave strobe, no pulse
  // pending, no reset), the fabric and the capture unit share no signal with
  // the SPI slave. The clocks of a frame can then clock the slave alone
  // (step_bus) and bring the sensor side up by as many clocks later
  // (advance_sensors, or skip with runs), before the first clock that is not
  // quiet: bit-identical to stepping, because the bus side reads the sensor
  // side (the snapshot, a read) and writes it (pulses, configuration) only in
  // such a clock.
  [[nodiscard]] bool bus_quiet(const In& pins) const {
    return registers_.quiet(spi_.strobing(), pins.reset);
  }
  // One clock of the SPI slave alone, bus_quiet(pins); the sensor side is
  // then one more clock behind.
  void step_bus(const In& pins) {
    record_spi_pins(pins);
    spi_.step(quiet_spi_in(pins));
  }
  // How many of the next clocks the sensor side can skip (reads no pin).
  [[nodiscard]] std::uint64_t sensor_clocks_until_event() const {
    return fabric_.clocks_until_event(idle_fabric_in_, config_);
  }
  // n clocks of the sensor side alone with `pins` held, bit-identical to
  // n quiet steps of it; returns how many were skipped.
  std::uint64_t advance_sensors(std::uint64_t n, const In& pins) {
    SensorSide sensors{*this};
    return fast_forward(sensors, n, pins);
  }

  void reset_now() {
    fabric_.reset_now();
    tof_.reset_now();
    spi_.reset_now();
    registers_.reset_now();
    config_ = registers_.config();
  }

  [[nodiscard]] UInt<1> miso() const { return spi_.miso(); }
  // The pins of the last clock.
  [[nodiscard]] const ChipPins& pins() const { return spi_pins_; }
  [[nodiscard]] const OdometryFabric& fabric() const { return fabric_; }
  [[nodiscard]] const ChipTofCapture& tof() const { return tof_; }
  [[nodiscard]] const SpiSlave& spi() const { return spi_; }
  [[nodiscard]] const FabricRegisters& registers() const { return registers_; }
  // The configuration ports: registers().config(), kept decoded.
  [[nodiscard]] const ports::Config& config() const { return config_; }

  template <class V>
  void trace(V& v) const {
    trace_fields(v, spi_pins_);
    v.signal("miso", miso());
    trace_scope(v, "spi", spi_);
    trace_scope(v, "registers", registers_);
    trace_scope(v, "fabric", fabric_);
    trace_scope(v, "tof", tof_);
  }

 private:
  // The slave's inputs on a clock without a read or a refused write.
  [[nodiscard]] SpiSlave::In quiet_spi_in(const In& pins) const {
    return {.sclk = pins.sclk,
            .cs_n = pins.cs_n,
            .mosi = pins.mosi,
            .crc_enable = config_.top.ctrl.crc_enable,
            .spi_mode3 = config_.top.ctrl.spi_mode3,
            .read_data = UInt<32>{},
            .write_refused = UInt<1>{},
            .reset = pins.reset};
  }
  // The fabric's and capture unit's inputs on a clock without strobes.
  static void set_sensor_pins(OdometryFabric::In& fabric, ChipTofCapture::In& tof, const In& pins) {
    for (std::size_t w = 0; w < kEncoderCount; ++w)  // per pin: see record_pins
      fabric.pins[w] = pins.encoders[w];
    tof.comparators = pins.comparators;
    tof.sync = pins.tof_sync;
  }
  // Field by field: testbenches set the pins one field at a time just before
  // the clock, and one wide copy of them would stall on store forwarding.
  void record_pins(const ChipPins& pins) {
    record_sensor_pins(pins);
    record_spi_pins(pins);
  }
  void record_sensor_pins(const ChipPins& pins) {
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      spi_pins_.encoders[w] = pins.encoders[w];
    spi_pins_.comparators = pins.comparators;
    spi_pins_.tof_sync = pins.tof_sync;
  }
  void record_spi_pins(const ChipPins& pins) {
    spi_pins_.sclk = pins.sclk;
    spi_pins_.cs_n = pins.cs_n;
    spi_pins_.mosi = pins.mosi;
    spi_pins_.reset = pins.reset;
  }

  // The fabric and the capture unit on quiet clocks, as a block of their
  // own for fast_forward (advance_sensors).
  struct SensorSide {
    using In = ChipPins;
    OdolocChip& chip;
    [[nodiscard]] std::uint64_t clocks_until_event(const In& /*pins*/) const {
      return chip.sensor_clocks_until_event();
    }
    void step(const In& pins) {
      chip.record_sensor_pins(pins);
      set_sensor_pins(chip.idle_fabric_in_, chip.idle_tof_in_, pins);
      chip.fabric_.step(chip.idle_fabric_in_, chip.config_);
      chip.tof_.step_pins(chip.idle_tof_in_, chip.config_);
    }
    void skip(std::uint64_t n, const In& pins) { chip.skip(n, pins); }
  };

  // A clock with a strobe or pulse: out of line, so the quiet clocks do not
  // pay for its large frame (the wires carry the whole status).
  template <Gating G, class Order>
  [[gnu::noinline]] void step_all(const In& pins, const Order& order) {
    const Wires w = wires(pins);
    const bool writes = (w.registers.spi.commit & w.registers.spi.commit_write) == UInt<1>{1};
    order([&] { fabric_.step<G>(w.fabric, config_, order); },
          [&] { tof_.step<G>(w.tof, config_, order); }, [&] { spi_.step<G>(w.spi, order); },
          [&] { clock_block<G>(registers_, w.registers); });
    if (writes || pins.reset)  // the configuration ports decode the stored words
      config_ = registers_.config();
  }

  OdometryFabric fabric_;
  ChipTofCapture tof_;
  SpiSlave spi_;
  FabricRegisters registers_;
  // registers_.config(), refreshed whenever a write or reset changes the
  // stored words: a pure function of registers_' registers, kept decoded for
  // simulation speed.
  ports::Config config_;
  OdometryFabric::In idle_fabric_in_;  // the fabric's inputs when no strobe is pending
  ChipTofCapture::In idle_tof_in_;     // the capture unit's inputs when no strobe is pending
  ChipPins spi_pins_;                  // the pins of the last clock, for waveforms
};

}  // namespace odoloc::rtl
