// LCM event logs: a run published through LCM's file:// provider is a log
// that lcm::LogFile reads back event for event (channels, bytes and order as
// published, every event decoding as its channel's type); a log replayed
// through file://...?mode=r reaches typed subscriptions, in order.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "lcm_test_messages.hpp"
#include "odoloc/lcm/connection.hpp"
#include "scratch_files.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using odoloc::lcm::Connection;
using odoloc::lcm::Receipt;
namespace msg = odoloc::tb::lcm;

// The bytes of a log event.
std::vector<std::uint8_t> payload(const lcm::LogEvent& event) {
  const auto* data = static_cast<const std::uint8_t*>(event.data);
  return {data, data + event.datalen};
}

TEST(LcmLog, WrittenThroughLcmReadsBackEventForEvent) {
  const fs::path log = odoloc::tb::fresh_dir("odoloc_lcm_log", "write") / "drive.lcmlog";
  const std::vector<msg::Event> events = msg::drive_sequence(300);
  {
    Connection writer("file://" + log.string() + "?mode=w");
    for (const msg::Event& e : events)
      writer.publish_raw(e.channel, e.bytes.data(), e.bytes.size());
  }
  lcm::LogFile reader(log.string(), "r");
  ASSERT_TRUE(reader.good()) << log;
  std::size_t i = 0;
  std::int64_t last_time = 0;
  for (const lcm::LogEvent* event = reader.readNextEvent(); event != nullptr;
       event = reader.readNextEvent(), ++i) {
    ASSERT_LT(i, events.size()) << "more events than published";
    SCOPED_TRACE(i);
    EXPECT_EQ(event->eventnum, static_cast<std::int64_t>(i));
    EXPECT_GE(event->timestamp, last_time);
    last_time = event->timestamp;
    ASSERT_EQ(event->channel, events[i].channel);
    ASSERT_EQ(payload(*event), events[i].bytes);
    EXPECT_TRUE(msg::decodes_as_channel_type(event->channel, event->data,
                                             static_cast<std::size_t>(event->datalen)));
  }
  EXPECT_EQ(i, events.size());
  EXPECT_GT(last_time, 0);  // wall-clock microseconds of the publishing
}

TEST(LcmLog, ReplayedThroughFileProviderReachesSubscriptions) {
  const fs::path log = odoloc::tb::fresh_dir("odoloc_lcm_log", "replay") / "drive.lcmlog";
  const std::vector<msg::Event> events = msg::drive_sequence(300);
  ASSERT_TRUE(msg::write_log(log.string(), events)) << log;
  // speed=0: as fast as the log can be read.
  Connection replay("file://" + log.string() + "?mode=r&speed=0");
  struct Received {
    std::string channel;
    std::vector<std::uint8_t> bytes;
    std::int64_t recv_utime;
  };
  std::vector<Received> received;
  msg::for_each_channel([&]<class Message>(const char* name) {
    replay.subscribe<Message>(name, [&](const Message& m, const Receipt& receipt) {
      received.push_back(Received{.channel = std::string(receipt.channel),
                                  .bytes = odoloc::lcm::encode(m),
                                  .recv_utime = receipt.recv_utime});
    });
  });
  while (received.size() < events.size() && replay.handle(2000ms)) {
  }
  ASSERT_EQ(received.size(), events.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(received[i].channel, events[i].channel);
    EXPECT_EQ(received[i].bytes, events[i].bytes);
    if (i > 0) {
      EXPECT_GE(received[i].recv_utime, received[i - 1].recv_utime);
    }
  }
  EXPECT_EQ(replay.malformed(), 0U);
}

}  // namespace
