// The TOF capture kernel (hls/tof_kernel.hpp) against the cycle model
// (rtl::TofCapture<>, the chip's unit), compiled once per type family:
// - under the reference's seeded stimulus (hls/verification/src/
//   tof_reference.cpp) every output equals the model's after every call, and
//   every register (the filter's counters, the prescaler, the FIFO slots
//   beyond the register window, the snapshot levels ...) equals the model's;
// - from preset states the stimulus cannot reach in a test's time (the
//   timestamp just before its 2^32 wrap or an epoch, pulses in progress that
//   have seen 0 ... 3 epochs, counters and FIFOs at saturation), kernel and
//   model, both preset, stay equal register for register;
// - the documented latency, widths and filter (docs/tof-capture.md), against
//   their formulas: an edge at the pin in call t is stamped with the
//   timestamp of call t + max(N, 1) + 2; a width is (fall - rise) mod 2^32,
//   saturated at 2^24 - 1 and after three epochs, around both bounds and
//   across the wrap; a rise is recorded when (ts - open) mod 2^32 <
//   (close - open) mod 2^32, at every timestamp around both bounds of the
//   listening window; a glitch of N - 1 calls is never seen.
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
#include "odoloc/hls/tof_kernel.hpp"
#include "odoloc/hls_export/kernels.hpp"
#include "odoloc/ports.hpp"
#include "odoloc/rtl/tof_capture.hpp"

