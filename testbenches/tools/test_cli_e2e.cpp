// The real `odoloc` binary, run as a child process (posix_spawn) on the
// simulated board: every command, --json parsed back, exit codes, messages.
// Expected values come from the generated register map, never from a run.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "enum_name.hpp"
#include "odoloc/board/sim_target.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "vcd_check.hpp"

extern char** environ;

namespace {

namespace regs = odoloc::regs;
using nlohmann::json;

// A scenario of SimTarget in which the robot drives, so the wheels turn.
constexpr const char* kDrivingScenario = "straight";

struct Result {
  int code = -1;
  std::string out, err;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs the tool with `args`, `input` on its standard input.
Result run(const std::vector<std::string>& args, const std::string& input = {}) {
  static int serial = 0;
  const std::string base =
      fmt::format("{}odoloc_e2e_{}_{}", ::testing::TempDir(), ::getpid(), ++serial);
  const std::string in_path = base + ".in", out_path = base + ".out", err_path = base + ".err";
  std::ofstream(in_path) << input;

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, in_path.c_str(), O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  std::vector<std::string> argv_strings{ODOLOC_CLI};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_strings)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  Result r;
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, ODOLOC_CLI, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    ADD_FAILURE() << "cannot run " << ODOLOC_CLI << ": " << std::strerror(spawned);
    return r;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  for (const std::string& p : {in_path, out_path, err_path})
    std::remove(p.c_str());
  return r;
}

// --json output: one document per line, every line parsed.
std::vector<json> json_lines(const std::string& out) {
  std::vector<json> docs;
  std::istringstream s(out);
  for (std::string line; std::getline(s, line);) {
    EXPECT_NO_THROW(docs.push_back(json::parse(line))) << line;
  }
  return docs;
}

json only_json(const Result& r) {
  const std::vector<json> docs = json_lines(r.out);
  EXPECT_EQ(docs.size(), 1U) << r.out;
  return docs.empty() ? json{} : docs.front();
}

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::ranges::count(text, '\n'));
}

// A usage failure: exit 2, nothing on stdout, one "odoloc: " line on stderr.
void expect_usage_error(const Result& r, const std::string& needle) {
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(r.err.starts_with("odoloc: ")) << r.err;
  EXPECT_EQ(lines(r.err), 1U) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
}

using odoloc::tb::enum_name;

TEST(CliE2e, TheDrivingScenarioExists) {
  const std::vector<std::string> known = odoloc::board::SimTarget::scenarios();
  EXPECT_NE(std::ranges::find(known, kDrivingScenario), known.end());
}

