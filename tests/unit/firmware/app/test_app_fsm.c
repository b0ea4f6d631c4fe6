/*
 * State machine, fault latching and the command/telemetry exchange of the
 * drive application, with the HAL replaced by a stub (hal_stub.c); the
 * timing the firmware takes from the HAL at init (realised PWM period,
 * sample-to-apply delay) and where it shows: the deadline and the delay
 * compensation.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "hal_stub.h"
#include "mc/app.h"

#define CALIB_N 8u

static mc_app_t app;
static mc_config_t cfg;
static mc_command_t cmd;

static mc_telemetry_t tlm(void)
{
    mc_telemetry_t t;
    assert_int_equal(mc_app_get_telemetry(&app, &t), MC_OK);
    return t;
}

static void isr(void)
{
    assert_int_equal(mc_app_set_command(&app, &cmd), MC_OK);
    mc_app_fast_isr(&app);
}

static int setup(void **state)
{
    (void)state;
    hal_stub_reset();
    mc_config_init_default(&cfg);
    cfg.timing.calib_time_s = (float)CALIB_N / cfg.timing.f_pwm_Hz;
    cfg.timing.isr_overrun_limit = 1u;
    assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
    cmd = (mc_command_t){ .mode = MC_MODE_CURRENT };
    return 0;
}

/* IDLE -> CALIBRATING -> RUN with the PWM on. */
static void go_to_run(void)
{
    cmd.enable = true;
    isr();
    assert_int_equal(tlm().state, MC_STATE_CALIBRATING);
    for (uint32_t k = 0; k < CALIB_N; ++k) {
        assert_false(g_hal.outputs_enabled);
        isr();
    }
    assert_int_equal(tlm().state, MC_STATE_RUN);
    assert_true(g_hal.outputs_enabled);
    assert_true(g_hal.power_stage);
}

static void test_init_leaves_pwm_off_in_idle(void **state)
{
    (void)state;
    assert_true(fabsf(g_hal.f_pwm_Hz - 20000.0f) == 0.0f);
    assert_false(g_hal.outputs_enabled);
    assert_false(g_hal.power_stage);
    assert_int_equal(tlm().state, MC_STATE_IDLE);
    for (int k = 0; k < 10; ++k) {
        isr(); /* enable false: stays idle */
    }
    const mc_telemetry_t t = tlm();
    assert_int_equal(t.state, MC_STATE_IDLE);
    assert_int_equal(t.isr_count, 10u);
    assert_false(g_hal.outputs_enabled);
}

static void test_init_rejects_encoder_mismatch(void **state)
{
    (void)state;
    g_hal.encoder_cpr = 4096u;
    assert_int_equal(mc_app_init(&app, &cfg), MC_ERR_PARAM);
    g_hal.encoder_cpr = 10000u;
    cfg.motor.R_ohm = NAN;
    assert_int_equal(mc_app_init(&app, &cfg), MC_ERR_NONFINITE);
}

static void test_calibration_measures_offsets(void **state)
{
    (void)state;
    const float offs[3] = { 0.125f, -0.25f, 0.0625f };
    for (int k = 0; k < 3; ++k) {
        g_hal.adc.i_abc_A[k] = offs[k];
    }
    go_to_run();
    isr(); /* the first ISR that uses the new offsets */
    const mc_telemetry_t t = tlm();
    for (int k = 0; k < 3; ++k) {
        assert_near(t.i_offset_abc_A[k], offs[k], 1e-6);
        assert_near(t.i_abc_A[k], 0.0f, 1e-6); /* corrected */
    }
    /* Disable: IDLE and PWM off in the same call. */
    cmd.enable = false;
    isr();
    assert_int_equal(tlm().state, MC_STATE_IDLE);
    assert_false(g_hal.outputs_enabled);
    assert_false(g_hal.power_stage);
}

