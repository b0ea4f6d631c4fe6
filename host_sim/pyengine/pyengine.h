/*
 * The simulated drive as a shared library (libpmsm_engine.so) for tests in
 * other languages (the telemetry tool's pytest loads it with ctypes): a
 * shipped scenario file's plant and firmware in one engine whose command
 * comes from its CAN node (mc/can_node.h), stepped by the caller, with
 * frames in and out. Not thread-safe: one caller thread per handle.
 */
#ifndef PYENGINE_H
#define PYENGINE_H

#include <stdint.h>

typedef struct pe pe_t;

#define PE_FRAME_EXTENDED 1
#define PE_FRAME_RTR      2

/* Load the scenario file with --set-style overrides set[0 .. n_set-1],
 * build its engine and attach a CAN node (node_id 0..63, command timeout
 * timeout_s). NULL on error, with the message in err (err_len bytes). */
pe_t *pe_open(const char *scenario_file, const char *const *set, int n_set, uint32_t node_id,
              double timeout_s, char *err, int err_len);

/* Step n PWM periods (n >= 0). 0, or the engine's error code (negative)
 * of the first failing step. */
int pe_step(pe_t *h, int n);

/* Simulated time (s) and the plant's true mechanical speed (rad/s). */
double pe_time_s(const pe_t *h);
double pe_speed_rad_s(const pe_t *h);

/* A frame to the drive: 1 queued, 0 its receive queue was full (counted
 * as an overrun), -1 a bad frame (dlc > 8, id too large). */
int pe_deliver(pe_t *h, uint32_t id, uint32_t dlc, const uint8_t *data, int flags);

/* The oldest frame the drive sent: 1 taken (data: 8 bytes), 0 none. */
int pe_collect(pe_t *h, uint32_t *id, uint32_t *dlc, uint8_t *data, int *flags);

void pe_close(pe_t *h);

#endif /* PYENGINE_H */
