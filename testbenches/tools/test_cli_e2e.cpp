// The real `odoloc` binary, run as a child process (posix_spawn) on the
// simulated board: every command, --json parsed back, exit codes, messages.
// Expected values come from the generated register map, never from a run;
// `locate`'s from the positions its files were written from.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "beacon_geometry.hpp"
#include "child_process.hpp"
#include "enum_name.hpp"
#include "odoloc/board/sim_target.hpp"
#include "odoloc/cli/locate.hpp"
#include "odoloc/process/run_program.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/rtl/clocked.hpp"
#include "png_size.hpp"
#include "vcd_check.hpp"

namespace {

namespace regs = odoloc::regs;
using nlohmann::json;

// A scenario of SimTarget in which the robot drives, so the wheels turn.
constexpr const char* kDrivingScenario = "straight";

using Result = odoloc::tb::ChildResult;
using odoloc::tb::Child;
using odoloc::tb::finish;
using odoloc::tb::slurp;
using odoloc::tb::spawn;

// Runs the tool with `args`, `input` on its standard input.
Result run(const std::vector<std::string>& args, const std::string& input = {}) {
  return finish(spawn(ODOLOC_CLI, args, input));
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
  // Beyond the word addresses and not the byte address of a register either.
  std::uint32_t beyond = space;
  while (regs::find(beyond / 4) != nullptr)
    beyond += 4;
  expect_usage_error(run({"reg", "read", fmt::format("0x{:x}", beyond)}), "out of range");
  std::uint16_t hole = 0;
  while (regs::find(std::uint32_t{hole}) != nullptr)
    ++hole;
  expect_usage_error(run({"reg", "read", std::to_string(hole)}), "unmapped");
  expect_usage_error(run({"--target", "nowhere", "reg", "read", "top.id"}), "unknown target");
  expect_usage_error(run({"--target", "sim:no_such_scenario", "reg", "read", "top.id"}),
                     kDrivingScenario);
  expect_usage_error(run({"--target", "lcm", "--crc", "reg", "read", "top.id"}),
                     "target lcm reaches the simulator's registers through its register bridge");
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

// --cycle-step acts on the simulated chip only, and is chosen once per run.
TEST(CliE2e, CycleStepNeedsTheSimTargetAndTheCommandLine) {
  expect_usage_error(run({"--cycle-step", "-t", "spidev:/dev/spidev9.9", "reg", "read", "top.id"}),
                     "--cycle-step");
  expect_usage_error(run({"script", "-"}, "--cycle-step reg read top.id\n"), "--cycle-step");
  expect_usage_error(run({"--cycle-step", "locate", "--layout", "l", "--arrivals", "a"}),
                     "--cycle-step does not apply to locate");
}

// ------------------------------------------------------------ issue 9

// The first Ctrl-C ends any command within milliseconds, exit 130 (the
// simulated board polls the flag every simulated millisecond).
Result interrupt(const std::vector<std::string>& args, const std::string& input = {},
                 const std::string& wait_for_output = {}) {
  const Child c = spawn(ODOLOC_CLI, args, input);
  // Let it get going: until it has printed `wait_for_output`, or 300 ms.
  const auto started = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - started < std::chrono::seconds{20}) {
    std::this_thread::sleep_for(std::chrono::milliseconds{20});
    if (wait_for_output.empty()
            ? std::chrono::steady_clock::now() - started > std::chrono::milliseconds{300}
            : slurp(c.out_path).find(wait_for_output) != std::string::npos)
      break;
  }
  const auto sent = std::chrono::steady_clock::now();
  ::kill(c.pid, SIGINT);
  const Result r = finish(c, std::chrono::seconds{10});
  EXPECT_LT(std::chrono::steady_clock::now() - sent, std::chrono::seconds{2})
      << "Ctrl-C was not prompt";
  return r;
}

// Cycle stepped, so that 9 s of simulated time take seconds of CPU (with
// fast-forward they may end before the Ctrl-C).
TEST(CliE2eLimits, FirstCtrlCEndsEveryCommandWith130) {
  const std::string target = fmt::format("sim:{}", kDrivingScenario);
  const Result wait = interrupt({"-t", target, "--cycle-step", "wait", "9s"});
  EXPECT_EQ(wait.code, 130) << wait.err;
  EXPECT_TRUE(wait.err.empty()) << wait.err;
  // A watch without --count ends after its complete lines.
  const Result watch = interrupt(
      {"-t", target, "--cycle-step", "reg", "watch", "top.id", "--interval", "9s"}, {}, "top.id=");
  EXPECT_EQ(watch.code, 130) << watch.err;
  EXPECT_EQ(lines(watch.out), 1U) << watch.out;
  const Result counted = interrupt({"-t", target, "--cycle-step", "--json", "reg", "watch",
                                    "top.id", "--interval", "5s", "--count", "3"},
                                   {}, "sample");
  EXPECT_EQ(counted.code, 130) << counted.err;
  EXPECT_EQ(json_lines(counted.out).size(), 1U);
  // A script: the line running ends, the next never starts.
  const Result script = interrupt({"-t", target, "--cycle-step", "script", "-"},
                                  "wait 9s\nreg write top.scratch=1\n");
  EXPECT_EQ(script.code, 130) << script.err;
  EXPECT_TRUE(script.out.empty()) << script.out;
}

TEST(CliE2eLimits, SimulatedTimeBeyondTheLimitIsRefusedAtOnce) {
  const auto started = std::chrono::steady_clock::now();
  expect_usage_error(run({"reg", "watch", "top.id", "--interval", "600s", "--count", "3"}),
                     "simulated");
  expect_usage_error(run({"wait", "121s"}), "at most 120 s per command");
  expect_usage_error(run({"--cycle-step", "wait", "11s"}),
                     "at most 10 s per command with --cycle-step");
  expect_usage_error(run({"script", "-"}, "reg read top.id\nwait 1h\n"), "<stdin>:2: bad interval");
  expect_usage_error(run({"script", "-"}, "reg read top.id\nwait 200s\n"), "<stdin>:2: ");
  expect_usage_error(run({"--cycle-step", "script", "-"}, "reg read top.id\nwait 11s\n"),
                     "<stdin>:2: ");
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds{5});
}

