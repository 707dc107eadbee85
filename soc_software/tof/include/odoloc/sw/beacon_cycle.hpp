// Kleeman's beacon cycle on the SoC: from the capture driver's envelope
// events to per-cycle measurement sets (docs/tof-measurements.md).
//
// The beacons fire in strict sequence, one every t_fire; beacon 0 sends a
// double pulse (two bursts t_double apart, start to start). The decoder
//   1. turns each pulse into an arrival time at its receiver: the rise on the
//      robot clock minus the rise-time compensation from its width
//      (tof_envelope.hpp);
//   2. groups the pulses of one wavefront across the receivers (times within
//      |r_i - r_j|/c plus a margin of each other) and fits a plane wave
//      (tof_doa.hpp): direction of arrival and time at the robot origin;
//   3. searches the double pulse (two wavefronts t_double apart from the same
//      direction with the same amplitude), confirms it one cycle later and
//      locks: the anchor of each cycle is beacon 0's first arrival, slot k
//      starts at anchor + k t_fire;
//   4. per slot keeps every wavefront as a candidate (direct and echoes),
//      rejects the ones earlier than the beacon could produce (Kleeman 4.3:
//      a pulse can only arrive late), and flags what looks wrong;
//   5. while locked, expects the next double pulse one cycle later (within
//      the robot's possible motion); missing, it coasts up to
//      max_coast_cycles on the predicted anchor, then drops the lock and
//      searches; found elsewhere, it drops the lock at once.
// Every record the decoder emits says which of these happened.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "odoloc/sw/tof_doa.hpp"
#include "odoloc/sw/tof_envelope.hpp"
#include "odoloc/sw/tof_measurement.hpp"

namespace odoloc::sw::tof {

// The beacon controller's timing (Kleeman section 2).
struct BeaconSchedule {
  int beacons = 6;
  // t_fire: 2^16 ticks of the controller's timer, "approximately 150 ms"
  // (2^16 x 20 / 9.11 MHz = 143.9 ms on the paper's 64180; 163.8 ms with a
  // 2.5 us timer). Set it to the controller's real value: an error of delta
  // shifts beacon k's distance by k delta c (not a common offset).
  double fire_period_s = 0.150;
  // t_pulse: burst length (also EnvelopeModel::burst_s).
  double pulse_s = 2.5e-3;
  // t_double: beacon 0's second burst starts this long after its first
  // (start to start: the receiver times rises; Kleeman's "separation ...
  // slightly larger" than the pulse leaves a 3 ms gap).
  double double_spacing_s = 5.5e-3;
  // Slots after the last beacon's in which no beacon fires: a base
  // station's ranging burst goes there (docs/fusion.md, "Liu's base
  // station"), out of the beacons' way. What arrives in them is reported in
  // CycleMeasurement::reserved, not taken for a beacon.
  int reserved_slots = 0;

  // The cycle: (beacons + reserved_slots) t_fire.
  [[nodiscard]] double cycle_s() const { return (beacons + reserved_slots) * fire_period_s; }
};

struct KleemanConfig {
  BeaconSchedule schedule;
  ReceiverArray array = ReceiverArray::polygon(8, 0.05);
  EnvelopeModel envelope;  // burst_s should equal schedule.pulse_s
  Timebase timebase;       // batches must carry this one (std::invalid_argument otherwise)
  double speed_of_sound_mps = 343.2;  // 20 C dry air: 331.3 sqrt(1 + 20/273.15)

  // Longest direct path (the room's diagonal) and, optionally, the beacons'
  // positions (world frame, index = beacon). With positions, a slot accepts
  // arrivals from anchor + k t_fire - (|b0 bk| + geometry_tolerance_m)/c on
  // (Kleeman's triangle inequality |Pb0| - |Pbk| <= |b0 bk|); without, from
  // anchor + k t_fire - max_range_m/c.
  double max_range_m = 15.0;
  std::vector<Vec2> beacon_positions;
  double geometry_tolerance_m = 0.3;
  // Slots are separated max_range/c + early_guard before their nominal
  // start; what falls between the separation and the acceptance start is
  // early-rejected.
  double early_guard_s = 5e-3;

  // Robot speed bound: how far beacon 0's double pulse can move from one
  // cycle to the next (with clock_tolerance_ppm of the two clocks), and how
  // much later than in the last cycle a direct arrival may come before it is
  // occluded-suspect.
  double max_speed_mps = 1.5;
  double clock_tolerance_ppm = 200;

  // Timing noise per receiver besides the tick quantisation (turbulence,
  // threshold noise, compensation model error).
  double timing_sd_s = 1e-6;
  // Slack on the pairwise grouping bound |t_i - t_j| <= |r_i - r_j|/c.
  double group_margin_s = 60e-6;
  // The double pulse's second wavefront must come t_double +- this after the
  // first, from within double_bearing_tolerance_rad of the same direction
  // (when both have one) and with amplitudes within a factor
  // double_amplitude_tolerance on a receiver both heard.
  double double_tolerance_s = 150e-6;
  double double_bearing_tolerance_rad = 0.5;
  double double_amplitude_tolerance = 2.0;

  // Pulses narrower than min_width_s are noise (dropped, counted, kNoise);
  // wider than stuck_width_s (or saturated) a stuck comparator.
  double min_width_s = 0.25e-3;
  double stuck_width_s = 0.05;
  // A first arrival below weak_ratio (A/V) with a later candidate
  // occlusion_contrast times stronger is occluded-suspect.
  double weak_ratio = 1.5;
  double occlusion_contrast = 4.0;
  // A channel facing within expect_half_angle_rad of an arrival at least
  // strong_ratio strong, silent all cycle, is reported dead.
  double expect_half_angle_rad = 0.4;
  double strong_ratio = 3.0;
  int min_receivers = 2;  // for a primary candidate
  // After a beacon's first arrival jumped later than the robot's motion
  // allows, it stays occluded-suspect until it jumps back earlier, or for
  // this many cycles (then the later track is taken as the direct path).
  int occlusion_memory_cycles = 10;

