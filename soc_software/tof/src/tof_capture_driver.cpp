#include "odoloc/sw/tof_capture_driver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace odoloc::sw::tof {

namespace {

namespace ch = regs::tof_channel;
namespace unit = regs::tof;

constexpr Tick kWrap = Tick{1} << 32;
constexpr unsigned kWindowEntries = 8;  // entry0 .. entry7 (sync_entry0 .. sync_entry7)

// One channel frame: status .. entry7_hi; entry k at kEntryWord + 2k.
constexpr std::uint16_t kChannelFirst = ch::status::kOffset;
constexpr unsigned kEntryWord = ch::entry0_lo::kOffset - kChannelFirst;
constexpr unsigned kChannelWords = kEntryWord + 2 * kWindowEntries;
constexpr unsigned kEventsWord = ch::events::kOffset - kChannelFirst;
// One sync frame: timestamp .. sync_entry7; entry k at kSyncEntryWord + k.
constexpr std::uint16_t kSyncFirst = unit::timestamp::kAddress;
constexpr unsigned kSyncStatusWord = unit::sync_status::kAddress - kSyncFirst;
constexpr unsigned kSyncEntryWord = unit::sync_entry0::kAddress - kSyncFirst;
constexpr unsigned kSyncWords = kSyncEntryWord + kWindowEntries;
static_assert(kChannelWords <= regs::spi::kMaxBurst && kSyncWords <= regs::spi::kMaxBurst);
static_assert(ch::entry7_hi::kOffset == ch::entry0_lo::kOffset + 2 * kWindowEntries - 1);
static_assert(unit::sync_entry7::kAddress == unit::sync_entry0::kAddress + kWindowEntries - 1);

std::uint32_t mask_of(std::uint32_t channels) {
  if (channels >> kCaptureChannels != 0)
    throw std::invalid_argument("tof::CaptureDriver: channel mask 0x" + std::to_string(channels) +
                                " names channels the unit does not have");
  return channels;
}

}  // namespace

CaptureDriver::CaptureDriver(RegisterBus& bus, const CaptureSetup& setup)
    : bus_(bus), setup_(setup) {
  setup_.timebase.input_latency_clocks = std::max(setup.filter_clocks, 1U) + 2;
  setup_.timebase.validate();
  if (setup.filter_clocks > 255)
    throw std::invalid_argument("tof::CaptureDriver: filter_clocks " +
                                std::to_string(setup.filter_clocks) + " does not fit 8 bits");
  if (!(setup.stuck_after_s > 0))
    throw std::invalid_argument("tof::CaptureDriver: stuck_after_s must be positive");
  for (const ChannelSetup& c : setup.channels)
    if (c.edges > 255)
      throw std::invalid_argument("tof::CaptureDriver: carrier edges " + std::to_string(c.edges) +
                                  " does not fit 8 bits");
  const std::uint32_t info = bus_.read(unit::info::kAddress);
  fifo_depth_ = unit::info::fifo_depth.get(info);
  if (unit::info::channels.get(info) < kCaptureChannels || fifo_depth_ < kWindowEntries)
    throw std::runtime_error("tof::CaptureDriver: tof.info reads 0x" + std::to_string(info) +
                             ": no capture unit with " + std::to_string(kCaptureChannels) +
                             " channels");
  std::uint32_t cfg = unit::cfg::prescale.set(0, setup_.timebase.prescale);
  cfg = unit::cfg::filter_clocks.set(cfg, setup.filter_clocks);
  cfg = unit::cfg::sync_enable.set(cfg, setup.sync_enable ? 1 : 0);
  bus_.write(unit::cfg::kAddress, cfg);
  for (unsigned c = 0; c < kCaptureChannels; ++c)
    write_channel_config(c);
  std::uint32_t command = unit::command::disarm.set(0, 0xFFU);
  command = unit::command::flush.set(command, 0xFFU);
  command = unit::command::sync_flush.set(command, 1);
  bus_.write(unit::command::kAddress, command);
  // Tick 0 lies 2^32 ticks before the unit's timestamp 0 of this epoch, so
  // events just before the first read stay positive.
  read_tick_ = kWrap + bus_.read(unit::timestamp::kAddress);
  previous_read_ = read_tick_;
  for (ChannelState& s : channels_)
    s.last_read = read_tick_;
  sync_.last_read = read_tick_;
}

