// Instruction-count driver (scripts/count-instructions.sh): the four EPPMs of
// BM_FourEppm_CycleStep, 400 000 clocks under issue 13's stimulus. The step
// is called out of line, as the benchmark's compiler calls it: inlined here,
// the all-zero configuration would fold into it and the count would be of
// code the benchmark does not run.
#include <cstdio>

#include "issue_stimulus.hpp"
#include "odoloc/rtl/encoder_fabric.hpp"
using namespace odoloc::rtl;  // NOLINT(google-build-using-namespace): the blocks under test
int main() {
  EncoderFabric fabric;
  EncoderFabric::Config cfg{};
  EncoderFabric::In in{};
  odoloc::tb::IssueStimulus stimulus;
  auto step = &EncoderFabric::step<Gating::kOn, DeclarationOrder>;
  asm volatile("" : "+r"(step));  // opaque: no inlining, no folding
  for (int i = 0; i < 400000; ++i) {
    if (stimulus.tick()) {
      for (std::size_t w = 0; w < kEncoderCount; ++w) {
        in[w].a = stimulus.pins()[w].bit<1>();
        in[w].b = stimulus.pins()[w].bit<0>();
      }
    }
    (fabric.*step)(in, cfg, DeclarationOrder{});
  }
  std::printf("%lld\n", static_cast<long long>(fabric.eppm(Encoder::kLeftRear).count().value()));
}
