/*
 * The CAN node (mc/can_node.h) on a real drive over the simulator-mailbox
 * HAL (can_bench.h): every rejection cause (counted, answered, nothing
 * changed), the frames that are not the node's, commands reaching the
 * drive, telemetry at the requested decimations with the E2E protection
 * checked by the test's own CRC, the command timeout latching
 * MC_FAULT_COMM_TIMEOUT, the ClearFaults pulse, and the parameter
 * protocol (read of every parameter, write, validation, refusals, the
 * apply callback).
 */
#include "can_bench.h"

#include <math.h>
#include <stdlib.h>

#include "mc/can_params.h"

static can_bench_t bench;

/* ---- apply callback: counts, re-initialises the drive as the host bench
 * does, or fails with a chosen status ------------------------------------- */

static struct {
    uint32_t calls;
    mc_status_t result; /* MC_OK: re-initialise the drive */
    mc_config_t last;
} applied;

static mc_status_t apply_cb(void *ctx, const mc_config_t *cfg)
{
    can_bench_t *b = ctx;
    applied.calls++;
    applied.last = *cfg;
    assert_int_equal(mc_config_validate(cfg), MC_OK); /* the node validated it */
    if (applied.result != MC_OK) {
        return applied.result;
    }
    return mc_app_init(&b->app, cfg);
}

static int setup(void **state)
{
    (void)state;
    mc_can_node_config_t nc;
    mc_can_node_config_default(&nc);
    nc.node_id = 5u;
    applied.calls = 0u;
    applied.result = MC_OK;
    bench_init(&bench, &nc, apply_cb, &bench);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    hal_sim_bind(NULL);
    return 0;
}

/* What a rejected frame must leave alone. */
typedef struct {
    mc_command_t node_cmd, app_cmd;
    mc_config_t drive_cfg;
    mc_can_node_config_t ncfg;
    mc_state_t state;
    uint64_t last_valid;
} snapshot_t;

static snapshot_t snap(void)
{
    snapshot_t s = {
        .node_cmd = bench.node.cmd,
        .app_cmd = bench_app_command(&bench),
        .drive_cfg = bench.node.drive_cfg,
        .ncfg = bench.node.cfg,
        .state = bench_tlm(&bench).state,
        .last_valid = bench.node.last_valid_ticks,
    };
    return s;
}

static void assert_unchanged(const snapshot_t *s)
{
    assert_true(command_equal(&s->node_cmd, &bench.node.cmd));
    const mc_command_t app_cmd = bench_app_command(&bench);
    assert_true(command_equal(&s->app_cmd, &app_cmd));
    assert_memory_equal(&s->drive_cfg, &bench.node.drive_cfg, sizeof(mc_config_t));
    assert_memory_equal(&s->ncfg, &bench.node.cfg, sizeof(mc_can_node_config_t));
    assert_int_equal(s->state, bench_tlm(&bench).state);
    assert_int_equal(s->last_valid, bench.node.last_valid_ticks);
}

/* Deliver one frame of our node and poll: it was taken, not accepted,
 * and counted once under `cause`; its reply. */
static hal_can_frame_t send_rejected(uint32_t msg, uint8_t dlc, const uint8_t *data, uint32_t cause)
{
    const mc_can_counters_t before = bench.node.counters;
    bench_drain(&bench);
    bench_send(&bench, msg, dlc, data);
    bench_poll(&bench);
    const mc_can_counters_t *c = mc_can_node_counters(&bench.node);
    assert_int_equal(c->rx_frames, before.rx_frames + 1u);
    assert_int_equal(c->rx_accepted, before.rx_accepted);
    for (uint32_t k = 0; k < MC_CAN_REJ_COUNT; ++k) {
        assert_int_equal(c->rejected[k], before.rejected[k] + (k == cause ? 1u : 0u));
    }
    return bench_reply(&bench);
}

/* Deliver one frame of our node, poll, expect exactly one rejection of
 * `cause` answered by Rsp_Error, and nothing changed. */
static void expect_rsp_error(uint32_t msg, uint8_t dlc, const uint8_t *data, uint32_t cause)
{
    const snapshot_t s = snap();
    const hal_can_frame_t r = send_rejected(msg, dlc, data, cause);
    assert_rsp_error(&bench, &r, msg, cause, dlc > 8u ? 8u : dlc);
    bench_assert_no_reply(&bench);
    assert_unchanged(&s);
}

/* ---- init ---------------------------------------------------------------- */

static void test_config_default_and_init_checks(void **state)
{
    (void)state;
    mc_can_node_config_t c;
    mc_can_node_config_default(&c);
    assert_int_equal(c.node_id, 0u);
    assert_true(c.timeout_s == 0.1f);
    for (uint32_t k = 0; k < MC_CAN_TLM_COUNT; ++k) {
        assert_int_equal(c.decimation[k], k == 0u ? 1000u : 0u);
    }
    mc_can_node_t n;
    memset(&n, 0xA5, sizeof n);
    const mc_can_node_t untouched = n;
    const struct {
        uint32_t node_id;
        float timeout_s;
        mc_status_t expect;
    } cases[] = {
        { 63u, 0.1f, MC_OK },          { 64u, 0.1f, MC_ERR_PARAM },    { 0u, 60.0f, MC_OK },
        { 0u, 60.001f, MC_ERR_PARAM }, { 0u, 0.0f, MC_ERR_PARAM },     { 0u, -0.1f, MC_ERR_PARAM },
        { 0u, NAN, MC_ERR_PARAM },     { 0u, INFINITY, MC_ERR_PARAM }, { 0u, 1e-6f, MC_OK },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        c.node_id = cases[i].node_id;
        c.timeout_s = cases[i].timeout_s;
        memset(&n, 0xA5, sizeof n);
        assert_int_equal(mc_can_node_init(&n, &c, &bench.cfg, NULL, NULL), cases[i].expect);
        if (cases[i].expect != MC_OK) {
            assert_memory_equal(&n, &untouched, sizeof n);
        } else {
            assert_false(n.cmd.enable);
            assert_int_equal(n.cmd.mode, MC_MODE_CURRENT);
            assert_int_equal(n.counters.rx_frames, 0u);
        }
    }
    c.node_id = 1u;
    c.timeout_s = 0.1f;
    assert_int_equal(mc_can_node_init(NULL, &c, &bench.cfg, NULL, NULL), MC_ERR_PARAM);
    assert_int_equal(mc_can_node_init(&n, NULL, &bench.cfg, NULL, NULL), MC_ERR_PARAM);
    assert_int_equal(mc_can_node_init(&n, &c, NULL, NULL, NULL), MC_ERR_PARAM);
    /* the timeout in ticks of the mailbox (1 ns) */
    assert_int_equal(mc_can_node_init(&n, &c, &bench.cfg, NULL, NULL), MC_OK);
    assert_int_equal(n.timeout_ticks, 100000000u);
}