namespace {

namespace ht = odoloc::hls::tof;
namespace rtl = odoloc::rtl;
namespace ports = odoloc::ports;
using odoloc::hls::to_s64;
using rtl::UInt;
using Unit = rtl::TofCapture<>;
constexpr std::size_t kChannels = Unit::kChannels;
constexpr std::size_t kDepth = Unit::kDepth;
using Channel = rtl::TofChannel<kDepth>;
using Sync = rtl::TofSync<kDepth>;
static_assert(ht::kChannels == static_cast<int>(kChannels) &&
              ht::kDepth == static_cast<int>(kDepth));

template <class U>
void set(U& field, long long value) {
  field = U::truncate(static_cast<std::uint64_t>(value));
}

// Every input port 0. (`Inputs{}` leaves ap_int and ac_int fields undefined:
// their default constructors do not initialise.)
ht::Inputs quiet_inputs() {
  ht::Inputs in;
  ht::visit_fields(in, [](const char*, auto& field) { field = 0; });
  return in;
}

// The kernel's input ports as the model's ports.
void to_model(const ht::Inputs& k, Unit::In& in, ports::Config& cfg) {
  set(in.comparators, to_s64(k.comparators));
  set(in.sync, to_s64(k.sync));
  set(in.tof.command.arm, to_s64(k.arm));
  set(in.tof.command.disarm, to_s64(k.disarm));
  set(in.tof.command.flush, to_s64(k.flush));
  set(in.tof.command.sync_flush, to_s64(k.sync_flush));
  set(in.tof.sync_status.overflow, to_s64(k.sync_overflow_clear));
  set(in.tof.sync_entry.pops, to_s64(k.sync_pops));
  set(in.snapshot, to_s64(k.snapshot));
  set(in.clear_all, to_s64(k.clear_all));
  set(in.reset, to_s64(k.reset));
  set(cfg.tof.cfg.prescale, to_s64(k.prescale));
  set(cfg.tof.cfg.filter_clocks, to_s64(k.filter_clocks));
  set(cfg.tof.cfg.sync_enable, to_s64(k.sync_enable));
  for (std::size_t i = 0; i < kChannels; ++i) {
    set(in.channel[i].status.overflow, to_s64(k.rx_pulses[i].overflow_clear));
    set(in.channel[i].entry.pops, to_s64(k.rx_pulses[i].pops));
    const ht::ChannelConfig& c = k.rx_config[i];
    auto& m = cfg.tof_channel[i];
    set(m.cfg.mode, to_s64(c.mode));
    set(m.cfg.window_enable, to_s64(c.window_enable));
    set(m.cfg.edges, to_s64(c.edges));
    set(m.window_open.ticks, to_s64(c.window_open));
    set(m.window_close.ticks, to_s64(c.window_close));
  }
}

// Every register of the model's unit, block by block.
struct ModelRegs {
  Unit::Conditioner::Regs conditioner;
  rtl::TofTimebase::Regs timebase;
  Sync::Regs sync;
  std::array<Channel::Regs, kChannels> channel;
};

ModelRegs regs_of(const Unit& unit) {
  ModelRegs m{unit.conditioner(), unit.timebase(), unit.sync(), {}};
  for (std::size_t i = 0; i < kChannels; ++i)
    m.channel[i] = unit.channel(i);
  return m;
}

// Where a register is: its name, channel (or line) and FIFO slot.
struct Where {
  const char* name;
  int index = -1;
  int slot = -1;
};
std::string describe(const Where& w) {
  std::string text = w.name;
  if (w.index >= 0)
    text += " [" + std::to_string(w.index) + "]";
  if (w.slot >= 0)
    text += " slot " + std::to_string(w.slot);
  return text;
}

template <class K, class M, class F>
void walk_entry(const Where& w, odoloc::logic::tof::SyncEvent<K>& k,
                odoloc::logic::tof::SyncEvent<M>& m, F& f) {
  f(w, k.ticks, m.ticks);
}
template <class K, class M, class F>
void walk_entry(const Where& w, odoloc::logic::tof::Event<K>& k, odoloc::logic::tof::Event<M>& m,
                F& f) {
  f(Where{"fifo.ticks", w.index, w.slot}, k.ticks, m.ticks);
  f(Where{"fifo.width", w.index, w.slot}, k.width, m.width);
  f(Where{"fifo.edge", w.index, w.slot}, k.edge, m.edge);
}
template <class KernelFifo, class ModelFifo, class F>
void walk_fifo(int index, KernelFifo& k, ModelFifo& m, F& f) {
  for (std::size_t s = 0; s < kDepth; ++s)
    walk_entry(Where{"fifo.slot", index, static_cast<int>(s)}, k.slots[s], m.slots[s], f);
  f(Where{"fifo.head", index}, k.head, m.head);
  f(Where{"fifo.level", index}, k.level, m.level);
  f(Where{"fifo.snapshot_level", index}, k.snapshot_level, m.snapshot_level);
  f(Where{"fifo.overflow", index}, k.overflow, m.overflow);
  f(Where{"fifo.dropped", index}, k.dropped, m.dropped);
}

// f(Where, kernel register, model register) for every register of the unit
// (the sync FIFO's index is -1).
template <class F>
void walk(ht::Registers& k, ModelRegs& m, F&& f) {
  f(Where{"sync1"}, k.conditioner.sync1, m.conditioner.sync1);
  f(Where{"sync2"}, k.conditioner.sync2, m.conditioner.sync2);
  f(Where{"filtered"}, k.conditioner.filtered, m.conditioner.filtered);
  for (std::size_t l = 0; l < kChannels + 1; ++l)
    f(Where{"stable", static_cast<int>(l)}, k.conditioner.line[l].stable,
      m.conditioner.line[l].stable);
  f(Where{"prescale_count"}, k.timebase.prescale_count, m.timebase.prescale_count);
  f(Where{"timestamp"}, k.timebase.timestamp, m.timebase.timestamp);
  f(Where{"sync.level"}, k.sync.level, m.sync.level);
  walk_fifo(-1, k.sync.fifo, m.sync.fifo, f);
  for (std::size_t i = 0; i < kChannels; ++i) {
    auto& kc = k.rx[i];
    Channel::Regs& mc = m.channel[i];
    const int c = static_cast<int>(i);
    f(Where{"level", c}, kc.level, mc.level);
    f(Where{"armed", c}, kc.armed, mc.armed);
    f(Where{"done", c}, kc.done, mc.done);
    f(Where{"in_progress", c}, kc.in_progress, mc.in_progress);
    f(Where{"epochs", c}, kc.epochs, mc.epochs);
    f(Where{"rise", c}, kc.rise, mc.rise);
    f(Where{"edges", c}, kc.edges, mc.edges);
    f(Where{"ignored", c}, kc.ignored, mc.ignored);
    walk_fifo(c, kc.fifo, mc.fifo, f);
  }
}

// The kernel's registers holding the model's values.
ht::Registers kernel_registers(ModelRegs m) {
  ht::Registers k;
  walk(k, m, [](const Where&, auto& kf, const auto& mf) { kf = mf.value(); });
  return k;
}

// The first register in which kernel and model differ, or "".
std::string first_difference(const ht::Registers& kernel, const ModelRegs& model) {
  ht::Registers k = kernel;
  ModelRegs m = model;
  std::string first;
  walk(k, m, [&](const Where& w, const auto& kf, const auto& mf) {
    const long long got = to_s64(kf);
    const auto want = static_cast<long long>(mf.value());
    if (first.empty() && got != want)
      first = describe(w) + ": kernel " + std::to_string(got) + ", model " + std::to_string(want);
  });
  return first;
}

// The reference's stimulus, one call's inputs at a time, as kernel ports.
// The reference is stepped too: its stimulus reads its model (the
// timestamp windows are set around, the levels a frame pops).
class Stimulus {
 public:
  explicit Stimulus(std::uint64_t seed)
      : reference_(odoloc::hls_export::find_kernel("tof")->make_reference(seed)),
        row_(reference_->input_names().size()),
        outputs_(reference_->output_names().size()) {}
  ht::Inputs next() {
    reference_->stimulus(row_);
    reference_->step(row_, outputs_);
    ht::Inputs in;  // every field set below
    std::size_t at = 0;
    ht::visit_fields(in, [&](const char*, auto& field) { field = row_[at++]; });
    return in;
  }

