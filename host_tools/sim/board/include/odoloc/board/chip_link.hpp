// sw::SpiLink onto the pins of the whole chip: a pin-level SPI master shifts
// each frame one fabric clock at a time, so the SoC-side bus code drives the
// model exactly as it would drive the FPGA.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "odoloc/board/spi_pin_master.hpp"
#include "odoloc/rtl/odoloc_chip.hpp"
#include "odoloc/rtl/vcd.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::board {

// What drives the sensor pins (encoders, ultrasonic comparators, TOF sync)
// of a simulated chip. For fast-forward it says how long they hold.
class SensorStimulus {
 public:
  static constexpr std::uint64_t kForever = ~std::uint64_t{0};
  SensorStimulus() = default;
  SensorStimulus(const SensorStimulus&) = delete;
  SensorStimulus& operator=(const SensorStimulus&) = delete;
  virtual ~SensorStimulus() = default;
  // Sets the sensor pins of the next clock, and moves on one clock.
  virtual void tick(rtl::ChipPins& pins) = 0;
  // How many of the clocks after it keep every pin the last tick() set but
  // the encoders' (0: unknown). Over such a stretch the encoders' pins are
  // piecewise constant: begin_encoder_runs() returns whether they change in
  // it (by default they hold too) and, if so, starts one cursor per encoder
  // at the last tick's levels; encoder_run(w, max) then returns encoder w's
  // next run (at most max clocks, w in fabric order) and moves its cursor
  // on.
  [[nodiscard]] virtual std::uint64_t hold() const = 0;
  [[nodiscard]] virtual bool begin_encoder_runs() { return false; }
  virtual rtl::PinRun encoder_run(std::size_t /*w*/, std::uint64_t /*max*/) {
    throw std::logic_error("SensorStimulus::encoder_run without encoder runs");
  }
  // Moves on by clocks <= hold() at once.
  virtual void skip(std::uint64_t clocks) = 0;
};

class ChipLink final : public sw::SpiLink {
 public:
  // Sets the sensor pins before every clock, with no knowledge of when they
  // change: every clock is stepped. Empty: the pins stay as they are.
  using EncoderPins = decltype(rtl::ChipPins::encoders);
  using Stimulus = std::function<void(rtl::ChipPins&)>;

  explicit ChipLink(SpiMasterConfig config, Stimulus stimulus = {})
      : master_(config), per_clock_(std::move(stimulus)) {
    if (per_clock_)
      stimulus_ = &per_clock_;
  }
  // A stimulus that tells how long its pins hold: idle stretches fast-forward
  // between its pin changes. It must outlive the link.
  ChipLink(SpiMasterConfig config, SensorStimulus& stimulus)
      : master_(config), per_clock_(Stimulus{}), stimulus_(&stimulus) {}

  void transfer(std::span<const std::uint8_t> mosi, std::span<std::uint8_t> miso) override {
    const std::vector<std::uint8_t> got = transfer_bits(mosi, SpiPinMaster::kNoAbort);
    std::ranges::copy(got.begin(), got.begin() + static_cast<std::ptrdiff_t>(miso.size()),
                      miso.begin());
  }
  void set_mode3(bool mode3) override { master_.set_mode3(mode3); }

  // One frame cut after `bits` rising SCLK edges (SpiPinMaster::transfer).
  std::vector<std::uint8_t> transfer_bits(std::span<const std::uint8_t> mosi, std::size_t bits) {
    in_frame_ = true;
    std::vector<std::uint8_t> miso = master_.transfer(
        mosi,
        [this](rtl::UInt<1> sclk, rtl::UInt<1> cs_n, rtl::UInt<1> mosi_pin) {
          return clock(sclk, cs_n, mosi_pin);
        },
        bits);
    in_frame_ = false;
    catch_up_sensors();
    return miso;
  }

  // Dumps the whole chip into `vcd` during every frame (not while idle:
  // the timebases change every clock and would bury the frames).
  void trace_frames(rtl::VcdWriter& vcd) {
    vcd.declare(chip_);
    vcd_ = &vcd;
  }

  // Dumps only the four SPI pins (cs_n, sclk, mosi, miso: one-bit wires
  // with distinct names, beside the writer's clk) during every frame: the
  // waveform logic-analyser software such as sigrok-cli's VCD input reads.
  void trace_pins(rtl::VcdWriter& vcd) {
    vcd.declare(SpiPins{pins_, chip_.miso()});
    pins_vcd_ = &vcd;
  }

  // Clocks with cs_n high and SCLK at its idle level. While the sensor pins
  // hold, the chip fast-forwards (OdolocChip::advance, bit-identical to
  // stepping) unless cycle stepping was asked for.
  void advance(std::uint64_t clocks) {
    const rtl::UInt<1> idle_sclk = rtl::UInt<1>::truncate(master_.config().mode3 ? 1 : 0);
    if (cycle_step_) {
      for (std::uint64_t i = 0; i < clocks; ++i)
        clock(idle_sclk, rtl::UInt<1>{1}, rtl::UInt<1>{});
      return;
    }
    pins_.sclk = idle_sclk;
    pins_.cs_n = rtl::UInt<1>{1};
    pins_.mosi = rtl::UInt<1>{};
    skipped_ += drive_stimulus(chip_, clocks);
    clocks_ += clocks;
  }
  // Every clock stepped, as before fast-forward (for comparisons: --cycle-step).
  void set_cycle_step(bool cycle_step) { cycle_step_ = cycle_step; }
  // Clocks advance() skipped rather than stepped.
  [[nodiscard]] std::uint64_t skipped_clocks() const { return skipped_; }

