// The LCM message layer in one process (memq://): every message type
// round-trips through LCM field for field; messages that do not decode
// (another type's fingerprint, every truncation, bytes left over, length
// fields out of range, thousands of seeded random buffers) are ignored and
// counted exactly while good ones in between still arrive, in order; a
// handler's exception comes out of handle(), not through LCM; URLs and
// channel patterns LCM refuses are errors that name them.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "lcm_test_messages.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc/lcm/connection.hpp"

namespace {

using namespace std::chrono_literals;
using odoloc::lcm::Connection;
using odoloc::lcm::LcmError;
using odoloc::lcm::Receipt;
namespace msg = odoloc::tb::lcm;
namespace channel = odoloc::lcm::channel;
using Bytes = std::vector<std::uint8_t>;

// Dispatches everything memq:// holds.
void drain(Connection& connection) {
  while (connection.handle(0ms)) {
  }
}

// ------------------------------------------------ every field, every type

void expect_same(const odoloc_lcm::encoder_state_t& a, const odoloc_lcm::encoder_state_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  for (int i = 0; i < 4; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a.position_count[i], b.position_count[i]);
    EXPECT_EQ(a.speed_value[i], b.speed_value[i]);
    EXPECT_EQ(a.speed_mode[i], b.speed_mode[i]);
    EXPECT_EQ(a.valid[i], b.valid[i]);
    EXPECT_EQ(a.stalled[i], b.stalled[i]);
    EXPECT_EQ(a.forward[i], b.forward[i]);
  }
}

void expect_same(const odoloc_lcm::odometry_increment_t& a,
                 const odoloc_lcm::odometry_increment_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.updates, b.updates);
  EXPECT_EQ(a.dx, b.dx);
  EXPECT_EQ(a.dy, b.dy);
  EXPECT_EQ(a.dtheta, b.dtheta);
  EXPECT_EQ(a.ds, b.ds);
  EXPECT_EQ(a.last_rear_ds, b.last_rear_ds);
  EXPECT_EQ(a.last_rear_dtheta, b.last_rear_dtheta);
  EXPECT_EQ(a.last_front_ds, b.last_front_ds);
  EXPECT_EQ(a.last_front_dtheta, b.last_front_dtheta);
  EXPECT_EQ(a.last_ds, b.last_ds);
  EXPECT_EQ(a.last_dtheta, b.last_dtheta);
  EXPECT_EQ(a.ds_from_front, b.ds_from_front);
  EXPECT_EQ(a.dtheta_from_front, b.dtheta_from_front);
  EXPECT_EQ(a.steer_phi, b.steer_phi);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.theta, b.theta);
}

void expect_same(const odoloc_lcm::tof_measurement_set_t& a,
                 const odoloc_lcm::tof_measurement_set_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.cycle, b.cycle);
  EXPECT_EQ(a.tick_s, b.tick_s);
  EXPECT_EQ(a.num_channels, b.num_channels);
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (std::size_t c = 0; c < a.channels.size(); ++c) {
    SCOPED_TRACE(c);
    EXPECT_EQ(a.channels[c].channel, b.channels[c].channel);
    EXPECT_EQ(a.channels[c].num_events, b.channels[c].num_events);
    EXPECT_EQ(a.channels[c].rise_ticks, b.channels[c].rise_ticks);
  }
  EXPECT_EQ(a.has_sync, b.has_sync);
  EXPECT_EQ(a.sync_tick, b.sync_tick);
}

void expect_same(const odoloc_lcm::beacon_fix_t& a, const odoloc_lcm::beacon_fix_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.solver, b.solver);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(a.covariance[i], b.covariance[i]) << i;
  EXPECT_EQ(a.beacons_used, b.beacons_used);
  EXPECT_EQ(a.residual_rms, b.residual_rms);
  EXPECT_EQ(a.valid, b.valid);
}

void expect_same(const odoloc_lcm::station_measurement_t& a,
                 const odoloc_lcm::station_measurement_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.sd, b.sd);
  EXPECT_EQ(a.station_x, b.station_x);
  EXPECT_EQ(a.station_y, b.station_y);
  EXPECT_EQ(a.outcome, b.outcome);
}

void expect_same(const odoloc_lcm::pose_estimate_t& a, const odoloc_lcm::pose_estimate_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.theta, b.theta);
  for (int i = 0; i < 9; ++i)
    EXPECT_EQ(a.covariance[i], b.covariance[i]) << i;
  EXPECT_EQ(a.odometry_only, b.odometry_only);
  EXPECT_EQ(a.last_update_utime, b.last_update_utime);
}

