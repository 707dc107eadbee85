// rtl::TofCapture<> (the chip's unit: 8 channels, 16-entry FIFOs) behind the
// TOF capture kernel's ports (hls/tof_kernel.hpp).
//
// Stimulus, in regimes of 1 000 ... 100 000 clocks (log-uniform); each regime
// draws its command and read rates and redraws about half the configuration:
// - pins (8 comparators and sync), each a sequence of bursts: envelope pulses
//   (35 % of 1 ... 4 filter lengths, 58 % of 5 ... 300 clocks, 7 % up to
//   20 000, 1 in 5 000 up to 2^21; after the first 2^21 calls 3 in 10^5 of
//   3 ... 4 epochs, 2^25 clocks: the width saturates), pulses with a dropout
//   around the filter length,
//   carrier bursts (half period 1 ... 16 clocks, 1 ... 40 cycles), glitches
//   of N-2 ... N+1 clocks around the filter length N, and chatter (toggles
//   every 1 ... 3 clocks); gaps of 1 ... 50 clocks (echoes, an echo arriving
//   while the channel is done, disarmed, full or outside its window), up to
//   500 and up to 5 000. One clock in 4 000 a burst reaches every channel
//   with 1 ... 12 clocks of spread (Kleeman's octagon), with a sync pulse (the
//   RF trigger);
// - arm / disarm / flush: all channels, one, or a random mask, at a regime's
//   rates (1 in 100 ... 10 000 clocks; disarm 3x, flush 4x rarer), in the
//   same clock too (disarm wins), arming armed and done channels;
//   sync_flush; overflow clears per channel and for sync, and clear_all;
// - read frames as the register file makes them: a snapshot, 3 ... 60 clocks
//   later the pops of one FIFO, mostly one that holds entries (the SoC's
//   min(snapshot level, 8); or 0 ... 8; or 9 ... 15, more than the frame saw;
//   or none: an aborted frame), sometimes pops on a second FIFO in the same
//   clock; a new snapshot during a frame; pops without a frame; regimes with
//   a frame every 10, 50, 300 or 3 000 clocks or none (full FIFOs, drops);
// - configuration: prescale (70 % 0; 1 ... 3, 4 ... 200, any 16-bit value),
//   filter_clocks (0 or 1, 3, 2 ... 4, 5 ... 20, 21 ... 60, 255, any),
//   sync_enable (3 in 4: sync pulses with the input enabled and disabled);
//   per channel the mode, K (0 = no limit, 1 ... 16, 255, any) and the
//   window (enabled 1 in 3): around the current timestamp, a few ticks wide
//   and opening soon, empty, spanning the 2^32 wrap, or any; one field also
//   changes mid-regime once in 30 000 clocks;
// - resets (held 1 ... 3 clocks, with whatever strobes those clocks carry):
//   in the first 2^21 calls at one regime start in 16 and once in 500 000
//   clocks anywhere; later at one regime start in 4 096 only, so that the
//   timestamp of a long run passes epochs (2^23 ticks) and pulses of 3 ... 4
//   epochs saturate their width;
// - one regime in 150 is a storm: filter 0 or 1, every pin a continuous
//   carrier of half period 1 ... 3, every channel armed with no edge limit,
//   windows empty on some, no reads, flushes or resets for 140 000 ...
//   300 000 clocks, so events.ignored and events.dropped (2^16 - 1) and the
//   edge count (255, index 127) saturate.
// The timestamp reaches an epoch only in long runs and never its 2^32 wrap:
// test_hls_tof presets kernel and model there, and near every counter's
// saturation.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "odoloc/ports.hpp"
#include "odoloc/rtl/tof_capture.hpp"
#include "odoloc/verification/reference.hpp"

