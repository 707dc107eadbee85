// The EPPM kernel (hls/eppm_kernel.hpp) against the cycle model (rtl::Eppm),
// compiled once per type family:
// - under the reference's seeded stimulus (hls/verification/src/
//   eppm_reference.cpp) every output equals the model's after every call
//   (1e6 calls; 1e8 in hls_long), and every register (synchroniser, filter
//   counters, the decoder's previous level, timebase, pulse accumulator,
//   period counter, armed, the sampled strobes) equals the model's, while the
//   stimulus demonstrably reaches the corners (carry, borrow, error_count
//   saturation, mode switches both ways, stall, bound ...);
// - the decoder's 16 transitions in each of the 4 decode modes equal a
//   table derived from the forward A/B sequence;
// - the documented latency and filter (docs/eppm.md): a pin change first
//   applied in call t reaches the count in call t + max(N, 1) + 2, a glitch
//   of N - 1 calls never does;
// - directed runs the random stimulus meets rarely, every output and every
//   register equal to the model's on every call: the 20-bit wrap both ways
//   (carry, borrow; a latch_clear and the flag's clear in the wrapping
//   clock: the event wins), error_count saturation and
//   its clear, the period counter's saturation after 2^23 ticks
//   (period_overflow, bound, invalid sample; the model alone runs through
//   the middle of that standstill, then the kernel takes its registers), the
//   speed word reading this call's stall_ticks;
// - from random register states near the limits (presets), kernel and model
//   stay equal register for register.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "hls_kernel_check.hpp"
#include "odoloc/hls/eppm_kernel.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/rtl/eppm.hpp"

