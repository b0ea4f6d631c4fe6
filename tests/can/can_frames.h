/*
 * The CAN protocol's frames built and read by hand from the layout of
 * tools/dbc/pmsm_drive.dbc (little-endian signals; float32 as IEEE 754),
 * independently of the codec generated from it, for the CAN tests.
 */
#ifndef CAN_TEST_FRAMES_H
#define CAN_TEST_FRAMES_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "hal/can.h"

/* Message numbers (identifier = node_id * 32 + message number). */
enum {
    CAN_MSG_ENABLE = 1,
    CAN_MSG_MODE = 2,
    CAN_MSG_SPEED = 4,
    CAN_MSG_CLEAR_FAULTS = 6,
    CAN_MSG_PARAM_READ = 7,
    CAN_MSG_PARAM_WRITE = 8,
    CAN_MSG_TELEMETRY_RATE = 10,
    CAN_MSG_TLM_STATUS = 16,
    CAN_MSG_RSP_PARAM = 25,
    CAN_MSG_RSP_ERROR = 26
};

static inline uint32_t can_id(uint32_t node, uint32_t msg)
{
    return node * 32u + msg;
}

/* CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, not reflected, no final
 * XOR): the parameter ids, of "block.field". Check: "123456789" -> 0x29B1. */
static inline uint16_t can_crc16_ccitt_false(const char *s)
{
    uint16_t crc = 0xFFFFu;
    for (; *s != '\0'; ++s) {
        crc ^= (uint16_t)((uint16_t)(uint8_t)*s << 8);
        for (int b = 0; b < 8; ++b) {
            crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
        }
    }
    return crc;
}

/* CRC-8/SAE-J1850 (poly 0x1D, init 0xFF, final XOR 0xFF) over n bytes,
 * continuing from crc (start with 0xFF, XOR 0xFF at the end). */
static inline uint8_t can_crc8_j1850_update(uint8_t crc, const uint8_t *p, unsigned n)
{
    for (unsigned i = 0; i < n; ++i) {
        crc ^= p[i];
        for (int b = 0; b < 8; ++b) {
            crc = (crc & 0x80u) ? (uint8_t)((crc << 1) ^ 0x1Du) : (uint8_t)(crc << 1);
        }
    }
    return crc;
}

/* The E2E CRC of a telemetry frame (the DBC's comment): over the data ID
 * (the 11-bit identifier, low byte then high byte) and bytes 1..7. */
static inline uint8_t can_e2e_crc(const hal_can_frame_t *f)
{
    const uint8_t id[2] = { (uint8_t)(f->id & 0xFFu), (uint8_t)(f->id >> 8) };
    uint8_t crc = can_crc8_j1850_update(0xFFu, id, 2u);
    crc = can_crc8_j1850_update(crc, &f->data[1], 7u);
    return (uint8_t)(crc ^ 0xFFu);
}

static inline void can_put_f32(uint8_t *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    for (int i = 0; i < 4; ++i) {
        p[i] = (uint8_t)(u >> (8 * i));
    }
}