/* ---- (a) each rejection cause --------------------------------------------- */

static void test_reject_unknown_message(void **state)
{
    (void)state;
    const uint8_t d[8] = { 1, 2, 3, 4, 5, 6, 7, 8 };
    const uint32_t unknown[] = { 0u, 11u, 12u, 15u, 27u, 31u };
    for (size_t i = 0; i < sizeof unknown / sizeof unknown[0]; ++i) {
        expect_rsp_error(unknown[i], 1u, d, MC_CAN_REJ_UNKNOWN_MESSAGE);
        expect_rsp_error(unknown[i], 8u, d, MC_CAN_REJ_UNKNOWN_MESSAGE);
    }
    /* extended or remote frames with our node id, even a valid command */
    for (int k = 0; k < 3; ++k) {
        const snapshot_t s = snap();
        const uint32_t before = bench.node.counters.rejected[MC_CAN_REJ_UNKNOWN_MESSAGE];
        const uint8_t on = 1u;
        bench_deliver_raw(&bench, bench_id(&bench, MSG_ENABLE), k != 1, k != 0, 1u, &on);
        bench_poll(&bench);
        assert_int_equal(bench.node.counters.rejected[MC_CAN_REJ_UNKNOWN_MESSAGE], before + 1u);
        const hal_can_frame_t r = bench_reply(&bench);
        assert_rsp_error(&bench, &r, MSG_ENABLE, MC_CAN_REJ_UNKNOWN_MESSAGE, 1u);
        assert_unchanged(&s);
        assert_false(bench.node.cmd.enable);
    }
}

static void test_reject_wrong_dlc(void **state)
{
    (void)state;
    const uint8_t d[8] = { 0 };
    for (uint32_t msg = 1u; msg <= 10u; ++msg) {
        const int len = bench_cmd_dlc(msg);
        for (int dlc = 0; dlc <= 8; ++dlc) {
            if (dlc != len) {
                expect_rsp_error(msg, (uint8_t)dlc, d, MC_CAN_REJ_WRONG_DLC);
            }
        }
    }
    /* a DLC over 8 (a binding outside hal/can.h) is reported as 8 */
    expect_rsp_error(MSG_ENABLE, 9u, d, MC_CAN_REJ_WRONG_DLC);
    expect_rsp_error(MSG_CURRENT, 15u, d, MC_CAN_REJ_WRONG_DLC);
}

static void test_reject_bad_value(void **state)
{
    (void)state;
    uint8_t d[8];
    /* Cmd_Mode 0..2 */
    d[0] = 3u;
    expect_rsp_error(MSG_MODE, 1u, d, MC_CAN_REJ_BAD_VALUE);
    d[0] = 255u;
    expect_rsp_error(MSG_MODE, 1u, d, MC_CAN_REJ_BAD_VALUE);
    /* float setpoints: non-finite or outside the DBC range, never clamped */
    const float bad_i[] = { NAN, INFINITY, -INFINITY, 1000.0001f, -1000.0001f, 3e38f };
    for (size_t i = 0; i < sizeof bad_i / sizeof bad_i[0]; ++i) {
        put_f32(d, 1.0f);
        put_f32(d + 4, bad_i[i]);
        expect_rsp_error(MSG_CURRENT, 8u, d, MC_CAN_REJ_BAD_VALUE);
        put_f32(d, bad_i[i]);
        put_f32(d + 4, 1.0f);
        expect_rsp_error(MSG_CURRENT, 8u, d, MC_CAN_REJ_BAD_VALUE);
    }
    put_f32(d, 10000.001f);
    expect_rsp_error(MSG_SPEED, 4u, d, MC_CAN_REJ_BAD_VALUE);
    put_f32(d, -NAN);
    expect_rsp_error(MSG_SPEED, 4u, d, MC_CAN_REJ_BAD_VALUE);
    put_f32(d, -1000000.1f);
    expect_rsp_error(MSG_POSITION, 4u, d, MC_CAN_REJ_BAD_VALUE);
    put_f32(d, INFINITY);
    expect_rsp_error(MSG_POSITION, 4u, d, MC_CAN_REJ_BAD_VALUE);
    /* telemetry rate of a message that is no telemetry */
    const uint8_t not_tlm[] = { 0u, 15u, 25u, 26u, 255u };
    for (size_t i = 0; i < sizeof not_tlm; ++i) {
        d[0] = not_tlm[i];
        put_u16(d + 1, 10u);
        expect_rsp_error(MSG_TRATE, 3u, d, MC_CAN_REJ_BAD_VALUE);
    }
    /* Cmd_Controller 0..3 */
    d[0] = 4u;
    expect_rsp_error(MSG_CONTROLLER, 1u, d, MC_CAN_REJ_BAD_VALUE);
    /* Cmd_ParamWrite: type outside 0..2, non-finite or out-of-range f32,
     * bool other than 0/1 (whatever the id) */
    const uint16_t kp = ref_param_id("position", "kp_per_s");
    memset(d, 0, sizeof d);
    put_u16(d, kp);
    d[2] = 3u;
    expect_rsp_error(MSG_PWRITE, 7u, d, MC_CAN_REJ_BAD_VALUE);
    d[2] = 0u;
    put_f32(d + 3, NAN);
    expect_rsp_error(MSG_PWRITE, 7u, d, MC_CAN_REJ_BAD_VALUE);
    put_f32(d + 3, 3.401e38f);
    expect_rsp_error(MSG_PWRITE, 7u, d, MC_CAN_REJ_BAD_VALUE);
    put_u16(d, ref_param_id("timing", "delay_compensation"));
    d[2] = 2u;
    d[3] = 2u;
    expect_rsp_error(MSG_PWRITE, 7u, d, MC_CAN_REJ_BAD_VALUE);
    assert_int_equal(applied.calls, 0u);
}

