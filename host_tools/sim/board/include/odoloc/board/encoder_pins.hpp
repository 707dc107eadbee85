// Where the world meets the chip's encoder pins: the one mapping of the
// world's encoders onto the fabric's encoder inputs, and the one conversion
// of A/B levels into the pin type (A in bit 1).
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>

#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
#include "odoloc/world/quadrature_source.hpp"
#include "odoloc/world/tricycle.hpp"

namespace odoloc::board {

// The chip's A/B pins of one encoder.
using EncoderPins = rtl::UInt<2>;
// All encoder pins of the chip, indexed by the fabric's rtl::Encoder.
using ChipEncoderPins = std::array<EncoderPins, rtl::kEncoderCount>;

static_assert(world::kEncoderCount == rtl::kEncoderCount, "one fabric input per world encoder");

// The fabric input each of the robot's encoders is wired to.
constexpr rtl::Encoder fabric_input(world::Encoder e) {
  switch (e) {
    case world::Encoder::kLeftRear:
      return rtl::Encoder::kLeftRear;
    case world::Encoder::kRightRear:
      return rtl::Encoder::kRightRear;
    case world::Encoder::kFrontDrive:
      return rtl::Encoder::kFrontDrive;
    case world::Encoder::kSteering:
      return rtl::Encoder::kSteering;
  }
  throw std::invalid_argument("no such encoder");
}

constexpr EncoderPins encoder_pins(world::QuadratureLevels levels) {
  return EncoderPins::truncate((levels.a ? 2U : 0U) | (levels.b ? 1U : 0U));
}

// Drives the chip's encoder pins from the world's encoders.
constexpr void drive_encoder_pins(
    ChipEncoderPins& pins,
    const std::array<world::QuadratureLevels, world::kEncoderCount>& levels) {
  for (const world::Encoder e : world::kEncoders)
    pins[static_cast<std::size_t>(fabric_input(e))] = encoder_pins(levels[world::index(e)]);
}

}  // namespace odoloc::board
