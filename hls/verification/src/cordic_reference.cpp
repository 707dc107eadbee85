// rtl::SequentialCordic behind the CORDIC kernel's ports. Stimulus: a LOAD
// one clock in eight (many while busy, so load_ignored is exercised), a flag
// clear one in 64, a reset one in 4096, random angles.
#include <array>
#include <cstdint>
#include <random>

#include "odoloc/rtl/cordic.hpp"
#include "odoloc/verification/reference.hpp"

namespace odoloc::verification {

namespace {

class CordicReference final : public Reference {
 public:
  explicit CordicReference(std::uint64_t seed) : rng_(seed) {}

  [[nodiscard]] std::span<const std::string_view> input_names() const override { return kIn; }
  [[nodiscard]] std::span<const std::string_view> output_names() const override { return kOut; }

  void stimulus(std::span<std::int64_t> in) override {
    const std::uint64_t draw = rng_();
    in[0] = (draw & 7U) == 0 ? 1 : 0;
    in[1] = static_cast<std::int64_t>(draw >> 32 & 0xFFFFU);
    in[2] = (draw >> 3 & 63U) == 0 ? 1 : 0;
    in[3] = (draw >> 9 & 4095U) == 0 ? 1 : 0;
  }

  void step(std::span<const std::int64_t> in, std::span<std::int64_t> out) override {
    using rtl::UInt;
    const auto flag = [](std::int64_t v) {
      return UInt<1>::truncate(static_cast<std::uint64_t>(v));
    };
    model_.commit(
        model_.eval({flag(in[0]), rtl::cordic::Angle::truncate(static_cast<std::uint64_t>(in[1])),
                     flag(in[2]), flag(in[3])}));
    const auto& r = model_.regs();
    out[0] = r.busy.value();
    out[1] = r.ready.value();
    out[2] = r.load_ignored.value();
    out[3] = r.result.sin.value();
    out[4] = r.result.cos.value();
  }

 private:
  static constexpr std::array<std::string_view, 4> kIn{"load", "angle", "clear_flags", "reset"};
  static constexpr std::array<std::string_view, 5> kOut{"busy", "ready", "load_ignored", "sin",
                                                        "cos"};
  std::mt19937_64 rng_;
  rtl::SequentialCordic model_;
};

}  // namespace

std::unique_ptr<Reference> make_cordic_reference(std::uint64_t seed) {
  return std::make_unique<CordicReference>(seed);
}

}  // namespace odoloc::verification
