// The LCM channels of odoloc and the default LCM URL, in one place
// (docs/lcm.md lists each channel's message type and rate).
#pragma once

#include <array>
#include <string_view>

namespace odoloc::lcm {

// UDP multicast with ttl=0: the packets never leave the host.
inline constexpr char kDefaultUrl[] = "udpm://239.255.76.67:7667?ttl=0";

namespace channel {

inline constexpr char kEncoders[] = "ODOLOC_ENCODERS";  // encoder_state_t, 10 Hz
inline constexpr char kOdometry[] = "ODOLOC_ODOMETRY";  // odometry_increment_t, 100 Hz
inline constexpr char kTof[] = "ODOLOC_TOF";            // tof_measurement_set_t, per cycle
inline constexpr char kFix[] = "ODOLOC_FIX";            // beacon_fix_t, per cycle
inline constexpr char kStation[] = "ODOLOC_STATION";    // station_measurement_t, per measurement
// pose_estimate_t, 100 Hz each: one channel per estimator (LCM's
// convention: a channel is one stream), ODOLOC_POSE_<SOURCE>.
inline constexpr char kPoseFused[] = "ODOLOC_POSE_FUSED";        // the EKF
inline constexpr char kPoseOdometry[] = "ODOLOC_POSE_ODOMETRY";  // the fabric (min-select)
inline constexpr char kPoseRear[] = "ODOLOC_POSE_REAR";          // rear-only (simulator)
inline constexpr char kPoseFront[] = "ODOLOC_POSE_FRONT";        // front-only (simulator)
inline constexpr char kPoseLiu[] = "ODOLOC_POSE_LIU";  // Liu et al.'s filter, where it runs
inline constexpr std::string_view kPosePrefix = "ODOLOC_POSE_";
// LCM subscriptions take a regular expression: every pose channel.
inline constexpr char kPoseAny[] = "ODOLOC_POSE_.*";
inline constexpr char kTruth[] = "ODOLOC_TRUTH";             // pose_estimate_t, 100 Hz (simulator)
inline constexpr char kRegRequest[] = "ODOLOC_REG_REQUEST";  // register_request_t
inline constexpr char kRegResponse[] = "ODOLOC_REG_RESPONSE";  // register_response_t
inline constexpr char kSimStatus[] = "ODOLOC_SIM_STATUS";      // sim_status_t, 1 Hz

// A pose channel and the pose_estimate_t.source its messages carry.
struct PoseStream {
  const char* channel;
  std::string_view source;
};
inline constexpr std::array<PoseStream, 5> kPoseStreams{{{kPoseFused, "fused"},
                                                         {kPoseOdometry, "odometry"},
                                                         {kPoseRear, "rear"},
                                                         {kPoseFront, "front"},
                                                         {kPoseLiu, "liu"}}};

// The channel of a pose source ("fused" -> ODOLOC_POSE_FUSED), nullptr for
// a name that is none of them.
constexpr const char* pose_channel(std::string_view source) {
  for (const PoseStream& stream : kPoseStreams)
    if (stream.source == source)
      return stream.channel;
  return nullptr;
}

}  // namespace channel

}  // namespace odoloc::lcm