static void test_calibration_fault_on_large_offset(void **state)
{
    (void)state;
    g_hal.adc.i_abc_A[2] = 2.5f; /* > i_offset_max_A = 2 A */
    cmd.enable = true;
    for (uint32_t k = 0; k <= CALIB_N; ++k) {
        isr();
    }
    const mc_telemetry_t t = tlm();
    assert_int_equal(t.state, MC_STATE_FAULT);
    assert_int_equal(t.faults_latched, MC_FAULT_CALIBRATION);
    assert_false(g_hal.outputs_enabled);
}

/* First RUN ISR output against an independent computation: i_q_ref = 1 A,
 * zero measured current, rotor at count 0: v_q = kp + ki Ts (backward
 * Euler PI), v_d = 0, then inverse Park, inverse Clarke, min-max SVPWM. */
static void test_first_control_output_matches_reference(void **state)
{
    (void)state;
    go_to_run();
    cmd.i_q_ref_A = 1.0f;
    isr();
    const double Ts = 1.0 / 20000.0;
    const double w_c = (double)cfg.current.bandwidth_rad_s;
    const double v_q = 3.8e-3 * w_c + 0.225 * w_c * Ts;
    const double th = 3.0 * 0.5 * MC_TEST_TWO_PI / 10000.0; /* centre of count 0 */
    const double v_al = -v_q * sin(th), v_be = v_q * cos(th);
    const double va = v_al;
    const double vb = -0.5 * v_al + sqrt(3.0) / 2.0 * v_be;
    const double vc = -0.5 * v_al - sqrt(3.0) / 2.0 * v_be;
    const double vmax = fmax(va, fmax(vb, vc)), vmin = fmin(va, fmin(vb, vc));
    const double v0 = -0.5 * (vmax + vmin);
    const double d[3] = { 0.5 + (va + v0) / 48.0, 0.5 + (vb + v0) / 48.0, 0.5 + (vc + v0) / 48.0 };
    const mc_telemetry_t t = tlm();
    assert_near(t.v_q_V, v_q, 1e-4 * v_q);
    assert_near(t.v_d_V, 0.0, 1e-6);
    for (int k = 0; k < 3; ++k) {
        assert_near(g_hal.duty_abc[k], d[k], 1e-5);
    }
    assert_true(g_hal.outputs_enabled);
}

/* ---- each fault: latched, PWM off in the same ISR call ----------------- */

typedef void (*cause_fn)(bool present);

static void cause_overcurrent(bool on)
{
    g_hal.adc.i_abc_A[1] = on ? -25.0f : 0.0f;
}
static void cause_overvoltage(bool on)
{
    g_hal.adc.v_dc_V = on ? 65.0f : 48.0f;
}
static void cause_undervoltage(bool on)
{
    g_hal.adc.v_dc_V = on ? 15.0f : 48.0f;
}
static void cause_nan_current(bool on)
{
    g_hal.adc.i_abc_A[0] = on ? NAN : 0.0f;
}
static void cause_inf_vdc(bool on)
{
    g_hal.adc.v_dc_V = on ? INFINITY : 48.0f;
}
static void cause_external(bool on)
{
    g_hal.fault_input = on;
}
static void cause_encoder(bool on)
{
    g_hal.encoder_count = on ? 10000u : 0u;
}
/* Each cycle-counter read advances the stub clock by cycle_step, so the
 * ISR measures its cost as one step: 51 cycles = 51 us at
 * HAL_STUB_CYCLE_HZ, over the 50 us period at 20 kHz. */
#define OVERRUN_CYCLES 51u
static void cause_overrun(bool on)
{
    g_hal.cycle_step = on ? OVERRUN_CYCLES : 2u;
}

static const struct {
    cause_fn cause;
    uint32_t fault;
} fault_cases[] = {
    { cause_overcurrent, MC_FAULT_OVERCURRENT },
    { cause_overvoltage, MC_FAULT_DC_OVERVOLTAGE },
    { cause_undervoltage, MC_FAULT_DC_UNDERVOLTAGE },
    { cause_nan_current, MC_FAULT_NONFINITE },
    { cause_inf_vdc, MC_FAULT_NONFINITE },
    { cause_external, MC_FAULT_EXTERNAL },
    { cause_encoder, MC_FAULT_ENCODER },
    { cause_overrun, MC_FAULT_ISR_OVERRUN },
};