/* A parameter command rejected at the parameter level: counted by cause,
 * answered by Rsp_Param with its status (no Rsp_Error), nothing changed. */
static rsp_param_t expect_rsp_param_reject(uint32_t msg, uint8_t dlc, const uint8_t *data,
                                           uint32_t cause, uint32_t status)
{
    const snapshot_t s = snap();
    const hal_can_frame_t r = send_rejected(msg, dlc, data, cause);
    const rsp_param_t p = decode_rsp_param(&bench, &r);
    assert_int_equal(p.status, status);
    bench_assert_no_reply(&bench);
    assert_unchanged(&s);
    return p;
}

static void test_reject_parameter_level(void **state)
{
    (void)state;
    /* an id no parameter has (the test's own CRC) */
    const uint16_t unknown = ref_param_id("no_such_block", "field");
    mc_can_param_ref_t ref;
    assert_false(mc_can_param_find(unknown, &ref));
    uint8_t d[8] = { 0 };
    put_u16(d, unknown);
    rsp_param_t p = expect_rsp_param_reject(MSG_PREAD, 2u, d, MC_CAN_REJ_UNKNOWN_PARAM, 1u);
    assert_int_equal(p.id, unknown);
    d[2] = 0u;
    put_f32(d + 3, 1.0f);
    p = expect_rsp_param_reject(MSG_PWRITE, 7u, d, MC_CAN_REJ_UNKNOWN_PARAM, 1u);
    assert_int_equal(p.id, unknown);

    /* wrong type: u32 to a float parameter, f32 to a u32 one, bool to the
     * controller; the reply carries the parameter's type and value */
    const uint16_t kp = ref_param_id("position", "kp_per_s");
    put_u16(d, kp);
    d[2] = 1u;
    put_u32(d + 3, 7u);
    p = expect_rsp_param_reject(MSG_PWRITE, 7u, d, MC_CAN_REJ_WRONG_PARAM_TYPE, 4u);
    assert_int_equal(p.type, 0u);
    assert_int_equal(p.raw, f32_bits(bench.cfg.position.kp_per_s));
    put_u16(d, ref_param_id("motor", "pole_pairs"));
    d[2] = 0u;
    put_f32(d + 3, 3.0f);
    p = expect_rsp_param_reject(MSG_PWRITE, 7u, d, MC_CAN_REJ_WRONG_PARAM_TYPE, 4u);
    assert_int_equal(p.type, 1u);
    assert_int_equal(p.raw, bench.cfg.motor.pole_pairs);
    put_u16(d, ref_param_id("", "controller"));
    d[2] = 2u;
    d[3] = 1u;
    (void)expect_rsp_param_reject(MSG_PWRITE, 7u, d, MC_CAN_REJ_WRONG_PARAM_TYPE, 4u);

    /* a value the validation rejects: status 3, cause BAD_VALUE */
    put_u16(d, kp);
    d[2] = 0u;
    put_f32(d + 3, -1.0f);
    p = expect_rsp_param_reject(MSG_PWRITE, 7u, d, MC_CAN_REJ_BAD_VALUE, 3u);
    assert_int_equal(p.raw, f32_bits(bench.cfg.position.kp_per_s)); /* still in force */
    /* an estimator id outside the list */
    put_u16(d, ref_param_id("", "estimator"));
    d[2] = 1u;
    put_u32(d + 3, 99u);
    (void)expect_rsp_param_reject(MSG_PWRITE, 7u, d, MC_CAN_REJ_BAD_VALUE, 3u);
    assert_int_equal(applied.calls, 0u);
}

/* Frames that are not the node's: not counted, not answered. */
static void test_ignored_frames(void **state)
{
    (void)state;
    const uint8_t on = 1u;
    const snapshot_t s = snap();
    bench_drain(&bench);
    /* another node's command */
    bench_deliver_raw(&bench, 4u * 32u + MSG_ENABLE, false, false, 1u, &on);
    bench_deliver_raw(&bench, 6u * 32u + 0u, false, false, 0u, &on);
    /* our node id with a number the drive sends, any flags */
    for (uint32_t msg = 16u; msg <= 26u; ++msg) {
        const uint8_t d[8] = { 0 };
        bench_deliver_raw(&bench, bench_id(&bench, msg), false, false, 8u, d);
        bench_deliver_raw(&bench, bench_id(&bench, msg), false, true, 0u, d);
    }
    /* 29-bit identifiers beyond the 11-bit range */
    bench_deliver_raw(&bench, 0x10000u + bench_id(&bench, MSG_ENABLE), true, false, 1u, &on);
    bench_deliver_raw(&bench, 0x1FFFFFFFu, true, true, 0u, &on);
    for (int k = 0; k < 3; ++k) {
        bench_poll(&bench);
    }
    assert_int_equal(bench.node.counters.rx_frames, 0u);
    assert_int_equal(rejected_total(&bench.node.counters), 0u);
    bench_assert_no_reply(&bench);
    assert_unchanged(&s);
}

/* ---- (c) commands reach the drive, telemetry -------------------------------- */