namespace odoloc::verification {

namespace {

using rtl::UInt;
using Unit = rtl::TofCapture<>;
constexpr int kChannels = static_cast<int>(Unit::kChannels);
constexpr int kWindow = rtl::tof_capture::kWindow;
constexpr int kSyncPin = kChannels;  // pins_[kSyncPin] drives the sync input

// A port's column name: a + index i + b + index k + c, an index < 0 left out
// ("rx3_pops", "rx3_entry5_ticks", "sync_entry5_ticks"), as the kernel names them.
struct Column {
  std::string_view a;
  int i = -1;
  std::string_view b{};
  int k = -1;
  std::string_view c{};
};

std::string column_name(const Column& c) {
  std::string name(c.a);
  if (c.i >= 0)
    name += std::to_string(c.i);
  name += c.b;
  if (c.k >= 0)
    name += std::to_string(c.k);
  name += c.c;
  return name;
}

// The kernel's inputs, in its visit_fields order, as the model's ports:
// f(Column, UInt<W>&) once per column.
template <class F>
void for_each_input(Unit::In& in, ports::Config& cfg, F&& f) {
  f(Column{"comparators"}, in.comparators);
  f(Column{"sync"}, in.sync);
  f(Column{"arm"}, in.tof.command.arm);
  f(Column{"disarm"}, in.tof.command.disarm);
  f(Column{"flush"}, in.tof.command.flush);
  f(Column{"sync_flush"}, in.tof.command.sync_flush);
  f(Column{"sync_overflow_clear"}, in.tof.sync_status.overflow);
  f(Column{"sync_pops"}, in.tof.sync_entry.pops);
  for (int i = 0; i < kChannels; ++i) {
    auto& pulses = in.channel[static_cast<std::size_t>(i)];
    f(Column{"rx", i, "_overflow_clear"}, pulses.status.overflow);
    f(Column{"rx", i, "_pops"}, pulses.entry.pops);
  }
  f(Column{"snapshot"}, in.snapshot);
  f(Column{"clear_all"}, in.clear_all);
  f(Column{"reset"}, in.reset);
  f(Column{"prescale"}, cfg.tof.cfg.prescale);
  f(Column{"filter_clocks"}, cfg.tof.cfg.filter_clocks);
  f(Column{"sync_enable"}, cfg.tof.cfg.sync_enable);
  for (int i = 0; i < kChannels; ++i) {
    auto& c = cfg.tof_channel[static_cast<std::size_t>(i)];
    f(Column{"rx", i, "_mode"}, c.cfg.mode);
    f(Column{"rx", i, "_window_enable"}, c.cfg.window_enable);
    f(Column{"rx", i, "_edges"}, c.cfg.edges);
    f(Column{"rx", i, "_window_open"}, c.window_open.ticks);
    f(Column{"rx", i, "_window_close"}, c.window_close.ticks);
  }
}

// The kernel's outputs, in its visit_fields order, from the status the
// register file reads: f(Column, value) once per column.
template <class F>
void for_each_output(const ports::Status& s, F&& f) {
  f(Column{"fifo_depth"}, s.tof.info.fifo_depth.value());
  f(Column{"channels"}, s.tof.info.channels.value());
  f(Column{"timestamp"}, s.tof.timestamp.ticks.value());
  f(Column{"sync_fill_level"}, s.tof.sync_status.fill_level.value());
  f(Column{"sync_overflow"}, s.tof.sync_status.overflow.value());
  f(Column{"sync_dropped"}, s.tof.sync_status.dropped.value());
  for (int k = 0; k < kWindow; ++k)
    f(Column{"sync_entry", k, "_ticks"},
      s.tof.sync_entry[static_cast<std::size_t>(k)].ticks.value());
  for (int i = 0; i < kChannels; ++i) {
    const auto& c = s.tof_channel[static_cast<std::size_t>(i)];
    f(Column{"rx", i, "_fill_level"}, c.status.fill_level.value());
    f(Column{"rx", i, "_not_empty"}, c.status.not_empty.value());
    f(Column{"rx", i, "_in_progress"}, c.status.in_progress.value());
    f(Column{"rx", i, "_armed"}, c.status.armed.value());
    f(Column{"rx", i, "_done"}, c.status.done.value());
    f(Column{"rx", i, "_overflow"}, c.status.overflow.value());
    f(Column{"rx", i, "_dropped"}, c.events.dropped.value());
    f(Column{"rx", i, "_ignored"}, c.events.ignored.value());
    for (int k = 0; k < kWindow; ++k) {
      const auto& e = c.entry[static_cast<std::size_t>(k)];
      f(Column{"rx", i, "_entry", k, "_ticks"}, e.ticks.value());
      f(Column{"rx", i, "_entry", k, "_width"}, e.width.value());
      f(Column{"rx", i, "_entry", k, "_edge_index"}, e.edge_index.value());
      f(Column{"rx", i, "_entry", k, "_valid"}, e.valid.value());
    }
  }
}

template <class U>
void set(U& field, std::uint64_t value) {
  field = U::truncate(value);
}

// What a pin does next: a high segment of `first` clocks, then `toggles`
// level changes every `half` clocks (0: every 1 ... 3, chatter).
struct Burst {
  std::uint64_t first = 1;
  std::uint64_t half = 0;
  int toggles = 0;
};

struct Pin {
  bool level = false;
  std::uint64_t hold = 1;  // clocks left at this level
  std::uint64_t half = 0;
  int toggles = 0;
  bool pending = false;  // `next` starts when `hold` runs out
  Burst next;
};

// One regime's rates: one event in N clocks (0: never).
struct Regime {
  std::uint64_t left = 0;
  std::uint64_t arm = 0, disarm = 0, flush = 0, clear = 0, read = 0;
  bool storm = false;
};

// A read frame in progress: its snapshot was taken, its pops are due.
struct Frame {
  bool active = false;
  std::uint64_t left = 0;
  int target = 0;  // a channel, or kSyncPin for the sync FIFO
};

class TofReference final : public Reference {
 public:
  explicit TofReference(std::uint64_t seed) : rng_(seed) {
    model_.reset_now();
    Unit::In in{};
    ports::Config cfg{};
    for_each_input(in, cfg, [&](const Column& c, auto&) { in_text_.push_back(column_name(c)); });
    for_each_output(status_,
                    [&](const Column& c, std::uint64_t) { out_text_.push_back(column_name(c)); });
    in_names_.assign(in_text_.begin(), in_text_.end());
    out_names_.assign(out_text_.begin(), out_text_.end());
  }

