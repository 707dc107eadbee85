// The user's path to a simulator's registers and poses: `odoloc --target lcm
// reg ...` and `odoloc watch pose`, run in process through run_cli() with
// the tool's own target opener, over udpm:// at the default URL, against a
// stand-in simulator in a thread (the simulated chip behind a
// RegisterBridge, publishing pose estimates at 100 Hz on its own LCM
// connection). The process first moves into a private network namespace
// with multicast on its loopback, so nothing reaches or comes from the
// host's network and tests can run side by side; where that is not
// permitted the tests are skipped, saying so. Expected outputs are the same
// commands on `--target sim` (a fresh chip there as here) and the estimates
// the stand-in published.
#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <filesystem>
#include <future>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/bridge/register_bridge.hpp"
#include "odoloc/cli/app.hpp"
#include "odoloc/cli/errors.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/process/run_program.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc_lcm/pose_estimate_t.hpp"

namespace {

using namespace std::chrono_literals;
namespace cli = odoloc::cli;
namespace channel = odoloc::lcm::channel;
using nlohmann::json;
using Pose = odoloc_lcm::pose_estimate_t;

// Moves this thread (and every thread and process it starts from now on)
// into a fresh network namespace whose loopback carries multicast, which
// udpm:// needs. Returns why it could not; empty when done.
std::string enter_private_network() {
  if (::unshare(CLONE_NEWNET) != 0)
    return std::string("unshare(CLONE_NEWNET): ") + std::strerror(errno);
  const odoloc::process::ProgramResult r = odoloc::process::run_shell(
      "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo",
      std::filesystem::temp_directory_path());
  return r.ok() ? "" : "multicast on lo: " + r.message;
}

// The stand-in's estimates: tick k (100 Hz), five sources, values from k.
constexpr const char* kSources[] = {"fused", "odometry", "rear", "front", "truth"};
std::int64_t tick_utime(std::int64_t k) {
  return 1'000'000 + 10'000 * k;
}
Pose estimate(std::int64_t k, int source) {
  Pose p{};
  p.utime = tick_utime(k);
  p.source = kSources[source];
  p.x = 0.01 * static_cast<double>(k) + source;
  p.y = -0.02 * static_cast<double>(k);
  p.theta = std::remainder(0.05 * static_cast<double>(k), 2 * std::numbers::pi);
  const double sd = 0.001 * (source + 1);
  p.covariance[0] = sd * sd;
  p.covariance[4] = 4 * sd * sd;
  p.covariance[8] = 1e-4 * (source + 1);
  p.covariance[1] = p.covariance[3] = 0.1 * sd * sd;
  p.odometry_only = k % 2 == 0;
  p.last_update_utime = source == 0 ? tick_utime(k - 1) : 0;
  return p;
}

// `odoloc sim` in miniature: the chip, its bridge and 100 Hz of estimates
// on the default URL, served from a thread of its own.
class StandIn {
 public:
  explicit StandIn(bool allow_write) : thread_([this, allow_write] { run(allow_write); }) {
    ready_.get_future().wait();
  }
  StandIn(const StandIn&) = delete;
  StandIn& operator=(const StandIn&) = delete;
  ~StandIn() { stop(); }
  // Stops the thread and rethrows what went wrong in it.
  void check() {
    stop();
    if (error_)
      std::rethrow_exception(error_);
  }
  // The bridge's counters when it stopped (after check()).
  [[nodiscard]] odoloc::bridge::RegisterBridge::Counters counters() const { return counters_; }

 private:
  void run(bool allow_write) {
    bool ready = false;
    try {
      odoloc::lcm::Connection connection;
      odoloc::board::ChipLink link{{}};
      odoloc::sw::SpiRegisterBus bus{link, {.crc = false, .confirm_writes = true}};
      odoloc::bridge::RegisterBridge bridge(connection, bus, allow_write);
      ready_.set_value();
      ready = true;
      auto next = std::chrono::steady_clock::now();
      for (std::int64_t k = 0; !stop_;) {
        (void)connection.handle(1ms);
        if (std::chrono::steady_clock::now() >= next) {
          for (int s = 0; s < 5; ++s)
            connection.publish(s == 4 ? channel::kTruth : channel::kPoseStreams.at(s).channel,
                               estimate(k, s));
          ++k;
          next += 10ms;
        }
      }
      counters_ = bridge.counters();
    } catch (...) {
      error_ = std::current_exception();
      if (!ready)
        ready_.set_value();
    }
  }
  void stop() {
    stop_ = true;
    if (thread_.joinable())
      thread_.join();
  }

