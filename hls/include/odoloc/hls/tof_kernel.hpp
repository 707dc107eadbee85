// The ultrasonic time-of-flight capture unit as an HLS kernel: one call = one
// 50 MHz fabric clock of rtl::ChipTofCapture = rtl::TofCapture<8, 16>
// (rtl_model/include/odoloc/rtl/tof_capture.hpp, docs/tof-capture.md), in
// odoloc::hls integer types (types.hpp: ap_int.h, ac_int.h or the project's
// own). C++14. Inside: the input conditioner of the 9 lines (2-flop
// synchroniser and level filter, logic/input_conditioner.hpp), the timebase
// (prescaler, 32-bit timestamp, epoch strobe), the sync input and 8 receiver
// channels, each with a 16-entry event FIFO.
//
// Inputs, per call (bit i of a mask = channel rx<i>; <i> = 0..7):
//   comparators [8]   receiver comparator pins, asynchronous
//   sync [1]          sync pin (RF trigger, beacon-cycle start), asynchronous
//   arm, disarm, flush [8 each], sync_flush [1]
//                     tof.command strobes (w1p); disarm wins over arm
//   sync_overflow_clear [1], sync_pops [4]
//                     the sync FIFO's overflow clear (w1c) and the entries a
//                     completed read frame popped (rpop)
//   rx<i>_overflow_clear [1], rx<i>_pops [4]   the same per channel
//   snapshot [1]      a read frame starts: every FIFO captures its level, the
//                     bound of that frame's pops
//   clear_all [1]     odometry.command.clear_flags: clears every overflow flag
//   reset [1]         synchronous reset of every register
//   prescale [16], filter_clocks [8], sync_enable [1]      tof.cfg
//   rx<i>_mode [1] (0 envelope, 1 carrier), rx<i>_window_enable [1],
//   rx<i>_edges [8], rx<i>_window_open [32], rx<i>_window_close [32]
//                     tof_channel.rx<i>.cfg and its listening window
// The configuration ports are the register file's stored words (wires); the
// strobes last one call.
//
// Outputs, the status wires the register file reads (snapshots, reads), i.e.
// the registers after this call's clock edge:
//   fifo_depth [8] = 16, channels [8] = 8              tof.info (constants)
//   timestamp [32]                                     tof.timestamp
//   sync_fill_level [6], sync_overflow [1], sync_dropped [16]   tof.sync_status
//   sync_entry<k>_ticks [32], k = 0..7: the k-th oldest sync entry, 0 beyond
//                     the fill level                   tof.sync_entry<k>
//   rx<i>_fill_level [6], rx<i>_not_empty [1], rx<i>_in_progress [1],
//   rx<i>_armed [1], rx<i>_done [1], rx<i>_overflow [1]   tof_channel.rx<i>.status
//   rx<i>_dropped [16], rx<i>_ignored [16]             tof_channel.rx<i>.events
//   rx<i>_entry<k>_ticks [32], _width [24], _edge_index [7], _valid [1]
//                     the k-th oldest event, all 0 beyond the fill level
//                                                      tof_channel.rx<i>.entry<k>
//
// Latency: a pin edge first applied in call t is stamped with the timestamp
// of call t + N + 2 (N = max(filter_clocks, 1)) and an entry it completes is
// in the outputs of that call; a glitch shorter than N calls never reaches a
// channel. Reset: the `reset` port, and the registers' initial values (all 0).
//
// The widths and parameters are the model's own (rtl/tof_constants.hpp, which
// the model static_asserts against its register types), so the kernel cannot
// drift from them; test_hls_tof_* proves every output equal to the model's on
// every call, and every register equal, per type family. No heap, no
// containers, no floating point, static loop bounds.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/logic/input_conditioner.hpp"
#include "odoloc/rtl/tof_constants.hpp"

