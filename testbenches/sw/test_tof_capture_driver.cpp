// The TOF capture driver against a scripted bus that expects exact register
// reads and writes, named by their register-map paths: configuration,
// arming, window setting, FIFO bursts with more entries than one window,
// timestamp unwrapping across the 2^32 wrap, overflow and stuck incidents,
// and a failed read reported as lost events while the next read works.
#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/regs.hpp"
#include "odoloc/sw/register_bus.hpp"
#include "odoloc/sw/tof_capture_driver.hpp"

namespace {

namespace regs = odoloc::regs;
namespace tof = odoloc::sw::tof;
using odoloc::sw::BusError;
using Words = std::vector<std::uint32_t>;

std::string path_of(std::uint16_t a) {
  const regs::Register* r = regs::find(a);
  return r == nullptr ? "unmapped " + std::to_string(a) : std::string{r->path};
}

// Every access the driver makes must be the next one in the script.
class ScriptedBus final : public odoloc::sw::RegisterBus {
 public:
  struct Access {
    bool write;
    std::string path;
    Words words;        // written, or returned by a read (its size is the burst length)
    bool fail = false;  // a read that throws BusError
  };
  void expect_read(std::string_view path, Words reply) {
    script_.push_back({false, std::string{path}, std::move(reply)});
  }
  void expect_failed_read(std::string_view path, std::size_t count) {
    script_.push_back({false, std::string{path}, Words(count), true});
  }
  void expect_write(std::string_view path, Words words) {
    script_.push_back({true, std::string{path}, std::move(words)});
  }
  [[nodiscard]] bool done() const { return script_.empty(); }

  using RegisterBus::read;
  using RegisterBus::write;
  void read(std::uint16_t a, std::span<std::uint32_t> words) override {
    const Access next = take("read " + path_of(a) + " x" + std::to_string(words.size()));
    EXPECT_FALSE(next.write) << "read " << path_of(a) << " where a write was expected";
    EXPECT_EQ(path_of(a), next.path);
    EXPECT_EQ(words.size(), next.words.size()) << path_of(a);
    if (next.fail)
      throw BusError("scripted CRC mismatch");
    std::copy_n(next.words.begin(), std::min(words.size(), next.words.size()), words.begin());
  }
  void write(std::uint16_t a, std::span<const std::uint32_t> words) override {
    const Access next = take("write " + path_of(a));
    EXPECT_TRUE(next.write) << "write " << path_of(a) << " where a read was expected";
    EXPECT_EQ(path_of(a), next.path);
    EXPECT_EQ(Words(words.begin(), words.end()), next.words) << path_of(a);
  }

 private:
  Access take(const std::string& what) {
    if (script_.empty()) {
      ADD_FAILURE() << "unexpected " << what;
      return {false, "", {}};
    }
    Access a = script_.front();
    script_.pop_front();
    return a;
  }
  std::deque<Access> script_;
};

constexpr std::uint32_t kInfo =
    regs::tof::info::channels.set(0, 8) | regs::tof::info::fifo_depth.set(0, 16);

// The configuration writes of a setup: tof.cfg, every channel's cfg, then
// disarm + flush of everything, then the timestamp read.
void expect_setup(ScriptedBus& bus, const tof::CaptureSetup& s, std::uint32_t timestamp) {
  bus.expect_read("tof.info", {kInfo});
  std::uint32_t cfg = regs::tof::cfg::prescale.set(0, s.timebase.prescale);
  cfg = regs::tof::cfg::filter_clocks.set(cfg, s.filter_clocks);
  cfg = regs::tof::cfg::sync_enable.set(cfg, s.sync_enable ? 1 : 0);
  bus.expect_write("tof.cfg", {cfg});
  for (unsigned c = 0; c < 8; ++c) {
    const auto& ch = s.channels[c];
    std::uint32_t w = regs::tof_channel::cfg::mode.set(0, ch.mode == tof::ChannelMode::kCarrier);
    w = regs::tof_channel::cfg::edges.set(w, ch.edges);
    bus.expect_write("tof_channel.rx" + std::to_string(c) + ".cfg", {w});
  }
  bus.expect_write("tof.command", {regs::tof::command::disarm.set(0, 0xFF) |
                                   regs::tof::command::flush.set(0, 0xFF) |
                                   regs::tof::command::sync_flush.set(0, 1)});
  bus.expect_read("tof.timestamp", {timestamp});
}

// The sync frame: timestamp, sync_status, 3 unmapped words, 8 entries.
Words sync_frame(std::uint32_t timestamp, std::vector<std::uint32_t> entries, std::uint32_t level,
                 std::uint32_t status_bits = 0) {
  Words w(13, 0);
  w[0] = timestamp;
  w[1] = regs::tof::sync_status::fill_level.set(status_bits, level);
  for (std::size_t k = 0; k < entries.size(); ++k)
    w[5 + k] = entries[k];
  return w;
}
struct Entry {
  std::uint32_t ticks, width = 0, edge = 0;
};
// The channel frame: status, events, 3 unmapped words, 8 two-word entries.
Words channel_frame(std::uint32_t level, std::vector<Entry> entries, std::uint32_t status_bits = 0,
                    std::uint32_t dropped = 0) {
  namespace c = regs::tof_channel;
  Words w(21, 0);
  w[0] = c::status::fill_level.set(status_bits, level);
  w[1] = c::events::dropped.set(0, dropped);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    w[5 + 2 * k] = entries[k].ticks;
    w[6 + 2 * k] = c::entry0_hi::width.set(0, entries[k].width) |
                   c::entry0_hi::edge_index.set(0, entries[k].edge) | c::entry0_hi::valid.mask();
  }
  return w;
}

