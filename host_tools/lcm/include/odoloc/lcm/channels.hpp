// The LCM channels of odoloc and the default LCM URL, in one place
// (docs/lcm.md lists each channel's message type and rate).
#pragma once

namespace odoloc::lcm {

// UDP multicast with ttl=0: the packets never leave the host.
inline constexpr char kDefaultUrl[] = "udpm://239.255.76.67:7667?ttl=0";

namespace channel {

inline constexpr char kEncoders[] = "ODOLOC_ENCODERS";  // encoder_state_t, 10 Hz
inline constexpr char kOdometry[] = "ODOLOC_ODOMETRY";  // odometry_increment_t, 100 Hz
inline constexpr char kTof[] = "ODOLOC_TOF";            // tof_measurement_set_t, per cycle
inline constexpr char kFix[] = "ODOLOC_FIX";            // beacon_fix_t, per cycle
inline constexpr char kStation[] = "ODOLOC_STATION";    // station_measurement_t, per measurement
inline constexpr char kPose[] = "ODOLOC_POSE";          // pose_estimate_t, 100 Hz
inline constexpr char kTruth[] = "ODOLOC_TRUTH";        // pose_estimate_t, 100 Hz (simulator)
inline constexpr char kRegRequest[] = "ODOLOC_REG_REQUEST";    // register_request_t
inline constexpr char kRegResponse[] = "ODOLOC_REG_RESPONSE";  // register_response_t
inline constexpr char kSimStatus[] = "ODOLOC_SIM_STATUS";      // sim_status_t, 1 Hz

}  // namespace channel

}  // namespace odoloc::lcm