static void test_enable_speed_reaches_drive(void **state)
{
    (void)state;
    bench_send_u8(&bench, MSG_MODE, 1u);
    bench_send_f32(&bench, MSG_SPEED, 100.0f);
    bench_send_f32(&bench, MSG_POSITION, -2.5f);
    bench_send_current(&bench, 0.25f, -0.5f);
    bench_send_u8(&bench, MSG_ENABLE, 1u);
    bench_poll(&bench);
    assert_int_equal(bench.node.counters.rx_accepted, 5u);
    assert_int_equal(rejected_total(&bench.node.counters), 0u);
    bench_assert_no_reply(&bench);
    const mc_command_t c = bench_app_command(&bench);
    assert_true(c.enable);
    assert_int_equal(c.mode, MC_MODE_SPEED);
    assert_true(c.omega_m_ref_rad_s == 100.0f);
    assert_true(c.theta_m_ref_rad == -2.5f);
    assert_true(c.i_d_ref_A == 0.25f && c.i_q_ref_A == -0.5f);
    assert_false(c.comm_lost || c.clear_fault);
    bench_step(&bench);
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_CALIBRATING);
    for (uint32_t k = 0; k < BENCH_CALIB_N + 2u; ++k) {
        bench_step(&bench);
    }
    const mc_telemetry_t t = bench_tlm(&bench);
    assert_int_equal(t.state, MC_STATE_RUN);
    assert_int_equal(t.mode, MC_MODE_SPEED);
    assert_true(bench_app_command(&bench).omega_m_ref_rad_s == 100.0f); /* the ISR's */
    assert_true(bench.mb.pwm_outputs_enabled);
    /* Enable 0 stops it in the next ISR */
    bench_send_u8(&bench, MSG_ENABLE, 0u);
    bench_poll(&bench);
    bench_step(&bench);
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_IDLE);
    assert_false(bench.mb.pwm_outputs_enabled);
}

typedef struct {
    uint32_t n;
    uint32_t last_counter;
    uint32_t isr_at[64];
} tlm_log_t;

static void test_telemetry_decimation_e2e(void **state)
{
    (void)state;
    /* check values of the test's own CRCs */
    assert_int_equal(ref_crc8_j1850((const uint8_t *)"123456789", 9u), 0x4Bu);
    assert_int_equal(ref_crc16_ccitt_false((const uint8_t *)"123456789", 9u), 0x29B1u);

    const uint32_t dec[MC_CAN_TLM_COUNT] = { 1u, 3u, 0u, 7u, 2u, 0u, 5u, 4u, 6u };
    for (uint32_t k = 0; k < MC_CAN_TLM_COUNT; ++k) {
        bench_send_rate(&bench, 16u + k, dec[k]);
    }
    bench_poll(&bench);
    assert_int_equal(bench.node.counters.rx_accepted, MC_CAN_TLM_COUNT);
    for (uint32_t k = 0; k < MC_CAN_TLM_COUNT; ++k) {
        assert_int_equal(bench.node.cfg.decimation[k], dec[k]);
    }
    bench_drain(&bench); /* the first frames of that poll (isr_count 0) */
    static tlm_log_t log[MC_CAN_TLM_COUNT];
    memset(log, 0, sizeof log);
    const uint32_t steps = 42u;
    for (uint32_t s = 0; s < steps; ++s) {
        bench_step(&bench);
        const uint32_t isr = bench_tlm(&bench).isr_count;
        hal_can_frame_t f;
        while (bench_collect(&bench, &f)) {
            const uint32_t msg = f.id & 31u;
            assert_int_equal(f.id >> 5, 5u);
            assert_false(f.extended || f.rtr);
            assert_true(msg >= 16u && msg <= 24u);
            assert_true(ref_e2e_ok(&f));
            tlm_log_t *l = &log[msg - 16u];
            const uint32_t counter = f.data[1] & 0x0Fu;
            assert_true(counter <= 14u);
            if (l->n > 0u) {
                assert_int_equal(counter, (l->last_counter + 1u) % 15u);
            }
            l->last_counter = counter;
            l->isr_at[l->n++] = isr;
            /* one corrupted bit anywhere fails the check */
            hal_can_frame_t g = f;
            g.data[1 + s % 7u] ^= (uint8_t)(1u << (s % 8u));
            assert_false(ref_e2e_ok(&g));
            g = f;
            g.id ^= 0x20u; /* another node's data ID */
            assert_false(ref_e2e_ok(&g));
        }
    }
    for (uint32_t k = 0; k < MC_CAN_TLM_COUNT; ++k) {
        if (dec[k] == 0u) {
            assert_int_equal(log[k].n, 0u);
            continue;
        }
        /* the first poll sent one at isr_count 0; then every dec ISRs */
        assert_int_equal(log[k].n, steps / dec[k]);
        for (uint32_t j = 0; j < log[k].n; ++j) {
            assert_int_equal(log[k].isr_at[j], (j + 1u) * dec[k]);
        }
    }
    assert_true(log[0].n > 15u); /* the status counter wrapped */
    assert_int_equal(bench.node.counters.tx_drops, 0u);
}