namespace odoloc {
namespace hls {
namespace tof {

namespace tc = rtl::tof_capture;

// Loop labels name the loops in the HLS tools' reports; no C++ jumps to them.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-label"
#endif

constexpr int kChannels = tc::kChannels;
constexpr int kLines = kChannels + 1;  // the conditioner's lines: comparators, then sync on top
constexpr int kDepth = tc::kDepth;
constexpr int kWindow = tc::kWindow;
constexpr int kMaxWidth = (1 << tc::kWidthBits) - 1;
constexpr int kMaxEdgeIndex = (1 << tc::kEdgeIndexBits) - 1;
constexpr int kMaxEdges = (1 << tc::kEdgeCountBits) - 1;
constexpr int kMaxCount = (1 << tc::kCounterBits) - 1;
constexpr int kMaxEpochs = (1 << tc::kEpochCountBits) - 1;  // three epochs: width saturates

using Mask = uint<kChannels>;
using Lines = uint<kLines>;
using Timestamp = uint<tc::kTimestampBits>;
using Width = uint<tc::kWidthBits>;
using EdgeIndex = uint<tc::kEdgeIndexBits>;
using Edges = uint<tc::kEdgeCountBits>;
using Count = uint<tc::kCounterBits>;
using Level = uint<tc::kLevelBits>;
using Pops = uint<tc::kPopBits>;
using Slot = uint<tc::kDepthBits>;  // a FIFO position, mod kDepth

// ---- ports ----------------------------------------------------------------------
struct ChannelPulses {
  uint<1> overflow_clear;
  Pops pops;
};
struct ChannelConfig {
  uint<1> mode, window_enable;
  Edges edges;
  Timestamp window_open, window_close;
};

struct Inputs {
  Mask comparators;
  uint<1> sync;
  Mask arm, disarm, flush;
  uint<1> sync_flush;
  uint<1> sync_overflow_clear;
  Pops sync_pops;
  ChannelPulses rx_pulses[kChannels];
  uint<1> snapshot, clear_all, reset;
  uint<tc::kPrescaleBits> prescale;
  uint<tc::kFilterBits> filter_clocks;
  uint<1> sync_enable;
  ChannelConfig rx_config[kChannels];
};

struct EntryPort {
  Timestamp ticks;
  Width width;
  EdgeIndex edge_index;
  uint<1> valid;
};
struct ChannelStatus {
  Level fill_level;
  uint<1> not_empty, in_progress, armed, done, overflow;
  Count dropped, ignored;
  EntryPort entry[kWindow];
};

struct Outputs {
  uint<8> fifo_depth, channels;
  Timestamp timestamp;
  Level sync_fill_level;
  uint<1> sync_overflow;
  Count sync_dropped;
  Timestamp sync_entry[kWindow];
  ChannelStatus rx[kChannels];
};

// ---- registers (the model's, by name; arrays of structs so that every element
// gets its reset value from the default member initialisers) ------------------------
struct Event {  // rtl::TofEvent
  Timestamp ticks = 0;
  Width width = 0;
  EdgeIndex edge = 0;
};
struct SyncEvent {
  Timestamp ticks = 0;
};
template <class Entry>
struct Fifo {  // rtl::CaptureFifo<Entry, kDepth>
  Entry slots[kDepth];
  uint<tc::kHeadBits> head = 0;  // oldest entry
  Level level = 0;
  Level snapshot_level = 0;  // level when the current read frame started
  uint<1> overflow = 0;
  Count dropped = 0;
};
struct Channel {  // rtl::TofChannelRegs<kDepth>
  uint<1> level = 0, armed = 0, done = 0, in_progress = 0;
  uint<tc::kEpochCountBits> epochs = 0;
  Timestamp rise = 0;
  Edges edges = 0;
  Count ignored = 0;
  Fifo<Event> fifo;
};

struct Registers {
  logic::conditioner::Regs<Family, kLines> conditioner;
  uint<tc::kPrescaleBits> prescale_count = 0;  // the timebase
  Timestamp timestamp = 0;
  uint<1> sync_level = 0;  // the sync input
  Fifo<SyncEvent> sync_fifo;
  Channel rx[kChannels];
};

// ---- port names (testbenches only: never synthesised) ------------------------------
// Column names built at compile time: "rx3_pops", "rx3_entry5_ticks", "sync_entry5_ticks".
constexpr int kNameChars = 24;
static_assert(kChannels <= 10 && kWindow <= 10, "port names carry one digit");
struct Name {
  char text[kNameChars];
};
template <int N>
struct Names {
  Name of[N];
};

// a + digit i + b + digit k + c; a negative index is left out. Longer names
// are cut, which the testbenches' name check reports.
constexpr Name port_name(const char* a, int i, const char* b, int k = -1, const char* c = "") {
  Name name = {};
  int n = 0;
  const char* parts[3] = {a, b, c};
  const int digits[3] = {i, k, -1};
  for (int p = 0; p < 3; ++p) {
    for (const char* s = parts[p]; *s != '\0' && n < kNameChars - 1; ++s)
      name.text[n++] = *s;
    if (digits[p] >= 0 && n < kNameChars - 1)
      name.text[n++] = static_cast<char>('0' + digits[p]);
  }
  return name;
}
// "rx<i><field>" for every channel.
constexpr Names<kChannels> channel_names(const char* field) {
  Names<kChannels> names = {};
  for (int i = 0; i < kChannels; ++i)
    names.of[i] = port_name("rx", i, field);
  return names;
}
// "sync_entry<k>_ticks".
constexpr Names<kWindow> sync_entry_names() {
  Names<kWindow> names = {};
  for (int k = 0; k < kWindow; ++k)
    names.of[k] = port_name("sync_entry", k, "_ticks");
  return names;
}
// "rx<i>_entry<k><field>", channel-major.
constexpr Names<kChannels * kWindow> entry_names(const char* field) {
  Names<kChannels* kWindow> names = {};
  for (int i = 0; i < kChannels; ++i)
    for (int k = 0; k < kWindow; ++k)
      names.of[i * kWindow + k] = port_name("rx", i, "_entry", k, field);
  return names;
}

// The ports by name, in the golden vectors' column order (testbenches only).
template <class Visit>
void visit_fields(Inputs& s, Visit&& v) {
  static constexpr Names<kChannels> kOverflowClear = channel_names("_overflow_clear");
  static constexpr Names<kChannels> kPops = channel_names("_pops");
  static constexpr Names<kChannels> kMode = channel_names("_mode");
  static constexpr Names<kChannels> kWindowEnable = channel_names("_window_enable");
  static constexpr Names<kChannels> kEdges = channel_names("_edges");
  static constexpr Names<kChannels> kWindowOpen = channel_names("_window_open");
  static constexpr Names<kChannels> kWindowClose = channel_names("_window_close");
  v("comparators", s.comparators);
  v("sync", s.sync);
  v("arm", s.arm);
  v("disarm", s.disarm);
  v("flush", s.flush);
  v("sync_flush", s.sync_flush);
  v("sync_overflow_clear", s.sync_overflow_clear);
  v("sync_pops", s.sync_pops);
pulses_names:
  for (int i = 0; i < kChannels; ++i) {
    v(kOverflowClear.of[i].text, s.rx_pulses[i].overflow_clear);
    v(kPops.of[i].text, s.rx_pulses[i].pops);
  }
  v("snapshot", s.snapshot);
  v("clear_all", s.clear_all);
  v("reset", s.reset);
  v("prescale", s.prescale);
  v("filter_clocks", s.filter_clocks);
  v("sync_enable", s.sync_enable);
config_names:
  for (int i = 0; i < kChannels; ++i) {
    v(kMode.of[i].text, s.rx_config[i].mode);
    v(kWindowEnable.of[i].text, s.rx_config[i].window_enable);
    v(kEdges.of[i].text, s.rx_config[i].edges);
    v(kWindowOpen.of[i].text, s.rx_config[i].window_open);
    v(kWindowClose.of[i].text, s.rx_config[i].window_close);
  }
}
template <class Visit>
void visit_fields(Outputs& s, Visit&& v) {
  static constexpr Names<kWindow> kSyncEntry = sync_entry_names();
  static constexpr Names<kChannels> kFillLevel = channel_names("_fill_level");
  static constexpr Names<kChannels> kNotEmpty = channel_names("_not_empty");
  static constexpr Names<kChannels> kInProgress = channel_names("_in_progress");
  static constexpr Names<kChannels> kArmed = channel_names("_armed");
  static constexpr Names<kChannels> kDone = channel_names("_done");
  static constexpr Names<kChannels> kOverflow = channel_names("_overflow");
  static constexpr Names<kChannels> kDropped = channel_names("_dropped");
  static constexpr Names<kChannels> kIgnored = channel_names("_ignored");
  static constexpr Names<kChannels* kWindow> kTicks = entry_names("_ticks");
  static constexpr Names<kChannels* kWindow> kWidth = entry_names("_width");
  static constexpr Names<kChannels* kWindow> kEdgeIndex = entry_names("_edge_index");
  static constexpr Names<kChannels* kWindow> kValid = entry_names("_valid");
  v("fifo_depth", s.fifo_depth);
  v("channels", s.channels);
  v("timestamp", s.timestamp);
  v("sync_fill_level", s.sync_fill_level);
  v("sync_overflow", s.sync_overflow);
  v("sync_dropped", s.sync_dropped);
sync_entry_names:
  for (int k = 0; k < kWindow; ++k)
    v(kSyncEntry.of[k].text, s.sync_entry[k]);
channel_status_names:
  for (int i = 0; i < kChannels; ++i) {
    ChannelStatus& c = s.rx[i];
    v(kFillLevel.of[i].text, c.fill_level);
    v(kNotEmpty.of[i].text, c.not_empty);
    v(kInProgress.of[i].text, c.in_progress);
    v(kArmed.of[i].text, c.armed);
    v(kDone.of[i].text, c.done);
    v(kOverflow.of[i].text, c.overflow);
    v(kDropped.of[i].text, c.dropped);
    v(kIgnored.of[i].text, c.ignored);
  entry_port_names:
    for (int k = 0; k < kWindow; ++k) {
      const int at = i * kWindow + k;
      v(kTicks.of[at].text, c.entry[k].ticks);
      v(kWidth.of[at].text, c.entry[k].width);
      v(kEdgeIndex.of[at].text, c.entry[k].edge_index);
      v(kValid.of[at].text, c.entry[k].valid);
    }
  }
}

// ---- the logic ----------------------------------------------------------------------
inline int slot_index(Slot s) {
  return static_cast<int>(to_s64(s));
}

// One clock's controls of a FIFO (rtl::FifoControl).
struct FifoControl {
  uint<1> snapshot;
  Pops pops;
  uint<1> flush, clear_overflow;
};

// Pops first (they free room; a frame pops at most what its snapshot saw),
// then snapshot, flush and clear, as rtl::CaptureFifo::control.
template <class Entry>
inline void fifo_control(Fifo<Entry>& f, const FifoControl& c) {
  Level popped = c.pops;
  if (popped > f.snapshot_level)
    popped = f.snapshot_level;
  const Slot head = f.head + popped;
  f.head = head;
  f.level = f.level - popped;
  if (c.pops != 0)
    f.snapshot_level = 0;
  if (c.snapshot == 1)
    f.snapshot_level = f.level;
  if (c.flush == 1) {
    f.level = 0;
    f.snapshot_level = 0;
    f.overflow = 0;
    f.dropped = 0;
  }
  if (c.clear_overflow == 1)
    f.overflow = 0;
}

// A full FIFO keeps its oldest entries: the new one is dropped and counted.
template <class Entry>
inline void fifo_push(Fifo<Entry>& f, const Entry& e) {
  if (f.level == kDepth) {
    f.overflow = 1;
    if (f.dropped != kMaxCount)
      f.dropped = f.dropped + 1;
    return;
  }
  const Slot tail = f.head + f.level;
  f.slots[slot_index(tail)] = e;
  f.level = f.level + 1;
}

// The k-th oldest entry, or an all-zero one beyond the level.
template <class Entry>
inline Entry window_entry(const Fifo<Entry>& f, int k) {
  Entry e;
  if (k < f.level) {
    const Slot at = f.head + k;
    e = f.slots[slot_index(at)];
  }
  return e;
}

// The wires that cross the unit's blocks this clock, from the current
// registers only (rtl::TofCapture::Wires).
struct Wires {
  Lines filtered;
  Timestamp timestamp;
  bool epoch;
};

inline bool tick(const Registers& r, const Inputs& in) {
  return r.prescale_count >= in.prescale;
}

// The tick on which timestamp bits 22:0 roll over.
inline Wires wires(const Registers& r, const Inputs& in) {
  const Timestamp next = r.timestamp + 1;
  Wires w;
  w.filtered = r.conditioner.filtered;
  w.timestamp = r.timestamp;
  w.epoch = tick(r, in) && bits<tc::kEpochBits - 1, 0>(next) == 0;
  return w;
}

inline void count_time(Registers& n, const Registers& r, const Inputs& in) {
  if (tick(r, in)) {
    n.prescale_count = 0;
    n.timestamp = r.timestamp + 1;
  } else {
    n.prescale_count = r.prescale_count + 1;
  }
}

// Ticks from the rise to now, exact below three epochs, else saturated.
inline Width pulse_width(const Channel& n, const Channel& r, Timestamp now) {
  if (n.epochs == kMaxEpochs)
    return kMaxWidth;
  const Timestamp ticks = now - r.rise;
  if (ticks > kMaxWidth)
    return kMaxWidth;
  const Width width = ticks;
  return width;
}

// [open, close) modulo 2^32, so a window may span the timestamp's wrap.
inline bool in_window(const ChannelConfig& cfg, Timestamp now) {
  if (cfg.window_enable == 0)
    return true;
  const Timestamp since_open = now - cfg.window_open;
  const Timestamp length = cfg.window_close - cfg.window_open;
  return since_open < length;
}

// Receiver channel i (rtl::TofChannel::eval).
inline void clock_channel(Channel& n, const Channel& r, int i, const Wires& w, const Inputs& in) {
  const ChannelConfig& cfg = in.rx_config[i];
  const bool comparator = bit(w.filtered, i);
  n.level = comparator ? 1 : 0;
  FifoControl control;
  control.snapshot = in.snapshot;
  control.pops = in.rx_pulses[i].pops;
  control.flush = bit(in.flush, i) ? 1 : 0;
  control.clear_overflow = in.rx_pulses[i].overflow_clear | in.clear_all;
  fifo_control(n.fifo, control);
  if (control.flush == 1)
    n.ignored = 0;
  if (bit(in.arm, i)) {
    n.armed = 1;
    n.done = 0;
    n.edges = 0;
  }
  if (bit(in.disarm, i))  // wins over arm
    n.armed = 0;
  if (r.in_progress == 1 && w.epoch && n.epochs != kMaxEpochs)
    n.epochs = n.epochs + 1;
  const bool rise = r.level == 0 && comparator;
  const bool fall = r.level == 1 && !comparator;
  if (fall && r.in_progress == 1) {  // recorded whole, even if disarmed meanwhile
    Event e;
    e.ticks = r.rise;
    e.width = pulse_width(n, r, w.timestamp);
    fifo_push(n.fifo, e);
    n.in_progress = 0;
  }
  if (!rise || n.armed == 0)
    return;
  if (!in_window(cfg, w.timestamp)) {
    if (n.ignored != kMaxCount)
      n.ignored = n.ignored + 1;
    return;
  }
  if (cfg.mode == tc::kModeEnvelope) {
    n.in_progress = 1;
    n.rise = w.timestamp;
    n.epochs = 0;
    return;
  }
  Event e;
  e.ticks = w.timestamp;
  e.edge = kMaxEdgeIndex;
  if (n.edges < kMaxEdgeIndex)
    e.edge = n.edges;
  fifo_push(n.fifo, e);
  if (n.edges != kMaxEdges)
    n.edges = n.edges + 1;
  if (cfg.edges != 0 && n.edges >= cfg.edges) {  // K edges recorded: disarm
    n.armed = 0;
    n.done = 1;
  }
}

// The sync input (rtl::TofSync::eval): rising edges into its FIFO.
inline void clock_sync(Registers& n, const Registers& r, const Wires& w, const Inputs& in) {
  const bool sync = bit(w.filtered, kChannels);
  n.sync_level = sync ? 1 : 0;
  FifoControl control;
  control.snapshot = in.snapshot;
  control.pops = in.sync_pops;
  control.flush = in.sync_flush;
  control.clear_overflow = in.sync_overflow_clear | in.clear_all;
  fifo_control(n.sync_fifo, control);
  if (in.sync_enable == 1 && r.sync_level == 0 && sync) {
    SyncEvent e;
    e.ticks = w.timestamp;
    fifo_push(n.sync_fifo, e);
  }
}

// What the register file reads (rtl::TofCapture::status).
inline void drive(Outputs& out, const Registers& n) {
  out.fifo_depth = kDepth;
  out.channels = kChannels;
  out.timestamp = n.timestamp;
  out.sync_fill_level = n.sync_fifo.level;
  out.sync_overflow = n.sync_fifo.overflow;
  out.sync_dropped = n.sync_fifo.dropped;
sync_window_loop:
  for (int k = 0; k < kWindow; ++k) {
#pragma HLS unroll
    out.sync_entry[k] = window_entry(n.sync_fifo, k).ticks;
  }
status_loop:
  for (int i = 0; i < kChannels; ++i) {
#pragma HLS unroll
    const Channel& c = n.rx[i];
    ChannelStatus& s = out.rx[i];
    s.fill_level = c.fifo.level;
    s.not_empty = c.fifo.level != 0 ? 1 : 0;
    s.in_progress = c.in_progress;
    s.armed = c.armed;
    s.done = c.done;
    s.overflow = c.fifo.overflow;
    s.dropped = c.fifo.dropped;
    s.ignored = c.ignored;
  window_loop:
    for (int k = 0; k < kWindow; ++k) {
#pragma HLS unroll
      const Event e = window_entry(c.fifo, k);
      s.entry[k].ticks = e.ticks;
      s.entry[k].width = e.width;
      s.entry[k].edge_index = e.edge;
      s.entry[k].valid = k < c.fifo.level ? 1 : 0;
    }
  }
}

// One fabric clock: the next registers from the current ones (`r` is read
// only before the commit) and the inputs, then the commit (`regs` is the
// register bank) and the outputs.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  const Registers& r = regs;
  Registers n = r;
#pragma HLS array_partition variable = n.conditioner.line complete
#pragma HLS array_partition variable = n.sync_fifo.slots complete
#pragma HLS array_partition variable = n.rx complete dim = 0
  if (in.reset == 1) {
    n = Registers();
  } else {
    const Wires w = wires(r, in);
    const Lines sync = in.sync;  // widened before the shift
    logic::conditioner::In<Family, kLines> pins;
    pins.pins = (sync << kChannels) | in.comparators;
    pins.filter_clocks = in.filter_clocks;
    n.conditioner = logic::conditioner::InputConditioner<Family, kLines>::next(r.conditioner, pins);
    count_time(n, r, in);
    clock_sync(n, r, w, in);
  channel_loop:
    for (int i = 0; i < kChannels; ++i) {
#pragma HLS unroll
      clock_channel(n.rx[i], r.rx[i], i, w, in);
    }
  }
  regs = n;
  drive(out, n);
}

#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

}  // namespace tof
}  // namespace hls
}  // namespace odoloc

// The top function (hls/src/tof_top.cpp): one call = one clock, the registers
// held in the function's static state.
void odoloc_tof(const odoloc::hls::tof::Inputs& in, odoloc::hls::tof::Outputs& out);
