// The ultrasonic time-of-flight capture unit's logic, written once
// (docs/tof-capture.md; docs/hls.md, "One source per block"): the cycle
// model (rtl/tof_capture.hpp) runs it with the model's types, the HLS kernel
// (hls/tof_kernel.hpp) with the vendor's, and `odoloc export-hls` exports
// this file.
//
//   comparators[C], sync -> input conditioner (C+1 lines) --filtered--> channel x C --> FIFO
//                                                               +-> sync input --> FIFO
//   timebase (prescaler, 32-bit timestamp, epoch strobe every 2^23 ticks) --timestamp--^
//
// Events are timestamped in the clock their filtered level change reaches
// the channel: a pin change in clock t is stamped with the timestamp of clock
// t+N+2 (N = max(filter_clocks, 1)); the driver subtracts that constant.
// Widths and parameters: rtl/tof_constants.hpp. Each leaf is Regs, In and a
// next(); the unit (TofCapture) computes every wire that crosses the leaves
// from the current registers, then each leaf's In. The unit's configuration,
// strobes and status are the register map's port structs (odoloc/ports.hpp
// in the model, odoloc/logic/ports.hpp in the kernel), taken as template
// parameters: Config has tof and tof_channel[i], Status the same, ModuleIn
// comparators, sync, tof and channel[i] (the Pulses), snapshot, clear_all
// and reset.
// C++14, no heap, no containers, static loop bounds (int_family.hpp).
#pragma once

#include <type_traits>

#include "odoloc/logic/input_conditioner.hpp"
#include "odoloc/logic/int_family.hpp"
#include "odoloc/logic/ports.hpp"
#include "odoloc/rtl/tof_constants.hpp"

namespace odoloc {
namespace logic {
namespace tof {

namespace constants = rtl::tof_capture;

template <class F>
using Timestamp = uint<F, constants::kTimestampBits>;
template <class F>
using Level = uint<F, constants::kLevelBits>;
template <class F>
using Count = uint<F, constants::kCounterBits>;  // saturating

// ---- timebase -----------------------------------------------------------------
// One tick every prescale+1 clocks; the timestamp counts ticks and wraps at
// 2^32. The epoch strobe marks the tick on which bits 22:0 of the timestamp
// roll over: a pulse that has seen three epochs is longer than 2^24 ticks, so
// widths saturate exactly without a per-clock width counter.
template <class F>
struct TimebaseRegs {
  uint<F, constants::kPrescaleBits> prescale_count{0};  // clocks since the last tick
  Timestamp<F> timestamp{0};                            // ticks since reset, wrapping
};
template <class F>
struct TimebaseIn {
  uint<F, constants::kPrescaleBits> prescale{0};
  uint<F, 1> reset{0};
};

template <class F>
struct Timebase {
  using R = TimebaseRegs<F>;
  using Prescale = uint<F, constants::kPrescaleBits>;
  static bool tick(const R& r, Prescale prescale) { return r.prescale_count >= prescale; }
  static bool epoch(const R& r, Prescale prescale) {
    const Timestamp<F> next = wrap<Timestamp<F> >(r.timestamp + uint<F, 1>(1));
    return tick(r, prescale) && is_zero(bits<constants::kEpochBits - 1, 0>(next));
  }
  static R next(const R& r, const TimebaseIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    if (tick(r, in.prescale))
      return R{Prescale(0), wrap<Timestamp<F> >(r.timestamp + uint<F, 1>(1))};
    return R{wrap<Prescale>(r.prescale_count + uint<F, 1>(1)), r.timestamp};
  }
};

// ---- event FIFO -----------------------------------------------------------------
// A FIFO of Depth entries with the bookkeeping that makes SPI reads lossless:
// the level captured when a read frame starts bounds what that frame's
// commit may pop, so an entry pushed while the frame runs is never popped
// unread; a full FIFO drops the new event and counts it, keeping the
// oldest, unread ones.
template <class F>
struct FifoControl {
  uint<F, 1> snapshot{0};        // a read frame starts: capture the level
  Level<F> pops{0};              // a read frame committed having read this many entries
  uint<F, 1> flush{0};           // empty, clear overflow and dropped
  uint<F, 1> clear_overflow{0};  // w1c
};

// One FIFO entry of a channel. Envelope mode: the pulse's rise timestamp and
// width; carrier mode: a rising edge's timestamp and its number since arming.
template <class F>
struct Event {
  Timestamp<F> ticks{0};
  uint<F, constants::kWidthBits> width{0};     // ticks, saturating at 2^24-1
  uint<F, constants::kEdgeIndexBits> edge{0};  // saturating at 127
};
// One FIFO entry of the sync input.
template <class F>
struct SyncEvent {
  Timestamp<F> ticks{0};
};

// log2 of a FIFO depth (8, 16 or 32).
constexpr int bits_for_depth(int depth) {
  return depth == 8 ? 3 : depth == 16 ? 4 : 5;
}

template <class Entry, class F, int Depth>
struct Fifo {
  Entry slots[Depth];
  uint<F, constants::kHeadBits> head{0};  // oldest entry (mod Depth)
  Level<F> level{0};                      // entries held
  Level<F> snapshot_level{0};             // level when the current read frame started
  uint<F, 1> overflow{0};                 // sticky: an event was dropped
  Count<F> dropped{0};                    // events dropped since the last flush, saturating
};

template <class Entry, class F, int Depth>
struct CaptureFifo {
  static_assert(Depth >= 8 && Depth <= 32 && (Depth & (Depth - 1)) == 0,
                "FIFO depth: a power of two, 8..32 (status.level is 6 bits)");
  using R = Fifo<Entry, F, Depth>;
  using Slot = uint<F, bits_for_depth(Depth)>;  // a position, mod Depth
  using Head = uint<F, constants::kHeadBits>;