/* Telemetry values against the drive's snapshot (decoded by the test). */
static void test_telemetry_values(void **state)
{
    (void)state;
    for (uint32_t k = 0; k < MC_CAN_TLM_COUNT; ++k) {
        bench_send_rate(&bench, 16u + k, 1u);
    }
    bench_send_u8(&bench, MSG_MODE, 7u);                   /* rejected: bad value */
    bench_send(&bench, MSG_ENABLE, 2u, (uint8_t[2]){ 0 }); /* rejected: DLC */
    bench_send_u8(&bench, MSG_ENABLE, 1u);
    bench_poll(&bench);
    for (uint32_t s = 0; s < BENCH_CALIB_N + 5u; ++s) {
        bench_drain(&bench);
        bench_step(&bench);
    }
    const mc_telemetry_t t = bench_tlm(&bench);
    assert_int_equal(t.state, MC_STATE_RUN);
    hal_can_frame_t f;
    uint32_t seen = 0;
    while (bench_collect(&bench, &f)) {
        const uint8_t *d = f.data;
        switch (f.id & 31u) {
        case MSG_STATUS:
            assert_int_equal(d[1] >> 4, MC_STATE_RUN);
            assert_int_equal(d[2] & 0x0Fu, MC_MODE_CURRENT);
            assert_int_equal((d[2] >> 4) & 1u, 1u); /* outputs on */
            assert_int_equal((d[2] >> 7) & 1u, 1u); /* enabled */
            assert_int_equal(get_u16(&d[3]), t.faults_latched & 0xFFFFu);
            assert_int_equal(get_u16(&d[5]), t.first_fault & 0xFFFFu);
            assert_int_equal(d[7], (uint32_t)bench.node.drive_cfg.controller);
            break;
        case MSG_CURRENTS:
            assert_near(sign_extend(get_u16(&d[2]), 16) * 0.002, t.i_d_A, 0.0011);
            assert_near(sign_extend(get_u16(&d[4]), 16) * 0.002, t.i_q_A, 0.0011);
            assert_int_equal(get_u16(&d[6]), 4800u); /* 48 V */
            break;
        case MSG_VOLTAGES:
            assert_near(sign_extend(get_u16(&d[2]), 16) * 0.01, t.v_d_V, 0.0051);
            assert_near(sign_extend(get_u16(&d[4]), 16) * 0.01, t.v_q_V, 0.0051);
            break;
        case MSG_MOTION:
            assert_near(sign_extend(get_u24(&d[2]), 24) * 0.001, t.omega_m_rad_s, 0.00051);
            assert_near(sign_extend(get_u24(&d[5]), 24) * 0.001, t.theta_m_rad, 0.00051);
            break;
        case MSG_ESTIMATES: {
            double th = fmod((double)t.theta_e_rad, MC_TEST_TWO_PI);
            th += (th < 0.0) ? MC_TEST_TWO_PI : 0.0;
            assert_near(get_u16(&d[2]) * 9.58737992428526e-05, th, 5e-5);
            assert_near(get_u16(&d[6]) * 0.0001, t.flux_ratio_sq, 0.00006);
            break;
        }
        case MSG_ISRCOST:
            assert_near(get_u16(&d[2]) * 0.01, t.isr_cost_s * 1e6, 0.0051);
            assert_near(get_u16(&d[4]) * 0.01, fmin(t.isr_cost_max_s * 1e6, 655.35), 0.0051);
            break;
        case MSG_ERRORS:
            assert_int_equal(d[2], 0u);
            assert_int_equal(d[3], 1u); /* the wrong DLC */
            assert_int_equal(d[4], 1u); /* the bad mode */
            assert_int_equal(d[5], 0u);
            assert_int_equal(d[7], 0u);
            break;
        case MSG_COUNTERS: assert_int_equal(get_u24(&d[2]), t.isr_overruns); break;
        default: break;
        }
        seen++;
    }
    assert_int_equal(seen, MC_CAN_TLM_COUNT);
}

/* The ISR cost mean over the snapshots since the previous frame. */
static void test_isr_cost_mean(void **state)
{
    (void)state;
    bench_send_rate(&bench, MSG_STATUS, 0u);
    bench_send_rate(&bench, MSG_ISRCOST, 4u);
    bench_poll(&bench);
    bench_drain(&bench);
    double sum = 0.0;
    uint32_t n = 0;
    for (uint32_t s = 1; s <= 12u; ++s) {
        bench_step(&bench);
        const mc_telemetry_t t = bench_tlm(&bench);
        sum += (double)t.isr_cost_s;
        n++;
        hal_can_frame_t f;
        if (bench_collect(&bench, &f)) {
            assert_int_equal(s % 4u, 0u);
            assert_near(get_u16(&f.data[6]) * 0.01, fmin(1e6 * sum / n, 655.35), 0.0051 + 1e-3);
            sum = 0.0;
            n = 0;
        }
    }
}

/* Telemetry is skipped, not blocked, when the HAL queue is full; the
 * counter still advances (a gap shows the loss). */
static void test_tx_queue_full_drops(void **state)
{
    (void)state;
    bench_send_rate(&bench, MSG_STATUS, 1u);
    bench_send_rate(&bench, MSG_CURRENTS, 1u);
    bench_poll(&bench);
    for (uint32_t s = 0; s < 40u; ++s) { /* 2 frames per ISR, queue of 64 */
        bench_step(&bench);
    }
    assert_int_equal(bench.node.counters.tx_frames + bench.node.counters.tx_drops, 2u + 80u);
    assert_int_equal(bench.node.counters.tx_frames, HAL_SIM_CAN_QUEUE_LEN);
    assert_int_equal(bench.node.counters.tx_drops, 82u - HAL_SIM_CAN_QUEUE_LEN);
    bench_drain(&bench);
    bench_step(&bench);
    hal_can_frame_t f;
    assert_true(bench_collect(&bench, &f));
    assert_int_equal(f.id & 31u, MSG_STATUS);
    assert_int_equal(f.data[1] & 0x0Fu, 41u % 15u); /* the 42nd status frame */
    bench_send_rate(&bench, MSG_ERRORS, 1u);
    bench_step(&bench);
    bool got = false;
    while (bench_collect(&bench, &f)) {
        if ((f.id & 31u) == MSG_ERRORS) {
            assert_int_equal(f.data[7], 82u - HAL_SIM_CAN_QUEUE_LEN);
            got = true;
        }
    }
    assert_true(got);
}

/* ---- (d) the command timeout ------------------------------------------------- */