  std::promise<void> ready_;
  std::atomic<bool> stop_{false};
  std::exception_ptr error_;
  odoloc::bridge::RegisterBridge::Counters counters_;
  std::thread thread_;
};

struct Outcome {
  int code = -1;
  std::string out, err;
};
// Runs the tool in process. Without `stop`, Ctrl-C comes after 10 s, so a
// command that waits for what never comes fails (exit 130) instead of hanging.
Outcome run(const std::vector<std::string>& args, const std::atomic<bool>* stop = nullptr) {
  std::atomic<bool> timed_out{false};
  std::mutex mutex;
  std::condition_variable_any never;
  const std::jthread watchdog([&](const std::stop_token& done) {
    std::unique_lock lock(mutex);
    never.wait_for(lock, done, 10s, [] { return false; });
    timed_out = !done.stop_requested();
  });
  std::istringstream in;
  std::ostringstream out, err;
  Outcome r;
  r.code =
      cli::run_cli(args, {in, out, err}, cli::open_target, stop != nullptr ? stop : &timed_out);
  r.out = out.str();
  r.err = err.str();
  return r;
}
// The same command on `--target lcm` and on a fresh simulated chip here.
void expect_as_on_sim(std::vector<std::string> args) {
  SCOPED_TRACE(args.back());
  args.insert(args.begin(), {"--target", "lcm"});
  const Outcome remote = run(args);
  args[1] = "sim";
  const Outcome local = run(args);
  EXPECT_EQ(remote.code, 0) << remote.err;
  EXPECT_EQ(remote.err, "");
  EXPECT_EQ(local.code, 0) << local.err;
  EXPECT_EQ(remote.out, local.out);
  EXPECT_FALSE(remote.out.empty());
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);)
    out.push_back(line);
  return out;
}

class BridgeCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { why_not_ = enter_private_network(); }
  void SetUp() override {
    if (!why_not_.empty())
      GTEST_SKIP() << "network namespaces are not permitted here, so udpm:// cannot be tested in "
                      "isolation: "
                   << why_not_;
  }
  static std::string why_not_;
};
std::string BridgeCli::why_not_;

TEST_F(BridgeCli, RegReadAndDumpAreThoseOfTheChip) {
  StandIn simulator(false);
  // First, while both chips have seen the same frames: live words such as
  // tof.timestamp count the clocks the frames took.
  expect_as_on_sim({"reg", "dump"});
  expect_as_on_sim({"reg", "read", "top.id", "eppm.left_rear.cfg", "eppm.left_rear.speed",
                    "eppm.left_rear.cfg.decode_mode"});
  expect_as_on_sim({"--json", "reg", "read", "odometry.pose_x_lo", "odometry.pose_x_hi"});
  simulator.check();
  EXPECT_GE(simulator.counters().served, 3U);
  EXPECT_EQ(simulator.counters().errors, 0U);
}

TEST_F(BridgeCli, WritesNeedAllowWrite) {
  {
    StandIn simulator(false);
    const Outcome refused = run({"--target", "lcm", "reg", "write", "top.scratch=42"});
    EXPECT_EQ(refused.code, cli::kExitBus);
    EXPECT_EQ(refused.out, "");
    EXPECT_NE(refused.err.find("odoloc: bus error: register writes are refused"), std::string::npos)
        << refused.err;
    EXPECT_NE(refused.err.find("--allow-write"), std::string::npos) << refused.err;
    const Outcome read = run({"--target", "lcm", "reg", "read", "top.scratch"});
    EXPECT_EQ(read.out, "top.scratch @ 0x004 = 0x00000000\n  value  [31:0]   0 (0x00000000)\n");
    simulator.check();
    EXPECT_EQ(simulator.counters().refused, 1U);
  }
  StandIn simulator(true);
  expect_as_on_sim({"reg", "write", "top.scratch=42", "eppm.left_rear.cfg.decode_mode=x2"});
  const Outcome read = run({"--target", "lcm", "reg", "read", "top.scratch"});
  EXPECT_EQ(read.out, "top.scratch @ 0x004 = 0x0000002a\n  value  [31:0]   42 (0x0000002a)\n");
  simulator.check();
}

TEST_F(BridgeCli, RegWatchRunsOnWallClockTime) {
  StandIn simulator(false);
  const auto start = std::chrono::steady_clock::now();
  const Outcome watch = run({"--target", "lcm", "--json", "reg", "watch", "top.id", "--interval",
                             "50ms", "--count", "3"});
  EXPECT_GE(std::chrono::steady_clock::now() - start, 100ms);
  ASSERT_EQ(watch.code, 0) << watch.err;
  const std::vector<std::string> samples = lines(watch.out);
  ASSERT_EQ(samples.size(), 3U);
  std::int64_t last = -1;
  for (const std::string& line : samples) {
    const json doc = json::parse(line);
    EXPECT_EQ(doc["values"][0]["value"], odoloc::regs::top::id::kReset);
    const std::int64_t t = doc["time_ns"];
    EXPECT_GE(t, last < 0 ? 0 : last + 50'000'000) << line;
    last = t;
  }
}

