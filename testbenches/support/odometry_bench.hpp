// The odometry fabric configured from a vehicle geometry, driven by ideal
// quadrature sources: the harness of the odometry testbenches.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/board/scenario_runner.hpp"
#include "odoloc/rtl/odometry_fabric.hpp"
#include "odoloc/sw/odometry_setup.hpp"
#include "odoloc/world/quadrature_source.hpp"

namespace odoloc::tb {

struct SiPose {
  double x, y, theta;
};

inline SiPose si_pose(const rtl::PoseIntegrator::Regs& p) {
  return {sw::pose_metres(rtl::pose_coordinate(p.x).value()),
          sw::pose_metres(rtl::pose_coordinate(p.y).value()), sw::heading_radians(p.theta.value())};
}

inline double angle_difference(double a, double b) {
  return std::remainder(a - b, 2 * M_PI);
}

struct OdometryBench {
  sw::VehicleGeometry geometry;
  rtl::OdometryFabric fabric;
  rtl::OdometryFabric::Config cfg;  // the configuration ports, set without register traffic
  rtl::OdometryFabric::In in;
  std::array<world::QuadratureSource, rtl::kEncoderCount> sources{};  // by fabric input
  std::uint64_t clocks = 0;
  std::uint64_t latch_clock = 0;  // the clock whose edge latched the counts of the last update

  explicit OdometryBench(rtl::MinSelectPolicy policy = rtl::MinSelectPolicy::kPerComponent,
                         board::MinSelectTuning tuning = board::MinSelectTuning::kVehicle) {
    cfg.odometry = board::odometry_config(geometry, policy, tuning);
  }

  void set_pose(const SiPose& p) {
    cfg.odometry.set_x.bits = rtl::SInt<64>{sw::metres_to_pose(p.x)};
    cfg.odometry.set_y.bits = rtl::SInt<64>{sw::metres_to_pose(p.y)};
    cfg.odometry.set_theta.bits = rtl::UInt<40>{sw::radians_to_heading(p.theta)};
    in.odometry.command.set_pose = rtl::UInt<1>{1};
    step();
    in.odometry.command.set_pose = rtl::UInt<1>{};
  }
  void step() {
    if (fabric.phase() == rtl::OdometryPhase::kLatch)
      latch_clock = clocks;
    for (std::size_t w = 0; w < rtl::kEncoderCount; ++w)
      in.pins[w] = board::encoder_pins(sources[w].tick());
    fabric.step(in, cfg);
    ++clocks;
  }
  void run(std::uint64_t n) {
    for (std::uint64_t i = 0; i < n; ++i)
      step();
  }
  // Runs until the sequencer latches, then through the update it starts.
  void run_to_next_update() {
    while (fabric.phase() != rtl::OdometryPhase::kLatch)
      step();
    const auto updates = fabric.sequencer().updates;
    while (fabric.sequencer().updates == updates)
      step();
  }

  // Turns the steering (vehicle standing) to the nearest whole steering edge
  // of `phi`; returns the exact angle reached.
  double steer_to(double phi) {
    const double turns_per_edge = geometry.steering.turns_per_edge();
    const auto target = static_cast<std::int64_t>(std::lround(phi / (2 * M_PI) / turns_per_edge));
    auto& s = sources[static_cast<std::size_t>(rtl::Encoder::kSteering)];
    while (s.edges() != target) {
      s.set_rate(s.edges() < target ? 0.05 : -0.05);
      step();
    }
    s.set_rate(0.0);
    run(100);
    return static_cast<double>(target) * turns_per_edge * 2 * M_PI;
  }

  // Wheel rates for a rear-midpoint speed v at steering angle phi.
  void drive(double v, double phi) {
    const double curvature = std::tan(phi) / geometry.wheelbase_m;
    const double half_track = geometry.rear_track_m / 2;
    const double per_clock = 1.0 / sw::kFabricClockHz;
    const double rear = geometry.rear.metres_per_edge();
    sources[0].set_rate(v * (1 - half_track * curvature) / rear * per_clock);
    sources[1].set_rate(v * (1 + half_track * curvature) / rear * per_clock);
    sources[2].set_rate(v / std::cos(phi) / geometry.front.metres_per_edge() * per_clock);
  }
};

}  // namespace odoloc::tb