 private:
  std::unique_ptr<odoloc::verification::Reference> reference_;
  std::vector<std::int64_t> row_, outputs_;
};

TEST(HlsTof, EveryOutputEqualsTheModelEveryCall) {
  const auto check = odoloc::tb::check_kernel<ht::Inputs, ht::Outputs, ht::Registers>(
      "tof", 7, odoloc::tb::hls_calls(200000), ht::step);
  EXPECT_EQ(check.names_error, "");
  EXPECT_GT(check.calls, 0U);
  EXPECT_EQ(check.mismatches, 0U) << check.first_mismatch;
}

TEST(HlsTof, EveryRegisterEqualsTheModelEveryCall) {
  const std::uint64_t calls = odoloc::tb::scaled(80000);
  Stimulus stimulus(8);
  Unit model;
  model.reset_now();
  ht::Registers regs;
  ht::Outputs out;
  std::uint64_t differing = 0;
  std::string first;
  for (std::uint64_t call = 0; call < calls; ++call) {
    const ht::Inputs in = stimulus.next();
    Unit::In model_in{};
    ports::Config cfg{};
    to_model(in, model_in, cfg);
    model.step(model_in, cfg);
    ht::step(regs, in, out);
    const std::string difference = first_difference(regs, regs_of(model));
    if (!difference.empty() && differing++ == 0)
      first = "call " + std::to_string(call) + ", " + difference;
  }
  std::printf("tof (%s): %llu calls, %llu with a differing register\n", odoloc::hls::kTypeFamily,
              static_cast<unsigned long long>(calls), static_cast<unsigned long long>(differing));
  EXPECT_EQ(differing, 0U) << first;
}

// The unit's blocks clocked as TofCapture clocks them (its own wiring
// functions, every block every clock), so that a test can preset registers
// the unit keeps private.
class PresetUnit {
 public:
  void load(const ModelRegs& m) {
    conditioner_.commit(m.conditioner);
    timebase_.commit(m.timebase);
    sync_.commit(m.sync);
    for (std::size_t i = 0; i < kChannels; ++i)
      channels_[i].commit(m.channel[i]);
  }
  [[nodiscard]] ModelRegs regs() const {
    ModelRegs m{conditioner_.regs(), timebase_.regs(), sync_.regs(), {}};
    for (std::size_t i = 0; i < kChannels; ++i)
      m.channel[i] = channels_[i].regs();
    return m;
  }
  void step(const Unit::In& in, const ports::Config& cfg) {
    const Unit::Wires w{.filtered = conditioner_.regs().filtered,
                        .timestamp = timebase_.regs().timestamp,
                        .epoch = timebase_.epoch(cfg.tof.cfg.prescale)};
    ModelRegs next{conditioner_.eval(Unit::conditioner_in(in, cfg)),
                   timebase_.eval(Unit::timebase_in(in, cfg)),
                   sync_.eval(Unit::sync_in(w, in, cfg)),
                   {}};
    for (std::size_t i = 0; i < kChannels; ++i)
      next.channel[i] = channels_[i].eval(Unit::channel_in(i, w, in, cfg));
    load(next);
  }

 private:
  Unit::Conditioner conditioner_;
  rtl::TofTimebase timebase_;
  Sync sync_;
  std::array<Channel, kChannels> channels_;
};

// A random register state near the edges: timestamps just before the wrap
// or an epoch, pulses in progress with 0 ... 3 epochs seen, counters and
// FIFOs full or nearly so.
class Presets {
 public:
  explicit Presets(std::uint64_t seed) : rng_(seed) {}