TEST_F(BridgeCli, WatchPosePrintsWhatWasPublished) {
  StandIn simulator(false);
  const Outcome text = run({"watch", "pose", "--count", "3"});
  ASSERT_EQ(text.code, 0) << text.err;
  const std::vector<std::string> table = lines(text.out);
  ASSERT_EQ(table.size(), 4U) << text.out;
  EXPECT_EQ(table[0],
            "     time_s  source           x_m         y_m  theta_deg     sd_x_m     sd_y_m  "
            "sd_theta_deg  odometry_only");
  for (std::size_t i = 1; i < table.size(); ++i) {
    std::istringstream row(table[i]);
    double t = 0, x = 0, y = 0, theta_deg = 0, sd_x = 0, sd_y = 0, sd_theta_deg = 0;
    std::string source, odometry_only;
    row >> t >> source >> x >> y >> theta_deg >> sd_x >> sd_y >> sd_theta_deg >> odometry_only;
    ASSERT_FALSE(row.fail()) << table[i];
    const auto k = std::llround((t * 1e6 - 1e6) / 1e4);
    const Pose p = estimate(k, 0);
    EXPECT_EQ(source, "fused");
    EXPECT_NEAR(x, p.x, 1e-6);
    EXPECT_NEAR(y, p.y, 1e-6);
    EXPECT_NEAR(theta_deg, p.theta * 180 / std::numbers::pi, 1e-4);
    EXPECT_NEAR(sd_x, 0.001, 1e-6);
    EXPECT_NEAR(sd_y, 0.002, 1e-6);
    EXPECT_NEAR(sd_theta_deg, 0.01 * 180 / std::numbers::pi, 1e-4);
    EXPECT_EQ(odometry_only, p.odometry_only ? "yes" : "no");
  }

  // Every source, as JSON: each line one published estimate, field for field.
  const Outcome all = run({"--json", "watch", "pose", "--source", "all", "--count", "25"});
  ASSERT_EQ(all.code, 0) << all.err;
  const std::vector<std::string> docs = lines(all.out);
  ASSERT_EQ(docs.size(), 25U);
  std::set<std::string> seen;
  for (const std::string& line : docs) {
    const json doc = json::parse(line);
    const std::string source = doc["source"];
    seen.insert(source);
    const int s = static_cast<int>(std::find(std::begin(kSources), std::end(kSources), source) -
                                   std::begin(kSources));
    ASSERT_LT(s, 5) << line;
    const std::int64_t utime = doc["utime_us"];
    const Pose p = estimate((utime - tick_utime(0)) / 10'000, s);
    EXPECT_EQ(utime, p.utime);
    EXPECT_EQ(doc["time_s"], static_cast<double>(p.utime) * 1e-6);
    EXPECT_EQ(doc["x_m"], p.x);
    EXPECT_EQ(doc["y_m"], p.y);
    EXPECT_EQ(doc["theta_rad"], p.theta);
    EXPECT_EQ(doc["sd_x_m"], std::sqrt(p.covariance[0]));
    EXPECT_EQ(doc["sd_y_m"], std::sqrt(p.covariance[4]));
    EXPECT_EQ(doc["sd_theta_rad"], std::sqrt(p.covariance[8]));
    EXPECT_EQ(doc["covariance"], json(p.covariance));
    EXPECT_EQ(doc["odometry_only"], json(p.odometry_only != 0));  // a JSON boolean
    EXPECT_EQ(doc["last_update_utime_us"], p.last_update_utime);
  }
  EXPECT_EQ(seen.size(), 5U) << "25 consecutive estimates hold every source";

  const Outcome truth = run({"--json", "watch", "pose", "--source", "truth", "--count", "2"});
  ASSERT_EQ(truth.code, 0) << truth.err;
  for (const std::string& line : lines(truth.out))
    EXPECT_EQ(json::parse(line)["source"], "truth");
  simulator.check();
}

TEST_F(BridgeCli, WithoutASimulator) {
  // Nobody answers: the request times out, naming the URL, after 2 s.
  const auto start = std::chrono::steady_clock::now();
  const Outcome alone = run({"--target", "lcm", "reg", "read", "top.id"});
  EXPECT_GE(std::chrono::steady_clock::now() - start, 2s);
  EXPECT_EQ(alone.code, cli::kExitBus);
  EXPECT_EQ(alone.err, std::string("odoloc: bus error: no simulator answered on ") +
                           odoloc::lcm::kDefaultUrl +
                           " within 2 s: start `odoloc sim` (docs/lcm.md, \"Register bridge\")\n");

  // Ctrl-C ends a request's wait and a silent watch at once, printing nothing.
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--target", "lcm", "reg", "read", "top.id"},
        std::vector<std::string>{"watch", "pose"}}) {
    std::atomic<bool> stop{false};
    std::thread ctrl_c([&stop] {
      std::this_thread::sleep_for(100ms);
      stop = true;
    });
    const auto begun = std::chrono::steady_clock::now();
    const Outcome interrupted = run(args, &stop);
    ctrl_c.join();
    EXPECT_EQ(interrupted.code, cli::kExitInterrupted) << args.back();
    EXPECT_LT(std::chrono::steady_clock::now() - begun, 1s) << args.back();
    EXPECT_EQ(interrupted.out + interrupted.err, "") << args.back();
  }
}

}  // namespace