  [[nodiscard]] std::span<const std::string_view> input_names() const override { return in_names_; }
  [[nodiscard]] std::span<const std::string_view> output_names() const override {
    return out_names_;
  }

  void stimulus(std::span<std::int64_t> row) override {
    Unit::In in{};
    if (regime_.left == 0)
      start_regime(in);
    --regime_.left;
    if (!regime_.storm) {
      commands(in);
      read_frames(in);
      if (one_in(30000))
        change_config(rng_() % 4);
      if (early() && one_in(500000))
        reset_clocks_ = 1 + rng_() % 3;
    }
    ++calls_;
    if (reset_clocks_ > 0) {
      --reset_clocks_;
      in.reset = UInt<1>{1};
    }
    if (one_in(4000))
      broadcast();
    std::uint64_t comparators = 0;
    for (int i = 0; i < kChannels; ++i)
      comparators |= std::uint64_t{advance(pins_[static_cast<std::size_t>(i)])} << i;
    set(in.comparators, comparators);
    set(in.sync, advance(pins_[kSyncPin]) ? 1 : 0);
    std::size_t at = 0;
    for_each_input(in, cfg_, [&](const Column&, auto& field) {
      row[at++] = static_cast<std::int64_t>(field.value());
    });
  }

  void step(std::span<const std::int64_t> row, std::span<std::int64_t> out) override {
    Unit::In in{};
    ports::Config cfg{};
    std::size_t at = 0;
    for_each_input(in, cfg, [&](const Column&, auto& field) {
      set(field, static_cast<std::uint64_t>(row[at++]));
    });
    model_.step(in, cfg);
    status_.tof = {};  // status() writes the entries below the fill level only
    status_.tof_channel = {};
    model_.status(status_);
    at = 0;
    for_each_output(status_, [&](const Column&, std::uint64_t value) {
      out[at++] = static_cast<std::int64_t>(value);
    });
  }

