/*
 * 10,000 seeded random frames through the CAN node (random identifiers of
 * our node and of others, random DLC 0..8, random payloads biased towards
 * the interesting values, random extended / RTR flags), one per poll, the
 * drive IDLE (no ISR runs). The test keeps its own expectation of
 * everything the node may change, derived from the frame bytes with its
 * own bit arithmetic (can_bench.h) and the DBC's text: the command, the
 * telemetry rates, the configuration in force (a parameter write goes
 * through mc_config_validate, the one judge of values), the counters per
 * cause, and the one reply each frame gets. After every frame the node,
 * the command the drive holds and the configuration in force must equal
 * the expectation; the apply callback fails the test unless the
 * expectation says this frame puts a configuration in force.
 */
#include "can_bench.h"

#include <math.h>

#include "test_rng.h"

#define NODE    5u
#define FRAMES  10000u
#define NO_MSG  0xFFu
#define MAX_IDS 512u

static can_bench_t bench;

/* ---- the test's expectation ------------------------------------------------ */

typedef enum { R_NONE, R_ERROR, R_PARAM } reply_kind_t;

typedef struct {
    reply_kind_t kind;
    uint32_t msg, cause, dlc;       /* R_ERROR */
    uint32_t id, type, status, raw; /* R_PARAM */
} reply_t;

static struct {
    mc_command_t cmd;
    uint16_t decimation[MC_CAN_TLM_COUNT];
    mc_config_t cfg;
    mc_can_counters_t counters;
    uint32_t applies;
    bool expect_apply; /* this frame puts a configuration in force */
} model;

/* every parameter: its id by the test's CRC, its place and type */
typedef struct {
    uint16_t id;
    size_t offset;
    mc_param_type_t type;
} param_info_t;
static param_info_t params[MAX_IDS];
static uint32_t n_params;

static mc_status_t apply_cb(void *ctx, const mc_config_t *cfg)
{
    (void)ctx;
    if (!model.expect_apply) {
        fail_msg("apply called for a frame the expectation rejects");
    }
    assert_memory_equal(cfg, &model.cfg, sizeof *cfg);
    model.applies++;
    return MC_OK;
}

static int find_param(uint32_t id)
{
    for (uint32_t i = 0; i < n_params; ++i) {
        if (params[i].id == id) {
            return (int)i;
        }
    }
    return -1;
}

static uint32_t wire_type(mc_param_type_t t)
{
    return (t == MC_PARAM_F32) ? 0u : (t == MC_PARAM_BOOL) ? 2u : 1u;
}

/* the value in force of parameter i, as Rsp_Param carries it */
static uint32_t value_raw(const mc_config_t *cfg, int i)
{
    const uint8_t *p = (const uint8_t *)cfg + params[i].offset;
    switch (params[i].type) {
    case MC_PARAM_BOOL: {
        bool b;
        memcpy(&b, p, sizeof b);
        return b ? 1u : 0u;
    }
    case MC_PARAM_CONTROLLER: {
        mc_controller_t c;
        memcpy(&c, p, sizeof c);
        return (uint32_t)c;
    }
    case MC_PARAM_ESTIMATOR: {
        mc_estimator_t e;
        memcpy(&e, p, sizeof e);
        return (uint32_t)e;
    }
    default: {
        uint32_t u;
        memcpy(&u, p, sizeof u);
        return u;
    }
    }
}

static reply_t reject(uint32_t msg, uint32_t cause, uint32_t dlc)
{
    model.counters.rejected[cause]++;
    return (reply_t){ .kind = R_ERROR, .msg = msg, .cause = cause, .dlc = dlc };
}

static reply_t param_reply(uint32_t id, int i, uint32_t type, uint32_t status, uint32_t cause)
{
    if (cause != 0u) {
        model.counters.rejected[cause]++;
    } else {
        model.counters.rx_accepted++;
    }
    reply_t r = { .kind = R_PARAM, .id = id, .type = type, .status = status };
    if (i >= 0) {
        r.type = wire_type(params[i].type);
        r.raw = value_raw(&model.cfg, i);
    }
    return r;
}

/* a write of parameter id with wire type `type` and raw value `raw`
 * (frame checks passed) */
