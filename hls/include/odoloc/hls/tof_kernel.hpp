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
// The logic is the model's own (logic/tof_capture.hpp, which the cycle model
// rtl::TofCapture runs): this file maps the kernel's flat ports onto the
// register map's port structs (odoloc/logic/ports.hpp) and back, nothing
// else. test_hls_tof_* checks every output and register against the model
// per type family. No heap, no containers, no floating point, static loop
// bounds.
#pragma once

#include "odoloc/hls/types.hpp"
#include "odoloc/logic/tof_capture.hpp"
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

// ---- registers: the model's blocks, register for register -------------------------
using Logic = logic::tof::TofCapture<Family, kChannels, kDepth>;
using Registers = logic::tof::Regs<Family, kChannels, kDepth>;

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

// ---- port mapping -----------------------------------------------------------------
// The flat ports as the register map's port structs.
inline logic::tof::In<Family, kChannels> unit_in(const Inputs& in) {
  logic::tof::In<Family, kChannels> u;
  u.comparators = in.comparators;
  u.sync = in.sync;
  u.tof.command.arm = in.arm;
  u.tof.command.disarm = in.disarm;
  u.tof.command.flush = in.flush;
  u.tof.command.sync_flush = in.sync_flush;
  u.tof.sync_status.overflow = in.sync_overflow_clear;
  u.tof.sync_entry.pops = in.sync_pops;
rx_pulses_loop:
  for (int i = 0; i < kChannels; ++i) {
    u.channel[i].status.overflow = in.rx_pulses[i].overflow_clear;
    u.channel[i].entry.pops = in.rx_pulses[i].pops;
  }
  u.snapshot = in.snapshot;
  u.clear_all = in.clear_all;
  u.reset = in.reset;
  return u;
}
inline logic::tof::UnitConfig<Family> config(const Inputs& in) {
  logic::tof::UnitConfig<Family> c;
  c.tof.cfg.prescale = in.prescale;
  c.tof.cfg.filter_clocks = in.filter_clocks;
  c.tof.cfg.sync_enable = in.sync_enable;
rx_config_loop:
  for (int i = 0; i < kChannels; ++i) {
    c.tof_channel[i].cfg.mode = in.rx_config[i].mode;
    c.tof_channel[i].cfg.window_enable = in.rx_config[i].window_enable;
    c.tof_channel[i].cfg.edges = in.rx_config[i].edges;
    c.tof_channel[i].window_open.ticks = in.rx_config[i].window_open;
    c.tof_channel[i].window_close.ticks = in.rx_config[i].window_close;
  }
  return c;
}
inline void drive(Outputs& out, const logic::tof::UnitStatus<Family>& s) {
  out.fifo_depth = s.tof.info.fifo_depth;
  out.channels = s.tof.info.channels;
  out.timestamp = s.tof.timestamp.ticks;
  out.sync_fill_level = s.tof.sync_status.fill_level;
  out.sync_overflow = s.tof.sync_status.overflow;
  out.sync_dropped = s.tof.sync_status.dropped;
sync_window_loop:
  for (int k = 0; k < kWindow; ++k)
    out.sync_entry[k] = s.tof.sync_entry[k].ticks;
status_loop:
  for (int i = 0; i < kChannels; ++i) {
    const logic::ports::tof_channel::Status<Family>& c = s.tof_channel[i];
    ChannelStatus& o = out.rx[i];
    o.fill_level = c.status.fill_level;
    o.not_empty = c.status.not_empty;
    o.in_progress = c.status.in_progress;
    o.armed = c.status.armed;
    o.done = c.status.done;
    o.overflow = c.status.overflow;
    o.dropped = c.events.dropped;
    o.ignored = c.events.ignored;
  window_loop:
    for (int k = 0; k < kWindow; ++k) {
      o.entry[k].ticks = c.entry[k].ticks;
      o.entry[k].width = c.entry[k].width;
      o.entry[k].edge_index = c.entry[k].edge_index;
      o.entry[k].valid = c.entry[k].valid;
    }
  }
}

// One fabric clock: the registers after this clock's edge (`regs` is the
// register bank), then the status of those registers.
inline void step(Registers& regs, const Inputs& in, Outputs& out) {
#pragma HLS inline
  regs = Logic::next(regs, unit_in(in), config(in));
  logic::tof::UnitStatus<Family> status;
  Logic::status(regs, status);
  drive(out, status);
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