 private:
  bool one_in(std::uint64_t n) { return n != 0 && rng_() % n == 0; }
  // The first 2^21 calls (golden vectors, default tests) reset often; later
  // ones rarely, so that long runs see epochs and saturated widths.
  [[nodiscard]] bool early() const { return calls_ < (std::uint64_t{1} << 21); }
  std::uint64_t between(std::uint64_t lo, std::uint64_t hi) { return lo + rng_() % (hi - lo + 1); }
  // Uniform in the logarithm: as many short values as long ones.
  std::uint64_t log_between(std::uint64_t lo, std::uint64_t hi) {
    const std::uint64_t top = between(std::bit_width(lo), std::bit_width(hi));
    return std::clamp(between(std::uint64_t{1} << (top - 1), (std::uint64_t{1} << top) - 1), lo,
                      hi);
  }
  std::uint64_t filter() const {
    return std::max<std::uint64_t>(cfg_.tof.cfg.filter_clocks.value(), 1);
  }
  std::uint64_t mask() {
    switch (rng_() % 5) {
      case 0:
      case 1:
        return 0xFF;
      case 2:
      case 3:
        return std::uint64_t{1} << (rng_() % kChannels);
      default:
        return rng_() & 0xFF;
    }
  }

  void start_regime(Unit::In& in) {
    const bool after_storm = regime_.storm;
    regime_ = Regime{};
    regime_.storm = one_in(150);
    if (after_storm)  // its carriers end with it; a long pulse goes on
      for (Pin& pin : pins_)
        pin.toggles = 0;
    for (unsigned field = 0; field < 3; ++field)
      if (rng_() % 2 == 0)
        change_config(field);
    for (auto& c : cfg_.tof_channel)
      if (rng_() % 2 == 0)
        channel_config(c);
    if (regime_.storm) {
      regime_.left = between(140000, 300000);
      set(cfg_.tof.cfg.filter_clocks, rng_() % 2);
      for (auto& c : cfg_.tof_channel) {  // no edge limit; empty windows on some: rises ignored
        set(c.cfg.edges, 0);
        set(c.cfg.window_enable, rng_() % 2);
        c.window_close.ticks = c.window_open.ticks;
      }
      set(in.tof.command.arm, 0xFF);
      reset_clocks_ = 0;
      return;
    }
    if (one_in(early() ? 16 : 4096))
      reset_clocks_ = 1 + rng_() % 3;
    regime_.left = log_between(1000, 100000);
    constexpr std::array<std::uint64_t, 3> kCommandRates{100, 1000, 10000};
    constexpr std::array<std::uint64_t, 5> kReadRates{10, 50, 300, 3000, 0};
    regime_.arm = kCommandRates[rng_() % kCommandRates.size()];
    regime_.disarm = 3 * kCommandRates[rng_() % kCommandRates.size()];
    regime_.flush = 4 * kCommandRates[rng_() % kCommandRates.size()];
    regime_.clear = 5 * kCommandRates[rng_() % kCommandRates.size()];
    regime_.read = kReadRates[rng_() % kReadRates.size()];
  }

  // field: 0 prescale, 1 filter, 2 sync_enable, 3 one channel's configuration.
  void change_config(std::uint64_t field) {
    auto& tof = cfg_.tof.cfg;
    switch (field) {
      case 0: {
        const std::uint64_t p = rng_() % 20;
        set(tof.prescale, p < 14 ? 0 : p < 17 ? between(1, 3) : p < 19 ? between(4, 200) : rng_());
        break;
      }
      case 1: {
        const std::uint64_t p = rng_() % 100;
        set(tof.filter_clocks, p < 25   ? rng_() % 2
                               : p < 40 ? 3
                               : p < 70 ? between(2, 4)
                               : p < 90 ? between(5, 20)
                               : p < 95 ? between(21, 60)
                               : p < 98 ? 255
                                        : rng_());
        break;
      }
      case 2:
        set(tof.sync_enable, rng_() % 4 != 0 ? 1 : 0);
        break;
      default:
        channel_config(cfg_.tof_channel[rng_() % kChannels]);
        break;
    }
  }