static reply_t write_param(uint32_t id, uint32_t type, uint32_t raw)
{
    const int i = find_param(id);
    if (i < 0) {
        return param_reply(id, -1, type, 1u, MC_CAN_REJ_UNKNOWN_PARAM);
    }
    if (type != wire_type(params[i].type)) {
        return param_reply(id, i, type, 4u, MC_CAN_REJ_WRONG_PARAM_TYPE);
    }
    if (model.cmd.enable) { /* the drive is IDLE: only the enable refuses */
        return param_reply(id, i, type, 2u, MC_CAN_REJ_REFUSED_STATE);
    }
    mc_config_t next = model.cfg;
    uint8_t *p = (uint8_t *)&next + params[i].offset;
    switch (params[i].type) {
    case MC_PARAM_F32:
    case MC_PARAM_U32: memcpy(p, &raw, 4); break;
    case MC_PARAM_BOOL: {
        const bool b = raw != 0u;
        memcpy(p, &b, sizeof b);
        break;
    }
    case MC_PARAM_CONTROLLER: {
        if (raw >= (uint32_t)MC_CONTROLLER_COUNT) {
            return param_reply(id, i, type, 3u, MC_CAN_REJ_BAD_VALUE);
        }
        const mc_controller_t c = (mc_controller_t)raw;
        memcpy(p, &c, sizeof c);
        break;
    }
    case MC_PARAM_ESTIMATOR: {
        if (raw >= (uint32_t)MC_ESTIMATOR_COUNT) {
            return param_reply(id, i, type, 3u, MC_CAN_REJ_BAD_VALUE);
        }
        const mc_estimator_t e = (mc_estimator_t)raw;
        memcpy(p, &e, sizeof e);
        break;
    }
    }
    if (mc_config_validate(&next) != MC_OK) {
        return param_reply(id, i, type, 3u, MC_CAN_REJ_BAD_VALUE);
    }
    model.cfg = next;
    model.expect_apply = true;
    return param_reply(id, i, type, 0u, 0u);
}

static bool f32_ok(uint32_t bits, float lim)
{
    const float v = bits_f32(bits);
    return isfinite(v) && v >= -lim && v <= lim;
}

/* What the node must do with frame f: update the expectation, return the
 * reply. */
static reply_t expect(const hal_can_frame_t *f)
{
    if (f->id > 0x7FFu || (f->id >> 5) != NODE) {
        return (reply_t){ R_NONE };
    }
    const uint32_t msg = f->id & 31u;
    if (msg >= 16u && msg <= 26u) {
        return (reply_t){ R_NONE };
    }
    model.counters.rx_frames++;
    if (f->extended || f->rtr) {
        return reject(msg, MC_CAN_REJ_UNKNOWN_MESSAGE, f->dlc);
    }
    const int len = bench_cmd_dlc(msg);
    if (len < 0) {
        return reject(msg, MC_CAN_REJ_UNKNOWN_MESSAGE, f->dlc);
    }
    if (f->dlc != (uint8_t)len) {
        return reject(msg, MC_CAN_REJ_WRONG_DLC, f->dlc);
    }
    const uint8_t *d = f->data;
    mc_command_t c = model.cmd;
    switch (msg) {
    case MSG_ENABLE: c.enable = (d[0] & 1u) != 0u; break;
    case MSG_MODE:
        if (d[0] > 2u) {
            return reject(msg, MC_CAN_REJ_BAD_VALUE, f->dlc);
        }
        c.mode = (mc_mode_t)d[0];
        break;
    case MSG_CURRENT:
        if (!f32_ok(get_u32(d), 1000.0f) || !f32_ok(get_u32(d + 4), 1000.0f)) {
            return reject(msg, MC_CAN_REJ_BAD_VALUE, f->dlc);
        }
        c.i_d_ref_A = bits_f32(get_u32(d));
        c.i_q_ref_A = bits_f32(get_u32(d + 4));
        break;
    case MSG_SPEED:
        if (!f32_ok(get_u32(d), 10000.0f)) {
            return reject(msg, MC_CAN_REJ_BAD_VALUE, f->dlc);
        }
        c.omega_m_ref_rad_s = bits_f32(get_u32(d));
        break;
    case MSG_POSITION:
        if (!f32_ok(get_u32(d), 1000000.0f)) {
            return reject(msg, MC_CAN_REJ_BAD_VALUE, f->dlc);
        }
        c.theta_m_ref_rad = bits_f32(get_u32(d));
        break;
    case MSG_CLEAR: c.clear_fault = true; break; /* no ISR: stays raised */
    case MSG_PREAD: {
        const uint32_t id = get_u16(d);
        const int i = find_param(id);
        return (i < 0) ? param_reply(id, -1, 0u, 1u, MC_CAN_REJ_UNKNOWN_PARAM)
                       : param_reply(id, i, 0u, 0u, 0u);
    }
    case MSG_PWRITE: {
        const uint32_t type = d[2];
        const uint32_t raw = (type == 2u) ? d[3] : get_u32(d + 3);
        if (type > 2u || (type == 0u && !f32_ok(raw, 3.4e38f)) || (type == 2u && raw > 1u)) {
            return reject(msg, MC_CAN_REJ_BAD_VALUE, f->dlc);
        }
        return write_param(get_u16(d), type, raw);
    }
    case MSG_CONTROLLER:
        if (d[0] > 3u) {
            return reject(msg, MC_CAN_REJ_BAD_VALUE, f->dlc);
        }
        return write_param(ref_param_id("", "controller"), 1u, d[0]);
    case MSG_TRATE:
        if (d[0] < 16u || d[0] > 24u) {
            return reject(msg, MC_CAN_REJ_BAD_VALUE, f->dlc);
        }
        model.decimation[d[0] - 16u] = (uint16_t)get_u16(d + 1);
        break;
    default: fail();
    }
    model.cmd = c;
    model.counters.rx_accepted++;
    return (reply_t){ R_NONE };
}

