// Every `odoloc` command that writes a file, run as users run it (the real
// binary, docs/host-tool.md#files-devices-links-and-signals): a symbolic
// link, a FIFO and a private device node as outputs (followed, streamed,
// never replaced), file names that gnuplot would run as commands if it took
// them as code, and SIGINT, SIGTERM and SIGHUP in the middle of a run (the
// documented status, nothing left behind).
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "png_size.hpp"
#include "scratch_files.hpp"

namespace {

namespace fs = std::filesystem;
using odoloc::tb::ChildResult;
using odoloc::tb::fresh_dir;
using odoloc::tb::slurp;

const fs::path kExamples = fs::path{ODOLOC_SOURCE_DIR} / "examples";

ChildResult run_in(const fs::path& dir, const std::vector<std::string>& args,
                   const std::vector<std::string>& environment = {}) {
  return odoloc::tb::finish(odoloc::tb::spawn(ODOLOC_CLI, args, "", {}, dir, environment));
}

using odoloc::tb::entries;
using odoloc::tb::is_kind;

// A private null device (1,3) named `name` in `dir`, or an empty path
// without CAP_MKNOD.
fs::path null_device(const fs::path& dir, const std::string& name) {
  const fs::path node = dir / name;
  return ::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0 ? node : fs::path{};
}

// Reads a FIFO to its end on a thread of its own, as a consumer would. The
// read end is open before the command starts (so the command's open does
// not wait), non-blocking, and polled: when the command has ended without
// ever writing to it (it replaced the FIFO instead), received() gives ""
// and the test fails instead of hanging.
class FifoReader {
 public:
  explicit FifoReader(const fs::path& fifo)
      : fd_(::open(fifo.c_str(), O_RDONLY | O_NONBLOCK)), reader_([this] { read_all(); }) {
    EXPECT_GE(fd_, 0) << fifo;
  }
  FifoReader(const FifoReader&) = delete;
  FifoReader& operator=(const FifoReader&) = delete;
  ~FifoReader() {
    if (reader_.joinable())
      (void)received();
  }
  std::string received() {
    ended_.store(true);
    reader_.join();
    ::close(fd_);
    return received_;
  }

 private:
  void read_all() {
    bool written = false;
    std::array<char, 4096> chunk{};
    for (;;) {
      pollfd p{.fd = fd_, .events = POLLIN, .revents = 0};
      if (::poll(&p, 1, 20) > 0) {
        if ((p.revents & POLLIN) != 0) {
          const ssize_t n = ::read(fd_, chunk.data(), chunk.size());
          if (n == 0)
            return;  // the writer closed
          if (n > 0) {
            received_.append(chunk.data(), static_cast<std::size_t>(n));
            written = true;
          }
          continue;
        }
        if ((p.revents & POLLHUP) != 0)
          return;  // the writer closed (Linux: only once one had opened it)
      }
      if (!written && ended_.load())
        return;  // the command ended without ever writing here
    }
  }

  int fd_;
  std::atomic<bool> ended_{false};
  std::string received_;
  std::thread reader_;
};

fs::path make_fifo(const fs::path& path) {
  EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0) << path;
  return path;
}

// A sweep of 8 beacon-fix jobs (a fraction of a second).
void write_small_spec(const fs::path& file, const std::string& name = "small") {
  std::ofstream(file) << "name: " << name
                      << "\nexperiment: beacons\nseed: 3\ntrials: 4\n"
                         "grid:\n  echo_probability: [0, 0.2]\n";
}

// ------------------------------------------------------------ outputs