namespace {

namespace he = odoloc::hls::eppm;
namespace rtl = odoloc::rtl;
using odoloc::hls::to_s64;
using rtl::SInt;
using rtl::UInt;

constexpr long long kCountMax = (1LL << (he::ec::kCountBits - 1)) - 1;
constexpr long long kCountMin = -kCountMax - 1;
constexpr long long kErrorCountMax = (1LL << he::ec::kErrorCountBits) - 1;
constexpr long long kTicksMax = (1LL << he::ec::kPeriodBits) - 1;

template <class U>
void set(U& field, long long value) {
  field = U::truncate(static_cast<std::uint64_t>(value));
}
template <int W>
void set(SInt<W>& field, long long value) {
  field = SInt<W>::truncate(value);
}

// Every input port 0 but the configuration, which takes the register map's
// resets. (`Inputs{}` leaves ap_int and ac_int fields undefined.)
he::Inputs reset_inputs() {
  he::Inputs in;
  he::visit_fields(in, [](const char*, auto& field) { field = 0; });
  const rtl::EppmConfig cfg{};
  in.filter_clocks = static_cast<long long>(cfg.cfg.filter_clocks.value());
  in.window_clocks = static_cast<long long>(cfg.window.clocks.value());
  in.prescale_divider = static_cast<long long>(cfg.prescale.divider.value());
  in.to_period_below = static_cast<long long>(cfg.to_period_below.edges.value());
  in.to_pulse_at = static_cast<long long>(cfg.to_pulse_at.edges.value());
  in.stall_ticks = static_cast<long long>(cfg.stall_ticks.ticks.value());
  return in;
}

// The kernel's input ports as the model's ports, field by field by name (a
// mapping written independently of the reference's).
void to_model(const he::Inputs& k, rtl::EppmInputs& in, rtl::EppmConfig& cfg) {
  set(in.a, to_s64(k.a));
  set(in.b, to_s64(k.b));
  set(in.latch_clear, to_s64(k.latch_clear));
  set(in.clear.status.phase_error, to_s64(k.clear_phase_error));
  set(in.clear.status.carry, to_s64(k.clear_carry));
  set(in.clear.status.borrow, to_s64(k.clear_borrow));
  set(in.clear.status.period_overflow, to_s64(k.clear_period_overflow));
  set(in.reset, to_s64(k.reset));
  set(cfg.cfg.filter_clocks, to_s64(k.filter_clocks));
  set(cfg.cfg.decode_mode, to_s64(k.decode_mode));
  set(cfg.cfg.speed_mode_select, to_s64(k.speed_mode_select));
  set(cfg.cfg.reverse, to_s64(k.reverse));
  set(cfg.window.clocks, to_s64(k.window_clocks));
  set(cfg.prescale.divider, to_s64(k.prescale_divider));
  set(cfg.to_period_below.edges, to_s64(k.to_period_below));
  set(cfg.to_pulse_at.edges, to_s64(k.to_pulse_at));
  set(cfg.stall_ticks.ticks, to_s64(k.stall_ticks));
}

// Every register of the model's module, block by block.
struct ModelRegs {
  rtl::QuadratureConditioner::Regs conditioner;
  rtl::QuadratureDecoder::Regs decoder;
  rtl::PositionCounter::Regs counter;
  rtl::SpeedTimebase::Regs timebase;
  rtl::PulseMeter::Regs pulse;
  rtl::PeriodMeter::Regs period;
};

ModelRegs regs_of(const rtl::Eppm& m) {
  return {m.conditioner(), m.decoder(), m.counter(), m.timebase(), m.pulse(), m.period()};
}

// f(name, kernel register, model register) for every register of the module.
template <class K, class M, class F>
void walk(K& k, M& m, F&& f) {
  f("conditioner.sync1", k.conditioner.sync1, m.conditioner.sync1);
  f("conditioner.sync2", k.conditioner.sync2, m.conditioner.sync2);
  f("conditioner.filtered", k.conditioner.filtered, m.conditioner.filtered);
  f("conditioner.line[0].stable", k.conditioner.line[0].stable, m.conditioner.line[0].stable);
  f("conditioner.line[1].stable", k.conditioner.line[1].stable, m.conditioner.line[1].stable);
  f("decoder.prev", k.decoder.prev, m.decoder.prev);
  f("decoder.direction", k.decoder.direction, m.decoder.direction);
  f("decoder.phase_error", k.decoder.phase_error, m.decoder.phase_error);
  f("decoder.error_count", k.decoder.error_count, m.decoder.error_count);
  f("counter.count", k.counter.count, m.counter.count);
  f("counter.latched", k.counter.latched, m.counter.latched);
  f("counter.carry", k.counter.carry, m.counter.carry);
  f("counter.borrow", k.counter.borrow, m.counter.borrow);
  f("timebase.window_count", k.timebase.window_count, m.timebase.window_count);
  f("timebase.prescale_count", k.timebase.prescale_count, m.timebase.prescale_count);
  f("pulse.acc", k.pulse.acc, m.pulse.acc);
  f("pulse.last", k.pulse.last, m.pulse.last);
  f("pulse.mode", k.pulse.mode, m.pulse.mode);
  f("pulse.sampled", k.pulse.sampled, m.pulse.sampled);
  f("period.count", k.period.count, m.period.count);
  f("period.last", k.period.last, m.period.last);
  f("period.valid", k.period.valid, m.period.valid);
  f("period.armed", k.period.armed, m.period.armed);
  f("period.last_dir", k.period.last_dir, m.period.last_dir);
  f("period.overflow", k.period.overflow, m.period.overflow);
  f("period.sampled", k.period.sampled, m.period.sampled);
}

// The first register in which kernel and model differ, or "".
std::string first_difference(const he::Registers& kernel, const ModelRegs& model) {
  return odoloc::tb::first_difference([&](const auto& f) { walk(kernel, model, f); });
}

// The reference's stimulus, one call's inputs at a time, as kernel ports.
class Stimulus {
 public:
  explicit Stimulus(std::uint64_t seed)
      : reference_(odoloc::hls_export::find_kernel("eppm")->make_reference(seed)),
        row_(reference_->input_names().size()),
        out_(reference_->output_names().size()) {}
  he::Inputs next() {
    reference_->stimulus(row_);
    reference_->step(row_, out_);  // the stimulus follows its own model's count
    he::Inputs in;                 // every field set below
    std::size_t at = 0;
    he::visit_fields(in, [&](const char*, auto& field) { field = row_[at++]; });
    return in;
  }

