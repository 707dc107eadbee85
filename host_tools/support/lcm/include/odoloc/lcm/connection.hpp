// An LCM instance for odoloc's message types (docs/lcm.md): publishes them
// and hands received ones to typed handlers. Received bytes are decoded here,
// not by LCM: a message that does not decode (another type's fingerprint,
// truncated, garbage) is ignored and counted per subscription, and nothing
// ever throws into LCM's dispatch.
#pragma once

#include <atomic>
#include <chrono>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "odoloc/lcm/channels.hpp"

namespace odoloc::lcm {

// A URL LCM cannot open, a channel pattern it refuses, a failed publish or
// wait; the message names the URL and channel.
class LcmError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `size` bytes as one whole Message (an lcm-gen type): false when they are
// not one (wrong fingerprint, truncated, bytes left over, a length field out
// of range). Never throws: the generated decoder's std::length_error or
// std::bad_alloc on a negative or impossible length is a failure too.
template <class Message>
[[nodiscard]] bool decode(const void* data, std::size_t size, Message& message) noexcept {
  if (size > static_cast<std::size_t>(INT_MAX))
    return false;
  const int length = static_cast<int>(size);
  try {
    return message.decode(data, 0, length) == length;
  } catch (...) {
    return false;
  }
}

// The message's LCM encoding (fingerprint first). Every num_* length field
// must equal its array's size: the generated encoder reads that many.
template <class Message>
[[nodiscard]] std::vector<std::uint8_t> encode(const Message& message) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
  const int length = static_cast<int>(bytes.size());
  if (message.encode(bytes.data(), 0, length) != length)
    throw LcmError(std::string("LCM: cannot encode a ") + Message::getTypeName());
  return bytes;
}

// Where and when a received message came.
struct Receipt {
  // The channel it came on (a pattern may match several); valid during the
  // handler's call only.
  std::string_view channel;
  // When LCM received it, microseconds since the Unix epoch (a file:// replay:
  // the replay's clock, paced by the logged times; not the logged time).
  std::int64_t recv_utime = 0;
};

// What one subscription has seen; the counters may be read from any thread.
class SubscriptionBase {
 public:
  SubscriptionBase(const SubscriptionBase&) = delete;
  SubscriptionBase& operator=(const SubscriptionBase&) = delete;
  virtual ~SubscriptionBase() = default;

  // The channel name or pattern (a regular expression matched against the
  // whole channel name) it was subscribed with.
  [[nodiscard]] const std::string& channel() const { return channel_; }
  // Messages decoded and handed to the handler.
  [[nodiscard]] std::uint64_t received() const { return received_.load(); }
  // Messages ignored because they did not decode.
  [[nodiscard]] std::uint64_t malformed() const { return malformed_.load(); }

 protected:
  SubscriptionBase(std::string channel, std::exception_ptr& handler_error)
      : channel_(std::move(channel)), handler_error_(handler_error) {}

  std::string channel_;
  std::atomic<std::uint64_t> received_{0};
  std::atomic<std::uint64_t> malformed_{0};
  // The connection's slot for the first exception a handler threw.
  std::exception_ptr& handler_error_;
};

template <class Message>
class Subscription final : public SubscriptionBase {
 public:
  using Handler = std::function<void(const Message&, const Receipt&)>;

  Subscription(std::string channel, Handler handler, std::exception_ptr& handler_error)
      : SubscriptionBase(std::move(channel), handler_error), handler_(std::move(handler)) {}

  // LCM's raw callback; `user` is the subscription.
  static void on_message(const lcm_recv_buf_t* buffer, const char* channel, void* user) noexcept {
    static_cast<Subscription*>(user)->deliver(*buffer, channel);
  }

 private:
  void deliver(const lcm_recv_buf_t& buffer, std::string_view channel) noexcept {
    Message message{};
    if (!decode(buffer.data, buffer.data_size, message)) {
      ++malformed_;
      return;
    }
    ++received_;
    try {
      handler_(message, Receipt{.channel = channel, .recv_utime = buffer.recv_utime});
    } catch (...) {
      if (!handler_error_)
        handler_error_ = std::current_exception();
    }
  }

  Handler handler_;
};

class Connection {
 public:
  // Opens `url` in LCM's syntax: udpm://group:port?ttl=N, memq:// (this
  // process only), file:///path?mode=w (writes an event log) or ?mode=r.
  // Throws LcmError naming the URL when LCM cannot open it.
  explicit Connection(std::string url = kDefaultUrl);
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  [[nodiscard]] const std::string& url() const { return url_; }

  // Publishes `message` on `channel`; throws LcmError when LCM cannot.
  template <class Message>
  void publish(const std::string& channel, const Message& message) {
    const std::vector<std::uint8_t> bytes = encode(message);
    publish_raw(channel, bytes.data(), bytes.size());
  }

  // Publishes bytes as they are (a bridge, or a test of what receivers do
  // with bad ones); throws LcmError when LCM cannot.
  void publish_raw(const std::string& channel, const void* data, std::size_t size);

  // Calls `handler` with every message on the channels `channel` matches (a
  // regular expression matched against the whole name) that decodes as a
  // Message; counts the others. The subscription lives as long as the
  // connection. Throws LcmError when LCM refuses the pattern.
  template <class Message>
  Subscription<Message>& subscribe(const std::string& channel,
                                   typename Subscription<Message>::Handler handler) {
    auto owned =
        std::make_unique<Subscription<Message>>(channel, std::move(handler), handler_error_);
    Subscription<Message>& subscription = *owned;
    add_subscription(std::move(owned), &Subscription<Message>::on_message, &subscription);
    return subscription;
  }

  // Waits at most `timeout` for one message and dispatches it; true when one
  // was handled, false on time-out (0 ms: only what is already there) or
  // when a signal interrupted the wait (Ctrl-C: the caller checks its flag).
  // Rethrows the first exception a handler threw since the last call; throws
  // LcmError when LCM fails (a file://...?mode=r replay: past its last event).
  bool handle(std::chrono::milliseconds timeout);

  // Messages of every subscription that did not decode.
  [[nodiscard]] std::uint64_t malformed() const;

  // The LCM instance, e.g. for getFileno() in an event loop.
  ::lcm::LCM& lcm() { return lcm_; }

 private:
  void add_subscription(std::unique_ptr<SubscriptionBase> subscription,
                        lcm_msg_handler_t on_message, void* user);

  std::string url_;
  std::vector<std::unique_ptr<SubscriptionBase>> subscriptions_;
  std::exception_ptr handler_error_;
  // Last, so destroyed first: no dispatch can reach a freed subscription.
  ::lcm::LCM lcm_;
};

}  // namespace odoloc::lcm
