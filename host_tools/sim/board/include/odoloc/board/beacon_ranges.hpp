// Beacon range sets straight from the acoustic world's arrivals, without the
// pins: what the capture chain (docs/tof-measurements.md) would hand the
// beacon solvers, formed the same way. Per beacon, every wavefront the robot
// heard (the direct path and each wall's echo) is one candidate, timed at
// the robot's origin (each receiver's arrival moved back along its path,
// averaged over the receivers that heard it), earliest first, with one
// unknown common offset per cycle. The capture chain's own residual timing
// error (rise-time compensation, quantisation: test_tof_chain measures
// about 1 mm) is a Gaussian the caller draws.
//
// Used by the solvers' Monte Carlo testbench (test_beacon_solvers) and by
// the `beacons` experiment of `odoloc sweep`.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "odoloc/sw/beacon_cycle.hpp"
#include "odoloc/sw/beacon_fix.hpp"
#include "odoloc/world/acoustic_systems.hpp"
#include "odoloc/world/acoustics.hpp"

namespace odoloc::board {

// The world's first `count` beacons (all by default; the others are not
// Kleeman's, e.g. a base station's transmitter) as the solvers' layout, in
// the world's order, each at the world's transmitter height.
sw::locate::BeaconLayout beacon_layout(const world::AcousticWorld& world,
                                       std::size_t count = SIZE_MAX);

// What the beacon-cycle decoder is told about a Kleeman world: the
// controller's timing (with its reserved slots), the receivers' envelope
// model (calibrated: the beacons' time constant), the air's speed of sound
// and the positions of the timing's beacon_count beacons. The timebase and the timing noise are the
// caller's.
sw::tof::KleemanConfig kleeman_config(const world::AcousticWorld& world,
                                      const world::KleemanTiming& timing);
// The same from what a robot is told: the beacons' surveyed positions (the
// timing's beacon_count of them), the calibrated envelope time constant and
// a speed of sound (a thermometer's).
sw::tof::KleemanConfig kleeman_config(const world::KleemanTiming& timing,
                                      std::span<const world::Vec2> beacons, double envelope_tau_s,
                                      double speed_of_sound_mps);

struct MeasuredCycle {
  sw::locate::RangeSet ranges;      // one BeaconRange per beacon of the world
  std::vector<int> direct;          // beacons whose first candidate is their direct path
  std::vector<double> direct_sd_m;  // those candidates' sd, in the order of `direct`
};

// One of Kleeman's beacon cycles (world::kleeman_schedule over the world's
// beacons, starting 10 ms into the run; beacon 0's second pulse ignored)
// heard by a robot standing
// at `pose`. A candidate's distance is
//     c_used_mps x (arrival at the origin - emission) + offset_m + chain_error_m(),
// chain_error_m() called once per candidate in beacon order; its sd is the
// world's turbulence jitter (per path, and per receiver averaged over the
// receivers that heard it) times c_used_mps, combined with chain_sd_m. A
// beacon heard on no path is Flag::kMissing. `world_seed` seeds
// world::simulate. Throws what world::simulate throws.
MeasuredCycle measure_kleeman_cycle(const world::AcousticWorld& world, const world::Pose& pose,
                                    double c_used_mps, double offset_m, double chain_sd_m,
                                    std::uint64_t world_seed,
                                    const std::function<double()>& chain_error_m);

}  // namespace odoloc::board
