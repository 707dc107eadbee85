/* The generated C header's firmware helpers as C compiles them (C99:
 * c_helpers_tables.c, c_firmware.c), for test_c_helpers.cpp: tables of the
 * real map's signed and split fields, and a small firmware driver that
 * talks to the chip through a byte-level SPI transfer. */
#ifndef ODOLOC_TB_C_HELPERS_H
#define ODOLOC_TB_C_HELPERS_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A signed field's helpers; `name` is the stem after "odoloc_" and before
 * "_get_signed" ("eppm_count_value"). */
struct tb_signed_field {
  const char* name;
  int32_t (*get_signed)(uint32_t word);
};
extern const struct tb_signed_field tb_signed_fields[];
extern const unsigned tb_signed_field_count;

/* A field split over the two words of a wide register ("odometry_pose_x_bits"):
 * a signed one has join_signed (and, when writable, set_lo_signed and
 * set_hi_signed), an unsigned one the _unsigned members; the others are 0. */
struct tb_split_field {
  const char* name;
  int64_t (*join_signed)(uint32_t lo, uint32_t hi);
  uint32_t (*set_lo_signed)(uint32_t lo, int64_t value);
  uint32_t (*set_hi_signed)(uint32_t hi, int64_t value);
  uint64_t (*join_unsigned)(uint32_t lo, uint32_t hi);
  uint32_t (*set_lo_unsigned)(uint32_t lo, uint64_t value);
  uint32_t (*set_hi_unsigned)(uint32_t hi, uint64_t value);
};
extern const struct tb_split_field tb_split_fields[];
extern const unsigned tb_split_field_count;

/* The SPI helpers, called from C. */
bool tb_spi_command(uint16_t* command, bool read, uint32_t address, uint32_t count);
uint8_t tb_spi_crc8(const uint8_t* bytes, uint32_t count);
uint8_t tb_spi_crc8_update(uint8_t crc, uint8_t byte);
uint32_t tb_spi_encode(uint8_t* frame, bool read, uint32_t address, uint32_t count,
                       const uint32_t* words, bool crc);
bool tb_spi_decode(const uint8_t* frame, uint32_t count, bool crc, uint8_t* status,
                   uint32_t* words);
uint32_t tb_spi_frame_bytes(uint32_t count, bool crc);
/* The header's SPI macros, for comparison with regs.hpp and the docs. */
struct tb_spi_constants {
  uint32_t command_read, burst_shift, burst_mask, address_mask, header_bytes, word_bytes,
      frame_max_bytes, max_burst, crc_polynomial, crc_init, crc_xor_out;
};
extern const struct tb_spi_constants tb_spi;

/* ---- A firmware driver built only on odoloc_regs.h (c_firmware.c) ---- */

/* One chip-select assertion: `bytes` bytes out on MOSI, as many in on MISO. */
typedef void (*tb_spi_transfer)(void* link, const uint8_t* mosi, uint8_t* miso, uint32_t bytes);

struct tb_firmware {
  tb_spi_transfer transfer;
  void* link;
  bool crc;            /* frames carry the CRC-8 (top.ctrl.crc_enable) */
  uint8_t last_status; /* the status byte of the last reply (the frame before it) */
};

/* Reads or writes `count` words from `address`; false for a bad request or a
 * reply whose CRC does not match. */
bool tb_fw_read(struct tb_firmware* fw, uint32_t address, uint32_t count, uint32_t* words);
bool tb_fw_write(struct tb_firmware* fw, uint32_t address, uint32_t count, const uint32_t* words);
/* Turns the CRC on (top.ctrl) and confirms it with a read of top.id in CRC
 * framing: false unless the slave answers with status 0 and the id. */
bool tb_fw_enable_crc(struct tb_firmware* fw);
/* odometry.cfg.update_clocks = 0: no updates, so no latch-and-clear of the counts. */
bool tb_fw_stop_odometry(struct tb_firmware* fw);
/* eppm instance `encoder`: the signed count, and the speed word's signed value
 * and whether it is a valid pulse-mode reading. */
bool tb_fw_read_count(struct tb_firmware* fw, uint32_t encoder, int32_t* count);
bool tb_fw_read_speed(struct tb_firmware* fw, uint32_t encoder, int32_t* value, bool* pulse);
/* set_x, set_y, set_theta, then odometry.command.set_pose. */
bool tb_fw_set_pose(struct tb_firmware* fw, int64_t x, int64_t y, uint64_t theta);
/* The pose words in one burst (one snapshot), joined. */
bool tb_fw_read_pose(struct tb_firmware* fw, int64_t* x, int64_t* y, uint64_t* theta);

#ifdef __cplusplus
}
#endif

#endif /* ODOLOC_TB_C_HELPERS_H */
