// The other process of test_lcm_tools: a subscriber that lcm-logplayer
// replays a log into, or a publisher that lcm-logger records. Both know the
// sequence a 100 Hz run of TICKS ticks publishes (msg::drive_sequence).
//
//   odoloc_lcm_peer subscribe URL READY_FILE TICKS TIMEOUT_S
//     subscribes every odoloc channel, creates READY_FILE, and exits 0 once
//     every message of the sequence arrived, decoded and in order per
//     channel (nothing missing, nothing extra, nothing malformed); prints
//     what went wrong and exits 1 otherwise (or after TIMEOUT_S seconds).
//   odoloc_lcm_peer subscribe-log URL READY_FILE LOG TIMEOUT_S
//     the same, expecting every event of the LCM log LOG (`odoloc sim`'s)
//     instead of the sequence.
//   odoloc_lcm_peer garbage URL CHANNEL COUNT 0
//     publishes COUNT messages of bytes that are no odoloc type on CHANNEL.
//   odoloc_lcm_peer publish URL LOG_FILE TICKS TIMEOUT_S
//     publishes on kProbeChannel until LOG_FILE (lcm-logger's output) grows,
//     then the sequence, paced at one tick per millisecond, then probes
//     again until LOG_FILE holds all of the sequence, and exits 0; 1 when it
//     does not within TIMEOUT_S seconds.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "lcm_test_messages.hpp"
#include "odoloc/lcm/connection.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using odoloc::lcm::Connection;
using odoloc::lcm::Receipt;
namespace msg = odoloc::tb::lcm;
using Bytes = std::vector<std::uint8_t>;

// Every event of an LCM log, in order.
std::vector<msg::Event> log_events(const std::string& log_file) {
  lcm::LogFile log(log_file, "r");
  if (!log.good())
    throw std::runtime_error("cannot read the log " + log_file);
  std::vector<msg::Event> events;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    const auto* data = static_cast<const std::uint8_t*>(e->data);
    events.push_back({e->channel, {data, data + e->datalen}, e->timestamp});
  }
  return events;
}

int subscribe(const std::string& url, const std::string& ready_file,
              const std::vector<msg::Event>& expected, std::chrono::seconds timeout) {
  Connection connection(url);
  std::map<std::string, std::vector<Bytes>> received;
  std::size_t total = 0;
  msg::for_each_channel([&]<class Message>(const char* name) {
    connection.subscribe<Message>(name, [&](const Message& m, const Receipt& receipt) {
      received[std::string(receipt.channel)].push_back(odoloc::lcm::encode(m));
      ++total;
    });
  });
  std::ofstream(ready_file).put('\n');
  const Clock::time_point deadline = Clock::now() + timeout;
  while (total < expected.size() && Clock::now() < deadline)
    connection.handle(100ms);
  // Anything after the last expected message is one too many.
  while (connection.handle(200ms)) {
  }

  std::map<std::string, std::vector<Bytes>> wanted;
  for (const msg::Event& e : expected)
    wanted[e.channel].push_back(e.bytes);
  int problems = 0;
  for (const auto& [channel, messages] : wanted) {
    const std::vector<Bytes>& got = received[channel];
    for (std::size_t i = 0; i < got.size() && i < messages.size(); ++i) {
      if (got[i] != messages[i]) {
        std::printf("%s: message %zu of %zu is not the one sent (missing or out of order)\n",
                    channel.c_str(), i, messages.size());
        ++problems;
        break;
      }
    }
    if (got.size() != messages.size()) {
      std::printf("%s: %zu of %zu messages\n", channel.c_str(), got.size(), messages.size());
      ++problems;
    }
  }
  if (connection.malformed() != 0) {
    std::printf("%llu malformed messages\n",
                static_cast<unsigned long long>(connection.malformed()));
    ++problems;
  }
  std::printf("subscriber: %zu of %zu messages on %zu channels, %s\n", total, expected.size(),
              wanted.size(), problems == 0 ? "complete and in order" : "INCOMPLETE");
  return problems == 0 ? 0 : 1;
}

// Events of the sequence (not probes) in the log so far.
std::size_t logged_events(const std::string& log_file) {
  lcm::LogFile log(log_file, "r");
  std::size_t events = 0;
  if (!log.good())
    return 0;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent())
    events += e->channel != msg::kProbeChannel ? 1 : 0;
  return events;
}

int publish(const std::string& url, const std::string& log_file, int ticks,
            std::chrono::seconds timeout) {
  const std::vector<msg::Event> events = msg::drive_sequence(ticks);
  Connection connection(url);
  const Clock::time_point deadline = Clock::now() + timeout;
  const char probe[] = "probe";
  std::error_code error;
  while (!(std::filesystem::file_size(log_file, error) > 0 && !error)) {
    if (Clock::now() > deadline) {
      std::printf("publisher: %s stayed empty: lcm-logger records nothing\n", log_file.c_str());
      return 1;
    }
    connection.publish_raw(msg::kProbeChannel, probe, sizeof probe);
    std::this_thread::sleep_for(20ms);
  }
  std::int64_t tick_time = events.front().utime;
  for (const msg::Event& e : events) {
    if (e.utime != tick_time) {
      tick_time = e.utime;
      std::this_thread::sleep_for(1ms);
    }
    connection.publish_raw(e.channel, e.bytes.data(), e.bytes.size());
  }
  // lcm-logger flushes its file only when a message arrives: probes until
  // the log holds the whole sequence.
  std::size_t logged = 0;
  while ((logged = logged_events(log_file)) < events.size() && Clock::now() < deadline) {
    connection.publish_raw(msg::kProbeChannel, probe, sizeof probe);
    std::this_thread::sleep_for(20ms);
  }
  std::printf("publisher: %zu messages sent, %zu in %s\n", events.size(), logged, log_file.c_str());
  return logged == events.size() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() != 5 || (args[0] != "subscribe" && args[0] != "subscribe-log" &&
                           args[0] != "publish" && args[0] != "garbage")) {
    std::fprintf(stderr,
                 "usage: odoloc_lcm_peer subscribe URL READY_FILE TICKS TIMEOUT_S\n"
                 "       odoloc_lcm_peer subscribe-log URL READY_FILE LOG TIMEOUT_S\n"
                 "       odoloc_lcm_peer garbage URL CHANNEL COUNT 0\n"
                 "       odoloc_lcm_peer publish URL LOG_FILE TICKS TIMEOUT_S\n");
    return 2;
  }
  try {
    if (args[0] == "garbage") {
      Connection connection(args[1]);
      const char junk[] = "not an odoloc message";
      for (int i = 0; i < std::stoi(args[3]); ++i)
        connection.publish_raw(args[2], junk, sizeof junk - static_cast<std::size_t>(i % 5));
      return 0;
    }
    const std::chrono::seconds timeout{std::stoi(args[4])};
    if (args[0] == "subscribe-log")
      return subscribe(args[1], args[2], log_events(args[3]), timeout);
    const int ticks = std::stoi(args[3]);
    return args[0] == "subscribe" ? subscribe(args[1], args[2], msg::drive_sequence(ticks), timeout)
                                  : publish(args[1], args[2], ticks, timeout);
  } catch (const std::exception& e) {
    std::printf("odoloc_lcm_peer: %s\n", e.what());
    return 1;
  }
}
