/*
 * The simulated drive with its CAN node (sim_engine_can_attach), driven by
 * frames built by hand from the DBC (can_frames.h), on the shipped paper 002
 * Case I FOC scenario (10 kHz, 500 rpm step in the scenario; here the
 * reference comes over CAN only):
 *   - the engine's CAN API around attach (refusals, NULL before attach);
 *   - speed mode over CAN: Cmd_TelemetryRate (Tlm_Status every 10 ms),
 *     Cmd_Mode speed, Cmd_Speed, Cmd_Enable 1, then a Cmd_Speed every
 *     10 ms: the drive reaches RUN and the true speed settles within 3 %
 *     of the reference; Tlm_Status says RUN, speed mode, enabled, with a
 *     valid E2E CRC and counter;
 *   - the commands stop: MC_FAULT_COMM_TIMEOUT latches 0.1 s (the node's
 *     timeout) after the last command, the PWM goes off in that period and
 *     stays off, Tlm_Status says FAULT with bit 15;
 *   - Enable 0, then a parameter write (foc_pi.speed_bandwidth_rad_s) while
 *     in FAULT: Rsp_Param status 0 with the new value, the engine
 *     re-initialised the drive with it (IDLE, faults cleared), a parameter
 *     read returns it, an invalid value is refused (status 3) and changes
 *     nothing; the re-initialised drive runs again on Enable 1;
 *   - a write whose mc_app_init fails after re-initialising the drive (made
 *     to through -Wl,--wrap=mc_app_init) is answered with status 3 and leaves the drive
 *     exactly as it was (FAULT with its latched fault, the old value in
 *     force); it clears and runs again on the old configuration.
 */
#include "mc_test.h"

#include <stdio.h>
#include <stdlib.h>

#include "can_frames.h"
#include "mc/can_node.h"
#include "mc/faults.h"
#include "shipped_scenario.h"

#define SCENARIO      "paper002_case1_foc.json"
#define NODE          3u
#define OMEGA_REF     (500.0 * MC_TEST_RAD_S_PER_RPM) /* the scenario's step */
#define CMD_EVERY_S   0.01
#define TLM_DECIMATE  100u /* Tlm_Status every 100 ISRs = 10 ms at 10 kHz */
#define PARAM_NAME    "foc_pi.speed_bandwidth_rad_s"
#define PARAM_NEW     150.0f /* the scenario's is 200 */
#define STATE_RUN     2u     /* Tlm_Status.State (the DBC's value table) */
#define STATE_FAULT   3u
#define PARAM_OK      0u /* Rsp_Param.Status */
#define PARAM_INVALID 3u

static scenario_t scn; /* large: off the stack */

/* mc_app_init, made to fail on demand (linked with -Wl,--wrap=mc_app_init)
 * the worst way: after it has re-initialised the drive. */
static bool app_init_fails;
mc_status_t __real_mc_app_init(mc_app_t *app, const mc_config_t *cfg);
mc_status_t __wrap_mc_app_init(mc_app_t *app, const mc_config_t *cfg);
mc_status_t __wrap_mc_app_init(mc_app_t *app, const mc_config_t *cfg)
{
    const mc_status_t st = __real_mc_app_init(app, cfg);
    return app_init_fails ? MC_ERR_PARAM : st;
}

typedef struct {
    sim_engine_t *e;
    double ts;
    /* Tlm_Status frames */
    unsigned n_status;
    hal_can_frame_t last_status;
    unsigned e2e_errors; /* bad CRC or counter step */
    int prev_counter;    /* -1: none yet */
    /* Rsp_Param */
    unsigned n_rsp;
    hal_can_frame_t last_rsp;
    unsigned n_rsp_error;
} bench_t;

static void collect(bench_t *b)
{
    hal_can_frame_t f;
    while (sim_engine_can_collect(b->e, &f)) {
        assert_false(f.extended);
        if (f.id == can_id(NODE, CAN_MSG_TLM_STATUS)) {
            assert_int_equal(f.dlc, 8);
            if (can_e2e_crc(&f) != f.data[0]) {
                b->e2e_errors++;
            }
            const int c = (int)can_status_counter(&f);
            if (b->prev_counter >= 0 && c != (b->prev_counter + 1) % 15) {
                b->e2e_errors++;
            }
            b->prev_counter = c;
            b->n_status++;
            b->last_status = f;
        } else if (f.id == can_id(NODE, CAN_MSG_RSP_PARAM)) {
            assert_int_equal(f.dlc, 8);
            b->n_rsp++;
            b->last_rsp = f;
        } else if (f.id == can_id(NODE, CAN_MSG_RSP_ERROR)) {
            print_message("Rsp_Error: message %u cause %u dlc %u\n", f.data[0], f.data[1],
                          f.data[2]);
            b->n_rsp_error++;
        }
    }
}

