// The LCM layer across processes with LCM's own tools, over udpm:// with
// ttl=0 inside a private network namespace (unshare --net, multicast on the
// loopback), so nothing reaches or comes from the host's network:
//   - lcm-logplayer replays a log this test wrote into a subscriber process
//     (odoloc_lcm_peer), which checks that every message decodes and that
//     each channel's sequence is complete and in order;
//   - lcm-logger records what a publisher process sends, and the recorded
//     log is read back here with lcm::LogFile;
//   - `odoloc sim` as a user runs it: its log replays into a subscriber
//     process, a live simulator answers the register bridge.
// Skipped, saying so, where network namespaces are not permitted; except
// SimulatorJson, which needs no network (the simulator writes a log).
// Every process runs under a time limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
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

// Starts odoloc_lcm_peer with `peer_args` (in them $2 is the URL, $3 the
// folder) in a private network namespace, waits until it has subscribed
// (it creates $3/ready), replays `log` (relative to `dir`) with
// lcm-logplayer and `player_options`, and waits for the peer's verdict,
// which it writes to $3/subscriber.txt.
ProgramResult replay_into_peer(const std::string& peer_args, const std::string& player_options,
                               const std::string& log, const fs::path& dir) {
  const std::string script = "\"$1\" " + peer_args + R"( >"$3/subscriber.txt" 2>&1 &
subscriber=$!
n=0
while [ ! -e "$3/ready" ]; do
  n=$((n + 1))
  if [ $n -gt 1000 ]; then echo "the subscriber was not ready within 10 s"; kill $subscriber; exit 98; fi
  sleep 0.01
done
if ! "$4" )" + player_options +
                             R"( --lcm-url "$2" "$3/$5"; then
  echo "lcm-logplayer failed"; kill $subscriber; exit 99
fi
wait $subscriber
)";
  return in_namespace(
      script, {ODOLOC_LCM_PEER, odoloc::lcm::kDefaultUrl, dir.string(), ODOLOC_LCM_LOGPLAYER, log},
      60, dir);
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
  // The log plays at 4x (0.5 s).
  const ProgramResult r =
      replay_into_peer("subscribe \"$2\" \"$3/ready\" " + std::to_string(kTicks) + " 15",
                       "--speed 4", "drive.lcmlog", dir);
  const std::string report = odoloc::tb::slurp(dir / "subscriber.txt");
  EXPECT_TRUE(r.ok()) << "exit " << r.exit_status << "\n" << r.message << "\n" << report;
  std::set<std::string> channels;
  for (const msg::Event& e : events)
    channels.insert(e.channel);
  EXPECT_NE(report.find("subscriber: " + std::to_string(events.size()) + " of " +
                        std::to_string(events.size()) + " messages on " +
                        std::to_string(channels.size()) + " channels, complete and in order"),
            std::string::npos)
      << report;
}

// `odoloc sim` writes a real LCM event log: every stage's channel is in it,
// every event decodes as its channel's type, and lcm-logplayer replays the
// whole of it, in order, into a subscriber process.
TEST_F(LcmTools, SimulatorLogReplaysIntoASubscriberProcess) {
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_lcm_tools", "sim");
  const ProgramResult sim = odoloc::process::run_program(
      ODOLOC_CLI, {"sim", "--duration", "3", "--out", (dir / "run").string(), "--no-plot"}, dir);
  ASSERT_TRUE(sim.ok()) << sim.message;
  const fs::path log = dir / "run" / "odoloc.lcmlog";
  std::map<std::string, int> per_channel;
  int undecodable = 0;
  for (const Logged& e : read_log(log)) {
    ++per_channel[e.channel];
    undecodable += msg::decodes_as_channel_type(e.channel, e.bytes.data(), e.bytes.size()) ? 0 : 1;
  }
  EXPECT_EQ(undecodable, 0);
  // 3 s of the 100 Hz loop: truth, odometry and the min-select, rear,
  // front and (after the first fix) fused poses every 10 ms; encoders every
  // 100 ms; three beacon cycles of 0.9 s (the first locks).
  EXPECT_EQ(per_channel[odoloc::lcm::channel::kTruth], 300);
  EXPECT_EQ(per_channel[odoloc::lcm::channel::kOdometry], 300);
  EXPECT_EQ(per_channel[odoloc::lcm::channel::kEncoders], 30);
  namespace channel = odoloc::lcm::channel;
  for (const char* pose : {channel::kPoseOdometry, channel::kPoseRear, channel::kPoseFront})
    EXPECT_EQ(per_channel[pose], 300) << pose;
  EXPECT_GT(per_channel[channel::kPoseFused], 0);
  EXPECT_GE(per_channel[odoloc::lcm::channel::kFix], 2);
  EXPECT_EQ(per_channel[odoloc::lcm::channel::kTof], per_channel[odoloc::lcm::channel::kFix]);
  // The log's event times are simulated: it plays at the robot's pace (3 s).
  const ProgramResult r =
      replay_into_peer("subscribe-log \"$2\" \"$3/ready\" \"$3/run/odoloc.lcmlog\" 20", "",
                       "run/odoloc.lcmlog", dir);
  const std::string report = odoloc::tb::slurp(dir / "subscriber.txt");
  EXPECT_TRUE(r.ok()) << "exit " << r.exit_status << "\n" << r.message << "\n" << report;
  int events = 0;
  for (const auto& [channel, n] : per_channel)
    events += n;
  EXPECT_NE(report.find("subscriber: " + std::to_string(events) + " of " + std::to_string(events) +
                        " messages on " + std::to_string(per_channel.size()) +
                        " channels, complete and in order"),
            std::string::npos)
      << report;
}

