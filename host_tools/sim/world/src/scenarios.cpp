#include "odoloc/world/scenarios.hpp"

#include <initializer_list>
#include <numbers>

namespace odoloc::world {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Disturbances merged(std::initializer_list<Disturbances> parts) {
  Disturbances all;
  for (const auto& p : parts) {
    all.bumps.insert(all.bumps.end(), p.bumps.begin(), p.bumps.end());
    all.slips.insert(all.slips.end(), p.slips.begin(), p.slips.end());
  }
  return all;
}

// Bumps of 2.5 cm over 30 cm: each adds bump_extra_length (about 5 mm) of roll.
constexpr double kBumpHeight = 0.025;
constexpr double kBumpLength = 0.30;

}  // namespace

const char* name(BumpCase c) {
  switch (c) {
    case BumpCase::kNone:
      return "no disturbance";
    case BumpCase::kBothRear:
      return "both rear wheels over bumps";
    case BumpCase::kOneRear:
      return "one rear wheel over bumps";
    case BumpCase::kFront:
      return "front wheel over bumps";
  }
  return "?";
}

Scenario bump_scenario(BumpCase c, double metres, double heading_rad) {
  Scenario s{name(c), {}, straight_path(metres, 1.0), {}, {0.5, -0.25, heading_rad}};
  for (const double at : {0.2 * metres, 0.5 * metres, 0.8 * metres}) {
    switch (c) {
      case BumpCase::kNone:
        break;
      case BumpCase::kBothRear:
        s.disturbances =
            merged({s.disturbances, bump_under_both_rear(at, kBumpHeight, kBumpLength)});
        break;
      case BumpCase::kOneRear:
        s.disturbances = merged(
            {s.disturbances, bump_under_one_rear(Wheel::kLeftRear, at, kBumpHeight, kBumpLength)});
        break;
      case BumpCase::kFront:
        s.disturbances = merged({s.disturbances, bump_under_front(at, kBumpHeight, kBumpLength)});
        break;
    }
  }
  return s;
}

Scenario default_square() {
  Scenario s;
  s.name = "6 m square (24 m perimeter, rounded corners) with bumps and slip";
  s.path = square_path(s.geometry, 6.0, 1.0, 30.0 * kDeg);
  s.disturbances = merged({
      bump_under_both_rear(2.0, kBumpHeight, kBumpLength),
      bump_under_one_rear(Wheel::kRightRear, 9.0, kBumpHeight, kBumpLength),
      bump_under_front(15.0, kBumpHeight, kBumpLength),
      Disturbances{{}, {Slip{Wheel::kFront, 19.0, 20.0, 0.05}}},
  });
  return s;
}

Scenario patrol(double seconds) {
  Scenario s;
  s.name = "laps of the 6 m square";
  s.start = {2.0, 2.0, 0.0};  // the square inside Kleeman's 10 m x 10 m room
  const Path lap = square_path(s.geometry, 6.0, 1.0, 30.0 * kDeg);
  // A lap is about 24 m at 1 m/s (rounded corners are shorter, turning in
  // and out takes longer): 20 s is a lower bound of its duration.
  constexpr double kLapAtLeastS = 20.0;
  s.path.steer_rate_radps = lap.steer_rate_radps;
  for (double t = 0; t < seconds; t += kLapAtLeastS)
    s.path.segments.insert(s.path.segments.end(), lap.segments.begin(), lap.segments.end());
  return s;
}

}  // namespace odoloc::world