void expect_same(const odoloc_lcm::register_request_t& a, const odoloc_lcm::register_request_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.request_id, b.request_id);
  EXPECT_EQ(a.op, b.op);
  EXPECT_EQ(a.address, b.address);
  EXPECT_EQ(a.count, b.count);
  EXPECT_EQ(a.num_values, b.num_values);
  EXPECT_EQ(a.values, b.values);
}

void expect_same(const odoloc_lcm::register_response_t& a,
                 const odoloc_lcm::register_response_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.request_id, b.request_id);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.message, b.message);
  EXPECT_EQ(a.address, b.address);
  EXPECT_EQ(a.num_values, b.num_values);
  EXPECT_EQ(a.values, b.values);
}

void expect_same(const odoloc_lcm::sim_status_t& a, const odoloc_lcm::sim_status_t& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.fabric_clocks, b.fabric_clocks);
  EXPECT_EQ(a.real_time_factor, b.real_time_factor);
  EXPECT_EQ(a.keeping_up, b.keeping_up);
  EXPECT_EQ(a.write_allowed, b.write_allowed);
  EXPECT_EQ(a.malformed_messages, b.malformed_messages);
  EXPECT_EQ(a.pacing, b.pacing);
}

// The k-th test message of each type.
template <class Message>
Message sample(int k);
template <>
odoloc_lcm::encoder_state_t sample(int k) {
  return msg::encoder_state(k);
}
template <>
odoloc_lcm::odometry_increment_t sample(int k) {
  return msg::odometry_increment(k);
}
template <>
odoloc_lcm::tof_measurement_set_t sample(int k) {
  return msg::tof_measurement_set(k);
}
template <>
odoloc_lcm::beacon_fix_t sample(int k) {
  return msg::beacon_fix(k);
}
template <>
odoloc_lcm::station_measurement_t sample(int k) {
  return msg::station_measurement(k);
}
template <>
odoloc_lcm::pose_estimate_t sample(int k) {
  return msg::pose_estimate(k);
}
template <>
odoloc_lcm::register_request_t sample(int k) {
  return msg::register_request(k);
}
template <>
odoloc_lcm::register_response_t sample(int k) {
  return msg::register_response(k);
}
template <>
odoloc_lcm::sim_status_t sample(int k) {
  return msg::sim_status(k);
}

TEST(LcmMessages, ChannelNamesAreDistinctLcmNames) {
  std::set<std::string> names;
  std::size_t channels = 0;
  msg::for_each_channel([&]<class Message>(const char* name) {
    EXPECT_LE(std::strlen(name), 63U) << name;  // LCM_MAX_CHANNEL_NAME_LENGTH
    EXPECT_EQ(std::string(name).rfind("ODOLOC_", 0), 0U) << name;
    names.insert(name);
    ++channels;
  });
  EXPECT_EQ(names.size(), channels);
  EXPECT_EQ(channels, 14U);  // channels.hpp's ten streams, the pose in five
  for (const auto& stream : odoloc::lcm::channel::kPoseStreams) {
    EXPECT_STREQ(odoloc::lcm::channel::pose_channel(stream.source), stream.channel);
    EXPECT_EQ(std::string(stream.channel).rfind(odoloc::lcm::channel::kPosePrefix, 0), 0U);
  }
  EXPECT_EQ(odoloc::lcm::channel::pose_channel("truth"), nullptr);
  EXPECT_STREQ(odoloc::lcm::kDefaultUrl, "udpm://239.255.76.67:7667?ttl=0");
}

TEST(LcmMessages, EveryTypeRoundTripsFieldForField) {
  Connection connection("memq://");
  msg::for_each_channel([&]<class Message>(const char* name) {
    SCOPED_TRACE(name);
    std::vector<Message> received;
    std::vector<std::string> channels;
    auto& subscription =
        connection.subscribe<Message>(name, [&](const Message& m, const Receipt& receipt) {
          received.push_back(m);
          channels.emplace_back(receipt.channel);
          EXPECT_GT(receipt.recv_utime, 0);
        });
    // Six messages: each variant of the ops, statuses, sources and lists.
    constexpr int kMessages = 6;
    for (int k = 0; k < kMessages; ++k) {
      connection.publish(name, sample<Message>(k));
      drain(connection);
    }
    ASSERT_EQ(received.size(), std::size_t{kMessages});
    for (int k = 0; k < kMessages; ++k) {
      SCOPED_TRACE(k);
      expect_same(received[static_cast<std::size_t>(k)], sample<Message>(k));
      EXPECT_EQ(channels[static_cast<std::size_t>(k)], name);
    }
    EXPECT_EQ(subscription.received(), std::uint64_t{kMessages});
    EXPECT_EQ(subscription.malformed(), 0U);
  });
  EXPECT_EQ(connection.malformed(), 0U);
}