void CaptureDriver::write_channel_config(unsigned channel) {
  const ChannelSetup& c = setup_.channels[channel];
  std::uint32_t cfg = ch::cfg::mode.set(
      0, static_cast<std::uint32_t>(c.mode == ChannelMode::kCarrier ? ch::cfg::Mode::kCarrier
                                                                    : ch::cfg::Mode::kEnvelope));
  cfg = ch::cfg::edges.set(cfg, c.edges);
  bus_.write(ch::cfg::address(channel), cfg);
}

void CaptureDriver::arm(std::uint32_t channels) {
  bus_.write(unit::command::kAddress, unit::command::arm.set(0, mask_of(channels)));
}

void CaptureDriver::disarm(std::uint32_t channels) {
  bus_.write(unit::command::kAddress, unit::command::disarm.set(0, mask_of(channels)));
}

void CaptureDriver::set_window(unsigned channel, std::optional<ListeningWindow> window) {
  if (channel >= kCaptureChannels)
    throw std::invalid_argument("tof::CaptureDriver: no channel " + std::to_string(channel));
  if (window) {
    const std::array<std::uint32_t, 2> bounds{window->open, window->close};
    bus_.write(ch::window_open::address(channel), bounds);
  }
  const std::uint32_t cfg = bus_.read(ch::cfg::address(channel));
  bus_.write(ch::cfg::address(channel), ch::cfg::window_enable.set(cfg, window ? 1 : 0));
}

Tick CaptureDriver::now() {
  const std::uint32_t ts = bus_.read(unit::timestamp::kAddress);
  return read_tick_ + static_cast<std::uint32_t>(ts - wrapped(read_tick_));
}

Tick CaptureDriver::unwrap_read(std::uint32_t timestamp) {
  previous_read_ = read_tick_;
  read_tick_ += static_cast<std::uint32_t>(timestamp - wrapped(read_tick_));
  return read_tick_;
}

Tick CaptureDriver::unwrap_event(std::uint32_t ticks) const {
  const Tick base = previous_read_ - kUnwrapMargin;
  return base + static_cast<std::uint32_t>(ticks - wrapped(base));
}

CaptureBatch CaptureDriver::read() {
  CaptureBatch batch;
  batch.timebase = setup_.timebase;
  batch.channels.resize(kCaptureChannels);
  for (unsigned c = 0; c < kCaptureChannels; ++c)
    batch.channels[c].mode = setup_.channels[c].mode;
  drain_sync(batch);
  batch.read_tick = read_tick_;
  if (read_tick_ - previous_read_ >= kWrap - 2 * Tick{kUnwrapMargin}) {
    for (unsigned c = 0; c < kCaptureChannels; ++c)
      if (setup_.channels[c].enabled)
        batch.incidents.push_back({.kind = IncidentKind::kUnwrapAmbiguous,
                                   .channel = static_cast<int>(c),
                                   .from = previous_read_,
                                   .until = read_tick_,
                                   .count = 0});
  }
  for (unsigned c = 0; c < kCaptureChannels; ++c)
    if (setup_.channels[c].enabled)
      drain_channel(c, batch);
  return batch;
}

