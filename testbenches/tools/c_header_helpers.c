/* The firmware helpers of odoloc_regs.h give the right values on every
 * compiler test_regmap_corpus has: avr-gcc (16-bit int), arm-none-eabi-gcc
 * and the host's, as C99 at -O2. Each check calls a function carrying GCC's
 * error attribute unless the optimiser proves it holds, so a wrong value
 * (integer promotion, a shift of a signed value, 1 << 31 in a 16-bit int)
 * fails the compile on that target. The values are docs/spi.md's and plain
 * two's complement arithmetic. */
#include "odoloc_regs.h"

extern void odoloc_c_helper_check_failed(void)
    __attribute__((error("a firmware helper of odoloc_regs.h gives a wrong value")));

#define EXPECT(cond)                  \
  do {                                \
    if (!(cond))                      \
      odoloc_c_helper_check_failed(); \
  } while (0)

#define INT32_LOWEST (-INT32_C(2147483647) - 1)
#define INT64_LOWEST (-INT64_C(9223372036854775807) - 1)

static void sign_extension(void) {
  /* eppm.count.value: 20 bits; the bits above it are not the field's. */
  EXPECT(odoloc_eppm_count_value_get_signed(UINT32_C(0x000fffff)) == -1);
  EXPECT(odoloc_eppm_count_value_get_signed(UINT32_C(0xfff80000)) == -INT32_C(524288));
  EXPECT(odoloc_eppm_count_value_get_signed(UINT32_C(0xfff7ffff)) == INT32_C(524287));
  EXPECT(odoloc_eppm_count_value_get_signed(UINT32_C(0xfff00005)) == 5);
  /* eppm.speed.value: 24 bits under the mode and flag bits. */
  EXPECT(odoloc_eppm_speed_value_get_signed(UINT32_C(0x0f800000)) == -INT32_C(8388608));
  EXPECT(odoloc_eppm_speed_value_get_signed(UINT32_C(0x03fff63c)) == -INT32_C(2500));
  /* A whole word: pose_x_hi. */
  EXPECT(odoloc_odometry_pose_x_hi_bits_get_signed(UINT32_C(0x80000000)) == INT32_LOWEST);
  EXPECT(odoloc_odometry_pose_x_hi_bits_get_signed(UINT32_C(0x7fffffff)) == INT32_C(2147483647));
  EXPECT(odoloc_odometry_steer_phi_hi_bits_get_signed(UINT32_C(0xffffff80)) == -128);
}

static void joins(void) {
  EXPECT(odoloc_odometry_pose_x_bits_join(UINT32_C(0), UINT32_C(0x80000000)) == INT64_LOWEST);
  EXPECT(odoloc_odometry_pose_x_bits_join(UINT32_C(0xffffffff), UINT32_C(0xffffffff)) == -1);
  EXPECT(odoloc_odometry_pose_x_bits_join(UINT32_C(0x80000000), UINT32_C(0)) ==
         INT64_C(2147483648));
  EXPECT(odoloc_odometry_pose_y_bits_join(UINT32_C(0x79f22087), UINT32_C(0xffff8fb7)) ==
         -INT64_C(123456789012345));
  /* 40-bit fields: the hi word's bits above bit 39 are not the field's. */
  EXPECT(odoloc_odometry_pose_theta_bits_join(UINT32_C(0xffffffff), UINT32_C(0xffffffff)) ==
         UINT64_C(0xffffffffff));
  EXPECT(odoloc_odometry_steer_phi_bits_join(UINT32_C(0), UINT32_C(0x80)) ==
         -INT64_C(549755813888));
  EXPECT(odoloc_odometry_rear_ds_bits_join(UINT32_C(0xffffffff), UINT32_C(0x7fff)) ==
         INT64_C(140737488355327));
}

static void splits(void) {
  EXPECT(odoloc_odometry_set_x_bits_set_lo(UINT32_C(0), -INT64_C(2)) == UINT32_C(0xfffffffe));
  EXPECT(odoloc_odometry_set_x_bits_set_hi(UINT32_C(0), -INT64_C(2)) == UINT32_C(0xffffffff));
  EXPECT(odoloc_odometry_set_x_bits_set_hi(UINT32_C(0), INT64_LOWEST) == UINT32_C(0x80000000));
  EXPECT(odoloc_odometry_set_theta_bits_set_hi(UINT32_C(0xffffffff), UINT64_C(0)) ==
         UINT32_C(0xffffff00));
  EXPECT(odoloc_odometry_set_theta_bits_set_hi(UINT32_C(0), UINT64_C(0xab12345678)) ==
         UINT32_C(0xab));
  EXPECT(odoloc_odometry_set_theta_bits_set_lo(UINT32_C(0), UINT64_C(0xab12345678)) ==
         UINT32_C(0x12345678));
}

static void spi(void) {
  uint16_t command = 0;
  uint8_t frame[ODOLOC_SPI_FRAME_MAX_BYTES];
  uint8_t status = 0xff;
  uint32_t word = 0;
  const uint32_t one = UINT32_C(0x600df00d);
  EXPECT(odoloc_spi_command(&command, true, UINT32_C(0x3ff), UINT32_C(32)) && command == 0xffffu);
  EXPECT(odoloc_spi_command(&command, false, UINT32_C(0), UINT32_C(1)) && command == 0u);
  EXPECT(odoloc_spi_command(&command, true, UINT32_C(0x010), UINT32_C(2)) && command == 0x8410u);
  EXPECT(!odoloc_spi_command(&command, true, UINT32_C(0), UINT32_C(0)) && command == 0x8410u);
  EXPECT(!odoloc_spi_command(&command, true, UINT32_C(0), UINT32_C(33)));
  EXPECT(!odoloc_spi_command(&command, true, UINT32_C(0x400), UINT32_C(1)));
  /* A one-word write of top.scratch, with and without CRC (its value is
   * checked on the host, test_c_helpers: the optimiser does not fold the
   * CRC's loops), and a reply read back. */
  EXPECT(odoloc_spi_encode(frame, false, ODOLOC_TOP_SCRATCH_ADDR, 1u, &one, true) == 7u);
  EXPECT(odoloc_spi_encode(frame, false, ODOLOC_TOP_SCRATCH_ADDR, 1u, &one, false) == 6u);
  EXPECT(frame[0] == 0x00u && frame[1] == 0x04u && frame[2] == 0x60u && frame[3] == 0x0du &&
         frame[4] == 0xf0u && frame[5] == 0x0du);
  EXPECT(odoloc_spi_encode(frame, true, UINT32_C(0x3ff), 1u, 0, false) == 6u);
  EXPECT(frame[0] == 0x83u && frame[1] == 0xffu && frame[2] == 0u && frame[5] == 0u);
  EXPECT(odoloc_spi_encode(frame, true, UINT32_C(0x400), 1u, 0, false) == 0u);
  frame[0] = 0x02u; /* as a reply: the previous frame's bad_length, then the word */
  odoloc_spi_put_word(&frame[2], one);
  EXPECT(odoloc_spi_decode(frame, 1u, false, &status, &word) && status == 0x02u && word == one);
  EXPECT(!odoloc_spi_decode(frame, 33u, false, &status, &word));
  EXPECT(odoloc_spi_frame_bytes(32u, true) == ODOLOC_SPI_FRAME_MAX_BYTES);
}

void odoloc_c_helper_checks(void);
void odoloc_c_helper_checks(void) {
  sign_extension();
  joins();
  splits();
  spi();
}