  [[nodiscard]] const rtl::OdolocChip& chip() const { return chip_; }
  [[nodiscard]] SpiPinMaster& master() { return master_; }
  [[nodiscard]] std::uint64_t clocks() const { return clocks_; }

  // One fabric clock with these SPI pin levels; returns MISO after it.
  // Inside a frame, while the register file is quiet, the slave is clocked
  // alone and the sensor side caught up later (OdolocChip::step_bus), unless
  // cycle stepping or the whole chip's waveform was asked for.
  rtl::UInt<1> clock(rtl::UInt<1> sclk, rtl::UInt<1> cs_n, rtl::UInt<1> mosi) {
    pins_.sclk = sclk;
    pins_.cs_n = cs_n;
    pins_.mosi = mosi;
    if (in_frame_ && !cycle_step_ && vcd_ == nullptr && chip_.bus_quiet(pins_)) {
      chip_.step_bus(pins_);
      ++sensor_lag_;
    } else {
      catch_up_sensors();
      if (stimulus_ != nullptr)
        stimulus_->tick(pins_);
      chip_.step(pins_);
    }
    if (vcd_ != nullptr && in_frame_)
      vcd_->sample(chip_, clocks_);
    if (pins_vcd_ != nullptr && in_frame_)
      pins_vcd_->sample(SpiPins{pins_, chip_.miso()}, clocks_);
    ++clocks_;
    return chip_.miso();
  }

 private:
  // `clocks` clocks of `block` (the whole chip with the bus idle, or its
  // sensor side behind a frame) on the stimulus's pins. Each tick() is
  // followed by the clocks its pins hold: with the encoders holding too,
  // fast-forwarded (block.advance); with them moving, skipped up to the
  // block's horizon with the encoders following their runs (skip with
  // runs), or one clock stepped. Returns how many clocks were skipped
  // rather than stepped.
  template <class Block>
  std::uint64_t drive_stimulus(Block&& block, std::uint64_t clocks) {
    if (stimulus_ == nullptr)
      return block.advance(clocks, pins_);
    std::uint64_t skipped = 0;
    while (clocks != 0) {
      stimulus_->tick(pins_);
      const std::uint64_t run = 1 + std::min(clocks - 1, stimulus_->hold());  // on these pins
      std::uint64_t n = run;
      if (run > 1 && stimulus_->begin_encoder_runs()) {
        n = std::min(run, block.clocks_until_event(pins_));
        if (n < 2) {
          block.step(pins_);
          n = 1;
        } else {
          block.skip(n, pins_, [this](std::size_t w, std::uint64_t max) {
            return stimulus_->encoder_run(w, max);
          });
          pins_.encoders = chip_.pins().encoders;
          skipped += n;
        }
      } else {
        skipped += block.advance(run, pins_);
      }
      stimulus_->skip(n - 1);
      clocks -= n;
    }
    return skipped;
  }
  // The sensor side's clocks behind the slave's, brought up.
  void catch_up_sensors() {
    const std::uint64_t lag = std::exchange(sensor_lag_, 0);
    if (lag != 0)
      drive_stimulus(chip_.sensors(), lag);
  }

  // A per-clock function as a stimulus that never knows how long it holds.
  class PerClock final : public SensorStimulus {
   public:
    explicit PerClock(Stimulus f) : f_(std::move(f)) {}
    explicit operator bool() const { return static_cast<bool>(f_); }
    void tick(rtl::ChipPins& pins) override { f_(pins); }
    [[nodiscard]] std::uint64_t hold() const override { return 0; }
    void skip(std::uint64_t /*clocks*/) override {}

   private:
    Stimulus f_;
  };

  // The SPI pins as the board sees them after a clock: the master's three
  // outputs and the chip's MISO.
  struct SpiPins {
    const rtl::ChipPins& pins;
    rtl::UInt<1> miso;
    template <class V>
    void trace(V& v) const {
      v.signal("cs_n", pins.cs_n);
      v.signal("sclk", pins.sclk);
      v.signal("mosi", pins.mosi);
      v.signal("miso", miso);
    }
  };

  rtl::OdolocChip chip_;
  rtl::ChipPins pins_;
  SpiPinMaster master_;
  PerClock per_clock_;
  SensorStimulus* stimulus_ = nullptr;
  std::uint64_t clocks_ = 0;
  std::uint64_t skipped_ = 0;
  std::uint64_t sensor_lag_ = 0;  // clocks the sensor side is behind (clock())
  bool cycle_step_ = false;
  rtl::VcdWriter* vcd_ = nullptr;
  rtl::VcdWriter* pins_vcd_ = nullptr;
  bool in_frame_ = false;
};

}  // namespace odoloc::board