  void channel_config(ports::tof_channel::Config& c) {
    set(c.cfg.mode, rng_() % 2);
    const std::uint64_t k = rng_() % 10;
    set(c.cfg.edges, k < 3 ? 0 : k < 8 ? between(1, 16) : k < 9 ? 255 : rng_());
    set(c.cfg.window_enable, rng_() % 3 == 0 ? 1 : 0);
    const std::uint64_t now = model_.timebase().timestamp.value();
    std::uint64_t open = 0, close = 0;
    switch (rng_() % 10) {
      case 0:  // spans the wrap
        open = (std::uint64_t{1} << 32) - between(1, 50000);
        close = between(0, 50000);
        break;
      case 1:  // empty, opening soon
        open = close = now + between(0, 2000);
        break;
      case 2:
        open = rng_();
        close = rng_();
        break;
      case 3:
      case 4:  // a few ticks wide, soon: edges on both bounds
        open = now + between(0, 500);
        close = open + between(1, 30);
        break;
      default:  // around now: already open, or opening soon
        open = now + (std::uint64_t{1} << 32) - 2000 + between(0, 22000);
        close = open + between(0, 30000);
        break;
    }
    set(c.window_open.ticks, open);
    set(c.window_close.ticks, close);
  }

  void commands(Unit::In& in) {
    auto& command = in.tof.command;
    if (one_in(regime_.arm))
      set(command.arm, mask());
    if (one_in(regime_.disarm))
      set(command.disarm, mask());
    if (one_in(regime_.flush))
      set(command.flush, mask());
    if (one_in(regime_.flush))
      set(command.sync_flush, 1);
    if (one_in(regime_.clear)) {
      const std::uint64_t m = mask();
      for (int i = 0; i < kChannels; ++i)
        set(in.channel[static_cast<std::size_t>(i)].status.overflow, m >> i & 1U);
      set(in.tof.sync_status.overflow, rng_() % 2);
    }
    if (one_in(4 * regime_.clear))
      set(in.clear_all, 1);
  }

  // The pops a frame on this FIFO commits.
  std::uint64_t frame_pops(int target) {
    const std::uint64_t seen =
        target == kSyncPin
            ? model_.sync().fifo.snapshot_level.value()
            : model_.channel(static_cast<std::size_t>(target)).fifo.snapshot_level.value();
    switch (rng_() % 10) {
      case 0:
        return 0;  // aborted, bad CRC
      case 1:
        return between(9, 15);
      case 2:
      case 3:
      case 4:
        return rng_() % 9;
      default:
        return std::min<std::uint64_t>(seen, kWindow);
    }
  }
  void pop(Unit::In& in, int target, std::uint64_t pops) {
    if (target == kSyncPin)
      set(in.tof.sync_entry.pops, pops);
    else
      set(in.channel[static_cast<std::size_t>(target)].entry.pops, pops);
  }

  // Mostly a FIFO that holds entries, as the SoC driver picks them.
  int frame_target() {
    const int any = static_cast<int>(rng_() % (kChannels + 1));
    if (rng_() % 10 < 3)
      return any;
    for (int k = 0; k <= kChannels; ++k) {
      const int target = (any + k) % (kChannels + 1);
      const std::uint64_t level =
          target == kSyncPin ? model_.sync().fifo.level.value()
                             : model_.channel(static_cast<std::size_t>(target)).fifo.level.value();
      if (level != 0)
        return target;
    }
    return any;
  }

  void read_frames(Unit::In& in) {
    if (frame_.active && --frame_.left == 0) {
      frame_.active = false;
      pop(in, frame_.target, frame_pops(frame_.target));
      if (one_in(10))  // several FIFOs in one commit
        pop(in, static_cast<int>(rng_() % (kChannels + 1)), rng_() % 9);
    }
    if (one_in(20000))  // pops without a frame
      pop(in, static_cast<int>(rng_() % (kChannels + 1)), rng_() % 16);
    if ((!frame_.active || one_in(50)) && one_in(regime_.read)) {
      set(in.snapshot, 1);
      frame_ = Frame{.active = true, .left = between(3, 60), .target = frame_target()};
    }
  }

