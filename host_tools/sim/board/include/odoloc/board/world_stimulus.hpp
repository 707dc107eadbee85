// The world simulators on the chip's sensor pins, for ChipLink: the
// ground-truth tricycle on the encoders and the acoustic world on the
// ultrasonic comparators and the TOF sync input, either one optional. Both
// know when their pins next change, so the link fast-forwards in between.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/world/acoustics.hpp"
#include "odoloc/world/tricycle.hpp"

namespace odoloc::board {

class WorldStimulus final : public SensorStimulus {
 public:
  // Either may be null; both must outlive the stimulus. When the tricycle's
  // path ends the robot stands still: the encoder pins keep their levels.
  WorldStimulus(world::TricycleSimulator* truth, world::AcousticPins* acoustics)
      : truth_(truth), acoustics_(acoustics) {}

  void tick(rtl::ChipPins& pins) override {
    if (moving())
      drive_encoder_pins(pins.encoders, truth_->tick());
    if (acoustics_ != nullptr) {
      const world::PinLevels levels = acoustics_->tick();
      pins.comparators = decltype(pins.comparators)::truncate(levels.channels);
      pins.tof_sync = rtl::UInt<1>::truncate(levels.sync);
    }
  }
  // Inside one physics step each encoder's phase moves at a fixed rate, so
  // a copy of its source walks its edges (TricycleSimulator::source): the
  // encoders' runs last to the step's end, the other pins to the acoustic
  // world's next transition.
  [[nodiscard]] std::uint64_t hold() const override {
    std::uint64_t hold = moving() ? truth_->ticks_to_step_end() : kForever;
    if (acoustics_ != nullptr && acoustics_->next_transition_clock() != world::PinSource::kNever)
      hold = std::min(hold, acoustics_->next_transition_clock() - acoustics_->clock());
    return hold;
  }
  bool begin_encoder_runs() override {
    if (!moving())
      return false;
    for (const world::Encoder e : world::kEncoders)
      cursors_[static_cast<std::size_t>(fabric_input(e))] = truth_->source(e);
    return true;
  }
  rtl::PinRun encoder_run(std::size_t w, std::uint64_t max) override {
    world::QuadratureSource& cursor = cursors_[w];
    const rtl::PinRun run{encoder_pins(cursor.level()), std::min(max, cursor.ticks_to_next_edge())};
    cursor.skip(run.clocks);
    return run;
  }
  void skip(std::uint64_t clocks) override {
    if (moving())
      truth_->skip(clocks);
    if (acoustics_ != nullptr)
      acoustics_->skip_to(acoustics_->clock() + clocks);
  }

 private:
  [[nodiscard]] bool moving() const { return truth_ != nullptr && !truth_->done(); }
  world::TricycleSimulator* truth_;
  world::AcousticPins* acoustics_;
  std::array<world::QuadratureSource, rtl::kEncoderCount> cursors_{};  // by fabric encoder
};

}  // namespace odoloc::board
