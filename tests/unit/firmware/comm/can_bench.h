/*
 * The bench of the CAN node tests: a real drive (mc_app_t) on the
 * simulator-mailbox HAL (hal/sim_mailbox, host backend), its CAN node, and
 * the test's OWN encoding of the protocol (little-endian fields, float32
 * bits, CRC-8/SAE-J1850, CRC-16/CCITT-FALSE, written here bit by bit from
 * the DBC's text, not taken from the generated codec or from the
 * firmware), so that the node is checked against the DBC rather than
 * against itself.
 *
 * Time: the mailbox's sim_time_ns; bench_step advances it by one PWM
 * period, runs one fast ISR and polls the node, as the host bench does.
 */
#ifndef CAN_BENCH_H
#define CAN_BENCH_H

#include "mc_test.h"

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "hal_host.h"
#include "mc/app.h"
#include "mc/can_node.h"

#define BENCH_F_PWM_HZ  20000.0f
#define BENCH_PERIOD_NS 50000u
#define BENCH_CALIB_N   8u
#define BENCH_CPR       10000u

/* message numbers and lengths, from the DBC's text */
enum {
    MSG_ENABLE = 1,
    MSG_MODE = 2,
    MSG_CURRENT = 3,
    MSG_SPEED = 4,
    MSG_POSITION = 5,
    MSG_CLEAR = 6,
    MSG_PREAD = 7,
    MSG_PWRITE = 8,
    MSG_CONTROLLER = 9,
    MSG_TRATE = 10,
    MSG_STATUS = 16,
    MSG_CURRENTS = 17,
    MSG_VOLTAGES = 18,
    MSG_MOTION = 19,
    MSG_ESTIMATES = 20,
    MSG_REFERENCES = 21,
    MSG_ISRCOST = 22,
    MSG_ERRORS = 23,
    MSG_COUNTERS = 24,
    MSG_RSP_PARAM = 25,
    MSG_RSP_ERROR = 26
};

/* DBC length of a command (1..10), -1 for other numbers */
static inline int bench_cmd_dlc(uint32_t msg)
{
    static const int dlc[11] = { -1, 1, 1, 8, 4, 4, 0, 2, 7, 1, 3 };
    return (msg <= 10u) ? dlc[msg] : -1;
}

typedef struct {
    hal_sim_mailbox_t mb;
    mc_config_t cfg; /* the drive's configuration at init */
    mc_app_t app;
    mc_can_node_t node;
    mc_can_node_config_t ncfg;
} can_bench_t;

/* ---- the test's own protocol arithmetic --------------------------------- */

static inline uint8_t ref_crc8_j1850(const uint8_t *d, uint32_t n)
{
    uint8_t crc = 0xFFu;
    for (uint32_t i = 0; i < n; ++i) {
        for (int b = 7; b >= 0; --b) {
            const unsigned in = (d[i] >> b) & 1u;
            const unsigned top = (crc >> 7) & 1u;
            crc = (uint8_t)(crc << 1);
            if (in ^ top) {
                crc ^= 0x1Du;
            }
        }
    }
    return (uint8_t)(crc ^ 0xFFu);
}

static inline uint16_t ref_crc16_ccitt_false(const uint8_t *d, uint32_t n)
{
    uint16_t crc = 0xFFFFu;
    for (uint32_t i = 0; i < n; ++i) {
        for (int b = 7; b >= 0; --b) {
            const unsigned in = (d[i] >> b) & 1u;
            const unsigned top = (crc >> 15) & 1u;
            crc = (uint16_t)(crc << 1);
            if (in ^ top) {
                crc ^= 0x1021u;
            }
        }
    }
    return crc;
}

static inline uint16_t ref_param_id(const char *block, const char *field)
{
    char name[160];
    size_t n = 0;
    if (block[0] != '\0') {
        n = strlen(block);
        memcpy(name, block, n);
        name[n++] = '.';
    }
    const size_t m = strlen(field);
    memcpy(name + n, field, m);
    return ref_crc16_ccitt_false((const uint8_t *)name, (uint32_t)(n + m));
}

/* the E2E check of a telemetry frame: CRC over id low, id high, bytes 1..7 */
static inline bool ref_e2e_ok(const hal_can_frame_t *f)
{
    uint8_t buf[10] = { (uint8_t)(f->id & 0xFFu), (uint8_t)((f->id >> 8) & 0x07u) };
    memcpy(&buf[2], &f->data[1], 7);
    return f->dlc == 8u && f->data[0] == ref_crc8_j1850(buf, 9u);
}

