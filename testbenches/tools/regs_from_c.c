/* The C header seen from C: a few values for test_regmap to compare with the
 * C++ header (both generated from regmap/odoloc.yaml). */
#include "odoloc_regs.h"

unsigned odoloc_c_register_count(void) {
  return ODOLOC_REGISTER_COUNT;
}
unsigned odoloc_c_eppm_steering_speed_addr(void) {
  return ODOLOC_EPPM_STEERING_SPEED_ADDR;
}
unsigned odoloc_c_speed_mode_mask(void) {
  return ODOLOC_EPPM_SPEED_MODE_MASK;
}
unsigned odoloc_c_odometry_cfg_reset(void) {
  return ODOLOC_ODOMETRY_CFG_RESET;
}
unsigned odoloc_c_policy_rear_only(void) {
  return ODOLOC_ODOMETRY_CFG_POLICY_REAR_ONLY;
}
unsigned odoloc_c_set_decode(unsigned word, unsigned value) {
  return odoloc_eppm_cfg_decode_mode_set(word, value);
}
unsigned odoloc_c_fabric_clock_period_ns(void) {
  return ODOLOC_FABRIC_CLOCK_PERIOD_NS;
}
unsigned odoloc_c_spi_max_sclk_hz(void) {
  return ODOLOC_SPI_MAX_SCLK_HZ;
}
unsigned odoloc_c_spi_crc_polynomial(void) {
  return ODOLOC_SPI_CRC_POLYNOMIAL;
}
