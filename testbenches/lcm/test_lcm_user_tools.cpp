// The main job's LCM log as users' own tools see it (docs/lcm.md):
//   - its event timestamps never go backwards, each message's utime (the
//     capture time) at or before its event, one channel per pose source;
//   - odometry_increment_t carries the motion since the previous message:
//     the increments compose into the fabric's pose, and their ds sum to the
//     distance the truth drove;
//   - the Python reader (odoloc_lcmlog with lcm-gen's Python types) decodes
//     every event as the C++ types do, keeps every whole event of a damaged
//     log and says what it skipped; its CSV holds the same numbers;
//   - a real lcm-spy (Debian's liblcm-java) on the test's own Xvfb finds
//     the generated Java types and decodes every message of every channel;
//     the launcher odoloc-lcm-spy starts it and lcm-logplayer-gui on
//     OpenJDK 17, and SIGTERM ends them.
// The Python and Java cases skip when python3, Xvfb, java or the types jar
// are absent (scripts/setup-debian.sh --tests installs them).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "lcm_test_messages.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/sw/pose_ekf.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
namespace channel = odoloc::lcm::channel;
namespace msg = odoloc::tb::lcm;
using nlohmann::json;
using odoloc::tb::finish;
using odoloc::tb::spawn;

// ------------------------------------------------ the C++ decode as JSON

// JSON has no NaN: null, as the Python reader writes it.
json number(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}
template <class T>
json number(const T& v) {
  return json(v);
}
json number(std::int8_t v) {
  return json(static_cast<int>(v));
}
template <class T, std::size_t N>
json number(const T (&a)[N]) {
  json out = json::array();
  for (const T& v : a)
    out.push_back(number(v));
  return out;
}
template <class T>
json number(const std::vector<T>& a) {
  json out = json::array();
  for (const T& v : a)
    out.push_back(number(v));
  return out;
}

// LCM's C++ holds a boolean in an int8_t: named as such.
json flag(std::int8_t v) {
  return json(v != 0);
}
template <std::size_t N>
json flag(const std::int8_t (&a)[N]) {
  json out = json::array();
  for (const std::int8_t v : a)
    out.push_back(flag(v));
  return out;
}

#define ODOLOC_FIELD(m, j, name) j[#name] = number(m.name)
#define ODOLOC_FLAG(m, j, name) j[#name] = flag(m.name)

json to_json(const odoloc_lcm::pose_estimate_t& m) {
  json j;
  ODOLOC_FIELD(m, j, utime);
  ODOLOC_FIELD(m, j, source);
  ODOLOC_FIELD(m, j, x);
  ODOLOC_FIELD(m, j, y);
  ODOLOC_FIELD(m, j, theta);
  ODOLOC_FIELD(m, j, covariance);
  ODOLOC_FLAG(m, j, odometry_only);
  ODOLOC_FIELD(m, j, last_update_utime);
  return j;
}
json to_json(const odoloc_lcm::odometry_increment_t& m) {
  json j;
  ODOLOC_FIELD(m, j, utime);
  ODOLOC_FIELD(m, j, updates);
  ODOLOC_FIELD(m, j, dx);
  ODOLOC_FIELD(m, j, dy);
  ODOLOC_FIELD(m, j, dtheta);
  ODOLOC_FIELD(m, j, ds);
  ODOLOC_FIELD(m, j, last_rear_ds);
  ODOLOC_FIELD(m, j, last_rear_dtheta);
  ODOLOC_FIELD(m, j, last_front_ds);
  ODOLOC_FIELD(m, j, last_front_dtheta);
  ODOLOC_FIELD(m, j, last_ds);
  ODOLOC_FIELD(m, j, last_dtheta);
  ODOLOC_FLAG(m, j, ds_from_front);
  ODOLOC_FLAG(m, j, dtheta_from_front);
  ODOLOC_FIELD(m, j, steer_phi);
  ODOLOC_FIELD(m, j, x);
  ODOLOC_FIELD(m, j, y);
  ODOLOC_FIELD(m, j, theta);
  return j;
}
json to_json(const odoloc_lcm::encoder_state_t& m) {
  json j;
  ODOLOC_FIELD(m, j, utime);
  ODOLOC_FIELD(m, j, position_count);
  ODOLOC_FIELD(m, j, speed_value);
  ODOLOC_FIELD(m, j, speed_mode);
  ODOLOC_FLAG(m, j, valid);
  ODOLOC_FLAG(m, j, stalled);
  ODOLOC_FLAG(m, j, forward);
  return j;
}
json to_json(const odoloc_lcm::tof_measurement_set_t& m) {
  json j;
  ODOLOC_FIELD(m, j, utime);
  ODOLOC_FIELD(m, j, cycle);
  ODOLOC_FIELD(m, j, tick_s);
  ODOLOC_FIELD(m, j, num_channels);
  j["channels"] = json::array();
  for (const odoloc_lcm::tof_channel_events_t& c : m.channels) {
    json e;
    ODOLOC_FIELD(c, e, channel);
    ODOLOC_FIELD(c, e, num_events);
    ODOLOC_FIELD(c, e, rise_ticks);
    j["channels"].push_back(e);
  }
  ODOLOC_FLAG(m, j, has_sync);
  ODOLOC_FIELD(m, j, sync_tick);
  return j;
}
json to_json(const odoloc_lcm::beacon_fix_t& m) {
  json j;
  ODOLOC_FIELD(m, j, utime);
  ODOLOC_FIELD(m, j, solver);
  ODOLOC_FIELD(m, j, x);
  ODOLOC_FIELD(m, j, y);
  ODOLOC_FIELD(m, j, covariance);
  ODOLOC_FIELD(m, j, beacons_used);
  ODOLOC_FIELD(m, j, residual_rms);
  ODOLOC_FLAG(m, j, valid);
  return j;
}
json to_json(const odoloc_lcm::station_measurement_t& m) {
  json j;
  ODOLOC_FIELD(m, j, utime);
  ODOLOC_FIELD(m, j, kind);
  ODOLOC_FIELD(m, j, value);
  ODOLOC_FIELD(m, j, sd);
  ODOLOC_FIELD(m, j, station_x);
  ODOLOC_FIELD(m, j, station_y);
  ODOLOC_FIELD(m, j, outcome);
  return j;
}
// The simulator's log carries no register or status messages (a live run's).
template <class Message>
json to_json(const Message& /*unused*/) {
  return nullptr;
}

