// Beacon layouts and exact range sets for the solver testbenches: distances
// computed in long double from a known position, plus a chosen common offset
// and, optionally, seeded Gaussian noise.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "odoloc/sw/beacon_fix.hpp"

namespace odoloc::tb {

// Kleeman's six beacons in a width x depth room: the corners and the middles
// of the two long walls, `inset` in front of the walls (the acoustic world's
// kleeman_beacons uses 5 cm), in its beacon order.
inline sw::locate::BeaconLayout kleeman_layout(double width_m = 10, double depth_m = 10,
                                               double inset_m = 0.05, double height_m = 0) {
  const double w = width_m;
  const double d = depth_m;
  const double i = inset_m;
  sw::locate::BeaconLayout layout;
  for (const sw::locate::Vec2 p :
       {sw::locate::Vec2{i, i}, {w / 2, i}, {w - i, i}, {w - i, d - i}, {w / 2, d - i}, {i, d - i}})
    layout.beacons.push_back({p, height_m});
  return layout;
}

// The exact 3-D range to beacon `b` from p, in long double.
inline long double exact_range(const sw::locate::BeaconLayout& layout, std::size_t b,
                               sw::locate::Vec2 p) {
  const sw::locate::Beacon& beacon = layout.beacons[b];
  const long double dx = static_cast<long double>(p.x) - beacon.position_m.x;
  const long double dy = static_cast<long double>(p.y) - beacon.position_m.y;
  const long double h = beacon.height_m;
  return std::sqrt(dx * dx + dy * dy + h * h);
}

// One primary candidate per beacon: scale x range + offset (+ noise of sd_m
// when rng is given; sd_m is reported either way).
inline sw::locate::RangeSet exact_range_set(const sw::locate::BeaconLayout& layout,
                                            sw::locate::Vec2 p, double offset_m, double sd_m = 1e-3,
                                            std::mt19937_64* rng = nullptr,
                                            long double scale = 1.0L) {
  sw::locate::RangeSet set;
  std::normal_distribution<double> noise(0.0, sd_m);
  for (std::size_t b = 0; b < layout.beacons.size(); ++b) {
    const long double d = scale * exact_range(layout, b, p) + offset_m;
    const double n = rng != nullptr ? noise(*rng) : 0.0;
    set.beacons.push_back({{{static_cast<double>(d) + n, sd_m, {}}}, 0, {}});
  }
  return set;
}

}  // namespace odoloc::tb
