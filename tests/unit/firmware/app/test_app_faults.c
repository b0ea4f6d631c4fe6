/*
 * Fault latching through the application with the HAL stub (hal_stub.c):
 * the first fault since the last clear, the latched mask, and the fault
 * history ring (mc_app_fault_history: the latest MC_FAULT_HISTORY_LEN
 * events, newest first). The expected events are built here from what the
 * test injected and from its own count of ISR calls.
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "hal_stub.h"
#include "mc/app.h"

#define CALIB_N 8u

static mc_app_t app;
static mc_config_t cfg;
static mc_command_t cmd;
static uint32_t isr_calls; /* the test's own count of fast ISRs */

/* Offsets the calibration measures (exact in float), so the events' phase
 * currents are checked as offset-corrected. */
static const float offs[3] = { 0.125f, -0.25f, 0.0625f };

static mc_telemetry_t tlm(void)
{
    mc_telemetry_t t;
    assert_int_equal(mc_app_get_telemetry(&app, &t), MC_OK);
    return t;
}

static mc_telemetry_t isr(void)
{
    assert_int_equal(mc_app_set_command(&app, &cmd), MC_OK);
    mc_app_fast_isr(&app);
    isr_calls++;
    const mc_telemetry_t t = tlm();
    assert_int_equal(t.isr_count, isr_calls);
    return t;
}

/* Raw ADC currents whose offset-corrected values are i_A. */
static void set_currents(float a, float b, float c)
{
    g_hal.adc.i_abc_A[0] = a + offs[0];
    g_hal.adc.i_abc_A[1] = b + offs[1];
    g_hal.adc.i_abc_A[2] = c + offs[2];
}

static int setup(void **state)
{
    (void)state;
    hal_stub_reset();
    mc_config_init_default(&cfg);
    cfg.timing.calib_time_s = (float)CALIB_N / cfg.timing.f_pwm_Hz;
    assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
    cmd = (mc_command_t){ .mode = MC_MODE_CURRENT };
    isr_calls = 0u;
    for (int k = 0; k < 3; ++k) {
        g_hal.adc.i_abc_A[k] = offs[k];
    }
    return 0;
}

static void go_to_run(void)
{
    cmd.enable = true;
    for (uint32_t k = 0; k <= CALIB_N; ++k) {
        (void)isr();
    }
    assert_int_equal(isr().state, MC_STATE_RUN);
}

/* The event the test expects. */
static mc_fault_event_t event(uint32_t isr_count, uint32_t bits, mc_state_t st, float a, float b,
                              float c, float v_dc)
{
    mc_fault_event_t e;
    memset(&e, 0, sizeof e);
    e.isr_count = isr_count;
    e.faults = bits;
    e.state = st;
    e.i_abc_A[0] = a;
    e.i_abc_A[1] = b;
    e.i_abc_A[2] = c;
    e.v_dc_V = v_dc;
    e.omega_m_rad_s = 0.0f; /* the encoder does not move */
    return e;
}

static void assert_event(const mc_fault_event_t *got, const mc_fault_event_t *exp, int index)
{
    if (got->isr_count != exp->isr_count || got->faults != exp->faults ||
        got->state != exp->state) {
        fail_msg("event %d: isr %u bits 0x%x state %d, expected isr %u bits 0x%x state %d", index,
                 (unsigned)got->isr_count, (unsigned)got->faults, (int)got->state,
                 (unsigned)exp->isr_count, (unsigned)exp->faults, (int)exp->state);
    }
    for (int k = 0; k < 3; ++k) {
        assert_true(got->i_abc_A[k] == exp->i_abc_A[k]);
    }
    assert_true(got->v_dc_V == exp->v_dc_V);
    assert_true(got->omega_m_rad_s == exp->omega_m_rad_s);
}