#undef ODOLOC_FIELD
#undef ODOLOC_FLAG

struct LoggedEvent {
  std::int64_t timestamp = 0;
  std::string channel;
  std::optional<std::int64_t> utime;  // the message's, when it decoded
  json message;                       // null when it did not decode
};

std::vector<LoggedEvent> read_log(const fs::path& path) {
  ::lcm::LogFile log(path.string(), "r");
  EXPECT_TRUE(log.good()) << path;
  std::vector<LoggedEvent> events;
  for (const ::lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    LoggedEvent out{e->timestamp, e->channel, std::nullopt, nullptr};
    msg::for_each_channel([&]<class Message>(const char* name) {
      Message m{};
      if (out.channel != name ||
          !odoloc::lcm::decode(e->data, static_cast<std::size_t>(e->datalen), m))
        return;
      out.utime = m.utime;
      out.message = to_json(m);
    });
    events.push_back(std::move(out));
  }
  return events;
}

// ------------------------------------------------------------ the run

std::string program_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");  // NOLINT(concurrency-mt-unsafe)
  std::stringstream dirs(path != nullptr ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((fs::path(dir) / name).c_str(), X_OK) == 0)
      return (fs::path(dir) / name).string();
  return {};
}

class MainJobLog : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(odoloc::tb::fresh_dir("odoloc_lcm_users", "main_job"));
    const odoloc::tb::ChildResult sim =
        finish(spawn(ODOLOC_CLI, {"sim", "--out", "run", "--no-plot"}, "", {}, *dir_),
               std::chrono::minutes{10});
    ASSERT_EQ(sim.code, 0) << sim.out << sim.err;
    events_ = new std::vector<LoggedEvent>(read_log(log()));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete events_;
  }
  static fs::path log() { return *dir_ / "run" / "odoloc.lcmlog"; }
  static std::map<std::string, std::size_t> per_channel() {
    std::map<std::string, std::size_t> counts;
    for (const LoggedEvent& e : *events_)
      ++counts[e.channel];
    return counts;
  }
  static fs::path* dir_;
  static std::vector<LoggedEvent>* events_;
};
fs::path* MainJobLog::dir_ = nullptr;
std::vector<LoggedEvent>* MainJobLog::events_ = nullptr;

