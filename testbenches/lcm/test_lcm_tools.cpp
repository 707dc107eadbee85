// The LCM layer across processes with LCM's own tools, over udpm:// with
// ttl=0 inside a private network namespace (unshare --net, multicast on the
// loopback), so nothing reaches or comes from the host's network:
//   - lcm-logplayer replays a log this test wrote into a subscriber process
//     (odoloc_lcm_peer), which checks that every message decodes and that
//     each channel's sequence is complete and in order;
//   - lcm-logger records what a publisher process sends, and the recorded
//     log is read back here with lcm::LogFile.
// Skipped, saying so, where network namespaces are not permitted. Every
// process runs under a time limit.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "lcm_test_messages.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc/process/run_program.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::process::ProgramResult;
namespace msg = odoloc::tb::lcm;

constexpr int kTicks = 200;  // 2 s of a 100 Hz run: 650 messages

// The namespace's own loopback with multicast, which udpm:// needs.
constexpr char kLoopbackMulticast[] =
    "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo "
    "|| exit 97\n";

// Runs `script` (sh, arguments "$1"...) in a fresh network namespace with
// multicast on its loopback; killed after `limit_s` seconds (and 5 s later
// with SIGKILL), every process the script started with it.
ProgramResult in_namespace(const std::string& script, const std::vector<std::string>& args,
                           int limit_s, const fs::path& dir) {
  std::vector<std::string> argv = {"-k", "5",  std::to_string(limit_s),     "unshare", "--net",
                                   "sh", "-c", kLoopbackMulticast + script, "sh"};
  argv.insert(argv.end(), args.begin(), args.end());
  return odoloc::process::run_program("timeout", argv, dir);
}

// Why such a namespace cannot be made here; empty when it can.
std::string namespace_unavailable() {
  const ProgramResult r = in_namespace("true", {}, 10, fs::temp_directory_path());
  if (r.ok())
    return "";
  return r.message.empty() ? "exit status " + std::to_string(r.exit_status) : r.message;
}

// The events of a log, in order.
struct Logged {
  std::string channel;
  std::vector<std::uint8_t> bytes;
  std::int64_t eventnum;
  std::int64_t timestamp;
};
std::vector<Logged> read_log(const fs::path& path) {
  lcm::LogFile log(path.string(), "r");
  EXPECT_TRUE(log.good()) << path;
  std::vector<Logged> events;
  if (!log.good())
    return events;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    const auto* data = static_cast<const std::uint8_t*>(e->data);
    events.push_back(Logged{.channel = e->channel,
                            .bytes = {data, data + e->datalen},
                            .eventnum = e->eventnum,
                            .timestamp = e->timestamp});
  }
  return events;
}

class LcmTools : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string why = namespace_unavailable();
    if (!why.empty())
      GTEST_SKIP() << "network namespaces are not permitted here (unshare --net with multicast "
                      "on lo failed), so udpm:// cannot be tested in isolation: "
                   << why;
  }
};

TEST_F(LcmTools, LogplayerReplaysALogIntoASubscriberProcess) {
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_lcm_tools", "replay");
  const std::vector<msg::Event> events = msg::drive_sequence(kTicks);
  // Logged at the simulated times: lcm-logplayer keeps the 100 Hz pace.
  ASSERT_TRUE(msg::write_log((dir / "drive.lcmlog").string(), events));
  // $1 peer, $2 URL, $3 folder, $4 lcm-logplayer, $5 ticks. The subscriber
  // is ready once it has subscribed; the log plays at 4x (0.5 s).
  const std::string script = R"(
"$1" subscribe "$2" "$3/ready" "$5" 15 >"$3/subscriber.txt" 2>&1 &
subscriber=$!
n=0
while [ ! -e "$3/ready" ]; do
  n=$((n + 1))
  if [ $n -gt 1000 ]; then echo "the subscriber was not ready within 10 s"; kill $subscriber; exit 98; fi
  sleep 0.01
done
if ! "$4" --speed 4 --lcm-url "$2" "$3/drive.lcmlog"; then
  echo "lcm-logplayer failed"; kill $subscriber; exit 99
fi
wait $subscriber
)";
  const ProgramResult r = in_namespace(script,
                                       {ODOLOC_LCM_PEER, odoloc::lcm::kDefaultUrl, dir.string(),
                                        ODOLOC_LCM_LOGPLAYER, std::to_string(kTicks)},
                                       40, dir);
  const std::string report = odoloc::tb::slurp(dir / "subscriber.txt");
  EXPECT_TRUE(r.ok()) << "exit " << r.exit_status << "\n" << r.message << "\n" << report;
  EXPECT_NE(
      report.find("subscriber: " + std::to_string(events.size()) + " of " +
                  std::to_string(events.size()) + " messages on 8 channels, complete and in order"),
      std::string::npos)
      << report;
}

TEST_F(LcmTools, LoggerRecordsAPublisherProcess) {
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_lcm_tools", "record");
  const fs::path log = dir / "recorded.lcmlog";
  // $1 peer, $2 URL, $3 log, $4 lcm-logger, $5 ticks. The publisher returns
  // once the log holds the whole sequence; SIGINT then stops the logger.
  const std::string script = R"(
"$4" --lcm-url "$2" --flush-interval=10 --quiet --force "$3" &
logger=$!
"$1" publish "$2" "$3" "$5" 15
published=$?
kill -INT $logger
wait $logger
logged=$?
[ $published -eq 0 ] || exit $published
exit $logged
)";
  const ProgramResult r = in_namespace(script,
                                       {ODOLOC_LCM_PEER, odoloc::lcm::kDefaultUrl, log.string(),
                                        ODOLOC_LCM_LOGGER, std::to_string(kTicks)},
                                       40, dir);
  ASSERT_TRUE(r.ok()) << "exit " << r.exit_status << "\n" << r.message;

  const std::vector<msg::Event> sent = msg::drive_sequence(kTicks);
  const std::vector<Logged> logged = read_log(log);
  // Probes (sent until the logger was seen recording), exactly the
  // sequence, maybe probes again (sent until the logger had written it all).
  std::size_t first = 0;
  while (first < logged.size() && logged[first].channel == msg::kProbeChannel)
    ++first;
  EXPECT_GE(first, 1U);
  ASSERT_GE(logged.size() - first, sent.size()) << "probes first: " << first;
  for (std::size_t i = 0; i < logged.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(logged[i].eventnum, static_cast<std::int64_t>(i));
    if (i > 0) {
      EXPECT_GE(logged[i].timestamp, logged[i - 1].timestamp);
    }
    if (i < first || i >= first + sent.size()) {
      EXPECT_EQ(logged[i].channel, msg::kProbeChannel);
      continue;
    }
    const msg::Event& expected = sent[i - first];
    ASSERT_EQ(logged[i].channel, expected.channel);
    ASSERT_EQ(logged[i].bytes, expected.bytes);
    EXPECT_TRUE(msg::decodes_as_channel_type(logged[i].channel, logged[i].bytes.data(),
                                             logged[i].bytes.size()));
  }
}

}  // namespace
