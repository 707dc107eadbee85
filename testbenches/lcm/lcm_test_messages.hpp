// Messages of every odoloc LCM type with non-trivial values (extremes of the
// registers' ranges, negative numbers, empty and long variable-length
// lists, several strings), and the sequence a 100 Hz simulator run publishes,
// shared by the LCM testbenches and their peer process (lcm_peer.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "odoloc/lcm/channels.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc_lcm/beacon_fix_t.hpp"
#include "odoloc_lcm/encoder_state_t.hpp"
#include "odoloc_lcm/odometry_increment_t.hpp"
#include "odoloc_lcm/pose_estimate_t.hpp"
#include "odoloc_lcm/register_request_t.hpp"
#include "odoloc_lcm/register_response_t.hpp"
#include "odoloc_lcm/sim_status_t.hpp"
#include "odoloc_lcm/station_measurement_t.hpp"
#include "odoloc_lcm/tof_measurement_set_t.hpp"

namespace odoloc::tb::lcm {

namespace channel = odoloc::lcm::channel;

// A channel no odoloc subscriber listens to: the cross-process test's
// publisher sends on it until lcm-logger is seen recording.
inline constexpr char kProbeChannel[] = "ODOLOC_TEST_PROBE";

// Simulated time of tick t of a 100 Hz run, microseconds.
inline std::int64_t tick_utime(int t) {
  return 1'000'000 + std::int64_t{t} * 10'000;
}

// The k-th message of each type: every field depends on k or takes a value
// at the edge of its range.
inline odoloc_lcm::encoder_state_t encoder_state(int k) {
  odoloc_lcm::encoder_state_t m{};
  m.utime = tick_utime(k);
  const std::int32_t kk = k;
  // eppm.count is 20-bit and eppm.speed.value 24-bit two's complement.
  const std::int32_t counts[4] = {-524288 + kk, 524287 - 2 * kk, 100 * kk, -7 * kk - 1};
  const std::int32_t speeds[4] = {8388607 - kk, -8388608 + kk, 50 * kk, -3};
  for (int i = 0; i < 4; ++i) {
    m.position_count[i] = counts[i];
    m.speed_value[i] = speeds[i];
    m.speed_mode[i] = (i + k) % 2 == 0 ? odoloc_lcm::encoder_state_t::SPEED_MODE_PULSE
                                       : odoloc_lcm::encoder_state_t::SPEED_MODE_PERIOD;
    m.valid[i] = (i + k) % 3 != 0;
    m.stalled[i] = (i * k) % 4 == 1;
    m.forward[i] = (i + 2 * k) % 5 < 3;
  }
  return m;
}

inline odoloc_lcm::odometry_increment_t odometry_increment(int k) {
  odoloc_lcm::odometry_increment_t m{};
  m.utime = tick_utime(k);
  m.updates = (0xFFFF'FFF0LL + k) & 0xFFFF'FFFFLL;  // the 32-bit counter wraps during a run
  m.dx = 1.0e-2 * (k + 1) + 1.5e-9;
  m.dy = -3.0e-6 * k;
  m.dtheta = -2.5e-3 * (k + 1);
  m.ds = m.dx * (1 + 1e-7 * k);
  m.last_rear_ds = 1.0e-4 * (k + 1) + 1.5e-9;
  m.last_rear_dtheta = -2.5e-5 * (k + 1);
  m.last_front_ds = 0.9999e-4 * (k + 1);
  m.last_front_dtheta = -2.4e-5 * (k + 1) - 3.0e-12;
  m.last_ds = k % 2 == 0 ? m.last_rear_ds : m.last_front_ds;
  m.last_dtheta = k % 3 == 0 ? m.last_front_dtheta : m.last_rear_dtheta;
  m.ds_from_front = k % 2 != 0;
  m.dtheta_from_front = k % 3 == 0;
  m.steer_phi = -0.6981317007977318 + 1.0e-3 * k;  // from the -40 degree limit
  m.x = 12.345678901234 + 1.0e-3 * k;
  m.y = -3.25 - 2.0e-3 * k;
  m.theta = -std::numbers::pi + 1.0e-3 * k;
  return m;
}

inline odoloc_lcm::tof_measurement_set_t tof_measurement_set(int k) {
  odoloc_lcm::tof_measurement_set_t m{};
  m.utime = tick_utime(10 * k);
  m.cycle = k;
  m.tick_s = 125 / 50.0e6;  // prescale 124: Kleeman's 2.5 us
  // An empty list every fourth cycle, ticks beyond 32 bits (unwrapped).
  const int8_t channels[3] = {0, 3, 7};
  const int events[3] = {k % 4, 5, 1};
  for (int c = 0; c < 3; ++c) {
    odoloc_lcm::tof_channel_events_t e{};
    e.channel = channels[c];
    for (int i = 0; i < events[c]; ++i)
      e.rise_ticks.push_back((std::int64_t{1} << 40) + 4000LL * k + 37LL * i + c);
    e.num_events = static_cast<std::int16_t>(e.rise_ticks.size());
    m.channels.push_back(e);
  }
  m.num_channels = static_cast<std::int16_t>(m.channels.size());
  m.has_sync = k % 2 == 0;
  m.sync_tick = (std::int64_t{1} << 40) + 4000LL * k - 11;
  return m;
}

inline odoloc_lcm::station_measurement_t station_measurement(int k) {
  odoloc_lcm::station_measurement_t m{};
  m.utime = tick_utime(40 * k + 7);
  constexpr const char* kKinds[] = {"station_bearing", "station_range", "robot_bearing"};
  m.kind = kKinds[k % 3];
  m.value = -1.5 + 0.75 * k;
  m.sd = 1e-3 * (k + 1);
  m.station_x = 0.3;
  m.station_y = 5.0 - 0.125 * k;
  m.outcome = k % 2 == 0 ? "accepted" : "gated";
  return m;
}

inline odoloc_lcm::beacon_fix_t beacon_fix(int k) {
  odoloc_lcm::beacon_fix_t m{};
  m.utime = tick_utime(10 * k);
  m.solver = k % 2 == 0 ? "gauss_newton" : "kleeman_triple";
  m.x = 4.75 + 0.01 * k;
  m.y = -1.125 - 0.02 * k;
  const double covariance[4] = {4.0e-4 + 1e-6 * k, -1.5e-5, -1.5e-5, 9.0e-4};
  for (int i = 0; i < 4; ++i)
    m.covariance[i] = covariance[i];
  m.beacons_used = static_cast<std::int16_t>(4 + k % 3);
  m.residual_rms = 0.0123 + 1e-4 * k;
  m.valid = k % 5 != 4;
  return m;
}

inline odoloc_lcm::pose_estimate_t pose_estimate(int k) {
  static constexpr const char* kSources[] = {"fused", "odometry", "rear", "front", "liu"};
  odoloc_lcm::pose_estimate_t m{};
  m.utime = tick_utime(k);
  m.source = kSources[k % 5];
  m.x = -0.5 + 0.01 * k;
  m.y = 7.0 / 3.0 + 0.005 * k;
  m.theta = std::numbers::pi - 1.0e-9 - 1e-3 * k;
  for (int i = 0; i < 9; ++i)
    m.covariance[i] = i % 4 == 0 ? 1.0e-4 * (i + 1) * (k + 1) : -2.0e-7 * (i + k);
  m.odometry_only = k % 7 == 6;
  m.last_update_utime = k < 3 ? 0 : tick_utime(k - 3);
  return m;
}

// A 32-bit register word, all bits used.
inline std::int64_t register_word(int i) {
  return (0x9E37'79B9LL * (i + 1)) & 0xFFFF'FFFFLL;
}

inline odoloc_lcm::register_request_t register_request(int k) {
  odoloc_lcm::register_request_t m{};
  m.utime = 1'700'000'000'000'000 + k;  // wall-clock time
  m.request_id = 1000 + k;
  m.op = static_cast<std::int8_t>(k % 3);
  m.address = 0x110 + 0x18 * (k % 8);
  m.count = 1 + k % 32;
  if (m.op == odoloc_lcm::register_request_t::WRITE)
    m.values = {0xFFFF'FFFFLL, 0, 0x8000'0000LL, register_word(k)};
  m.num_values = static_cast<std::int16_t>(m.values.size());
  return m;
}

inline odoloc_lcm::register_response_t register_response(int k) {
  static constexpr const char* kMessages[] = {
      "", "write refused: the simulator was started without --allow-write",
      "address 0x3ff: no register"};
  odoloc_lcm::register_response_t m{};
  m.utime = 1'700'000'000'000'100 + k;
  m.request_id = 1000 + k;
  m.status = static_cast<std::int8_t>(k % 3);
  m.message = kMessages[k % 3];
  m.address = k % 3 == 0 ? 0x110 : 0;
  if (m.status == odoloc_lcm::register_response_t::OK) {
    for (int i = 0; i < 40 + k % 5; ++i)
      m.values.push_back(register_word(i + k));
  }
  m.num_values = static_cast<std::int16_t>(m.values.size());
  return m;
}

inline odoloc_lcm::sim_status_t sim_status(int k) {
  odoloc_lcm::sim_status_t m{};
  m.utime = tick_utime(100 * k);
  m.fabric_clocks = 50 * m.utime + 17;
  m.real_time_factor = 37.5 + 0.25 * k;
  m.keeping_up = k % 2 == 0;
  m.write_allowed = k % 3 == 1;
  m.malformed_messages = 3LL * k;
  m.pacing = k % 2 == 0 ? "fast" : "realtime";
  return m;
}

// Calls f.template operator()<Message>(channel) for each channel and its
// message type.
template <class F>
void for_each_channel(F&& f) {
  f.template operator()<odoloc_lcm::encoder_state_t>(channel::kEncoders);
  f.template operator()<odoloc_lcm::odometry_increment_t>(channel::kOdometry);
  f.template operator()<odoloc_lcm::tof_measurement_set_t>(channel::kTof);
  f.template operator()<odoloc_lcm::beacon_fix_t>(channel::kFix);
  f.template operator()<odoloc_lcm::station_measurement_t>(channel::kStation);
  for (const channel::PoseStream& stream : channel::kPoseStreams)
    f.template operator()<odoloc_lcm::pose_estimate_t>(stream.channel);
  f.template operator()<odoloc_lcm::pose_estimate_t>(channel::kTruth);
  f.template operator()<odoloc_lcm::register_request_t>(channel::kRegRequest);
  f.template operator()<odoloc_lcm::register_response_t>(channel::kRegResponse);
  f.template operator()<odoloc_lcm::sim_status_t>(channel::kSimStatus);
}

// Whether `size` bytes decode as the type of `channel` (false for a channel
// that is not odoloc's).
inline bool decodes_as_channel_type(std::string_view channel, const void* data, std::size_t size) {
  bool decoded = false;
  for_each_channel([&]<class Message>(const char* name) {
    Message message{};
    if (channel == name)
      decoded = odoloc::lcm::decode(data, size, message);
  });
  return decoded;
}

// One message as published: channel, encoding, and the simulated time it
// was published at (a log's event time), microseconds.
struct Event {
  std::string channel;
  std::vector<std::uint8_t> bytes;
  std::int64_t utime = 0;
};

// What a 100 Hz simulator run of `ticks` ticks publishes, in order: per tick
// the encoders, the odometry increment and a pose; every 10th tick a beacon
// cycle (TOF set and fix); every 100th the status; a register request and
// its response every 50th. Each channel's messages carry their sequence in
// the payload (utime, odometry updates, TOF cycle, request_id).
inline std::vector<Event> drive_sequence(int ticks) {
  std::vector<Event> events;
  auto add = [&](const char* name, const auto& message, int t) {
    events.push_back(
        Event{.channel = name, .bytes = odoloc::lcm::encode(message), .utime = tick_utime(t)});
  };
  for (int t = 0; t < ticks; ++t) {
    if (t % 100 == 0)
      add(channel::kSimStatus, sim_status(t / 100), t);
    add(channel::kEncoders, encoder_state(t), t);
    add(channel::kOdometry, odometry_increment(t), t);
    const auto pose = pose_estimate(t);
    add(channel::pose_channel(pose.source), pose, t);
    if (t % 10 == 9) {
      add(channel::kTof, tof_measurement_set(t / 10), t);
      add(channel::kFix, beacon_fix(t / 10), t);
    }
    if (t % 50 == 25) {
      add(channel::kRegRequest, register_request(t / 50), t);
      add(channel::kRegResponse, register_response(t / 50), t);
    }
  }
  return events;
}

// Writes `events` as an LCM log at their simulated times (lcm-logplayer keeps
// that pace); false if the file cannot be written.
inline bool write_log(const std::string& path, const std::vector<Event>& events) {
  ::lcm::LogFile log(path, "w");
  if (!log.good())
    return false;
  for (const Event& e : events) {
    std::vector<std::uint8_t> bytes = e.bytes;
    ::lcm::LogEvent event{.eventnum = 0,
                          .timestamp = e.utime,
                          .channel = e.channel,
                          .datalen = static_cast<std::int32_t>(bytes.size()),
                          .data = bytes.data()};
    if (log.writeEvent(&event) != 0)
      return false;
  }
  return true;
}

}  // namespace odoloc::tb::lcm
