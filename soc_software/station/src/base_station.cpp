// Liu's base station on the SoC (base_station.hpp).
#include "odoloc/sw/base_station.hpp"

#include <cmath>
#include <numbers>

#include "odoloc/sw/detail/config_checks.hpp"

namespace odoloc::sw::station {

double LaserEncoder::step_rad() const {
  return 2 * std::numbers::pi / counts_per_rev;
}

double LaserEncoder::angle_rad(std::uint32_t count) const {
  return sweep_start_rad + (count + 0.5) * step_rad();
}

double LaserEncoder::sd_rad() const {
  return step_rad() / std::sqrt(12.0);
}

void PacketTimer::add_edges(std::span<const double> edges_s, bool edges_lost) {
  if (edges_lost) {
    dropped_ += packets_.size();
    packets_.clear();
    edges_s_.clear();
    return;
  }
  edges_s_.insert(edges_s_.end(), edges_s.begin(), edges_s.end());
}

std::optional<TimedReport> PacketTimer::next() {
  if (edges_s_.empty() || packets_.empty())
    return std::nullopt;
  const TimedReport paired{packets_.front(), edges_s_.front()};
  packets_.pop_front();
  edges_s_.pop_front();
  return paired;
}

void StationConfig::validate() const {
  constexpr std::string_view kOwner = "StationConfig";
  detail::require(position_m.allFinite(), kOwner, "position_m must be finite");
  detail::require(detail::finite_non_negative(height_m), kOwner,
                  "height_m must be finite and >= 0");
  detail::require(detail::finite_non_negative(t0_s) && t0_s < 1, kOwner,
                  "t0_s must be in [0, 1) s");
  for (const LaserEncoder* laser : {&station_laser, &robot_laser})
    detail::require(std::isfinite(laser->sweep_start_rad) && laser->counts_per_rev >= 4, kOwner,
                    "a laser encoder needs a finite sweep_start_rad and >= 4 counts_per_rev");
  detail::require(detail::finite_positive(max_range_m), kOwner,
                  "max_range_m must be finite and positive");
  detail::require(detail::finite_positive(ranging_after_alpha_s), kOwner,
                  "ranging_after_alpha_s must be finite and positive");
  detail::require(detail::finite_non_negative(chain_sd_m), kOwner,
                  "chain_sd_m must be finite and >= 0");
  detail::require(detail::finite_non_negative(bearing_sd_rad), kOwner,
                  "bearing_sd_rad must be finite and >= 0");
}

namespace {

double bearing_sd(const StationConfig& config, const LaserEncoder& laser) {
  return std::hypot(laser.sd_rad(), config.bearing_sd_rad);
}

}  // namespace

fuse::StationBearing station_bearing(const StationConfig& config, std::uint32_t count) {
  return {config.position_m, config.station_laser.angle_rad(count),
          bearing_sd(config, config.station_laser)};
}

fuse::RobotBearing robot_bearing(const StationConfig& config, std::uint32_t count) {
  return {config.position_m, config.robot_laser.angle_rad(count),
          bearing_sd(config, config.robot_laser)};
}

}  // namespace odoloc::sw::station