static void test_timeout_latches_comm_fault(void **state)
{
    (void)state;
    bench_send_u8(&bench, MSG_ENABLE, 1u);
    bench_poll(&bench);
    const uint64_t t0 = bench.mb.sim_time_ns;
    uint32_t steps = 0;
    while (!bench.node.cmd.comm_lost) {
        bench_step(&bench);
        steps++;
        assert_true(steps < 10000u);
    }
    /* the first poll with more than 0.1 s since the command */
    assert_true(bench.mb.sim_time_ns - t0 > 100000000u);
    assert_true(bench.mb.sim_time_ns - t0 <= 100000000u + BENCH_PERIOD_NS);
    assert_int_equal(bench.node.counters.timeouts, 1u);
    assert_true(bench_app_command(&bench).comm_lost);
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_RUN);
    bench_step(&bench); /* the ISR latches it, PWM off */
    mc_telemetry_t t = bench_tlm(&bench);
    assert_int_equal(t.state, MC_STATE_FAULT);
    assert_true((t.faults_latched & MC_FAULT_COMM_TIMEOUT) != 0u);
    assert_false(bench.mb.pwm_outputs_enabled);
    for (int k = 0; k < 100; ++k) {
        bench_step(&bench);
    }
    assert_int_equal(bench.node.counters.timeouts, 1u); /* one rising edge */
    /* a valid command clears comm_lost; the fault stays latched */
    bench_send_u8(&bench, MSG_ENABLE, 0u);
    bench_poll(&bench);
    assert_false(bench.node.cmd.comm_lost);
    assert_false(bench_app_command(&bench).comm_lost);
    bench_step(&bench);
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_FAULT);
    /* ClearFaults: clear_fault is seen by exactly one ISR, the drive clears */
    bench_send(&bench, MSG_CLEAR, 0u, NULL);
    bench_poll(&bench);
    assert_true(bench_app_command(&bench).clear_fault);
    mc_app_fast_isr(&bench.app);
    assert_true(bench_app_command(&bench).clear_fault); /* the ISR's */
    bench_poll(&bench);
    assert_false(bench_app_command(&bench).clear_fault);
    mc_app_fast_isr(&bench.app);
    assert_false(bench_app_command(&bench).clear_fault);
    t = bench_tlm(&bench);
    assert_int_equal(t.state, MC_STATE_IDLE);
    assert_int_equal(t.faults_latched, 0u);
    /* polls without an ISR keep it raised (the pulse waits for an ISR) */
    bench_send(&bench, MSG_CLEAR, 0u, NULL);
    for (int k = 0; k < 5; ++k) {
        bench_poll(&bench);
        assert_true(bench_app_command(&bench).clear_fault);
    }
    bench_step(&bench);
    bench_poll(&bench);
    assert_false(bench_app_command(&bench).clear_fault);
}

/* The boundary: elapsed == timeout keeps the link, one tick more loses
 * it; valid commands feed it, rejected ones do not. */
static void test_timeout_boundary_and_feeding(void **state)
{
    (void)state;
    bench_send_u8(&bench, MSG_ENABLE, 1u);
    bench_poll(&bench);
    const uint64_t t0 = bench.mb.sim_time_ns;
    bench.mb.sim_time_ns = t0 + 60000000u;
    bench_send_f32(&bench, MSG_SPEED, 5.0f); /* valid: feeds */
    bench_poll(&bench);
    const uint64_t t1 = bench.mb.sim_time_ns;
    bench.mb.sim_time_ns = t1 + 60000000u;
    bench_send_f32(&bench, MSG_SPEED, NAN); /* rejected: does not feed */
    bench_poll(&bench);
    assert_false(bench.node.cmd.comm_lost);
    bench.mb.sim_time_ns = t1 + 100000000u;
    bench_poll(&bench);
    assert_false(bench.node.cmd.comm_lost);
    bench.mb.sim_time_ns = t1 + 100000001u;
    bench_poll(&bench);
    assert_true(bench.node.cmd.comm_lost);
    assert_true(bench_app_command(&bench).comm_lost);
    assert_int_equal(bench.node.counters.timeouts, 1u);
    /* a parameter read is a valid frame too: it clears comm_lost */
    bench_send_pread(&bench, ref_param_id("position", "kp_per_s"));
    bench_poll(&bench);
    assert_false(bench.node.cmd.comm_lost);
    assert_false(bench_app_command(&bench).comm_lost);
    bench.mb.sim_time_ns += 200000000u;
    bench_poll(&bench);
    assert_int_equal(bench.node.counters.timeouts, 2u);
}

static void test_no_timeout_while_disabled(void **state)
{
    (void)state;
    bench_send_f32(&bench, MSG_SPEED, 5.0f);
    bench_poll(&bench);
    for (int k = 0; k < 20000; ++k) { /* 1 s */
        bench_step(&bench);
    }
    assert_false(bench.node.cmd.comm_lost);
    assert_int_equal(bench.node.counters.timeouts, 0u);
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_IDLE);
    assert_int_equal(bench_tlm(&bench).faults_latched, 0u);
    /* disabled after a timeout: no new edge */
    bench_send_u8(&bench, MSG_ENABLE, 1u);
    bench_poll(&bench);
    bench.mb.sim_time_ns += 200000000u;
    bench_poll(&bench);
    assert_int_equal(bench.node.counters.timeouts, 1u);
    bench_send_u8(&bench, MSG_ENABLE, 0u);
    bench_poll(&bench);
    bench.mb.sim_time_ns += 2000000000u;
    bench_poll(&bench);
    assert_false(bench.node.cmd.comm_lost);
    assert_int_equal(bench.node.counters.timeouts, 1u);
}

/* ---- (e) parameters ------------------------------------------------------------ */