  ModelRegs next() {
    ModelRegs m{};
    ht::Registers scratch;
    walk(scratch, m, [&](const Where&, auto&, auto& field) { field = edgy(field); });
    constexpr std::uint64_t kEpoch = std::uint64_t{1} << rtl::TofTimebase::kEpochBits;
    const std::uint64_t before = 1 + rng_() % 3000;
    switch (rng_() % 3) {
      case 0:
        set(m.timebase.timestamp, static_cast<long long>((std::uint64_t{1} << 32) - before));
        break;
      case 1:
        set(m.timebase.timestamp, static_cast<long long>((1 + rng_() % 511) * kEpoch - before));
        break;
      default:
        break;
    }
    const std::uint64_t now = m.timebase.timestamp.value();
    fifo(m.sync.fifo);
    for (Channel::Regs& c : m.channel) {
      if (c.level.value() == 0)
        c.in_progress = UInt<1>{};
      if (rng_() % 2 == 0)  // risen a while ago, maybe before the wrap
        set(c.rise, static_cast<long long>(now - rng_() % (std::uint64_t{1} << 26)));
      fifo(c.fifo);
    }
    return m;
  }
  std::uint64_t draw() { return rng_(); }

 private:
  // A third each: at most 5 below the maximum, at most 5, anything.
  template <class U>
  U edgy(U) {
    switch (rng_() % 3) {
      case 0:
        return U::truncate(U::max_value - rng_() % 6);
      case 1:
        return U::truncate(rng_() % 6);
      default:
        return U::truncate(rng_());
    }
  }
  // A FIFO as the model keeps it: head < depth, snapshot level <= level <= depth.
  template <class Fifo>
  void fifo(Fifo& f) {
    set(f.head, static_cast<long long>(rng_() % kDepth));
    const std::uint64_t level = rng_() % 2 == 0 ? kDepth - rng_() % 3 : rng_() % (kDepth + 1);
    set(f.level, static_cast<long long>(level));
    set(f.snapshot_level, static_cast<long long>(rng_() % (level + 1)));
  }

