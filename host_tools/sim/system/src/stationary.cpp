#include "odoloc/sim/stationary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace odoloc::sim {

Scenario standing_at(const Scenario& scenario, world::Vec2 point, std::size_t fixes) {
  Scenario s = scenario;
  s.stationary.reset();
  world::RoomTour& tour = s.tour;
  tour.drive.start = {point.x_m, point.y_m, 0};
  const double cycles = std::ceil(1.25 * static_cast<double>(fixes)) + 5;
  tour.duration_s = tour.first_burst_s + cycles * tour.timing.cycle_s();
  tour.drive.path.segments = {world::Segment::duration(0, 0, tour.duration_s)};
  tour.drive.disturbances = {};
  return s;
}

Standing measure_standing(const Scenario& scenario, world::Vec2 point, std::size_t fixes,
                          const SystemOptions& options) {
  LocalisationSystem system(standing_at(scenario, point, fixes), options);
  Standing out;
  out.truth = point;
  while (!system.done() && out.fixes.size() < fixes) {
    const Frame f = system.step();
    for (const sw::CycleResult& c : f.soc.cycles) {
      ++out.cycles;
      if (c.fix.valid && out.fixes.size() < fixes)
        out.fixes.push_back({c.fix.position_m.x, c.fix.position_m.y});
    }
  }
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (out.fixes.empty()) {
    out.mean_m = {kNaN, kNaN};
    out.sd_m = {kNaN, kNaN};
    out.worst_m = kNaN;
    return out;
  }
  const double n = static_cast<double>(out.fixes.size());
  for (const world::Vec2& p : out.fixes) {
    out.mean_m.x_m += p.x_m / n;
    out.mean_m.y_m += p.y_m / n;
    out.worst_m = std::max(out.worst_m, std::hypot(p.x_m - point.x_m, p.y_m - point.y_m));
  }
  double sxx = 0, syy = 0;
  for (const world::Vec2& p : out.fixes) {
    sxx += (p.x_m - out.mean_m.x_m) * (p.x_m - out.mean_m.x_m);
    syy += (p.y_m - out.mean_m.y_m) * (p.y_m - out.mean_m.y_m);
  }
  out.sd_m = out.fixes.size() > 1 ? world::Vec2{std::sqrt(sxx / (n - 1)), std::sqrt(syy / (n - 1))}
                                  : world::Vec2{kNaN, kNaN};
  return out;
}

}  // namespace odoloc::sim
