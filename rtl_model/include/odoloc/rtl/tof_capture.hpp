// Ultrasonic time-of-flight capture unit: timestamps the comparator outputs
// of the receivers on the robot and a sync input, into per-channel event FIFOs
// the SoC drains over SPI. One unit serves Kleeman's beacon octagon, Thamma's
// RF-synchronised head/tail boxes and the binaural pair (docs/tof-capture.md).
//
//   comparators[C], sync -> InputConditioner<C+1> --filtered--> TofChannel x C --> CaptureFifo
//                           (2-flop sync, filter)           +-> TofSync      --> CaptureFifo
//   TofTimebase (prescaler, 32-bit timestamp, epoch strobe every 2^23 ticks) --timestamp--^
//
// Events are timestamped in the clock their filtered level change reaches
// the channel: a pin change in clock t is stamped with the timestamp of clock
// t+N+2 (N = max(filter_clocks, 1)); the driver subtracts that constant.
// Every counter is a function of the clock count and the input edges, so an
// analytic fast-forward can jump the timebase between events.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "odoloc/ports.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/input_conditioner.hpp"
#include "odoloc/rtl/tof_constants.hpp"

namespace odoloc::rtl {

// ---- ports (generated from regmap/odoloc.yaml: odoloc/ports.hpp) -------------
using TofMode = regs::tof_channel::cfg::Mode;
inline constexpr std::size_t kTofChannelInstances = regs::tof_channel::kInstances;
// The constants the HLS kernel shares (tof_constants.hpp) are the register map's.
static_assert(tof_capture::kChannels == kTofChannelInstances &&
              tof_capture::kWindow ==
                  std::tuple_size<decltype(ports::tof_channel::Status::entry)>::value &&
              tof_capture::kModeEnvelope == encoding(TofMode::kEnvelope) &&
              tof_capture::kModeCarrier == encoding(TofMode::kCarrier));

// ---- timebase -----------------------------------------------------------------
// One tick every prescale+1 clocks; the timestamp counts ticks and wraps at
// 2^32. The epoch strobe marks the tick on which bits 22:0 of the timestamp
// roll over: a pulse that has seen three epochs is longer than 2^24 ticks, so
// widths saturate exactly without a per-clock width counter.
struct TofTimebaseRegs {
  UInt<16> prescale_count;  // clocks since the last tick
  UInt<32> timestamp;       // ticks since reset, wrapping
  bool operator==(const TofTimebaseRegs&) const = default;
  ODOLOC_FIELDS(prescale_count, timestamp)
};

class TofTimebase : public Registers<TofTimebaseRegs> {
 public:
  static constexpr int kEpochBits = tof_capture::kEpochBits;
  struct In {
    UInt<16> prescale;
    UInt<1> reset;
  };

  [[nodiscard]] bool tick(UInt<16> prescale) const { return r_.prescale_count >= prescale; }
  [[nodiscard]] bool epoch(UInt<16> prescale) const {
    constexpr std::uint64_t kEpochMask = (std::uint64_t{1} << kEpochBits) - 1;
    return tick(prescale) && ((r_.timestamp.value() + 1) & kEpochMask) == 0;
  }

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    if (tick(in.prescale))
      return {UInt<16>{}, (r_.timestamp + UInt<1>{1}).wrap<32>()};
    return {(r_.prescale_count + UInt<1>{1}).wrap<16>(), r_.timestamp};
  }
  [[nodiscard]] bool idle(const In&) const { return false; }  // counts every clock

  // Fast-forward (clocked.hpp): the prescaler restarts after its tick; the
  // next epoch is the tick that brings the timestamp's low kEpochBits to 0.
  [[nodiscard]] std::uint64_t clocks_to_epoch(UInt<16> prescale) const {
    constexpr std::uint64_t kEpochTicks = std::uint64_t{1} << kEpochBits;
    const std::uint64_t ticks = kEpochTicks - (r_.timestamp.value() & (kEpochTicks - 1));
    return clock_of_fire(r_.prescale_count.value(), prescale.value(), ticks);
  }
  void skip(std::uint64_t n, const In& in) {
    const RestartingCount c = run_restarting(r_.prescale_count.value(), in.prescale.value(), n);
    commit({UInt<16>::truncate(c.count), UInt<32>::truncate(r_.timestamp.value() + c.fires)});
  }
};