static void deliver(bench_t *b, hal_can_frame_t f)
{
    assert_true(sim_engine_can_deliver(b->e, &f));
}

static const sim_trace_sample_t *step(bench_t *b)
{
    assert_int_equal(sim_engine_step(b->e, NULL), SIM_ENGINE_OK);
    collect(b);
    return sim_engine_last(b->e);
}

static void steps(bench_t *b, unsigned n)
{
    for (unsigned i = 0; i < n; ++i) {
        (void)step(b);
    }
}

/* Step `seconds`, resending Cmd_Speed (OMEGA_REF) every CMD_EVERY_S (it
 * feeds the command timeout), no fault latched; the last sample. */
static const sim_trace_sample_t *run_commanded(bench_t *b, double seconds)
{
    const uint32_t cmd_every = (uint32_t)lround(CMD_EVERY_S / b->ts);
    const sim_trace_sample_t *s = sim_engine_last(b->e);
    for (uint32_t k = 0; k < (uint32_t)lround(seconds / b->ts); ++k) {
        if (k > 0u && k % cmd_every == 0u) {
            deliver(b, can_cmd_speed(NODE, (float)OMEGA_REF));
        }
        s = step(b);
        assert_int_equal(s->fw.faults_latched, 0u);
    }
    return s;
}

static sim_engine_t *load_engine(void)
{
    return shipped_scenario_engine(SCENARIO, NULL, 0u, &scn);
}

static void bench_attach(bench_t *b)
{
    *b = (bench_t){ .e = load_engine(), .prev_counter = -1 };
    b->ts = sim_engine_period_s(b->e);
    mc_can_node_config_t cfg;
    mc_can_node_config_default(&cfg);
    cfg.node_id = NODE;
    cfg.timeout_s = 0.1f;
    assert_int_equal(sim_engine_can_attach(b->e, &cfg), SIM_ENGINE_OK);
}

/* The CAN API of the engine around attach. */
static void test_attach_api(void **state)
{
    (void)state;
    sim_engine_t *e = load_engine();
    hal_can_frame_t f = can_cmd_enable(NODE, true);
    assert_null(sim_engine_can_node(e));
    assert_false(sim_engine_can_deliver(e, &f));
    assert_false(sim_engine_can_collect(e, &f));
    assert_int_equal(sim_engine_step(e, NULL), SIM_ENGINE_ERR_NULL); /* no node: cmd needed */

    mc_can_node_config_t cfg;
    mc_can_node_config_default(&cfg);
    cfg.node_id = MC_CAN_NODE_ID_MAX + 1u;
    assert_int_equal(sim_engine_can_attach(e, &cfg), SIM_ENGINE_ERR_CAN);
    assert_null(sim_engine_can_node(e));
    cfg.node_id = NODE;
    assert_int_equal(sim_engine_can_attach(e, NULL), SIM_ENGINE_ERR_NULL);
    assert_int_equal(sim_engine_can_attach(e, &cfg), SIM_ENGINE_OK);
    const mc_can_node_t *node = sim_engine_can_node(e);
    assert_non_null(node);
    assert_int_equal(mc_can_node_counters(node)->rx_frames, 0);
    assert_int_equal(sim_engine_can_attach(e, &cfg), SIM_ENGINE_ERR_STATE);

    hal_can_frame_t bad = f;
    bad.dlc = 9u;
    assert_false(sim_engine_can_deliver(e, &bad));
    bad = f;
    bad.id = 0x800u; /* too large for 11 bits */
    assert_false(sim_engine_can_deliver(e, &bad));

    /* the command argument is ignored: the node's (disabled) is used */
    const mc_command_t run = { .enable = true, .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = 10.0f };
    for (int k = 0; k < 500; ++k) {
        assert_int_equal(sim_engine_step(e, (k % 2) ? &run : NULL), SIM_ENGINE_OK);
        assert_int_equal(sim_engine_last(e)->fw.state, MC_STATE_IDLE);
        assert_false(sim_engine_last(e)->cmd.enable);
    }
    /* a full receive queue refuses the frame and counts it */
    unsigned accepted = 0;
    for (unsigned i = 0; i < HAL_SIM_CAN_QUEUE_LEN + 4u; ++i) {
        accepted += sim_engine_can_deliver(e, &f) ? 1u : 0u;
    }
    assert_int_equal(accepted, HAL_SIM_CAN_QUEUE_LEN);
    free(e);
}

