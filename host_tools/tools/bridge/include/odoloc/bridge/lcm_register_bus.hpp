// The client's side of the register bridge (docs/lcm.md, "Register bridge"):
// a sw::RegisterBus whose reads and writes are requests to a simulator's
// RegisterBridge over LCM (`odoloc --target lcm`).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "odoloc/bridge/protocol.hpp"
#include "odoloc/lcm/connection.hpp"
#include "odoloc/sw/register_bus.hpp"

namespace odoloc::bridge {

struct LcmRegisterBusOptions {
  // How long one request waits for its response.
  std::chrono::milliseconds timeout = kDefaultTimeout;
  // Called at least every 10 ms while a request waits; it may throw to
  // abandon the request (the host tool throws on Ctrl-C). Empty: none.
  std::function<void()> poll = {};
};

class LcmRegisterBus final : public sw::RegisterBus {
 public:
  // Subscribes to ODOLOC_REG_RESPONSE on `connection`, which must outlive
  // the bus. Request ids start at a random number, so two clients on one
  // URL do not take each other's responses.
  explicit LcmRegisterBus(lcm::Connection& connection, LcmRegisterBusOptions options = {});
  ~LcmRegisterBus() override;

  using RegisterBus::read;
  using RegisterBus::write;
  // One READ (or WRITE) per kMaxWords words: publishes the request on
  // ODOLOC_REG_REQUEST, then calls connection.handle() (dispatching whatever
  // else the connection subscribes to) until the response with its id comes;
  // responses with other ids are ignored. Throws sw::BusError with the
  // simulator's message when it answers REFUSED or ERROR (a failed request
  // of a split transfer leaves the parts before it done), with a message
  // naming the URL when no response comes within the timeout, and when the
  // response does not fit the request. lcm::LcmError when LCM fails.
  void read(std::uint16_t address, std::span<std::uint32_t> words) override;
  void write(std::uint16_t address, std::span<const std::uint32_t> words) override;

  // One DUMP: the words at addresses 0 … kDumpWords − 1, unmapped addresses
  // 0. Errors as read().
  [[nodiscard]] std::vector<std::uint32_t> dump();

 private:
  struct Inbox;

  // The words of the response to `op` (its address and count checked);
  // `values` are a WRITE's words.
  std::vector<std::uint32_t> exchange(std::int8_t op, std::int32_t address, std::int32_t count,
                                      std::span<const std::uint32_t> values = {});

  lcm::Connection& connection_;
  LcmRegisterBusOptions options_;
  std::int64_t next_id_;
  // Shared with the subscription's handler only weakly, since the connection
  // keeps its handlers as long as it lives.
  std::shared_ptr<Inbox> inbox_;
};

}  // namespace odoloc::bridge