// ---- event FIFO -----------------------------------------------------------------
// A FIFO of Depth entries with the bookkeeping that makes SPI reads lossless:
// the level captured when a read frame starts bounds what that frame's
// commit may pop, so an entry pushed while the frame runs is never popped
// unread; a full FIFO drops the new event and counts it, keeping the
// oldest, unread ones.
struct FifoControl {
  UInt<1> snapshot{};        // a read frame starts: capture the level
  UInt<6> pops{};            // a read frame committed having read this many entries
  UInt<1> flush{};           // empty, clear overflow and dropped
  UInt<1> clear_overflow{};  // w1c
};

template <class Entry, std::size_t Depth>
struct CaptureFifo {
  static_assert(Depth >= 8 && Depth <= 32 && (Depth & (Depth - 1)) == 0,
                "FIFO depth: a power of two, 8..32 (status.level is 6 bits)");
  std::array<Entry, Depth> slots{};
  UInt<5> head;            // oldest entry (mod Depth)
  UInt<6> level;           // entries held
  UInt<6> snapshot_level;  // level when the current read frame started
  UInt<1> overflow;        // sticky: an event was dropped
  UInt<16> dropped;        // events dropped since the last flush, saturating
  bool operator==(const CaptureFifo&) const = default;
  ODOLOC_FIELDS(slots, head, level, snapshot_level, overflow, dropped)

  // The k-th oldest entry (k < level).
  [[nodiscard]] const Entry& at(std::size_t k) const {
    return slots[(static_cast<std::size_t>(head.value()) + k) % Depth];
  }
  [[nodiscard]] bool quiet(const FifoControl& c) const {
    return (c.snapshot | c.pops | c.flush | c.clear_overflow).is_zero();
  }
  // This clock's controls applied to a next-state copy: pops first (they
  // free room), then flush and clear; an event pushed after them in the same
  // clock survives.
  void control(const FifoControl& c) {
    // A frame commits once: its pops end what its snapshot allowed.
    const std::uint64_t popped = std::min(c.pops.value(), snapshot_level.value());
    head = UInt<5>::truncate((head.value() + popped) % Depth);
    level = UInt<6>::truncate(level.value() - popped);
    if (!c.pops.is_zero())
      snapshot_level = UInt<6>{};
    if (c.snapshot)
      snapshot_level = level;
    if (c.flush) {
      level = UInt<6>{};
      snapshot_level = UInt<6>{};
      overflow = UInt<1>{};
      dropped = UInt<16>{};
    }
    if (c.clear_overflow)
      overflow = UInt<1>{};
  }
  void push(const Entry& e) {
    if (level.value() == Depth) {
      overflow = UInt<1>{1};
      dropped = (dropped + UInt<1>{1}).sat<16>();
      return;
    }
    slots[(static_cast<std::size_t>(head.value()) + level.value()) % Depth] = e;
    level = (level + UInt<1>{1}).wrap<6>();
  }
};

// ---- receiver channel ---------------------------------------------------------
// One FIFO entry. Envelope mode: the pulse's rise timestamp and width;
// carrier mode: a rising edge's timestamp and its number since arming.
struct TofEvent {
  UInt<32> ticks;
  UInt<24> width;  // ticks, saturating at 2^24-1
  UInt<7> edge;    // saturating at 127
  bool operator==(const TofEvent&) const = default;
  ODOLOC_FIELDS(ticks, width, edge)
};