static void test_each_fault_latches_and_clears_only_without_cause(void **state)
{
    for (size_t i = 0; i < sizeof fault_cases / sizeof fault_cases[0]; ++i) {
        setup(state);
        go_to_run();
        fault_cases[i].cause(true);
        isr();
        mc_telemetry_t t = tlm();
        assert_int_equal(t.state, MC_STATE_FAULT);
        assert_int_equal(t.faults_latched, fault_cases[i].fault);
        assert_false(g_hal.outputs_enabled); /* same call */
        assert_false(g_hal.power_stage);
        assert_false(t.outputs_enabled);
        /* Clear request while the cause is present: refused. */
        if (fault_cases[i].fault != MC_FAULT_ISR_OVERRUN) {
            cmd.clear_fault = true;
            isr();
            assert_int_equal(tlm().state, MC_STATE_FAULT);
            cmd.clear_fault = false;
        }
        /* Cause gone: still latched without a request. */
        fault_cases[i].cause(false);
        for (int k = 0; k < 5; ++k) {
            isr();
            assert_int_equal(tlm().state, MC_STATE_FAULT);
            assert_false(g_hal.outputs_enabled);
        }
        t = tlm();
        assert_int_equal(t.faults_active, 0u);
        assert_int_equal(t.faults_latched, fault_cases[i].fault);
        /* Rising edge of clear_fault: IDLE, but enable must be re-armed. */
        cmd.clear_fault = true;
        isr();
        t = tlm();
        assert_int_equal(t.state, MC_STATE_IDLE);
        assert_int_equal(t.faults_latched, 0u);
        isr();
        assert_int_equal(tlm().state, MC_STATE_IDLE);
        cmd.enable = false;
        isr();
        go_to_run();
    }
}

/* A clear_fault held true does not clear a later fault (edge only). */
static void test_held_clear_does_not_clear(void **state)
{
    (void)state;
    go_to_run();
    cmd.clear_fault = true;
    isr();
    cause_external(true);
    isr();
    cause_external(false);
    for (int k = 0; k < 20; ++k) {
        isr();
    }
    assert_int_equal(tlm().state, MC_STATE_FAULT);
}

/* With isr_overrun_limit = 3, isolated overruns are counted but only the
 * third consecutive one faults. */
static void test_overrun_limit_counts_consecutive(void **state)
{
    (void)state;
    cfg.timing.isr_overrun_limit = 3u;
    assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
    go_to_run();
    for (int k = 0; k < 2; ++k) {
        cause_overrun(true);
        isr();
        isr();
        cause_overrun(false);
        isr();
    }
    mc_telemetry_t t = tlm();
    assert_int_equal(t.state, MC_STATE_RUN);
    assert_int_equal(t.isr_overruns, 4u);
    assert_near(t.isr_cost_max_s, (double)OVERRUN_CYCLES / (double)HAL_STUB_CYCLE_HZ, 1e-9);
    cause_overrun(true);
    isr();
    isr();
    assert_int_equal(tlm().state, MC_STATE_RUN);
    isr();
    t = tlm();
    assert_int_equal(t.state, MC_STATE_FAULT);
    assert_int_equal(t.faults_latched, MC_FAULT_ISR_OVERRUN);
    assert_false(g_hal.outputs_enabled);
}

/* Non-finite references in RUN fault in the same call. */
static void test_nan_reference_faults(void **state)
{
    (void)state;
    go_to_run();
    cmd.i_d_ref_A = NAN;
    isr();
    assert_int_equal(tlm().state, MC_STATE_FAULT);
    assert_int_equal(tlm().faults_latched, MC_FAULT_NONFINITE);
    assert_false(g_hal.outputs_enabled);
}

/* A non-finite position reference faults in the ISR that first sees it in
 * MC_MODE_POSITION, also after steady ISRs (mc_app_run_key sends that
 * ISR through the general path, which tests it); in the other modes the
 * field is unused and does not fault. */