  std::uint64_t gap() {
    const std::uint64_t p = rng_() % 100;
    return p < 50 ? between(1, 50) : p < 90 ? between(50, 500) : between(500, 5000);
  }

  std::uint64_t pulse_width() {
    const std::uint64_t p = rng_() % 100000;
    if (!early() && p < 3)  // three epochs or more: the width saturates
      return between(std::uint64_t{3} << 23, std::uint64_t{1} << 25);
    const std::uint64_t q = p % 10000;
    return q < 3500   ? between(1, 4 * filter())
           : q < 9300 ? between(5, 300)
           : q < 9998 ? log_between(300, 20000)
                      : log_between(20000, std::uint64_t{1} << 21);
  }

  Burst burst() {
    if (regime_.storm)
      return Burst{.first = between(1, 3), .half = between(1, 3), .toggles = 1000000};
    const std::uint64_t n = filter();
    switch (rng_() % 10) {
      case 0:
      case 1:
      case 2:
        return Burst{.first = pulse_width(), .half = 0, .toggles = 0};
      case 3:  // a pulse with a dropout
        return Burst{.first = pulse_width(), .half = between(1, n + 1), .toggles = 2};
      case 4:
      case 5: {
        const std::uint64_t half = rng_() % 4 == 0 ? between(1, 3) : between(4, 16);
        const int cycles = static_cast<int>(between(1, 40));
        return Burst{.first = half, .half = half, .toggles = 2 * cycles - 1};
      }
      case 6:
      case 7:  // glitches around the filter length
        return Burst{
            .first = std::max<std::uint64_t>(n + between(0, 3), 3) - 2, .half = 0, .toggles = 0};
      default:  // chatter
        return Burst{
            .first = between(1, 3), .half = 0, .toggles = static_cast<int>(between(4, 40))};
    }
  }

  // One burst on every channel, 1 ... 12 clocks apart, and the sync pulse.
  void broadcast() {
    const Burst b = burst();
    for (int i = 0; i < kChannels; ++i) {
      Pin& pin = pins_[static_cast<std::size_t>(i)];
      if (pin.level || pin.toggles > 0)
        continue;
      pin.pending = true;
      pin.next = b;
      pin.hold = between(1, 12);
    }
    Pin& sync = pins_[kSyncPin];
    if (!sync.level && sync.toggles == 0) {
      sync.pending = true;
      sync.next = Burst{.first = between(20, 200), .half = 0, .toggles = 0};
      sync.hold = 1;
    }
  }

  // The pin's level this clock.
  bool advance(Pin& pin) {
    if (--pin.hold > 0)
      return pin.level;
    if (pin.toggles > 0) {
      pin.level = !pin.level;
      --pin.toggles;
      pin.hold = pin.toggles == 0 && !pin.level ? gap() : pin.half != 0 ? pin.half : between(1, 3);
    } else if (pin.level) {
      pin.level = false;
      pin.hold = regime_.storm ? 1 : gap();
    } else {
      const Burst b = pin.pending ? pin.next : burst();
      pin.pending = false;
      pin.level = true;
      pin.hold = std::max<std::uint64_t>(b.first, 1);
      pin.half = b.half;
      pin.toggles = b.toggles;
    }
    return pin.level;
  }

  std::mt19937_64 rng_;
  Unit model_;
  ports::Status status_{};
  ports::Config cfg_{};  // the configuration the stimulus drives
  Regime regime_;
  Frame frame_;
  std::uint64_t reset_clocks_ = 0;
  std::uint64_t calls_ = 0;
  std::array<Pin, kChannels + 1> pins_{};
  std::vector<std::string> in_text_, out_text_;
  std::vector<std::string_view> in_names_, out_names_;
};

}  // namespace

std::unique_ptr<Reference> make_tof_reference(std::uint64_t seed) {
  return std::make_unique<TofReference>(seed);
}

}  // namespace odoloc::verification
