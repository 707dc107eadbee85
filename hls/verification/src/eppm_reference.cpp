// rtl::Eppm behind the EPPM kernel's ports (hls/eppm_kernel.hpp): one call =
// one model step(in, cfg), then status(cfg) with the same configuration.
//
// Stimulus: an encoder wheel (its phase in the forward Gray cycle, A and B
// derived from it) plus noise on the pins, in regimes; the model's count
// steers the sprints, so the 20-bit wrap comes within a test's time.
// - drive (1 000 ... 100 000 clocks, log-uniform): one edge every 1 ... 20 000
//   clocks (a log-uniform target, redrawn one clock in 2 000, 20 000 or
//   200 000 and reached by a ramp of 1, 16 or 256 edges; +-10 % jitter),
//   reversals (none, 1 edge in 2 000, 100, 8 or 2: dithering on an edge),
//   illegal double steps (none, 1 edge in 5 000, 200, 20), standstills of
//   10 ... 30 000 clocks (none, 1 in 50 000 or 10 000 clocks); glitches on A,
//   B or both of N-2 ... N+1 clocks around the filter length N (or 1 clock),
//   at none, 1 in 5 000, 300 or 30 clocks, and contact bounce after an edge;
// - still (1 000 ... 400 000 clocks): no motion, glitches shorter than the
//   filter, so the speed decays through the bound and stalls. The regimes
//   40, 440, 840 ... (and one still in 200) hold 8.5 M clocks at prescale 0
//   with nothing else: the period counter saturates (period_overflow) in the
//   long runs;
// - storm (66 000 ... 106 000 flips): A and B flip together every 1 ... 3
//   clocks, the filter short enough to pass them, every flip an illegal
//   transition, no phase_error clear: error_count saturates at 65 535;
// - sprint: filter 0 or 1, decode mode 0 or 3 (x4), no latch_clear, reset or
//   change of the decoding; one edge per clock in the direction of the
//   count's sign until the count is 64 edges from the wrap, then 10 000 ...
//   40 000 clocks of a walk biased towards the wrap (an edge every 1 ... 4
//   clocks), so the count crosses +2^19-1 <-> -2^19 again and again (carry,
//   borrow), with flag clears one clock in 2 000;
// - the first regimes are fixed so the default 1e6-call test sees each kind:
//   a lively drive of 30 000 clocks (the golden vectors), a storm of one
//   flip per clock, a sprint; then 80 % drive, 10 % still, 5 % storm, 5 %
//   sprint. The lively drive: window 16 ... 64, prescale 0 ... 7, a
//   switching band at 1/16 ... 1/6 edges per window clock while the edge
//   interval moves through 1 ... 200 clocks (new target one clock in 500),
//   stall 8 ... 100 ticks with standstills of 10 ... 3 000 clocks, filter
//   0 ... 3, reversals 1 edge in 50, periodic latches, decode mode or
//   reverse changed one clock in 2 000: the modes switch and stalls come
//   and go within the 20 000 golden calls;
// - controls per regime: latch_clear none, periodic (every 40 ... 10 000
//   clocks, as the odometry sequencer), random (1 in 20 ... 20 000) or bursts
//   of 1 ... 5 consecutive clocks; flag clears (all four, or one) at none,
//   1 in 50, 1 000 or 20 000 clocks; a reset at one regime start in 8 (held
//   1 ... 3 clocks) and one clock in 100 000 of drives and stills;
// - configuration: half the fields redrawn at each regime start (reverse
//   flipped at one start in 8), one field one clock in 30 000 (not the
//   decoding in sprints and storms, nothing in the long stills). Windows 0,
//   1, 2 ... 64, 65 ... 2 000, to 60 000, 50 000 or any; prescale 0, 1 ... 7,
//   8 ... 200, 49 or any; thresholds small (0 ... 64) with a band of 0 ... 16,
//   inverted, the reset pair or huge; stall 0, 1 ... 100, to 5 000, to
//   100 000, 50 000 or any; filter 0, 1, 2 ... 4, 3, 5 ... 20, 255 or any;
//   every decode mode and mode select (3 included).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string_view>
#include <vector>

