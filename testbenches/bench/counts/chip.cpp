// Instruction-count driver (scripts/count-instructions.sh): the chip of
// BM_OdolocChip_CycleStep, 200 000 clocks under issue 13's stimulus.
#include <cstdio>

#include "issue_stimulus.hpp"
#include "odoloc/rtl/odoloc_chip.hpp"
int main() {
  odoloc::rtl::OdolocChip chip;
  odoloc::rtl::ChipPins pins;
  odoloc::tb::IssueStimulus stimulus;
  for (int i = 0; i < 200000; ++i) {
    if (stimulus.tick())
      pins.encoders = stimulus.pins();
    chip.step(pins);
  }
  std::printf("%u\n", static_cast<unsigned>(sizeof(chip)) +
                          static_cast<unsigned>(chip.fabric().report().steer_position.value()));
}