template <std::size_t Depth>
struct TofChannelRegs {
  UInt<1> level;        // the filtered comparator level of the last clock
  UInt<1> armed;        // records events
  UInt<1> done;         // carrier mode: K edges recorded, disarmed itself
  UInt<1> in_progress;  // envelope mode: a recorded pulse has risen, not yet fallen
  UInt<2> epochs;       // epoch strobes seen during the pulse in progress, saturating
  UInt<32> rise;        // the pulse in progress: its rise timestamp
  UInt<8> edges;        // carrier mode: rising edges recorded since arming, saturating
  UInt<16> ignored;     // rising edges outside the listening window, saturating
  CaptureFifo<TofEvent, Depth> fifo;
  bool operator==(const TofChannelRegs&) const = default;
  ODOLOC_FIELDS(level, armed, done, in_progress, epochs, rise, edges, ignored, fifo)
};
// The register widths the HLS kernel mirrors by name (tof_constants.hpp).
static_assert(decltype(TofEvent::ticks)::width == tof_capture::kTimestampBits &&
              decltype(TofEvent::width)::width == tof_capture::kWidthBits &&
              decltype(TofEvent::edge)::width == tof_capture::kEdgeIndexBits &&
              decltype(TofChannelRegs<8>::epochs)::width == tof_capture::kEpochCountBits &&
              decltype(TofChannelRegs<8>::edges)::width == tof_capture::kEdgeCountBits &&
              decltype(TofChannelRegs<8>::ignored)::width == tof_capture::kCounterBits &&
              decltype(CaptureFifo<TofEvent, 8>::head)::width == tof_capture::kHeadBits &&
              decltype(CaptureFifo<TofEvent, 8>::level)::width == tof_capture::kLevelBits &&
              decltype(CaptureFifo<TofEvent, 8>::dropped)::width == tof_capture::kCounterBits &&
              decltype(TofTimebaseRegs::prescale_count)::width == tof_capture::kPrescaleBits &&
              decltype(ports::tof_channel::Pulses::EntryReg::pops)::width ==
                  tof_capture::kPopBits &&
              decltype(ports::tof::Config::CfgReg::filter_clocks)::width ==
                  tof_capture::kFilterBits &&
              logic::conditioner::kFilterBits == tof_capture::kFilterBits);

template <std::size_t Depth>
class TofChannel : public Registers<TofChannelRegs<Depth>> {
  using Base = Registers<TofChannelRegs<Depth>>;
  using Base::r_;

 public:
  using Regs = typename Base::Regs;
  static constexpr std::uint64_t kMaxWidth = UInt<24>::max_value;
  struct In {
    UInt<1> comparator;  // filtered
    UInt<32> timestamp;
    bool epoch;
    ports::tof_channel::Config cfg;
    UInt<1> arm, disarm;
    FifoControl fifo;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    n.level = in.comparator;
    n.fifo.control(in.fifo);
    if (in.fifo.flush)
      n.ignored = UInt<16>{};
    if (in.arm) {
      n.armed = UInt<1>{1};
      n.done = UInt<1>{};
      n.edges = UInt<8>{};
    }
    if (in.disarm)  // wins over arm
      n.armed = UInt<1>{};
    if (r_.in_progress && in.epoch)
      n.epochs = (n.epochs + UInt<1>{1}).template sat<2>();
    const bool rise = !r_.level && in.comparator;
    const bool fall = r_.level && !in.comparator;
    if (fall && r_.in_progress) {
      n.fifo.push({.ticks = r_.rise, .width = width(n.epochs, in.timestamp), .edge = {}});
      n.in_progress = UInt<1>{};
    }
    if (!rise || !n.armed)
      return n;
    if (!in_window(in)) {
      n.ignored = (n.ignored + UInt<1>{1}).template sat<16>();
      return n;
    }
    if (in.cfg.cfg.mode.value() == encoding(TofMode::kEnvelope)) {
      n.in_progress = UInt<1>{1};
      n.rise = in.timestamp;
      n.epochs = UInt<2>{};
      return n;
    }
    n.fifo.push({.ticks = in.timestamp, .width = {}, .edge = n.edges.template sat<7>()});
    n.edges = (n.edges + UInt<1>{1}).template sat<8>();
    if (!in.cfg.cfg.edges.is_zero() && n.edges >= in.cfg.cfg.edges) {
      n.armed = UInt<1>{};
      n.done = UInt<1>{1};
    }
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.comparator == r_.level && !(in.epoch && r_.in_progress) &&
           (in.arm | in.disarm | in.reset).is_zero() && r_.fifo.quiet(in.fifo);
  }