// The samples use every variant the comparisons above should see.
TEST(LcmMessages, SamplesCoverEveryVariant) {
  std::set<int> ops;
  std::set<int> statuses;
  std::set<std::string> sources;
  bool empty_events = false;
  for (int k = 0; k < 6; ++k) {
    ops.insert(msg::register_request(k).op);
    statuses.insert(msg::register_response(k).status);
    sources.insert(msg::pose_estimate(k).source);
    for (const auto& channel_events : msg::tof_measurement_set(k).channels)
      empty_events = empty_events || channel_events.rise_ticks.empty();
  }
  EXPECT_EQ(ops, (std::set<int>{odoloc_lcm::register_request_t::READ,
                                odoloc_lcm::register_request_t::WRITE,
                                odoloc_lcm::register_request_t::DUMP}));
  EXPECT_EQ(statuses, (std::set<int>{odoloc_lcm::register_response_t::OK,
                                     odoloc_lcm::register_response_t::REFUSED,
                                     odoloc_lcm::register_response_t::ERROR}));
  EXPECT_EQ(sources, (std::set<std::string>{"fused", "odometry", "rear", "front", "liu"}));
  EXPECT_TRUE(empty_events);
}

// ------------------------------------------------------- malformed input

// Bytes that are not one Message: every other type's encoding (another
// fingerprint), every truncation of a good one, the good one with bytes
// left over, and `randoms` seeded random buffers up to twice its length.
template <class Message>
std::vector<Bytes> bad_buffers(const Bytes& good, unsigned seed, int randoms) {
  std::vector<Bytes> bad;
  msg::for_each_channel([&]<class Other>(const char*) {
    if (!std::is_same_v<Other, Message>)
      bad.push_back(odoloc::lcm::encode(sample<Other>(1)));
  });
  for (std::size_t length = 0; length < good.size(); ++length)
    bad.emplace_back(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length));
  for (const std::size_t extra : {std::size_t{1}, std::size_t{100}}) {
    bad.push_back(good);
    bad.back().resize(good.size() + extra, 0);
  }
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::size_t> length(0, 2 * good.size());
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < randoms; ++i) {
    Bytes b(length(random));
    for (std::uint8_t& x : b)
      x = static_cast<std::uint8_t>(byte(random));
    bad.push_back(std::move(b));
  }
  return bad;
}

// Publishes `bad` raw on `name` with a good message after every fifth, and
// checks that exactly the bad ones are counted and the good ones arrive in
// order, whole.
template <class Message>
void expect_ignored_and_counted(const char* name, const std::vector<Bytes>& bad) {
  Connection connection("memq://");
  std::vector<Message> received;
  auto& subscription = connection.subscribe<Message>(
      name, [&](const Message& m, const Receipt&) { received.push_back(m); });
  int good = 0;
  for (std::size_t i = 0; i < bad.size(); ++i) {
    connection.publish_raw(name, bad[i].data(), bad[i].size());
    if (i % 5 == 0)
      connection.publish(name, sample<Message>(good++));
    drain(connection);
  }
  EXPECT_EQ(subscription.malformed(), bad.size());
  EXPECT_EQ(connection.malformed(), bad.size());
  EXPECT_EQ(subscription.received(), static_cast<std::uint64_t>(good));
  ASSERT_EQ(received.size(), static_cast<std::size_t>(good));
  for (int k = 0; k < good; ++k) {
    const Bytes expected = odoloc::lcm::encode(sample<Message>(k));
    ASSERT_EQ(odoloc::lcm::encode(received[static_cast<std::size_t>(k)]), expected) << k;
  }
}

TEST(LcmMessages, MalformedMessagesAreIgnoredAndCounted) {
  unsigned seed = 14;
  msg::for_each_channel([&]<class Message>(const char* name) {
    SCOPED_TRACE(name);
    const Bytes good = odoloc::lcm::encode(sample<Message>(5));
    const std::vector<Bytes> bad = bad_buffers<Message>(good, seed++, 3000);
    // decode() refuses each on its own: a miscount below is the subscription's.
    for (const Bytes& b : bad) {
      Message m{};
      ASSERT_FALSE(odoloc::lcm::decode(b.data(), b.size(), m)) << b.size() << " bytes";
    }
    expect_ignored_and_counted<Message>(name, bad);
  });
}

// `good` with the big-endian integer of `width` bytes at `offset` replaced.
Bytes patched(Bytes good, std::size_t offset, std::size_t width, std::uint64_t value) {
  for (std::size_t i = 0; i < width; ++i)
    good.at(offset + i) = static_cast<std::uint8_t>(value >> (8 * (width - 1 - i)));
  return good;
}