TEST(CliE2eLimits, NumbersWithUnitsThatOverflowAreRefused) {
  expect_usage_error(run({"wait", "18446744073.999999999s"}), "too long");
  expect_usage_error(run({"reg", "watch", "top.id", "--interval", "18446744073.999999999s"}),
                     "too long");
  expect_usage_error(run({"-t", "spidev:/dev/spidev0.0@18446744073709.999999M", "reg", "dump"}),
                     "too large");
  expect_usage_error(run({"reg", "watch", "top.id", "--count", "18446744073709551616"}),
                     "too large");
}

TEST(CliE2eLimits, UnknownCommandsAndDirectoriesAreErrors) {
  expect_usage_error(run({"frobnicate", "--help"}), "unknown command 'frobnicate'");
  expect_usage_error(run({"scirpt", "--help"}), "did you mean script?");
  expect_usage_error(run({"reg", "raed", "--help"}), "did you mean read?");
  expect_usage_error(run({"script", ::testing::TempDir()}), "directory");
  const Result version = run({"--version"});
  EXPECT_EQ(version.code, 0);
  EXPECT_TRUE(version.out.starts_with("odoloc 0.")) << version.out;
}

// Byte addresses and names copied from odoloc.rdl mean the same register,
// or are refused naming both readings.
TEST(CliE2eLimits, RdlAddressesAndNames) {
  const regs::Register& left_rear_cfg = *regs::find("eppm.left_rear.cfg");
  const std::string byte_address = fmt::format("0x{:x}", left_rear_cfg.address * 4U);
  for (const std::string& name : {std::string{"eppm_left_rear.cfg"}, "b:" + byte_address,
                                  fmt::format("w:0x{:x}", left_rear_cfg.address)}) {
    const Result r = run({"--json", "reg", "read", name});
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    EXPECT_EQ(only_json(r)["values"][0]["path"], "eppm.left_rear.cfg") << name;
  }
  const auto as_word = static_cast<std::uint32_t>(std::stoul(byte_address, nullptr, 16));
  if (const regs::Register* other = regs::find(as_word); other != nullptr) {
    expect_usage_error(run({"reg", "read", byte_address}), "ambiguous");
    expect_usage_error(run({"reg", "write", byte_address + "=0"}), "ambiguous");
  }
}

