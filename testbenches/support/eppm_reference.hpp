// An untimed reference of what one EPPM must report, written from
// docs/eppm.md alone (not from the model's pipeline): pin runs per channel ->
// filtered-level change events -> quadrature transitions -> the count and
// flags after each step, sums per window, tick counts per edge interval.
//
//   const auto exp = odoloc::tb::expect_eppm(pins, latch_steps, clear_steps, cfg);
//   // after step k: exp.after[k].count, exp.speed_after(k), ...
//
// Scope: one run from reset with a constant configuration and no reset strobe;
// pins[k] is the A/B level (A in bit 1) applied at step k.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <vector>

#include "odoloc/rtl/eppm.hpp"

namespace odoloc::tb {

// The configuration as plain numbers, with the documented "0 behaves as 1" rules.
struct EppmRefConfig {
  explicit EppmRefConfig(const rtl::EppmConfig& c)
      : filter_len(std::max<std::uint64_t>(c.cfg.filter_clocks.value(), 1)),
        decode_mode(c.cfg.decode_mode.value()),
        select(c.cfg.speed_mode_select.value()),
        window(std::max<std::uint64_t>(c.window.clocks.value(), 1)),
        tick_every(c.prescale.divider.value() + 1),
        to_period_below(c.to_period_below.edges.value()),
        to_pulse_at(c.to_pulse_at.edges.value()),
        stall_ticks(c.stall_ticks.ticks.value()) {}
  std::uint64_t filter_len;  // N
  std::uint64_t decode_mode;
  std::uint64_t select;
  std::uint64_t window;  // W
  std::uint64_t tick_every;
  std::uint64_t to_period_below, to_pulse_at, stall_ticks;
};

// Steps after which a channel's filtered level has just changed. The filter
// takes a run of the other level once it lasts N samples; the run's first
// sample reaches the filter two clocks late (synchroniser), so its N-th sample
// is filtered after step run_start + N + 1. Before step 0 the pins read 0
// (the synchronisers reset low).
inline std::vector<std::uint64_t> filtered_changes(const std::vector<std::uint8_t>& pins,
                                                   unsigned bit, std::uint64_t filter_len) {
  std::vector<std::uint64_t> changes;
  unsigned filtered = 0;
  const auto level = [&](std::size_t k) { return (pins[k] >> bit) & 1U; };
  std::size_t run_start = 0;
  for (std::size_t k = 1; k <= pins.size(); ++k) {
    if (k < pins.size() && level(k) == level(run_start))
      continue;
    if (level(run_start) != filtered && k - run_start >= filter_len) {
      filtered ^= 1U;
      changes.push_back(run_start + filter_len + 1);
    }
    run_start = k;
  }
  return changes;
}

enum class Motion : std::uint8_t { kForward, kBackward, kIllegal };

// Forward is A leading B: AB = 00 -> 10 -> 11 -> 01 -> 00; both bits changed is illegal.
inline Motion classify(unsigned prev, unsigned curr) {
  constexpr std::array<unsigned, 4> kForwardFrom = {0b10, 0b00, 0b11, 0b01};  // index: prev AB
  if ((prev ^ curr) == 0b11)
    return Motion::kIllegal;
  return kForwardFrom[prev] == curr ? Motion::kForward : Motion::kBackward;
}

// x4 counts every legal step, x2 the steps of A, x1 only 00 <-> 10.
inline bool counted(unsigned prev, unsigned curr, std::uint64_t decode_mode) {
  const bool a_edge = ((prev ^ curr) & 0b10) != 0;
  switch (decode_mode) {
    case 1:
      return a_edge;
    case 2:
      return a_edge && ((prev | curr) & 0b01) == 0;
    default:
      return true;
  }
}

// A change of the filtered A/B pair as the counter and the meters see it:
// one clock after the filtered change (the decoder compares with its `prev`).
struct Transition {
  std::uint64_t step;
  Motion motion;
  bool counted;
};

inline std::vector<Transition> transitions(const std::vector<std::uint8_t>& pins,
                                           const EppmRefConfig& cfg) {
  const auto a = filtered_changes(pins, 1, cfg.filter_len);
  const auto b = filtered_changes(pins, 0, cfg.filter_len);
  constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max();
  std::vector<Transition> out;
  unsigned ab = 0;
  for (std::size_t i = 0, j = 0; i < a.size() || j < b.size();) {
    const std::uint64_t step = std::min(i < a.size() ? a[i] : kNone, j < b.size() ? b[j] : kNone);
    unsigned next = ab;
    if (i < a.size() && a[i] == step) {
      next ^= 0b10U;
      ++i;
    }
    if (j < b.size() && b[j] == step) {
      next ^= 0b01U;
      ++j;
    }
    if (step + 1 >= pins.size())
      break;  // seen after the last recorded step
    const Motion motion = classify(ab, next);
    out.push_back(
        {step + 1, motion, motion != Motion::kIllegal && counted(ab, next, cfg.decode_mode)});
    ab = next;
  }
  return out;
}

// Reference ticks (at steps j with (j+1) % (prescale+1) == 0) among steps [from, to).
inline std::uint64_t ticks_in(std::uint64_t from, std::uint64_t to, std::uint64_t tick_every) {
  return to / tick_every - from / tick_every;
}

inline std::int32_t wrap_s20(std::int64_t v) {
  constexpr std::int64_t kSpan = std::int64_t{1} << 20;
  const std::int64_t low = ((v % kSpan) + kSpan) % kSpan;
  return static_cast<std::int32_t>(low >= kSpan / 2 ? low - kSpan : low);
}

// The counter and decoder registers after one step.
struct CounterState {
  std::int32_t count = 0;
  std::uint16_t error_count = 0;
  bool phase_error = false, carry = false, borrow = false;
  bool forward = false;  // direction of the last legal transition (reset: 0)
};
struct PulseSample {
  std::int64_t edges;  // net signed edges of the window
  bool pulse_mode;     // the mode bit decided at this window's end
};
struct PeriodSample {
  std::uint64_t step;   // the edge's step (`period.sampled` after it)
  std::uint64_t ticks;  // ticks in [previous edge (or reset), this edge), saturated
  bool valid;
  bool forward;
};
struct SpeedWord {
  std::int64_t value;
  bool pulse_mode, valid, stalled;
  bool bound = false;
};

struct EppmExpected {
  static constexpr std::uint64_t kMaxTicks = (std::uint64_t{1} << 23) - 1;