TEST(CommandOutputs, SweepRunFollowsALinkAndStreamsToAFifoAndADevice) {
  const fs::path dir = fresh_dir("outputs", "sweep_run");
  write_small_spec(dir / "spec.yaml");
  const ChildResult plain = run_in(dir, {"sweep", "run", "spec.yaml", "--out", "plain.jsonl"});
  ASSERT_EQ(plain.code, 0) << plain.err;
  const std::string expected = slurp(dir / "plain.jsonl");
  ASSERT_FALSE(expected.empty());

  fs::create_directory(dir / "results");
  std::ofstream(dir / "results" / "r.jsonl") << "old";
  fs::create_symlink("results/r.jsonl", dir / "link.jsonl");
  EXPECT_EQ(run_in(dir, {"sweep", "run", "spec.yaml", "--out", "link.jsonl"}).code, 0);
  EXPECT_TRUE(is_kind(dir / "link.jsonl", S_IFLNK));
  EXPECT_EQ(slurp(dir / "results" / "r.jsonl"), expected);

  FifoReader reader(make_fifo(dir / "r.fifo"));
  EXPECT_EQ(run_in(dir, {"sweep", "run", "spec.yaml", "--out", "r.fifo"}).code, 0);
  EXPECT_EQ(reader.received(), expected);
  EXPECT_TRUE(is_kind(dir / "r.fifo", S_IFIFO));

  fs::create_symlink("nowhere/r.jsonl", dir / "dangling.jsonl");
  const ChildResult dangling =
      run_in(dir, {"sweep", "run", "spec.yaml", "--out", "dangling.jsonl"});
  EXPECT_EQ(dangling.code, 2);
  EXPECT_NE(dangling.err.find("symbolic link to nowhere/r.jsonl"), std::string::npos)
      << dangling.err;
  EXPECT_TRUE(is_kind(dir / "dangling.jsonl", S_IFLNK));

  const fs::path null = null_device(dir, "null");
  if (null.empty())
    GTEST_SKIP() << "mknod needs CAP_MKNOD";
  EXPECT_EQ(run_in(dir, {"sweep", "run", "spec.yaml", "--out", "null"}).code, 0);
  EXPECT_TRUE(is_kind(null, S_IFCHR));
}

// One simulated run, the log the picture tests plot: --duration 2, so the
// return-to-start column has no values (the robot is not back).
class SimulatedRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fresh_dir("outputs", "sim"));
    // A folder whose files are a link (to a file elsewhere) and a FIFO.
    fs::create_directory(*dir_ / "run");
    std::ofstream(*dir_ / "elsewhere.csv") << "old";
    fs::create_symlink("../elsewhere.csv", *dir_ / "run" / "trajectories.csv");
    // The picture to a private null device, where there is CAP_MKNOD.
    device_ = new bool(!null_device(*dir_ / "run", "localisation.png").empty());
    FifoReader fixes(make_fifo(*dir_ / "run" / "fixes.csv"));
    const ChildResult r = run_in(*dir_, {"sim", "--duration", "2", "--out", "run"});
    fixes_ = new std::string(fixes.received());
    result_ = new ChildResult(r);
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete fixes_;
    delete result_;
    delete device_;
  }
  static fs::path* dir_;
  static std::string* fixes_;
  static ChildResult* result_;
  static bool* device_;
};
bool* SimulatedRun::device_ = nullptr;
fs::path* SimulatedRun::dir_ = nullptr;
std::string* SimulatedRun::fixes_ = nullptr;
ChildResult* SimulatedRun::result_ = nullptr;

TEST_F(SimulatedRun, SimWritesThroughTheLinkAndTheFifoInItsFolder) {
  ASSERT_EQ(result_->code, 0) << result_->err;
  const fs::path run = *dir_ / "run";
  EXPECT_TRUE(is_kind(run / "trajectories.csv", S_IFLNK));
  EXPECT_TRUE(slurp(*dir_ / "elsewhere.csv").starts_with("time_s,")) << "the link's file";
  EXPECT_TRUE(is_kind(run / "fixes.csv", S_IFIFO));
  EXPECT_TRUE(fixes_->starts_with("time_s,")) << *fixes_;
  if (*device_) {
    EXPECT_TRUE(is_kind(run / "localisation.png", S_IFCHR));
  }
  EXPECT_EQ(entries(run), (std::vector<std::string>{"fixes.csv", "localisation.png",
                                                    "odoloc.lcmlog", "trajectories.csv"}));
}

TEST_F(SimulatedRun, ARunCutShortHasNoReturnToStart) {
  ASSERT_EQ(result_->code, 0) << result_->err;
  EXPECT_NE(result_->out.find("return to start: none"), std::string::npos) << result_->out;
  // Every row's last column (return, mm) is "-".
  std::istringstream table(result_->out);
  int rows = 0;
  for (std::string line; std::getline(table, line);) {
    if (line.find("odometry") == 0 || line.starts_with("rear-only") ||
        line.starts_with("front-only") || line.starts_with("min-select") ||
        line.starts_with("fused (EKF)") || line.starts_with("ultrasonic fixes")) {
      ++rows;
      EXPECT_TRUE(line.ends_with(" -")) << line;
    }
  }
  EXPECT_GE(rows, 4);
}