// Every file the tool writes: a full disk is exit 1 with a message.
TEST(CliE2eLimits, FailedWritesAreErrors) {
  if (::access("/dev/full", W_OK) != 0)
    GTEST_SKIP() << "no /dev/full";
  const Result out = finish(spawn(ODOLOC_CLI, {"reg", "dump"}, {}, "/dev/full"));
  EXPECT_EQ(out.code, 1);
  EXPECT_EQ(out.err, "odoloc: writing standard output failed\n");
  for (const char* option : {"--vcd", "--vcd-pins"}) {
    const Result vcd = run({option, "/dev/full", "reg", "read", "top.id"});
    EXPECT_EQ(vcd.code, 1) << option;
    EXPECT_NE(vcd.err.find("writing the waveform to '/dev/full' failed"), std::string::npos)
        << vcd.err;
  }
  expect_usage_error(run({"--vcd-pins", "/nonexistent-odoloc/x.vcd", "reg", "read", "top.id"}),
                     "cannot write the waveform");
}

// ------------------------------------------------------------ sigrok-cli

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path != nullptr ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    if (!dir.empty() && ::access((dir + "/" + program).c_str(), X_OK) == 0)
      return true;
  }
  return false;
}

// sigrok-cli's SPI decoder over the pins-only waveform: one byte vector per
// chip-select frame, MOSI or MISO.
std::vector<std::vector<std::uint8_t>> sigrok_frames(const std::string& vcd, const char* pin) {
  const Result r = finish(
      spawn("sigrok-cli",
            {"-I", "vcd:compress=1000", "-i", vcd, "-P", "spi:clk=sclk:mosi=mosi:miso=miso:cs=cs_n",
             "-A", fmt::format("spi={}-transfer", pin)},
            {}),
      std::chrono::seconds{30});
  EXPECT_EQ(r.code, 0) << r.err;
  std::vector<std::vector<std::uint8_t>> frames;
  std::istringstream s(r.out);
  for (std::string line; std::getline(s, line);) {
    if (!line.starts_with("spi-1: "))
      continue;
    std::istringstream bytes(line.substr(7));
    std::vector<std::uint8_t> frame;
    for (std::string b; bytes >> b;)
      frame.push_back(static_cast<std::uint8_t>(std::stoul(b, nullptr, 16)));
    frames.push_back(std::move(frame));
  }
  return frames;
}

std::vector<std::uint8_t> word_bytes(std::uint32_t w) {
  return {static_cast<std::uint8_t>(w >> 24U), static_cast<std::uint8_t>(w >> 16U),
          static_cast<std::uint8_t>(w >> 8U), static_cast<std::uint8_t>(w)};
}

std::vector<std::uint8_t> header(bool read, unsigned count, std::uint16_t address) {
  const auto h = static_cast<std::uint16_t>((read ? 0x8000U : 0U) | (count - 1U) << 10U | address);
  return {static_cast<std::uint8_t>(h >> 8U), static_cast<std::uint8_t>(h)};
}

// J1850 CRC-8 of docs/spi.md, written out here, not taken from the codec.
std::uint8_t crc8(std::span<const std::uint8_t> bytes) {
  std::uint8_t crc = 0xFF;
  for (const std::uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i)
      crc = static_cast<std::uint8_t>((crc & 0x80U) != 0 ? (crc << 1U) ^ 0x1DU : crc << 1U);
  }
  return static_cast<std::uint8_t>(crc ^ 0xFFU);
}

