// Driver of the fabric's ultrasonic time-of-flight capture unit (tof.* and
// tof_channel.* registers, docs/tof-capture.md), over sw::RegisterBus only,
// so the same code runs on the simulator and on a board over spidev.
//
// It configures the unit, arms and disarms channels, sets listening windows,
// and drains every FIFO in SPI bursts into a tof::CaptureBatch: timestamps
// unwrapped to 64 bits, overflow, lost reads and stuck comparators reported
// as incidents, never dropped silently.
//
// Reading is lossless by construction: a read frame pops only the entries it
// returned, and only if the slave received it intact (docs/spi.md, rpop). A
// reply corrupted on MISO is detected by the bus (BusError) after the slave
// has popped: those entries are reported as an IncidentKind::kLostEvents.
//
// Timestamp unwrapping: every event stamped after the previous read started
// is within (previous read, this read] up to the short time the bursts take,
// so an event is placed in the 2^32-tick interval that starts kUnwrapMargin
// ticks before the previous read's timestamp. That holds when read() runs at
// least every 2^32 - 2 kUnwrapMargin ticks (85.8 s at 20 ns per tick);
// a longer gap is reported as IncidentKind::kUnwrapAmbiguous.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "odoloc/regs.hpp"
#include "odoloc/sw/register_bus.hpp"
#include "odoloc/sw/tof_measurement.hpp"

namespace odoloc::sw::tof {

inline constexpr unsigned kCaptureChannels = regs::tof_channel::kInstances;

// [open, close) in ticks of the unit's timestamp, modulo 2^32.
struct ListeningWindow {
  std::uint32_t open = 0, close = 0;
};

struct ChannelSetup {
  bool enabled = false;  // drained by read()
  ChannelMode mode = ChannelMode::kEnvelope;
  // Carrier mode: keep the first `edges` rising edges after arming (1..255; 0: all).
  unsigned edges = 8;
};

struct CaptureSetup {
  Timebase timebase;  // prescale is written to tof.cfg; the latency follows filter_clocks
  unsigned filter_clocks = 3;
  bool sync_enable = false;
  std::array<ChannelSetup, kCaptureChannels> channels{};
  // A comparator high for longer than this is reported stuck (kStuckHigh).
  double stuck_after_s = 0.05;
};

class CaptureDriver {
 public:
  // Ticks before the previous read's timestamp an event may be stamped and
  // still belong to this read (the bursts of one read take far less).
  static constexpr std::uint32_t kUnwrapMargin = 1U << 20;

  // Checks tof.info (the unit exists with enough channels), writes the
  // configuration, flushes every FIFO and starts the unwrapped count at the
  // unit's current timestamp. Throws std::invalid_argument for a bad setup,
  // BusError when the bus fails, std::runtime_error when the unit is absent.
  CaptureDriver(RegisterBus& bus, const CaptureSetup& setup);

  // One write of tof.command: these channels (bit i: rx i) start / stop
  // recording. Carrier mode: arming restarts the edge count.
  void arm(std::uint32_t channels);
  void disarm(std::uint32_t channels);
  // Listens only within `window` (nullopt: always).
  void set_window(unsigned channel, std::optional<ListeningWindow> window);
  // The unit's timestamp now, unwrapped, without draining anything.
  [[nodiscard]] Tick now();
  // Unwrapped tick -> the 32-bit value the unit's registers hold.
  [[nodiscard]] static std::uint32_t wrapped(Tick t) { return static_cast<std::uint32_t>(t); }

  // Drains the sync FIFO and every enabled channel's FIFO. Never throws for a
  // failed bus read: it becomes an incident and the next read() goes on.
  CaptureBatch read();

  [[nodiscard]] const Timebase& timebase() const { return setup_.timebase; }
  [[nodiscard]] unsigned fifo_depth() const { return fifo_depth_; }

 private:
  struct ChannelState {
    Tick last_read = 0;              // read_tick of the last good drain
    std::optional<Tick> high_since;  // first read that saw in_progress, while it lasts
    std::uint32_t dropped_seen = 0;  // events.dropped already reported
  };

  Tick unwrap_read(std::uint32_t timestamp);
  [[nodiscard]] Tick unwrap_event(std::uint32_t ticks) const;
  void drain_sync(CaptureBatch& batch);
  void drain_channel(unsigned channel, CaptureBatch& batch);
  void write_channel_config(unsigned channel);

  RegisterBus& bus_;
  CaptureSetup setup_;
  unsigned fifo_depth_ = 0;
  Tick read_tick_ = 0;      // the timestamp of the current read (unwrapped)
  Tick previous_read_ = 0;  // of the read before
  std::array<ChannelState, kCaptureChannels> channels_{};
  ChannelState sync_;
};

}  // namespace odoloc::sw::tof