#include "odoloc/rtl/eppm.hpp"
#include "odoloc/verification/reference.hpp"

namespace odoloc::verification {

namespace {

using rtl::UInt;
using Config = rtl::EppmConfig;
using In = rtl::EppmInputs;

// The kernel's inputs, in its visit_fields order, as the model's ports:
// f(name, UInt<W>&) once per column.
template <class F>
void for_each_input(In& in, Config& cfg, F&& f) {
  f("a", in.a);
  f("b", in.b);
  f("latch_clear", in.latch_clear);
  f("clear_phase_error", in.clear.status.phase_error);
  f("clear_carry", in.clear.status.carry);
  f("clear_borrow", in.clear.status.borrow);
  f("clear_period_overflow", in.clear.status.period_overflow);
  f("reset", in.reset);
  f("filter_clocks", cfg.cfg.filter_clocks);
  f("decode_mode", cfg.cfg.decode_mode);
  f("speed_mode_select", cfg.cfg.speed_mode_select);
  f("reverse", cfg.cfg.reverse);
  f("window_clocks", cfg.window.clocks);
  f("prescale_divider", cfg.prescale.divider);
  f("to_period_below", cfg.to_period_below.edges);
  f("to_pulse_at", cfg.to_pulse_at.edges);
  f("stall_ticks", cfg.stall_ticks.ticks);
}

// The kernel's outputs, in its visit_fields order, from the status the
// register file reads: f(name, value) once per column.
template <class F>
void for_each_output(const rtl::EppmStatus& s, F&& f) {
  const auto u = [](auto field) { return static_cast<std::int64_t>(field.value()); };
  f("count", s.count.value.value());
  f("latched", s.latched.value.value());
  f("speed_value", s.speed.value.value());
  f("speed_mode", u(s.speed.mode));
  f("speed_valid", u(s.speed.valid));
  f("speed_stalled", u(s.speed.stalled));
  f("speed_bound", u(s.speed.bound));
  f("pulse_last", s.pulse_last.edges.value());
  f("period_last_ticks", u(s.period_last.ticks));
  f("period_last_valid", u(s.period_last.valid));
  f("period_last_forward", u(s.period_last.forward));
  f("phase_error", u(s.status.phase_error));
  f("carry", u(s.status.carry));
  f("borrow", u(s.status.borrow));
  f("period_overflow", u(s.status.period_overflow));
  f("forward", u(s.status.forward));
  f("error_count", u(s.error_count.count));
}

template <class U>
void set(U& field, std::uint64_t value) {
  field = U::truncate(value);
}

enum class Kind { kDrive, kStill, kStorm, kSprint };
enum class Latch { kNone, kPeriodic, kRandom, kBursts };
// Which fields change mid-regime: kSpeed those the decoding does not use,
// kDecoding the decode mode and reverse only.
enum class Changes { kAny, kSpeed, kDecoding, kNone };

constexpr std::int64_t kCountLimit = std::int64_t{1} << (rtl::PositionCount::width - 1);
constexpr std::uint64_t kLongStill = 8'500'000;  // > 2^23 ticks at prescale 0

// One regime's motion, noise and control rates. "1 in N" rates: 0 = never.
struct Regime {
  Kind kind = Kind::kDrive;
  std::uint64_t left = 0;        // clocks
  double target = 100;           // edge interval the ramp heads for, clocks
  double ramp = 1;               // edges to close the gap to the target
  std::uint64_t speed_rate = 0;  // a new target
  bool fastest_only = false;     // targets up to 200 clocks
  double reversal = 0;           // per edge
  double illegal = 0;            // per edge
  std::uint64_t hold_rate = 0;   // standstills of 10 ... hold_longest clocks
  double hold_longest = 30'000;
  std::uint64_t glitch_rate = 0;
  double bounce = 0;  // per edge
  Latch latch = Latch::kNone;
  std::uint64_t latch_rate = 0;
  std::uint64_t clear_rate = 0;
  std::uint64_t reset_rate = 0;
  Changes changes = Changes::kAny;  // mid-regime configuration changes
  std::uint64_t change_rate = 30'000;
  bool phase_error_clears = true;
  std::uint64_t storm_period = 1;
  // sprint
  int sprint_sign = 1;  // counting direction, +1 up
  bool dithering = false;
};

class EppmReference final : public Reference {
 public:
  explicit EppmReference(std::uint64_t seed) : rng_(seed) {
    In in{};
    Config cfg{};
    for_each_input(in, cfg, [&](std::string_view name, auto&) { in_names_.push_back(name); });
    for_each_output(model_.status(cfg),
                    [&](std::string_view name, std::int64_t) { out_names_.push_back(name); });
  }