  // The k-th oldest entry (k < level).
  static const Entry& at(const R& f, int k) {
    return f.slots[to_s64(wrap<Slot>(f.head + uint<F, constants::kLevelBits>(k)))];
  }
  static bool quiet(const FifoControl<F>& c) {
    return is_zero(c.snapshot | c.flush | c.clear_overflow) && is_zero(c.pops);
  }
  // This clock's controls applied to a next-state copy: pops first (they
  // free room; a frame commits once, its pops end what its snapshot
  // allowed), then snapshot, flush and clear; an event pushed after them in
  // the same clock survives.
  static void control(R& f, const FifoControl<F>& c) {
    const Level<F> popped = c.pops < f.snapshot_level ? c.pops : f.snapshot_level;
    f.head = wrap<Head>(wrap<Slot>(f.head + popped));
    f.level = wrap<Level<F> >(f.level - popped);
    if (!is_zero(c.pops))
      f.snapshot_level = Level<F>(0);
    if (!is_zero(c.snapshot))
      f.snapshot_level = f.level;
    if (!is_zero(c.flush)) {
      f.level = Level<F>(0);
      f.snapshot_level = Level<F>(0);
      f.overflow = uint<F, 1>(0);
      f.dropped = Count<F>(0);
    }
    if (!is_zero(c.clear_overflow))
      f.overflow = uint<F, 1>(0);
  }
  static void push(R& f, const Entry& e) {
    if (to_s64(f.level) == Depth) {
      f.overflow = uint<F, 1>(1);
      if (to_s64(f.dropped) != kCountMax)
        f.dropped = wrap<Count<F> >(f.dropped + uint<F, 1>(1));
      return;
    }
    f.slots[to_s64(wrap<Slot>(f.head + f.level))] = e;
    f.level = wrap<Level<F> >(f.level + uint<F, 1>(1));
  }

 private:
  static constexpr long long kCountMax = (1LL << constants::kCounterBits) - 1;
};

// ---- receiver channel ---------------------------------------------------------
template <class F, int Depth>
struct ChannelRegs {
  uint<F, 1> level{0};        // the filtered comparator level of the last clock
  uint<F, 1> armed{0};        // records events
  uint<F, 1> done{0};         // carrier mode: K edges recorded, disarmed itself
  uint<F, 1> in_progress{0};  // envelope mode: a recorded pulse has risen, not yet fallen
  uint<F, constants::kEpochCountBits> epochs{0};  // epochs seen during the pulse, saturating
  Timestamp<F> rise{0};                           // the pulse in progress: its rise timestamp
  uint<F, constants::kEdgeCountBits> edges{0};    // carrier mode: rising edges since arming
  Count<F> ignored{0};  // rising edges outside the listening window, saturating
  Fifo<Event<F>, F, Depth> fifo;
};
// Config: tof_channel Config ports (cfg.mode, cfg.window_enable, cfg.edges,
// window_open, window_close).
template <class F, class Config>
struct ChannelIn {
  uint<F, 1> comparator{0};  // filtered
  Timestamp<F> timestamp{0};
  bool epoch = false;
  Config cfg;
  uint<F, 1> arm{0}, disarm{0};
  FifoControl<F> fifo;
  uint<F, 1> reset{0};
};

template <class F, int Depth>
struct Channel {
  using R = ChannelRegs<F, Depth>;
  using Fifo = CaptureFifo<Event<F>, F, Depth>;
  using Width = uint<F, constants::kWidthBits>;