  // What the register file reads: tof_channel.status, events and the entry window.
  [[nodiscard]] ports::tof_channel::Status status() const {
    ports::tof_channel::Status s;
    const auto& f = r_.fifo;
    s.status.fill_level = f.level;
    s.status.not_empty = UInt<1>::truncate(!f.level.is_zero());
    s.status.in_progress = r_.in_progress;
    s.status.armed = r_.armed;
    s.status.done = r_.done;
    s.status.overflow = f.overflow;
    s.events.dropped = f.dropped;
    s.events.ignored = r_.ignored;
    for (std::size_t k = 0; k < s.entry.size(); ++k) {
      if (k >= f.level.value())
        break;
      const TofEvent& e = f.at(k);
      s.entry[k] = {.ticks = e.ticks, .width = e.width, .edge_index = e.edge, .valid = UInt<1>{1}};
    }
    return s;
  }

 private:
  // Ticks from the rise to this clock; exact below 3 * 2^23 ticks (fewer than
  // three epochs seen), and longer pulses saturate.
  [[nodiscard]] UInt<24> width(UInt<2> epochs, UInt<32> now) const {
    if (epochs.value() == 3)
      return UInt<24>::truncate(kMaxWidth);
    const std::uint64_t ticks = (now.value() - r_.rise.value()) & UInt<32>::mask;
    return UInt<24>::truncate(std::min(ticks, kMaxWidth));
  }
  // [open, close) modulo 2^32, so a window may span the timestamp wrap.
  static bool in_window(const In& in) {
    if (!in.cfg.cfg.window_enable)
      return true;
    const std::uint64_t open = in.cfg.window_open.ticks.value();
    const std::uint64_t since_open = (in.timestamp.value() - open) & UInt<32>::mask;
    const std::uint64_t length = (in.cfg.window_close.ticks.value() - open) & UInt<32>::mask;
    return since_open < length;
  }
};

// ---- sync input ---------------------------------------------------------------
template <std::size_t Depth>
struct TofSyncRegs {
  UInt<1> level;  // the filtered sync level of the last clock
  CaptureFifo<UInt<32>, Depth> fifo;
  bool operator==(const TofSyncRegs&) const = default;
  ODOLOC_FIELDS(level, fifo)
};

template <std::size_t Depth>
class TofSync : public Registers<TofSyncRegs<Depth>> {
  using Base = Registers<TofSyncRegs<Depth>>;
  using Base::r_;

 public:
  using Regs = typename Base::Regs;
  struct In {
    UInt<1> sync;  // filtered
    UInt<32> timestamp;
    UInt<1> enable;
    FifoControl fifo;
    UInt<1> reset;
  };

  [[nodiscard]] Regs eval(const In& in) const {
    if (in.reset)
      return Regs{};
    Regs n = r_;
    n.level = in.sync;
    n.fifo.control(in.fifo);
    if (in.enable && !r_.level && in.sync)
      n.fifo.push(in.timestamp);
    return n;
  }
  [[nodiscard]] bool idle(const In& in) const {
    return in.sync == r_.level && in.reset.is_zero() && r_.fifo.quiet(in.fifo);
  }

  // tof.sync_status and the sync entry window.
  void status(ports::tof::Status& s) const {
    const auto& f = r_.fifo;
    s.sync_status.fill_level = f.level;
    s.sync_status.overflow = f.overflow;
    s.sync_status.dropped = f.dropped;
    for (std::size_t k = 0; k < s.sync_entry.size() && k < f.level.value(); ++k)
      s.sync_entry[k].ticks = f.at(k);
  }
};

// ---- the unit -------------------------------------------------------------------
template <std::size_t Channels>
struct TofCaptureInputs {
  UInt<Channels> comparators;  // receiver comparator outputs, channel i in bit i, asynchronous
  UInt<1> sync;                // sync input (RF trigger, beacon-cycle start), asynchronous
  ports::tof::Pulses tof;      // command.*, sync_status.overflow clear, sync_entry pops
  std::array<ports::tof_channel::Pulses, kTofChannelInstances> channel{};  // overflow clear, pops
  UInt<1> snapshot;   // a read frame starts (the register file captures its snapshot)
  UInt<1> clear_all;  // odometry.command.clear_flags: every sticky flag of the fabric
  UInt<1> reset;
  ODOLOC_FIELDS(comparators, sync, tof, channel, snapshot, clear_all, reset)
};

template <std::size_t Channels = kTofChannelInstances, std::size_t Depth = tof_capture::kDepth>
class TofCapture {
  static_assert(Channels >= 1 && Channels <= kTofChannelInstances);
  static constexpr int kLines = static_cast<int>(Channels) + 1;  // the sync input is the top line