static inline float can_get_f32(const uint8_t *p)
{
    uint32_t u = 0;
    for (int i = 0; i < 4; ++i) {
        u |= (uint32_t)p[i] << (8 * i);
    }
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static inline hal_can_frame_t can_frame(uint32_t node, uint32_t msg, uint8_t dlc)
{
    hal_can_frame_t f = { .id = can_id(node, msg), .dlc = dlc };
    return f;
}

/* Cmd_Enable: Enable 0|1. */
static inline hal_can_frame_t can_cmd_enable(uint32_t node, bool enable)
{
    hal_can_frame_t f = can_frame(node, CAN_MSG_ENABLE, 1u);
    f.data[0] = enable ? 1u : 0u;
    return f;
}

/* Cmd_Mode: Mode 0|8 (0 current, 1 speed, 2 position). */
static inline hal_can_frame_t can_cmd_mode(uint32_t node, uint8_t mode)
{
    hal_can_frame_t f = can_frame(node, CAN_MSG_MODE, 1u);
    f.data[0] = mode;
    return f;
}

/* Cmd_Speed: Omega_ref 0|32 float32, rad/s. */
static inline hal_can_frame_t can_cmd_speed(uint32_t node, float omega_rad_s)
{
    hal_can_frame_t f = can_frame(node, CAN_MSG_SPEED, 4u);
    can_put_f32(f.data, omega_rad_s);
    return f;
}

/* Cmd_TelemetryRate: Telemetry_msg 0|8, Decimation 8|16. */
static inline hal_can_frame_t can_cmd_telemetry_rate(uint32_t node, uint8_t msg,
                                                     uint16_t decimation)
{
    hal_can_frame_t f = can_frame(node, CAN_MSG_TELEMETRY_RATE, 3u);
    f.data[0] = msg;
    f.data[1] = (uint8_t)(decimation & 0xFFu);
    f.data[2] = (uint8_t)(decimation >> 8);
    return f;
}

/* Cmd_ParamRead: Param_id 0|16. */
static inline hal_can_frame_t can_cmd_param_read(uint32_t node, uint16_t param_id)
{
    hal_can_frame_t f = can_frame(node, CAN_MSG_PARAM_READ, 2u);
    f.data[0] = (uint8_t)(param_id & 0xFFu);
    f.data[1] = (uint8_t)(param_id >> 8);
    return f;
}

/* Cmd_ParamWrite of a float32: Param_id 0|16, Param_type 16|8 = 0,
 * Value_f32 24|32. */
static inline hal_can_frame_t can_cmd_param_write_f32(uint32_t node, uint16_t param_id, float v)
{
    hal_can_frame_t f = can_frame(node, CAN_MSG_PARAM_WRITE, 7u);
    f.data[0] = (uint8_t)(param_id & 0xFFu);
    f.data[1] = (uint8_t)(param_id >> 8);
    f.data[2] = 0u;
    can_put_f32(&f.data[3], v);
    return f;
}

/* Cmd_ParamWrite of a bool: Param_id 0|16, Param_type 16|8 = 2,
 * Value_bool 24|8 (DLC 7 as every write). */
static inline hal_can_frame_t can_cmd_param_write_bool(uint32_t node, uint16_t param_id, bool v)
{
    hal_can_frame_t f = can_frame(node, CAN_MSG_PARAM_WRITE, 7u);
    f.data[0] = (uint8_t)(param_id & 0xFFu);
    f.data[1] = (uint8_t)(param_id >> 8);
    f.data[2] = 2u;
    f.data[3] = v ? 1u : 0u;
    return f;
}

/* Tlm_Status fields. */
static inline unsigned can_status_state(const hal_can_frame_t *f) /* 12|4 */
{
    return (f->data[1] >> 4) & 0x0Fu;
}
static inline unsigned can_status_counter(const hal_can_frame_t *f) /* 8|4 */
{
    return f->data[1] & 0x0Fu;
}
static inline unsigned can_status_mode(const hal_can_frame_t *f) /* 16|4 */
{
    return f->data[2] & 0x0Fu;
}
static inline bool can_status_enabled(const hal_can_frame_t *f) /* 23|1 */
{
    return (f->data[2] & 0x80u) != 0u;
}
static inline bool can_status_outputs_on(const hal_can_frame_t *f) /* 20|1 */
{
    return (f->data[2] & 0x10u) != 0u;
}
static inline uint16_t can_status_faults(const hal_can_frame_t *f) /* 24|16 */
{
    return (uint16_t)(f->data[3] | (f->data[4] << 8));
}

/* Rsp_Param fields: Param_id 0|16, Param_type 16|8, Status 24|8,
 * Value 32|32. */
static inline uint16_t can_rsp_param_id(const hal_can_frame_t *f)
{
    return (uint16_t)(f->data[0] | (f->data[1] << 8));
}

#endif /* CAN_TEST_FRAMES_H */