TEST(CliE2e, ListHasEveryRegisterWithItsFields) {
  const Result r = run({"--json", "reg", "list"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json doc = only_json(r);
  const json& list = doc["registers"];
  ASSERT_EQ(list.size(), std::size(regs::kRegisters));
  for (std::size_t i = 0; i < list.size(); ++i) {
    const regs::Register& reg = regs::kRegisters[i];
    EXPECT_EQ(list[i]["path"], std::string{reg.path});
    EXPECT_EQ(list[i]["address"], reg.address);
    EXPECT_EQ(list[i]["reset"], reg.reset);
    ASSERT_EQ(list[i]["fields"].size(), reg.fields.size());
    for (std::size_t f = 0; f < reg.fields.size(); ++f) {
      const json& field = list[i]["fields"][f];
      EXPECT_EQ(field["name"], std::string{reg.fields[f].name});
      EXPECT_EQ(field["signed"], reg.fields[f].is_signed);
      ASSERT_EQ(field["enums"].size(), reg.fields[f].enums.size());
      for (std::size_t e = 0; e < reg.fields[f].enums.size(); ++e)
        EXPECT_EQ(field["enums"][e]["name"], std::string{reg.fields[f].enums[e].name});
    }
  }
  const Result text = run({"reg", "list"});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_EQ(lines(text.out), std::size(regs::kRegisters) + 1);  // a header, then one per register
  for (const regs::Register& reg : regs::kRegisters)
    EXPECT_NE(text.out.find(fmt::format("0x{:03x}", reg.address)), std::string::npos);

  const Result filtered = run({"--json", "reg", "list", "--filter", "eppm.*.count"});
  ASSERT_EQ(filtered.code, 0) << filtered.err;
  EXPECT_EQ(only_json(filtered)["registers"].size(), regs::eppm::kInstances);
}

TEST(CliE2e, ReadTopIdGivesTheMagic) {
  const Result r = run({"--json", "reg", "read", "top.id"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json v = only_json(r)["values"].at(0);
  EXPECT_EQ(v["value"], regs::top::id::kReset);
  EXPECT_EQ(v["fields"]["magic"], regs::top::id::magic.reset);
  EXPECT_EQ(regs::top::id::magic.get(v["value"].get<std::uint32_t>()), 0x0D01U);
  EXPECT_EQ(v["fields"]["version"], regs::top::id::version.reset);

  // By address, in hex and decimal, and the field alone.
  for (const std::string& address :
       {fmt::format("0x{:x}", regs::top::id::kAddress), std::to_string(regs::top::id::kAddress)}) {
    const Result a = run({"--json", "reg", "read", address});
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_EQ(only_json(a)["values"][0]["path"], "top.id");
  }
  const Result field = run({"reg", "read", "top.id.magic"});
  ASSERT_EQ(field.code, 0) << field.err;
  EXPECT_EQ(field.out, fmt::format("top.id.magic = {} (0x{:04x})\n", regs::top::id::magic.reset,
                                   regs::top::id::magic.reset));
  const Result text = run({"reg", "read", "top.id"});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_TRUE(text.out.starts_with(fmt::format("top.id @ 0x{:03x} = 0x{:08x}\n",
                                               regs::top::id::kAddress, regs::top::id::kReset)))
      << text.out;
}

TEST(CliE2e, ScriptKeepsOneChipAcrossCommands) {
  const std::uint32_t value = regs::top::scratch::kReset ^ 0xA5C3'5A3CU;
  const std::string script = fmt::format(
      "# scratch round trip\n"
      "reg write top.scratch=0x{:08x}\n"
      "\n"
      "reg read top.scratch   # read it back\n",
      value);
  const Result r = run({"--json", "script", "-"}, script);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<json> docs = json_lines(r.out);
  ASSERT_EQ(docs.size(), 2U) << r.out;
  EXPECT_EQ(docs[0]["writes"][0]["word"], value);
  EXPECT_EQ(docs[1]["values"][0]["value"], value);

  // From a file, in text.
  const std::string path =
      fmt::format("{}odoloc_e2e_script_{}.txt", ::testing::TempDir(), getpid());
  std::ofstream(path) << script;
  const Result file = run({"script", path});
  std::remove(path.c_str());
  ASSERT_EQ(file.code, 0) << file.err;
  EXPECT_NE(file.out.find(fmt::format("top.scratch @ 0x{:03x} = 0x{:08x}",
                                      regs::top::scratch::kAddress, value)),
            std::string::npos)
      << file.out;

  // Two processes: two fresh chips, the write is gone.
  ASSERT_EQ(run({"reg", "write", fmt::format("top.scratch={}", value)}).code, 0);
  const Result fresh = run({"--json", "reg", "read", "top.scratch"});
  ASSERT_EQ(fresh.code, 0) << fresh.err;
  EXPECT_EQ(only_json(fresh)["values"][0]["value"], regs::top::scratch::kReset);
}

TEST(CliE2e, FieldWriteIsReadModifyWrite) {
  namespace cfg = regs::eppm::cfg;
  const auto x2 = static_cast<std::uint32_t>(cfg::DecodeMode::kX2);
  const std::string x2_name = enum_name(cfg::decode_mode, x2);
  const Result r = run({"--json", "script", "-"},
                       fmt::format("reg write eppm.left_rear.cfg.decode_mode={}\n"
                                   "reg read eppm.left_rear.cfg eppm.left_rear.cfg.decode_mode\n",
                                   x2_name));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<json> docs = json_lines(r.out);
  ASSERT_EQ(docs.size(), 2U) << r.out;
  EXPECT_EQ(docs[0]["writes"][0]["mode"], "read-modify-write");
  EXPECT_EQ(docs[0]["writes"][0]["read"], cfg::kReset);
  const auto word = docs[1]["values"][0]["value"].get<std::uint32_t>();
  EXPECT_EQ(word, cfg::decode_mode.set(cfg::kReset, x2));
  EXPECT_EQ(cfg::decode_mode.get(word), x2);
  EXPECT_EQ(cfg::filter_clocks.get(word), cfg::filter_clocks.reset);  // the other fields kept
  EXPECT_EQ(cfg::speed_mode_select.get(word), cfg::speed_mode_select.reset);
  EXPECT_EQ(docs[1]["values"][0]["fields"]["decode_mode"], x2_name);
  EXPECT_EQ(docs[1]["values"][1]["value"], x2_name);
  EXPECT_EQ(docs[1]["values"][1]["raw"], x2);
  // The other instances are untouched.
  const Result other =
      run({"--json", "script", "-"}, fmt::format("reg write eppm.left_rear.cfg.decode_mode={}\n"
                                                 "reg read eppm.right_rear.cfg\n",
                                                 x2_name));
  ASSERT_EQ(other.code, 0) << other.err;
  EXPECT_EQ(json_lines(other.out).at(1)["values"][0]["value"], cfg::kReset);
}

TEST(CliE2e, WritesToReadOnlyRegistersAreRefused) {
  expect_usage_error(run({"reg", "write", "top.id=0"}), "read-only");
  expect_usage_error(run({"reg", "write", "eppm.left_rear.count.value=1"}), "read-only");
  expect_usage_error(run({"reg", "write", "top.frame_errors=0"}), "rc");
  // In a script the whole script is refused: the scratch write never runs.
  expect_usage_error(run({"script", "-"}, "reg write top.scratch=7\nreg write top.id=1\n"),
                     "<stdin>:2: top.id is read-only");
}

TEST(CliE2e, UnknownNamesSuggestTheClosest) {
  const Result r = run({"reg", "read", "eppm.left_rear.cnt"});
  expect_usage_error(r, "unknown register 'eppm.left_rear.cnt'");
  EXPECT_NE(r.err.find("did you mean eppm.left_rear.count"), std::string::npos) << r.err;
  expect_usage_error(run({"reg", "write", "eppm.left_rear.cfg.decode=x2"}),
                     "eppm.left_rear.cfg.decode_mode");
  expect_usage_error(run({"reg", "watch", "top.scratc", "--count", "1"}), "top.scratch");
}

TEST(CliE2e, BadValuesAddressesAndTargetsAreUsageErrors) {
  const auto& filter = regs::eppm::cfg::filter_clocks;
  const std::uint64_t too_big = std::uint64_t{1} << filter.width;
  expect_usage_error(
      run({"reg", "write", fmt::format("eppm.left_rear.cfg.filter_clocks={}", too_big)}),
      fmt::format("0..{}", too_big - 1));
  expect_usage_error(run({"reg", "write", "top.scratch=0x1_0000_0000"}), "out of range");
  expect_usage_error(run({"reg", "write", "top.scratch=twelve"}), "not a number");
  expect_usage_error(run({"reg", "write", "eppm.left_rear.cfg.decode_mode=x3"}),
                     enum_name(regs::eppm::cfg::decode_mode, 0));
  expect_usage_error(run({"reg", "write", "odometry.cfg.policy=-1"}), "policy");
  expect_usage_error(run({"reg", "write", "top.scratch"}), "NAME=VALUE");
  const auto space = std::uint32_t{1} << regs::kAddressBits;
  expect_usage_error(run({"reg", "read", fmt::format("0x{:x}", space)}), "out of range");
  std::uint16_t hole = 0;
  while (regs::find(std::uint32_t{hole}) != nullptr)
    ++hole;
  expect_usage_error(run({"reg", "read", std::to_string(hole)}), "unmapped");
  expect_usage_error(run({"--target", "nowhere", "reg", "read", "top.id"}), "unknown target");
  expect_usage_error(run({"--target", "sim:no_such_scenario", "reg", "read", "top.id"}),
                     kDrivingScenario);
  expect_usage_error(run({"--target", "lcm", "reg", "read", "top.id"}),
                     "target lcm is not available yet");
  expect_usage_error(run({"reg", "watch", "top.id", "--interval", "100", "--count", "2"}),
                     "interval");
  expect_usage_error(run({"reg", "frobnicate"}), "frobnicate");
}

TEST(CliE2e, MissingSpidevDeviceIsAClearError) {
  const std::string device = "/nonexistent-odoloc/spidev0.0";
  const Result r = run({"--target", "spidev:" + device, "reg", "read", "top.id"});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, fmt::format("odoloc: cannot open {}: {}\n", device, std::strerror(ENOENT)));
  if (::access("/dev/spidev0.0", F_OK) != 0) {
    const Result dev = run({"--target", "spidev:/dev/spidev0.0@500k", "reg", "dump"});
    EXPECT_EQ(dev.code, 2);
    EXPECT_EQ(dev.err, "odoloc: cannot open /dev/spidev0.0: No such file or directory\n");
  }
  expect_usage_error(run({"--target", "spidev:/dev/spidev0.0@50M", "reg", "read", "top.id"}),
                     "limit");
}

TEST(CliE2e, CrcFramesWork) {
  const Result ctrl = run({"--crc", "--json", "reg", "read", "top.ctrl", "top.spi_status"});
  ASSERT_EQ(ctrl.code, 0) << ctrl.err;
  const json values = only_json(ctrl)["values"];
  const auto ctrl_word = values[0]["value"].get<std::uint32_t>();
  EXPECT_EQ(regs::top::ctrl::crc_enable.get(ctrl_word), 1U);
  EXPECT_EQ(values[1]["value"], regs::top::spi_status::kReset);  // no crc_error, no bad frame

  const Result plain = run({"--json", "reg", "read", "top.ctrl"});
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(
      regs::top::ctrl::crc_enable.get(only_json(plain)["values"][0]["value"].get<std::uint32_t>()),
      regs::top::ctrl::crc_enable.reset);

  const std::uint32_t value = ~regs::top::scratch::kReset;
  const Result script =
      run({"--crc", "--json", "script", "-"},
          fmt::format("reg write top.scratch={}\nreg read top.scratch top.spi_status\n", value));
  ASSERT_EQ(script.code, 0) << script.err;
  const std::vector<json> docs = json_lines(script.out);
  ASSERT_EQ(docs.size(), 2U);
  EXPECT_EQ(docs[1]["values"][0]["value"], value);
  EXPECT_EQ(docs[1]["values"][1]["value"], regs::top::spi_status::kReset);
}

TEST(CliE2e, WatchOnADrivingScenarioSeesTheWheelTurn) {
  using std::chrono::nanoseconds;
  const nanoseconds interval = std::chrono::milliseconds{100};
  const std::string target = fmt::format("sim:{}", kDrivingScenario);
  // Stop the odometry updates, which latch-and-clear the counts, so the left
  // rear count accumulates the wheel's edges.
  const Result r = run({"--target", target, "--json", "script", "-"},
                       "reg write odometry.cfg.update_clocks=0\n"
                       "reg watch eppm.left_rear.count --count 3 --interval 100ms\n");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<json> docs = json_lines(r.out);
  ASSERT_EQ(docs.size(), 4U) << r.out;
  std::vector<std::int64_t> counts;
  for (std::size_t i = 0; i < 3; ++i) {
    const json& sample = docs[i + 1];
    EXPECT_EQ(sample["sample"], i);
    EXPECT_EQ(sample["values"][0]["path"], "eppm.left_rear.count");
    counts.push_back(sample["values"][0]["fields"]["value"].get<std::int64_t>());
    if (i > 0) {
      // Simulated time: the interval plus the read frame's few microseconds.
      const nanoseconds dt{sample["time_ns"].get<std::int64_t>() -
                           docs[i]["time_ns"].get<std::int64_t>()};
      EXPECT_GE(dt, interval);
      EXPECT_LT(dt, interval + std::chrono::milliseconds{1});
    }
  }
  EXPECT_NE(counts[0], counts[1]);
  EXPECT_NE(counts[1], counts[2]);
  EXPECT_EQ(counts[1] > counts[0], counts[2] > counts[1]) << "the robot drives one way";

  // Without the script, in text: one line per sample; the pose updates
  // advance by one per update period (odometry.cfg.update_clocks at reset).
  const nanoseconds period{static_cast<std::int64_t>(regs::odometry::cfg::update_clocks.reset) *
                           odoloc::rtl::kFabricClockPeriodNs};
  const Result direct = run({"--target", target, "--json", "reg", "watch", "odometry.updates",
                             "eppm.left_rear.latched", "--count", "3", "--interval", "10ms"});
  ASSERT_EQ(direct.code, 0) << direct.err;
  const std::vector<json> samples = json_lines(direct.out);
  ASSERT_EQ(samples.size(), 3U);
  const std::int64_t expected = std::chrono::milliseconds{10} / period;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const std::int64_t diff = samples[i]["values"][0]["value"].get<std::int64_t>() -
                              samples[i - 1]["values"][0]["value"].get<std::int64_t>();
    EXPECT_NEAR(static_cast<double>(diff), static_cast<double>(expected), 1.0);
  }
  const Result text =
      run({"--target", target, "reg", "watch", "eppm.left_rear.count", "--count", "3"});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_EQ(lines(text.out), 3U);
}

TEST(CliE2e, DumpReadsEveryRegister) {
  const Result r = run({"--json", "reg", "dump"});
  ASSERT_EQ(r.code, 0) << r.err;
  const json values = only_json(r)["values"];
  ASSERT_EQ(values.size(), std::size(regs::kRegisters));
  for (const json& v : values) {
    const regs::Register* reg = regs::find(v["path"].get<std::string>());
    ASSERT_NE(reg, nullptr);
    EXPECT_EQ(v["address"], reg->address);
    if (reg->access == regs::Access::kRw || reg->path == "top.id") {
      EXPECT_EQ(v["value"], reg->reset) << reg->path;  // a fresh chip
    }
  }
  const Result text = run({"reg", "dump"});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_EQ(lines(text.out), std::size(regs::kRegisters));
}

TEST(CliE2e, WaitAndHelp) {
  const Result wait = run({"--json", "wait", "2ms"});
  ASSERT_EQ(wait.code, 0) << wait.err;
  EXPECT_EQ(only_json(wait)["waited_ns"], 2'000'000);
  const Result help = run({"--help"});
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("reg"), std::string::npos);
  EXPECT_NE(help.out.find("script"), std::string::npos);
}

// --vcd: the waveform's SPI pins carry the frames the tool sent, decoded
// here bit by bit as a logic analyser would.
TEST(CliE2e, VcdWaveformCarriesTheFrames) {
  const std::string path = ::testing::TempDir() + fmt::format("odoloc_e2e_{}.vcd", ::getpid());
  const std::uint32_t value = 0xA5A5F00DU;
  const Result r = run({"--vcd", path, "script", "-"},
                       fmt::format("reg write top.scratch={:#x}\nreg read top.scratch\n", value));
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream file(path);
  const auto vcd = odoloc::tb::check_vcd(file);
  ASSERT_TRUE(vcd.ok()) << vcd.error_text();
  std::remove(path.c_str());

  struct Frame {
    std::vector<std::uint8_t> mosi, miso;
  };
  std::vector<Frame> frames;
  std::size_t bit = 0;
  std::uint64_t last = 0;
  for (const auto& changes : vcd.history)
    if (!changes.empty())
      last = std::max(last, changes.back().time);
  const auto at = [&](const char* pin, std::uint64_t t) {
    const auto v = vcd.value_at(std::string{"odoloc."} + pin, t);
    EXPECT_TRUE(v.has_value()) << pin << " at " << t;
    return v.value_or(0);
  };
  constexpr std::uint64_t kClockNs = 20;
  for (std::uint64_t t = kClockNs; t <= last; t += kClockNs) {
    if (at("cs_n", t - kClockNs) == 1 && at("cs_n", t) == 0) {
      frames.emplace_back();
      bit = 0;
    }
    if (at("cs_n", t) == 0 && at("sclk", t - kClockNs) == 0 && at("sclk", t) == 1) {
      Frame& f = frames.back();
      if (bit % 8 == 0) {
        f.mosi.push_back(0);
        f.miso.push_back(0);
      }
      const auto shift = 7U - static_cast<unsigned>(bit % 8);
      f.mosi.back() = static_cast<std::uint8_t>(f.mosi.back() | at("mosi", t) << shift);
      f.miso.back() = static_cast<std::uint8_t>(f.miso.back() | at("miso", t - kClockNs) << shift);
      ++bit;
    }
  }
  const auto bytes = [](std::uint32_t w) {
    return std::vector<std::uint8_t>{
        static_cast<std::uint8_t>(w >> 24U), static_cast<std::uint8_t>(w >> 16U),
        static_cast<std::uint8_t>(w >> 8U), static_cast<std::uint8_t>(w)};
  };
  const auto address = regs::top::scratch::kAddress;
  std::vector<std::uint8_t> write{0x00, static_cast<std::uint8_t>(address)};
  std::vector<std::uint8_t> read{0x80, static_cast<std::uint8_t>(address)};
  const std::vector<std::uint8_t> data = bytes(value);
  write.insert(write.end(), data.begin(), data.end());
  bool wrote = false, read_back = false;
  for (const Frame& f : frames) {
    wrote |= f.mosi == write;
    if (f.mosi.size() == 6 && f.mosi[0] == read[0] && f.mosi[1] == read[1]) {
      EXPECT_EQ(std::vector<std::uint8_t>(f.miso.begin() + 2, f.miso.end()), data);
      read_back = true;
    }
  }
  EXPECT_TRUE(wrote) << frames.size() << " frames";
  EXPECT_TRUE(read_back);
}

TEST(CliE2e, VcdNeedsTheSimTarget) {
  expect_usage_error(
      run({"--vcd", "x.vcd", "-t", "spidev:/dev/spidev9.9", "reg", "read", "top.id"}), "--vcd");
}

}  // namespace