static void test_nan_position_reference_faults_in_position_mode(void **state)
{
    (void)state;
    go_to_run();
    cmd.mode = MC_MODE_SPEED;
    cmd.theta_m_ref_rad = NAN;
    for (int k = 0; k < 25; ++k) { /* steady ones, and slow ticks */
        isr();
    }
    assert_int_equal(tlm().state, MC_STATE_RUN);
    cmd.mode = MC_MODE_POSITION;
    cmd.theta_m_ref_rad = 0.2f;
    for (int k = 0; k < 25; ++k) {
        isr();
    }
    assert_int_equal(tlm().state, MC_STATE_RUN);
    cmd.theta_m_ref_rad = INFINITY;
    isr();
    assert_int_equal(tlm().state, MC_STATE_FAULT);
    assert_int_equal(tlm().faults_latched, MC_FAULT_NONFINITE);
    assert_false(g_hal.outputs_enabled);
}

/* Current references are limited to the i_max circle. */
static void test_current_reference_limited(void **state)
{
    (void)state;
    go_to_run();
    cmd.i_d_ref_A = -30.0f;
    cmd.i_q_ref_A = 40.0f;
    isr();
    const mc_telemetry_t t = tlm();
    assert_near(t.i_d_ref_A, -6.0, 1e-4); /* i_max = 10 A, 3-4-5 */
    assert_near(t.i_q_ref_A, 8.0, 1e-4);
}

static void test_command_mode_validated(void **state)
{
    (void)state;
    mc_command_t bad = { .mode = (mc_mode_t)7 };
    assert_int_equal(mc_app_set_command(&app, &bad), MC_ERR_PARAM);
}

/* With the under-voltage check off (v_dc_min_V = 0), a bus in RUN that
 * the modulator cannot divide by (at or below 0 V, or below the smallest
 * normal float) is DC_UNDERVOLTAGE, not a non-finite value, in current
 * and in speed mode; the smallest normal bus still runs. */
static void test_zero_bus_with_check_off_is_undervoltage(void **state)
{
    const mc_mode_t modes[] = { MC_MODE_CURRENT, MC_MODE_SPEED };
    const float buses[] = { 0.0f, -0.0f, -48.0f, 1e-40f, FLT_MIN * 0.5f };
    for (size_t m = 0; m < 2u; ++m) {
        for (size_t b = 0; b < sizeof buses / sizeof buses[0]; ++b) {
            (void)setup(state);
            cfg.protection.v_dc_min_V = 0.0f;
            assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
            go_to_run();
            cmd.mode = modes[m];
            cmd.i_q_ref_A = 1.0f;
            cmd.omega_m_ref_rad_s = 5.0f;
            isr();
            assert_int_equal(tlm().state, MC_STATE_RUN);
            g_hal.adc.v_dc_V = FLT_MIN;
            isr();
            isr(); /* a steady ISR too */
            assert_int_equal(tlm().state, MC_STATE_RUN);
            g_hal.adc.v_dc_V = buses[b];
            isr();
            assert_int_equal(tlm().state, MC_STATE_FAULT);
            assert_int_equal(tlm().faults_latched, MC_FAULT_DC_UNDERVOLTAGE);
            assert_false(g_hal.outputs_enabled);
        }
    }
}

/* Speed mode: the slow loop runs in the first RUN ISR of the mode and then
 * in every (f_pwm / slow_loop_Hz)-th ISR; telemetry says which; current
 * mode never runs it. */
static void test_slow_loop_decimation_reported(void **state)
{
    (void)state;
    go_to_run();
    isr();
    assert_false(tlm().slow_loop_ran); /* current mode */
    cmd.mode = MC_MODE_SPEED;
    cmd.omega_m_ref_rad_s = 0.0f;
    const uint32_t n =
        (uint32_t)lround((double)cfg.timing.f_pwm_Hz / (double)cfg.timing.slow_loop_Hz);
    assert_int_equal(n, 10u); /* 20 kHz / 2 kHz */
    assert_true(n > 1u);
    for (uint32_t k = 0; k < 3u * n; ++k) {
        isr();
        assert_int_equal(tlm().state, MC_STATE_RUN);
        assert_int_equal(tlm().slow_loop_ran, (k % n) == 0u);
    }
}

