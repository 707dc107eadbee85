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
// analytic fast-forward can jump the timebase between events. The logic:
// logic/tof_capture.hpp (the one source, also the HLS kernel's). Here: what
// only a simulator needs around it (field lists, the waveform's ports, the
// quiet fast path and activity gating, the fast-forward).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "odoloc/logic/tof_capture.hpp"
#include "odoloc/ports.hpp"
#include "odoloc/rtl/bits.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "odoloc/rtl/family.hpp"
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

// ---- the leaves (logic/tof_capture.hpp) -----------------------------------------
ODOLOC_LOGIC_FIELDS(logic::tof::TimebaseRegs, prescale_count, timestamp)
ODOLOC_LOGIC_FIELDS(logic::tof::Event, ticks, width, edge)
ODOLOC_LOGIC_FIELDS(logic::tof::SyncEvent, ticks)
ODOLOC_LOGIC_FIELDS_OF((class Entry, int Depth), (logic::tof::Fifo<Entry, Family, Depth>), slots,
                       head, level, snapshot_level, overflow, dropped)
ODOLOC_LOGIC_FIELDS_OF((int Depth), (logic::tof::ChannelRegs<Family, Depth>), level, armed, done,
                       in_progress, epochs, rise, edges, ignored, fifo)
ODOLOC_LOGIC_FIELDS_OF((int Depth), (logic::tof::SyncRegs<Family, Depth>), level, fifo)

using TofTimebaseRegs = logic::tof::TimebaseRegs<Family>;
using TofEvent = logic::tof::Event<Family>;
using TofSyncEvent = logic::tof::SyncEvent<Family>;
using FifoControl = logic::tof::FifoControl<Family>;
template <class Entry, std::size_t Depth>
using CaptureFifo = logic::tof::Fifo<Entry, Family, static_cast<int>(Depth)>;
template <std::size_t Depth>
using TofChannelRegs = logic::tof::ChannelRegs<Family, static_cast<int>(Depth)>;
template <std::size_t Depth>
using TofSyncRegs = logic::tof::SyncRegs<Family, static_cast<int>(Depth)>;

// The k-th oldest entry of a FIFO (k < level).
template <class Entry, int Depth>
[[nodiscard]] const Entry& fifo_entry(const logic::tof::Fifo<Entry, Family, Depth>& f,
                                      std::size_t k) {
  return logic::tof::CaptureFifo<Entry, Family, Depth>::at(f, static_cast<int>(k));
}

// The register widths the HLS kernel mirrors by name (tof_constants.hpp).
static_assert(decltype(TofChannelRegs<8>::ignored)::width == tof_capture::kCounterBits &&
              decltype(ports::tof_channel::Pulses::EntryReg::pops)::width ==
                  tof_capture::kPopBits &&
              decltype(ports::tof::Config::CfgReg::filter_clocks)::width ==
                  tof_capture::kFilterBits &&
              decltype(ports::tof::Config::CfgReg::prescale)::width == tof_capture::kPrescaleBits &&
              logic::conditioner::kFilterBits == tof_capture::kFilterBits);

// One tick every prescale+1 clocks, a 32-bit timestamp, the epoch strobe
// (logic/tof_capture.hpp).
class TofTimebase : public Registers<TofTimebaseRegs> {
  using Logic = logic::tof::Timebase<Family>;

 public:
  static constexpr int kEpochBits = tof_capture::kEpochBits;
  using In = logic::tof::TimebaseIn<Family>;

  [[nodiscard]] bool tick(UInt<16> prescale) const { return Logic::tick(r_, prescale); }
  [[nodiscard]] bool epoch(UInt<16> prescale) const { return Logic::epoch(r_, prescale); }
  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
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

// A receiver channel: envelope or carrier events into its FIFO.
template <std::size_t Depth>
class TofChannel : public Registers<TofChannelRegs<Depth>> {
  using Base = Registers<TofChannelRegs<Depth>>;
  using Base::r_;
  using Logic = logic::tof::Channel<Family, static_cast<int>(Depth)>;

 public:
  using Regs = typename Base::Regs;
  using In = logic::tof::ChannelIn<Family, ports::tof_channel::Config>;

  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  [[nodiscard]] bool idle(const In& in) const {
    return in.comparator == r_.level && !(in.epoch && r_.in_progress) &&
           (in.arm | in.disarm | in.reset).is_zero() && Logic::Fifo::quiet(in.fifo);
  }
  // What the register file reads: tof_channel.status, events and the entry window.
  [[nodiscard]] ports::tof_channel::Status status() const {
    return Logic::template status<ports::tof_channel::Status>(r_);
  }
};

// The sync input: its rising edges into its FIFO.
template <std::size_t Depth>
class TofSync : public Registers<TofSyncRegs<Depth>> {
  using Base = Registers<TofSyncRegs<Depth>>;
  using Base::r_;
  using Logic = logic::tof::Sync<Family, static_cast<int>(Depth)>;

 public:
  using Regs = typename Base::Regs;
  using In = logic::tof::SyncIn<Family>;

  [[nodiscard]] Regs eval(const In& in) const { return Logic::next(r_, in); }
  [[nodiscard]] bool idle(const In& in) const {
    return in.sync == r_.level && in.reset.is_zero() && Logic::Fifo::quiet(in.fifo);
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
  using Logic = logic::tof::TofCapture<Family, static_cast<int>(Channels), static_cast<int>(Depth)>;

 public:
  using In = TofCaptureInputs<Channels>;
  using Config = ports::Config;  // reads its tof and tof_channel blocks
  using Conditioner = InputConditioner<kLines>;
  static constexpr std::size_t kChannels = Channels;
  static constexpr std::size_t kDepth = Depth;

  using Wires = logic::tof::Wires<Family, static_cast<int>(Channels)>;
  // The wires that cross the children, from the current registers only, and
  // each child's inputs (logic/tof_capture.hpp).
  [[nodiscard]] Wires wires(const Config& cfg) const {
    return Logic::wires(conditioner_.regs(), timebase_.regs(), cfg);
  }
  static UInt<kLines> pins(const In& in) { return Logic::pins(in); }
  static typename Conditioner::In conditioner_in(const In& in, const Config& cfg) {
    return Logic::conditioner_in(in, cfg);
  }
  static TofTimebase::In timebase_in(const In& in, const Config& cfg) {
    return Logic::timebase_in(in, cfg);
  }
  static typename TofChannel<Depth>::In channel_in(std::size_t i, const Wires& w, const In& in,
                                                   const Config& cfg) {
    return Logic::channel_in(static_cast<int>(i), w, in, cfg);
  }
  static typename TofSync<Depth>::In sync_in(const Wires& w, const In& in, const Config& cfg) {
    return Logic::sync_in(w, in, cfg);
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
    Logic::unit_status(timebase_.regs(), sync_.regs(), s);
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
  [[gnu::noinline, gnu::flatten]] void step_all(const In& in, const Config& cfg,
                                                const Order& order) {
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