/* ---- the frames ------------------------------------------------------------ */

static float special_f32(test_rng_t *r, float lim)
{
    const float s[] = { 0.0f, -0.0f,    lim,       -lim,   nextafterf(lim, INFINITY),
                        NAN,  INFINITY, -INFINITY, 1e-40f, 1.0f };
    const uint64_t k = test_rng_next_u64(&r->state);
    return (k % 3u == 0u) ? s[(k >> 8) % 10u] : (float)test_rng_range(r, -1.2 * lim, 1.2 * lim);
}

static hal_can_frame_t random_frame(test_rng_t *r)
{
    hal_can_frame_t f = { 0 };
    const uint64_t a = test_rng_next_u64(&r->state);
    const uint64_t b = test_rng_next_u64(&r->state);
    memcpy(f.data, &b, 8);
    f.extended = (a & 0xFu) == 0u;
    f.rtr = ((a >> 4) & 0xFu) == 0u;
    const uint32_t msg = (uint32_t)((a >> 8) & 31u);
    if (((a >> 13) & 1u) != 0u) { /* ours */
        f.id = NODE * 32u + msg;
        const int len = bench_cmd_dlc(msg);
        f.dlc = (len >= 0 && ((a >> 14) % 5u) != 0u) ? (uint8_t)len : (uint8_t)((a >> 17) % 9u);
        const bool biased = ((a >> 21) % 4u) != 0u;
        if (biased) {
            switch (msg) {
            case MSG_ENABLE:
            case MSG_MODE: f.data[0] = (uint8_t)((a >> 23) % 4u); break;
            case MSG_CURRENT:
                put_f32(f.data, special_f32(r, 1000.0f));
                put_f32(f.data + 4, special_f32(r, 1000.0f));
                break;
            case MSG_SPEED: put_f32(f.data, special_f32(r, 10000.0f)); break;
            case MSG_POSITION: put_f32(f.data, special_f32(r, 1000000.0f)); break;
            case MSG_PREAD:
            case MSG_PWRITE: {
                const uint32_t i = (uint32_t)((a >> 25) % n_params);
                put_u16(f.data, params[i].id);
                if (msg == MSG_PWRITE) {
                    f.data[2] = (uint8_t)((a >> 35) % 4u);
                    if ((a >> 37) % 2u == 0u) {
                        f.data[2] = (uint8_t)wire_type(params[i].type);
                    }
                    if (f.data[2] == 0u) {
                        put_f32(f.data + 3, (float)test_rng_range(r, -2.0, 2000.0));
                    } else if (f.data[2] == 1u) {
                        put_u32(f.data + 3, (uint32_t)((a >> 40) % 8u));
                    } else {
                        f.data[3] = (uint8_t)((a >> 40) % 3u);
                    }
                }
                break;
            }
            case MSG_CONTROLLER: f.data[0] = (uint8_t)((a >> 23) % 6u); break;
            case MSG_TRATE: f.data[0] = (uint8_t)(14u + (a >> 23) % 13u); break;
            default: break;
            }
        }
    } else if (f.extended && ((a >> 14) & 1u) != 0u) {
        f.id = (uint32_t)((a >> 32) & 0x1FFFFFFFu);
        f.dlc = (uint8_t)((a >> 17) % 9u);
    } else {
        f.id = (uint32_t)((a >> 32) & 0x7FFu);
        f.dlc = (uint8_t)((a >> 17) % 9u);
    }
    return f;
}

