// The SoC's localisation loop (docs/simulator.md, "The SoC loop"):
// the odometry driver, the time-of-flight capture driver, Kleeman's beacon
// cycle decoder, the multilateration solver and the pose EKF, run together
// over one sw::RegisterBus. The same code drives the simulated board and a
// real one.
//
// Time: seconds on the robot clock, the capture unit's timestamp counter
// (tof.timestamp, unwrapped by the capture driver) from where the driver
// started counting; every output is stamped on it.
//
// Each step():
//   1. reads the fabric's odometry snapshot and the timestamp, and predicts
//      the filter with the increment since the last step's snapshot
//      (fuse::increment_between);
//   2. every capture_period_s, drains the capture unit and hands the batch
//      to the decoder (a beacon cycle lasts 0.9 s: the FIFOs need no more);
//   3. for each beacon cycle the batch completed: a fix from all beacons
//      (locate::multilaterate, the robust Gauss-Newton with the offset) and
//      a heading from the directions of arrival (locate::beacon_heading),
//      then
//        - before the filter has a pose: the first valid fix with a valid
//          heading initialises it at the fix's time, and the odometry since
//          then is replayed onto it;
//        - after: the cycle's ranges as one fuse::RangeSet at the time of
//          beacon 0's arrival, each range with the robot's motion (from the
//          odometry kept) between that time and its own capture, fused late
//          (the filter replays its history).
//   4. with Liu's base station (base_station.hpp): the sync input's rising
//      edges of the batch, paired in order with the RF link's packets,
//      time them: alpha and beta are fused as bearings at their packet's
//      time; a ranging packet's burst is listened for t0 after it
//      (burst_listener.hpp), and its range (Liu eq. 14.8) fused at its
//      arrival. Before the filter has a pose they are dropped. With
//      liu_filter, Liu's own filter (liu_filter.hpp) runs beside: the
//      same odometry, a fix from each alpha and the range that follows it
//      (eqs. 14.9, 14.10), a heading from each beta (eqs. 14.17-14.19).
// The robot is expected to stand still for the first fix (a cycle of
// Kleeman's six beacons lasts 0.9 s: a moving robot's fix is smeared along
// its path; the filter's motion-compensated ranges are not). Placed on a
// surveyed mark (start_covariance), it starts from there instead; without
// beacons (a lawn with Liu's station alone) it must.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "odoloc/sw/base_station.hpp"
#include "odoloc/sw/beacon_cycle.hpp"
#include "odoloc/sw/beacon_fix.hpp"
#include "odoloc/sw/beacon_heading.hpp"
#include "odoloc/sw/burst_listener.hpp"
#include "odoloc/sw/liu_filter.hpp"
#include "odoloc/sw/multilateration.hpp"
#include "odoloc/sw/odometry_driver.hpp"
#include "odoloc/sw/pose_ekf.hpp"
#include "odoloc/sw/register_bus.hpp"
#include "odoloc/sw/thamma_cycle.hpp"
#include "odoloc/sw/thamma_pose.hpp"
#include "odoloc/sw/tof_capture_driver.hpp"

namespace odoloc::sw {

struct LocaliserConfig {
  // The odometry fabric (OdometryDriver::configure) and the pose it starts
  // from (x m, y m, theta rad: where the robot is docked; only the
  // odometry's own track starts there, the filter waits for a fix).
  VehicleGeometry vehicle;
  MinSelectSetup min_select;
  std::uint16_t update_clocks = 5000;  // 100 us
  OdometryPolicy policy = OdometryPolicy::kPerComponent;
  fuse::Vector3 start_pose = fuse::Vector3::Zero();
  // Set: the robot stands on a surveyed mark at start_pose, and the filter
  // starts there at the first step with this covariance (Liu's X(0|0) and
  // P(0|0)) instead of waiting for a beacon fix. Required without beacons.
  std::optional<fuse::Matrix3> start_covariance;