  std::mt19937_64 rng_;
};

TEST(HlsTof, PresetNearWrapEpochsAndSaturationEqualsTheModel) {
  constexpr int kClocks = 4000;
  const int presets = static_cast<int>(odoloc::tb::scaled(30 * kClocks) / kClocks);
  Presets draw(21);
  std::uint64_t differing = 0;
  std::string first;
  for (int p = 0; p < presets; ++p) {
    Stimulus stimulus(1000 + static_cast<std::uint64_t>(p));
    const ModelRegs preset = draw.next();
    PresetUnit model;
    model.load(preset);
    ht::Registers regs = kernel_registers(preset);
    // Pulses in progress stay high a while, so that they see epochs.
    const std::uint64_t high_for = draw.draw() % 3000;
    std::uint64_t hold_high = 0;
    for (std::size_t i = 0; i < kChannels; ++i)
      hold_high |= std::uint64_t{preset.channel[i].in_progress.value()} << i;
    ht::Outputs out;
    for (int clock = 0; clock < kClocks; ++clock) {
      ht::Inputs in = stimulus.next();
      if (static_cast<std::uint64_t>(clock) < high_for)
        in.comparators = to_s64(in.comparators) | static_cast<long long>(hold_high);
      Unit::In model_in{};
      ports::Config cfg{};
      to_model(in, model_in, cfg);
      model.step(model_in, cfg);
      ht::step(regs, in, out);
      const std::string difference = first_difference(regs, model.regs());
      if (!difference.empty() && differing++ == 0)
        first =
            "preset " + std::to_string(p) + ", clock " + std::to_string(clock) + ", " + difference;
    }
  }
  std::printf("tof (%s): %d presets x %d clocks, %llu with a differing register\n",
              odoloc::hls::kTypeFamily, presets, kClocks,
              static_cast<unsigned long long>(differing));
  EXPECT_EQ(differing, 0U) << first;
}

// docs/tof-capture.md, "Latency": a comparator or sync edge first applied in
// call t is stamped with the timestamp of call t + max(N, 1) + 2, the
// timestamp of call c being floor(c / (p + 1)); widths are differences of
// two such stamps.
TEST(HlsTof, LatencyFromPinToTimestampIsTheDocumentedOne) {
  std::mt19937_64 rng(11);
  for (unsigned n = 0; n <= 6; ++n) {
    for (unsigned p : {0U, 1U, 2U, 7U, 124U}) {
      ht::Registers regs;
      ht::Outputs out;
      ht::Inputs in = quiet_inputs();
      in.filter_clocks = n;
      in.prescale = p;
      in.sync_enable = 1;
      in.arm = 1;
      in.rx_config[0].mode = odoloc::rtl::tof_capture::kModeEnvelope;
      std::uint64_t call = 0;
      ht::step(regs, in, out);
      ++call;
      in.arm = 0;
      const std::uint64_t rise = 50 + rng() % 1000;
      const std::uint64_t width = 20 + rng() % 2000;
      while (call < rise + width + 400) {
        const bool high = call >= rise && call < rise + width;
        in.comparators = high ? 1 : 0;
        in.sync = high ? 1 : 0;
        ht::step(regs, in, out);
        ++call;
      }
      const std::uint64_t latency = std::max(n, 1U) + 2;
      const auto ts = [&](std::uint64_t c) { return static_cast<long long>(c / (p + 1)); };
      ASSERT_EQ(to_s64(out.rx[0].fill_level), 1) << "N " << n << " p " << p;
      EXPECT_EQ(to_s64(out.rx[0].entry[0].ticks), ts(rise + latency)) << "N " << n << " p " << p;
      EXPECT_EQ(to_s64(out.rx[0].entry[0].width), ts(rise + width + latency) - ts(rise + latency))
          << "N " << n << " p " << p;
      ASSERT_EQ(to_s64(out.sync_fill_level), 1);
      EXPECT_EQ(to_s64(out.sync_entry[0]), ts(rise + latency)) << "N " << n << " p " << p;
      EXPECT_EQ(to_s64(out.rx[1].fill_level), 0) << "channel 1 is armed but saw nothing";
    }
  }
}

// docs/tof-capture.md, "Timestamp": a pulse's width is (fall - rise) mod 2^32
// ticks, exact below 2^24 - 1 and saturated there, and saturated whatever
// the difference once the pulse has seen three epochs (2^23 ticks each).
TEST(HlsTof, PulseWidthsSaturateAsDocumented) {
  constexpr std::uint64_t kMaxWidth = (std::uint64_t{1} << 24) - 1;
  constexpr std::uint64_t kEpoch = std::uint64_t{1} << rtl::TofTimebase::kEpochBits;
  struct Start {
    std::uint64_t timestamp;
    unsigned epochs;  // epoch strobes before the fall
  };
  for (const Start start : {Start{5 * kEpoch + 1000, 0}, Start{(std::uint64_t{1} << 32) - 2, 1}}) {
    for (unsigned seen = 0; seen <= 3; ++seen) {
      for (int delta = -3; delta <= 3; ++delta) {
        // Channel 0 holds a pulse that rose `width` ticks before the stamp
        // of its fall, which the pin applies in call 0: call N + 2 = 3.
        const std::uint64_t width = kMaxWidth - 3 + static_cast<std::uint64_t>(delta + 3);
        const std::uint64_t rise = (start.timestamp + 3 - width) & 0xFFFFFFFFU;
        ModelRegs m{};
        m.conditioner.sync1 = m.conditioner.sync2 = m.conditioner.filtered = UInt<9>{1};
        set(m.timebase.timestamp, static_cast<long long>(start.timestamp & 0xFFFFFFFFU));
        Channel::Regs& c = m.channel[0];
        c.level = c.armed = c.in_progress = UInt<1>{1};
        set(c.epochs, seen);
        set(c.rise, static_cast<long long>(rise));
        PresetUnit model;
        model.load(m);
        ht::Registers regs = kernel_registers(m);
        ht::Inputs in = quiet_inputs();
        in.filter_clocks = 1;
        ht::Outputs out;
        for (int call = 0; call < 6; ++call) {
          Unit::In model_in{};
          ports::Config cfg{};
          to_model(in, model_in, cfg);
          model.step(model_in, cfg);
          ht::step(regs, in, out);
          EXPECT_EQ(first_difference(regs, model.regs()), "") << "call " << call;
        }
        const bool saturated = std::min(seen + start.epochs, 3U) == 3;
        const auto want =
            static_cast<long long>(saturated ? kMaxWidth : std::min(width, kMaxWidth));
        ASSERT_EQ(to_s64(out.rx[0].fill_level), 1);
        EXPECT_EQ(to_s64(out.rx[0].entry[0].ticks), static_cast<long long>(rise));
        EXPECT_EQ(to_s64(out.rx[0].entry[0].width), want)
            << "width " << width << ", epochs " << seen << " + " << start.epochs;
      }
    }
  }
}

// docs/tof-capture.md, "Channels": a rising edge is recorded when
// (ts - open) mod 2^32 < (close - open) mod 2^32, else counted as ignored;
// a rise on every timestamp around each bound, windows spanning the wrap,
// empty and almost full among them.
TEST(HlsTof, ListeningWindowBoundsAreTheDocumentedOnes) {
  constexpr std::uint64_t kWrap = std::uint64_t{1} << 32;
  struct Window {
    std::uint64_t open, close;
  };
  const Window windows[] = {{1000, 1010}, {kWrap - 6, 6}, {1000, 1000}, {1000, 999}, {0, 1}};
  for (const Window window : windows) {
    for (const std::uint64_t bound : {window.open, window.close}) {
      for (std::uint64_t phase = 0; phase < 2; ++phase) {
        // With N = 1, a rise applied in call t is stamped t + 3 ticks after
        // the preset timestamp; rises in odd calls cover bound - 6 ... bound + 6.
        const std::uint64_t start = (bound + kWrap - 10 - phase) % kWrap;
        ModelRegs m{};
        set(m.timebase.timestamp, static_cast<long long>(start));
        PresetUnit model;
        model.load(m);
        ht::Registers regs = kernel_registers(m);
        ht::Inputs in = quiet_inputs();
        in.filter_clocks = 1;
        in.rx_config[0].mode = rtl::tof_capture::kModeCarrier;
        in.rx_config[0].window_enable = 1;
        in.rx_config[0].window_open = static_cast<long long>(window.open);
        in.rx_config[0].window_close = static_cast<long long>(window.close);
        ht::Outputs out;
        std::vector<long long> recorded;
        long long ignored = 0;
        for (std::uint64_t call = 0; call < 18; ++call) {
          in.arm = call == 0 ? 1 : 0;
          in.comparators = call % 2;
          if (call % 2 == 1 && call < 14) {
            const std::uint64_t stamp = (start + call + 3) % kWrap;
            const bool inside =
                (stamp - window.open) % kWrap < (window.close - window.open) % kWrap;
            if (inside)
              recorded.push_back(static_cast<long long>(stamp));
            else
              ++ignored;
          }
          if (call >= 14)
            in.comparators = 0;
          Unit::In model_in{};
          ports::Config cfg{};
          to_model(in, model_in, cfg);
          model.step(model_in, cfg);
          ht::step(regs, in, out);
          EXPECT_EQ(first_difference(regs, model.regs()), "") << "call " << call;
        }
        const std::string where = "window [" + std::to_string(window.open) + ", " +
                                  std::to_string(window.close) + "), bound " +
                                  std::to_string(bound) + ", phase " + std::to_string(phase);
        ASSERT_EQ(to_s64(out.rx[0].fill_level), static_cast<long long>(recorded.size())) << where;
        for (std::size_t k = 0; k < recorded.size(); ++k)
          EXPECT_EQ(to_s64(out.rx[0].entry[k].ticks), recorded[k]) << where << ", entry " << k;
        EXPECT_EQ(to_s64(out.rx[0].ignored), ignored) << where;
      }
    }
  }
}

// A glitch of N - 1 calls never reaches a channel; one of N calls does.
TEST(HlsTof, GlitchesShorterThanTheFilterAreInvisible) {
  for (unsigned n = 2; n <= 8; ++n) {
    ht::Registers regs;
    ht::Outputs out;
    ht::Inputs in = quiet_inputs();
    in.filter_clocks = n;
    in.rx_config[0].mode = odoloc::rtl::tof_capture::kModeCarrier;
    in.arm = 1;
    ht::step(regs, in, out);
    in.arm = 0;
    const auto pulse = [&](unsigned length) {
      in.comparators = 1;
      for (unsigned k = 0; k < length; ++k)
        ht::step(regs, in, out);
      in.comparators = 0;
      for (unsigned k = 0; k < n + 3; ++k)
        ht::step(regs, in, out);
    };
    for (unsigned g = 0; g < 20; ++g)
      pulse(n - 1);
    EXPECT_EQ(to_s64(out.rx[0].fill_level), 0) << n;
    pulse(n);
    EXPECT_EQ(to_s64(out.rx[0].fill_level), 1) << n;
  }
}

}  // namespace