/* ---- the test ----------------------------------------------------------------- */

static void check_reply(const reply_t *e)
{
    hal_can_frame_t f;
    bool got = false;
    while (bench_collect(&bench, &f)) {
        const uint32_t msg = f.id & 31u;
        assert_int_equal(f.id >> 5, NODE);
        if (msg >= 16u && msg <= 24u) {
            assert_true(ref_e2e_ok(&f));
            continue;
        }
        assert_false(got); /* one reply at most */
        got = true;
        if (e->kind == R_ERROR) {
            assert_rsp_error(&bench, &f, e->msg, e->cause, e->dlc);
        } else {
            assert_int_equal(e->kind, R_PARAM);
            const rsp_param_t p = decode_rsp_param(&bench, &f);
            assert_int_equal(p.id, e->id);
            assert_int_equal(p.status, e->status);
            assert_int_equal(p.type, e->type);
            assert_int_equal(p.raw, e->raw);
        }
    }
    assert_true(got == (e->kind != R_NONE));
}

static void test_random_frames_change_only_what_they_command(void **state)
{
    (void)state;
    mc_can_node_config_t nc;
    mc_can_node_config_default(&nc);
    nc.node_id = NODE;
    nc.timeout_s = 60.0f;
    bench_init(&bench, &nc, apply_cb, NULL);
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            assert_true(n_params < MAX_IDS);
            params[n_params++] =
                (param_info_t){ ref_param_id(b->name, p->name), b->offset + p->offset, p->type };
        }
    }
    model.cmd = (mc_command_t){ .mode = MC_MODE_CURRENT };
    memcpy(model.decimation, nc.decimation, sizeof model.decimation);
    model.cfg = bench.cfg;

    test_rng_t rng = test_rng_seed(0xC0FFEE5EEDull);
    uint32_t ours = 0, accepted_cmds = 0;
    for (uint32_t k = 0; k < FRAMES; ++k) {
        const hal_can_frame_t f = random_frame(&rng);
        model.expect_apply = false;
        const uint32_t applies = model.applies;
        const uint32_t acc = model.counters.rx_accepted;
        const reply_t e = expect(&f);
        const bool expect_apply = model.expect_apply;
        assert_true(hal_sim_can_deliver(&bench.mb, &f));
        bench_poll(&bench);
        ours += ((f.id >> 5) == NODE && f.id <= 0x7FFu) ? 1u : 0u;
        accepted_cmds += model.counters.rx_accepted - acc;
        assert_int_equal(model.applies, applies + (expect_apply ? 1u : 0u));
        check_reply(&e);
        const mc_can_counters_t *c = mc_can_node_counters(&bench.node);
        assert_int_equal(c->rx_frames, model.counters.rx_frames);
        assert_int_equal(c->rx_accepted, model.counters.rx_accepted);
        for (uint32_t j = 0; j < MC_CAN_REJ_COUNT; ++j) {
            assert_int_equal(c->rejected[j], model.counters.rejected[j]);
        }
        assert_int_equal(c->rx_frames, c->rx_accepted + rejected_total(c));
        assert_true(command_equal(&bench.node.cmd, &model.cmd));
        if (model.counters.rx_accepted > 0u) {
            const mc_command_t app_cmd = bench_app_command(&bench);
            assert_true(command_equal(&app_cmd, &model.cmd));
        }
        assert_memory_equal(bench.node.cfg.decimation, model.decimation, sizeof model.decimation);
        assert_memory_equal(&bench.node.drive_cfg, &model.cfg, sizeof model.cfg);
        assert_int_equal(bench_tlm(&bench).state, MC_STATE_IDLE);
        assert_false(bench.node.cmd.comm_lost);
    }
    /* the mix exercised every outcome */
    print_message("random frames: %u, ours %u, accepted %u, applied %u, rejected by cause "
                  "%u %u %u %u %u %u\n",
                  FRAMES, ours, accepted_cmds, model.applies, model.counters.rejected[1],
                  model.counters.rejected[2], model.counters.rejected[3],
                  model.counters.rejected[4], model.counters.rejected[5],
                  model.counters.rejected[6]);
    assert_true(ours > FRAMES / 3u);
    assert_true(accepted_cmds > 500u);
    assert_true(model.applies > 0u);
    for (uint32_t j = 1; j < MC_CAN_REJ_COUNT; ++j) {
        assert_true(model.counters.rejected[j] > 0u);
    }
    hal_sim_bind(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_frames_change_only_what_they_command),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
