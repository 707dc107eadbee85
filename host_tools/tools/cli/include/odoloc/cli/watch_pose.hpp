// `odoloc watch pose`: prints the pose estimates a simulator (or a robot)
// publishes on LCM, one line each (docs/host-tool.md, "watch pose").
#pragma once

#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>

#include "odoloc/lcm/channels.hpp"

namespace odoloc::cli {

struct WatchPoseCommand {
  // A pose_estimate_t source: fused, odometry, rear, front (each on its
  // channel ODOLOC_POSE_<SOURCE>), truth (ODOLOC_TRUTH), or all of them.
  std::string source = "fused";
  std::uint64_t count = 0;  // estimates to print; 0: until Ctrl-C
  std::string url = lcm::kDefaultUrl;
};

// `text` when it is one of the sources above; UsageError listing them otherwise.
[[nodiscard]] std::string parse_pose_source(std::string_view text);

// Listens on `cmd.url` and prints every estimate of the source as it comes:
// text columns (with a header before the first line), or with `json` one
// JSON object per line. Messages that do not decode are skipped silently.
// Returns after `cmd.count` estimates; throws Interrupted when `stop` is set
// (checked every 10 ms), UsageError when LCM cannot open the URL.
void run_watch_pose(const WatchPoseCommand& cmd, std::ostream& out, bool json,
                    const std::atomic<bool>* stop);

}  // namespace odoloc::cli
