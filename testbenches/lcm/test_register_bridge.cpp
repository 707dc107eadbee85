// The register bridge in one process over memq:// (one connection carries
// both sides: the client's handle() loop dispatches its request to the
// bridge, then the bridge's response to the client). Behind the bridge is
// the simulated chip behind its SPI pins, tapped so that the test sees every
// bus access the bridge makes:
//   - reads, bursts and a dump through the bridge equal what the chip's bus
//     returned, and the values written directly before them;
//   - writes are refused without allow_write (nothing written) and land
//     with it;
//   - malformed messages on ODOLOC_REG_REQUEST are ignored and counted while
//     the bridge keeps answering; invalid requests are ERROR and touch
//     nothing;
//   - the client splits long transfers, ignores other ids' responses and
//     refuses answers that do not fit; with nobody answering it times out
//     naming the URL.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/bridge/lcm_register_bus.hpp"
#include "odoloc/bridge/protocol.hpp"
#include "odoloc/bridge/register_bridge.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/regs.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc_lcm/pose_estimate_t.hpp"
#include "odoloc_lcm/register_request_t.hpp"
#include "odoloc_lcm/register_response_t.hpp"

namespace {

using namespace std::chrono_literals;
namespace regs = odoloc::regs;
namespace channel = odoloc::lcm::channel;
using odoloc::bridge::kDumpWords;
using odoloc::bridge::kMapped;
using odoloc::bridge::kMaxWords;
using odoloc::bridge::LcmRegisterBus;
using odoloc::bridge::RegisterBridge;
using odoloc::lcm::Connection;
using odoloc::sw::BusError;
using Request = odoloc_lcm::register_request_t;
using Response = odoloc_lcm::register_response_t;

// A bus that forwards to another and logs every access.
class TappedBus final : public odoloc::sw::RegisterBus {
 public:
  struct Access {
    bool read;
    std::uint16_t address;
    std::vector<std::uint32_t> words;
  };
  explicit TappedBus(odoloc::sw::RegisterBus& bus) : bus_(bus) {}
  using RegisterBus::read;
  using RegisterBus::write;
  void read(std::uint16_t address, std::span<std::uint32_t> words) override {
    bus_.read(address, words);
    log.push_back({true, address, {words.begin(), words.end()}});
  }
  void write(std::uint16_t address, std::span<const std::uint32_t> words) override {
    log.push_back({false, address, {words.begin(), words.end()}});
    bus_.write(address, words);
  }
  std::vector<Access> log;

 private:
  odoloc::sw::RegisterBus& bus_;
};

// The simulated chip at rest (wheels still), its bus, and the bridge's tap.
struct Chip {
  odoloc::board::ChipLink link{{}};
  odoloc::sw::SpiRegisterBus bus{link, {.crc = false, .confirm_writes = true}};
  TappedBus tap{bus};
};

// A recognisable word for each register: the rw bits of a hash of its address.
std::uint32_t pattern(const regs::Register& r) {
  return (0x9e3779b9U * (r.address + 1U)) & r.rw_mask;
}

// Registers whose every bit is rw storage: they read back what was written
// and the fabric never changes them. top.ctrl is left out (it changes the
// SPI framing).
std::vector<const regs::Register*> storage_registers() {
  std::vector<const regs::Register*> out;
  for (const regs::Register& r : regs::kRegisters)
    if (r.access == regs::Access::kRw && r.address != regs::top::ctrl::kAddress)
      out.push_back(&r);
  return out;
}

class BridgeTest : public ::testing::Test {
 protected:
  // Writes pattern() into every storage register, directly on the chip.
  void fill_storage() {
    for (const regs::Register* r : storage_registers())
      chip.bus.write(r->address, pattern(*r));
  }
  // Publishes `request` and returns the bridge's response to it.
  Response ask(Request request) {
    request.num_values = static_cast<std::int16_t>(request.values.size());
    const std::size_t before = responses_.size();
    connection.publish(channel::kRegRequest, request);
    while (connection.handle(0ms)) {
    }
    EXPECT_EQ(responses_.size(), before + 1);
    return responses_.size() == before + 1 ? responses_.back() : Response{};
  }

  Connection connection{"memq://"};
  Chip chip;