  [[nodiscard]] std::span<const std::string_view> input_names() const override { return in_names_; }
  [[nodiscard]] std::span<const std::string_view> output_names() const override {
    return out_names_;
  }

  void stimulus(std::span<std::int64_t> row) override {
    if (regime_.left == 0)
      start_regime();
    --regime_.left;
    In in{};
    if (reset_hold_ > 0) {
      --reset_hold_;
      in.reset = UInt<1>{1};
    } else if (chance(regime_.reset_rate)) {
      in.reset = UInt<1>{1};
    }
    if (regime_.changes != Changes::kNone && chance(regime_.change_rate))
      change_field();
    move();
    const unsigned ab = pins();
    set(in.a, ab >> 1);
    set(in.b, ab & 1U);
    set(in.latch_clear, latch_clear() ? 1 : 0);
    clear_flags(in);
    Config cfg = cfg_;
    std::size_t i = 0;
    for_each_input(in, cfg, [&](std::string_view, auto& field) {
      row[i++] = static_cast<std::int64_t>(field.value());
    });
  }

  void step(std::span<const std::int64_t> row, std::span<std::int64_t> out) override {
    In in{};
    Config cfg{};
    std::size_t i = 0;
    for_each_input(in, cfg, [&](std::string_view, auto& field) {
      set(field, static_cast<std::uint64_t>(row[i++]));
    });
    model_.step(in, cfg);
    std::size_t o = 0;
    for_each_output(model_.status(cfg), [&](std::string_view, std::int64_t v) { out[o++] = v; });
  }

 private:
  // ---- random draws ----
  std::uint64_t uniform(std::uint64_t lo, std::uint64_t hi) { return lo + rng_() % (hi - lo + 1); }
  bool chance(std::uint64_t one_in) { return one_in != 0 && rng_() % one_in == 0; }
  bool bernoulli(double p) { return p > 0 && real_(rng_) < p; }
  double log_uniform(double lo, double hi) {
    return std::exp(std::log(lo) + real_(rng_) * (std::log(hi) - std::log(lo)));
  }
  template <std::size_t N>
  std::uint64_t pick(const std::array<std::uint64_t, N>& options) {
    return options[rng_() % N];
  }
  template <std::size_t N>
  double pick(const std::array<double, N>& options) {
    return options[rng_() % N];
  }