static void assert_history(const mc_fault_event_t *expected_oldest_first, uint32_t n_events,
                           uint32_t n_asked)
{
    mc_fault_event_t out[MC_FAULT_HISTORY_LEN + 4];
    memset(out, 0xa5, sizeof out);
    uint32_t copied = 12345u;
    assert_true(n_asked <= MC_FAULT_HISTORY_LEN + 4u);
    assert_int_equal(mc_app_fault_history(&app, out, n_asked, &copied), MC_OK);
    uint32_t kept = (n_events < MC_FAULT_HISTORY_LEN) ? n_events : MC_FAULT_HISTORY_LEN;
    const uint32_t m = (n_asked < kept) ? n_asked : kept;
    assert_int_equal(copied, m);
    for (uint32_t j = 0; j < m; ++j) {
        assert_event(&out[j], &expected_oldest_first[n_events - 1u - j], (int)j);
    }
    /* nothing written past the copied events */
    mc_fault_event_t untouched;
    memset(&untouched, 0xa5, sizeof untouched);
    for (uint32_t j = m; j < n_asked; ++j) {
        assert_memory_equal(&out[j], &untouched, sizeof untouched);
    }
}

/* Two different faults in successive ISRs: an over-current sample in RUN,
 * then the external fault input in FAULT. first_fault: the first ISR's
 * bits; latched: both; the history: both events, newest first, with their
 * ISR, bits, the state they interrupted and the sample's values. A cause
 * that stays present adds no event (only new bits are events). */
static void test_two_faults_first_and_history(void **state)
{
    (void)state;
    go_to_run();
    mc_fault_event_t exp[2];

    set_currents(0.0f, -25.0f, 0.0f); /* |i_b| > i_trip = 20 A */
    mc_telemetry_t t = isr();
    exp[0] = event(isr_calls, MC_FAULT_OVERCURRENT, MC_STATE_RUN, 0.0f, -25.0f, 0.0f, 48.0f);
    assert_int_equal(t.state, MC_STATE_FAULT);
    assert_int_equal(t.first_fault, MC_FAULT_OVERCURRENT);
    assert_int_equal(t.faults_latched, MC_FAULT_OVERCURRENT);
    assert_history(exp, 1u, 4u);

    set_currents(0.0f, 0.0f, 0.0f);
    g_hal.fault_input = true;
    t = isr();
    exp[1] = event(isr_calls, MC_FAULT_EXTERNAL, MC_STATE_FAULT, 0.0f, 0.0f, 0.0f, 48.0f);
    assert_int_equal(t.first_fault, MC_FAULT_OVERCURRENT);
    assert_int_equal(t.faults_latched, MC_FAULT_OVERCURRENT | MC_FAULT_EXTERNAL);
    assert_history(exp, 2u, 4u);
    assert_history(exp, 2u, 1u); /* only the newest */
    assert_history(exp, 2u, 0u);

    for (int k = 0; k < 5; ++k) { /* the cause stays: no new event */
        t = isr();
        assert_int_equal(t.faults_active & MC_FAULT_EXTERNAL, MC_FAULT_EXTERNAL);
    }
    assert_history(exp, 2u, 4u);
    assert_int_equal(tlm().first_fault, MC_FAULT_OVERCURRENT);
}

static void clear_faults(void)
{
    cmd.clear_fault = false;
    (void)isr();
    cmd.clear_fault = true;
    const mc_telemetry_t t = isr();
    cmd.clear_fault = false;
    assert_int_equal(t.state, MC_STATE_IDLE);
    assert_int_equal(t.faults_latched, 0u);
    assert_int_equal(t.first_fault, 0u);
}

/* A clear resets first_fault and the latched mask, not the history; after
 * more faults (clear and re-fault from IDLE, with different causes) the
 * ring keeps the latest MC_FAULT_HISTORY_LEN events; the first fault after
 * each clear is that fault; an ISR with two new causes is one event with
 * both bits (and both are the first fault). */