// The register bridge of a running `odoloc sim`, from other processes over
// udpm: `odoloc --target lcm reg read` gets the chip's words, a write is
// refused (the simulator runs without --allow-write) and changes nothing,
// garbage on the request channel is ignored and counted, and
// `odoloc watch pose` prints the live estimate.
// `odoloc --json sim --no-beacon-ranges`: the JSON counts what the filter
// did with each kind of measurement, Kleeman's ranges none (they only
// initialise it), and the log's ODOLOC_STATION messages agree with those
// counts outcome for outcome. No network: the run writes its log.
TEST(SimulatorJson, FilterUpdatesAgreeWithTheStationMessages) {
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_lcm_tools", "json");
  const ProgramResult sim =
      odoloc::process::run_program(ODOLOC_CLI,
                                   {"--json", "sim", "--duration", "12", "--no-beacon-ranges",
                                    "--out", (dir / "run").string(), "--no-plot"},
                                   dir);
  ASSERT_TRUE(sim.ok()) << sim.message;
  const std::size_t brace = sim.message.rfind("\n{");
  const nlohmann::json j = nlohmann::json::parse(
      sim.message.substr(brace == std::string::npos ? 0 : brace + 1), nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << sim.message;
  const nlohmann::json& updates = j.at("filter_updates");
  EXPECT_EQ(updates.size(), 7U);
  EXPECT_EQ(updates.at("beacon_range").at("accepted"), 0);
  std::map<std::pair<std::string, std::string>, int> logged;  // (kind, outcome)
  for (const Logged& e : read_log(dir / "run" / "odoloc.lcmlog")) {
    if (e.channel != odoloc::lcm::channel::kStation)
      continue;
    odoloc_lcm::station_measurement_t m{};
    ASSERT_TRUE(odoloc::lcm::decode(e.bytes.data(), e.bytes.size(), m));
    ++logged[{m.kind, m.outcome}];
  }
  int accepted = 0;
  for (const std::string kind : {"station_bearing", "station_range", "robot_bearing"}) {
    SCOPED_TRACE(kind);
    for (const std::string outcome : {"accepted", "reopened", "gated"})
      EXPECT_EQ(updates.at(kind).at(outcome), (logged[{kind, outcome}])) << outcome;
    accepted += updates.at(kind).at("accepted").get<int>();
  }
  // 12 s: the first fix after about 2 s, then a hit of each laser every
  // 2.5 s or so.
  EXPECT_GE(accepted, 6);
  std::set<std::string> kinds;
  for (const auto& [key, n] : logged)
    kinds.insert(key.first);
  EXPECT_EQ(kinds, (std::set<std::string>{"station_bearing", "station_range", "robot_bearing"}));
}

TEST_F(LcmTools, SimulatorAnswersTheRegisterBridge) {
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_lcm_tools", "bridge");
  // $1 odoloc, $2 URL, $3 folder, $4 peer.
  const std::string script = R"(
"$1" sim --realtime --duration 8 --lcm-url "$2" >"$3/sim.txt" 2>&1 &
sim=$!
n=0
until "$1" --target "lcm:$2" reg read top.id >"$3/read.txt" 2>&1; do
  n=$((n + 1))
  if [ $n -gt 50 ]; then echo "no answer from the simulator"; kill $sim; exit 90; fi
  sleep 0.1
done
"$1" --target "lcm:$2" reg write top.scratch=0x1234 >"$3/write.txt" 2>&1
echo $? >"$3/write_status.txt"
"$4" garbage "$2" ODOLOC_REG_REQUEST 7 0
"$1" --target "lcm:$2" reg read top.scratch >"$3/scratch.txt" 2>&1 || { kill $sim; exit 91; }
"$1" watch pose --source odometry --count 3 --lcm-url "$2" >"$3/pose.txt" 2>&1 || { kill $sim; exit 92; }
wait $sim
)";
  const ProgramResult r = in_namespace(
      script, {ODOLOC_CLI, odoloc::lcm::kDefaultUrl, dir.string(), ODOLOC_LCM_PEER}, 60, dir);
  const std::string sim = odoloc::tb::slurp(dir / "sim.txt");
  ASSERT_TRUE(r.ok()) << "exit " << r.exit_status << "\n" << r.message << "\n" << sim;
  EXPECT_NE(odoloc::tb::slurp(dir / "read.txt").find("top.id @ 0x000 = 0x0d010002"),
            std::string::npos);
  const std::string write = odoloc::tb::slurp(dir / "write.txt");
  EXPECT_NE(odoloc::tb::slurp(dir / "write_status.txt"), "0\n") << write;
  EXPECT_NE(write.find("--allow-write"), std::string::npos) << write;
  EXPECT_NE(odoloc::tb::slurp(dir / "scratch.txt").find("top.scratch @ 0x004 = 0x00000000"),
            std::string::npos);
  const std::string pose = odoloc::tb::slurp(dir / "pose.txt");
  EXPECT_EQ(std::count(pose.begin(), pose.end(), '\n'), 4) << pose;  // a header and 3 estimates
  // The simulator's closing line counts what the bridge saw. At least the
  // two reads were served: a slow start (a sanitizer build) makes the first
  // reads time out and be asked again, and the simulator answers them all.
  const std::size_t at = sim.find("register bridge: ");
  ASSERT_NE(at, std::string::npos) << sim;
  int served = -1, refused = -1, errors = -1, malformed = -1;
  ASSERT_EQ(std::sscanf(sim.c_str() + at,
                        "register bridge: %d served, %d refused, %d errors; %d malformed", &served,
                        &refused, &errors, &malformed),
            4)
      << sim;
  EXPECT_GE(served, 2) << sim;
  EXPECT_EQ(refused, 1) << sim;
  EXPECT_EQ(errors, 0) << sim;
  EXPECT_EQ(malformed, 7) << sim;
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