/* A steady RUN ISR skips the clear of the telemetry record (fast_isr.c):
 * for every controller (with the encoder) and mode, over ISRs with
 * varying currents and encoder counts, its record must equal byte for
 * byte the record of the same ISR from a copy of the drive forced to
 * clear it first (the same HAL inputs for both). A field that a RUN path
 * writes only sometimes differs. */
static void test_steady_run_record_equals_cleared_record(void **state)
{
    (void)state;
    static const mc_mode_t modes[] = { MC_MODE_CURRENT, MC_MODE_SPEED, MC_MODE_POSITION };
    static mc_app_t ref;
    uint32_t compared = 0u;
    uint32_t controllers = 0u;
    for (int c = 0; c < (int)MC_CONTROLLER_COUNT; ++c) {
        hal_stub_reset();
        mc_config_init_default(&cfg);
        cfg.timing.calib_time_s = (float)CALIB_N / cfg.timing.f_pwm_Hz;
        cfg.controller = (mc_controller_t)c;
        if (mc_app_init(&app, &cfg) != MC_OK) {
            continue; /* needs its own motor / tuning */
        }
        controllers++;
        cmd = (mc_command_t){ .mode = MC_MODE_CURRENT };
        go_to_run();
        uint32_t k = 0u;
        for (size_t m = 0; m < sizeof modes / sizeof modes[0]; ++m) {
            cmd.mode = modes[m];
            cmd.i_q_ref_A = 0.5f;
            cmd.omega_m_ref_rad_s = 20.0f;
            cmd.theta_m_ref_rad = 0.3f;
            for (uint32_t n = 0; n < 60u; ++n, ++k) {
                g_hal.adc.i_abc_A[0] = 0.2f * sinf(0.05f * (float)k);
                g_hal.adc.i_abc_A[1] = 0.2f * sinf(0.05f * (float)k + 2.1f);
                g_hal.adc.i_abc_A[2] = -g_hal.adc.i_abc_A[0] - g_hal.adc.i_abc_A[1];
                g_hal.encoder_count = (k * 3u) % g_hal.encoder_cpr;
                assert_int_equal(mc_app_set_command(&app, &cmd), MC_OK);
                const bool steady = app.state == MC_STATE_RUN &&
                                    app.tlm_entry_state == MC_STATE_RUN &&
                                    app.cmd_buf[app.cmd_index].mode == app.mode;
                ref = app;
                ref.tlm_entry_state = MC_STATE_IDLE; /* forces the clear */
                ref.steady_key = MC_APP_NO_RUN_KEY;  /* in the general ISR */
                const hal_stub_t hal_in = g_hal;
                mc_app_fast_isr(&ref);
                g_hal = hal_in;
                mc_app_fast_isr(&app);
                assert_memory_equal(&ref.tlm, &app.tlm, sizeof app.tlm);
                compared += steady ? 1u : 0u;
            }
        }
    }
    /* all but the first ISR of each mode steady, no fault; the default
     * motor suits foc_pi, idapbc and one of the papers' regulators */
    assert_true(controllers >= 3u);
    assert_int_equal(compared, controllers * 3u * 59u);
}

/* ---- timing taken from the HAL (mc/timing.h, hal/pwm.h) ----------------- */

/* The HAL's realised period must be within 0.1 % of the request. */
static void test_init_checks_realised_period(void **state)
{
    (void)state;
    const double Ts = 1.0 / 20000.0;
    const double rel[] = { 0.002, -0.002, 0.0015, 0.0005, -0.0005, 0.0 };
    const mc_status_t expected[] = {
        MC_ERR_PARAM, MC_ERR_PARAM, MC_ERR_PARAM, MC_OK, MC_OK, MC_OK
    };
    for (size_t i = 0; i < sizeof rel / sizeof rel[0]; ++i) {
        hal_stub_reset();
        g_hal.pwm_period_s = (float)(Ts * (1.0 + rel[i]));
        if (mc_app_init(&app, &cfg) != expected[i]) {
            fail_msg("realised period %+.2f %%: got %d, expected %d", 100.0 * rel[i],
                     (int)mc_app_init(&app, &cfg), (int)expected[i]);
        }
        assert_int_equal(g_hal.pwm_inits, 1u);
        assert_true(g_hal.f_pwm_Hz == 20000.0f); /* what was asked */
    }
}