 private:
  std::unique_ptr<odoloc::verification::Reference> reference_;
  std::vector<std::int64_t> row_, out_;
};

// The model's status as the kernel's outputs, field by field by name (a
// mapping written independently of the reference's).
he::Outputs expected(const rtl::EppmStatus& s) {
  he::Outputs o;
  o.count = s.count.value.value();
  o.latched = s.latched.value.value();
  o.speed_value = s.speed.value.value();
  o.speed_mode = s.speed.mode.value();
  o.speed_valid = s.speed.valid.value();
  o.speed_stalled = s.speed.stalled.value();
  o.speed_bound = s.speed.bound.value();
  o.pulse_last = s.pulse_last.edges.value();
  o.period_last_ticks = s.period_last.ticks.value();
  o.period_last_valid = s.period_last.valid.value();
  o.period_last_forward = s.period_last.forward.value();
  o.phase_error = s.status.phase_error.value();
  o.carry = s.status.carry.value();
  o.borrow = s.status.borrow.value();
  o.period_overflow = s.status.period_overflow.value();
  o.forward = s.status.forward.value();
  o.error_count = s.error_count.count.value();
  return o;
}

// The first output in which kernel and model differ, or "".
std::string first_difference(const he::Outputs& kernel, const he::Outputs& model) {
  he::Outputs k = kernel, m = model;
  std::vector<long long> want;
  he::visit_fields(m, [&](const char*, auto& field) { want.push_back(to_s64(field)); });
  std::string first;
  std::size_t at = 0;
  he::visit_fields(k, [&](const char* name, auto& field) {
    if (first.empty() && to_s64(field) != want[at])
      first = std::string(name) + ": kernel " + std::to_string(to_s64(field)) + ", model " +
              std::to_string(want[at]);
    ++at;
  });
  return first;
}

// Kernel and model side by side on chosen inputs: every output and every
// register compared after every call, the first difference kept.
class Pair {
 public:
  Pair() { model_.reset_now(); }
  const he::Outputs& step(const he::Inputs& in) {
    rtl::EppmInputs model_in{};
    rtl::EppmConfig cfg{};
    to_model(in, model_in, cfg);
    model_.step(model_in, cfg);
    he::step(regs_, in, out_);
    std::string difference = first_difference(out_, expected(model_.status(cfg)));
    if (difference.empty())
      difference = first_difference(regs_, regs_of(model_));
    if (!difference.empty() && differences_++ == 0)
      first_ = "call " + std::to_string(calls_) + ", " + difference;
    ++calls_;
    return out_;
  }
  // n calls with the same inputs; the outputs of the last.
  const he::Outputs& hold(const he::Inputs& in, std::uint64_t n) {
    for (std::uint64_t k = 1; k < n; ++k)
      step(in);
    return step(in);
  }
  // n calls of the model alone (its fast path), then the kernel takes the
  // model's registers: a long standstill at the model's speed.
  void fast_forward(const he::Inputs& in, std::uint64_t n) {
    rtl::EppmInputs model_in{};
    rtl::EppmConfig cfg{};
    to_model(in, model_in, cfg);
    for (std::uint64_t k = 0; k < n; ++k)
      model_.step(model_in, cfg);
    ModelRegs m = regs_of(model_);
    walk(regs_, m, [](const char*, auto& kf, const auto& mf) { kf = mf.value(); });
    calls_ += n;
  }
  [[nodiscard]] std::uint64_t differences() const { return differences_; }
  [[nodiscard]] const std::string& first() const { return first_; }

