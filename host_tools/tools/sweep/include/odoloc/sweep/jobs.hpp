// Seeds and shards (docs/sweep.md#seeds-and-shards). Job j of a spec is
// trial j % trials of point j / trials; its seed depends on the spec's seed,
// the point and the trial only, never on how the jobs are split, so any
// sharding gives the same results.
#pragma once

#include <cstdint>
#include <string_view>

namespace odoloc::sweep {

// SplitMix64's output function (Steele, Lea and Flood 2014; Vigna's
// splitmix64.c): the first number a SplitMix64 generator seeded with x
// returns. z = x + 0x9e3779b97f4a7c15; z = (z ^ z >> 30) * 0xbf58476d1ce4e5b9;
// z = (z ^ z >> 27) * 0x94d049bb133111eb; z ^ z >> 31 (modulo 2^64).
[[nodiscard]] constexpr std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9e3779b97f4a7c15U;
  z = (z ^ (z >> 30U)) * 0xbf58476d1ce4e5b9U;
  z = (z ^ (z >> 27U)) * 0x94d049bb133111ebU;
  return z ^ (z >> 31U);
}

// splitmix64(splitmix64(splitmix64(spec_seed) + point) + trial), modulo 2^64.
[[nodiscard]] constexpr std::uint64_t job_seed(std::uint64_t spec_seed, std::uint64_t point,
                                               std::uint64_t trial) {
  return splitmix64(splitmix64(splitmix64(spec_seed) + point) + trial);
}

// Shard K of N (1 <= K <= N) runs the jobs j with j % N == K - 1: every job
// is in exactly one shard, and the shards' sizes differ by at most one.
struct Shard {
  std::uint64_t k = 1;
  std::uint64_t n = 1;

  [[nodiscard]] bool owns(std::uint64_t job) const { return job % n == k - 1; }
  // How many of `jobs` jobs (0 .. jobs - 1) it runs.
  [[nodiscard]] std::uint64_t size(std::uint64_t jobs) const {
    return jobs / n + (jobs % n > k - 1 ? 1 : 0);
  }
  bool operator==(const Shard&) const = default;
};

// The most shards one run may have.
inline constexpr std::uint64_t kMaxShards = 1'000'000;

// "K/N" in decimal, 1 <= K <= N <= kMaxShards. Throws SweepError (usage)
// saying what is wrong with it ("--shard: '0/4': K counts from 1 to N").
[[nodiscard]] Shard parse_shard(std::string_view text);

}  // namespace odoloc::sweep