  template <class Config>
  static R next(const R& r, const ChannelIn<F, Config>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    n.level = in.comparator;
    Fifo::control(n.fifo, in.fifo);
    if (!is_zero(in.fifo.flush))
      n.ignored = Count<F>(0);
    if (!is_zero(in.arm)) {
      n.armed = uint<F, 1>(1);
      n.done = uint<F, 1>(0);
      n.edges = Edges(0);
    }
    if (!is_zero(in.disarm))  // wins over arm
      n.armed = uint<F, 1>(0);
    if (!is_zero(r.in_progress) && in.epoch && to_s64(n.epochs) != kMaxEpochs)
      n.epochs = wrap<Epochs>(n.epochs + uint<F, 1>(1));
    const bool rise = is_zero(r.level) && !is_zero(in.comparator);
    const bool fall = !is_zero(r.level) && is_zero(in.comparator);
    if (fall && !is_zero(r.in_progress)) {  // recorded whole, even if disarmed meanwhile
      Event<F> e;
      e.ticks = r.rise;
      e.width = width(r, n.epochs, in.timestamp);
      Fifo::push(n.fifo, e);
      n.in_progress = uint<F, 1>(0);
    }
    if (!rise || is_zero(n.armed))
      return n;
    if (!in_window(in)) {
      if (to_s64(n.ignored) != kMaxCount)
        n.ignored = wrap<Count<F> >(n.ignored + uint<F, 1>(1));
      return n;
    }
    if (to_s64(in.cfg.cfg.mode) == constants::kModeEnvelope) {
      n.in_progress = uint<F, 1>(1);
      n.rise = in.timestamp;
      n.epochs = Epochs(0);
      return n;
    }
    Event<F> e;
    e.ticks = in.timestamp;
    e.edge = to_s64(n.edges) < kMaxEdgeIndex ? wrap<EdgeIndex>(n.edges) : EdgeIndex(kMaxEdgeIndex);
    Fifo::push(n.fifo, e);
    if (to_s64(n.edges) != kMaxEdges)
      n.edges = wrap<Edges>(n.edges + uint<F, 1>(1));
    if (!is_zero(in.cfg.cfg.edges) && n.edges >= in.cfg.cfg.edges) {  // K edges: disarm
      n.armed = uint<F, 1>(0);
      n.done = uint<F, 1>(1);
    }
    return n;
  }

  // What the register file reads: tof_channel.status, events and the entry
  // window (the k-th oldest event in entry k, all 0 beyond the level).
  template <class Status>
  static Status status(const R& r) {
    Status s;
    const typename Fifo::R& f = r.fifo;
    s.status.fill_level = f.level;
    s.status.not_empty = wrap<uint<F, 1> >(!is_zero(f.level));
    s.status.in_progress = r.in_progress;
    s.status.armed = r.armed;
    s.status.done = r.done;
    s.status.overflow = f.overflow;
    s.events.dropped = f.dropped;
    s.events.ignored = r.ignored;
    for (int k = 0; k < constants::kWindow; ++k) {
      if (k < to_s64(f.level)) {
        const Event<F>& e = Fifo::at(f, k);
        s.entry[k].ticks = e.ticks;
        s.entry[k].width = e.width;
        s.entry[k].edge_index = e.edge;
        s.entry[k].valid = uint<F, 1>(1);
      }
    }
    return s;
  }

 private:
  using Epochs = uint<F, constants::kEpochCountBits>;
  using Edges = uint<F, constants::kEdgeCountBits>;
  using EdgeIndex = uint<F, constants::kEdgeIndexBits>;
  static constexpr long long kMaxEpochs = (1LL << constants::kEpochCountBits) - 1;
  static constexpr long long kMaxWidth = (1LL << constants::kWidthBits) - 1;
  static constexpr long long kMaxEdgeIndex = (1LL << constants::kEdgeIndexBits) - 1;
  static constexpr long long kMaxEdges = (1LL << constants::kEdgeCountBits) - 1;
  static constexpr long long kMaxCount = (1LL << constants::kCounterBits) - 1;

