// Instruction-count driver (scripts/count-instructions.sh): 20 iterations of
// BM_Scaling_Encoders/encoders:4/cycle_step:0 (four encoders at 100 k
// edges/s, 20 ms each, SPI idle): fast-forward with moving encoders, each
// edge stepped through its EPPM.
#include <cstdio>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "synthetic_pins.hpp"
int main() {
  odoloc::tb::SyntheticPins pins(4, 100e3, 0);
  odoloc::board::ChipLink link({.half_period = 4}, pins);
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = false});
  bus.write(odoloc::regs::tof::command::kAddress, odoloc::regs::tof::command::arm.set(0, 0xFF));
  for (int i = 0; i < 20; ++i)
    link.advance(1'000'000);
  std::printf("%llu\n", static_cast<unsigned long long>(link.skipped_clocks()));
}