/* The deadline is the realised period, not the requested one: with a
 * 100 MHz cycle counter an ISR costing 50.01 us overruns a 50 us period
 * but not a realised 50.025 us (+0.05 %), and one costing 49.99 us
 * overruns a realised 49.975 us (-0.05 %). isr_overrun_limit = 1: the
 * first overrun faults, even in IDLE. */
static void test_deadline_uses_realised_period(void **state)
{
    (void)state;
    const struct {
        double rel;      /* realised period - request, relative */
        uint32_t cycles; /* ISR cost at 100 MHz */
        bool overrun;
    } c[] = {
        { 0.0, 5001u, true },
        { 0.0005, 5001u, false },
        { -0.0005, 4999u, true },
        { 0.0, 4999u, false },
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; ++i) {
        hal_stub_reset();
        g_hal.cycle_hz = 100000000u;
        g_hal.pwm_period_s = (float)((1.0 + c[i].rel) / 20000.0);
        assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
        g_hal.cycle_step = c[i].cycles;
        cmd = (mc_command_t){ .mode = MC_MODE_CURRENT };
        isr();
        const mc_telemetry_t t = tlm();
        assert_near(t.isr_cost_s, c[i].cycles * 1e-8, 1e-10);
        if (c[i].overrun) {
            assert_int_equal(t.isr_overruns, 1u);
            assert_int_equal(t.state, MC_STATE_FAULT);
            assert_int_equal(t.faults_latched, MC_FAULT_ISR_OVERRUN);
        } else {
            assert_int_equal(t.isr_overruns, 0u);
            assert_int_equal(t.state, MC_STATE_IDLE);
        }
    }
}

/* HAL failures at init: a rejected PWM rate, no cycle counter. */
static void test_init_rejects_hal_failures(void **state)
{
    (void)state;
    g_hal.pwm_init_status = HAL_ERR_PARAM;
    assert_int_equal(mc_app_init(&app, &cfg), MC_ERR_PARAM);
    hal_stub_reset();
    g_hal.cycle_hz = 0u;
    assert_int_equal(mc_app_init(&app, &cfg), MC_ERR_PARAM);
    hal_stub_reset();
    assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
}

/* delay_periods = 0 (default): the HAL's delay, which must lie in
 * [0.5, 1.5]; an override in the configuration replaces it, whatever the
 * HAL reports. */
static void test_init_delay_from_hal_or_override(void **state)
{
    (void)state;
    assert_near(cfg.timing.delay_periods, 0.0, 0.0);
    const float ok[] = { 0.5f, 1.0f, 1.5f };
    const float bad[] = { 0.4f, 1.6f, 0.0f, -1.0f };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; ++i) {
        g_hal.pwm_delay_periods = ok[i];
        assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
    }
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        g_hal.pwm_delay_periods = bad[i];
        assert_int_equal(mc_app_init(&app, &cfg), MC_ERR_PARAM);
    }
    cfg.timing.delay_periods = 1.2f;
    const float any[] = { 0.4f, 1.6f, 0.0f, 1.0f };
    for (size_t i = 0; i < sizeof any / sizeof any[0]; ++i) {
        g_hal.pwm_delay_periods = any[i];
        assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
    }
    /* An override outside [0.5, 1.5] is rejected even with a valid HAL. */
    g_hal.pwm_delay_periods = 1.0f;
    cfg.timing.delay_periods = 1.6f;
    assert_int_equal(mc_app_init(&app, &cfg), MC_ERR_PARAM);
}

/* The delay in use reaches the delay compensation (mc/delay_comp.h): the
 * inverse Park runs at theta_v = theta_e + omega_e d Ts, so the applied
 * voltage's angle minus the dq voltage's angle minus theta_e, divided by
 * omega_e Ts, is d. Measured from telemetry in RUN with the encoder turning
 * at a constant 2 counts per ISR (25.1 rad/s) and a small current
 * reference (no voltage limit). Error budget: sin/cos 3e-7, float angles
 * ~5e-7 rad against an advance of omega_e Ts = 3.8e-3 rad per period:
 * < 3e-4 periods; tolerance 2e-3. */
