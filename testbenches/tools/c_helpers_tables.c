/* The real map's signed and split fields, and the SPI helpers, as C99
 * compiles odoloc_regs.h. test_c_helpers.cpp checks that these tables name
 * exactly the fields regmap/odoloc.yaml marks signed or splits over two
 * words (so a field added to the map and missed here fails), then checks
 * each helper against independent arithmetic. */
#include "c_helpers.h"
#include "odoloc_regs.h"

#define SIGNED(stem) \
  { #stem, odoloc_##stem##_get_signed }

const struct tb_signed_field tb_signed_fields[] = {
    SIGNED(eppm_count_value),           SIGNED(eppm_latched_value),
    SIGNED(eppm_speed_value),           SIGNED(eppm_pulse_last_edges),
    SIGNED(odometry_pose_x_hi_bits),    SIGNED(odometry_pose_y_hi_bits),
    SIGNED(odometry_rear_ds_hi_bits),   SIGNED(odometry_rear_dtheta_hi_bits),
    SIGNED(odometry_front_ds_hi_bits),  SIGNED(odometry_front_dtheta_hi_bits),
    SIGNED(odometry_ds_hi_bits),        SIGNED(odometry_dtheta_hi_bits),
    SIGNED(odometry_steer_phi_hi_bits), SIGNED(odometry_steer_position_counts),
    SIGNED(odometry_set_x_hi_bits),     SIGNED(odometry_set_y_hi_bits),
};
const unsigned tb_signed_field_count = sizeof tb_signed_fields / sizeof tb_signed_fields[0];

#define SPLIT_RO_SIGNED(stem) \
  { #stem, odoloc_##stem##_join, 0, 0, 0, 0, 0 }
#define SPLIT_RO_UNSIGNED(stem) \
  { #stem, 0, 0, 0, odoloc_##stem##_join, 0, 0 }
#define SPLIT_RW_SIGNED(stem) \
  { #stem, odoloc_##stem##_join, odoloc_##stem##_set_lo, odoloc_##stem##_set_hi, 0, 0, 0 }
#define SPLIT_RW_UNSIGNED(stem) \
  { #stem, 0, 0, 0, odoloc_##stem##_join, odoloc_##stem##_set_lo, odoloc_##stem##_set_hi }

const struct tb_split_field tb_split_fields[] = {
    SPLIT_RO_SIGNED(odometry_pose_x_bits),       SPLIT_RO_SIGNED(odometry_pose_y_bits),
    SPLIT_RO_UNSIGNED(odometry_pose_theta_bits), SPLIT_RO_SIGNED(odometry_rear_ds_bits),
    SPLIT_RO_SIGNED(odometry_rear_dtheta_bits),  SPLIT_RO_SIGNED(odometry_front_ds_bits),
    SPLIT_RO_SIGNED(odometry_front_dtheta_bits), SPLIT_RO_SIGNED(odometry_ds_bits),
    SPLIT_RO_SIGNED(odometry_dtheta_bits),       SPLIT_RO_SIGNED(odometry_steer_phi_bits),
    SPLIT_RW_SIGNED(odometry_set_x_bits),        SPLIT_RW_SIGNED(odometry_set_y_bits),
    SPLIT_RW_UNSIGNED(odometry_set_theta_bits),
};
const unsigned tb_split_field_count = sizeof tb_split_fields / sizeof tb_split_fields[0];

bool tb_spi_command(uint16_t* command, bool read, uint32_t address, uint32_t count) {
  return odoloc_spi_command(command, read, address, count);
}
uint8_t tb_spi_crc8(const uint8_t* bytes, uint32_t count) {
  return odoloc_spi_crc8(bytes, count);
}
uint8_t tb_spi_crc8_update(uint8_t crc, uint8_t byte) {
  return odoloc_spi_crc8_update(crc, byte);
}
uint32_t tb_spi_encode(uint8_t* frame, bool read, uint32_t address, uint32_t count,
                       const uint32_t* words, bool crc) {
  return odoloc_spi_encode(frame, read, address, count, words, crc);
}
bool tb_spi_decode(const uint8_t* frame, uint32_t count, bool crc, uint8_t* status,
                   uint32_t* words) {
  return odoloc_spi_decode(frame, count, crc, status, words);
}
uint32_t tb_spi_frame_bytes(uint32_t count, bool crc) {
  return odoloc_spi_frame_bytes(count, crc);
}

const struct tb_spi_constants tb_spi = {
    ODOLOC_SPI_COMMAND_READ,       ODOLOC_SPI_COMMAND_BURST_SHIFT,
    ODOLOC_SPI_COMMAND_BURST_MASK, ODOLOC_SPI_COMMAND_ADDRESS_MASK,
    ODOLOC_SPI_HEADER_BYTES,       ODOLOC_SPI_WORD_BYTES,
    ODOLOC_SPI_FRAME_MAX_BYTES,    ODOLOC_SPI_MAX_BURST,
    ODOLOC_SPI_CRC_POLYNOMIAL,     ODOLOC_SPI_CRC_INIT,
    ODOLOC_SPI_CRC_XOR_OUT,
};
