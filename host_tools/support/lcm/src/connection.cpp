#include "odoloc/lcm/connection.hpp"

#include <glib.h>

#include <algorithm>
#include <cerrno>

namespace odoloc::lcm {

Connection::Connection(std::string url) : url_(std::move(url)), lcm_(url_) {
  if (lcm_.good())
    return;
  // What usually goes wrong with udpm:// on a host that has no network.
  const bool udpm = url_.rfind("udpm://", 0) == 0;
  throw LcmError("LCM: cannot open '" + url_ + "'" +
                 (udpm ? " (is there a multicast route? docs/lcm.md)" : ""));
}

void Connection::publish_raw(const std::string& channel, const void* data, std::size_t size) {
  if (size > UINT_MAX || lcm_.publish(channel, data, static_cast<unsigned int>(size)) != 0)
    throw LcmError("LCM: cannot publish " + std::to_string(size) + " bytes on " + channel +
                   " to '" + url_ + "'");
}

void Connection::add_subscription(std::unique_ptr<SubscriptionBase> subscription,
                                  lcm_msg_handler_t on_message, void* user) {
  const std::string& channel = subscription->channel();
  // LCM compiles the pattern with GLib as ^pattern$. Compiling it here first
  // gives GLib's reason, and keeps a refused pattern from lcm_subscribe,
  // which leaks memory on one (LCM 1.3.1).
  GError* error = nullptr;
  GRegex* regex = g_regex_new(("^" + channel + "$").c_str(), static_cast<GRegexCompileFlags>(0),
                              static_cast<GRegexMatchFlags>(0), &error);
  if (regex == nullptr) {
    const std::string why = error != nullptr ? error->message : "not a regular expression";
    g_clear_error(&error);
    throw LcmError("LCM: cannot subscribe to '" + channel + "' on '" + url_ + "': " + why);
  }
  g_regex_unref(regex);
  subscriptions_.reserve(subscriptions_.size() + 1);  // LCM must not hold a freed one
  if (lcm_subscribe(lcm_.getUnderlyingLCM(), channel.c_str(), on_message, user) == nullptr)
    throw LcmError("LCM: cannot subscribe to '" + channel + "' on '" + url_ + "'");
  subscriptions_.push_back(std::move(subscription));
}

bool Connection::handle(std::chrono::milliseconds timeout) {
  const auto millis = static_cast<int>(std::min<std::chrono::milliseconds::rep>(
      std::max<std::chrono::milliseconds::rep>(timeout.count(), 0), INT_MAX));
  errno = 0;
  const int handled = lcm_.handleTimeout(millis);
  if (handler_error_)
    std::rethrow_exception(std::exchange(handler_error_, nullptr));
  // A signal (Ctrl-C) that interrupts the wait is no failure: nothing was
  // handled, and the caller looks at its stop flag.
  if (handled < 0 && errno == EINTR)
    return false;
  if (handled < 0)
    throw LcmError("LCM: error while waiting for messages on '" + url_ + "'");
  return handled > 0;
}

std::uint64_t Connection::malformed() const {
  std::uint64_t total = 0;
  for (const std::unique_ptr<SubscriptionBase>& subscription : subscriptions_)
    total += subscription->malformed();
  return total;
}

}  // namespace odoloc::lcm
