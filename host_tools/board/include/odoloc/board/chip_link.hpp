// sw::SpiLink onto the pins of the whole chip: a pin-level SPI master shifts
// each frame one fabric clock at a time, so the SoC-side bus code drives the
// model exactly as it would drive the FPGA.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "odoloc/board/spi_pin_master.hpp"
#include "odoloc/rtl/odoloc_chip.hpp"
#include "odoloc/rtl/vcd.hpp"
#include "odoloc/sw/spi_frame.hpp"

namespace odoloc::board {

class ChipLink final : public sw::SpiLink {
 public:
  // Sets the sensor pins (encoders, ultrasonic comparators, TOF sync) before
  // every clock; empty: they stay as they are. The SPI pins are the master's.
  using EncoderPins = decltype(rtl::ChipPins::encoders);
  using Stimulus = std::function<void(rtl::ChipPins&)>;

  explicit ChipLink(SpiMasterConfig config, Stimulus stimulus = {})
      : master_(config), stimulus_(std::move(stimulus)) {}

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

  // Clocks with cs_n high and SCLK at its idle level. Without a stimulus the
  // pins hold, and the chip fast-forwards (OdolocChip::advance, bit-identical)
  // unless cycle stepping was asked for.
  void advance(std::uint64_t clocks) {
    const rtl::UInt<1> idle_sclk = rtl::UInt<1>::truncate(master_.config().mode3 ? 1 : 0);
    if (!stimulus_ && !cycle_step_) {
      pins_.sclk = idle_sclk;
      pins_.cs_n = rtl::UInt<1>{1};
      pins_.mosi = rtl::UInt<1>{};
      skipped_ += chip_.advance(clocks, pins_);
      clocks_ += clocks;
      return;
    }
    for (std::uint64_t i = 0; i < clocks; ++i)
      clock(idle_sclk, rtl::UInt<1>{1}, rtl::UInt<1>{});
  }
  // Every clock stepped, as before fast-forward (for comparisons: --cycle-step).
  void set_cycle_step(bool cycle_step) { cycle_step_ = cycle_step; }
  // Clocks advance() skipped rather than stepped.
  [[nodiscard]] std::uint64_t skipped_clocks() const { return skipped_; }

  [[nodiscard]] const rtl::OdolocChip& chip() const { return chip_; }
  [[nodiscard]] SpiPinMaster& master() { return master_; }
  [[nodiscard]] std::uint64_t clocks() const { return clocks_; }

  // One fabric clock with these SPI pin levels; returns MISO after it.
  rtl::UInt<1> clock(rtl::UInt<1> sclk, rtl::UInt<1> cs_n, rtl::UInt<1> mosi) {
    if (stimulus_)
      stimulus_(pins_);
    pins_.sclk = sclk;
    pins_.cs_n = cs_n;
    pins_.mosi = mosi;
    chip_.step(pins_);
    if (vcd_ != nullptr && in_frame_)
      vcd_->sample(chip_, clocks_);
    if (pins_vcd_ != nullptr && in_frame_)
      pins_vcd_->sample(SpiPins{pins_, chip_.miso()}, clocks_);
    ++clocks_;
    return chip_.miso();
  }

 private:
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
  Stimulus stimulus_;
  std::uint64_t clocks_ = 0;
  std::uint64_t skipped_ = 0;
  bool cycle_step_ = false;
  rtl::VcdWriter* vcd_ = nullptr;
  rtl::VcdWriter* pins_vcd_ = nullptr;
  bool in_frame_ = false;
};

}  // namespace odoloc::board