TEST_F(SimulatedRun, PlotAndLocatePicturesFollowLinksAndStreamToFifosAndDevices) {
  ASSERT_EQ(result_->code, 0) << result_->err;
  const fs::path dir = fresh_dir("outputs", "pictures");
  fs::copy_file(*dir_ / "run" / "odoloc.lcmlog", dir / "run.lcmlog");
  const std::vector<std::string> layout = {"locate",
                                           "--layout",
                                           (kExamples / "locate" / "layout.yaml").string(),
                                           "--arrivals",
                                           (kExamples / "locate" / "arrivals.csv").string(),
                                           "--plot"};
  const auto command = [&](bool plot, const std::string& out) {
    std::vector<std::string> args =
        plot ? std::vector<std::string>{"plot", "run.lcmlog", "--out"} : layout;
    args.push_back(out);
    return args;
  };
  for (const bool plot : {true, false}) {
    const std::string tag = plot ? "plot" : "locate";
    fs::create_directory(dir / tag);
    std::ofstream(dir / tag / "old.png") << "old";
    fs::create_symlink(tag + "/old.png", dir / (tag + "-link.png"));
    const ChildResult linked = run_in(dir, command(plot, tag + "-link.png"));
    EXPECT_EQ(linked.code, 0) << linked.err;
    EXPECT_TRUE(is_kind(dir / (tag + "-link.png"), S_IFLNK));
    EXPECT_GT(odoloc::tb::png_size(dir / tag / "old.png").width, 0U) << tag;

    FifoReader reader(make_fifo(dir / (tag + ".png")));
    const ChildResult streamed = run_in(dir, command(plot, tag + ".png"));
    EXPECT_EQ(streamed.code, 0) << streamed.err;
    EXPECT_TRUE(reader.received().starts_with("\x89PNG")) << tag;
    EXPECT_TRUE(is_kind(dir / (tag + ".png"), S_IFIFO));

    const fs::path null = null_device(dir, tag + "-null.png");
    if (null.empty())
      continue;
    EXPECT_EQ(run_in(dir, command(plot, null.filename().string())).code, 0) << tag;
    EXPECT_TRUE(is_kind(null, S_IFCHR)) << tag;
  }
}

// The command in the names creates X in $HOME, set to the test's folder:
// gnuplot runs in a staging folder, and a file name holds no '/'.
TEST_F(SimulatedRun, HostileFileNamesAreData) {
  ASSERT_EQ(result_->code, 0) << result_->err;
  const fs::path dir = fresh_dir("outputs", "hostile");
  const std::vector<std::string> home = {"HOME=" + dir.string()};
  const std::string touch = "`cd;touch X`";
  fs::create_directory(dir / "w");
  // The report's name, then one with quotes, `$`, `;`, a line break and a
  // byte that is not UTF-8.
  for (const std::string& log :
       {"w/a" + touch + ".lcmlog", "w/b" + touch + "'\"$x;\n\xff.lcmlog"}) {
    fs::copy_file(*dir_ / "run" / "odoloc.lcmlog", dir / log);
    const ChildResult plotted = run_in(dir, {"plot", log, "--keep-script"}, home);
    EXPECT_EQ(plotted.code, 0) << plotted.err;
    EXPECT_GT(odoloc::tb::png_size(dir / fs::path(log).replace_extension(".png")).width, 0U);
    EXPECT_FALSE(fs::exists(dir / "X")) << log << " ran as a command";
  }
  // The name on the terminal: one line, its line break and its byte escaped.
  const ChildResult summary =
      run_in(dir, {"plot", "w/b" + touch + "'\"$x;\n\xff.lcmlog", "--out", "s.png"}, home);
  EXPECT_NE(summary.out.find("$x;\\x0a\\xff.lcmlog: "), std::string::npos) << summary.out;
  EXPECT_EQ(summary.out.find("\n\xff"), std::string::npos);
  const ChildResult located =
      run_in(dir,
             {"locate", "--layout", (kExamples / "locate" / "layout.yaml").string(), "--arrivals",
              (kExamples / "locate" / "arrivals.csv").string(), "--plot", "p" + touch + "'.png"},
             home);
  EXPECT_EQ(located.code, 0) << located.err;
  EXPECT_GT(odoloc::tb::png_size(dir / ("p" + touch + "'.png")).width, 0U);
  write_small_spec(dir / "spec.yaml");
  EXPECT_EQ(run_in(dir, {"sweep", "run", "spec.yaml", "--out", "r" + touch + ".jsonl"}, home).code,
            0);
  EXPECT_EQ(
      run_in(dir, {"sweep", "merge", "r" + touch + ".jsonl", "--out", "m" + touch}, home).code, 0);
  EXPECT_GT(odoloc::tb::png_size(dir / ("m" + touch) / "echo_probability.png").width, 0U);
  const ChildResult simulated = run_in(dir, {"sim", "--duration", "1", "--out", "o" + touch}, home);
  EXPECT_EQ(simulated.code, 0) << simulated.err;
  EXPECT_GT(odoloc::tb::png_size(dir / ("o" + touch) / "localisation.png").width, 0U);
  EXPECT_FALSE(fs::exists(dir / "X")) << "a name ran as a command";
}

