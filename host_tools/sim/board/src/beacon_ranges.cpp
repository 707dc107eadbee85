#include "odoloc/board/beacon_ranges.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>

#include "odoloc/world/acoustic_systems.hpp"

namespace odoloc::board {

namespace loc = sw::locate;

loc::BeaconLayout beacon_layout(const world::AcousticWorld& world, std::size_t count) {
  loc::BeaconLayout layout;
  for (const world::Beacon& b :
       std::span(world.beacons).first(std::min(count, world.beacons.size())))
    layout.beacons.push_back({{b.position.x_m, b.position.y_m}, world.height_m});
  return layout;
}

sw::tof::KleemanConfig kleeman_config(const world::KleemanTiming& timing,
                                      std::span<const world::Vec2> beacons, double envelope_tau_s,
                                      double speed_of_sound_mps) {
  sw::tof::KleemanConfig config;
  config.schedule.beacons = static_cast<int>(timing.beacon_count);
  config.schedule.fire_period_s = timing.fire_s();
  config.schedule.pulse_s = timing.pulse_s;
  config.schedule.double_spacing_s = timing.double_pulse_s;
  config.schedule.reserved_slots = static_cast<int>(timing.reserved_slots);
  config.envelope.rise_s = envelope_tau_s;
  config.envelope.fall_s = envelope_tau_s;
  config.envelope.burst_s = timing.pulse_s;
  config.speed_of_sound_mps = speed_of_sound_mps;
  for (const world::Vec2& b : beacons.first(std::min(timing.beacon_count, beacons.size())))
    config.beacon_positions.push_back({b.x_m, b.y_m});
  return config;
}

sw::tof::KleemanConfig kleeman_config(const world::AcousticWorld& world,
                                      const world::KleemanTiming& timing) {
  std::vector<world::Vec2> positions;
  for (const world::Beacon& b : world.beacons)
    positions.push_back(b.position);
  return kleeman_config(timing, positions, world.beacons.at(0).envelope_tau_s,
                        world.air.speed_of_sound_mps());
}

MeasuredCycle measure_kleeman_cycle(const world::AcousticWorld& world, const world::Pose& pose,
                                    double c_used_mps, double offset_m, double chain_sd_m,
                                    std::uint64_t world_seed,
                                    const std::function<double()>& chain_error_m) {
  const double c = world.air.speed_of_sound_mps();
  world::KleemanTiming timing;
  timing.beacon_count = world.beacons.size();
  const world::Schedule schedule = world::kleeman_schedule(timing, 1, 0.01);
  const world::AcousticRun run = world::simulate(world, schedule, world::stationary(pose),
                                                 0.01 + timing.cycle_s(), world_seed);
  const double path_jitter_s = world.noise.path_jitter_sd_s;
  const double receiver_jitter_s = world.noise.receiver_jitter_sd_s;
  MeasuredCycle out;
  out.ranges.speed_of_sound_mps = c_used_mps;
  out.ranges.beacons.resize(world.beacons.size());
  std::vector<bool> seen(world.beacons.size(), false);
  for (const world::EmissionRecord& e : run.emissions) {
    const std::size_t b = e.emission.beacon;
    if (seen[b])
      continue;  // beacon 0's second pulse
    seen[b] = true;
    // Each path (direct, each wall) as one wavefront: its time at the robot
    // origin from every receiver that heard it, averaged.
    struct Front {
      double time_s = 0;
      int receivers = 0;
      bool direct = false;
    };
    std::vector<Front> fronts(1 + world::kWallCount);
    for (const world::Reception& r : e.receivers) {
      const auto add = [&](const world::Arrival& a, std::size_t slot) {
        if (!a.above_threshold)
          return;
        const double to_origin = std::sqrt((a.source.x_m - pose.x_m) * (a.source.x_m - pose.x_m) +
                                           (a.source.y_m - pose.y_m) * (a.source.y_m - pose.y_m) +
                                           world.height_m * world.height_m);
        fronts[slot].time_s += a.time_s - (a.path_m - to_origin) / c;
        fronts[slot].receivers += 1;
        fronts[slot].direct = slot == 0;
      };
      add(r.direct, 0);
      for (const world::Arrival& echo : r.echoes)
        add(echo, 1 + world::index(*echo.wall));
    }
    std::vector<loc::RangeCandidate> candidates;
    std::vector<bool> is_direct;
    for (const Front& f : fronts) {
      if (f.receivers == 0)
        continue;
      const double sd_t = std::sqrt(path_jitter_s * path_jitter_s +
                                    receiver_jitter_s * receiver_jitter_s / f.receivers);
      const double sd = std::hypot(c_used_mps * sd_t, chain_sd_m);
      const double d =
          c_used_mps * (f.time_s / f.receivers - e.emission_s) + offset_m + chain_error_m();
      candidates.push_back({d, sd, {}});
      is_direct.push_back(f.direct);
    }
    std::vector<std::size_t> order(candidates.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      return candidates[x].distance_m < candidates[y].distance_m;
    });
    loc::BeaconRange& range = out.ranges.beacons[b];
    for (const std::size_t i : order)
      range.candidates.push_back(candidates[i]);
    if (range.candidates.empty()) {
      range.flags = loc::Flags(loc::Flag::kMissing);
      continue;
    }
    range.primary = 0;
    if (is_direct[order[0]]) {
      out.direct.push_back(static_cast<int>(b));
      out.direct_sd_m.push_back(range.candidates[0].sd_m);
    }
  }
  return out;
}

}  // namespace odoloc::board