  // Ultrasonic capture and Kleeman's beacons. kleeman.timebase is replaced
  // by the capture driver's. kleeman.schedule.beacons = 0 (and an empty
  // layout): no beacons, the base station alone; the receivers' array,
  // envelope, speed of sound, timing noise and min_receivers still serve
  // its bursts.
  tof::CaptureSetup capture;
  double capture_period_s = 0.05;  // between drains of the capture unit's FIFOs
  tof::KleemanConfig kleeman;
  locate::BeaconLayout layout;
  locate::MultilaterationOptions multilateration;
  locate::HeadingOptions heading;

  // Fusion. A range's standard deviation given to the filter is the
  // decoder's (timing noise) combined with chain_sd_m (the capture chain's
  // residual error: rise-time compensation, quantisation) and with the
  // odometry's along-track error over the range's motion.
  fuse::EkfOptions ekf;
  double chain_sd_m = 0.002;
  // false: the beacons only initialise the filter (then the base station
  // alone corrects the odometry).
  bool fuse_beacon_ranges = true;

  // Liu's base station: needs capture.sync_enable (the RF packets' strobes)
  // and, with beacons, kleeman.schedule.reserved_slots >= 1 (its bursts
  // go there), and a station::Link given to the Localiser.
  std::optional<station::StationConfig> station;
  // Liu et al.'s own filter beside the EKF (needs the station).
  std::optional<fuse::LiuFilterOptions> liu_filter;

  // Thamma's RF-triggered stations and the head and tail boxes: each
  // cycle's ranges (thamma_cycle.hpp) give the boxes' fixes and the pose
  // (thamma_pose.hpp); the first valid pose initialises the filter, the
  // later ones are fused as two body points, each at its stations' time.
  // Needs capture.sync_enable (the triggers); excludes beacons and the base
  // station (the sync input is the stations').
  struct Thamma {
    tof::ThammaConfig measure;
    tof::ThammaSchedule schedule;
    locate::BeaconLayout stations;  // index = the station's place in the cycle
    locate::ThammaBody body;
    locate::ThammaPoseOptions pose;
  };
  std::optional<Thamma> thamma;

  // Throws std::invalid_argument naming the first bad field.
  void validate() const;
};

// One beacon cycle and what the loop made of it.
struct CycleResult {
  tof::CycleMeasurement measurement;
  double time_s = 0;  // the fix's time: the mean capture time of the used ranges
  locate::Fix fix;
  locate::Heading heading;
  // What the filter did with the cycle's ranges: kNotInitialised before the
  // first pose (or with fuse_beacon_ranges off), kAccepted when this
  // cycle's fix initialised it, kAmbiguous when the fix was refused as
  // ambiguous (the ranges are not fused).
  fuse::Outcome fused = fuse::Outcome::kNotInitialised;
};

// One base-station measurement and what the filter did with it.
struct StationUpdate {
  // Its capture time on the robot clock: the packet's sync edge (bearings)
  // or the burst's arrival at the robot origin (a range).
  double time_s = 0;
  fuse::Measurement measurement;  // StationBearing, RobotBearing or StationRange
  fuse::Outcome fused = fuse::Outcome::kNotInitialised;
};

// One of Thamma's cycles and what the loop made of it.
struct ThammaResult {
  tof::ThammaCycle cycle;
  locate::ThammaPose pose;
  double time_s = 0;  // the pose's: the middle of the cycle's stations (the ranges
                      // moved there by the odometry)
  // The head and tail points' updates (kNotInitialised before the first
  // pose; the cycle that initialised the filter: kAccepted for both).
  fuse::Outcome head = fuse::Outcome::kNotInitialised;
  fuse::Outcome tail = fuse::Outcome::kNotInitialised;
};

struct LocaliserStep {
  double time_s = 0;  // the timestamp read with the odometry snapshot
  FabricOdometry odometry;
  // The fabric's motion since the previous step (the first step: since the
  // fabric's pose was loaded with config.start_pose), robot frame at the
  // previous pose: dx m, dy m, dtheta rad (fuse::increment_between), as the
  // filter predicts with it.
  fuse::Vector3 increment = fuse::Vector3::Zero();
  std::optional<tof::CaptureBatch> batch;  // when this step drained the capture unit
  std::vector<CycleResult> cycles;         // the cycles this step's batch completed
  std::vector<StationUpdate> station;      // the base station's measurements this step made
  std::vector<ThammaResult> thamma;        // Thamma's cycles this step's batch completed
  fuse::Estimate estimate;                 // at time_s (not initialised before the first fix)
  std::optional<fuse::LiuEstimate> liu;    // Liu's filter at time_s, when configured
};

class Localiser {
 public:
  // Configures the fabric's odometry and capture unit over `bus` (which
  // must outlive the localiser) and arms the enabled channels. `link`
  // (which must outlive the localiser too) brings the base station's
  // packets; it is required with config.station. Throws
  // std::invalid_argument for a bad configuration or a missing link,
  // BusError when the bus fails, std::runtime_error when the capture unit
  // is absent.
  Localiser(RegisterBus& bus, const LocaliserConfig& config, station::Link* link = nullptr);

