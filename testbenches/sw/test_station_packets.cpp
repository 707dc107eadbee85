// Liu's base station on the SoC (soc_software base_station.hpp): the laser
// encoders' counts as angles (every count of Liu's 1000 against long double
// interval middles), the bearings' deviations, the configuration's checks,
// and the pairing of RF packets with the sync input's edges, including a
// lost edge.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "odoloc/sw/base_station.hpp"

namespace {

namespace station = odoloc::sw::station;
using station::Report;
using station::ReportKind;

TEST(StationPackets, EveryCountIsItsIntervalsMiddle) {
  const station::LaserEncoder laser{-1.25, 1000};
  constexpr long double kPi = std::numbers::pi_v<long double>;
  for (std::uint32_t n = 0; n < 1000; ++n) {
    const long double low = -1.25L + 2 * kPi * n / 1000;
    const long double high = -1.25L + 2 * kPi * (n + 1) / 1000;
    EXPECT_NEAR(laser.angle_rad(n), static_cast<double>((low + high) / 2), 1e-14) << n;
  }
  // Liu: 0.36 degrees a count; uniform error over it.
  EXPECT_NEAR(laser.step_rad() * 180 / std::numbers::pi, 0.36, 1e-12);
  EXPECT_NEAR(laser.sd_rad(), 0.36 * std::numbers::pi / 180 / std::sqrt(12.0), 1e-15);
}

TEST(StationPackets, BearingsCarryTheStationAndBothErrors) {
  station::StationConfig config;
  config.position_m = {0.3, 5.0};
  config.station_laser = {-1.4, 1000};
  config.robot_laser = {-2.9, 4000};
  config.bearing_sd_rad = 0.5e-3;
  const auto alpha = station::station_bearing(config, 10);
  EXPECT_EQ(alpha.station_m, config.position_m);
  EXPECT_DOUBLE_EQ(alpha.bearing_rad, -1.4 + 10.5 * 2 * std::numbers::pi / 1000);
  EXPECT_DOUBLE_EQ(alpha.sd_rad,
                   std::sqrt(std::pow(2 * std::numbers::pi / 1000, 2) / 12 + 0.25e-6));
  const auto beta = station::robot_bearing(config, 3999);
  EXPECT_EQ(beta.station_m, config.position_m);
  EXPECT_DOUBLE_EQ(beta.bearing_rad, -2.9 + 3999.5 * 2 * std::numbers::pi / 4000);
  EXPECT_DOUBLE_EQ(beta.sd_rad, std::sqrt(std::pow(2 * std::numbers::pi / 4000, 2) / 12 + 0.25e-6));
}

TEST(StationPackets, BadConfigurationsAreRefusedByName) {
  const auto refused = [](auto change, const char* field) {
    station::StationConfig config;
    change(config);
    try {
      config.validate();
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  EXPECT_NO_THROW(station::StationConfig{}.validate());
  refused([](auto& c) { c.position_m.x() = NAN; }, "position_m");
  refused([](auto& c) { c.height_m = -0.1; }, "height_m");
  refused([](auto& c) { c.t0_s = 1.5; }, "t0_s");
  refused([](auto& c) { c.station_laser.counts_per_rev = 2; }, "counts_per_rev");
  refused([](auto& c) { c.robot_laser.sweep_start_rad = INFINITY; }, "sweep_start_rad");
  refused([](auto& c) { c.max_range_m = 0; }, "max_range_m");
  refused([](auto& c) { c.chain_sd_m = NAN; }, "chain_sd_m");
  refused([](auto& c) { c.bearing_sd_rad = -1; }, "bearing_sd_rad");
}

std::vector<station::TimedReport> drain(station::PacketTimer& timer) {
  std::vector<station::TimedReport> out;
  while (const auto p = timer.next())
    out.push_back(*p);
  return out;
}

// Packets and edges come in either order and in batches of any size: the
// n-th packet gets the n-th edge.
TEST(StationPackets, PacketsTakeTheirEdgesInOrder) {
  station::PacketTimer timer;
  timer.add_packet({ReportKind::kStationSawRobot, 17});
  EXPECT_TRUE(drain(timer).empty());  // its edge has not come
  const std::vector<double> first{1.0, 1.5};
  timer.add_edges(first, false);
  auto paired = drain(timer);
  ASSERT_EQ(paired.size(), 1U);
  EXPECT_EQ(paired[0].report.count, 17U);
  EXPECT_EQ(paired[0].time_s, 1.0);
  timer.add_packet({ReportKind::kRanging, 0});
  timer.add_packet({ReportKind::kRobotSawStation, 240});
  paired = drain(timer);
  ASSERT_EQ(paired.size(), 1U);
  EXPECT_EQ(paired[0].report.kind, ReportKind::kRanging);
  EXPECT_EQ(paired[0].time_s, 1.5);
  const std::vector<double> second{2.25};
  timer.add_edges(second, false);
  paired = drain(timer);
  ASSERT_EQ(paired.size(), 1U);
  EXPECT_EQ(paired[0].report.kind, ReportKind::kRobotSawStation);
  EXPECT_EQ(paired[0].report.count, 240U);
  EXPECT_EQ(paired[0].time_s, 2.25);
  EXPECT_EQ(timer.dropped(), 0U);
}

// A batch that lost sync edges: what was waiting and the batch's own edges
// are dropped (they may belong to any packet); from the next batch on the
// pairs are right again.
TEST(StationPackets, ALostEdgeRestartsThePairing) {
  station::PacketTimer timer;
  const std::vector<double> early{0.5};
  timer.add_edges(early, false);  // an edge whose packet has not come
  timer.add_packet({ReportKind::kStationSawRobot, 1});
  timer.add_packet({ReportKind::kStationSawRobot, 2});
  ASSERT_EQ(drain(timer).size(), 1U);
  const std::vector<double> overflowed{0.9, 1.0};
  timer.add_edges(overflowed, true);
  EXPECT_TRUE(drain(timer).empty());
  EXPECT_EQ(timer.dropped(), 1U);  // packet 2
  timer.add_packet({ReportKind::kRobotSawStation, 3});
  const std::vector<double> after{2.0};
  timer.add_edges(after, false);
  const auto paired = drain(timer);
  ASSERT_EQ(paired.size(), 1U);
  EXPECT_EQ(paired[0].report.count, 3U);
  EXPECT_EQ(paired[0].time_s, 2.0);
}

}  // namespace