// Issue 9: Debian 12's sigrok-cli stopped at the first vector of --vcd and
// printed nothing. --vcd-pins is the four pins as distinctly named scalars.
TEST(CliE2eSigrok, DecodesReadBurstWriteAndCrcFramesOfThePinsWaveform) {
  if (!on_path("sigrok-cli"))
    GTEST_SKIP() << "sigrok-cli is not installed (Debian package sigrok-cli)";
  const std::string vcd = ::testing::TempDir() + fmt::format("odoloc_pins_{}.vcd", ::getpid());
  const std::uint32_t value = 0xA5C3'0F96U;
  const auto scratch = regs::top::scratch::kAddress;
  const Result r = run({"--vcd-pins", vcd, "script", "-"},
                       fmt::format("reg write top.scratch={:#x}\nreg read top.scratch\n"
                                   "wait 1ms\nreg read top.id top.ctrl top.spi_status\n",
                                   value));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto mosi = sigrok_frames(vcd, "mosi");
  const auto miso = sigrok_frames(vcd, "miso");
  ASSERT_EQ(mosi.size(), miso.size());
  ASSERT_FALSE(mosi.empty()) << "sigrok-cli decoded nothing";

  const auto find = [&](const std::vector<std::uint8_t>& head, std::size_t size) {
    for (std::size_t i = 0; i < mosi.size(); ++i) {
      if (mosi[i].size() == size && std::equal(head.begin(), head.end(), mosi[i].begin()))
        return i;
    }
    ADD_FAILURE() << "no frame starting " << fmt::format("{:02x}", fmt::join(head, " "));
    return mosi.size();
  };
  // The write: header and the word, exactly.
  std::vector<std::uint8_t> write = header(false, 1, scratch);
  const auto v = word_bytes(value);
  write.insert(write.end(), v.begin(), v.end());
  EXPECT_NE(find(write, write.size()), mosi.size());
  // The read: the word comes back on MISO after the status byte and 0x00.
  if (const std::size_t i = find(header(true, 1, scratch), 6); i < miso.size()) {
    EXPECT_EQ(std::vector<std::uint8_t>(miso[i].begin() + 2, miso[i].end()), v);
  }
  // The burst: three consecutive words in one frame.
  if (const std::size_t i = find(header(true, 3, regs::top::id::kAddress), 14); i < miso.size()) {
    std::vector<std::uint8_t> words;
    for (const std::uint32_t w :
         {regs::top::id::kReset, regs::top::ctrl::kReset, regs::top::spi_status::kReset}) {
      const auto b = word_bytes(w);
      words.insert(words.end(), b.begin(), b.end());
    }
    EXPECT_EQ(std::vector<std::uint8_t>(miso[i].begin() + 2, miso[i].end()), words);
  }

  // A CRC frame: MOSI and MISO each end with the CRC-8 of the bytes before.
  const Result crc = run({"--crc", "--vcd-pins", vcd, "reg", "read", "top.scratch"});
  ASSERT_EQ(crc.code, 0) << crc.err;
  const auto crc_mosi = sigrok_frames(vcd, "mosi");
  const auto crc_miso = sigrok_frames(vcd, "miso");
  std::remove(vcd.c_str());
  bool checked = false;
  for (std::size_t i = 0; i < crc_mosi.size() && i < crc_miso.size(); ++i) {
    const auto& out = crc_mosi[i];
    const auto& in = crc_miso[i];
    const auto head = header(true, 1, scratch);
    if (out.size() != 7 || !std::equal(head.begin(), head.end(), out.begin()))
      continue;
    EXPECT_EQ(out.back(), crc8(std::span(out).first(6)));
    ASSERT_EQ(in.size(), 7U);
    EXPECT_EQ(in.back(), crc8(std::span(in).first(6)));
    EXPECT_EQ(std::vector<std::uint8_t>(in.begin() + 2, in.begin() + 6),
              word_bytes(regs::top::scratch::kReset));
    checked = true;
  }
  EXPECT_TRUE(checked) << crc_mosi.size() << " frames";
}

