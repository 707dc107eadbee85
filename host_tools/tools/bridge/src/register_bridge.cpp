#include "odoloc/bridge/register_bridge.hpp"

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

#include "odoloc/bridge/protocol.hpp"
#include "odoloc/lcm/channels.hpp"
#include "odoloc_lcm/register_request_t.hpp"
#include "odoloc_lcm/register_response_t.hpp"

namespace odoloc::bridge {
namespace {

using Request = odoloc_lcm::register_request_t;
using Response = odoloc_lcm::register_response_t;

// A request the bridge will not carry out; its message goes to the client.
class InvalidRequest : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::int64_t now_utime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string words_text(std::int64_t count) {
  return fmt::format("{} word{}", count, count == 1 ? "" : "s");
}

// The request as a person reads it, to begin its error messages:
// "READ of 3 words from 0x010".
std::string describe(const Request& request) {
  switch (request.op) {
    case Request::READ:
      return fmt::format("READ of {} from {:#05x}", words_text(request.count), request.address);
    case Request::WRITE:
      return fmt::format("WRITE of {} to {:#05x}",
                         words_text(static_cast<std::int64_t>(request.values.size())),
                         request.address);
    case Request::DUMP:
      return "DUMP";
    default:
      return fmt::format("op {}", request.op);
  }
}

// Throws InvalidRequest unless `count` words from `address` are all
// registers of the map.
void check_span(std::int32_t address, std::int64_t count) {
  if (count < 1 || count > kMaxWords)
    throw InvalidRequest(
        fmt::format("{} is out of range: 1 .. {} per request", words_text(count), kMaxWords));
  const std::int64_t end = std::int64_t{address} + count;
  if (address < 0 || end > std::int64_t{kMapped.size()})
    throw InvalidRequest(fmt::format("word addresses {:#05x} .. {:#05x} are outside 0 .. {:#05x}",
                                     address, end - 1, kMapped.size() - 1));
  for (std::int64_t a = address; a < end; ++a)
    if (!kMapped[static_cast<std::size_t>(a)])
      throw InvalidRequest(fmt::format("word address {:#05x} is not a register (unmapped)", a));
}

std::vector<std::int64_t> as_values(const std::vector<std::uint32_t>& words) {
  return {words.begin(), words.end()};
}

}  // namespace

class RegisterBridge::Server {
 public:
  Server(lcm::Connection& connection, sw::RegisterBus& bus, bool allow_write)
      : connection_(connection), bus_(bus), allow_write_(allow_write) {}

  void set_subscription(const lcm::SubscriptionBase& subscription) {
    subscription_ = &subscription;
  }
  [[nodiscard]] bool allow_write() const { return allow_write_; }
  [[nodiscard]] Counters counters() const {
    return {.served = served_.load(),
            .refused = refused_.load(),
            .errors = errors_.load(),
            .malformed = subscription_->malformed()};
  }

  void serve(const Request& request) {
    Response response{};
    response.request_id = request.request_id;
    response.status = Response::OK;
    response.address = request.op == Request::DUMP ? 0 : request.address;
    if (request.op == Request::WRITE && !allow_write_) {
      // Before any check: a simulator that takes no writes says so whatever
      // the request holds.
      response.status = Response::REFUSED;
      response.message =
          "register writes are refused: this simulator was started without --allow-write (LCM "
          "has no authentication); start it with `odoloc sim --allow-write` to allow them; "
          "nothing written";
    } else {
      try {
        response.values = as_values(carry_out(request));
      } catch (const InvalidRequest& e) {
        response.status = Response::ERROR;
        response.message = fmt::format("{}: {}; nothing done", describe(request), e.what());
      } catch (const sw::BusError& e) {
        response.status = Response::ERROR;
        response.message = fmt::format("{}: the bus failed: {}", describe(request), e.what());
      }
    }
    ++(response.status == Response::OK        ? served_
       : response.status == Response::REFUSED ? refused_
                                              : errors_);
    response.num_values = static_cast<std::int16_t>(response.values.size());
    response.utime = now_utime();
    connection_.publish(lcm::channel::kRegResponse, response);
  }

 private:
  // The words read, or written.
  std::vector<std::uint32_t> carry_out(const Request& request) {
    switch (request.op) {
      case Request::READ: {
        check_span(request.address, request.count);
        std::vector<std::uint32_t> words(static_cast<std::size_t>(request.count));
        bus_.read(static_cast<std::uint16_t>(request.address), words);
        return words;
      }
      case Request::WRITE: {
        check_span(request.address, static_cast<std::int64_t>(request.values.size()));
        std::vector<std::uint32_t> words;
        words.reserve(request.values.size());
        for (const std::int64_t v : request.values) {
          if (v < 0 || v > kMaxWord)
            throw InvalidRequest(
                fmt::format("value {} is not a 32-bit register word (0 .. {})", v, kMaxWord));
          words.push_back(static_cast<std::uint32_t>(v));
        }
        bus_.write(static_cast<std::uint16_t>(request.address), words);
        return words;
      }
      case Request::DUMP: {
        std::vector<std::uint32_t> words(static_cast<std::size_t>(kDumpWords), 0);
        for (std::size_t a = 0; a < words.size();) {
          if (!kMapped[a]) {
            ++a;
            continue;
          }
          std::size_t end = a + 1;
          while (end < words.size() && kMapped[end])
            ++end;
          bus_.read(static_cast<std::uint16_t>(a), std::span{words}.subspan(a, end - a));
          a = end;
        }
        return words;
      }
      default:
        throw InvalidRequest(fmt::format("unknown op; expected READ = {}, WRITE = {} or DUMP = {}",
                                         Request::READ, Request::WRITE, Request::DUMP));
    }
  }

  lcm::Connection& connection_;
  sw::RegisterBus& bus_;
  const bool allow_write_;
  const lcm::SubscriptionBase* subscription_ = nullptr;
  std::atomic<std::uint64_t> served_{0};
  std::atomic<std::uint64_t> refused_{0};
  std::atomic<std::uint64_t> errors_{0};
};

RegisterBridge::RegisterBridge(lcm::Connection& connection, sw::RegisterBus& bus, bool allow_write)
    : server_(std::make_shared<Server>(connection, bus, allow_write)) {
  server_->set_subscription(connection.subscribe<Request>(
      lcm::channel::kRegRequest,
      [weak = std::weak_ptr<Server>(server_)](const Request& request, const lcm::Receipt&) {
        if (const std::shared_ptr<Server> server = weak.lock())
          server->serve(request);
      }));
}

RegisterBridge::~RegisterBridge() = default;

bool RegisterBridge::allow_write() const {
  return server_->allow_write();
}

RegisterBridge::Counters RegisterBridge::counters() const {
  return server_->counters();
}

}  // namespace odoloc::bridge