tof::CaptureSetup one_envelope_channel() {
  tof::CaptureSetup s;
  s.channels[2].enabled = true;
  return s;
}

TEST(TofCaptureDriver, ConfiguresArmsAndSetsWindows) {
  ScriptedBus bus;
  tof::CaptureSetup s = one_envelope_channel();
  s.timebase.prescale = 124;
  s.filter_clocks = 5;
  s.sync_enable = true;
  s.channels[5] = {.enabled = true, .mode = tof::ChannelMode::kCarrier, .edges = 12};
  expect_setup(bus, s, 1000);
  tof::CaptureDriver driver(bus, s);
  EXPECT_EQ(driver.timebase().input_latency_clocks, 7U);
  EXPECT_EQ(driver.fifo_depth(), 16U);
  // now(): the counter read without draining, unwrapped past the 2^32 wrap.
  bus.expect_read("tof.timestamp", {500});
  const tof::Tick now = driver.now();
  EXPECT_EQ(now, (tof::Tick{2} << 32) + 500);
  EXPECT_EQ(tof::CaptureDriver::wrapped(now), 500U);
  bus.expect_write("tof.command", {regs::tof::command::arm.set(0, 0b100100)});
  driver.arm(0b100100);
  bus.expect_write("tof.command", {regs::tof::command::disarm.set(0, 0b100)});
  driver.disarm(0b100);
  bus.expect_write("tof_channel.rx2.window_open", {70000, 90000});
  bus.expect_read("tof_channel.rx2.cfg", {0});
  bus.expect_write("tof_channel.rx2.cfg", {regs::tof_channel::cfg::window_enable.mask()});
  driver.set_window(2, tof::ListeningWindow{70000, 90000});
  EXPECT_THROW(driver.arm(0x100), std::invalid_argument);
  EXPECT_THROW(driver.set_window(8, std::nullopt), std::invalid_argument);
  EXPECT_TRUE(bus.done());
}

TEST(TofCaptureDriver, RefusesAMissingUnitAndBadSetups) {
  ScriptedBus bus;
  bus.expect_read("tof.info", {0});
  EXPECT_THROW(tof::CaptureDriver(bus, one_envelope_channel()), std::runtime_error);
  tof::CaptureSetup s = one_envelope_channel();
  s.filter_clocks = 256;
  EXPECT_THROW(tof::CaptureDriver(bus, s), std::invalid_argument);
  s = one_envelope_channel();
  s.channels[0].edges = 300;
  EXPECT_THROW(tof::CaptureDriver(bus, s), std::invalid_argument);
  s = one_envelope_channel();
  s.stuck_after_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(tof::CaptureDriver(bus, s), std::invalid_argument);
  EXPECT_TRUE(bus.done());
}

// Eleven entries: a full window, then a second frame for the rest. Events
// and reads straddle the 2^32 wrap and come out monotonic, 64-bit.
TEST(TofCaptureDriver, DrainsInBurstsAndUnwrapsAcrossTheWrap) {
  ScriptedBus bus;
  const tof::CaptureSetup s = one_envelope_channel();
  const std::uint32_t start = 0xFFFF0000U;
  expect_setup(bus, s, start);
  tof::CaptureDriver driver(bus, s);
  const tof::Tick origin = (tof::Tick{1} << 32) + start;
  std::vector<Entry> entries;
  for (std::uint32_t k = 0; k < 11; ++k)
    entries.push_back({.ticks = start + 0x2000U * (k + 1), .width = 100 + k});  // wraps at k = 7
  const std::uint32_t now = start + 0x2000U * 12;
  bus.expect_read("tof.timestamp", sync_frame(now, {}, 0));
  bus.expect_read("tof_channel.rx2.status",
                  channel_frame(11, {entries.begin(), entries.begin() + 8}));
  bus.expect_read("tof_channel.rx2.status", channel_frame(3, {entries.begin() + 8, entries.end()}));
  const tof::CaptureBatch batch = driver.read();
  EXPECT_TRUE(bus.done());
  EXPECT_EQ(batch.read_tick, origin + 0x2000U * 12);
  ASSERT_EQ(batch.channels[2].envelope.size(), 11U);
  for (std::uint32_t k = 0; k < 11; ++k) {
    EXPECT_EQ(batch.channels[2].envelope[k].rise, origin + 0x2000U * (k + 1)) << k;
    EXPECT_EQ(batch.channels[2].envelope[k].width, 100 + k) << k;
  }
  EXPECT_TRUE(batch.incidents.empty());
}

