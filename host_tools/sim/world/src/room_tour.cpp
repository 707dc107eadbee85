#include "odoloc/world/room_tour.hpp"

#include <cmath>

namespace odoloc::world {

StationPlan RoomTour::station_plan(const Trajectory& robot) const {
  if (!station)
    return {};
  return plan_base_station(*station, acoustics, timing, robot, first_burst_s, duration_s);
}

Schedule RoomTour::schedule(const StationPlan& plan) const {
  if (thamma) {
    const TriggeredTiming& t = thamma->timing;
    const std::size_t n = acoustics.beacons.size();
    const auto cycles =
        static_cast<std::size_t>(std::ceil((duration_s - thamma->first_trigger_s) / t.cycle_s(n)));
    return triggered_schedule(t, n, cycles, thamma->first_trigger_s);
  }
  const auto cycles =
      static_cast<std::size_t>(std::ceil((duration_s - first_burst_s) / timing.cycle_s()));
  Schedule s = kleeman_schedule(timing, cycles, first_burst_s);
  s.emissions.insert(s.emissions.end(), plan.schedule.emissions.begin(),
                     plan.schedule.emissions.end());
  s.sync.insert(s.sync.end(), plan.schedule.sync.begin(), plan.schedule.sync.end());
  return s;
}

}  // namespace odoloc::world