// Length fields out of range with the right fingerprint: negative and
// maximal array lengths (the generated decoder sizes the vector first) and
// string lengths of 0 (no terminator), negative and beyond the buffer. The
// offsets follow the field order of the .lcm files; the fingerprint takes 8
// bytes.
TEST(LcmMessages, LengthFieldsOutOfRangeAreIgnoredAndCounted) {
  {
    SCOPED_TRACE("register_request_t.num_values");
    const Bytes good = odoloc::lcm::encode(msg::register_request(1));  // WRITE, 4 values
    const std::size_t at = 8 + 8 + 8 + 1 + 4 + 4;  // utime, request_id, op, address, count
    ASSERT_EQ(good.at(at + 1), 4);
    expect_ignored_and_counted<odoloc_lcm::register_request_t>(
        channel::kRegRequest, {patched(good, at, 2, 0xFFFF), patched(good, at, 2, 0x8000),
                               patched(good, at, 2, 0x7FFF), patched(good, at, 2, 5)});
  }
  {
    SCOPED_TRACE("tof_measurement_set_t.num_channels, num_events");
    const Bytes good = odoloc::lcm::encode(msg::tof_measurement_set(1));  // 3 channels
    const std::size_t at = 8 + 8 + 8 + 8;                                 // utime, cycle, tick_s
    ASSERT_EQ(good.at(at + 1), 3);
    ASSERT_EQ(good.at(at + 2), 0);      // the first channel's number
    ASSERT_EQ(good.at(at + 2 + 2), 1);  // and its events (k % 4)
    expect_ignored_and_counted<odoloc_lcm::tof_measurement_set_t>(
        channel::kTof, {patched(good, at, 2, 0xFFFF), patched(good, at, 2, 0x7FFF),
                        patched(good, at + 3, 2, 0xFFFB), patched(good, at + 3, 2, 0x7FFF)});
  }
  {
    SCOPED_TRACE("pose_estimate_t.source");
    const Bytes good = odoloc::lcm::encode(msg::pose_estimate(0));  // "fused"
    const std::size_t at = 8 + 8;                                   // utime
    ASSERT_EQ(good.at(at + 3), 6);                                  // with its terminator
    expect_ignored_and_counted<odoloc_lcm::pose_estimate_t>(
        channel::kPoseFused, {patched(good, at, 4, 0), patched(good, at, 4, 0xFFFF'FFFF),
                              patched(good, at, 4, 0x8000'0000), patched(good, at, 4, 0x7FFF'FFFF),
                              patched(good, at, 4, good.size())});
  }
}

// ------------------------------------------------------------ the caller

TEST(LcmMessages, HandlerExceptionComesOutOfHandle) {
  Connection connection("memq://");
  int calls = 0;
  auto& subscription = connection.subscribe<odoloc_lcm::sim_status_t>(
      channel::kSimStatus, [&](const odoloc_lcm::sim_status_t& m, const Receipt&) {
        ++calls;
        if (m.utime == msg::sim_status(1).utime)
          throw std::runtime_error("handler failed on status 1");
      });
  for (int k = 0; k < 3; ++k)
    connection.publish(channel::kSimStatus, msg::sim_status(k));
  EXPECT_TRUE(connection.handle(1000ms));
  try {
    connection.handle(1000ms);
    ADD_FAILURE() << "the handler's exception was lost";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "handler failed on status 1");
  }
  EXPECT_TRUE(connection.handle(1000ms));  // the next message is handled normally
  EXPECT_FALSE(connection.handle(0ms));
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(subscription.received(), 3U);
}

// The exception's message, or "" when `f` throws none.
std::string lcm_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const LcmError& e) {
    return e.what();
  }
  return "";
}

TEST(LcmMessages, ErrorsNameTheUrlAndChannel) {
  const std::string bad_url = "nonsense://239.255.76.67:7667";
  const std::string unopened = lcm_error_of([&] { Connection c(bad_url); });
  EXPECT_EQ(unopened, "LCM: cannot open '" + bad_url + "'");

  Connection connection("memq://");
  const std::string refused = lcm_error_of([&] {
    connection.subscribe<odoloc_lcm::pose_estimate_t>(
        "ODOLOC_(POSE", [](const odoloc_lcm::pose_estimate_t&, const Receipt&) {});
  });
  EXPECT_NE(refused.find("'ODOLOC_(POSE'"), std::string::npos) << refused;
  EXPECT_NE(refused.find("'memq://'"), std::string::npos) << refused;
}

}  // namespace