  explicit EppmExpected(const EppmRefConfig& c) : cfg(c) {}
  EppmRefConfig cfg;
  std::vector<CounterState> after;    // after each step
  std::vector<std::int32_t> latched;  // one per latch_clear, in order
  std::vector<PulseSample> windows;   // window j covers steps [jW, (j+1)W-1]
  std::vector<PeriodSample> edges;    // one per counted edge

  // The speed word after `step` (docs/eppm.md, "Speed meter").
  [[nodiscard]] SpeedWord speed_after(std::uint64_t step) const {
    const std::uint64_t done_windows = (step + 1) / cfg.window;
    const bool pulse_mode = done_windows > 0 && windows[done_windows - 1].pulse_mode;
    const auto next_edge =
        std::upper_bound(edges.begin(), edges.end(), step,
                         [](std::uint64_t s, const PeriodSample& e) { return s < e.step; });
    const PeriodSample* last = next_edge == edges.begin() ? nullptr : &*std::prev(next_edge);
    const std::uint64_t since = last != nullptr ? last->step : 0;
    const std::uint64_t ticks = std::min(ticks_in(since, step + 1, cfg.tick_every), kMaxTicks);
    if (cfg.stall_ticks != 0 && ticks >= cfg.stall_ticks)
      return {0, pulse_mode, true, true};
    if (pulse_mode)
      return {windows[done_windows - 1].edges, true, true, false};
    if (last == nullptr || !last->valid)
      return {0, false, false, false};
    // Period mode: the last period, bounded below by the open period (the
    // wheel has been slower than that since) and by one tick.
    const std::uint64_t bounded = std::max<std::uint64_t>({last->ticks, ticks, 1});
    const auto magnitude = static_cast<std::int64_t>(bounded);
    return {last->forward ? magnitude : -magnitude, false, true, false, bounded != last->ticks};
  }
};

// latch_steps and clear_steps: the steps carrying latch_clear / clear_flags, ascending.
inline EppmExpected expect_eppm(const std::vector<std::uint8_t>& pins,
                                const std::vector<std::uint64_t>& latch_steps,
                                const std::vector<std::uint64_t>& clear_steps,
                                const rtl::EppmConfig& config) {
  const EppmRefConfig cfg(config);
  EppmExpected exp(cfg);
  const auto moves = transitions(pins, cfg);

  // Counter and flags. latch_clear: the clearing clock's edge goes into
  // `latched`; clear_flags: an event in the clearing clock sets its flag again.
  exp.after.resize(pins.size());
  CounterState now;
  auto move = moves.begin();
  auto latch = latch_steps.begin();
  auto clear = clear_steps.begin();
  for (std::uint64_t k = 0; k < pins.size(); ++k) {
    if (clear != clear_steps.end() && *clear == k) {
      now.error_count = 0;
      now.phase_error = now.carry = now.borrow = false;
      ++clear;
    }
    for (; move != moves.end() && move->step == k; ++move) {
      if (move->motion == Motion::kIllegal) {
        now.error_count = static_cast<std::uint16_t>(std::min(now.error_count + 1, 65535));
        now.phase_error = true;
        continue;
      }
      now.forward = move->motion == Motion::kForward;
      if (!move->counted)
        continue;
      if (now.forward && now.count == (1 << 19) - 1)
        now.carry = true;
      if (!now.forward && now.count == -(1 << 19))
        now.borrow = true;
      now.count = wrap_s20(now.count + (now.forward ? 1 : -1));
    }
    if (latch != latch_steps.end() && *latch == k) {
      exp.latched.push_back(now.count);
      now.count = 0;
      ++latch;
    }
    exp.after[k] = now;
  }

  // Pulse windows, and the mode decided at each window end.
  exp.windows.resize(pins.size() / cfg.window);
  for (const Transition& t : moves) {
    const std::uint64_t w = t.step / cfg.window;
    if (t.counted && w < exp.windows.size()) {
      exp.windows[w].edges += t.motion == Motion::kForward ? 1 : -1;
    }
  }
  bool pulse_mode = false;  // reset: period
  for (PulseSample& w : exp.windows) {
    const auto magnitude = static_cast<std::uint64_t>(w.edges < 0 ? -w.edges : w.edges);
    if (cfg.select == 1) {
      pulse_mode = true;
    } else if (cfg.select == 2) {
      pulse_mode = false;
    } else if (pulse_mode) {
      pulse_mode = magnitude >= cfg.to_period_below;  // hysteresis band keeps the mode
    } else {
      pulse_mode = magnitude >= cfg.to_pulse_at;
    }
    w.pulse_mode = pulse_mode;
  }

  // Period samples: ticks since the previous edge; invalid on the first edge,
  // across a reversal, after a stall, or when the count saturated (a bound).
  for (const Transition& t : moves) {
    if (!t.counted)
      continue;
    const PeriodSample* previous = exp.edges.empty() ? nullptr : &exp.edges.back();
    const std::uint64_t since = previous != nullptr ? previous->step : 0;
    const std::uint64_t ticks =
        std::min(ticks_in(since, t.step, cfg.tick_every), EppmExpected::kMaxTicks);
    const bool forward = t.motion == Motion::kForward;
    const bool stalled = cfg.stall_ticks != 0 && ticks >= cfg.stall_ticks;
    const bool valid = previous != nullptr && previous->forward == forward && !stalled &&
                       ticks != EppmExpected::kMaxTicks;
    exp.edges.push_back({t.step, ticks, valid, forward});
  }
  return exp;
}

}  // namespace odoloc::tb