TEST(CommandOutputs, MergeAndExportFollowLinksAndNeverReplaceThem) {
  const fs::path dir = fresh_dir("outputs", "folders");
  write_small_spec(dir / "spec.yaml");
  ASSERT_EQ(run_in(dir, {"sweep", "run", "spec.yaml", "--out", "r.jsonl"}).code, 0);
  fs::create_directory(dir / "merged");
  std::ofstream(dir / "summary.md") << "old";
  fs::create_symlink("../summary.md", dir / "merged" / "summary.md");
  FifoReader jobs(make_fifo(dir / "merged" / "jobs.csv"));
  const fs::path points = null_device(dir / "merged", "points.csv");
  const ChildResult merged = run_in(dir, {"sweep", "merge", "r.jsonl", "--out", "merged"});
  EXPECT_EQ(merged.code, 0) << merged.err;
  EXPECT_TRUE(jobs.received().starts_with("job,")) << "the FIFO's content";
  EXPECT_TRUE(is_kind(dir / "merged" / "summary.md", S_IFLNK));
  EXPECT_TRUE(slurp(dir / "summary.md").starts_with("# Sweep small"));
  EXPECT_TRUE(is_kind(dir / "merged" / "jobs.csv", S_IFIFO));
  if (!points.empty()) {
    EXPECT_TRUE(is_kind(points, S_IFCHR));
  }

  // export-hls: OUT a link to a folder is followed; a link to nothing, or a
  // kernel's folder that is a link, is refused.
  fs::create_directory(dir / "trees");
  fs::create_symlink("trees", dir / "to-trees");
  const ChildResult exported =
      run_in(dir, {"export-hls", "--out", "to-trees", "--kernel", "cordic"});
  EXPECT_EQ(exported.code, 0) << exported.err;
  EXPECT_TRUE(is_kind(dir / "to-trees", S_IFLNK));
  EXPECT_TRUE(fs::is_regular_file(dir / "trees" / "cordic" / "kernel.cpp"));
  fs::create_symlink("missing", dir / "dangling");
  const ChildResult dangling =
      run_in(dir, {"export-hls", "--out", "dangling", "--kernel", "cordic"});
  EXPECT_EQ(dangling.code, 2) << dangling.err;
  EXPECT_TRUE(is_kind(dir / "dangling", S_IFLNK));
  fs::rename(dir / "trees" / "cordic", dir / "cordic-real");
  fs::create_symlink("../cordic-real", dir / "trees" / "cordic");
  const ChildResult forced =
      run_in(dir, {"export-hls", "--out", "trees", "--kernel", "cordic", "--force"});
  EXPECT_EQ(forced.code, 2) << forced.err;
  EXPECT_TRUE(is_kind(dir / "trees" / "cordic", S_IFLNK));
}

// The picture `sim --out DIR` delivers is the one `odoloc plot` draws of the
// log it delivers: its title names DIR/odoloc.lcmlog, not the staging
// folder the run was written in (a name that no longer exists, and another
// on every run).
TEST(CommandOutputs, SimPictureIsThePlotOfItsDeliveredLog) {
  const fs::path dir = fresh_dir("outputs", "sim_picture");
  const ChildResult simulated = run_in(dir, {"sim", "--duration", "1", "--out", "run"});
  ASSERT_EQ(simulated.code, 0) << simulated.err;
  const ChildResult plotted =
      run_in(dir, {"plot", (fs::path("run") / "odoloc.lcmlog").string(), "--out", "replot.png"});
  ASSERT_EQ(plotted.code, 0) << plotted.err;
  EXPECT_TRUE(slurp(dir / "run" / "localisation.png") == slurp(dir / "replot.png"));
}

