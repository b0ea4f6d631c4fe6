/*
 * End-to-end protection of the drive's telemetry frames, in the style of
 * AUTOSAR E2E profile 1 (tools/dbc/pmsm_drive.dbc, database comment):
 *
 *   byte 0      CRC-8/SAE-J1850 (polynomial 0x1D, initial value 0xFF,
 *               final XOR 0xFF, no reflection) over the data ID, the
 *               frame's 11-bit identifier as two bytes (low byte, then
 *               high byte), followed by bytes 1 .. len-1 of the frame;
 *   Counter     0..14, +1 per frame of a message, wrapping to 0 (its
 *               place, the low nibble of byte 1, belongs to the DBC: the
 *               caller packs it with the generated codec before
 *               mc_can_e2e_protect computes the CRC).
 *
 * Check value: mc_can_crc8_j1850 of ASCII "123456789" is 0x4B.
 * Pure functions on caller buffers, bounded time (len <= 8).
 * Interrupt context: yes (every function).
 */
#ifndef MC_CAN_E2E_H
#define MC_CAN_E2E_H

#include <stdbool.h>
#include <stdint.h>

#define MC_CAN_E2E_COUNTER_MAX 14u /* the counter runs 0 .. 14 */
#define MC_CAN_E2E_MAX_LEN     8u  /* classic CAN frame */

/* CRC-8/SAE-J1850 of data[0 .. n): initial value 0xFF, final XOR 0xFF.
 * Interrupt context: yes. */
uint8_t mc_can_crc8_j1850(const uint8_t *data, uint32_t n);

/* The E2E CRC of a frame: CRC-8/SAE-J1850 over the identifier's low and
 * high byte (id & 0x7FF) and data[1 .. len). len 1..8 (len 1: the data ID
 * only); 0 for a len outside that range. Interrupt context: yes. */
uint8_t mc_can_e2e_crc(uint32_t id, const uint8_t *data, uint32_t len);

/* Write the E2E CRC of the frame into data[0] (the counter is already in
 * place). false, data untouched, for len outside 1..8. Interrupt context:
 * yes. */
bool mc_can_e2e_protect(uint32_t id, uint8_t *data, uint32_t len);

/* True when data[0] holds the E2E CRC of the frame (len 1..8). The
 * receiver checks the counter sequence itself (mc_can_e2e_counter_next).
 * Interrupt context: yes. */
bool mc_can_e2e_check(uint32_t id, const uint8_t *data, uint32_t len);

/* The counter after c: c + 1, and 0 after MC_CAN_E2E_COUNTER_MAX (or for
 * any c above it). Interrupt context: yes. */
uint8_t mc_can_e2e_counter_next(uint8_t c);

#endif /* MC_CAN_E2E_H */
