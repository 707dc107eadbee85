/* A firmware driver as a bare-metal writer would build it: every frame, every
 * address and every value conversion from odoloc_regs.h alone (no C++ and no
 * hand-written bit layout). test_c_helpers.cpp runs it against the simulated
 * board; test_regmap_corpus compiles it with avr-gcc and arm-none-eabi-gcc. */
#include "c_helpers.h"
#include "odoloc_regs.h"

/* One frame out and its reply in; false for a bad request or a bad reply CRC. */
static bool frame(struct tb_firmware* fw, bool read, uint32_t address, uint32_t count,
                  const uint32_t* out, uint32_t* in) {
  uint8_t mosi[ODOLOC_SPI_FRAME_MAX_BYTES];
  uint8_t miso[ODOLOC_SPI_FRAME_MAX_BYTES];
  const uint32_t bytes = odoloc_spi_encode(mosi, read, address, count, out, fw->crc);
  if (bytes == 0)
    return false;
  fw->transfer(fw->link, mosi, miso, bytes);
  return odoloc_spi_decode(miso, count, fw->crc, &fw->last_status, in);
}

bool tb_fw_read(struct tb_firmware* fw, uint32_t address, uint32_t count, uint32_t* words) {
  return frame(fw, true, address, count, 0, words);
}

bool tb_fw_write(struct tb_firmware* fw, uint32_t address, uint32_t count, const uint32_t* words) {
  return frame(fw, false, address, count, words, 0);
}

bool tb_fw_enable_crc(struct tb_firmware* fw) {
  const uint32_t ctrl = odoloc_top_ctrl_crc_enable_set(ODOLOC_TOP_CTRL_RESET, 1u);
  uint32_t id = 0;
  if (!tb_fw_write(fw, ODOLOC_TOP_CTRL_ADDR, 1u, &ctrl))
    return false;
  fw->crc = true; /* the slave latches crc_enable when the next frame starts */
  return tb_fw_read(fw, ODOLOC_TOP_ID_ADDR, 1u, &id) && fw->last_status == 0u &&
         id == ODOLOC_TOP_ID_RESET;
}

bool tb_fw_stop_odometry(struct tb_firmware* fw) {
  const uint32_t cfg = odoloc_odometry_cfg_update_clocks_set(ODOLOC_ODOMETRY_CFG_RESET, 0u);
  return tb_fw_write(fw, ODOLOC_ODOMETRY_CFG_ADDR, 1u, &cfg);
}

/* eppm instance `encoder`'s register at `offset`. */
static uint32_t eppm_address(uint32_t encoder, uint32_t offset) {
  return ODOLOC_EPPM_BASE + encoder * ODOLOC_EPPM_STRIDE + offset;
}

bool tb_fw_read_count(struct tb_firmware* fw, uint32_t encoder, int32_t* count) {
  uint32_t word;
  if (encoder >= ODOLOC_EPPM_INSTANCES ||
      !tb_fw_read(fw, eppm_address(encoder, ODOLOC_EPPM_COUNT_OFFSET), 1u, &word))
    return false;
  *count = odoloc_eppm_count_value_get_signed(word);
  return true;
}

bool tb_fw_read_speed(struct tb_firmware* fw, uint32_t encoder, int32_t* value, bool* pulse) {
  uint32_t word;
  if (encoder >= ODOLOC_EPPM_INSTANCES ||
      !tb_fw_read(fw, eppm_address(encoder, ODOLOC_EPPM_SPEED_OFFSET), 1u, &word))
    return false;
  *value = odoloc_eppm_speed_value_get_signed(word);
  *pulse = odoloc_eppm_speed_mode_get(word) == ODOLOC_EPPM_SPEED_MODE_PULSE &&
           odoloc_eppm_speed_valid_get(word) != 0u;
  return true;
}

/* set_x_lo .. set_theta_hi and pose_x_lo .. pose_theta_hi: six words each. */
typedef char set_words_are_one_burst
    [ODOLOC_ODOMETRY_SET_THETA_HI_ADDR - ODOLOC_ODOMETRY_SET_X_LO_ADDR == 5u ? 1 : -1];
typedef char pose_words_are_one_burst
    [ODOLOC_ODOMETRY_POSE_THETA_HI_ADDR - ODOLOC_ODOMETRY_POSE_X_LO_ADDR == 5u ? 1 : -1];

bool tb_fw_set_pose(struct tb_firmware* fw, int64_t x, int64_t y, uint64_t theta) {
  uint32_t w[6] = {0, 0, 0, 0, 0, 0};
  const uint32_t command = odoloc_odometry_command_set_pose_set(0u, 1u);
  w[ODOLOC_ODOMETRY_SET_X_LO_ADDR - ODOLOC_ODOMETRY_SET_X_LO_ADDR] =
      odoloc_odometry_set_x_bits_set_lo(ODOLOC_ODOMETRY_SET_X_LO_RESET, x);
  w[ODOLOC_ODOMETRY_SET_X_HI_ADDR - ODOLOC_ODOMETRY_SET_X_LO_ADDR] =
      odoloc_odometry_set_x_bits_set_hi(ODOLOC_ODOMETRY_SET_X_HI_RESET, x);
  w[ODOLOC_ODOMETRY_SET_Y_LO_ADDR - ODOLOC_ODOMETRY_SET_X_LO_ADDR] =
      odoloc_odometry_set_y_bits_set_lo(ODOLOC_ODOMETRY_SET_Y_LO_RESET, y);
  w[ODOLOC_ODOMETRY_SET_Y_HI_ADDR - ODOLOC_ODOMETRY_SET_X_LO_ADDR] =
      odoloc_odometry_set_y_bits_set_hi(ODOLOC_ODOMETRY_SET_Y_HI_RESET, y);
  w[ODOLOC_ODOMETRY_SET_THETA_LO_ADDR - ODOLOC_ODOMETRY_SET_X_LO_ADDR] =
      odoloc_odometry_set_theta_bits_set_lo(ODOLOC_ODOMETRY_SET_THETA_LO_RESET, theta);
  w[ODOLOC_ODOMETRY_SET_THETA_HI_ADDR - ODOLOC_ODOMETRY_SET_X_LO_ADDR] =
      odoloc_odometry_set_theta_bits_set_hi(ODOLOC_ODOMETRY_SET_THETA_HI_RESET, theta);
  return tb_fw_write(fw, ODOLOC_ODOMETRY_SET_X_LO_ADDR, 6u, w) &&
         tb_fw_write(fw, ODOLOC_ODOMETRY_COMMAND_ADDR, 1u, &command);
}

bool tb_fw_read_pose(struct tb_firmware* fw, int64_t* x, int64_t* y, uint64_t* theta) {
  uint32_t w[6];
  const uint32_t first = ODOLOC_ODOMETRY_POSE_X_LO_ADDR;
  if (!tb_fw_read(fw, first, 6u, w))
    return false;
  *x = odoloc_odometry_pose_x_bits_join(w[ODOLOC_ODOMETRY_POSE_X_LO_ADDR - first],
                                        w[ODOLOC_ODOMETRY_POSE_X_HI_ADDR - first]);
  *y = odoloc_odometry_pose_y_bits_join(w[ODOLOC_ODOMETRY_POSE_Y_LO_ADDR - first],
                                        w[ODOLOC_ODOMETRY_POSE_Y_HI_ADDR - first]);
  *theta = odoloc_odometry_pose_theta_bits_join(w[ODOLOC_ODOMETRY_POSE_THETA_LO_ADDR - first],
                                                w[ODOLOC_ODOMETRY_POSE_THETA_HI_ADDR - first]);
  return true;
}