/* Speed over CAN, the command timeout, a parameter write through the
 * engine's apply callback. */
static void test_speed_timeout_param(void **state)
{
    (void)state;
    bench_t b;
    bench_attach(&b);
    const uint32_t cmd_every = (uint32_t)lround(CMD_EVERY_S / b.ts);

    /* 1. Start in speed mode; a Cmd_Speed every 10 ms for 0.3 s. */
    deliver(&b, can_cmd_telemetry_rate(NODE, CAN_MSG_TLM_STATUS, TLM_DECIMATE));
    deliver(&b, can_cmd_mode(NODE, 1u));
    deliver(&b, can_cmd_speed(NODE, (float)OMEGA_REF));
    deliver(&b, can_cmd_enable(NODE, true));
    double t_last_cmd = 0.0;
    double err_max = 0.0;
    const sim_trace_sample_t *s = NULL;
    const uint32_t n_run = (uint32_t)lround(0.3 / b.ts);
    for (uint32_t k = 0; k < n_run; ++k) {
        if (k > 0u && k % cmd_every == 0u) {
            deliver(&b, can_cmd_speed(NODE, (float)OMEGA_REF));
            t_last_cmd = sim_engine_time_s(b.e); /* polled after this ISR */
        }
        s = step(&b);
        assert_int_equal(s->fw.faults_latched, 0);
        if (s->t_s >= 0.2) {
            err_max = fmax(err_max, fabs(s->plant.omega_m_rad_s - OMEGA_REF));
        }
    }
    print_message("speed over CAN: max |omega - ref| over [0.2, 0.3] s = %.3f rad/s (%.2f %%)\n",
                  err_max, 100.0 * err_max / OMEGA_REF);
    assert_int_equal(s->fw.state, MC_STATE_RUN);
    assert_true(s->cmd.enable);
    assert_int_equal(s->cmd.mode, MC_MODE_SPEED);
    assert_near(s->cmd.omega_m_ref_rad_s, OMEGA_REF, 1e-4);
    assert_true(err_max <= 0.03 * OMEGA_REF);
    assert_true(s->outputs_applied);
    assert_true(b.n_status >= 25u); /* every 10 ms over 0.3 s */
    assert_int_equal(b.e2e_errors, 0);
    assert_int_equal(can_status_state(&b.last_status), STATE_RUN);
    assert_int_equal(can_status_mode(&b.last_status), 1u);
    assert_true(can_status_enabled(&b.last_status));
    assert_true(can_status_outputs_on(&b.last_status));
    assert_int_equal(can_status_faults(&b.last_status), 0u);
    const mc_can_counters_t *c = mc_can_node_counters(sim_engine_can_node(b.e));
    assert_int_equal(c->timeouts, 0);
    assert_true(c->rx_accepted >= 4u + (n_run - 1u) / cmd_every);
    for (unsigned r = 1; r < MC_CAN_REJ_COUNT; ++r) {
        assert_int_equal(c->rejected[r], 0);
    }
    assert_int_equal(b.n_rsp_error, 0);

    /* 2. No more commands: the timeout latches COMM_TIMEOUT, PWM off. */
    double t_fault = NAN;
    for (uint32_t k = 0; k < (uint32_t)lround(0.3 / b.ts); ++k) {
        s = step(&b);
        if (isnan(t_fault) && (s->fw.faults_latched & MC_FAULT_COMM_TIMEOUT) != 0u) {
            t_fault = s->t_s;
        }
        if (!isnan(t_fault)) {
            assert_false(s->outputs_applied); /* off from the faulting ISR on */
            assert_int_equal(s->fw.state, MC_STATE_FAULT);
        }
    }
    assert_false(isnan(t_fault));
    print_message("COMM_TIMEOUT latched %.4f s after the last command\n", t_fault - t_last_cmd);
    assert_true(t_fault - t_last_cmd >= 0.1 - 1.5 * b.ts);
    assert_true(t_fault - t_last_cmd <= 0.1 + 0.01);
    assert_int_equal(mc_can_node_counters(sim_engine_can_node(b.e))->timeouts, 1);
    assert_int_equal(can_status_state(&b.last_status), STATE_FAULT);
    assert_true((can_status_faults(&b.last_status) & 0x8000u) != 0u);
    assert_false(can_status_outputs_on(&b.last_status));

    /* 3. Enable 0, then a parameter write while in FAULT. */
    deliver(&b, can_cmd_enable(NODE, false));
    steps(&b, 20u);
    assert_int_equal(sim_engine_last(b.e)->fw.state, MC_STATE_FAULT); /* latched */
    const uint16_t pid = can_crc16_ccitt_false(PARAM_NAME);
    deliver(&b, can_cmd_param_write_f32(NODE, pid, PARAM_NEW));
    const unsigned n_rsp = b.n_rsp;
    steps(&b, 20u);
    assert_int_equal(b.n_rsp, n_rsp + 1u);
    assert_int_equal(can_rsp_param_id(&b.last_rsp), pid);
    assert_int_equal(b.last_rsp.data[2], 0u); /* float32 */
    assert_int_equal(b.last_rsp.data[3], PARAM_OK);
    assert_near(can_get_f32(&b.last_rsp.data[4]), PARAM_NEW, 0.0);
    /* the engine re-initialised the drive with it */
    s = sim_engine_last(b.e);
    assert_int_equal(s->fw.state, MC_STATE_IDLE);
    assert_int_equal(s->fw.faults_latched, 0u);
    assert_near(sim_engine_can_node(b.e)->drive_cfg.foc_pi.speed_bandwidth_rad_s, PARAM_NEW, 0.0);
    deliver(&b, can_cmd_param_read(NODE, pid));
    steps(&b, 20u);
    assert_int_equal(b.n_rsp, n_rsp + 2u);
    assert_int_equal(b.last_rsp.data[3], PARAM_OK);
    assert_near(can_get_f32(&b.last_rsp.data[4]), PARAM_NEW, 0.0);
    /* a value the validation refuses changes nothing */
    deliver(&b, can_cmd_param_write_f32(NODE, pid, -1.0f));
    steps(&b, 20u);
    assert_int_equal(b.n_rsp, n_rsp + 3u);
    assert_int_equal(b.last_rsp.data[3], PARAM_INVALID);
    deliver(&b, can_cmd_param_read(NODE, pid));
    steps(&b, 20u);
    assert_int_equal(b.n_rsp, n_rsp + 4u);
    assert_near(can_get_f32(&b.last_rsp.data[4]), PARAM_NEW, 0.0);
    assert_int_equal(sim_engine_last(b.e)->fw.state, MC_STATE_IDLE);

    /* 4. The re-initialised drive runs again. */
    deliver(&b, can_cmd_speed(NODE, (float)OMEGA_REF));
    deliver(&b, can_cmd_enable(NODE, true));
    s = run_commanded(&b, 0.2);
    assert_int_equal(s->fw.state, MC_STATE_RUN);
    assert_true(fabs(s->plant.omega_m_rad_s - OMEGA_REF) <= 0.05 * OMEGA_REF);
    assert_int_equal(b.e2e_errors, 0);
    free(b.e);
}

