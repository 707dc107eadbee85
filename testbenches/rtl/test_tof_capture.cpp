// The ultrasonic time-of-flight capture unit against independent references:
// - a receiver channel against an event-level model in 64-bit unwrapped time
//   (envelope widths across the 2^32 wrap and up to saturation, carrier edge
//   counts, listening windows, FIFO overflow, pops bounded by the snapshot);
// - the unit's exact latency from pin to timestamp for every filter length
//   and prescaler (the formula of docs/tof-capture.md);
// - activity gating: gated and ungated units agree register for register, and
//   every leaf keeps the idle contract.
// Reading the unit over SPI is test_tof_registers.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "idle_contract.hpp"
#include "odoloc/rtl/tof_capture.hpp"
#include "register_dump.hpp"
#include "test_scale.hpp"

namespace {

using odoloc::rtl::CaptureFifo;
using odoloc::rtl::FifoControl;
using odoloc::rtl::Gating;
using odoloc::rtl::TofCapture;
using odoloc::rtl::TofChannel;
using odoloc::rtl::TofEvent;
using odoloc::rtl::TofMode;
using odoloc::rtl::TofSync;
using odoloc::rtl::TofTimebase;
using odoloc::rtl::UInt;
using odoloc::tb::one_in;
using odoloc::tb::random_uint;
using odoloc::tb::Rng;
namespace ports = odoloc::ports;

constexpr std::size_t kDepth = 16;
using Channel = TofChannel<kDepth>;
constexpr std::uint64_t kMaxWidth = (std::uint64_t{1} << 24) - 1;
constexpr std::uint64_t kEpoch = std::uint64_t{1} << 23;

ports::tof_channel::Config channel_config(TofMode mode, unsigned edges = 0) {
  ports::tof_channel::Config c;
  c.cfg.mode = UInt<1>{static_cast<unsigned>(mode)};
  c.cfg.edges = UInt<8>{edges};
  return c;
}

// A channel driven event by event in unwrapped time: between two calls the
// inputs hold and no epoch passes that clock() does not deliver, so the
// clocks skipped are idle (LeafIdleContract.TofChannel proves idle clocks
// change nothing).
struct ChannelBench {
  Channel channel;
  ports::tof_channel::Config cfg;
  std::uint64_t time = 0;  // unwrapped ticks; one tick per clock (prescale 0)
  UInt<1> level;