 public:
  using In = TofCaptureInputs<Channels>;
  using Config = ports::Config;  // reads its tof and tof_channel blocks
  using Conditioner = InputConditioner<kLines>;
  static constexpr std::size_t kChannels = Channels;
  static constexpr std::size_t kDepth = Depth;

  // The wires that cross the children, from the current registers only.
  struct Wires {
    UInt<kLines> filtered;  // conditioner -> channels, sync
    UInt<32> timestamp;     // timebase -> channels, sync
    bool epoch;             // timebase -> channels
  };
  [[nodiscard]] Wires wires(const Config& cfg) const {
    return {.filtered = conditioner_.regs().filtered,
            .timestamp = timebase_.regs().timestamp,
            .epoch = timebase_.epoch(cfg.tof.cfg.prescale)};
  }
  static UInt<kLines> pins(const In& in) { return cat(in.sync, in.comparators); }
  static typename Conditioner::In conditioner_in(const In& in, const Config& cfg) {
    return {.pins = pins(in), .filter_clocks = cfg.tof.cfg.filter_clocks, .reset = in.reset};
  }
  static TofTimebase::In timebase_in(const In& in, const Config& cfg) {
    return {.prescale = cfg.tof.cfg.prescale, .reset = in.reset};
  }
  static typename TofChannel<Depth>::In channel_in(std::size_t i, const Wires& w, const In& in,
                                                   const Config& cfg) {
    const auto& command = in.tof.command;
    const auto& pulses = in.channel[i];
    const auto bit = [i](auto mask) { return UInt<1>::truncate(mask.value() >> i); };
    return {.comparator = bit(w.filtered),
            .timestamp = w.timestamp,
            .epoch = w.epoch,
            .cfg = cfg.tof_channel[i],
            .arm = bit(command.arm),
            .disarm = bit(command.disarm),
            .fifo = {.snapshot = in.snapshot,
                     .pops = pulses.entry.pops,
                     .flush = bit(command.flush),
                     .clear_overflow = pulses.status.overflow | in.clear_all},
            .reset = in.reset};
  }
  static typename TofSync<Depth>::In sync_in(const Wires& w, const In& in, const Config& cfg) {
    return {.sync = w.filtered.template bit<kLines - 1>(),
            .timestamp = w.timestamp,
            .enable = cfg.tof.cfg.sync_enable,
            .fifo = {.snapshot = in.snapshot,
                     .pops = in.tof.sync_entry.pops,
                     .flush = in.tof.command.sync_flush,
                     .clear_overflow = in.tof.sync_status.overflow | in.clear_all},
            .reset = in.reset};
  }

  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step(const In& in, const Config& cfg, const Order& order = {}) {
    if (!has_control(in)) {
      step_pins<G>(in, cfg, order);
      return;
    }
    step_all<G>(in, cfg, order);
  }
  // One clock whose inputs carry no control (no command, frame, pop, clear or
  // reset: the chip's quiet clocks), only pins. Fast path: every channel has
  // seen the settled inputs, so only the timebase moves (an epoch may end a
  // pulse's exact-width range: full path).
  template <Gating G = Gating::kOn, class Order = DeclarationOrder>
  void step_pins(const In& in, const Config& cfg, const Order& order = {}) {
    if (G == Gating::kOn && quiet(in) && !timebase_.epoch(cfg.tof.cfg.prescale)) {
      order([&] { clock_block<G>(timebase_, timebase_in(in, cfg)); });
      return;
    }
    step_all<G>(in, cfg, order);
  }
  // Fast-forward (clocked.hpp): while quiet, only the timebase moves, until
  // the next epoch tick.
  [[nodiscard]] std::uint64_t clocks_until_event(const In& in, const Config& cfg) const {
    return quiet(in) && !has_control(in) ? timebase_.clocks_to_epoch(cfg.tof.cfg.prescale) : 0;
  }
  void skip(std::uint64_t n, const In& in, const Config& cfg) {
    timebase_.skip(n, timebase_in(in, cfg));
  }
  // n clocks with `in` held: stepped through its events, skipped between.
  void advance(std::uint64_t n, const In& in, const Config& cfg) {
    fast_forward(*this, n, in, cfg);
  }
  [[nodiscard]] bool idle(const In& in, const Config& cfg) const {
    const Wires w = wires(cfg);
    bool idle = conditioner_.idle(conditioner_in(in, cfg)) &&
                timebase_.idle(timebase_in(in, cfg)) && sync_.idle(sync_in(w, in, cfg));
    for (std::size_t i = 0; i < Channels; ++i)
      idle = idle && channels_[i].idle(channel_in(i, w, in, cfg));
    return idle;
  }
  void reset_now() {
    ports_ = {};
    settled_ = false;
    conditioner_.reset_now();
    timebase_.reset_now();
    sync_.reset_now();
    for (auto& c : channels_)
      c.reset_now();
  }