static void test_read_every_parameter(void **state)
{
    (void)state;
    uint32_t n = 0;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            const uint16_t id = ref_param_id(b->name, p->name);
            bench_drain(&bench);
            bench_send_pread(&bench, id);
            bench_poll(&bench);
            const hal_can_frame_t f = bench_reply(&bench);
            const rsp_param_t r = decode_rsp_param(&bench, &f);
            assert_int_equal(r.id, id);
            assert_int_equal(r.status, 0u);
            const uint8_t *field = (const uint8_t *)&bench.cfg + b->offset + p->offset;
            switch (p->type) {
            case MC_PARAM_F32: {
                float v;
                memcpy(&v, field, sizeof v);
                assert_int_equal(r.type, 0u);
                assert_int_equal(r.raw, f32_bits(v));
                break;
            }
            case MC_PARAM_U32: {
                uint32_t v;
                memcpy(&v, field, sizeof v);
                assert_int_equal(r.type, 1u);
                assert_int_equal(r.raw, v);
                break;
            }
            case MC_PARAM_BOOL: {
                bool v;
                memcpy(&v, field, sizeof v);
                assert_int_equal(r.type, 2u);
                assert_int_equal(r.raw, v ? 1u : 0u);
                break;
            }
            case MC_PARAM_CONTROLLER:
                assert_int_equal(r.type, 1u);
                assert_int_equal(r.raw, (uint32_t)bench.cfg.controller);
                break;
            case MC_PARAM_ESTIMATOR:
                assert_int_equal(r.type, 1u);
                assert_int_equal(r.raw, (uint32_t)bench.cfg.estimator);
                break;
            }
            n++;
        }
    }
    assert_true(n > 50u);
    assert_int_equal(bench.node.counters.rx_accepted, n);
    assert_int_equal(rejected_total(&bench.node.counters), 0u);
}

static void test_write_valid_value(void **state)
{
    (void)state;
    const uint16_t kp = ref_param_id("position", "kp_per_s");
    const float v = 2.0f * bench.cfg.position.kp_per_s;
    /* a command set before the write survives the drive's re-init */
    bench_send_u8(&bench, MSG_MODE, 2u);
    bench_send_f32(&bench, MSG_POSITION, 1.5f);
    bench_poll(&bench);
    bench_step(&bench);
    bench_drain(&bench);
    bench_send_pwrite(&bench, kp, 0u, f32_bits(v));
    bench_poll(&bench);
    assert_int_equal(applied.calls, 1u);
    mc_config_t expect = bench.cfg;
    expect.position.kp_per_s = v;
    assert_memory_equal(&applied.last, &expect, sizeof expect);
    assert_memory_equal(&bench.node.drive_cfg, &expect, sizeof expect);
    const hal_can_frame_t f = bench_reply(&bench);
    rsp_param_t r = decode_rsp_param(&bench, &f);
    assert_int_equal(r.status, 0u);
    assert_int_equal(r.type, 0u);
    assert_int_equal(r.raw, f32_bits(v));
    assert_true(bench.app.cfg.position.kp_per_s == v); /* the drive runs it */
    const mc_command_t c = bench_app_command(&bench);
    assert_int_equal(c.mode, MC_MODE_POSITION);
    assert_true(c.theta_m_ref_rad == 1.5f);
    /* read back */
    bench_send_pread(&bench, kp);
    bench_poll(&bench);
    const hal_can_frame_t g = bench_reply(&bench);
    r = decode_rsp_param(&bench, &g);
    assert_int_equal(r.status, 0u);
    assert_int_equal(r.raw, f32_bits(v));
    /* a bool and a u32 parameter */
    const bool dc = !bench.cfg.timing.delay_compensation;
    bench_send_pwrite(&bench, ref_param_id("timing", "delay_compensation"), 2u, dc ? 1u : 0u);
    bench_poll(&bench);
    const hal_can_frame_t h = bench_reply(&bench);
    r = decode_rsp_param(&bench, &h);
    assert_int_equal(r.status, 0u);
    assert_int_equal(r.type, 2u);
    assert_int_equal(r.raw, dc ? 1u : 0u);
    assert_true(bench.node.drive_cfg.timing.delay_compensation == dc);
    const uint32_t lim = bench.cfg.timing.isr_overrun_limit - 1u;
    bench_send_pwrite(&bench, ref_param_id("timing", "isr_overrun_limit"), 1u, lim);
    bench_poll(&bench);
    const hal_can_frame_t k = bench_reply(&bench);
    r = decode_rsp_param(&bench, &k);
    assert_int_equal(r.status, 0u);
    assert_int_equal(r.type, 1u);
    assert_int_equal(r.raw, lim);
    assert_int_equal(bench.node.drive_cfg.timing.isr_overrun_limit, lim);
    assert_int_equal(applied.calls, 3u);
    assert_int_equal(bench.node.counters.rx_accepted, 6u);
}

static void send_kp_write(float v)
{
    bench_drain(&bench);
    bench_send_pwrite(&bench, ref_param_id("position", "kp_per_s"), 0u, f32_bits(v));
    bench_poll(&bench);
}

static void expect_write_status(uint32_t status, uint32_t cause)
{
    const hal_can_frame_t f = bench_reply(&bench);
    const rsp_param_t r = decode_rsp_param(&bench, &f);
    assert_int_equal(r.status, status);
    assert_int_equal(r.raw, f32_bits(bench.cfg.position.kp_per_s)); /* unchanged */
    assert_memory_equal(&bench.node.drive_cfg, &bench.cfg, sizeof(mc_config_t));
    assert_int_equal(bench.node.counters.rejected[cause], 1u);
    bench_assert_no_reply(&bench);
}

static void test_write_refused_while_running(void **state)
{
    (void)state;
    bench_send_u8(&bench, MSG_ENABLE, 1u);
    bench_poll(&bench);
    for (uint32_t k = 0; k < BENCH_CALIB_N + 2u; ++k) {
        bench_step(&bench);
    }
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_RUN);
    send_kp_write(3.0f);
    expect_write_status(2u, MC_CAN_REJ_REFUSED_STATE);
    assert_int_equal(applied.calls, 0u);
    /* Cmd_Controller as well */
    bench_send_u8(&bench, MSG_CONTROLLER, 0u);
    bench_poll(&bench);
    const hal_can_frame_t f = bench_reply(&bench);
    const rsp_param_t r = decode_rsp_param(&bench, &f);
    assert_int_equal(r.id, ref_param_id("", "controller"));
    assert_int_equal(r.status, 2u);
    assert_int_equal(bench.node.counters.rejected[MC_CAN_REJ_REFUSED_STATE], 2u);
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_RUN);
}