  // Ticks from the rise to now; exact below 3 * 2^23 ticks (fewer than three
  // epochs seen), and longer pulses saturate.
  static Width width(const R& r, Epochs epochs, Timestamp<F> now) {
    if (to_s64(epochs) == kMaxEpochs)
      return Width(kMaxWidth);
    const Timestamp<F> ticks = wrap<Timestamp<F> >(now - r.rise);
    return to_s64(ticks) > kMaxWidth ? Width(kMaxWidth) : wrap<Width>(ticks);
  }
  // [open, close) modulo 2^32, so a window may span the timestamp wrap.
  template <class Config>
  static bool in_window(const ChannelIn<F, Config>& in) {
    if (is_zero(in.cfg.cfg.window_enable))
      return true;
    const Timestamp<F> since_open = wrap<Timestamp<F> >(in.timestamp - in.cfg.window_open.ticks);
    const Timestamp<F> length =
        wrap<Timestamp<F> >(in.cfg.window_close.ticks - in.cfg.window_open.ticks);
    return since_open < length;
  }
};

// ---- sync input ---------------------------------------------------------------
template <class F, int Depth>
struct SyncRegs {
  uint<F, 1> level{0};  // the filtered sync level of the last clock
  Fifo<SyncEvent<F>, F, Depth> fifo;
};
template <class F>
struct SyncIn {
  uint<F, 1> sync{0};  // filtered
  Timestamp<F> timestamp{0};
  uint<F, 1> enable{0};
  FifoControl<F> fifo;
  uint<F, 1> reset{0};
};

template <class F, int Depth>
struct Sync {
  using R = SyncRegs<F, Depth>;
  using Fifo = CaptureFifo<SyncEvent<F>, F, Depth>;
  static R next(const R& r, const SyncIn<F>& in) {
    if (!is_zero(in.reset))
      return R();
    R n = r;
    n.level = in.sync;
    Fifo::control(n.fifo, in.fifo);
    if (!is_zero(in.enable) && is_zero(r.level) && !is_zero(in.sync)) {
      SyncEvent<F> e;
      e.ticks = in.timestamp;
      Fifo::push(n.fifo, e);
    }
    return n;
  }
  // tof.sync_status and the sync entry window.
  template <class TofStatus>
  static void status(const R& r, TofStatus& s) {
    const typename Fifo::R& f = r.fifo;
    s.sync_status.fill_level = f.level;
    s.sync_status.overflow = f.overflow;
    s.sync_status.dropped = f.dropped;
    for (int k = 0; k < constants::kWindow; ++k) {
      if (k < to_s64(f.level))
        s.sync_entry[k].ticks = Fifo::at(f, k).ticks;
    }
  }
};

// ---- the unit -------------------------------------------------------------------
template <class F, int Channels, int Depth>
struct Regs {
  conditioner::Regs<F, Channels + 1> conditioner;
  TimebaseRegs<F> timebase;
  SyncRegs<F, Depth> sync;
  ChannelRegs<F, Depth> rx[Channels];
};

// The unit's inputs besides configuration, in the kernel's family.
template <class F, int Channels>
struct In {
  uint<F, Channels> comparators{0};  // channel i in bit i, asynchronous
  uint<F, 1> sync{0};                // sync input (RF trigger, beacon-cycle start), asynchronous
  ports::tof::Pulses<F> tof;         // command.*, sync_status.overflow clear, sync_entry pops
  ports::tof_channel::Pulses<F> channel[constants::kChannels];  // overflow clear, pops
  uint<F, 1> snapshot{0};   // a read frame starts (the register file captures its snapshot)
  uint<F, 1> clear_all{0};  // odometry.command.clear_flags: every sticky flag of the fabric
  uint<F, 1> reset{0};
};

// The register map's blocks the unit reads and drives, in the kernel's
// family (the model passes the whole map's Config and Status, which hold
// the same members).
template <class F>
struct UnitConfig {
  ports::tof::Config<F> tof;
  ports::tof_channel::Config<F> tof_channel[constants::kChannels];
};
template <class F>
struct UnitStatus {
  ports::tof::Status<F> tof;
  ports::tof_channel::Status<F> tof_channel[constants::kChannels];
};

// The wires that cross the leaves, from the current registers only.
template <class F, int Channels>
struct Wires {
  uint<F, Channels + 1> filtered;  // conditioner -> channels, sync (the top line)
  Timestamp<F> timestamp;          // timebase -> channels, sync
  bool epoch;                      // timebase -> channels
};

template <class F, int Channels, int Depth>
struct TofCapture {
  static const int kLines = Channels + 1;
  using Conditioner = conditioner::InputConditioner<F, kLines>;
  using W = Wires<F, Channels>;