/* RUN, then no command until COMM_TIMEOUT latches, then Enable 0. */
static void run_then_time_out(bench_t *b)
{
    deliver(b, can_cmd_mode(NODE, 1u));
    deliver(b, can_cmd_speed(NODE, (float)OMEGA_REF));
    deliver(b, can_cmd_enable(NODE, true));
    assert_int_equal(run_commanded(b, 0.1)->fw.state, MC_STATE_RUN);
    steps(b, (uint32_t)lround(0.15 / b->ts));
    assert_int_equal(sim_engine_last(b->e)->fw.state, MC_STATE_FAULT);
    deliver(b, can_cmd_enable(NODE, false));
    steps(b, 20u);
}

/* A configuration mc_app_init refuses leaves the drive as it was. */
static void test_apply_refused(void **state)
{
    (void)state;
    bench_t b;
    bench_attach(&b);
    run_then_time_out(&b);
    const sim_trace_sample_t *s = sim_engine_last(b.e);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    const uint32_t faults = s->fw.faults_latched;
    assert_true((faults & MC_FAULT_COMM_TIMEOUT) != 0u);

    const uint16_t pid = can_crc16_ccitt_false(PARAM_NAME);
    app_init_fails = true;
    deliver(&b, can_cmd_param_write_f32(NODE, pid, PARAM_NEW));
    const unsigned n_rsp = b.n_rsp;
    steps(&b, 20u);
    app_init_fails = false;
    assert_int_equal(b.n_rsp, n_rsp + 1u);
    assert_int_equal(can_rsp_param_id(&b.last_rsp), pid);
    assert_int_equal(b.last_rsp.data[3], PARAM_INVALID);
    s = sim_engine_last(b.e);
    assert_int_equal(s->fw.state, MC_STATE_FAULT); /* not re-initialised */
    assert_int_equal(s->fw.faults_latched, faults);
    assert_false(s->outputs_applied);
    assert_near(sim_engine_can_node(b.e)->drive_cfg.foc_pi.speed_bandwidth_rad_s, 200.0, 0.0);
    deliver(&b, can_cmd_param_read(NODE, pid));
    steps(&b, 20u);
    assert_int_equal(b.n_rsp, n_rsp + 2u);
    assert_near(can_get_f32(&b.last_rsp.data[4]), 200.0, 0.0);

    /* the drive as it was clears and runs again */
    const hal_can_frame_t clear = can_frame(NODE, CAN_MSG_CLEAR_FAULTS, 0u);
    deliver(&b, clear);
    steps(&b, 20u);
    assert_int_equal(sim_engine_last(b.e)->fw.state, MC_STATE_IDLE);
    deliver(&b, can_cmd_enable(NODE, true));
    s = run_commanded(&b, 0.15);
    assert_int_equal(s->fw.state, MC_STATE_RUN);
    assert_true(fabs(s->plant.omega_m_rad_s - OMEGA_REF) <= 0.05 * OMEGA_REF);
    assert_int_equal(b.n_rsp_error, 0);
    free(b.e);
}