static void test_clear_and_ring(void **state)
{
    (void)state;
    go_to_run();
    enum { N_REFAULTS = 11 };
    mc_fault_event_t exp[2 + N_REFAULTS];
    uint32_t n = 0;
    set_currents(0.0f, -25.0f, 0.0f);
    (void)isr();
    exp[n++] = event(isr_calls, MC_FAULT_OVERCURRENT, MC_STATE_RUN, 0.0f, -25.0f, 0.0f, 48.0f);
    set_currents(0.0f, 0.0f, 0.0f);
    g_hal.fault_input = true;
    (void)isr();
    exp[n++] = event(isr_calls, MC_FAULT_EXTERNAL, MC_STATE_FAULT, 0.0f, 0.0f, 0.0f, 48.0f);
    g_hal.fault_input = false;
    cmd.enable = false; /* re-arm; stays IDLE after the clears */

    clear_faults();
    assert_history(exp, n, MC_FAULT_HISTORY_LEN); /* kept across the clear */

    for (int r = 0; r < N_REFAULTS; ++r) {
        uint32_t bits = 0u;
        float i_a = 0.0f, v_dc = 48.0f;
        switch (r % 4) {
        case 0:
            g_hal.fault_input = true;
            bits = MC_FAULT_EXTERNAL;
            break;
        case 1:
            i_a = 20.5f + (float)r; /* > i_trip */
            bits = MC_FAULT_OVERCURRENT;
            break;
        case 2:
            v_dc = 61.0f + (float)r; /* > v_dc_max */
            bits = MC_FAULT_DC_OVERVOLTAGE;
            break;
        default: /* two causes in one ISR */
            g_hal.fault_input = true;
            v_dc = 70.0f;
            bits = MC_FAULT_EXTERNAL | MC_FAULT_DC_OVERVOLTAGE;
            break;
        }
        set_currents(i_a, 0.0f, 0.0f);
        g_hal.adc.v_dc_V = v_dc;
        const mc_telemetry_t t = isr();
        exp[n++] = event(isr_calls, bits, MC_STATE_IDLE, i_a, 0.0f, 0.0f, v_dc);
        assert_int_equal(t.state, MC_STATE_FAULT);
        assert_int_equal(t.first_fault, bits);
        assert_int_equal(t.faults_latched, bits);
        assert_history(exp, n, MC_FAULT_HISTORY_LEN + 4u);
        g_hal.fault_input = false;
        set_currents(0.0f, 0.0f, 0.0f);
        g_hal.adc.v_dc_V = 48.0f;
        clear_faults();
        assert_history(exp, n, MC_FAULT_HISTORY_LEN + 4u);
    }
    assert_int_equal(n, 13u);
    assert_true(n > MC_FAULT_HISTORY_LEN);
    assert_history(exp, n, MC_FAULT_HISTORY_LEN); /* the latest 8 */
    assert_history(exp, n, 3u);                   /* the latest 3 */
}

/* A HAL with over-current comparators (hal_pwm_overcurrent_arm): the
 * drive arms them at its trip level; their trip in a steady RUN ISR, with
 * sampled currents inside the level, latches OVERCURRENT and stops the
 * outputs in that ISR; a non-finite current in a steady RUN ISR, which the
 * steady ISR no longer compares, still latches NONFINITE there (the
 * current loop's outputs). Without comparators nothing is armed. */
static void test_overcurrent_comparator(void **state)
{
    (void)state;
    assert_true(g_hal.oc_trip_A == 0.0f); /* the stub's default: none */
    for (int c = 0; c < 2; ++c) {
        (void)setup(NULL);
        g_hal.oc_comparator = true;
        assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
        assert_true(g_hal.oc_trip_A == cfg.protection.i_trip_A);
        cmd.i_q_ref_A = 1.0f;
        go_to_run();
        for (int k = 0; k < 5; ++k) {
            assert_int_equal(isr().state, MC_STATE_RUN);
        }
        if (c == 0) {
            g_hal.oc_active = true;
        } else {
            set_currents(NAN, 0.0f, 0.0f);
        }
        const mc_telemetry_t t = isr();
        assert_int_equal(t.state, MC_STATE_FAULT);
        assert_int_equal(t.first_fault, c == 0 ? MC_FAULT_OVERCURRENT : MC_FAULT_NONFINITE);
        assert_false(g_hal.outputs_enabled);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_two_faults_first_and_history, setup),
        cmocka_unit_test_setup(test_clear_and_ring, setup),
        cmocka_unit_test_setup(test_overcurrent_comparator, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