  // Fills the tof.* and tof_channel.* status the register file reads.
  void status(ports::Status& s) const {
    s.tof.info.fifo_depth = UInt<8>{Depth};
    s.tof.info.channels = UInt<8>{Channels};
    s.tof.timestamp.ticks = timebase_.regs().timestamp;
    sync_.status(s.tof);
    for (std::size_t i = 0; i < Channels; ++i)
      s.tof_channel[i] = channels_[i].status();
  }

  [[nodiscard]] const typename Conditioner::Regs& conditioner() const {
    return conditioner_.regs();
  }
  [[nodiscard]] const TofTimebase::Regs& timebase() const { return timebase_.regs(); }
  [[nodiscard]] const typename TofChannel<Depth>::Regs& channel(std::size_t i) const {
    return channels_[i].regs();
  }
  [[nodiscard]] const typename TofSync<Depth>::Regs& sync() const { return sync_.regs(); }

  template <class V>
  void trace(V& v) const {
    trace_fields(v, ports_);
    trace_scope(v, "conditioner", conditioner_);
    trace_scope(v, "timebase", timebase_);
    trace_scope(v, "sync", sync_);
    for (std::size_t i = 0; i < Channels; ++i)
      trace_scope(v, regs::tof_channel::kInstanceNames[i], channels_[i]);
  }

 private:
  // A command, frame, pop, clear or reset this clock.
  static bool has_control(const In& in) {
    return !(in.snapshot | in.clear_all | in.reset).is_zero() || any_set(in.tof) ||
           any_set(in.channel);
  }
  // Settled after the last full clock and the pins unchanged.
  [[nodiscard]] bool quiet(const In& in) const {
    return settled_ && pins(in) == conditioner_.regs().filtered;
  }
  template <Gating G, class Order>
  [[gnu::noinline]] void step_all(const In& in, const Config& cfg, const Order& order) {
    const Wires w = wires(cfg);
    ports_ = in;
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      order([&] { clock_block<G>(conditioner_, conditioner_in(in, cfg)); },
            [&] { clock_block<G>(timebase_, timebase_in(in, cfg)); },
            [&] { clock_block<G>(sync_, sync_in(w, in, cfg)); },
            [&] { clock_block<G>(channels_[I], channel_in(I, w, in, cfg)); }...);
    }
    (std::make_index_sequence<Channels>{});
    settled_ = G == Gating::kOn && settled();  // only the gated step reads it
  }
  // Every channel and the sync input have seen the conditioned levels, the
  // conditioner holds its pins and the last clock carried no control:
  // nothing but the timebase moves until a pin changes, a command or read
  // arrives, or an epoch comes (and the inputs recorded for the waveform are
  // those of every fast-path clock).
  [[nodiscard]] bool settled() const {
    std::uint64_t levels = sync_.regs().level.value() << Channels;
    for (std::size_t i = 0; i < Channels; ++i)
      levels |= channels_[i].regs().level.value() << i;
    return conditioner_.settled() && levels == conditioner_.regs().filtered.value() &&
           (ports_.snapshot | ports_.clear_all | ports_.reset).is_zero() && !any_set(ports_.tof) &&
           !any_set(ports_.channel);
  }

  In ports_;              // the inputs of the last full clock, for waveforms
  bool settled_ = false;  // simulator bookkeeping, not a register: settled() after the last clock
  Conditioner conditioner_;
  TofTimebase timebase_;
  TofSync<Depth> sync_;
  std::array<TofChannel<Depth>, Channels> channels_;
};

}  // namespace odoloc::rtl