  template <class Config>
  static W wires(const conditioner::Regs<F, kLines>& conditioner, const TimebaseRegs<F>& timebase,
                 const Config& cfg) {
    W w;
    w.filtered = conditioner.filtered;
    w.timestamp = timebase.timestamp;
    w.epoch = Timebase<F>::epoch(timebase, cfg.tof.cfg.prescale);
    return w;
  }
  template <class ModuleIn>
  static uint<F, kLines> pins(const ModuleIn& in) {
    return cat(in.sync, in.comparators);
  }
  template <class ModuleIn, class Config>
  static conditioner::In<F, kLines> conditioner_in(const ModuleIn& in, const Config& cfg) {
    conditioner::In<F, kLines> c;
    c.pins = pins(in);
    c.filter_clocks = cfg.tof.cfg.filter_clocks;
    c.reset = in.reset;
    return c;
  }
  template <class ModuleIn, class Config>
  static TimebaseIn<F> timebase_in(const ModuleIn& in, const Config& cfg) {
    TimebaseIn<F> t;
    t.prescale = cfg.tof.cfg.prescale;
    t.reset = in.reset;
    return t;
  }
  // Channel i: its comparator line, the unit's command masks' bit i, its
  // FIFO's controls (a clear_all clears every overflow flag).
  template <class ModuleIn, class Config>
  static auto channel_in(int i, const W& w, const ModuleIn& in, const Config& cfg) {
    // The model's std::array element or the family's C array element.
    typedef typename std::decay<decltype(cfg.tof_channel[0])>::type ChannelConfig;
    ChannelIn<F, ChannelConfig> c;
    c.comparator = line(w.filtered, i);
    c.timestamp = w.timestamp;
    c.epoch = w.epoch;
    c.cfg = cfg.tof_channel[i];
    c.arm = line(in.tof.command.arm, i);
    c.disarm = line(in.tof.command.disarm, i);
    c.fifo.snapshot = in.snapshot;
    c.fifo.pops = in.channel[i].entry.pops;
    c.fifo.flush = line(in.tof.command.flush, i);
    c.fifo.clear_overflow = in.channel[i].status.overflow | in.clear_all;
    c.reset = in.reset;
    return c;
  }
  template <class ModuleIn, class Config>
  static SyncIn<F> sync_in(const W& w, const ModuleIn& in, const Config& cfg) {
    SyncIn<F> s;
    s.sync = bit<kLines - 1>(w.filtered);
    s.timestamp = w.timestamp;
    s.enable = cfg.tof.cfg.sync_enable;
    s.fifo.snapshot = in.snapshot;
    s.fifo.pops = in.tof.sync_entry.pops;
    s.fifo.flush = in.tof.command.sync_flush;
    s.fifo.clear_overflow = in.tof.sync_status.overflow | in.clear_all;
    s.reset = in.reset;
    return s;
  }

  // One fabric clock of the whole unit.
  template <class ModuleIn, class Config>
  static Regs<F, Channels, Depth> next(const Regs<F, Channels, Depth>& r, const ModuleIn& in,
                                       const Config& cfg) {
    const W w = wires(r.conditioner, r.timebase, cfg);
    Regs<F, Channels, Depth> n;
    n.conditioner = Conditioner::next(r.conditioner, conditioner_in(in, cfg));
    n.timebase = Timebase<F>::next(r.timebase, timebase_in(in, cfg));
    n.sync = Sync<F, Depth>::next(r.sync, sync_in(w, in, cfg));
    // Unrolled by the HLS tools: a loop inside the pipelined top function.
    for (int i = 0; i < Channels; ++i)
      n.rx[i] = Channel<F, Depth>::next(r.rx[i], channel_in(i, w, in, cfg));
    return n;
  }

  // The tof.* status the register file reads (the unit's info, the
  // timestamp, the sync input's).
  template <class Status>
  static void unit_status(const TimebaseRegs<F>& timebase, const SyncRegs<F, Depth>& sync,
                          Status& s) {
    s.tof.info.fifo_depth = uint<F, 8>(Depth);
    s.tof.info.channels = uint<F, 8>(Channels);
    s.tof.timestamp.ticks = timebase.timestamp;
    Sync<F, Depth>::status(sync, s.tof);
  }
  // Every tof.* and tof_channel.* status.
  template <class Status>
  static void status(const Regs<F, Channels, Depth>& r, Status& s) {
    unit_status(r.timebase, r.sync, s);
    typedef typename std::decay<decltype(s.tof_channel[0])>::type ChannelStatus;
    for (int i = 0; i < Channels; ++i)
      s.tof_channel[i] = Channel<F, Depth>::template status<ChannelStatus>(r.rx[i]);
  }

 private:
  template <class Mask>
  static uint<F, 1> line(const Mask& mask, int i) {
    return wrap<uint<F, 1> >(to_s64(mask) >> i);
  }
};

}  // namespace tof
}  // namespace logic
}  // namespace odoloc