TEST_F(MainJobLog, EventTimesNeverGoBackwardsAndFollowTheCaptureTimes) {
  ASSERT_GT(events_->size(), 10'000U);
  std::int64_t previous = 0;
  std::size_t backwards = 0, late = 0;
  std::int64_t worst_lag = 0;
  for (const LoggedEvent& e : *events_) {
    backwards += e.timestamp < previous ? 1 : 0;
    previous = e.timestamp;
    ASSERT_TRUE(e.utime) << e.channel << " at " << e.timestamp << " does not decode";
    // Published when measured or later; a fix or a cycle's events when the
    // decoder closes the cycle: at most a 1.05 s beacon cycle after their
    // first capture, plus the capture unit's 50 ms drain period and a step.
    late += *e.utime > e.timestamp ? 1 : 0;
    worst_lag = std::max(worst_lag, e.timestamp - *e.utime);
    if (e.channel.starts_with(channel::kPosePrefix) || e.channel == channel::kTruth ||
        e.channel == channel::kOdometry || e.channel == channel::kEncoders) {
      EXPECT_EQ(*e.utime, e.timestamp) << e.channel;
    }
  }
  EXPECT_EQ(backwards, 0U);
  EXPECT_EQ(late, 0U);
  EXPECT_GT(worst_lag, 100'000);  // the case that went backwards: fixes a cycle late
  EXPECT_LE(worst_lag, 1'050'000 + 2 * 50'000 + 10'000);
}

TEST_F(MainJobLog, OneChannelPerPoseSource) {
  std::size_t poses = 0;
  for (const LoggedEvent& e : *events_) {
    if (!e.channel.starts_with(channel::kPosePrefix))
      continue;
    ++poses;
    const std::string source = e.message.at("source");
    ASSERT_NE(channel::pose_channel(source), nullptr) << source;
    EXPECT_EQ(e.channel, channel::pose_channel(source));
  }
  const auto counts = per_channel();
  EXPECT_EQ(counts.at(channel::kPoseOdometry), counts.at(channel::kTruth));
  EXPECT_GT(counts.at(channel::kPoseFused), counts.at(channel::kTruth) * 9 / 10);
  EXPECT_EQ(poses, counts.at(channel::kPoseFused) + counts.at(channel::kPoseOdometry) +
                       counts.at(channel::kPoseRear) + counts.at(channel::kPoseFront));
}

// The increments chain into the fabric's pose, read by read, and their ds
// add up to the truth's path (the odometry's own error is under 1 %: its
// return-to-start error is 0.18 m of 44 m).
TEST_F(MainJobLog, OdometryIncrementsAreTheMotionSinceThePreviousMessage) {
  using odoloc::sw::fuse::Pose;
  std::optional<Pose> chained;
  double ds_sum = 0, truth_path = 0, worst_mm = 0;
  std::optional<std::pair<double, double>> last_truth;
  std::size_t reads = 0;
  for (const LoggedEvent& e : *events_) {
    if (e.channel == channel::kTruth) {
      const double x = e.message.at("x"), y = e.message.at("y");
      if (last_truth)
        truth_path += std::hypot(x - last_truth->first, y - last_truth->second);
      last_truth = {x, y};
      continue;
    }
    if (e.channel != channel::kOdometry)
      continue;
    const json& m = e.message;
    const Pose fabric{odoloc::sw::fuse::Vector3(m.at("x").get<double>(), m.at("y").get<double>(),
                                                m.at("theta").get<double>())};
    const odoloc::sw::fuse::Vector3 d(m.at("dx").get<double>(), m.at("dy").get<double>(),
                                      m.at("dtheta").get<double>());
    EXPECT_DOUBLE_EQ(static_cast<double>(m.at("ds")), odoloc::sw::fuse::arc_length(d));
    // From the first read on: each increment moves the previous read's pose
    // to this one's.
    chained = chained ? odoloc::sw::fuse::compose(*chained, d) : fabric;
    worst_mm = std::max(worst_mm, 1e3 * (chained->position() - fabric.position()).norm());
    EXPECT_NEAR(odoloc::sw::fuse::wrap_angle(chained->heading() - fabric.heading()), 0, 1e-9);
    ds_sum += static_cast<double>(m.at("ds"));
    ++reads;
  }
  ASSERT_GT(reads, 9'000U);
  EXPECT_LT(worst_mm, 1e-3);  // a micrometre after 10 000 compositions
  EXPECT_GT(truth_path, 40.0);
  EXPECT_NEAR(ds_sum, truth_path, 0.01 * truth_path)
      << "ds sums to " << ds_sum << " m over a " << truth_path << " m drive";
}

// ---------------------------------------------------------------- Python

std::string python() {
  return program_on_path("python3");
}

odoloc::tb::ChildResult run_reader(const std::vector<std::string>& args, const fs::path& dir) {
  std::vector<std::string> all{"-m", "odoloc_lcmlog"};
  all.insert(all.end(), args.begin(), args.end());
  return finish(spawn(python(), all, "", {}, dir, {"PYTHONPATH=" ODOLOC_LCM_PYTHON_DIR}),
                std::chrono::minutes{5});
}

TEST_F(MainJobLog, PythonReaderDecodesEveryEventAsTheCppTypes) {
  if (python().empty())
    GTEST_SKIP() << "python3 not on PATH";
  const odoloc::tb::ChildResult r = run_reader({log().string()}, *dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  std::istringstream lines(r.out);
  std::size_t n = 0, compared = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    ASSERT_LT(n, events_->size()) << "more lines than the log has events";
    const LoggedEvent& e = (*events_)[n];
    json row = json::parse(line);
    EXPECT_EQ(row.at("channel"), e.channel) << n;
    EXPECT_EQ(row.at("timestamp"), e.timestamp) << n;
    row.erase("channel");
    row.erase("timestamp");
    ASSERT_FALSE(e.message.is_null()) << e.channel;
    EXPECT_EQ(row, e.message) << "event " << n << " on " << e.channel;
    ++compared;
  }
  EXPECT_EQ(n, events_->size());
  EXPECT_EQ(compared, events_->size());
}

TEST_F(MainJobLog, PythonReaderWritesOneChannelAsCsvAndLoadsIntoLists) {
  if (python().empty())
    GTEST_SKIP() << "python3 not on PATH";
  const odoloc::tb::ChildResult csv =
      run_reader({log().string(), "--channel", channel::kPoseFused, "--csv"}, *dir_);
  ASSERT_EQ(csv.code, 0) << csv.err;
  std::istringstream lines(csv.out);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header,
            "channel,timestamp,utime,source,x,y,theta,covariance[0],covariance[1],"
            "covariance[2],covariance[3],covariance[4],covariance[5],covariance[6],"
            "covariance[7],covariance[8],odometry_only,last_update_utime");
  std::vector<const LoggedEvent*> fused;
  for (const LoggedEvent& e : *events_)
    if (e.channel == channel::kPoseFused)
      fused.push_back(&e);
  std::size_t rows = 0;
  for (std::string line; std::getline(lines, line); ++rows) {
    ASSERT_LT(rows, fused.size());
    std::vector<std::string> cells;
    std::stringstream split(line);
    for (std::string cell; std::getline(split, cell, ',');)
      cells.push_back(cell);
    ASSERT_EQ(cells.size(), 18U) << line;
    EXPECT_EQ(std::stod(cells[4]), static_cast<double>(fused[rows]->message.at("x"))) << line;
  }
  EXPECT_EQ(rows, fused.size());

  // `python3 -c`, as docs/lcm.md shows it: the log into lists.
  const odoloc::tb::ChildResult lists =
      finish(spawn(python(),
                   {"-c",
                    "import odoloc_lcmlog as L, sys; o = L.load(sys.argv[1], 'ODOLOC_ODOMETRY'); "
                    "print(len(o), repr(sum(m['ds'] for m in o)))",
                    log().string()},
                   "", {}, *dir_, {"PYTHONPATH=" ODOLOC_LCM_PYTHON_DIR}));
  ASSERT_EQ(lists.code, 0) << lists.err;
  double ds_sum = 0;
  for (const LoggedEvent& e : *events_)
    if (e.channel == channel::kOdometry)
      ds_sum += static_cast<double>(e.message.at("ds"));
  std::ostringstream expected;
  expected.precision(17);
  expected << per_channel().at(channel::kOdometry) << " ";
  EXPECT_EQ(lists.out.substr(0, expected.str().size()), expected.str()) << lists.out;
  EXPECT_NEAR(std::stod(lists.out.substr(expected.str().size())), ds_sum, 1e-9);
}

// A log with garbage between events, a message that does not decode, a
// hostile channel name and a last event cut short: every whole event is
// kept, the rest counted on stderr, and nothing reaches the terminal raw.
TEST(PythonReader, DamagedLogLosesNothingWhole) {
  if (python().empty())
    GTEST_SKIP() << "python3 not on PATH";
  const fs::path dir = odoloc::tb::fresh_dir("odoloc_lcm_users", "damaged");
  const fs::path path = dir / "damaged.lcmlog";
  const std::string hostile = "ODOLOC_POSE_\x1b]0;owned\x07";
  {
    ::lcm::LogFile log(path.string(), "w");
    const auto write = [&](const std::string& name, const std::vector<std::uint8_t>& bytes) {
      ::lcm::LogEvent e{};
      e.timestamp = 1000;
      e.channel = name;
      e.datalen = static_cast<std::int32_t>(bytes.size());
      e.data = const_cast<std::uint8_t*>(bytes.data());  // NOLINT: LCM's API
      ASSERT_EQ(log.writeEvent(&e), 0);
    };
    write(channel::kPoseFused, odoloc::lcm::encode(msg::pose_estimate(0)));
    write(hostile, odoloc::lcm::encode(msg::pose_estimate(1)));
    std::vector<std::uint8_t> truncated = odoloc::lcm::encode(msg::beacon_fix(2));
    truncated.pop_back();
    write(channel::kFix, truncated);
  }
  std::string bytes = odoloc::tb::slurp(path);
  const std::string whole = bytes;
  bytes = whole + "garbage, no sync word" + whole.substr(0, whole.size() - 5);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

  const odoloc::tb::ChildResult r = run_reader({path.string()}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::vector<json> rows;
  for (std::string line; std::getline(lines, line);)
    rows.push_back(json::parse(line));
  // Both poses of each copy; not the fix that does not decode (counted) nor
  // the second copy's cut-off fix (the end, said).
  ASSERT_EQ(rows.size(), 4U) << r.out;
  EXPECT_EQ(rows[1].at("channel"), hostile);
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
  EXPECT_NE(r.err.find(": 1 event did not decode; "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("21 bytes were no event"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the last event is cut short"), std::string::npos) << r.err;

  const odoloc::tb::ChildResult csv =
      run_reader({path.string(), "--channel", "ODOLOC_POSE_.*", "--csv"}, dir);
  ASSERT_EQ(csv.code, 0) << csv.err;
  EXPECT_EQ(csv.out.find('\x1b'), std::string::npos);
  EXPECT_NE(csv.out.find("ODOLOC_POSE_\\x1b]0;owned\\x07"), std::string::npos) << csv.out;

  const odoloc::tb::ChildResult missing = run_reader({(dir / "none.lcmlog").string()}, dir);
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("none.lcmlog: No such file or directory"), std::string::npos)
      << missing.err;
  const odoloc::tb::ChildResult bad_regex = run_reader({path.string(), "--channel", "("}, dir);
  EXPECT_EQ(bad_regex.code, 2);
  EXPECT_NE(bad_regex.err.find("--channel: not a regular expression"), std::string::npos)
      << bad_regex.err;
  fs::remove_all(dir);
}

// ------------------------------------------------------------------ Java

// Xvfb on a display it picks itself (-displayfd), for the test's programs.
class Xvfb {
 public:
  Xvfb() {
    if (program_on_path("Xvfb").empty())
      return;
    out_ = odoloc::tb::fresh_dir("odoloc_lcm_users", "xvfb") / "display";
    child_ = spawn("Xvfb", {"-displayfd", "1", "-nolisten", "tcp", "-screen", "0", "1024x768x24"},
                   "", out_.string());
    for (int i = 0; i < 500 && display_.empty(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds{20});
      const std::string text = odoloc::tb::slurp(out_);
      if (!text.empty() && text.back() == '\n')
        display_ = ":" + text.substr(0, text.size() - 1);
    }
  }
  Xvfb(const Xvfb&) = delete;
  Xvfb& operator=(const Xvfb&) = delete;
  ~Xvfb() {
    if (child_.pid > 0) {
      ::kill(child_.pid, SIGTERM);
      (void)finish(child_);
    }
    fs::remove_all(out_.parent_path());
  }
  [[nodiscard]] const std::string& display() const { return display_; }

 private:
  odoloc::tb::Child child_;
  fs::path out_;
  std::string display_;
};

std::string java_missing() {
  if (program_on_path("java").empty())
    return "java not on PATH";
  for (const char* jar : {"/usr/share/java/lcm.jar", "/usr/share/java/jchart2d.jar",
                          ODOLOC_LCM_TYPES_JAR, ODOLOC_SPY_CHECK_DIR "/SpyCheck.class"})
    if (!fs::exists(jar))
      return std::string(jar) + " is missing (liblcm-java, libjchart2d-java, a JDK)";
  return {};
}

// The spy's own table after it played the whole log: every channel the log
// has, with the C++ decode's count, its type found, nothing undecodable.
TEST_F(MainJobLog, LcmSpyDecodesEveryMessageOfEveryChannel) {
  if (const std::string why = java_missing(); !why.empty())
    GTEST_SKIP() << why;
  const Xvfb x;
  if (x.display().empty())
    GTEST_SKIP() << "no Xvfb";
  const std::string classpath =
      std::string("/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:") + ODOLOC_LCM_TYPES_JAR +
      ":" + ODOLOC_SPY_CHECK_DIR;
  // 105 s of log at 50x; quiet for 1.5 s: played to its end.
  const odoloc::tb::ChildResult r =
      finish(spawn("java",
                   {"-Djava.net.preferIPv4Stack=true", "-cp", classpath, "SpyCheck",
                    "file://" + log().string() + "?speed=50", "1500"},
                   "", {}, *dir_, {"DISPLAY=" + x.display()}),
             std::chrono::minutes{3});
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("Found 10 LCM types\n"), std::string::npos) << r.out;
  std::map<std::string, std::string> type_of;
  msg::for_each_channel([&]<class Message>(const char* name) {
    type_of[name] = "odoloc_lcm." + std::string(Message::getTypeName());
  });
  std::map<std::string, std::size_t> seen;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    std::stringstream cells(line);
    std::string name, type, received, undecodable;
    if (!std::getline(cells, name, '\t') || !std::getline(cells, type, '\t') ||
        !std::getline(cells, received, '\t') || !std::getline(cells, undecodable))
      continue;  // the spy's own messages
    EXPECT_EQ(type, type_of[name]) << name;
    EXPECT_EQ(undecodable, "0") << name;
    seen[name] = std::stoul(received);
  }
  EXPECT_EQ(seen, per_channel());
}

odoloc::tb::Child launch(const std::vector<std::string>& args, const std::string& display,
                         const std::vector<std::string>& environment = {}) {
  std::vector<std::string> env = environment;
  env.push_back("DISPLAY=" + display);
  return spawn(ODOLOC_LCM_SPY, args, "", {}, {}, env);
}

bool alive_after(const odoloc::tb::Child& c, std::chrono::milliseconds wait) {
  std::this_thread::sleep_for(wait);
  return ::waitpid(c.pid, nullptr, WNOHANG) == 0;
}

TEST_F(MainJobLog, LauncherStartsTheSpyAndTheLogPlayerOnOpenJdk17) {
  if (const std::string why = java_missing(); !why.empty())
    GTEST_SKIP() << why;
  const Xvfb x;
  if (x.display().empty())
    GTEST_SKIP() << "no Xvfb";
  {
    const odoloc::tb::Child spy =
        launch({"--lcm-url=file://" + log().string() + "?speed=1"}, x.display());
    ASSERT_TRUE(alive_after(spy, std::chrono::seconds{4}));
    ::kill(spy.pid, SIGTERM);
    const odoloc::tb::ChildResult r = finish(spy);
    EXPECT_EQ(r.code, 128 + SIGTERM) << r.out << r.err;
    EXPECT_NE(r.out.find("Found 10 LCM types\n"), std::string::npos) << r.out << r.err;
    EXPECT_EQ(r.err.find("Unrecognized option"), std::string::npos) << r.err;
  }
  {
    const odoloc::tb::Child player = launch({"--logplayer-gui", log().string()}, x.display());
    ASSERT_TRUE(alive_after(player, std::chrono::seconds{3}));
    ::kill(player.pid, SIGHUP);
    const odoloc::tb::ChildResult r = finish(player);
    EXPECT_EQ(r.code, 128 + SIGHUP) << r.out << r.err;
    EXPECT_EQ(r.err.find("Exception"), std::string::npos) << r.err;
  }
  const odoloc::tb::ChildResult no_jar =
      finish(launch({"--lcm-url=memq://"}, x.display(), {"ODOLOC_LCM_TYPES_JAR=/nonexistent.jar"}));
  EXPECT_EQ(no_jar.code, 2);
  EXPECT_NE(no_jar.err.find("odoloc_lcm_types.jar"), std::string::npos) << no_jar.err;
}

}  // namespace
