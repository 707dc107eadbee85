#include "odoloc/sweep/jobs.hpp"

#include <fmt/format.h>

#include <optional>

#include "odoloc/sweep/error.hpp"
#include "odoloc/yaml/reader.hpp"

namespace odoloc::sweep {

Shard parse_shard(std::string_view text) {
  const auto fail = [&](std::string_view why) {
    throw SweepError(true, fmt::format("--shard: '{}': {}", text.substr(0, 40), why));
  };
  const std::size_t slash = text.find('/');
  if (slash == std::string_view::npos)
    fail("expected K/N, shard K of N (e.g. 2/4)");
  const std::optional<std::uint64_t> k = yaml::whole_number(text.substr(0, slash));
  const std::optional<std::uint64_t> n = yaml::whole_number(text.substr(slash + 1));
  if (!k || !n)
    fail("K and N are whole numbers (e.g. 2/4)");
  if (*n < 1 || *n > kMaxShards)
    fail(fmt::format("N counts the shards, 1 to {}", kMaxShards));
  if (*k < 1 || *k > *n)
    fail(fmt::format("K counts from 1 to N ({})", *n));
  return {*k, *n};
}

}  // namespace odoloc::sweep
