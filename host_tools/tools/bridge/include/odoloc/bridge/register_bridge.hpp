// The simulator's side of the register bridge (docs/lcm.md, "Register
// bridge"): answers every register_request_t on ODOLOC_REG_REQUEST with a
// register_response_t on ODOLOC_REG_RESPONSE, carrying it out on a register
// bus (in `odoloc sim`, the simulated chip behind its SPI pins).
#pragma once

#include <cstdint>
#include <memory>

#include "odoloc/lcm/connection.hpp"
#include "odoloc/sw/register_bus.hpp"

namespace odoloc::bridge {

class RegisterBridge {
 public:
  // What the bridge has answered since it was made; readable from any thread.
  struct Counters {
    std::uint64_t served = 0;     // status OK
    std::uint64_t refused = 0;    // status REFUSED: writes without allow_write
    std::uint64_t errors = 0;     // status ERROR: invalid requests and bus errors
    std::uint64_t malformed = 0;  // messages on ODOLOC_REG_REQUEST that did not decode, ignored
  };

  // Subscribes to ODOLOC_REG_REQUEST on `connection`. Requests are served
  // inside connection.handle(), on the owner's thread, which must therefore
  // call it often enough for clients (LcmRegisterBus waits 2 s by default):
  // a simulator loop calls handle(0 ms) between its steps until it returns
  // false. Each request is answered exactly once:
  //   READ  `count` (1 … kMaxWords) words from `address`, every one a
  //         register of the map; values are the words read;
  //   WRITE `values` (1 … kMaxWords, each 0 … 2³² − 1) to `address`,
  //         `address + 1`, …, every one a register; only with `allow_write`,
  //         else REFUSED with a message naming --allow-write and nothing
  //         written; values echo the words written;
  //   DUMP  the words at addresses 0 … kDumpWords − 1 (unmapped ones 0, not
  //         accessed), read in one bus read per run of registers; address 0.
  // Anything else (unknown op, count or length out of range, an unmapped or
  // out-of-range address, a word outside 32 bits) and a sw::BusError from
  // the bus are ERROR with a message and change nothing the bus had not
  // already done. Reads have the bus's side effects (rc registers clear,
  // rpop FIFOs pop), as `odoloc reg read` on the board. A response that
  // cannot be published is an lcm::LcmError out of connection.handle().
  // `connection` and `bus` must outlive the bridge; once the bridge is gone,
  // requests the connection still receives go unanswered.
  RegisterBridge(lcm::Connection& connection, sw::RegisterBus& bus, bool allow_write);
  RegisterBridge(const RegisterBridge&) = delete;
  RegisterBridge& operator=(const RegisterBridge&) = delete;
  ~RegisterBridge();

  [[nodiscard]] bool allow_write() const;
  [[nodiscard]] Counters counters() const;

 private:
  class Server;
  // Shared with the subscription's handler only weakly, since the connection
  // keeps its handlers as long as it lives.
  std::shared_ptr<Server> server_;
};

}  // namespace odoloc::bridge
