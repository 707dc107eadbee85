#include "odoloc/bridge/lcm_register_bus.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <random>
#include <string>
#include <utility>

#include "odoloc/lcm/channels.hpp"
#include "odoloc_lcm/register_request_t.hpp"
#include "odoloc_lcm/register_response_t.hpp"

namespace odoloc::bridge {
namespace {

using Request = odoloc_lcm::register_request_t;
using Response = odoloc_lcm::register_response_t;

// How often a waiting request calls the poll function.
constexpr std::chrono::milliseconds kSlice{10};

std::int64_t random_first_id() {
  // Far below the int64_t limit: ids only count up from here.
  std::uniform_int_distribution<std::int64_t> first(0, std::int64_t{1} << 62);
  std::random_device seed;
  return first(seed);
}

std::string duration_text(std::chrono::milliseconds d) {
  return d.count() % 1000 == 0 ? fmt::format("{} s", d.count() / 1000)
                               : fmt::format("{} ms", d.count());
}

const char* op_name(std::int8_t op) {
  return op == Request::READ ? "READ" : op == Request::WRITE ? "WRITE" : "DUMP";
}

}  // namespace

// The response awaited, filled in by the subscription's handler.
struct LcmRegisterBus::Inbox {
  static constexpr std::int64_t kNone = -1;  // ids are never negative
  std::int64_t awaited = kNone;
  std::optional<Response> response;
};

LcmRegisterBus::LcmRegisterBus(lcm::Connection& connection, LcmRegisterBusOptions options)
    : connection_(connection),
      options_(std::move(options)),
      next_id_(random_first_id()),
      inbox_(std::make_shared<Inbox>()) {
  connection_.subscribe<Response>(
      lcm::channel::kRegResponse,
      [weak = std::weak_ptr<Inbox>(inbox_)](const Response& response, const lcm::Receipt&) {
        const std::shared_ptr<Inbox> inbox = weak.lock();
        if (inbox && response.request_id == inbox->awaited && !inbox->response)
          inbox->response = response;
      });
}

LcmRegisterBus::~LcmRegisterBus() = default;

void LcmRegisterBus::read(std::uint16_t address, std::span<std::uint32_t> words) {
  for (std::size_t done = 0; done < words.size(); done += kMaxWords) {
    const std::span<std::uint32_t> part = words.subspan(done).first(
        std::min(words.size() - done, static_cast<std::size_t>(kMaxWords)));
    const std::vector<std::uint32_t> got =
        exchange(Request::READ, static_cast<std::int32_t>(address + done),
                 static_cast<std::int32_t>(part.size()));
    std::ranges::copy(got, part.begin());
  }
}

void LcmRegisterBus::write(std::uint16_t address, std::span<const std::uint32_t> words) {
  for (std::size_t done = 0; done < words.size(); done += kMaxWords) {
    const std::span<const std::uint32_t> part = words.subspan(done).first(
        std::min(words.size() - done, static_cast<std::size_t>(kMaxWords)));
    (void)exchange(Request::WRITE, static_cast<std::int32_t>(address + done),
                   static_cast<std::int32_t>(part.size()), part);
  }
}

std::vector<std::uint32_t> LcmRegisterBus::dump() {
  return exchange(Request::DUMP, 0, kDumpWords);
}

std::vector<std::uint32_t> LcmRegisterBus::exchange(std::int8_t op, std::int32_t address,
                                                    std::int32_t count,
                                                    std::span<const std::uint32_t> values) {
  Request request{};
  request.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  request.request_id = next_id_++;
  request.op = op;
  request.address = op == Request::DUMP ? 0 : address;
  request.count = op == Request::READ ? count : 0;
  request.values.assign(values.begin(), values.end());
  request.num_values = static_cast<std::int16_t>(request.values.size());

  inbox_->awaited = request.request_id;
  inbox_->response.reset();
  connection_.publish(lcm::channel::kRegRequest, request);
  const auto deadline = std::chrono::steady_clock::now() + options_.timeout;
  while (!inbox_->response) {
    if (options_.poll)
      options_.poll();
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline)
      throw sw::BusError(fmt::format(
          "no simulator answered on {} within {}: start `odoloc sim` (docs/lcm.md, \"Register "
          "bridge\")",
          connection_.url(), duration_text(options_.timeout)));
    connection_.handle(
        std::min(std::chrono::ceil<std::chrono::milliseconds>(deadline - now), kSlice));
  }
  const Response response = *std::exchange(inbox_->response, std::nullopt);

  if (response.status == Response::REFUSED || response.status == Response::ERROR)
    throw sw::BusError(response.message);
  if (response.status != Response::OK)
    throw sw::BusError(
        fmt::format("the simulator answered a {} with status {}, which is none of "
                    "OK, REFUSED or ERROR",
                    op_name(op), response.status));
  if (response.address != request.address ||
      response.values.size() != static_cast<std::size_t>(count))
    throw sw::BusError(fmt::format(
        "the simulator answered a {} of {} words at {:#05x} with {} words at {:#05x} (does it "
        "have another register map?)",
        op_name(op), count, request.address, response.values.size(), response.address));
  std::vector<std::uint32_t> words;
  words.reserve(response.values.size());
  for (const std::int64_t v : response.values) {
    if (v < 0 || v > kMaxWord)
      throw sw::BusError(
          fmt::format("the simulator answered a {} with {}, which is not a 32-bit register word",
                      op_name(op), v));
    words.push_back(static_cast<std::uint32_t>(v));
  }
  return words;
}

}  // namespace odoloc::bridge