/* A write of the telemetry rate (timing.telemetry_every_isr) is refused
 * by the engine, whose traces read the record after every ISR: the node
 * answers PARAM_INVALID and the configuration in force keeps the rate;
 * a write the engine can run goes through after it. */
static void test_telemetry_rate_write_refused(void **state)
{
    (void)state;
    bench_t b;
    bench_attach(&b);
    assert_int_equal(sim_engine_last(b.e)->fw.state, MC_STATE_IDLE);
    assert_true(sim_engine_can_node(b.e)->drive_cfg.timing.telemetry_every_isr);
    const uint16_t pid = can_crc16_ccitt_false("timing.telemetry_every_isr");
    deliver(&b, can_cmd_param_write_bool(NODE, pid, false));
    const unsigned n_rsp = b.n_rsp;
    steps(&b, 20u);
    assert_int_equal(b.n_rsp, n_rsp + 1u);
    assert_int_equal(can_rsp_param_id(&b.last_rsp), pid);
    assert_int_equal(b.last_rsp.data[3], PARAM_INVALID);
    assert_true(sim_engine_can_node(b.e)->drive_cfg.timing.telemetry_every_isr);
    assert_true(mc_app_timing(&b.e->app)->telemetry_every_isr);
    const uint16_t pid_ok = can_crc16_ccitt_false(PARAM_NAME);
    deliver(&b, can_cmd_param_write_f32(NODE, pid_ok, PARAM_NEW));
    steps(&b, 20u);
    assert_int_equal(b.n_rsp, n_rsp + 2u);
    assert_int_equal(b.last_rsp.data[3], PARAM_OK);
    assert_near(sim_engine_can_node(b.e)->drive_cfg.foc_pi.speed_bandwidth_rad_s, PARAM_NEW, 0.0);
    free(b.e);
}

/* The hand-made CRCs against their standard check values. */
static void test_crc_check_values(void **state)
{
    (void)state;
    assert_int_equal(can_crc16_ccitt_false("123456789"), 0x29B1);
    const uint8_t check[] = { '1', '2', '3', '4', '5', '6', '7', '8', '9' };
    assert_int_equal(can_crc8_j1850_update(0xFFu, check, 9u) ^ 0xFFu, 0x4B);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc_check_values),
        cmocka_unit_test(test_attach_api),
        cmocka_unit_test(test_speed_timeout_param),
        cmocka_unit_test(test_apply_refused),
        cmocka_unit_test(test_telemetry_rate_write_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