  // Moves to unwrapped tick `t`, delivering every epoch strobe on the way,
  // then clocks once with `comparator` and the controls.
  void at(std::uint64_t t, UInt<1> comparator, const FifoControl& fifo = {},
          UInt<1> arm = UInt<1>{}) {
    // Epoch strobe: in the clock whose timestamp + 1 is a multiple of 2^23.
    for (std::uint64_t e = (time / kEpoch + 1) * kEpoch; e <= t; e += kEpoch)
      clock(e - 1, level, {}, UInt<1>{}, true);
    clock(t, comparator, fifo, arm, (t + 1) % kEpoch == 0);
  }
  void arm(std::uint64_t t) { at(t, level, {}, UInt<1>{1}); }
  void clock(std::uint64_t t, UInt<1> comparator, const FifoControl& fifo, UInt<1> arm,
             bool epoch) {
    ASSERT_GE(t, time);
    channel.commit(channel.eval({.comparator = comparator,
                                 .timestamp = UInt<32>::truncate(t),
                                 .epoch = epoch,
                                 .cfg = cfg,
                                 .arm = arm,
                                 .disarm = UInt<1>{},
                                 .fifo = fifo,
                                 .reset = UInt<1>{}}));
    time = t + 1;
    level = comparator;
  }
  std::vector<TofEvent> drain() {
    std::vector<TofEvent> out;
    const auto& f = channel.regs().fifo;
    for (std::size_t k = 0; k < f.level.value(); ++k)
      out.push_back(odoloc::rtl::fifo_entry(f, k));
    return out;
  }
};

// Envelope pulses of random widths, some up to and past saturation, starting
// just before the 2^32 wrap: every entry is {rise mod 2^32, min(width, 2^24-1)}
// in unwrapped 64-bit arithmetic.
TEST(TofChannel, EnvelopeWidthsAcrossTheWrapAndSaturation) {
  Rng rng(10);
  const std::vector<std::uint64_t> special = {1,
                                              2,
                                              kMaxWidth - 1,
                                              kMaxWidth,
                                              kMaxWidth + 1,
                                              2 * kEpoch,
                                              3 * kEpoch - 1,
                                              3 * kEpoch,
                                              3 * kEpoch + 1,
                                              std::uint64_t{1} << 32,
                                              (std::uint64_t{1} << 32) + 7};
  for (int round = 0; round < 40; ++round) {
    ChannelBench b;
    b.cfg = channel_config(TofMode::kEnvelope);
    const std::uint64_t start = (std::uint64_t{1} << 32) - 1 - rng() % 100'000;
    b.time = start;
    b.arm(start);
    std::vector<TofEvent> expected;
    std::uint64_t t = start + 1;
    for (int p = 0; p < 10; ++p) {
      const std::uint64_t width =
          one_in(rng, 3) ? special[rng() % special.size()] : 1 + rng() % 5000;
      t += 1 + rng() % 3000;
      b.at(t, UInt<1>{1});
      b.at(t + width, UInt<1>{});
      expected.push_back({.ticks = UInt<32>::truncate(t),
                          .width = UInt<24>::truncate(std::min(width, kMaxWidth)),
                          .edge = {}});
      t += width;
    }
    EXPECT_EQ(b.drain(), expected) << "round " << round;
    EXPECT_EQ(b.channel.regs().fifo.dropped.value(), 0U);
  }
}

// Carrier mode keeps the first K rising edges after arming, numbered, then
// disarms itself; arming again restarts the count.
TEST(TofChannel, CarrierKeepsTheFirstKEdges) {
  for (const unsigned k : {1U, 3U, 8U, 0U}) {
    ChannelBench b;
    b.cfg = channel_config(TofMode::kCarrier, k);
    b.arm(100);
    std::vector<TofEvent> expected;
    for (unsigned e = 0; e < 12; ++e) {
      const std::uint64_t rise = 1000 + 1250 * e;  // 40 kHz at 20 ns
      b.at(rise, UInt<1>{1});
      b.at(rise + 625, UInt<1>{});
      if (k == 0 || e < k)
        expected.push_back(
            {.ticks = UInt<32>::truncate(rise), .width = {}, .edge = UInt<7>::truncate(e)});
    }
    EXPECT_EQ(b.drain(), expected) << "K = " << k;
    EXPECT_EQ(b.channel.regs().done.value(), k == 0 ? 0U : 1U) << k;
    EXPECT_EQ(b.channel.regs().armed.value(), k == 0 ? 1U : 0U) << k;
  }
}

// Rising edges outside [open, close) are ignored and counted, also for a
// window that spans the timestamp wrap.
TEST(TofChannel, ListeningWindowModuloTheWrap) {
  const std::uint64_t wrap = std::uint64_t{1} << 32;
  for (const std::uint64_t open : {std::uint64_t{5000}, wrap - 3000}) {
    ChannelBench b;
    b.cfg = channel_config(TofMode::kCarrier, 0);
    b.cfg.cfg.window_enable = UInt<1>{1};
    b.cfg.window_open.ticks = UInt<32>::truncate(open);
    b.cfg.window_close.ticks = UInt<32>::truncate(open + 6000);
    b.time = open - 4000;
    b.arm(open - 4000);
    std::vector<TofEvent> expected;
    unsigned ignored = 0;
    for (std::uint64_t t = open - 3000; t < open + 9000; t += 500) {
      b.at(t, UInt<1>{1});
      b.at(t + 100, UInt<1>{});
      if (t >= open && t < open + 6000)
        expected.push_back({.ticks = UInt<32>::truncate(t),
                            .width = {},
                            .edge = UInt<7>::truncate(expected.size())});
      else
        ++ignored;
    }
    EXPECT_EQ(b.drain(), expected) << open;
    EXPECT_EQ(b.channel.regs().ignored.value(), ignored) << open;
  }
}

// A full FIFO keeps its oldest entries, drops new ones, counts them and
// raises the sticky overflow; flush empties and clears; w1c clears the flag only.
TEST(TofChannel, OverflowKeepsTheOldestAndCounts) {
  ChannelBench b;
  b.cfg = channel_config(TofMode::kCarrier, 0);
  b.arm(0);
  for (unsigned e = 0; e < kDepth + 5; ++e) {
    b.at(10 + 20 * e, UInt<1>{1});
    b.at(20 + 20 * e, UInt<1>{});
  }
  const auto entries = b.drain();
  ASSERT_EQ(entries.size(), kDepth);
  EXPECT_EQ(entries.front().ticks.value(), 10U);
  EXPECT_EQ(entries.back().edge.value(), kDepth - 1);
  EXPECT_EQ(b.channel.regs().fifo.overflow.value(), 1U);
  EXPECT_EQ(b.channel.regs().fifo.dropped.value(), 5U);
  b.at(b.time, b.level, {.clear_overflow = UInt<1>{1}});
  EXPECT_EQ(b.channel.regs().fifo.overflow.value(), 0U);
  EXPECT_EQ(b.channel.regs().fifo.dropped.value(), 5U);
  EXPECT_EQ(b.channel.regs().fifo.level.value(), kDepth);
  b.at(b.time, b.level, {.flush = UInt<1>{1}});
  EXPECT_EQ(b.channel.regs().fifo.level.value(), 0U);
  EXPECT_EQ(b.channel.regs().fifo.dropped.value(), 0U);
}

// A frame's pops never exceed the level its snapshot saw: entries pushed
// while the frame ran survive even when the frame read the whole window.
TEST(TofChannel, PopsAreBoundedByTheSnapshotLevel) {
  ChannelBench b;
  b.cfg = channel_config(TofMode::kCarrier, 0);
  b.arm(0);
  const auto edge = [&](std::uint64_t t) {
    b.at(t, UInt<1>{1});
    b.at(t + 5, UInt<1>{});
  };
  edge(10);
  edge(30);
  b.at(b.time, b.level, {.snapshot = UInt<1>{1}});  // the frame starts: 2 entries
  edge(50);                                         // pushed while the frame runs
  b.at(b.time, b.level, {.pops = UInt<6>{8}});      // it read the whole window
  auto left = b.drain();
  ASSERT_EQ(left.size(), 1U);
  EXPECT_EQ(left[0].ticks.value(), 50U);
  // A frame that read one entry of three pops one.
  edge(70);
  edge(90);
  b.at(b.time, b.level, {.snapshot = UInt<1>{1}});
  b.at(b.time, b.level, {.pops = UInt<6>{1}});
  left = b.drain();
  ASSERT_EQ(left.size(), 2U);
  EXPECT_EQ(left[0].ticks.value(), 70U);
  // Pops without a snapshot (no frame started) pop nothing.
  b.at(b.time, b.level, {.pops = UInt<6>{2}});
  EXPECT_EQ(b.drain().size(), 2U);
}

// ---- the whole unit --------------------------------------------------------------

using Unit = TofCapture<2, 8>;

struct UnitBench {
  Unit unit;
  ports::Config cfg;
  Unit::In in;
  std::uint64_t clocks = 0;
  UnitBench() { unit.reset_now(); }
  template <Gating G = Gating::kOn>
  void step() {
    unit.step<G>(in, cfg);
    ++clocks;
  }
};

// A comparator edge applied in clock t is stamped with the timestamp of
// clock t + max(N, 1) + 2, the timestamp of clock c being floor(c / (p+1)).
TEST(TofCapture, LatencyFromPinToTimestampIsExact) {
  Rng rng(11);
  for (unsigned n = 0; n <= 6; ++n) {
    for (unsigned p : {0U, 1U, 2U, 7U, 124U}) {
      UnitBench b;
      b.cfg.tof.cfg.filter_clocks = UInt<8>{n};
      b.cfg.tof.cfg.prescale = UInt<16>{p};
      b.cfg.tof.cfg.sync_enable = UInt<1>{1};
      b.cfg.tof_channel[0] = channel_config(TofMode::kEnvelope);
      b.in.tof.command.arm = UInt<8>{1};
      b.step();
      b.in.tof.command.arm = UInt<8>{};
      const std::uint64_t rise = 50 + rng() % 1000;
      const std::uint64_t width = 20 + rng() % 5000;
      while (b.clocks < rise + width + 400) {
        const bool high = b.clocks >= rise && b.clocks < rise + width;
        b.in.comparators = UInt<2>{high ? 1U : 0U};
        b.in.sync = UInt<1>{high ? 1U : 0U};
        b.step();
      }
      const std::uint64_t latency = std::max(n, 1U) + 2;
      const auto ts = [&](std::uint64_t clock) { return clock / (p + 1); };
      const auto& fifo = b.unit.channel(0).fifo;
      ASSERT_EQ(fifo.level.value(), 1U) << n << " " << p;
      EXPECT_EQ(odoloc::rtl::fifo_entry(fifo, 0).ticks.value(), ts(rise + latency))
          << "N " << n << " p " << p;
      EXPECT_EQ(odoloc::rtl::fifo_entry(fifo, 0).width.value(),
                ts(rise + width + latency) - ts(rise + latency))
          << "N " << n << " p " << p;
      ASSERT_EQ(b.unit.sync().fifo.level.value(), 1U);
      EXPECT_EQ(odoloc::rtl::fifo_entry(b.unit.sync().fifo, 0).ticks.value(), ts(rise + latency));
      EXPECT_EQ(b.unit.channel(1).fifo.level.value(), 0U) << "channel 1 is not armed";
    }
  }
}

// A glitch shorter than the filter never reaches a channel.
TEST(TofCapture, GlitchesShorterThanTheFilterAreInvisible) {
  for (unsigned n = 2; n <= 8; ++n) {
    UnitBench b;
    b.cfg.tof.cfg.filter_clocks = UInt<8>{n};
    b.cfg.tof_channel[0] = channel_config(TofMode::kCarrier, 0);
    b.in.tof.command.arm = UInt<8>{1};
    b.step();
    b.in.tof.command.arm = UInt<8>{};
    for (unsigned g = 0; g < 20; ++g) {
      for (unsigned k = 0; k < n - 1; ++k) {
        b.in.comparators = UInt<2>{1};
        b.step();
      }
      b.in.comparators = UInt<2>{};
      for (unsigned k = 0; k < n + 3; ++k)
        b.step();
    }
    EXPECT_EQ(b.unit.channel(0).fifo.level.value(), 0U) << n;
    for (unsigned k = 0; k < n; ++k) {
      b.in.comparators = UInt<2>{1};
      b.step();
    }
    b.in.comparators = UInt<2>{};
    for (unsigned k = 0; k < n + 3; ++k)
      b.step();
    EXPECT_EQ(b.unit.channel(0).fifo.level.value(), 1U) << n;
  }
}

// The timebase's epoch strobe comes on the tick that rolls bits 22:0 over,
// for every prescaler.
TEST(TofTimebase, EpochOnTheRollOverTick) {
  for (unsigned p : {0U, 3U}) {
    TofTimebase t;
    t.commit({.prescale_count = UInt<16>{}, .timestamp = UInt<32>::truncate(3 * kEpoch - 3)});
    std::vector<std::uint64_t> epochs;
    for (int k = 0; k < 40; ++k) {
      if (t.epoch(UInt<16>{p}))
        epochs.push_back(t.regs().timestamp.value());
      t.commit(t.eval({.prescale = UInt<16>{p}, .reset = UInt<1>{}}));
    }
    EXPECT_EQ(epochs, std::vector<std::uint64_t>{3 * kEpoch - 1}) << p;
  }
}

// Gated, ungated and mixed units (gated and ungated in runs: the gating's
// bookkeeping survives them) agree on every register every clock under
// random pins, commands, frames (snapshot then pops), configuration and
// resets.
TEST(TofCapture, GatedAndUngatedAgreeEveryClock) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    Rng rng(seed);
    UnitBench gated, ungated, mixed;
    std::uint64_t quiet = 0;  // clocks in which nothing but the timebase changed
    const std::uint64_t clocks = odoloc::tb::scaled(300'000);
    for (std::uint64_t k = 0; k < clocks; ++k) {
      Unit::In& in = gated.in;
      in = {};
      in.comparators = one_in(rng, 40) ? random_uint<2>(rng) : ungated.in.comparators;
      in.sync = one_in(rng, 200) ? random_uint<1>(rng) : ungated.in.sync;
      in.tof.command.arm = UInt<8>::truncate(one_in(rng, 3000) ? rng() : 0);
      in.tof.command.disarm = UInt<8>::truncate(one_in(rng, 9000) ? rng() : 0);
      in.tof.command.flush = UInt<8>::truncate(one_in(rng, 20000) ? rng() : 0);
      in.snapshot = UInt<1>::truncate(one_in(rng, 2000));
      in.channel[0].entry.pops = UInt<4>::truncate(one_in(rng, 2000) ? rng() % 9 : 0);
      in.tof.sync_entry.pops = UInt<4>::truncate(one_in(rng, 2000) ? rng() % 9 : 0);
      in.channel[1].status.overflow = UInt<1>::truncate(one_in(rng, 5000));
      in.reset = UInt<1>::truncate(one_in(rng, 100'000));
      if (one_in(rng, 50'000)) {
        gated.cfg.tof.cfg.filter_clocks = UInt<8>::truncate(rng() % 5);
        gated.cfg.tof.cfg.prescale = UInt<16>::truncate(rng() % 3);
        gated.cfg.tof.cfg.sync_enable = random_uint<1>(rng);
        for (auto& c : gated.cfg.tof_channel) {
          c.cfg.mode = random_uint<1>(rng);
          c.cfg.edges = UInt<8>::truncate(rng() % 10);
          c.cfg.window_enable = UInt<1>::truncate(one_in(rng, 3));
          c.window_open.ticks = UInt<32>::truncate(rng() % 200'000);
          c.window_close.ticks = UInt<32>::truncate(rng() % 200'000);
        }
        ungated.cfg = gated.cfg;
        mixed.cfg = gated.cfg;
      }
      ungated.in = in;
      mixed.in = in;
      const auto channels_before = ungated.unit.channel(0);
      const auto conditioner_before = ungated.unit.conditioner();
      gated.step<Gating::kOn>();
      ungated.step<Gating::kOff>();
      if ((k / 1009) % 2 == 0)
        mixed.step<Gating::kOn>();
      else
        mixed.step<Gating::kOff>();
      if (channels_before == ungated.unit.channel(0) &&
          conditioner_before == ungated.unit.conditioner())
        ++quiet;
      ASSERT_EQ(odoloc::tb::first_difference(gated.unit, ungated.unit), "")
          << "seed " << seed << " clock " << k;
      ASSERT_EQ(odoloc::tb::first_difference(mixed.unit, ungated.unit), "")
          << "seed " << seed << " clock " << k << ", mixed gating";
    }
    EXPECT_GT(quiet, clocks / 2) << "seed " << seed << ": too little gating";
  }
}

// Frames (a snapshot, then pops), flushes and flag clears at random.
FifoControl random_fifo_control(Rng& rng) {
  return {.snapshot = UInt<1>::truncate(one_in(rng, 40)),
          .pops = UInt<6>::truncate(one_in(rng, 40) ? rng() % 9 : 0),
          .flush = UInt<1>::truncate(one_in(rng, 500)),
          .clear_overflow = UInt<1>::truncate(one_in(rng, 60))};
}

TEST(LeafIdleContract, TofChannel) {
  UInt<1> comparator;
  ports::tof_channel::Config cfg = channel_config(TofMode::kEnvelope, 3);
  const double idle_share = odoloc::tb::check_idle_contract<Channel>(
      31,
      [](Rng& rng) {
        Channel::Regs r;
        r.level = random_uint<1>(rng);
        r.armed = random_uint<1>(rng);
        r.in_progress = random_uint<1>(rng);
        r.epochs = random_uint<2>(rng);
        r.rise = random_uint<32>(rng);
        r.edges = random_uint<8>(rng);
        r.fifo.level = UInt<6>::truncate(rng() % (kDepth + 1));
        r.fifo.snapshot_level = UInt<6>::truncate(rng() % (kDepth + 1));
        r.fifo.head = random_uint<5>(rng).wrap<4>();
        return r;
      },
      [&](Rng& rng) {
        if (one_in(rng, 8))
          comparator = random_uint<1>(rng);
        if (one_in(rng, 100))
          cfg = channel_config(one_in(rng, 2) ? TofMode::kEnvelope : TofMode::kCarrier,
                               static_cast<unsigned>(rng() % 4));
        cfg.cfg.window_enable = UInt<1>::truncate(one_in(rng, 200) ? 1 : 0);
        return Channel::In{.comparator = comparator,
                           .timestamp = random_uint<32>(rng),
                           .epoch = one_in(rng, 50),
                           .cfg = cfg,
                           .arm = UInt<1>::truncate(one_in(rng, 50)),
                           .disarm = UInt<1>::truncate(one_in(rng, 80)),
                           .fifo = random_fifo_control(rng),
                           .reset = UInt<1>::truncate(one_in(rng, 1000))};
      });
  EXPECT_GT(idle_share, 0.05);
}

TEST(LeafIdleContract, TofSync) {
  UInt<1> sync;
  const double idle_share = odoloc::tb::check_idle_contract<TofSync<kDepth>>(
      32,
      [](Rng& rng) {
        TofSync<kDepth>::Regs r;
        r.level = random_uint<1>(rng);
        r.fifo.level = UInt<6>::truncate(rng() % (kDepth + 1));
        r.fifo.snapshot_level = UInt<6>::truncate(rng() % (kDepth + 1));
        return r;
      },
      [&](Rng& rng) {
        if (one_in(rng, 8))
          sync = random_uint<1>(rng);
        return TofSync<kDepth>::In{.sync = sync,
                                   .timestamp = random_uint<32>(rng),
                                   .enable = UInt<1>::truncate(!one_in(rng, 10)),
                                   .fifo = random_fifo_control(rng),
                                   .reset = UInt<1>::truncate(one_in(rng, 1000))};
      });
  EXPECT_GT(idle_share, 0.05);
}

TEST(LeafIdleContract, InputConditionerOfNineLines) {
  using Conditioner = odoloc::rtl::InputConditioner<9>;
  UInt<9> pins;
  const double idle_share = odoloc::tb::check_idle_contract<Conditioner>(
      33,
      [](Rng& rng) {
        Conditioner::Regs r{random_uint<9>(rng), random_uint<9>(rng), random_uint<9>(rng), {}};
        for (auto& line : r.line)
          line.stable = UInt<8>::truncate(one_in(rng, 2) ? 0 : rng() % 6);
        return r;
      },
      [&](Rng& rng) {
        if (one_in(rng, 8))
          pins = random_uint<9>(rng);
        return Conditioner::In{.pins = pins,
                               .filter_clocks = UInt<8>::truncate(rng() % 5),
                               .reset = UInt<1>::truncate(one_in(rng, 100))};
      });
  EXPECT_GT(idle_share, 0.05);
}

}  // namespace