  // ---- configuration ----
  std::uint64_t draw_filter() {
    switch (rng_() % 10) {
      case 0:
        return 0;
      case 1:
        return 1;
      case 2:
      case 3:
      case 4:
      case 5:
        return uniform(2, 4);
      case 6:
        return 3;
      case 7:
      case 8:
        return uniform(5, 20);
      default:
        return rng_() % 2 == 0 ? 255 : uniform(0, 255);
    }
  }
  std::uint64_t draw_window() {
    const std::uint64_t r = rng_() % 100;
    if (r < 3)
      return 0;
    if (r < 6)
      return 1;
    if (r < 36)
      return uniform(2, 64);
    if (r < 71)
      return uniform(65, 2'000);
    if (r < 91)
      return uniform(2'001, 60'000);
    if (r < 96)
      return 50'000;
    return uniform(0, (1U << 23) - 1);
  }
  std::uint64_t draw_prescale() {
    const std::uint64_t r = rng_() % 10;
    if (r < 2)
      return 0;
    if (r < 5)
      return uniform(1, 7);
    if (r < 8)
      return uniform(8, 200);
    if (r < 9)
      return 49;
    return uniform(0, 65'535);
  }
  std::uint64_t draw_stall() {
    const std::uint64_t r = rng_() % 20;
    if (r < 3)
      return 0;
    if (r < 7)
      return uniform(1, 100);
    if (r < 13)
      return uniform(101, 5'000);
    if (r < 17)
      return uniform(5'001, 100'000);
    if (r < 19)
      return 50'000;
    return uniform(0, (1U << 23) - 1);
  }
  // The automatic switch's band: small, so it flips often at small windows;
  // sometimes empty, inverted (to_pulse_at < to_period_below) or huge.
  void draw_thresholds() {
    const std::uint64_t r = rng_() % 20;
    std::uint64_t below = uniform(0, 64);
    std::uint64_t at = below + uniform(0, 16);
    if (r == 0) {
      at = uniform(0, below);
    } else if (r == 1) {
      below = uniform(1U << 20, (1U << 23) - 1);
      at = uniform(0, (1U << 23) - 1);
    } else if (r == 2) {
      below = 25;
      at = 40;
    }
    set(cfg_.to_period_below.edges, below);
    set(cfg_.to_pulse_at.edges, at);
  }
  // Field f (0 ... 8) redrawn; fields 0 ... 2 change the decoding, not only the speed.
  void draw_field(std::uint64_t f) {
    switch (f) {
      case 0:
        set(cfg_.cfg.filter_clocks, draw_filter());
        break;
      case 1:
        set(cfg_.cfg.decode_mode, rng_() % 2 == 0 ? 0 : uniform(0, 3));
        break;
      case 2:
        cfg_.cfg.reverse = ~cfg_.cfg.reverse;
        break;
      case 3:
        set(cfg_.cfg.speed_mode_select, rng_() % 2 == 0 ? 0 : uniform(0, 3));
        break;
      case 4:
        set(cfg_.window.clocks, draw_window());
        break;
      case 5:
        set(cfg_.prescale.divider, draw_prescale());
        break;
      case 6:
      case 7:
        draw_thresholds();
        break;
      default:
        set(cfg_.stall_ticks.ticks, draw_stall());
        break;
    }
  }
  // Small windows and prescalers, and a band at 1/16 ... 1/6 edges per
  // window clock, so the modes switch often while the edge interval moves
  // through 1 ... 200 clocks: what sprints and the golden vectors use.
  void lively_speed_config() {
    const std::uint64_t window = uniform(16, 64);
    set(cfg_.window.clocks, window);
    set(cfg_.prescale.divider, uniform(0, 7));
    set(cfg_.to_period_below.edges, uniform(window / 16, window / 6));
    set(cfg_.to_pulse_at.edges, cfg_.to_period_below.edges.value() + uniform(0, 4));
    set(cfg_.stall_ticks.ticks, uniform(8, 100));
    set(cfg_.cfg.speed_mode_select, rng_() % 4 == 0 ? uniform(1, 3) : 0);
  }

  void change_field() {
    switch (regime_.changes) {
      case Changes::kAny:
        draw_field(uniform(0, 8));
        break;
      case Changes::kSpeed:
        draw_field(uniform(3, 8));
        break;
      case Changes::kDecoding:
        if (rng_() % 4 == 0)
          draw_field(2);
        else
          set(cfg_.cfg.decode_mode, uniform(0, 3));
        break;
      case Changes::kNone:
        break;
    }
  }

  // ---- regimes ----
  void start_regime() {
    const std::uint64_t index = regimes_++;
    if (chance(8))
      reset_hold_ = uniform(1, 3);
    for (std::uint64_t f = 0; f < 9; ++f) {
      if (f == 2 ? rng_() % 8 == 0 : rng_() % 2 == 0)  // reverse flips one regime in 8
        draw_field(f);
    }
    Kind kind = Kind::kDrive;
    if (index == 1)
      kind = Kind::kStorm;
    else if (index == 2)
      kind = Kind::kSprint;
    else if (index % 400 == 40)
      kind = Kind::kStill;
    else if (index > 2) {
      const std::uint64_t r = rng_() % 100;
      kind = r < 80 ? Kind::kDrive : r < 90 ? Kind::kStill : r < 95 ? Kind::kStorm : Kind::kSprint;
    }
    regime_ = Regime{};
    regime_.kind = kind;
    regime_.latch = static_cast<Latch>(rng_() % 4);
    regime_.latch_rate = regime_.latch == Latch::kPeriodic ? uniform(40, 10'000)
                         : regime_.latch == Latch::kRandom ? uniform(20, 20'000)
                                                           : 2'000;
    regime_.clear_rate = pick(std::array<std::uint64_t, 4>{0, 50, 1'000, 20'000});
    switch (kind) {
      case Kind::kDrive:
        start_drive(index == 0);
        break;
      case Kind::kStill:
        start_still(index % 400 == 40 || chance(200));
        break;
      case Kind::kStorm:
        start_storm(index == 1);
        break;
      case Kind::kSprint:
        start_sprint();
        break;
    }
  }
  void start_drive(bool lively) {
    Regime& g = regime_;
    g.left = static_cast<std::uint64_t>(log_uniform(1'000, 100'000));
    g.target = log_uniform(1, 20'000);
    g.ramp = pick(std::array<double, 3>{1, 16, 256});
    g.reversal = pick(std::array<double, 5>{0, 1.0 / 2'000, 1.0 / 100, 1.0 / 8, 1.0 / 2});
    g.illegal = pick(std::array<double, 4>{0, 1.0 / 5'000, 1.0 / 200, 1.0 / 20});
    g.hold_rate = pick(std::array<std::uint64_t, 3>{0, 50'000, 10'000});
    g.glitch_rate = pick(std::array<std::uint64_t, 4>{0, 5'000, 300, 30});
    g.bounce = pick(std::array<double, 3>{0, 1.0 / 50, 1.0 / 4});
    g.reset_rate = 100'000;
    g.speed_rate = pick(std::array<std::uint64_t, 3>{2'000, 20'000, 200'000});
    if (lively) {  // the golden vectors: everything moves within 20 000 calls
      lively_speed_config();
      set(cfg_.cfg.speed_mode_select, 0);
      set(cfg_.cfg.filter_clocks, uniform(0, 3));
      g.left = 30'000;
      g.target = log_uniform(1, 200);
      g.speed_rate = 500;
      g.fastest_only = true;
      g.ramp = pick(std::array<double, 3>{1, 4, 16});
      g.change_rate = 2'000;
      g.changes = Changes::kDecoding;
      set(cfg_.cfg.decode_mode, uniform(0, 3));
      g.hold_rate = 3'000;
      g.hold_longest = 3'000;
      g.reversal = 1.0 / 50;
      g.illegal = 1.0 / 500;
      g.glitch_rate = 300;
      g.bounce = 1.0 / 50;
      g.latch = Latch::kPeriodic;
      g.latch_rate = uniform(200, 1'000);
      g.clear_rate = 1'000;
    }
  }
  void start_still(bool long_still) {
    Regime& g = regime_;
    g.left = static_cast<std::uint64_t>(log_uniform(1'000, 400'000));
    g.glitch_rate = pick(std::array<std::uint64_t, 3>{0, 5'000, 300});
    g.reset_rate = 100'000;
    if (long_still) {  // the period counter saturates: nothing may restart it
      set(cfg_.prescale.divider, 0);
      g.left = kLongStill + uniform(0, 200'000);
      g.glitch_rate = 0;
      g.reset_rate = 0;
      g.changes = Changes::kNone;
      reset_hold_ = 0;
    }
  }
  void start_storm(bool first) {
    Regime& g = regime_;
    g.storm_period = rng_() % 4 == 0 && !first ? uniform(2, 3) : 1;
    set(cfg_.cfg.filter_clocks, uniform(0, g.storm_period));
    g.left = (66'000 + uniform(0, 40'000)) * g.storm_period;
    g.phase_error_clears = false;
    g.changes = Changes::kSpeed;
    storm_phase_ = 0;
  }
  void start_sprint() {
    Regime& g = regime_;
    set(cfg_.cfg.filter_clocks, uniform(0, 1));
    set(cfg_.cfg.decode_mode, rng_() % 4 == 0 ? 3 : 0);
    lively_speed_config();
    const std::int64_t count = model_.count().value();
    g.sprint_sign = count > 0 ? 1 : count < 0 ? -1 : rng_() % 2 == 0 ? 1 : -1;
    g.left = 2'000'000;  // ended by the walk
    g.illegal = 1.0 / 20'000;
    g.latch = Latch::kNone;
    g.clear_rate = 2'000;
    g.changes = Changes::kSpeed;
    reset_hold_ = 0;
    hold_ = 0;
  }

  // ---- the wheel and the pins ----
  // The counting direction (+1 up) as the pins' direction: reverse exchanges
  // A and B at the input.
  int physical(int counting) const { return cfg_.cfg.reverse.value() != 0 ? -counting : counting; }

  // A and B of a phase of the forward cycle AB = 00, 10, 11, 01.
  static unsigned ab_of(int phase) {
    const unsigned a = phase == 1 || phase == 2 ? 1U : 0U;
    const unsigned b = phase >= 2 ? 1U : 0U;
    return a << 1 | b;
  }
  void edge(int direction, bool may_be_illegal) {
    const int steps = may_be_illegal && bernoulli(regime_.illegal) ? 2 : 1;
    const unsigned before = ab_of(phase_);
    phase_ = (phase_ + 4 + direction * steps) % 4;
    if (bernoulli(regime_.bounce)) {  // a line that changed bounces back briefly
      const unsigned changed = before ^ ab_of(phase_);
      glitch_[(changed & 1U) != 0 ? 0 : 1] = uniform(1, filter_length() + 1);
    }
  }
  std::uint64_t filter_length() const {
    return std::max<std::uint64_t>(cfg_.cfg.filter_clocks.value(), 1);
  }

  void move() {
    Regime& g = regime_;
    if (chance(g.speed_rate))
      g.target = log_uniform(1, g.fastest_only ? 200 : 20'000);
    switch (g.kind) {
      case Kind::kStorm:
        if (++storm_phase_ >= g.storm_period) {
          storm_phase_ = 0;
          phase_ = (phase_ + 2) % 4;
        }
        return;
      case Kind::kSprint:
        sprint();
        return;
      case Kind::kStill:
        noise();
        return;
      case Kind::kDrive:
        break;
    }
    noise();
    if (hold_ > 0) {
      --hold_;
      return;
    }
    if (chance(g.hold_rate)) {
      hold_ = static_cast<std::uint64_t>(log_uniform(10, g.hold_longest));
      return;
    }
    if (countdown_ > 1) {
      --countdown_;
      return;
    }
    if (bernoulli(g.reversal))
      direction_ = -direction_;
    edge(direction_, true);
    interval_ += (g.target - interval_) / g.ramp;
    const double jitter = 0.9 + 0.2 * real_(rng_);
    countdown_ = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(interval_ * jitter + 0.5));
  }

  // Glitches on A, B or both, of N-2 ... N+1 clocks (or 1); in a still only
  // shorter than the filter, so nothing moves.
  void noise() {
    if (!chance(regime_.glitch_rate))
      return;
    const std::uint64_t n = filter_length();
    std::uint64_t length = rng_() % 8 == 0 ? 1 : uniform(n > 2 ? n - 2 : 1, n + 1);
    if (regime_.kind == Kind::kStill) {
      if (n < 2)
        return;
      length = std::min(length, n - 1);
    }
    const std::uint64_t lines = uniform(1, 3);  // bit 0: B, bit 1: A
    for (std::size_t line = 0; line < 2; ++line) {
      if ((lines >> line & 1U) != 0)
        glitch_[line] = length;
    }
  }

  // Up to 64 edges before the wrap at one edge per clock, then a walk biased
  // towards the wrap point, crossing it again and again.
  void sprint() {
    Regime& g = regime_;
    const std::int64_t count = model_.count().value();
    if (!g.dithering && count * g.sprint_sign >= kCountLimit - 64) {
      g.dithering = true;
      g.left = uniform(10'000, 40'000);
    }
    if (countdown_ > 1) {
      --countdown_;
      return;
    }
    int counting = g.sprint_sign;
    countdown_ = 1;
    if (g.dithering) {
      const int towards = count * g.sprint_sign > 0 ? g.sprint_sign : -g.sprint_sign;
      counting = rng_() % 100 < 65 ? towards : -towards;
      countdown_ = uniform(1, 4);
    }
    edge(physical(counting), true);
  }

  // A and B from the wheel's phase (forward AB = 00, 10, 11, 01), each
  // inverted while a glitch runs on it.
  unsigned pins() {
    unsigned ab = ab_of(phase_);
    for (std::size_t line = 0; line < 2; ++line) {
      if (glitch_[line] > 0) {
        --glitch_[line];
        ab ^= 1U << line;
      }
    }
    return ab;
  }

  // ---- controls ----
  bool latch_clear() {
    switch (regime_.latch) {
      case Latch::kNone:
        return false;
      case Latch::kPeriodic:
        return ++latch_phase_ % regime_.latch_rate == 0;
      case Latch::kRandom:
        return chance(regime_.latch_rate);
      case Latch::kBursts:
        if (burst_ > 0) {
          --burst_;
          return true;
        }
        if (chance(regime_.latch_rate)) {
          burst_ = uniform(0, 4);
          return true;
        }
        return false;
    }
    return false;
  }
  void clear_flags(In& in) {
    if (!chance(regime_.clear_rate))
      return;
    auto& c = in.clear.status;
    const std::uint64_t which = rng_() % 5;
    if (which == 0 || which == 1)
      c.phase_error = UInt<1>{1};
    if (which == 0 || which == 2)
      c.carry = UInt<1>{1};
    if (which == 0 || which == 3)
      c.borrow = UInt<1>{1};
    if (which == 0 || which == 4)
      c.period_overflow = UInt<1>{1};
    if (!regime_.phase_error_clears)
      c.phase_error = UInt<1>{};
  }

  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> real_{0.0, 1.0};
  std::vector<std::string_view> in_names_, out_names_;
  rtl::Eppm model_;
  Config cfg_{};
  Regime regime_;
  std::uint64_t regimes_ = 0;
  std::uint64_t reset_hold_ = 0;
  // the wheel
  int phase_ = 0;      // 0 ... 3 in the forward cycle
  int direction_ = 1;  // of the pins, +1 forward
  double interval_ = 100;
  std::uint64_t countdown_ = 1;
  std::uint64_t hold_ = 0;
  std::array<std::uint64_t, 2> glitch_{};  // clocks left inverted: [0] B, [1] A
  std::uint64_t storm_phase_ = 0;
  std::uint64_t latch_phase_ = 0;
  std::uint64_t burst_ = 0;
};

}  // namespace

std::unique_ptr<Reference> make_eppm_reference(std::uint64_t seed) {
  return std::make_unique<EppmReference>(seed);
}

}  // namespace odoloc::verification