 private:
  rtl::Eppm model_;
  he::Registers regs_;
  he::Outputs out_;
  std::uint64_t calls_ = 0, differences_ = 0;
  std::string first_;
};

// A and B at phase p of the forward cycle AB = 00, 10, 11, 01.
void set_phase(he::Inputs& in, int p) {
  const int q = ((p % 4) + 4) % 4;
  in.a = q == 1 || q == 2 ? 1 : 0;
  in.b = q >= 2 ? 1 : 0;
}

TEST(HlsEppm, EveryOutputEqualsTheModelEveryCall) {
  const auto check = odoloc::tb::check_kernel<he::Inputs, he::Outputs, he::Registers>(
      "eppm", 5, odoloc::tb::hls_calls(1000000), he::step);
  EXPECT_EQ(check.names_error, "");
  EXPECT_GT(check.calls, 0U);
  EXPECT_EQ(check.mismatches, 0U) << check.first_mismatch;
}

// What the stimulus reached, seen at the kernel's ports.
struct Coverage {
  std::uint64_t carry = 0, borrow = 0, phase_errors = 0, error_count_saturated = 0;
  std::uint64_t to_pulse = 0, to_period = 0, stalled = 0, bound = 0, invalid = 0;
  std::uint64_t latches = 0, resets = 0, reversals = 0, backwards = 0, flag_clears = 0;
  std::uint64_t near_wrap = 0;
  std::array<std::uint64_t, 4> decode_modes{};
  std::array<std::uint64_t, 2> reverse{};
};

TEST(HlsEppm, EveryRegisterEqualsTheModelAndTheStimulusReachesTheCorners) {
  const std::uint64_t calls = odoloc::tb::scaled(1000000);
  Stimulus stimulus(6);
  rtl::Eppm model;
  model.reset_now();
  he::Registers regs;
  he::Outputs out, before;
  Coverage c;
  std::uint64_t differing = 0;
  std::string first;
  for (std::uint64_t call = 0; call < calls; ++call) {
    const he::Inputs in = stimulus.next();
    rtl::EppmInputs model_in{};
    rtl::EppmConfig cfg{};
    to_model(in, model_in, cfg);
    model.step(model_in, cfg);
    before = out;
    he::step(regs, in, out);
    const std::string difference = first_difference(regs, regs_of(model));
    if (!difference.empty() && differing++ == 0)
      first = "call " + std::to_string(call) + ", " + difference;
    const auto rose = [](const auto& now, const auto& was) {
      return to_s64(now) == 1 && to_s64(was) == 0 ? 1U : 0U;
    };
    c.carry += rose(out.carry, before.carry);
    c.borrow += rose(out.borrow, before.borrow);
    c.phase_errors += to_s64(out.error_count) != to_s64(before.error_count) ? 1U : 0U;
    c.error_count_saturated += to_s64(out.error_count) == kErrorCountMax ? 1U : 0U;
    c.to_pulse += rose(out.speed_mode, before.speed_mode);
    c.to_period += rose(before.speed_mode, out.speed_mode);
    c.stalled += rose(out.speed_stalled, before.speed_stalled);
    c.bound += rose(out.speed_bound, before.speed_bound);
    c.invalid += rose(before.period_last_valid, out.period_last_valid);
    c.latches += to_s64(in.latch_clear) == 1 ? 1U : 0U;
    c.resets += to_s64(in.reset) == 1 ? 1U : 0U;
    c.reversals += to_s64(out.forward) != to_s64(before.forward) ? 1U : 0U;
    c.backwards += to_s64(out.count) < to_s64(before.count) ? 1U : 0U;
    c.flag_clears += to_s64(in.clear_carry) + to_s64(in.clear_borrow) +
                                 to_s64(in.clear_phase_error) + to_s64(in.clear_period_overflow) >
                             0
                         ? 1U
                         : 0U;
    c.near_wrap +=
        to_s64(out.count) > kCountMax - 64 || to_s64(out.count) < kCountMin + 64 ? 1U : 0U;
    ++c.decode_modes[static_cast<std::size_t>(to_s64(in.decode_mode))];
    ++c.reverse[static_cast<std::size_t>(to_s64(in.reverse))];
  }
  std::printf("eppm (%s): %llu calls, %llu with a differing register\n", odoloc::hls::kTypeFamily,
              static_cast<unsigned long long>(calls), static_cast<unsigned long long>(differing));
  std::printf(
      "  coverage: carry %llu, borrow %llu, illegal %llu, error_count saturated %llu calls, "
      "mode -> pulse %llu, -> period %llu, stalls %llu, bounds %llu, invalid samples %llu, "
      "latches %llu, resets %llu, reversals %llu, flag clears %llu, near the wrap %llu calls, "
      "decode modes %llu/%llu/%llu/%llu, reverse %llu/%llu calls\n",
      static_cast<unsigned long long>(c.carry), static_cast<unsigned long long>(c.borrow),
      static_cast<unsigned long long>(c.phase_errors),
      static_cast<unsigned long long>(c.error_count_saturated),
      static_cast<unsigned long long>(c.to_pulse), static_cast<unsigned long long>(c.to_period),
      static_cast<unsigned long long>(c.stalled), static_cast<unsigned long long>(c.bound),
      static_cast<unsigned long long>(c.invalid), static_cast<unsigned long long>(c.latches),
      static_cast<unsigned long long>(c.resets), static_cast<unsigned long long>(c.reversals),
      static_cast<unsigned long long>(c.flag_clears), static_cast<unsigned long long>(c.near_wrap),
      static_cast<unsigned long long>(c.decode_modes[0]),
      static_cast<unsigned long long>(c.decode_modes[1]),
      static_cast<unsigned long long>(c.decode_modes[2]),
      static_cast<unsigned long long>(c.decode_modes[3]),
      static_cast<unsigned long long>(c.reverse[0]), static_cast<unsigned long long>(c.reverse[1]));
  EXPECT_EQ(differing, 0U) << first;
  if (calls >= 1000000) {  // the schedule's first regimes hold each corner
    EXPECT_GT(c.carry, 1U);
    EXPECT_GT(c.borrow, 1U);
    EXPECT_GT(c.error_count_saturated, 0U);
    EXPECT_GT(c.to_pulse, 10U);
    EXPECT_GT(c.to_period, 10U);
    EXPECT_GT(c.stalled, 0U);
    EXPECT_GT(c.bound, 0U);
    EXPECT_GT(c.invalid, 0U);
    EXPECT_GT(c.latches, 10U);
    EXPECT_GT(c.reversals, 100U);
    EXPECT_GT(c.flag_clears, 10U);
    for (const std::uint64_t m : c.decode_modes)
      EXPECT_GT(m, 0U);
  }
}

// Every (previous, current) pair in every decode mode: the decoder's logic
// (logic/eppm.hpp: the Gray code (B, A^B) read as binary, in this family)
// against a table derived another way, from the forward sequence of A/B
// levels AB = 00 -> 10 -> 11 -> 01 and the datasheet rules of x4/x2/x1
// counting (LS7366R: x1 counts A's edge with B low, x2 A's edges).
TEST(HlsEppm, DecoderEqualsTheForwardSequenceTable) {
  using Decoder = odoloc::logic::eppm::QuadratureDecoder<odoloc::hls::Family>;
  constexpr std::array<int, 4> kSequence = {0b00, 0b10, 0b11, 0b01};  // A in bit 1
  const auto position = [&](int ab) {
    return static_cast<int>(std::find(kSequence.begin(), kSequence.end(), ab) - kSequence.begin());
  };
  int mismatches = 0;
  for (int prev = 0; prev < 4; ++prev) {
    for (int curr = 0; curr < 4; ++curr) {
      const int delta = (position(curr) - position(prev) + 4) % 4;
      const int dir = delta == 1 ? 1 : delta == 3 ? -1 : 0;
      const bool a_edge = ((prev ^ curr) & 2) != 0;
      const bool b_low = (prev & 1) == 0 && (curr & 1) == 0;
      const std::array<int, 4> want = {dir, a_edge ? dir : 0, a_edge && b_low ? dir : 0, dir};
      for (int mode = 0; mode < 4; ++mode) {
        const Decoder::Transition t = Decoder::decode(prev, curr, mode);
        if (to_s64(t.step) != want[static_cast<std::size_t>(mode)] || t.illegal != (delta == 2) ||
            t.moved != (dir != 0) || (dir != 0 && t.forward != (dir > 0)))
          ++mismatches;
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
}

// The generated port structs of the logic (odoloc/logic/ports.hpp) start at
// the register map's resets in this family, as the model's do.
TEST(HlsEppm, LogicPortStructsStartAtTheRegisterMapsResets) {
  const odoloc::logic::ports::eppm::Config<odoloc::hls::Family> k;
  const rtl::EppmConfig m{};
  const auto v = [](auto field) { return static_cast<long long>(field.value()); };
  EXPECT_EQ(to_s64(k.cfg.filter_clocks), v(m.cfg.filter_clocks));
  EXPECT_EQ(to_s64(k.cfg.decode_mode), v(m.cfg.decode_mode));
  EXPECT_EQ(to_s64(k.cfg.speed_mode_select), v(m.cfg.speed_mode_select));
  EXPECT_EQ(to_s64(k.cfg.reverse), v(m.cfg.reverse));
  EXPECT_EQ(to_s64(k.window.clocks), v(m.window.clocks));
  EXPECT_EQ(to_s64(k.prescale.divider), v(m.prescale.divider));
  EXPECT_EQ(to_s64(k.to_period_below.edges), v(m.to_period_below.edges));
  EXPECT_EQ(to_s64(k.to_pulse_at.edges), v(m.to_pulse_at.edges));
  EXPECT_EQ(to_s64(k.stall_ticks.ticks), v(m.stall_ticks.ticks));
  EXPECT_NE(v(m.window.clocks), 0);  // the resets are not all 0
  const odoloc::logic::ports::eppm::Status<odoloc::hls::Family> status;
  EXPECT_EQ(to_s64(status.count.value), 0);
  EXPECT_EQ(to_s64(status.speed.value), 0);
}

// docs/eppm.md, "Input conditioning and latency": a change first applied in
// call t (held >= N calls) is in the count output of call t + max(N, 1) + 2;
// a pulse of N - 1 calls is rejected, one of N passes.
TEST(HlsEppm, LatencyAndFilterAreTheDocumentedOnes) {
  for (const unsigned n : {0U, 1U, 2U, 3U, 4U, 5U, 8U, 17U, 100U, 255U}) {
    const long long big_n = n < 1 ? 1 : n;
    Pair pair;
    he::Inputs in = reset_inputs();
    in.filter_clocks = n;
    pair.hold(in, 300);
    // One forward step: A rises at call t = 0 of this sequence.
    set_phase(in, 1);
    long long seen_at = -1;
    for (long long call = 0; call < big_n + 10; ++call) {
      if (to_s64(pair.step(in).count) == 1 && seen_at < 0)
        seen_at = call;
    }
    EXPECT_EQ(seen_at, big_n + 2) << "N = " << n;
    // A glitch of N - 1 calls on B never reaches the counter.
    if (big_n >= 2) {
      he::Inputs glitch = in;
      glitch.b = 1;
      pair.hold(glitch, static_cast<std::uint64_t>(big_n - 1));
      const he::Outputs& out = pair.hold(in, static_cast<std::uint64_t>(big_n) + 10);
      EXPECT_EQ(to_s64(out.count), 1) << "N = " << n;
      EXPECT_EQ(to_s64(out.forward), 1) << "N = " << n;
    }
    // One of N calls passes: a step forward and back.
    he::Inputs pulse = in;
    pulse.b = 1;
    pair.hold(pulse, static_cast<std::uint64_t>(big_n));
    pair.hold(in, 2);
    long long back = -1;
    for (long long call = 0; call < big_n + 10; ++call) {
      if (to_s64(pair.step(in).forward) == 0 && back < 0)
        back = call;
    }
    EXPECT_GE(back, 0) << "N = " << n;
    EXPECT_EQ(pair.differences(), 0U) << pair.first();
  }
}

// The 20-bit count wraps past +2^19-1 with carry and past -2^19 with borrow;
// a latch_clear in the wrapping clock latches the wrapped value.
TEST(HlsEppm, CountWrapsWithCarryAndBorrow) {
  Pair pair;
  he::Inputs in = reset_inputs();
  in.filter_clocks = 0;
  in.window_clocks = 37;
  in.prescale_divider = 3;
  in.to_period_below = 10;
  in.to_pulse_at = 20;
  pair.hold(in, 10);
  int phase = 0;
  const long long limit = kCountMax + 1;
  // One edge per call (A and B alternate, each held 2 calls) up to the top.
  for (long long e = 0; e < limit - 1; ++e) {
    set_phase(in, ++phase);
    pair.step(in);
  }
  const he::Outputs& top = pair.hold(in, 5);
  EXPECT_EQ(to_s64(top.count), kCountMax);
  EXPECT_EQ(to_s64(top.carry), 0);
  set_phase(in, ++phase);
  const he::Outputs& wrapped = pair.hold(in, 5);
  EXPECT_EQ(to_s64(wrapped.count), kCountMin);
  EXPECT_EQ(to_s64(wrapped.carry), 1);
  EXPECT_EQ(to_s64(wrapped.borrow), 0);
  set_phase(in, --phase);
  const he::Outputs& back = pair.hold(in, 5);
  EXPECT_EQ(to_s64(back.count), kCountMax);
  EXPECT_EQ(to_s64(back.borrow), 1);
  // Clear both; the wrap again, with a latch_clear and a carry clear in the
  // clock the counter sees the edge (the 4th call after the pin: filter
  // off): the wrapped value is latched and the event wins over the clear.
  in.clear_carry = 1;
  in.clear_borrow = 1;
  const he::Outputs& cleared = pair.step(in);
  EXPECT_EQ(to_s64(cleared.carry), 0);
  EXPECT_EQ(to_s64(cleared.borrow), 0);
  in.clear_carry = 0;
  in.clear_borrow = 0;
  set_phase(in, ++phase);
  pair.hold(in, 3);
  in.latch_clear = 1;
  in.clear_carry = 1;
  const he::Outputs& latched = pair.step(in);
  EXPECT_EQ(to_s64(latched.latched), kCountMin);
  EXPECT_EQ(to_s64(latched.count), 0);
  EXPECT_EQ(to_s64(latched.carry), 1);
  EXPECT_EQ(to_s64(latched.borrow), 0);
  in.latch_clear = 0;
  in.clear_carry = 0;
  // Down through the wrap with a borrow clear in the clock of the event.
  pair.hold(in, 3);
  in.latch_clear = 1;
  pair.step(in);
  in.latch_clear = 0;
  pair.hold(in, 3);
  for (long long e = 0; e < limit; ++e) {
    set_phase(in, --phase);
    pair.step(in);
  }
  const he::Outputs& bottom = pair.hold(in, 5);
  EXPECT_EQ(to_s64(bottom.count), kCountMin);
  EXPECT_EQ(to_s64(bottom.borrow), 0);
  set_phase(in, --phase);
  pair.hold(in, 3);
  in.clear_borrow = 1;
  const he::Outputs& under = pair.step(in);
  EXPECT_EQ(to_s64(under.count), kCountMax);
  EXPECT_EQ(to_s64(under.borrow), 1);
  EXPECT_EQ(pair.differences(), 0U) << pair.first();
}

// error_count saturates at 65 535; its clear restarts it, and an illegal
// transition in the clearing clock counts 1.
TEST(HlsEppm, ErrorCountSaturatesAndClears) {
  Pair pair;
  he::Inputs in = reset_inputs();
  in.filter_clocks = 0;
  pair.hold(in, 10);
  int phase = 0;
  for (long long k = 0; k < kErrorCountMax + 100; ++k) {
    phase += 2;  // both lines flip together
    set_phase(in, phase);
    pair.step(in);
  }
  const he::Outputs& full = pair.hold(in, 5);
  EXPECT_EQ(to_s64(full.error_count), kErrorCountMax);
  EXPECT_EQ(to_s64(full.phase_error), 1);
  in.clear_phase_error = 1;
  const he::Outputs& cleared = pair.step(in);
  EXPECT_EQ(to_s64(cleared.error_count), 0);
  EXPECT_EQ(to_s64(cleared.phase_error), 0);
  in.clear_phase_error = 0;
  phase += 2;
  set_phase(in, phase);
  pair.hold(in, 3);  // the decoder sees the flip in the 4th call
  in.clear_phase_error = 1;
  const he::Outputs& both = pair.step(in);
  EXPECT_EQ(to_s64(both.error_count), 1);
  EXPECT_EQ(to_s64(both.phase_error), 1);
  EXPECT_EQ(pair.differences(), 0U) << pair.first();
}

// After a standstill of 2^23 ticks (prescale 0: a tick per call) the period
// counter saturates and sets period_overflow; the speed word reads the bound;
// the next edge's sample reads the saturated count and is invalid. The
// speed word follows this call's stall_ticks.
TEST(HlsEppm, PeriodCounterSaturatesAfterAStandstill) {
  Pair pair;
  he::Inputs in = reset_inputs();
  in.filter_clocks = 1;
  in.prescale_divider = 0;
  in.speed_mode_select = odoloc::rtl::eppm::kSelectPeriod;
  in.window_clocks = 100;
  in.stall_ticks = 0;
  pair.hold(in, 10);
  int phase = 0;
  for (int e = 0; e < 4; ++e) {
    set_phase(in, ++phase);
    pair.hold(in, 50);
  }
  const he::Outputs& moving = pair.step(in);
  EXPECT_EQ(to_s64(moving.speed_valid), 1);
  EXPECT_EQ(to_s64(moving.period_last_ticks), 50);
  pair.hold(in, 1000);
  pair.fast_forward(in, (std::uint64_t{1} << odoloc::rtl::eppm::kPeriodBits) - 2000);
  const he::Outputs& still = pair.hold(in, 1000);
  EXPECT_EQ(to_s64(still.period_overflow), 1);
  EXPECT_EQ(to_s64(still.speed_bound), 1);
  EXPECT_EQ(to_s64(still.speed_value), kTicksMax);
  // The speed word reads this call's stall_ticks: stalled at once.
  in.stall_ticks = kTicksMax;
  const he::Outputs& stalled = pair.step(in);
  EXPECT_EQ(to_s64(stalled.speed_stalled), 1);
  EXPECT_EQ(to_s64(stalled.speed_value), 0);
  in.stall_ticks = 0;
  in.clear_period_overflow = 1;
  pair.step(in);
  in.clear_period_overflow = 0;
  const he::Outputs& saturated = pair.step(in);
  EXPECT_EQ(to_s64(saturated.period_overflow), 1);  // still saturated: set again
  set_phase(in, ++phase);
  const he::Outputs& sample = pair.hold(in, 10);
  EXPECT_EQ(to_s64(sample.period_last_ticks), kTicksMax);
  EXPECT_EQ(to_s64(sample.period_last_valid), 0);
  EXPECT_EQ(pair.differences(), 0U) << pair.first();
}

// The module's blocks clocked as Eppm clocks them (its own wiring functions,
// every block every clock), so that a test can preset registers the module
// keeps private.
class PresetEppm {
 public:
  void load(const ModelRegs& m) {
    conditioner_.commit(m.conditioner);
    decoder_.commit(m.decoder);
    counter_.commit(m.counter);
    timebase_.commit(m.timebase);
    pulse_.commit(m.pulse);
    period_.commit(m.period);
  }
  [[nodiscard]] ModelRegs regs() const {
    return {conditioner_.regs(), decoder_.regs(), counter_.regs(),
            timebase_.regs(),    pulse_.regs(),   period_.regs()};
  }
  void step(const rtl::EppmInputs& in, const rtl::EppmConfig& cfg) {
    using E = rtl::Eppm;
    const UInt<2> filtered = conditioner_.regs().filtered;
    const E::Wires w{.filtered = filtered,
                     .step = decoder_.step(filtered, cfg.cfg.decode_mode),
                     .window_end = timebase_.window_end(cfg.window.clocks),
                     .tick = timebase_.tick(cfg.prescale.divider)};
    load({conditioner_.eval(E::conditioner_in(in, cfg)), decoder_.eval(E::decoder_in(w, in)),
          counter_.eval(E::counter_in(w, in)), timebase_.eval(E::timebase_in(in, cfg)),
          pulse_.eval(E::pulse_in(w, in, cfg)), period_.eval(E::period_in(w, in, cfg))});
  }

 private:
  rtl::QuadratureConditioner conditioner_;
  rtl::QuadratureDecoder decoder_;
  rtl::PositionCounter counter_;
  rtl::SpeedTimebase timebase_;
  rtl::PulseMeter pulse_;
  rtl::PeriodMeter period_;
};

// A random register state near the limits: counts within 40 edges of the
// wrap, error_count and the period counter near saturation, the pulse
// accumulator near +-2^23, filter counters near 255, timers near their ends.
class Presets {
 public:
  explicit Presets(std::uint64_t seed) : rng_(seed) {}
  ModelRegs next() {
    ModelRegs m{};
    he::Registers scratch;
    walk(scratch, m, [&](const char*, auto&, auto& field) { edgy(field); });
    return m;
  }

 private:
  // Anywhere, or within 40 of a limit (0, the maximum, or for signed fields
  // the minimum and maximum).
  template <int W>
  void edgy(UInt<W>& field) {
    const std::uint64_t max = (std::uint64_t{1} << W) - 1;
    const std::uint64_t near = rng_() % 41;
    switch (rng_() % 3) {
      case 0:
        field = UInt<W>::truncate(rng_());
        break;
      case 1:
        field = UInt<W>::truncate(near);
        break;
      default:
        field = UInt<W>::truncate(max - std::min(near, max));
        break;
    }
  }
  template <int W>
  void edgy(SInt<W>& field) {
    const std::int64_t max = (std::int64_t{1} << (W - 1)) - 1;
    const auto near = static_cast<std::int64_t>(rng_() % 41);
    switch (rng_() % 3) {
      case 0:
        field = SInt<W>::truncate(static_cast<std::int64_t>(rng_()));
        break;
      case 1:
        field = SInt<W>::truncate(max - near);
        break;
      default:
        field = SInt<W>::truncate(-max - 1 + near);
        break;
    }
  }
  std::mt19937_64 rng_;
};

TEST(HlsEppm, PresetStatesNearTheLimitsEqualTheModel) {
  constexpr int kClocks = 2000;
  const int presets = static_cast<int>(odoloc::tb::scaled(200 * kClocks) / kClocks);
  Presets draw(21);
  std::uint64_t differing = 0;
  std::string first;
  for (int p = 0; p < presets; ++p) {
    Stimulus stimulus(1000 + static_cast<std::uint64_t>(p));
    const ModelRegs preset = draw.next();
    PresetEppm model;
    model.load(preset);
    he::Registers regs;
    ModelRegs copy = preset;
    walk(regs, copy, [](const char*, auto& kf, const auto& mf) { kf = mf.value(); });
    he::Outputs out;
    for (int clock = 0; clock < kClocks; ++clock) {
      he::Inputs in = stimulus.next();
      in.reset = 0;  // keep the preset
      rtl::EppmInputs model_in{};
      rtl::EppmConfig cfg{};
      to_model(in, model_in, cfg);
      model.step(model_in, cfg);
      he::step(regs, in, out);
      const std::string difference = first_difference(regs, model.regs());
      if (!difference.empty() && differing++ == 0)
        first =
            "preset " + std::to_string(p) + ", clock " + std::to_string(clock) + ", " + difference;
    }
  }
  std::printf("eppm (%s): %d presets x %d clocks, %llu with a differing register\n",
              odoloc::hls::kTypeFamily, presets, kClocks,
              static_cast<unsigned long long>(differing));
  EXPECT_EQ(differing, 0U) << first;
}

}  // namespace
