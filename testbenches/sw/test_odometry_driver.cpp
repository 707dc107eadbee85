// The SoC's odometry driver on the simulated board (chip behind the
// pin-level SPI master): configuration and set_pose over the bus, and the
// pose it reads against the physics of a straight drive at any heading.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "odoloc/board/chip_link.hpp"
#include "odoloc/board/encoder_pins.hpp"
#include "odoloc/sw/odometry_driver.hpp"
#include "odoloc/sw/pose_ekf.hpp"
#include "odoloc/sw/spi_frame.hpp"
#include "odoloc/world/quadrature_source.hpp"

namespace {

using odoloc::world::QuadratureSource;
constexpr double kPi = std::numbers::pi;

struct Board {
  std::array<QuadratureSource, 4> sources{};  // fabric order: left, right, front, steering
  odoloc::board::ChipLink link{{.half_period = 4}, [this](auto& pins) {
                                 for (std::size_t w = 0; w < 4; ++w)
                                   pins.encoders[w] =
                                       odoloc::board::encoder_pins(sources[w].tick());
                               }};
  odoloc::sw::SpiRegisterBus bus{link, {.crc = true, .confirm_writes = true}};
  odoloc::sw::OdometryDriver odometry{bus};
};

TEST(OdometryDriver, SetPoseReadsBack) {
  Board board;
  board.odometry.configure(odoloc::sw::VehicleGeometry{}, {0, 0, 0});
  for (const auto& [x, y, theta] : std::array<std::array<double, 3>, 3>{
           {{-3.5, 7.25, -2.0}, {1234.5, -0.001, 3.1}, {0, 0, -kPi}}}) {
    board.odometry.set_pose(x, y, theta);
    const odoloc::sw::FabricOdometry o = board.odometry.read();
    EXPECT_NEAR(o.x_m, x, 1e-13);
    EXPECT_NEAR(o.y_m, y, 1e-13);
    EXPECT_NEAR(odoloc::sw::fuse::wrap_angle(o.theta_rad - theta), 0, 1e-11);
  }
}

// Both rear wheels and the front wheel at 1 m/s, the steering straight: the
// fabric's pose moves along the heading it was set to, by the rear wheels'
// edges times metres per edge, and its heading does not change.
TEST(OdometryDriver, StraightDriveAtAnyHeading) {
  const odoloc::sw::VehicleGeometry vehicle;
  const double kappa_rear = vehicle.rear.metres_per_edge();
  const double kappa_front = vehicle.front.metres_per_edge();
  constexpr double kSpeed = 1.0;  // m/s
  for (const double heading : {0.0, 0.7, 2.0, -1.2, 3.0}) {
    Board board;
    board.odometry.configure(vehicle, odoloc::sw::min_select_setup(vehicle));
    board.odometry.set_pose(1, 2, heading);
    const odoloc::sw::FabricOdometry start = board.odometry.read();
    const double rear_rate = kSpeed / kappa_rear / odoloc::rtl::kFabricClockHz;
    board.sources[0].set_rate(rear_rate);
    board.sources[1].set_rate(rear_rate);
    board.sources[2].set_rate(kSpeed / kappa_front / odoloc::rtl::kFabricClockHz);
    const std::int64_t edges_before = board.sources[0].edges();
    board.link.advance(5'000'000);  // 0.1 s
    const odoloc::sw::FabricOdometry end = board.odometry.read();
    const double driven = static_cast<double>(board.sources[0].edges() - edges_before) * kappa_rear;
    const odoloc::sw::fuse::Vector3 d = odoloc::sw::fuse::increment_between(
        odoloc::sw::fuse::Pose{{start.x_m, start.y_m, start.theta_rad}},
        odoloc::sw::fuse::Pose{{end.x_m, end.y_m, end.theta_rad}});
    // The pose lags the wheels by the last update period (100 us) and the
    // sensor latency: at most 0.2 mm at 1 m/s. Each step's direction comes
    // from the CORDIC: its sin and cos are within 1 LSB (2^-14, docs/cordic.md)
    // of those of the heading rounded to its 16-bit input (pi 2^-16 rad).
    const double direction = std::ldexp(1.0, -14) + kPi * std::ldexp(1.0, -16);
    EXPECT_NEAR(d.x(), driven, 2e-4 + driven * direction) << heading;
    EXPECT_NEAR(d.y(), 0, driven * direction) << heading;
    EXPECT_NEAR(d.z(), 0, 1e-12) << heading;
    EXPECT_NEAR(end.ds_m, kSpeed * 100e-6, 2 * kappa_front) << heading;  // one update's
    EXPECT_EQ(end.dtheta_rad, 0.0) << heading;
    EXPECT_GT(end.updates - start.updates, 990U) << heading;  // every 100 us
    EXPECT_FALSE(end.overrun);
  }
}

}  // namespace