static double measured_delay_periods(float hal_delay, float override, bool compensation)
{
    hal_stub_reset();
    g_hal.pwm_delay_periods = hal_delay;
    cfg.timing.delay_periods = override;
    cfg.timing.delay_compensation = compensation;
    assert_int_equal(mc_app_init(&app, &cfg), MC_OK);
    cmd = (mc_command_t){ .mode = MC_MODE_CURRENT };
    isr(); /* primes the encoder at count 0 */
    go_to_run();
    cmd.i_q_ref_A = 0.2f;
    uint32_t count = 0u;
    for (int k = 0; k < 400; ++k) {
        count = (count + 2u) % 10000u;
        g_hal.encoder_count = count;
        isr();
    }
    const mc_telemetry_t t = tlm();
    assert_int_equal(t.state, MC_STATE_RUN);
    assert_false(t.v_saturated);
    const double w_e = 3.0 * (double)t.omega_m_rad_s;
    const double w_true = 2.0 * MC_TEST_TWO_PI / 10000.0 * 20000.0;
    assert_near(t.omega_m_rad_s, w_true, 1e-3 * w_true);
    const double adv =
        remainder(atan2((double)t.v_beta_V, (double)t.v_alpha_V) -
                      atan2((double)t.v_q_V, (double)t.v_d_V) - (double)t.theta_e_rad,
                  MC_TEST_TWO_PI);
    return adv / (w_e * (1.0 / 20000.0));
}

static void test_delay_compensation_uses_hal_delay(void **state)
{
    (void)state;
    assert_near(measured_delay_periods(1.0f, 0.0f, true), 1.0, 2e-3);
    assert_near(measured_delay_periods(1.5f, 0.0f, true), 1.5, 2e-3);
    assert_near(measured_delay_periods(0.5f, 0.0f, true), 0.5, 2e-3);
    /* The override wins over the HAL. */
    assert_near(measured_delay_periods(1.0f, 1.2f, true), 1.2, 2e-3);
    assert_near(measured_delay_periods(1.5f, 1.2f, true), 1.2, 2e-3);
    /* Compensation off: no advance whatever the delay. */
    assert_near(measured_delay_periods(1.5f, 0.0f, false), 0.0, 2e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_init_leaves_pwm_off_in_idle, setup),
        cmocka_unit_test_setup(test_init_rejects_encoder_mismatch, setup),
        cmocka_unit_test_setup(test_calibration_measures_offsets, setup),
        cmocka_unit_test_setup(test_calibration_fault_on_large_offset, setup),
        cmocka_unit_test_setup(test_first_control_output_matches_reference, setup),
        cmocka_unit_test_setup(test_each_fault_latches_and_clears_only_without_cause, setup),
        cmocka_unit_test_setup(test_held_clear_does_not_clear, setup),
        cmocka_unit_test_setup(test_overrun_limit_counts_consecutive, setup),
        cmocka_unit_test_setup(test_nan_reference_faults, setup),
        cmocka_unit_test_setup(test_nan_position_reference_faults_in_position_mode, setup),
        cmocka_unit_test_setup(test_current_reference_limited, setup),
        cmocka_unit_test_setup(test_command_mode_validated, setup),
        cmocka_unit_test_setup(test_slow_loop_decimation_reported, setup),
        cmocka_unit_test_setup(test_steady_run_record_equals_cleared_record, setup),
        cmocka_unit_test(test_zero_bus_with_check_off_is_undervoltage),
        cmocka_unit_test_setup(test_init_checks_realised_period, setup),
        cmocka_unit_test_setup(test_deadline_uses_realised_period, setup),
        cmocka_unit_test_setup(test_init_rejects_hal_failures, setup),
        cmocka_unit_test_setup(test_init_delay_from_hal_or_override, setup),
        cmocka_unit_test_setup(test_delay_compensation_uses_hal_delay, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