  // One pass of the loop (see the top of this file). Call it at least every
  // 85 s (the capture driver's unwrapping) and often enough for the
  // odometry's increments to stay straight enough for the filter (100 Hz).
  LocaliserStep step();

  [[nodiscard]] const fuse::PoseEkf& filter() const { return ekf_; }
  // Liu's filter; nullptr unless config.liu_filter.
  [[nodiscard]] const fuse::LiuFilter* liu_filter() const { return liu_ ? &*liu_ : nullptr; }
  [[nodiscard]] const LocaliserConfig& config() const { return config_; }
  // The capture unit's tick duration and latency.
  [[nodiscard]] const tof::Timebase& timebase() const { return capture_.timebase(); }

 private:
  struct OdometrySample {
    double time_s;
    fuse::Pose pose;
  };
  [[nodiscard]] double now_s();
  // The fabric's pose at time_s, interpolated between the samples kept
  // (clamped to the oldest and the newest).
  [[nodiscard]] fuse::Pose odometry_at(double time_s) const;
  void process(CycleResult& cycle);
  void initialise_from(const CycleResult& cycle);
  // The filter starts at time_s (in the past) and the odometry kept since
  // is replayed onto it.
  void initialise_at(double time_s, const fuse::Pose& pose, const fuse::Matrix3& covariance);
  void process(ThammaResult& result);
  // Liu's filter starts where the EKF first has a pose.
  void start_liu_filter();
  [[nodiscard]] fuse::RangeSet motion_compensated(const tof::CycleMeasurement& cycle) const;
  // Pairs the batch's sync edges with the link's packets (base_station.hpp).
  void take_packets(const tof::CaptureBatch& batch, LocaliserStep& out);
  // The ranges of the pending ranging packets whose bursts have been read.
  void take_ranges(LocaliserStep& out);
  void fuse_station(StationUpdate update, LocaliserStep& out);
  // Liu's fix from the range of the ranging packet at ranging_s, which
  // arrived at arrival_s, and the alpha that asked for it.
  void fuse_liu_fix(double ranging_s, double arrival_s, const fuse::StationRange& range);

  LocaliserConfig config_;
  OdometryDriver odometry_;
  tof::CaptureDriver capture_;
  std::optional<tof::BeaconCycleDecoder> decoder_;  // with beacons
  std::optional<tof::ThammaCycleDecoder> thamma_;   // with Thamma's stations
  fuse::PoseEkf ekf_;
  std::optional<fuse::LiuFilter> liu_;
  std::deque<OdometrySample> track_;  // the fabric's poses of the last steps
  double last_drain_s_ = -1;          // robot-clock time of the last capture drain
  station::Link* link_;
  station::PacketTimer packets_;
  std::optional<station::BurstListener> listener_;  // with the station
  std::deque<double> rangings_;                     // ranging packets' times, bursts not yet taken
  struct Alpha {
    double time_s;
    double bearing_rad;
  };
  std::deque<Alpha> alphas_;  // with Liu's filter: not yet paired with a range
};

}  // namespace odoloc::sw
