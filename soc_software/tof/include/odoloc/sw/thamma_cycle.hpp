// Thamma's ranging cycle on the SoC (docs/tof-measurements.md, "Thamma's
// cycle"): the base stations fire in turn, each `repeats` times one period
// apart, every trigger an RF sync edge on the capture unit's sync input,
// then the controller stays silent for cycle_gap_s. The decoder frames the
// cycles on that gap, gives each sync edge its place in the cycle (station
// and repeat, from its time after the cycle's first edge), keeps the
// receivers' events across capture batches, and once a cycle's last
// listening window has been read, measures every station's burst with
// measure_thamma (the boxes' times of flight, four repeats averaged).
//
// A lost sync edge leaves its place empty (measure_thamma says kSyncMissing
// and averages the rest); a lost first edge is found from the later ones'
// places; an edge far from every place is not used. Times are on the robot
// clock (tof::Timebase::edge_time_s from tick 0), as the capture driver's.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <vector>

#include "odoloc/sw/tof_sync_modes.hpp"

namespace odoloc::sw::tof {

struct ThammaSchedule {
  int stations = 4;
  int repeats = 4;           // ThammaConfig::repeats
  double period_s = 0.1;     // trigger to trigger
  double cycle_gap_s = 0.1;  // silence after a cycle's last period
  // An edge further than this from its place is not the controller's.
  double place_tolerance_s = 5e-3;

  // Throws std::invalid_argument naming the first bad field.
  void validate() const;
  [[nodiscard]] double cycle_s() const {
    return stations * repeats * period_s + cycle_gap_s;
  }
};

struct ThammaCycle {
  double time_s = 0;  // the cycle's first place (its first station's first trigger)
  // Per station (index = station): its first place's time, and its burst
  // measured (sync edges of its places that came; kSyncMissing for fewer).
  std::vector<double> station_time_s;
  std::vector<ThammaMeasurement> per_station;
};

class ThammaCycleDecoder {
 public:
  // Validates both (std::invalid_argument); measure.repeats must equal
  // schedule.repeats.
  ThammaCycleDecoder(ThammaConfig measure, ThammaSchedule schedule);

  // Takes the capture driver's next batch (read order); returns the cycles
  // it completed, oldest first. The batches' timebase must not change.
  std::vector<ThammaCycle> push(const CaptureBatch& batch);

  [[nodiscard]] bool framed() const { return start_s_.has_value(); }

 private:
  void keep(const CaptureBatch& batch);
  [[nodiscard]] ThammaCycle measure(double start_s) const;
  void drop_before(Tick tick);

  ThammaConfig measure_;
  ThammaSchedule schedule_;
  std::optional<Timebase> timebase_;
  std::deque<Tick> sync_;                // not yet in a measured cycle
  std::vector<ChannelEvents> channels_;  // kept across batches
  std::vector<Incident> incidents_;
  std::optional<double> start_s_;  // the next cycle's first place, once framed
  double last_edge_s_ = -1e300;
};

}  // namespace odoloc::sw::tof
