/* The generated C header is 32-bit everywhere: compiled by test_regmap_corpus
 * with avr-gcc (16-bit int), arm-none-eabi-gcc and the host compiler, as C99,
 * at -O1. Constant checks are static (a negative array size fails the
 * compile); the helper checks call a function carrying GCC's error
 * attribute, which only compiles when the optimiser proves the check holds. */
#include "odoloc_regs.h"

#define CHECK(name, cond) typedef char check_##name[(cond) ? 1 : -1]

CHECK(mask_is_32_bit, sizeof(ODOLOC_ODOMETRY_CFG_UPDATE_CLOCKS_MASK) >= 4);
CHECK(mask_value, ODOLOC_ODOMETRY_CFG_UPDATE_CLOCKS_MASK == 0x0000ffffUL);
CHECK(inverted_mask_keeps_high_bits, ~ODOLOC_ODOMETRY_CFG_UPDATE_CLOCKS_MASK == 0xffff0000UL);
CHECK(top_mask, ODOLOC_TOP_ID_MAGIC_MASK == 0xffff0000UL);
CHECK(top_mask_shift, (ODOLOC_TOP_ID_MAGIC_MASK >> ODOLOC_TOP_ID_MAGIC_SHIFT) == 0xffffUL);
CHECK(reset_is_32_bit, sizeof(ODOLOC_ODOMETRY_CFG_RESET) >= 4);
CHECK(clock, ODOLOC_FABRIC_CLOCK_HZ == 50000000UL && sizeof(ODOLOC_FABRIC_CLOCK_HZ) >= 4);
CHECK(enum_is_32_bit, sizeof(ODOLOC_ODOMETRY_CFG_POLICY_REAR_ONLY) >= 4);
CHECK(addr_is_32_bit, sizeof(ODOLOC_EPPM_STEERING_SPEED_ADDR) >= 4);
CHECK(shift_is_32_bit, sizeof(ODOLOC_ODOMETRY_CFG_POLICY_SHIFT) >= 4);

extern void odoloc_c_header_check_failed(void)
    __attribute__((error("a helper of odoloc_regs.h changed bits it must keep")));

#define EXPECT(cond)                  \
  do {                                \
    if (!(cond))                      \
      odoloc_c_header_check_failed(); \
  } while (0)

uint32_t odoloc_c_header_checks(void);
uint32_t odoloc_c_header_checks(void) {
  const uint32_t all = 0xffffffffUL;
  /* issue 9: update_clocks_set(w, 1000) must keep policy and select_shift. */
  const uint32_t w = odoloc_odometry_cfg_update_clocks_set(all, 1000u);
  EXPECT(w == ((all & 0xffff0000UL) | 1000u));
  EXPECT(odoloc_odometry_cfg_update_clocks_get(w) == 1000u);
  EXPECT(odoloc_odometry_cfg_policy_get(w) == odoloc_odometry_cfg_policy_get(all));
  /* A field in bits 31:16 read and written through the helpers. */
  EXPECT(odoloc_top_id_magic_get(0x0d010001UL) == 0x0d01u);
  EXPECT(odoloc_top_id_magic_set(0UL, 0xffffu) == 0xffff0000UL);
  EXPECT(odoloc_top_id_version_set(0xffffffffUL, 0u) == 0xffff0000UL);
  return w;
}