// ------------------------------------------------------------------ locate

namespace loc = odoloc::sw::locate;

bool have_gnuplot() {
  return odoloc::process::run_program("gnuplot", {"--version"}, ::testing::TempDir()).ok();
}

// Files written from known positions: Kleeman's six beacons in a 5 m x 4 m
// room, 0.8 m above the receivers; distances exact (long double) plus each
// cycle's common offset. Cycle by cycle (numbers from 100):
//   0  every beacon once
//   1  B3 heard twice: its direct arrival, then an echo 0.74 m later
//   2  B4 failed: nan
//   3  B1 not heard: no row
//   4  B2's direct path blocked: only an echo, 0.9 m late
//   5  only B0 and B3: no fix
struct LocateCase {
  loc::BeaconLayout layout = odoloc::tb::kleeman_layout(5, 4, 0.05, 0.8);
  std::vector<loc::Vec2> truth = {{1.0, 1.0}, {1.7, 1.4}, {2.4, 1.9},
                                  {3.1, 2.3}, {3.8, 2.8}, {2.0, 2.0}};
  std::string dir = fmt::format("{}odoloc_locate_{}_", ::testing::TempDir(), ::getpid());
  std::string layout_file = dir + "layout.yaml";
  std::string arrivals_file = dir + "arrivals.csv";
  std::string times_file = dir + "times.csv";

  LocateCase() {
    std::ofstream yaml(layout_file);
    yaml << "# Kleeman's six beacons, 0.8 m up\nbeacons:\n";
    for (std::size_t b = 0; b < layout.beacons.size(); ++b) {
      const loc::Beacon& beacon = layout.beacons[b];
      yaml << fmt::format("  - {{id: B{}, x: {:.17g}, y: {:.17g}, height: {:.17g}}}\n", b,
                          beacon.position_m.x, beacon.position_m.y, beacon.height_m);
    }
    std::ofstream distances(arrivals_file);
    std::ofstream times(times_file);
    distances << "cycle,beacon,distance_m,sd_m\n";
    times << "cycle,beacon,time_s\n";
    for (std::size_t c = 0; c < truth.size(); ++c) {
      const long double offset = 0.25L + 0.01L * static_cast<long double>(c);
      for (std::size_t b = 0; b < layout.beacons.size(); ++b) {
        const long double d = odoloc::tb::exact_range(layout, b, truth[c]) + offset;
        const auto row = [&](const std::string& value, long double metres) {
          distances << fmt::format("{},B{},{},0.001\n", 100 + c, b, value);
          times << fmt::format("{},B{},{:.21Lg}\n", 100 + c, b, metres / 343.2L);
        };
        const std::string exact = fmt::format("{:.17Lg}", d);
        if (c == 2 && b == 4) {
          distances << fmt::format("{},B{},nan,\n", 100 + c, b);
          times << fmt::format("{},B{},\n", 100 + c, b);
        } else if (c == 3 && b == 1) {
          continue;
        } else if (c == 4 && b == 2) {
          row(fmt::format("{:.17Lg}", d + 0.9L), d + 0.9L);
        } else if (c == 5 && b != 0 && b != 3) {
          continue;
        } else {
          row(exact, d);
          if (c == 1 && b == 3)
            row(fmt::format("{:.17Lg}", d + 0.74L), d + 0.74L);
        }
      }
    }
  }
  LocateCase(const LocateCase&) = delete;
  LocateCase& operator=(const LocateCase&) = delete;
  ~LocateCase() {
    for (const std::string& f : {layout_file, arrivals_file, times_file})
      std::remove(f.c_str());
  }

  [[nodiscard]] std::vector<std::string> args(const std::string& arrivals) const {
    return {"locate", "--layout", layout_file, "--arrivals", arrivals};
  }
};

const json& beacon(const json& fix, int b) {
  return fix["beacons"].at(static_cast<std::size_t>(b));
}