// Overflow becomes an incident with the dropped count (then cleared by w1c);
// a comparator high across reads for longer than stuck_after_s is stuck; a
// failed read is lost events, and the next read works.
TEST(TofCaptureDriver, IncidentsInsteadOfSilentLoss) {
  ScriptedBus bus;
  tof::CaptureSetup s = one_envelope_channel();
  s.stuck_after_s = 0.01;  // 500000 ticks
  expect_setup(bus, s, 0);
  tof::CaptureDriver driver(bus, s);
  const tof::Tick origin = tof::Tick{1} << 32;
  namespace c = regs::tof_channel;
  // Read 1: overflow with 4 dropped; the comparator is high.
  bus.expect_read("tof.timestamp", sync_frame(100'000, {}, 0));
  bus.expect_read("tof_channel.rx2.status",
                  channel_frame(1, {{.ticks = 50'000, .width = 10}},
                                c::status::overflow.mask() | c::status::in_progress.mask(), 4));
  bus.expect_write("tof_channel.rx2.status", {c::status::overflow.mask()});
  tof::CaptureBatch b = driver.read();
  ASSERT_EQ(b.incidents.size(), 1U);
  EXPECT_EQ(b.incidents[0].kind, tof::IncidentKind::kOverflow);
  EXPECT_EQ(b.incidents[0].count, 4U);
  EXPECT_EQ(b.incidents[0].from, origin + 50'000);
  EXPECT_EQ(b.incidents[0].until, origin + 100'000);
  // Read 2: still high, 0.02 s later: stuck since read 0.
  bus.expect_read("tof.timestamp", sync_frame(1'100'000, {}, 0));
  bus.expect_read("tof_channel.rx2.status", channel_frame(0, {}, c::status::in_progress.mask()));
  b = driver.read();
  ASSERT_EQ(b.incidents.size(), 1U);
  EXPECT_EQ(b.incidents[0].kind, tof::IncidentKind::kStuckHigh);
  EXPECT_EQ(b.incidents[0].from, origin);
  // Read 3: the channel frame fails on the bus.
  bus.expect_read("tof.timestamp", sync_frame(1'200'000, {}, 0));
  bus.expect_failed_read("tof_channel.rx2.status", 21);
  b = driver.read();
  ASSERT_EQ(b.incidents.size(), 1U);
  EXPECT_EQ(b.incidents[0].kind, tof::IncidentKind::kLostEvents);
  EXPECT_EQ(b.incidents[0].from, origin + 1'100'000);
  // Read 4 works: the comparator fell, one event, more overflow counted on.
  bus.expect_read("tof.timestamp", sync_frame(1'300'000, {}, 0));
  bus.expect_read("tof_channel.rx2.status", channel_frame(1, {{.ticks = 1'250'000, .width = 7}},
                                                          c::status::overflow.mask(), 6));
  bus.expect_write("tof_channel.rx2.status", {c::status::overflow.mask()});
  b = driver.read();
  ASSERT_EQ(b.channels[2].envelope.size(), 1U);
  EXPECT_EQ(b.channels[2].envelope[0].rise, origin + 1'250'000);
  ASSERT_EQ(b.incidents.size(), 1U);
  EXPECT_EQ(b.incidents[0].count, 2U) << "6 dropped, 4 already reported";
  EXPECT_TRUE(bus.done());
}

// Sync edges come from the global frame, with their own overflow.
TEST(TofCaptureDriver, SyncFifo) {
  ScriptedBus bus;
  tof::CaptureSetup s;
  s.sync_enable = true;
  expect_setup(bus, s, 10);
  tof::CaptureDriver driver(bus, s);
  const tof::Tick origin = (tof::Tick{1} << 32) + 0;
  bus.expect_read("tof.timestamp",
                  sync_frame(9000, {1000, 3000}, 2, regs::tof::sync_status::overflow.mask()));
  bus.expect_write("tof.sync_status", {regs::tof::sync_status::overflow.mask()});
  const tof::CaptureBatch b = driver.read();
  EXPECT_EQ(b.sync, (std::vector<tof::Tick>{origin + 1000, origin + 3000}));
  ASSERT_EQ(b.incidents.size(), 1U);
  EXPECT_EQ(b.incidents[0].channel, tof::kSyncChannel);
  EXPECT_TRUE(bus.done());
}

}  // namespace
