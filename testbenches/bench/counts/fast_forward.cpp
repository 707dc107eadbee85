// Instruction-count driver (scripts/count-instructions.sh): 40 periods of
// BM_OdolocChip_FastForward_EncodersStill (100 ms of still encoders, then an
// SPI read of 8 EPPM words).
#include <array>
#include <cstdio>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"
int main() {
  odoloc::board::ChipLink link({.half_period = 4});
  odoloc::sw::SpiRegisterBus bus(link, {.crc = false, .confirm_writes = false});
  std::array<std::uint32_t, 8> words{};
  unsigned sum = 0;
  for (int i = 0; i < 40; ++i) {
    link.advance(5'000'000);
    bus.read(odoloc::regs::eppm::kBase, words);
    sum += words[0];
  }
  std::printf("%u %llu\n", sum, static_cast<unsigned long long>(link.skipped_clocks()));
}