/* In FAULT with the enable still set, a write (which re-initialises the
 * drive) would restart it: refused until Enable 0. */
static void test_write_refused_while_enable_set(void **state)
{
    (void)state;
    bench_send_u8(&bench, MSG_ENABLE, 1u);
    bench_poll(&bench);
    bench.mb.fault_input_active = true; /* external fault */
    bench_step(&bench);
    bench.mb.fault_input_active = false;
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_FAULT);
    send_kp_write(3.0f);
    expect_write_status(2u, MC_CAN_REJ_REFUSED_STATE);
    bench_send_u8(&bench, MSG_ENABLE, 0u);
    bench_poll(&bench);
    send_kp_write(3.0f);
    const hal_can_frame_t f = bench_reply(&bench);
    assert_int_equal(decode_rsp_param(&bench, &f).status, 0u);
    assert_int_equal(applied.calls, 1u);
    assert_true(bench.node.drive_cfg.position.kp_per_s == 3.0f);
    assert_int_equal(bench_tlm(&bench).state, MC_STATE_IDLE); /* re-initialised */
}

static void test_write_without_apply_refused(void **state)
{
    (void)state;
    assert_int_equal(mc_can_node_init(&bench.node, &bench.ncfg, &bench.cfg, NULL, NULL), MC_OK);
    send_kp_write(3.0f);
    expect_write_status(2u, MC_CAN_REJ_REFUSED_STATE);
    /* reads still work */
    bench_send_pread(&bench, ref_param_id("position", "kp_per_s"));
    bench_poll(&bench);
    const hal_can_frame_t f = bench_reply(&bench);
    assert_int_equal(decode_rsp_param(&bench, &f).status, 0u);
}

static void test_apply_failure(void **state)
{
    (void)state;
    applied.result = MC_ERR_PARAM; /* e.g. a PWM rate the board cannot make */
    send_kp_write(3.0f);
    assert_int_equal(applied.calls, 1u);
    expect_write_status(3u, MC_CAN_REJ_BAD_VALUE);
    applied.result = MC_ERR_STATE; /* the integrator found it running */
    send_kp_write(3.0f);
    assert_int_equal(applied.calls, 2u);
    expect_write_status(2u, MC_CAN_REJ_REFUSED_STATE);
}

/* Cmd_Controller = a write of "controller": each id is put in force or
 * rejected exactly as mc_config_validate judges the modified copy. */
static void test_controller_command(void **state)
{
    (void)state;
    uint32_t accepted = 0;
    for (uint32_t c = 0; c < 4u; ++c) {
        mc_config_t next = bench.node.drive_cfg;
        next.controller = (mc_controller_t)c;
        const bool ok = mc_config_validate(&next) == MC_OK;
        const mc_config_t before = bench.node.drive_cfg;
        bench_drain(&bench);
        bench_send_u8(&bench, MSG_CONTROLLER, (uint8_t)c);
        bench_poll(&bench);
        const hal_can_frame_t f = bench_reply(&bench);
        const rsp_param_t r = decode_rsp_param(&bench, &f);
        assert_int_equal(r.id, ref_param_id("", "controller"));
        assert_int_equal(r.type, 1u);
        if (ok) {
            accepted++;
            assert_int_equal(r.status, 0u);
            assert_int_equal(r.raw, c);
            assert_memory_equal(&bench.node.drive_cfg, &next, sizeof next);
            assert_int_equal(bench.app.cfg.controller, c);
            /* Tlm_Status reports it */
            bench_send_rate(&bench, MSG_STATUS, 1u);
            bench_step(&bench);
            hal_can_frame_t g;
            bool seen = false;
            while (bench_collect(&bench, &g)) {
                if ((g.id & 31u) == MSG_STATUS) {
                    assert_int_equal(g.data[7], c);
                    seen = true;
                }
            }
            assert_true(seen);
        } else {
            assert_int_equal(r.status, 3u);
            assert_int_equal(r.raw, (uint32_t)before.controller);
            assert_memory_equal(&bench.node.drive_cfg, &before, sizeof before);
        }
    }
    assert_true(accepted >= 1u); /* foc_pi with the encoder at least */
    assert_int_equal(applied.calls, accepted);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_config_default_and_init_checks, setup, teardown),
        cmocka_unit_test_setup_teardown(test_reject_unknown_message, setup, teardown),
        cmocka_unit_test_setup_teardown(test_reject_wrong_dlc, setup, teardown),
        cmocka_unit_test_setup_teardown(test_reject_bad_value, setup, teardown),
        cmocka_unit_test_setup_teardown(test_reject_parameter_level, setup, teardown),
        cmocka_unit_test_setup_teardown(test_ignored_frames, setup, teardown),
        cmocka_unit_test_setup_teardown(test_enable_speed_reaches_drive, setup, teardown),
        cmocka_unit_test_setup_teardown(test_telemetry_decimation_e2e, setup, teardown),
        cmocka_unit_test_setup_teardown(test_telemetry_values, setup, teardown),
        cmocka_unit_test_setup_teardown(test_isr_cost_mean, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tx_queue_full_drops, setup, teardown),
        cmocka_unit_test_setup_teardown(test_timeout_latches_comm_fault, setup, teardown),
        cmocka_unit_test_setup_teardown(test_timeout_boundary_and_feeding, setup, teardown),
        cmocka_unit_test_setup_teardown(test_no_timeout_while_disabled, setup, teardown),
        cmocka_unit_test_setup_teardown(test_read_every_parameter, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_valid_value, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_refused_while_running, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_refused_while_enable_set, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_without_apply_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_apply_failure, setup, teardown),
        cmocka_unit_test_setup_teardown(test_controller_command, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