void CaptureDriver::drain_sync(CaptureBatch& batch) {
  std::array<std::uint32_t, kSyncWords> w{};
  bool first = true;
  for (;;) {
    try {
      bus_.read(kSyncFirst, w);
    } catch (const BusError&) {
      if (first)  // no timestamp: this read keeps the last one
        unwrap_read(wrapped(read_tick_));
      batch.incidents.push_back({.kind = IncidentKind::kLostEvents,
                                 .channel = kSyncChannel,
                                 .from = sync_.last_read,
                                 .until = read_tick_,
                                 .count = 0});
      return;
    }
    if (first)
      unwrap_read(w[0]);
    first = false;
    const std::uint32_t status = w[kSyncStatusWord];
    const unsigned level = unit::sync_status::fill_level.get(status);
    for (unsigned k = 0; k < std::min(level, kWindowEntries); ++k)
      batch.sync.push_back(unwrap_event(w[kSyncEntryWord + k]));
    if (unit::sync_status::overflow.get(status) != 0) {
      const std::uint32_t dropped = unit::sync_status::dropped.get(status);
      batch.incidents.push_back({.kind = IncidentKind::kOverflow,
                                 .channel = kSyncChannel,
                                 .from = batch.sync.empty() ? sync_.last_read : batch.sync.back(),
                                 .until = read_tick_,
                                 .count = dropped - std::min(dropped, sync_.dropped_seen)});
      sync_.dropped_seen = dropped;
      bus_.write(unit::sync_status::kAddress, unit::sync_status::overflow.mask());
    }
    if (level <= kWindowEntries)
      break;
  }
  sync_.last_read = read_tick_;
}

void CaptureDriver::drain_channel(unsigned channel, CaptureBatch& batch) {
  ChannelState& state = channels_[channel];
  ChannelEvents& events = batch.channels[channel];
  const auto last_event = [&] {
    if (events.mode == ChannelMode::kEnvelope)
      return events.envelope.empty() ? state.last_read : events.envelope.back().rise;
    return events.carrier.empty() ? state.last_read : events.carrier.back().rise;
  };
  const auto incident = [&](IncidentKind kind, Tick from, std::uint32_t count) {
    batch.incidents.push_back({.kind = kind,
                               .channel = static_cast<int>(channel),
                               .from = from,
                               .until = read_tick_,
                               .count = count});
  };
  std::array<std::uint32_t, kChannelWords> w{};
  for (;;) {
    try {
      bus_.read(ch::status::address(channel), w);
    } catch (const BusError&) {
      incident(IncidentKind::kLostEvents, state.last_read, 0);
      return;
    }
    const std::uint32_t status = w[0];
    const unsigned level = ch::status::fill_level.get(status);
    for (unsigned k = 0; k < std::min(level, kWindowEntries); ++k) {
      const std::uint32_t high = w[kEntryWord + 2 * k + 1];
      const Tick rise = unwrap_event(w[kEntryWord + 2 * k]);
      if (events.mode == ChannelMode::kEnvelope)
        events.envelope.push_back({.rise = rise, .width = ch::entry0_hi::width.get(high)});
      else
        events.carrier.push_back({.rise = rise, .edge = ch::entry0_hi::edge_index.get(high)});
    }
    if (ch::status::overflow.get(status) != 0) {
      const std::uint32_t dropped = ch::events::dropped.get(w[kEventsWord]);
      incident(IncidentKind::kOverflow, last_event(),
               dropped - std::min(dropped, state.dropped_seen));
      state.dropped_seen = dropped;
      bus_.write(ch::status::address(channel), ch::status::overflow.mask());
    }
    if (ch::status::in_progress.get(status) == 0) {
      state.high_since.reset();
    } else {
      if (!state.high_since)
        state.high_since = state.last_read;  // it rose after the last drain
      const double high_s =
          static_cast<double>(read_tick_ - *state.high_since) * setup_.timebase.tick_s();
      if (high_s > setup_.stuck_after_s)
        incident(IncidentKind::kStuckHigh, *state.high_since, 0);
    }
    if (level <= kWindowEntries)
      break;
  }
  state.last_read = read_tick_;
}

}  // namespace odoloc::sw::tof
