// The fabric's odometry over the register bus (odometry_driver.hpp).
#include "odoloc/sw/odometry_driver.hpp"

#include <array>
#include <cmath>
#include <numbers>

namespace odoloc::sw {

namespace {

namespace odo = regs::odometry;

// The burst: status up to steer_phi, one snapshot.
constexpr std::uint16_t kFirst = odo::status::kAddress;
constexpr std::uint16_t kLast = odo::steer_phi_hi::kAddress;
using Burst = std::array<std::uint32_t, kLast - kFirst + 1>;

// A wide register's value from its _lo word (at lo) and _hi word (the one
// after it, field `hi`), sign-extended from its width when signed (the _hi
// field says both).
std::int64_t wide(const Burst& words, std::uint16_t lo_address, const regs::Field& hi) {
  const std::uint64_t lo = words[lo_address - kFirst];
  const std::uint64_t high = hi.get(words[lo_address + 1U - kFirst]);
  const unsigned width = 32U + hi.width;
  const std::uint64_t value = lo | (high << 32U);
  if (!hi.is_signed || width == 64)
    return static_cast<std::int64_t>(value);
  const std::uint64_t sign = std::uint64_t{1} << (width - 1);
  return static_cast<std::int64_t>((value ^ sign) - sign);
}

double turns_to_radians(std::int64_t value, int fraction_bits) {
  return 2.0 * std::numbers::pi * std::ldexp(static_cast<double>(value), -fraction_bits);
}

void write_wide(RegisterBus& bus, std::uint16_t lo_address, std::uint64_t value) {
  const std::array<std::uint32_t, 2> words = {static_cast<std::uint32_t>(value),
                                              static_cast<std::uint32_t>(value >> 32U)};
  bus.write(lo_address, words);
}

}  // namespace

void OdometryDriver::configure(const VehicleGeometry& vehicle, const MinSelectSetup& select,
                               std::uint16_t update_clocks, OdometryPolicy policy) {
  const OdometryScales s = odometry_scales(vehicle);
  // rear_ds_scale .. select_dtheta_threshold are consecutive.
  static_assert(odo::select_dtheta_threshold::kAddress - odo::rear_ds_scale::kAddress == 7);
  const std::array<std::uint32_t, 8> scales = {
      s.rear_ds, s.rear_dtheta, s.front_ds,          s.front_dtheta,
      s.steer,   s.steer_limit, select.ds_threshold, select.dtheta_threshold};
  bus_.write(odo::rear_ds_scale::kAddress, scales);
  std::uint32_t cfg = odo::cfg::update_clocks.set(0, update_clocks);
  cfg = odo::cfg::policy.set(cfg, static_cast<std::uint32_t>(policy));
  cfg = odo::cfg::select_shift.set(cfg, select.shift);
  bus_.write(odo::cfg::kAddress, cfg);
}

void OdometryDriver::set_pose(double x_m, double y_m, double theta_rad) {
  write_wide(bus_, odo::set_x_lo::kAddress, static_cast<std::uint64_t>(metres_to_pose(x_m)));
  write_wide(bus_, odo::set_y_lo::kAddress, static_cast<std::uint64_t>(metres_to_pose(y_m)));
  write_wide(bus_, odo::set_theta_lo::kAddress, radians_to_heading(theta_rad));
  bus_.write(odo::command::kAddress, odo::command::set_pose.set(0, 1));
}

FabricOdometry OdometryDriver::read() {
  Burst w{};
  bus_.read(kFirst, w);
  const std::uint32_t status = w[odo::status::kAddress - kFirst];
  FabricOdometry o;
  o.updates = odo::updates::count.get(w[odo::updates::kAddress - kFirst]);
  o.x_m = pose_metres(wide(w, odo::pose_x_lo::kAddress, odo::pose_x_hi::bits));
  o.y_m = pose_metres(wide(w, odo::pose_y_lo::kAddress, odo::pose_y_hi::bits));
  o.theta_rad = heading_radians(
      static_cast<std::uint64_t>(wide(w, odo::pose_theta_lo::kAddress, odo::pose_theta_hi::bits)));
  o.rear_ds_m = std::ldexp(
      static_cast<double>(wide(w, odo::rear_ds_lo::kAddress, odo::rear_ds_hi::bits)), -32);
  o.front_ds_m = std::ldexp(
      static_cast<double>(wide(w, odo::front_ds_lo::kAddress, odo::front_ds_hi::bits)), -32);
  o.ds_m = std::ldexp(static_cast<double>(wide(w, odo::ds_lo::kAddress, odo::ds_hi::bits)), -32);
  o.rear_dtheta_rad =
      turns_to_radians(wide(w, odo::rear_dtheta_lo::kAddress, odo::rear_dtheta_hi::bits), 40);
  o.front_dtheta_rad =
      turns_to_radians(wide(w, odo::front_dtheta_lo::kAddress, odo::front_dtheta_hi::bits), 40);
  o.dtheta_rad = turns_to_radians(wide(w, odo::dtheta_lo::kAddress, odo::dtheta_hi::bits), 40);
  o.steer_rad = turns_to_radians(wide(w, odo::steer_phi_lo::kAddress, odo::steer_phi_hi::bits), 40);
  o.ds_from_front = odo::status::ds_from_front.get(status) != 0;
  o.dtheta_from_front = odo::status::dtheta_from_front.get(status) != 0;
  o.overrun = odo::status::overrun.get(status) != 0;
  o.steer_clamped = odo::status::steer_clamped.get(status) != 0;
  return o;
}

}  // namespace odoloc::sw