// A scenario's name is data: on the terminal its control bytes are
// escaped, as a file name's are.
TEST(CommandOutputs, AScenarioNameReachesTheTerminalEscaped) {
  const fs::path dir = fresh_dir("outputs", "scenario_name");
  std::string text = slurp(kExamples / "scenarios" / "room-tour.yaml");
  const std::string name = "name: the 6 m square in Kleeman's room";
  ASSERT_NE(text.find(name), std::string::npos);
  text.replace(text.find(name), name.size(), "name: \"\\e]0;owned\\a room\"");
  std::ofstream(dir / "hostile.yaml") << text;
  const ChildResult r = run_in(
      dir, {"sim", "--scenario", "hostile.yaml", "--duration", "0.5", "--out", "o", "--no-plot"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 laps of \\x1b]0;owned\\x07 room"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
}

// A stationary scenario prints its table: each point's fixes beside the
// paper's spread (here 3 fixes a point, not the paper's hundreds), and
// writes nothing.
TEST(CommandOutputs, AStationaryScenarioPrintsThePapersSpreadBesideItsOwn) {
  const fs::path dir = fresh_dir("outputs", "stationary");
  std::string text = slurp(kExamples / "scenarios" / "kleeman-stationary.yaml");
  for (const char* n : {"fixes: 532", "fixes: 1684", "fixes: 639"})
    text.replace(text.find(n), std::string(n).size(), "fixes: 3");
  text.erase(text.find("  grid: {"),
             text.find('\n', text.find("  grid: {")) + 1 - text.find("  grid: {"));
  std::ofstream(dir / "three.yaml") << text;
  const ChildResult r = run_in(dir, {"sim", "--scenario", "three.yaml"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("the robot standing, the ultrasonic fixes alone"), std::string::npos)
      << r.out;
  for (const char* row :
       {"(4.223, 7.902)        3", "(4.003, 4.892)        3", "(7.339, 5.885)        3"})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
  EXPECT_NE(r.out.find("8.0 / 11.0"), std::string::npos) << r.out;
  const ChildResult refused = run_in(dir, {"sim", "--scenario", "three.yaml", "--out", "o"});
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("a stationary scenario prints its table only"), std::string::npos)
      << refused.err;
  EXPECT_FALSE(fs::exists(dir / "o"));
}

TEST(CommandOutputs, SimDurationZeroIsRefused) {
  const fs::path dir = fresh_dir("outputs", "duration");
  const ChildResult zero = run_in(dir, {"sim", "--duration", "0", "--out", "d"});
  EXPECT_EQ(zero.code, 2);
  EXPECT_NE(zero.err.find("--duration must be more than 0"), std::string::npos) << zero.err;
  EXPECT_FALSE(fs::exists(dir / "d"));
}

// ------------------------------------------------------------ signals

// Runs `args` in `dir`, waits until `started(dir)` (what the command makes
// first: its temporary, its staging folder) or `settle`, sends `signal`, and
// expects the exit status 128 + signal within 2 s.
ChildResult interrupted(const fs::path& dir, const std::vector<std::string>& args, int signal,
                        const std::function<bool()>& started,
                        std::chrono::milliseconds settle = std::chrono::seconds{20}) {
  const odoloc::tb::Child child = odoloc::tb::spawn(ODOLOC_CLI, args, "", {}, dir);
  const auto begun = std::chrono::steady_clock::now();
  while (!started() && std::chrono::steady_clock::now() - begun < settle)
    std::this_thread::sleep_for(std::chrono::milliseconds{5});
  const auto sent = std::chrono::steady_clock::now();
  ::kill(child.pid, signal);
  const ChildResult r = odoloc::tb::finish(child, std::chrono::seconds{10});
  EXPECT_LT(std::chrono::steady_clock::now() - sent, std::chrono::seconds{2})
      << fmt::format("{} was not prompt", args.front());
  EXPECT_EQ(r.code, 128 + signal) << args.front() << ' ' << signal << ": " << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  return r;
}

bool has_entry_starting(const fs::path& dir, std::string_view prefix) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.path().filename().string().starts_with(prefix))
      return true;
  return false;
}