TEST(CliE2eLocate, FixesFromDistancesAndTimesAreTheKnownPositions) {
  const LocateCase lc;
  for (const std::string& file : {lc.arrivals_file, lc.times_file}) {
    SCOPED_TRACE(file);
    std::vector<std::string> args = lc.args(file);
    args.emplace_back("--json");
    const Result r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    const std::vector<json> fixes = json_lines(r.out);
    ASSERT_EQ(fixes.size(), lc.truth.size()) << r.out;  // every cycle, with or without a fix
    for (std::size_t c = 0; c + 1 < fixes.size(); ++c) {
      SCOPED_TRACE(c);
      const json& f = fixes[c];
      EXPECT_EQ(f["cycle"], 100 + c);
      EXPECT_EQ(f["solver"], "gauss_newton");
      ASSERT_EQ(f["valid"], true) << f.dump();
      EXPECT_NEAR(f["x_m"].get<double>(), lc.truth[c].x, 1e-6);
      EXPECT_NEAR(f["y_m"].get<double>(), lc.truth[c].y, 1e-6);
      EXPECT_NEAR(f["offset_m"].get<double>(), 0.25 + 0.01 * static_cast<double>(c), 1e-6);
      EXPECT_NEAR(f["speed_of_sound_mps"].get<double>(), 343.2, 1e-9);
      EXPECT_GT(f["sd_x_m"].get<double>(), 0);
      EXPECT_EQ(f["beacons"].size(), 6U);
    }
    EXPECT_EQ(beacon(fixes[0], 3)["status"], "used");
    EXPECT_EQ(beacon(fixes[1], 3)["candidate"], 0);  // the direct arrival, not the echo
    EXPECT_EQ(beacon(fixes[2], 4)["status"], "non_finite");
    EXPECT_EQ(fixes[2]["used"], 5);
    EXPECT_EQ(beacon(fixes[3], 1)["status"], "missing");
    EXPECT_EQ(beacon(fixes[4], 2)["status"], "outlier");
    EXPECT_NEAR(beacon(fixes[4], 2)["residual_m"].get<double>(), 0.9, 1e-6);
    const json& none = fixes[5];
    EXPECT_EQ(none["cycle"], 105);
    EXPECT_EQ(none["valid"], false);
    EXPECT_EQ(none["reason"], "too_few_beacons");
    EXPECT_TRUE(none["x_m"].is_null());
    EXPECT_EQ(beacon(none, 1)["status"], "missing");
  }
}

TEST(CliE2eLocate, TheTablePrintsTheSameFixes) {
  const LocateCase lc;
  const Result r = run(lc.args(lc.arrivals_file));
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::getline(lines, line);
  EXPECT_TRUE(line.starts_with("cycle  solver")) << line;
  for (std::size_t c = 0; c < lc.truth.size(); ++c) {
    ASSERT_TRUE(std::getline(lines, line));
    std::istringstream words(line);
    std::string cycle, solver, valid, reason, x, y;
    words >> cycle >> solver >> valid >> reason >> x >> y;
    EXPECT_EQ(cycle, std::to_string(100 + c));
    EXPECT_EQ(solver, "gauss_newton");
    if (c + 1 == lc.truth.size()) {
      EXPECT_EQ(valid, "no") << line;
      EXPECT_EQ(reason, "too_few_beacons") << line;
      EXPECT_EQ(x, "-") << line;
      continue;
    }
    EXPECT_EQ(valid, "yes") << line;
    EXPECT_NEAR(std::stod(x), lc.truth[c].x, 5.1e-5) << line;  // four decimals
    EXPECT_NEAR(std::stod(y), lc.truth[c].y, 5.1e-5) << line;
  }
  EXPECT_FALSE(std::getline(lines, line)) << line;
}

