// The whole FPGA: the odometry fabric, the ultrasonic time-of-flight capture
// unit and the register interface (the SPI slave and the register file) on
// one 50 MHz clock. Pins in, MISO out; the only door is SPI (docs/spi.md).
#pragma once

#include <array>

#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/rtl/register_interface.hpp"
#include "odoloc/rtl/tof_capture.hpp"

namespace odoloc::rtl {

using ChipTofCapture = TofCapture<>;  // every channel of the register map, 16-entry FIFOs
using ChipRegisterInterface = RegisterInterface<>;  // the fabric's status as typed ports
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
    ChipRegisterInterface::In interface;
    EncodedStatus status;  // the fabric's, for the register interface
  };
  [[nodiscard]] Wires wires(const In& pins) const {
    // The fabric's status is needed only by a snapshot or a read.
    EncodedStatus status;
    if (interface_.samples_status()) {
      status.status = fabric_.status(config());
      tof_.status(status.status);
    }
    const ports::Pulses& pulses = interface_.pulses();
    return {
        .fabric = {.pins = pins.encoders,
                   .eppm = pulses.eppm,
                   .odometry = pulses.odometry,
                   .reset = pins.reset},
        .tof = {.comparators = pins.comparators,
                .sync = pins.tof_sync,
                .tof = pulses.tof,
                .channel = pulses.tof_channel,
                .snapshot = interface_.snapshot(),
                .clear_all = pulses.odometry.command.clear_flags,
                .reset = pins.reset},
        .interface = interface_pins(pins),
        .status = status,
    };
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& pins, const Order& order = {}) {
    record_pins(pins);
    // No SPI strobe and no pulse pending (the common case): the register
    // file is idle, the fabric's strobes are all 0 and the slave reads nothing.
    if (G == Gating::kOn && interface_.quiet(pins.reset)) {
      set_sensor_pins(idle_fabric_in_, idle_tof_in_, pins);
      const ChipRegisterInterface::In bus = interface_pins(pins);
      order([&] { fabric_.step<G>(idle_fabric_in_, config(), order); },
            [&] { tof_.step_pins<G>(idle_tof_in_, config(), order); },
            [&] { interface_.step_quiet<G>(bus, order); });
      return;
    }
    step_all<G>(pins, order);
  }

  // Fast-forward (clocked.hpp): how many of the next clocks, with `pins`
  // held, can be skipped: the nearest of the register interface's horizon
  // (0 while the SPI slave or the register file has anything to do: a
  // strobe, a frame, a reset) and the sensor side's (the odometry period's
  // end). In between, the capture unit and the fabric's EPPMs share no
  // signal with anything, so each advances on its own through its events.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& pins) const {
    return nearest_event([&] { return interface_.clocks_until_event(interface_pins(pins)); },
                         [&] { return sensor_clocks_until_event(); });
  }
  void skip(std::uint64_t n, const In& pins) { skip(n, pins, held_runs(pins.encoders)); }
  // skip() with each encoder's pins following its own runs (runs(w, max):
  // encoder w's next PinRun, EncoderFabric::advance) and the other pins
  // held, n <= clocks_until_event(pins), which reads no encoder pin:
  // piecewise-constant pins, the one input form of a skip. A pin change
  // costs its EPPM's events only. It moves the sensor side only (the bus
  // side is idle), so behind a frame n <= sensors().clocks_until_event()
  // suffices.
  template <class Runs>
  void skip(std::uint64_t n, const In& pins, Runs&& runs) {
    record_sensor_pins(pins);
    set_sensor_pins(idle_fabric_in_, idle_tof_in_, pins);
    const auto last = fabric_.skip(n, idle_fabric_in_, config(), runs);
    tof_.advance(n, idle_tof_in_, config());
    for (std::size_t w = 0; w < kEncoderCount; ++w)
      spi_pins_.encoders[w] = last[w];
  }
  // n clocks with `pins` held, bit-identical to n calls of step(pins);
  // returns how many were not stepped as a whole chip (inside them the EPPMs
  // and the capture unit still step through their own events).
  std::uint64_t advance(std::uint64_t n, const In& pins) { return fast_forward(*this, n, pins); }
  [[nodiscard]] bool idle(const In& pins) const {
    const Wires w = wires(pins);
    return fabric_.idle(w.fabric, config()) && tof_.idle(w.tof, config()) &&
           interface_.idle(w.interface, w.status);
  }
  // ---- the two sides (fast-forward inside frames) ---------------------------
  // While the register file is quiet (bus_quiet: no slave strobe, no pulse
  // pending, no reset), the sensor side (the fabric and the capture unit)
  // shares no signal with the bus side (the SPI slave). The clocks of a
  // frame can then clock the bus side alone (step_bus) and bring the sensor
  // side, a fast-forward block of its own (sensors()), up by as many clocks
  // later, before the first clock that is not quiet: bit-identical to
  // stepping, because the bus side reads the sensor side (the snapshot, a
  // read) and writes it (pulses, configuration) only in such a clock.
  [[nodiscard]] bool bus_quiet(const In& pins) const { return interface_.quiet(pins.reset); }
  // One clock of the bus side alone, bus_quiet(pins); the sensor side is
  // then one more clock behind.
  void step_bus(const In& pins) {
    record_spi_pins(pins);
    interface_.step_quiet(interface_pins(pins));
  }
  // The sensor side on quiet clocks: the same contract as the chip's
  // (clocks_until_event reads no pin; skip as the chip's).
  class SensorSide {
   public:
    using In = ChipPins;
    [[nodiscard]] std::uint64_t clocks_until_event(const In& /*pins*/) const {
      return chip_->sensor_clocks_until_event();
    }
    void step(const In& pins) {
      OdolocChip& chip = *chip_;
      chip.record_sensor_pins(pins);
      set_sensor_pins(chip.idle_fabric_in_, chip.idle_tof_in_, pins);
      chip.fabric_.step(chip.idle_fabric_in_, chip.config());
      chip.tof_.step_pins(chip.idle_tof_in_, chip.config());
    }
    void skip(std::uint64_t n, const In& pins) { chip_->skip(n, pins); }
    template <class Runs>
    void skip(std::uint64_t n, const In& pins, Runs&& runs) {
      chip_->skip(n, pins, runs);
    }
    // n quiet clocks of the sensor side with `pins` held; returns how many
    // were skipped.
    std::uint64_t advance(std::uint64_t n, const In& pins) { return fast_forward(*this, n, pins); }

   private:
    friend class OdolocChip;
    explicit SensorSide(OdolocChip& chip) : chip_(&chip) {}
    OdolocChip* chip_;
  };
  [[nodiscard]] SensorSide sensors() { return SensorSide{*this}; }

  void reset_now() {
    fabric_.reset_now();
    tof_.reset_now();
    interface_.reset_now();
  }

  [[nodiscard]] UInt<1> miso() const { return interface_.miso(); }
  // The pins of the last clock.
  [[nodiscard]] const ChipPins& pins() const { return spi_pins_; }
  [[nodiscard]] const OdometryFabric& fabric() const { return fabric_; }
  [[nodiscard]] const ChipTofCapture& tof() const { return tof_; }
  [[nodiscard]] const ChipRegisterInterface& interface() const { return interface_; }
  [[nodiscard]] const SpiSlave& spi() const { return interface_.spi(); }
  [[nodiscard]] const ChipRegisterInterface::Registers& registers() const {
    return interface_.registers();
  }
  // The configuration ports: the register file's stored words, decoded.
  [[nodiscard]] const ports::Config& config() const { return interface_.config(); }

  template <class V>
  void trace(V& v) const {
    trace_fields(v, spi_pins_);
    v.signal("miso", miso());
    interface_.trace(v);  // its scopes spi and registers
    trace_scope(v, "fabric", fabric_);
    trace_scope(v, "tof", tof_);
  }

 private:
  static ChipRegisterInterface::In interface_pins(const In& pins) {
    return {.sclk = pins.sclk, .cs_n = pins.cs_n, .mosi = pins.mosi, .reset = pins.reset};
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

  // How many of the next clocks the sensor side can skip (reads no pin).
  [[nodiscard]] std::uint64_t sensor_clocks_until_event() const {
    return fabric_.clocks_until_event(idle_fabric_in_, config());
  }

  // A clock with a strobe or pulse: out of line, so the quiet clocks do not
  // pay for its large frame (the wires carry the whole status).
  template <Gating G, class Order>
  [[gnu::noinline]] void step_all(const In& pins, const Order& order) {
    const Wires w = wires(pins);
    const auto clock_children = [&](const ports::Config& cfg) {
      order([&] { fabric_.step<G>(w.fabric, cfg, order); },
            [&] { tof_.step<G>(w.tof, cfg, order); },
            [&] { interface_.step<G>(w.interface, w.status, order); });
    };
    // The configuration ports are the register file's registers, decoded: a
    // clock that may change them clocks the others with a copy of the
    // current ones.
    if (writes_config(w)) {
      const ports::Config before = config();
      clock_children(before);
    } else {
      clock_children(config());
    }
  }
  // A clock in which the register file may change the stored words.
  [[nodiscard]] bool writes_config(const Wires& w) const {
    const SpiEngineRegs& e = interface_.spi().engine();
    return !(e.commit & e.commit_write).is_zero() || !w.interface.reset.is_zero();
  }

  OdometryFabric fabric_;
  ChipTofCapture tof_;
  ChipRegisterInterface interface_;
  OdometryFabric::In idle_fabric_in_;  // the fabric's inputs when no strobe is pending
  ChipTofCapture::In idle_tof_in_;     // the capture unit's inputs when no strobe is pending
  ChipPins spi_pins_;                  // the pins of the last clock, for waveforms
};
static_assert(FastForwardBlock<OdolocChip> && FastForwardBlock<OdolocChip::SensorSide>);

}  // namespace odoloc::rtl