  int max_coast_cycles = 1;  // cycles decoded on a predicted anchor before the lock is dropped
  int confirm_cycles = 1;    // further double pulses one cycle apart needed to lock

  // Throws std::invalid_argument naming the first bad field: non-finite or
  // out-of-range values, a double pulse that overlaps itself or a slot too
  // short for the range and guard, beacon positions that do not match.
  void validate() const;

  // How far the double pulse may move between consecutive cycles.
  [[nodiscard]] double lock_tolerance_s() const;
};

class BeaconCycleDecoder {
 public:
  enum class State : std::uint8_t { kSearching, kLocked };

  // Validates the configuration (std::invalid_argument).
  explicit BeaconCycleDecoder(KleemanConfig config);

  // Takes the driver's next batch; returns the records of every cycle the
  // batch completed, oldest first (possibly none). Batches must come in read
  // order with the configured timebase (std::invalid_argument otherwise);
  // the events in them are checked, not trusted: out of order, too late,
  // malformed events are dropped and flagged.
  std::vector<CycleMeasurement> push(const CaptureBatch& batch);

  // The beacon controller's t_fire as measured on the robot clock (by a
  // solver, from cycle_period_s and its positions): used from the next cycle
  // on. Validated like the configuration (std::invalid_argument).
  void set_fire_period(double seconds);

  [[nodiscard]] State state() const { return state_; }
  [[nodiscard]] const KleemanConfig& config() const { return config_; }
  // Forgets everything: searching again, sequence from 0.
  void reset();

 private:
  struct Pulse {
    int channel = 0;
    Tick rise = 0;
    std::uint32_t width = 0;
    double time_s = 0;  // compensated arrival at the receiver, seconds after origin_
    double sd_s = 0;
    EnvelopeModel::Inverse comp;
  };
  struct Span {  // an incident in seconds after origin_
    IncidentKind kind;
    int channel;
    double from_s, until_s;
  };
  struct Group {
    std::vector<std::size_t> pulses;  // indices into the working vector
    Arrival arrival;                  // times relative to origin_ until placed in a slot
    double t0_s = 0;
  };

  [[nodiscard]] double tick_time(Tick t) const;
  void ingest(const CaptureBatch& batch);
  std::vector<Group> build_groups(double from_s, double until_s) const;
  Arrival make_arrival(const std::vector<std::size_t>& members, double& t0) const;
  [[nodiscard]] bool is_double(const Group& first, const Group& second) const;
  // The earliest double pulse whose first wavefront starts in [from, until).
  [[nodiscard]] const Group* find_double(const std::vector<Group>& groups, double from_s,
                                         double until_s) const;
  bool try_lock();
  bool try_cycle(std::vector<CycleMeasurement>& out);
  // One cycle's record from its wavefronts, in named steps.
  CycleMeasurement decode_cycle(std::vector<Group>& groups, double anchor, Flags cycle_flags,
                                bool measured);
  [[nodiscard]] std::vector<double> slot_bounds(double anchor) const;
  [[nodiscard]] double reserved_start(double anchor) const;
  [[nodiscard]] std::vector<double> beacon_reach() const;
  void assign_to_slots(std::vector<Group>& groups, double anchor, const std::vector<double>& part,
                       const std::vector<double>& reach, CycleMeasurement& rec) const;
  void check_reference(CycleMeasurement& rec, Flags& cycle_flags) const;
  void classify_beacon(BeaconMeasurement& b, std::size_t k, double from_s, double until_s,
                       double reach_m, Flags cycle_flags, double anchor, bool measured);
  void track_occlusion(std::size_t k, const Arrival& p, Flags& f, double anchor);
  void channel_status(CycleMeasurement& rec, double from_s, double end) const;
  CycleMeasurement empty_record(double anchor, Flags flags);
  [[nodiscard]] Flags incident_flags(double from_s, double until_s, int channel) const;
  void drop_before(double t_s);
  [[nodiscard]] double cycle_s() const;
  [[nodiscard]] double cycle_end(double anchor) const;

  static constexpr double kInf = std::numeric_limits<double>::infinity();
  KleemanConfig config_;
  double c_;
  double single_half_angle_ = 0;
  State state_ = State::kSearching;
  bool have_origin_ = false;
  Tick origin_ = 0;
  Tick last_read_ = 0;
  double horizon_s_ = -kInf;         // pulses rising before are complete
  double consumed_s_ = -kInf;        // time already decoded (or skipped)
  double dropped_before_s_ = -kInf;  // pulses before this are gone
  std::vector<Pulse> pulses_;        // not yet decoded, sorted by time
  std::vector<Span> spans_;
  std::vector<Tick> last_rise_;  // per channel
  struct Mark {                  // a dropped pulse: noise, or a saturated width
    int channel;
    double time_s;
  };
  std::vector<Mark> noise_, saturated_;
  int dropped_pending_ = 0;
  double anchor_pred_ = 0;
  double last_measured_anchor_ = std::numeric_limits<double>::quiet_NaN();
  int coast_ = 0;
  bool resync_pending_ = false;
  std::uint64_t sequence_ = 0, epoch_ = 0;
  struct Track {
    bool valid = false;  // a clean primary seen
    double distance_m = 0, anchor_s = 0;
    bool occluded = false;  // the primary jumped later than motion allows
    double last_m = 0, last_anchor_s = 0;
    int occluded_cycles = 0;
  };
  std::vector<Track> track_;  // per beacon, the last clean primary
};

}  // namespace odoloc::sw::tof