TEST(CommandSignals, SweepRunEndsOnEachSignalWithoutItsTemporary) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    const fs::path dir = fresh_dir("signals", fmt::format("sweep_run_{}", signal));
    std::ofstream(dir / "spec.yaml") << "name: long\nexperiment: beacons\nseed: 1\n"
                                        "trials: 1000000\ngrid:\n  echo_probability: [0.2]\n";
    interrupted(dir, {"sweep", "run", "spec.yaml", "--out", "r.jsonl"}, signal,
                [&] { return has_entry_starting(dir, ".r.jsonl."); });
    EXPECT_EQ(entries(dir), std::vector<std::string>{"spec.yaml"});
  }
}

TEST(CommandSignals, ExportSimAndLocateEndWithoutTheirFiles) {
  const fs::path dir = fresh_dir("signals", "export");
  interrupted(dir, {"export-hls", "--out", "trees"}, SIGTERM,
              [&] { return has_entry_starting(dir, ".odoloc-export-"); });
  EXPECT_TRUE(entries(dir).empty());

  const fs::path sim = fresh_dir("signals", "sim");
  interrupted(sim, {"sim", "--out", "run"}, SIGHUP, [&] {
    return fs::exists(sim / "run") && has_entry_starting(sim / "run", ".odoloc-sim-");
  });
  EXPECT_TRUE(entries(sim).empty());

  // 60 000 cycles of six beacons: seconds of solving.
  const fs::path locate = fresh_dir("signals", "locate");
  {
    std::ofstream arrivals(locate / "arrivals.csv");
    arrivals << "cycle,beacon,distance_m,sd_m\n";
    for (int c = 0; c < 60000; ++c)
      arrivals << fmt::format(
          "{0},B0,2.0511,0.001\n{0},B1,2.3935,0.001\n{0},B2,4.4859,0.001\n"
          "{0},B3,5.3236,0.001\n{0},B4,3.7694,0.001\n{0},B5,3.5732,0.001\n",
          c);
  }
  interrupted(
      locate,
      {"locate", "--layout", (kExamples / "locate" / "layout.yaml").string(), "--arrivals",
       "arrivals.csv", "--plot", "fixes.png"},
      SIGTERM, [] { return false; }, std::chrono::milliseconds{700});
  EXPECT_EQ(entries(locate), std::vector<std::string>{"arrivals.csv"});
}

TEST(CommandSignals, WaitWatchAndWatchPoseEndWithTheSignalsStatus) {
  const fs::path dir = fresh_dir("signals", "watch");
  const auto after = [](int ms) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds{ms};
    return [until] { return std::chrono::steady_clock::now() > until; };
  };
  interrupted(dir, {"-t", "sim:straight", "--cycle-step", "wait", "9s"}, SIGTERM, after(300));
  interrupted(dir,
              {"-t", "sim:straight", "--cycle-step", "reg", "watch", "top.id", "--interval", "9s"},
              SIGHUP, after(300));
  // memq:// in another process hears nothing: it waits until the signal.
  interrupted(dir, {"watch", "pose", "--lcm-url", "memq://"}, SIGTERM, after(300));
  EXPECT_TRUE(entries(dir).empty());
}

// A FIFO nobody reads: the command waits in its open at the very end, with
// everything else made; the signal must end the wait and deliver nothing.
TEST(CommandSignals, MergeAndPlotWaitingOnAnOutputEndWithNothingDelivered) {
  const fs::path dir = fresh_dir("signals", "merge");
  write_small_spec(dir / "spec.yaml");
  ASSERT_EQ(run_in(dir, {"sweep", "run", "spec.yaml", "--out", "r.jsonl"}).code, 0);
  fs::create_directory(dir / "merged");
  make_fifo(dir / "merged" / "jobs.csv");
  interrupted(
      dir, {"sweep", "merge", "r.jsonl", "--out", "merged"}, SIGHUP, [] { return false; },
      std::chrono::milliseconds{1500});
  EXPECT_EQ(entries(dir / "merged"), std::vector<std::string>{"jobs.csv"});

  const fs::path plot = fresh_dir("signals", "plot");
  ASSERT_EQ(run_in(plot, {"sim", "--duration", "1", "--out", "run", "--no-plot"}).code, 0);
  make_fifo(plot / "p.png");
  interrupted(
      plot, {"plot", "run/odoloc.lcmlog", "--out", "p.png"}, SIGINT, [] { return false; },
      std::chrono::milliseconds{1500});
  EXPECT_EQ(entries(plot), (std::vector<std::string>{"p.png", "run"}));
}

}  // namespace
