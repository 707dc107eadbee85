// The CORDIC's datapath in the model's types: logic/cordic.hpp instantiated
// with rtl::Family, the one source of its arithmetic (the HLS kernel
// instantiates the same file with the vendor's types). Formats: that file
// and docs/cordic.md; parameters and tables: cordic_constants.hpp.
#pragma once

#include <cstdint>

#include "odoloc/logic/cordic.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/cordic_constants.hpp"
#include "odoloc/rtl/family.hpp"

namespace odoloc::rtl {

ODOLOC_LOGIC_FIELDS(logic::cordic::State, x, y, z, quadrant)
ODOLOC_LOGIC_FIELDS(logic::cordic::SinCos, sin, cos)

namespace cordic {

using Logic = logic::cordic::Cordic<Family>;
using Angle = Logic::Angle;
using Xy = Logic::Xy;
using Z = Logic::Z;
using Output = Logic::Output;
using State = logic::cordic::State<Family>;
using SinCos = logic::cordic::SinCos<Family>;

inline constexpr Xy kX0 = Xy::truncate(kX0Units);

inline State load(Angle angle) {
  return Logic::load(angle);
}
inline State iterate(const State& s, UInt<4> k) {
  return Logic::iterate(s, k);
}
inline SinCos finish(const State& s) {
  return Logic::finish(s);
}
inline SinCos sincos(Angle angle) {
  return Logic::sincos(angle);
}

}  // namespace cordic
}  // namespace odoloc::rtl