static inline void put_u16(uint8_t *d, uint32_t v)
{
    d[0] = (uint8_t)v;
    d[1] = (uint8_t)(v >> 8);
}

static inline void put_u32(uint8_t *d, uint32_t v)
{
    for (int i = 0; i < 4; ++i) {
        d[i] = (uint8_t)(v >> (8 * i));
    }
}

static inline uint32_t f32_bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static inline float bits_f32(uint32_t u)
{
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static inline void put_f32(uint8_t *d, float x)
{
    put_u32(d, f32_bits(x));
}

static inline uint32_t get_u16(const uint8_t *d)
{
    return (uint32_t)d[0] | ((uint32_t)d[1] << 8);
}

static inline uint32_t get_u24(const uint8_t *d)
{
    return (uint32_t)d[0] | ((uint32_t)d[1] << 8) | ((uint32_t)d[2] << 16);
}

static inline uint32_t get_u32(const uint8_t *d)
{
    return get_u24(d) | ((uint32_t)d[3] << 24);
}

static inline int32_t sign_extend(uint32_t v, unsigned bits)
{
    const uint32_t m = 1u << (bits - 1u);
    return (int32_t)((v ^ m) - m);
}

/* ---- the drive and the node ---------------------------------------------- */

static inline void bench_drive_config(mc_config_t *cfg)
{
    mc_config_init_default(cfg);
    cfg->timing.calib_time_s = (float)BENCH_CALIB_N / BENCH_F_PWM_HZ;
    cfg->timing.isr_overrun_limit = MC_TIMING_OVERRUN_LIMIT_MAX; /* host time */
}

/* Mailbox (PWM, encoder, 48 V bus, CAN up), drive, node. */
static inline void bench_init(can_bench_t *b, const mc_can_node_config_t *ncfg,
                              mc_can_apply_config_fn apply, void *ctx)
{
    hal_sim_mailbox_reset(&b->mb);
    b->mb.pwm_f_Hz = BENCH_F_PWM_HZ;
    b->mb.pwm_delay_periods = 1.0f; /* duties apply at the next period */
    b->mb.encoder_cpr = BENCH_CPR;
    b->mb.adc.v_dc_V = 48.0f;
    b->mb.sim_time_ns = 1000000u; /* 1 ms after power-up */
    hal_sim_bind(&b->mb);
    assert_int_equal(hal_can_init(1000000u), HAL_OK);
    bench_drive_config(&b->cfg);
    assert_int_equal(mc_app_init(&b->app, &b->cfg), MC_OK);
    b->ncfg = *ncfg;
    assert_int_equal(mc_can_node_init(&b->node, ncfg, &b->cfg, apply, ctx), MC_OK);
}

static inline uint32_t bench_id(const can_bench_t *b, uint32_t msg)
{
    return b->node.cfg.node_id * 32u + msg;
}

static inline void bench_poll(can_bench_t *b)
{
    mc_can_node_poll(&b->node, &b->app);
}

/* one PWM period: time, fast ISR, poll */
static inline void bench_step(can_bench_t *b)
{
    b->mb.sim_time_ns += BENCH_PERIOD_NS;
    mc_app_fast_isr(&b->app);
    bench_poll(b);
}

static inline void bench_deliver_raw(can_bench_t *b, uint32_t id, bool ext, bool rtr, uint8_t dlc,
                                     const uint8_t *data)
{
    hal_can_frame_t f = { .id = id, .extended = ext, .rtr = rtr, .dlc = dlc };
    for (uint32_t i = 0; i < dlc && i < 8u; ++i) {
        f.data[i] = data[i];
    }
    assert_true(hal_sim_can_deliver(&b->mb, &f));
}

/* a data frame of our node */
static inline void bench_send(can_bench_t *b, uint32_t msg, uint8_t dlc, const uint8_t *data)
{
    bench_deliver_raw(b, bench_id(b, msg), false, false, dlc, data);
}

static inline void bench_send_u8(can_bench_t *b, uint32_t msg, uint8_t v)
{
    bench_send(b, msg, 1u, &v);
}

static inline void bench_send_f32(can_bench_t *b, uint32_t msg, float v)
{
    uint8_t d[4];
    put_f32(d, v);
    bench_send(b, msg, 4u, d);
}

static inline void bench_send_current(can_bench_t *b, float i_d, float i_q)
{
    uint8_t d[8];
    put_f32(d, i_d);
    put_f32(d + 4, i_q);
    bench_send(b, MSG_CURRENT, 8u, d);
}

static inline void bench_send_rate(can_bench_t *b, uint32_t tlm_msg, uint32_t decimation)
{
    uint8_t d[3] = { (uint8_t)tlm_msg };
    put_u16(d + 1, decimation);
    bench_send(b, MSG_TRATE, 3u, d);
}

static inline void bench_send_pread(can_bench_t *b, uint32_t id)
{
    uint8_t d[2];
    put_u16(d, id);
    bench_send(b, MSG_PREAD, 2u, d);
}

/* type 0: value = float bits, 1: u32, 2: bool byte */
static inline void bench_send_pwrite(can_bench_t *b, uint32_t id, uint8_t type, uint32_t value)
{
    uint8_t d[7] = { 0 };
    put_u16(d, id);
    d[2] = type;
    if (type == 2u) {
        d[3] = (uint8_t)value;
    } else {
        put_u32(d + 3, value);
    }
    bench_send(b, MSG_PWRITE, 7u, d);
}

static inline bool bench_collect(can_bench_t *b, hal_can_frame_t *f)
{
    return hal_sim_can_collect(&b->mb, f);
}

static inline void bench_drain(can_bench_t *b)
{
    hal_can_frame_t f;
    while (bench_collect(b, &f)) {
    }
}

/* The next frame that is not telemetry (a reply), asserting there is one. */
static inline hal_can_frame_t bench_reply(can_bench_t *b)
{
    hal_can_frame_t f;
    for (;;) {
        assert_true(bench_collect(b, &f));
        const uint32_t msg = f.id & 31u;
        if (msg == MSG_RSP_PARAM || msg == MSG_RSP_ERROR) {
            return f;
        }
    }
}

/* No reply queued (telemetry may be). */
static inline void bench_assert_no_reply(can_bench_t *b)
{
    hal_can_frame_t f;
    while (bench_collect(b, &f)) {
        const uint32_t msg = f.id & 31u;
        assert_true(msg >= MSG_STATUS && msg <= MSG_COUNTERS);
    }
}

typedef struct {
    uint32_t id;
    uint32_t type;
    uint32_t status;
    uint32_t raw; /* the value field, 4 bytes little-endian (bool: byte 4) */
} rsp_param_t;

static inline rsp_param_t decode_rsp_param(const can_bench_t *b, const hal_can_frame_t *f)
{
    assert_int_equal(f->id, bench_id(b, MSG_RSP_PARAM));
    assert_false(f->extended);
    assert_int_equal(f->dlc, 8);
    rsp_param_t r = { get_u16(f->data), f->data[2], f->data[3], get_u32(&f->data[4]) };
    if (r.type == 2u) {
        r.raw = f->data[4];
    }
    return r;
}

static inline void assert_rsp_error(const can_bench_t *b, const hal_can_frame_t *f, uint32_t msg,
                                    uint32_t cause, uint32_t dlc)
{
    assert_int_equal(f->id, bench_id(b, MSG_RSP_ERROR));
    assert_false(f->extended);
    assert_int_equal(f->dlc, 3);
    assert_int_equal(f->data[0], msg);
    assert_int_equal(f->data[1], cause);
    assert_int_equal(f->data[2], dlc);
}

/* The command the drive holds (the buffer mc_app_set_command wrote last;
 * the test reads the drive's private double buffer to see it without
 * running an ISR). */
static inline mc_command_t bench_app_command(const can_bench_t *b)
{
    return b->app.cmd_buf[b->app.cmd_index & 1u];
}

static inline bool command_equal(const mc_command_t *a, const mc_command_t *c)
{
    return a->enable == c->enable && a->clear_fault == c->clear_fault && a->mode == c->mode &&
           f32_bits(a->i_d_ref_A) == f32_bits(c->i_d_ref_A) &&
           f32_bits(a->i_q_ref_A) == f32_bits(c->i_q_ref_A) &&
           f32_bits(a->omega_m_ref_rad_s) == f32_bits(c->omega_m_ref_rad_s) &&
           f32_bits(a->theta_m_ref_rad) == f32_bits(c->theta_m_ref_rad) &&
           a->comm_lost == c->comm_lost;
}

static inline mc_telemetry_t bench_tlm(const can_bench_t *b)
{
    mc_telemetry_t t;
    assert_int_equal(mc_app_get_telemetry(&b->app, &t), MC_OK);
    return t;
}

static inline uint32_t rejected_total(const mc_can_counters_t *c)
{
    uint32_t s = 0;
    for (unsigned k = 0; k < MC_CAN_REJ_COUNT; ++k) {
        s += c->rejected[k];
    }
    return s;
}

#endif /* CAN_BENCH_H */