 private:
  // Every response on the connection, for ask().
  std::vector<Response> responses_;
  odoloc::lcm::Subscription<Response>& subscription_ = connection.subscribe<Response>(
      channel::kRegResponse,
      [this](const Response& r, const odoloc::lcm::Receipt&) { responses_.push_back(r); });
};

// ------------------------------------------------------------ reads, dump

TEST_F(BridgeTest, ReadsThroughTheBridgeEqualDirectReads) {
  fill_storage();
  RegisterBridge bridge(connection, chip.tap, false);
  LcmRegisterBus client(connection);

  for (const regs::Register* r : storage_registers()) {
    SCOPED_TRACE(r->path);
    const std::uint32_t remote = client.read(r->address);
    EXPECT_EQ(remote, pattern(*r));
    EXPECT_EQ(remote, chip.bus.read(r->address));
  }
  EXPECT_EQ(client.read(regs::top::id::kAddress), regs::top::id::kReset);

  // A burst over a whole EPPM block: rw words and live status words, equal
  // to what the chip's bus returned to the bridge for that burst.
  const std::uint16_t first = regs::eppm::cfg::address(0);
  std::uint16_t end = first;
  while (kMapped[end])
    ++end;
  std::vector<std::uint32_t> burst(end - first);
  chip.tap.log.clear();
  client.read(first, burst);
  ASSERT_EQ(chip.tap.log.size(), 1U) << "one bus read for the burst";
  EXPECT_TRUE(chip.tap.log[0].read);
  EXPECT_EQ(chip.tap.log[0].address, first);
  EXPECT_EQ(chip.tap.log[0].words, burst);
  for (std::size_t i = 0; i < burst.size(); ++i) {
    const regs::Register* r = regs::find(std::uint32_t{first} + static_cast<std::uint32_t>(i));
    ASSERT_NE(r, nullptr);
    if (r->access == regs::Access::kRw) {
      EXPECT_EQ(burst[i], pattern(*r)) << r->path;
    }
  }
  const RegisterBridge::Counters c = bridge.counters();
  EXPECT_EQ(c.served, storage_registers().size() + 2);
  EXPECT_EQ(c.refused + c.errors + c.malformed, 0U);
}

TEST_F(BridgeTest, DumpIsEveryRegisterWordForWord) {
  fill_storage();
  RegisterBridge bridge(connection, chip.tap, false);
  LcmRegisterBus client(connection);
  chip.tap.log.clear();
  const std::vector<std::uint32_t> dump = client.dump();
  ASSERT_EQ(dump.size(), static_cast<std::size_t>(kDumpWords));

  // Every register read exactly once, by bursts of consecutive registers,
  // and its word placed at its address; no unmapped address touched.
  std::vector<int> reads(dump.size(), 0);
  for (const TappedBus::Access& a : chip.tap.log) {
    ASSERT_TRUE(a.read);
    for (std::size_t i = 0; i < a.words.size(); ++i) {
      const std::size_t address = a.address + i;
      ASSERT_LT(address, dump.size());
      ++reads[address];
      EXPECT_EQ(dump[address], a.words[i]) << address;
    }
  }
  for (std::size_t a = 0; a < dump.size(); ++a) {
    SCOPED_TRACE(a);
    EXPECT_EQ(reads[a], kMapped[a] ? 1 : 0);
    if (!kMapped[a]) {
      EXPECT_EQ(dump[a], 0U);
    }
  }
  for (const regs::Register& r : regs::kRegisters)
    EXPECT_LT(r.address, dump.size()) << r.path;

  // The words that stay put equal a direct read of each register now.
  for (const regs::Register* r : storage_registers())
    EXPECT_EQ(dump[r->address], chip.bus.read(r->address)) << r->path;
  EXPECT_EQ(dump[regs::top::id::kAddress], chip.bus.read(regs::top::id::kAddress));
  EXPECT_EQ(dump[regs::top::id::kAddress], regs::top::id::kReset);
  EXPECT_EQ(bridge.counters().served, 1U);
}

// ------------------------------------------------------------------ writes

TEST_F(BridgeTest, WritesAreRefusedWithoutAllowWrite) {
  RegisterBridge bridge(connection, chip.tap, false);
  EXPECT_FALSE(bridge.allow_write());
  LcmRegisterBus client(connection);
  const std::uint16_t scratch = regs::top::scratch::kAddress;
  chip.bus.write(scratch, 0x1234'5678U);
  try {
    client.write(scratch, 0xdead'beefU);
    ADD_FAILURE() << "the write was not refused";
  } catch (const BusError& e) {
    EXPECT_NE(std::string(e.what()).find("--allow-write"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(chip.tap.log.empty()) << "the bridge touched the bus";
  EXPECT_EQ(chip.bus.read(scratch), 0x1234'5678U);

  // The response itself: REFUSED, nothing echoed.
  Request request{};
  request.op = Request::WRITE;
  request.address = scratch;
  request.values = {7};
  request.request_id = 42;
  const Response response = ask(request);
  EXPECT_EQ(response.status, Response::REFUSED);
  EXPECT_EQ(response.request_id, 42);
  EXPECT_TRUE(response.values.empty());
  EXPECT_NE(response.message.find("--allow-write"), std::string::npos);
  EXPECT_EQ(chip.bus.read(scratch), 0x1234'5678U);
  const RegisterBridge::Counters c = bridge.counters();
  EXPECT_EQ(c.refused, 2U);
  EXPECT_EQ(c.served + c.errors, 0U);
}

TEST_F(BridgeTest, WritesLandWithAllowWrite) {
  RegisterBridge bridge(connection, chip.tap, true);
  EXPECT_TRUE(bridge.allow_write());
  LcmRegisterBus client(connection);
  const std::uint16_t scratch = regs::top::scratch::kAddress;
  client.write(scratch, 0xdead'beefU);
  EXPECT_EQ(chip.bus.read(scratch), 0xdead'beefU);
  // A burst of rw words.
  const std::uint16_t window = regs::eppm::window::address(1);
  const std::vector<std::uint32_t> words = {0x1111, 0x22, 0x3333};
  client.write(window, words);
  std::vector<std::uint32_t> back(words.size());
  chip.bus.read(window, back);
  EXPECT_EQ(back, words);
  EXPECT_EQ(client.read(scratch), 0xdead'beefU);
  EXPECT_EQ(bridge.counters().served, 3U);

  Request request{};
  request.op = Request::WRITE;
  request.address = scratch;
  request.values = {0xffff'ffff};
  request.request_id = 5;
  const Response response = ask(request);
  EXPECT_EQ(response.status, Response::OK);
  EXPECT_EQ(response.address, scratch);
  EXPECT_EQ(response.values, request.values);  // the words written
  EXPECT_EQ(chip.bus.read(scratch), 0xffff'ffffU);
}

// -------------------------------------------------------- malformed, invalid

TEST_F(BridgeTest, MalformedRequestsAreIgnoredAndCounted) {
  RegisterBridge bridge(connection, chip.tap, true);
  LcmRegisterBus client(connection);
  // Bytes that are no register_request_t: random buffers, another type's
  // encoding, every truncation of a good request, a good one with a byte
  // left over.
  std::vector<std::vector<std::uint8_t>> bad;
  std::mt19937 random(14);
  for (int i = 0; i < 50; ++i) {
    std::vector<std::uint8_t> bytes(random() % 64);
    for (std::uint8_t& b : bytes)
      b = static_cast<std::uint8_t>(random());
    bad.push_back(bytes);
  }
  odoloc_lcm::pose_estimate_t pose{};
  pose.source = "fused";
  bad.push_back(odoloc::lcm::encode(pose));
  bad.push_back(odoloc::lcm::encode(Response{}));
  Request good{};
  good.op = Request::WRITE;
  good.address = regs::top::scratch::kAddress;
  good.values = {1, 2};
  good.num_values = 2;
  const std::vector<std::uint8_t> whole = odoloc::lcm::encode(good);
  for (std::size_t n = 0; n < whole.size(); ++n)
    bad.emplace_back(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n));
  bad.push_back(whole);
  bad.back().push_back(0);

  std::uint32_t value = 0;
  for (const std::vector<std::uint8_t>& bytes : bad) {
    connection.publish_raw(channel::kRegRequest, bytes.data(), bytes.size());
    // The bridge still answers, right after the bad message.
    client.write(regs::top::scratch::kAddress, ++value);
    ASSERT_EQ(client.read(regs::top::scratch::kAddress), value);
  }
  // Nothing but the client's own words reached the bus.
  for (const TappedBus::Access& a : chip.tap.log)
    if (!a.read) {
      EXPECT_EQ(a.address, regs::top::scratch::kAddress);
    }
  const RegisterBridge::Counters c = bridge.counters();
  EXPECT_EQ(c.malformed, bad.size());
  EXPECT_EQ(c.served, 2 * bad.size());
  EXPECT_EQ(c.errors + c.refused, 0U);
  EXPECT_EQ(connection.malformed(), bad.size());

  // A malformed response does not disturb the client either.
  const std::vector<std::uint8_t> junk = {1, 2, 3};
  connection.publish_raw(channel::kRegResponse, junk.data(), junk.size());
  EXPECT_EQ(client.read(regs::top::scratch::kAddress), value);
}

TEST_F(BridgeTest, InvalidRequestsAreErrorsAndTouchNothing) {
  RegisterBridge bridge(connection, chip.tap, true);
  const std::uint16_t scratch = regs::top::scratch::kAddress;
  chip.bus.write(scratch, 0x5a5a'5a5aU);
  std::int32_t hole = 0;
  while (kMapped[static_cast<std::size_t>(hole)])
    ++hole;
  const auto read = [](std::int32_t address, std::int32_t count) {
    Request r{};
    r.op = Request::READ;
    r.address = address;
    r.count = count;
    return r;
  };
  const auto write = [](std::int32_t address, std::vector<std::int64_t> values) {
    Request r{};
    r.op = Request::WRITE;
    r.address = address;
    r.values = std::move(values);
    return r;
  };
  const auto op = [](std::int8_t code) {
    Request r{};
    r.op = code;
    r.count = 1;
    return r;
  };
  struct Case {
    Request request;
    std::string says;
  };
  const std::vector<Case> cases = {
      {read(hole, 1), "not a register"},
      {read(scratch, 2), "not a register"},  // scratch, then a hole
      {read(-1, 1), "outside"},
      {read(1023, 2), "outside"},
      {read(0x7fff'ffff, 1), "outside"},
      {read(0, 0), "0 words is out of range"},
      {read(0, -1), "-1 words is out of range"},
      {read(0, kMaxWords + 1), "out of range"},
      {write(scratch, {-1}), "not a 32-bit register word"},
      {write(scratch, {std::int64_t{1} << 32}), "not a 32-bit register word"},
      {write(hole, {1}), "not a register"},
      {write(scratch, {}), "0 words is out of range"},
      {write(scratch, std::vector<std::int64_t>(kMaxWords + 1, 0)), "out of range"},
      {op(3), "op 3: unknown op"},
      {op(-1), "op -1: unknown op"},
  };
  std::int64_t id = 1000;
  for (Case c : cases) {
    c.request.request_id = ++id;
    const Response response = ask(c.request);
    SCOPED_TRACE(response.message);
    EXPECT_EQ(response.status, Response::ERROR);
    EXPECT_EQ(response.request_id, id);
    EXPECT_NE(response.message.find(c.says), std::string::npos);
    EXPECT_TRUE(response.values.empty());
  }
  EXPECT_TRUE(chip.tap.log.empty()) << "an invalid request reached the bus";
  EXPECT_EQ(chip.bus.read(scratch), 0x5a5a'5a5aU);
  EXPECT_EQ(bridge.counters().errors, cases.size());
  EXPECT_EQ(bridge.counters().served, 0U);

  // The client gets the message as a BusError.
  LcmRegisterBus client(connection);
  try {
    (void)client.read(static_cast<std::uint16_t>(hole));
    ADD_FAILURE() << "an unmapped read passed";
  } catch (const BusError& e) {
    EXPECT_NE(std::string(e.what()).find("not a register"), std::string::npos) << e.what();
  }
}

TEST_F(BridgeTest, BusErrorsAreErrors) {
  RegisterBridge bridge(connection, chip.tap, true);
  LcmRegisterBus client(connection);
  // top.id is read-only: the fabric refuses the write frame.
  try {
    client.write(regs::top::id::kAddress, 0);
    ADD_FAILURE() << "a write to top.id passed";
  } catch (const BusError& e) {
    EXPECT_NE(std::string(e.what()).find("WRITE of 1 word to 0x000: the bus failed: "),
              std::string::npos)
        << e.what();
  }
  ASSERT_FALSE(chip.tap.log.empty());
  EXPECT_FALSE(chip.tap.log[0].read);
  EXPECT_EQ(chip.bus.read(regs::top::id::kAddress), regs::top::id::kReset);
  EXPECT_EQ(bridge.counters().errors, 1U);
  // And it answers on.
  EXPECT_EQ(client.read(regs::top::id::kAddress), regs::top::id::kReset);
}

// ------------------------------------------------------------------ client

// A hand-made simulator: answers each request with a response to another id
// first, then its own, whose words are `word(address)`; `tamper` may spoil
// the own one.
struct FakeSimulator {
  explicit FakeSimulator(Connection& c) : connection(c) {
    connection.subscribe<Request>(
        channel::kRegRequest,
        [this](const Request& request, const odoloc::lcm::Receipt&) { answer(request); });
  }
  static std::int64_t word(std::int64_t address) { return 0x10000 + address; }
  void answer(const Request& request) {
    requests.push_back(request);
    Response other{};
    other.request_id = request.request_id + 1;
    other.status = Response::ERROR;
    other.message = "not yours";
    connection.publish(channel::kRegResponse, other);
    Response own{};
    own.request_id = request.request_id;
    own.status = Response::OK;
    own.address = request.address;
    const std::int32_t count =
        request.op == Request::READ ? request.count : static_cast<std::int32_t>(request.num_values);
    for (std::int32_t i = 0; i < count; ++i)
      own.values.push_back(request.op == Request::READ ? word(request.address + i)
                                                       : request.values[i]);
    if (tamper)
      tamper(own);
    own.num_values = static_cast<std::int16_t>(own.values.size());
    connection.publish(channel::kRegResponse, own);
  }
  Connection& connection;
  std::vector<Request> requests;
  std::function<void(Response&)> tamper;
};

TEST(LcmRegisterBus, SplitsLongTransfersAndIgnoresOtherIds) {
  Connection connection("memq://");
  FakeSimulator simulator(connection);
  LcmRegisterBus client(connection);
  std::vector<std::uint32_t> words(2 * kMaxWords + 88);
  client.read(100, words);
  ASSERT_EQ(simulator.requests.size(), 3U);
  const std::int32_t expected[3][2] = {
      {100, kMaxWords}, {100 + kMaxWords, kMaxWords}, {100 + 2 * kMaxWords, 88}};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(simulator.requests[i].op, Request::READ);
    EXPECT_EQ(simulator.requests[i].address, expected[i][0]);
    EXPECT_EQ(simulator.requests[i].count, expected[i][1]);
  }
  for (std::size_t i = 0; i < words.size(); ++i)
    ASSERT_EQ(words[i], FakeSimulator::word(100 + static_cast<std::int64_t>(i))) << i;
  // Fresh, increasing ids.
  EXPECT_EQ(simulator.requests[1].request_id, simulator.requests[0].request_id + 1);
  EXPECT_GE(simulator.requests[0].request_id, 0);

  simulator.requests.clear();
  const std::vector<std::uint32_t> out(kMaxWords + 1, 3);
  client.write(7, out);
  ASSERT_EQ(simulator.requests.size(), 2U);
  EXPECT_EQ(simulator.requests[0].values.size(), static_cast<std::size_t>(kMaxWords));
  EXPECT_EQ(simulator.requests[1].address, 7 + kMaxWords);
  EXPECT_EQ(simulator.requests[1].values, std::vector<std::int64_t>{3});
}

TEST(LcmRegisterBus, AnswersThatDoNotFitAreBusErrors) {
  Connection connection("memq://");
  FakeSimulator simulator(connection);
  LcmRegisterBus client(connection);
  const std::vector<std::pair<std::function<void(Response&)>, std::string>> spoilers = {
      {[](Response& r) { r.values.pop_back(); }, "another register map"},
      {[](Response& r) { r.values.push_back(0); }, "another register map"},
      {[](Response& r) { r.address += 1; }, "another register map"},
      {[](Response& r) { r.values[0] = -1; }, "not a 32-bit register word"},
      {[](Response& r) { r.values[0] = std::int64_t{1} << 32; }, "not a 32-bit register word"},
      {[](Response& r) { r.status = 9; }, "status 9"},
  };
  for (const auto& [spoil, says] : spoilers) {
    simulator.tamper = spoil;
    std::vector<std::uint32_t> words(2);
    try {
      client.read(4, words);
      ADD_FAILURE() << "accepted; expected " << says;
    } catch (const BusError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

TEST(LcmRegisterBus, TimesOutNamingTheUrlWhenNobodyAnswers) {
  Connection connection("memq://");
  LcmRegisterBus client(connection, {.timeout = 150ms});
  const auto start = std::chrono::steady_clock::now();
  try {
    (void)client.read(0);
    ADD_FAILURE() << "no time-out";
  } catch (const BusError& e) {
    EXPECT_EQ(std::string(e.what()),
              "no simulator answered on memq:// within 150 ms: start `odoloc sim` (docs/lcm.md, "
              "\"Register bridge\")");
  }
  const auto waited = std::chrono::steady_clock::now() - start;
  EXPECT_GE(waited, 150ms);
  EXPECT_LT(waited, 2s);

  // A bridge that is gone answers nothing (and its handler does no harm).
  Chip chip;
  { RegisterBridge gone(connection, chip.bus, true); }
  EXPECT_THROW((void)client.read(0), BusError);
}

TEST(LcmRegisterBus, PollCanAbandonAWait) {
  Connection connection("memq://");
  struct Abandoned {};
  int polls = 0;
  LcmRegisterBus client(connection, {.timeout = 10s, .poll = [&polls] {
                                       if (++polls == 3)
                                         throw Abandoned{};
                                     }});
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW((void)client.read(0), Abandoned);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 1s);
  EXPECT_EQ(polls, 3);
}

}  // namespace