// Kleeman's solvers on the same files: the clean cycles exact, every cycle
// reported.
TEST(CliE2eLocate, KleemansSolvers) {
  const LocateCase lc;
  for (const std::vector<std::string>& solver :
       {std::vector<std::string>{"--solver", "longsolve"},
        std::vector<std::string>{"--solver", "kleeman"},
        std::vector<std::string>{"--solver", "kleeman", "--triple", "B0,B2,B4"}}) {
    SCOPED_TRACE(solver.back());
    std::vector<std::string> args = lc.args(lc.arrivals_file);
    args.insert(args.end(), solver.begin(), solver.end());
    args.emplace_back("--json");
    const Result r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<json> fixes = json_lines(r.out);
    ASSERT_EQ(fixes.size(), lc.truth.size()) << r.out;
    for (std::size_t c = 0; c < 2; ++c) {
      ASSERT_EQ(fixes[c]["valid"], true) << fixes[c].dump();
      EXPECT_NEAR(fixes[c]["x_m"].get<double>(), lc.truth[c].x, 1e-6);
      EXPECT_NEAR(fixes[c]["y_m"].get<double>(), lc.truth[c].y, 1e-6);
    }
    EXPECT_EQ(fixes[5]["valid"], false);
  }
}

TEST(CliE2eLocate, ThePlotIsAPictureGnuplotDrew) {
  if (!have_gnuplot())
    GTEST_SKIP() << "gnuplot is not installed";
  const LocateCase lc;
  const std::string png = lc.dir + "fixes.png";
  const std::string svg = lc.dir + "fixes.svg";
  for (const std::string& picture : {png, svg}) {
    std::vector<std::string> args = lc.args(lc.arrivals_file);
    args.insert(args.end(), {"--plot", picture});
    const Result r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(lines(r.out), lc.truth.size() + 1);  // the table as well
  }
  const odoloc::tb::PngSize size = odoloc::tb::png_size(png);
  EXPECT_EQ(size.width, static_cast<std::uint32_t>(odoloc::cli::kLocatePlotWidth));
  EXPECT_EQ(size.height, static_cast<std::uint32_t>(odoloc::cli::kLocatePlotHeight));
  const std::string text = slurp(svg);
  EXPECT_TRUE(text.starts_with("<?xml")) << text.substr(0, 200);
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("Produced by GNUPLOT"), std::string::npos);
  EXPECT_NE(text.find(">B5<"), std::string::npos);  // the beacons' labels
  EXPECT_NE(text.find("2-sigma error ellipses"), std::string::npos);
  std::remove(png.c_str());
  std::remove(svg.c_str());

  // A picture that cannot be written: the fixes are printed, then exit 2,
  // before gnuplot runs.
  std::vector<std::string> args = lc.args(lc.arrivals_file);
  args.insert(args.end(), {"--plot", "/nonexistent/fixes.png"});
  const Result r = run(args);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.out), lc.truth.size() + 1);
  EXPECT_EQ(r.err,
            "odoloc: --plot: cannot write /nonexistent/fixes.png: the folder /nonexistent does "
            "not exist\n");
  EXPECT_EQ(lines(r.err), 1U) << r.err;
}

TEST(CliE2eLocate, MistakesInTheFilesAndOptionsAreUsageErrors) {
  const LocateCase lc;
  const std::string bad = lc.dir + "bad.csv";
  std::ofstream(bad) << "cycle,beacon,distance_m\n0,B0,2.5\n0,B7,2.5\n";
  expect_usage_error(
      run(lc.args(bad)),
      fmt::format("{}:3: unknown beacon 'B7' (the layout's: B0, B1, B2, B3, B4, B5)", bad));
  std::remove(bad.c_str());
  std::vector<std::string> args = lc.args(lc.arrivals_file);
  args.insert(args.end(), {"--solver", "longsolve", "--calibrate-c"});
  expect_usage_error(run(args), "--calibrate-c needs --solver gauss-newton");
  expect_usage_error(run({"locate", "--arrivals", lc.arrivals_file}), "--layout is required");
  expect_usage_error(run(lc.args(lc.dir + "none.csv")), "cannot open arrivals");
}

}  // namespace
