/*
 * The setpoint stage (mc/outer_loop.h) against references written out
 * here: work on the slow tick only (an input: the application's
 * decimation, tested in test_app_fsm), the position P loop and its clamp,
 * the speed clamp, the current-mode circle limit, references held between
 * ticks, reset, parameter checks.
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/outer_loop.h"
#include "test_rng.h"

#define KP    12.5
#define W_MAX 40.0
#define I_MAX 10.0

static mc_outer_loop_params_t params(void)
{
    return (mc_outer_loop_params_t){
        .position_kp_per_s = (float)KP,
        .omega_max_rad_s = (float)W_MAX,
        .i_max_A = (float)I_MAX,
    };
}

static mc_outer_loop_f32_t make(void)
{
    mc_outer_loop_f32_t o;
    const mc_outer_loop_params_t p = params();
    assert_int_equal(mc_outer_loop_init_f32(&o, &p), MC_OK);
    return o;
}

static double clamp(double x, double lim)
{
    return fmax(-lim, fmin(lim, x));
}

/* One call in speed / position mode, a slow tick or not, with a fresh
 * telemetry record; checks that the return value and the flag say it. */
static void step(mc_outer_loop_f32_t *o, const mc_command_t *cmd, float theta_m_rad,
                 mc_telemetry_t *t, bool tick)
{
    *t = (mc_telemetry_t){ .theta_m_rad = theta_m_rad };
    o->tick = tick;
    assert_int_equal(mc_outer_loop_speed_f32(o, cmd, t), tick);
    assert_int_equal(t->slow_loop_ran, tick);
    mc_outer_loop_publish_f32(o, t);
}

static void test_init_checks(void **state)
{
    (void)state;
    const struct {
        mc_outer_loop_params_t p;
        mc_status_t st;
    } c[] = {
        { { 0.0f, 40.0f, 10.0f }, MC_ERR_PARAM },
        { { 12.5f, 0.0f, 10.0f }, MC_ERR_PARAM },
        { { 12.5f, 40.0f, 0.0f }, MC_ERR_PARAM },
        { { 12.5f, 40.0f, -1.0f }, MC_ERR_PARAM },
        { { 12.5f, 40.0f, NAN }, MC_ERR_NONFINITE },
        { { NAN, 40.0f, 10.0f }, MC_ERR_NONFINITE },
        { { 12.5f, INFINITY, 10.0f }, MC_ERR_NONFINITE },
        { { 12.5f, 40.0f, 10.0f }, MC_OK },
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; ++i) {
        mc_outer_loop_f32_t o;
        memset(&o, 0x5A, sizeof o);
        mc_outer_loop_f32_t pattern;
        memset(&pattern, 0x5A, sizeof pattern);
        const mc_status_t st = mc_outer_loop_init_f32(&o, &c[i].p);
        if (st != c[i].st) {
            fail_msg("case %zu: got %d, expected %d", i, (int)st, (int)c[i].st);
        }
        if (st != MC_OK) {
            assert_memory_equal(&o, &pattern, sizeof o); /* untouched */
        } else {
            assert_true(o.i_d_ref_A == 0.0f && o.i_q_ref_A == 0.0f && o.omega_m_ref_rad_s == 0.0f);
        }
    }
}

/* Slow ticks on calls 0, N, 2N, ... for several N; the references change
 * only on a tick and are held (and published) in between. */
static void test_slow_tick_and_hold(void **state)
{
    (void)state;
    const uint32_t ns[] = { 1u, 2u, 7u, 10u };
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; ++i) {
        const uint32_t n = ns[i];
        mc_outer_loop_f32_t o = make();
        mc_command_t cmd = { .mode = MC_MODE_SPEED };
        double held = 0.0;
        for (uint32_t k = 0; k < 5u * n + 3u; ++k) {
            cmd.omega_m_ref_rad_s = (float)(0.5 * (double)k - 3.0);
            o.i_q_ref_A = 1.25f; /* the speed controller's, kept */
            o.i_d_ref_A = 0.75f; /* zeroed on a tick */
            mc_telemetry_t t;
            const bool tick = (k % n) == 0u;
            step(&o, &cmd, 0.0f, &t, tick);
            if (tick) {
                held = 0.5 * (double)k - 3.0;
            }
            assert_near(t.omega_m_ref_rad_s, held, 0.0);
            assert_near(t.i_d_ref_A, tick ? 0.0 : 0.75, 0.0);
            assert_near(t.i_q_ref_A, 1.25, 0.0);
        }
    }
}

/* Speed mode: the command limited to +-omega_max. */
static void test_speed_clamp(void **state)
{
    (void)state;
    mc_outer_loop_f32_t o = make();
    const float w[] = { 0.0f, 15.0f, -39.9f, 40.0f, 40.1f, -41.0f, 1e30f, -INFINITY, INFINITY };
    for (size_t i = 0; i < sizeof w / sizeof w[0]; ++i) {
        const mc_command_t cmd = { .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = w[i] };
        mc_telemetry_t t;
        step(&o, &cmd, 0.0f, &t, true);
        assert_near(t.omega_m_ref_rad_s, clamp((double)w[i], W_MAX), 0.0);
    }
    /* NaN is not clamped away (the application faults on it). */
    const mc_command_t nan_cmd = { .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = NAN };
    mc_telemetry_t t;
    step(&o, &nan_cmd, 0.0f, &t, true);
    assert_true(isnan(t.omega_m_ref_rad_s));
}

/* Position mode: omega_ref = clamp(kp (theta_ref - theta), omega_max),
 * computed from the measured position on each tick only. */
static void test_position_loop_output_and_clamp(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(0x0C7E2u);
    mc_outer_loop_f32_t o = make();
    for (int i = 0; i < 3000; ++i) {
        const double r = test_rng_range(&rng, -20.0, 20.0);
        const double y = test_rng_range(&rng, -20.0, 20.0);
        const mc_command_t cmd = { .mode = MC_MODE_POSITION,
                                   .theta_m_ref_rad = (float)r,
                                   .omega_m_ref_rad_s = 1.0f }; /* ignored */
        mc_telemetry_t t;
        const bool tick = (i % 3) == 0;
        const double held = (double)o.omega_m_ref_rad_s;
        step(&o, &cmd, (float)y, &t, tick);
        if (!tick) {
            assert_near(t.omega_m_ref_rad_s, held, 0.0);
        } else {
            const double want = clamp(KP * ((double)(float)r - (double)(float)y), W_MAX);
            assert_near(t.omega_m_ref_rad_s, want, 1e-6 * (1.0 + fabs(want)));
            assert_near(t.i_d_ref_A, 0.0, 0.0);
        }
    }
    /* Clamp both ways, exactly at the limit. */
    const mc_command_t far = { .mode = MC_MODE_POSITION, .theta_m_ref_rad = 100.0f };
    mc_telemetry_t t;
    step(&o, &far, 0.0f, &t, true);
    assert_near(t.omega_m_ref_rad_s, W_MAX, 0.0);
    step(&o, &far, 200.0f, &t, true);
    assert_near(t.omega_m_ref_rad_s, -W_MAX, 0.0);
    /* Within the limit: the P law, 12.5 * 2 = 25 rad/s. */
    const mc_command_t near = { .mode = MC_MODE_POSITION, .theta_m_ref_rad = 3.0f };
    step(&o, &near, 1.0f, &t, true);
    assert_near(t.omega_m_ref_rad_s, 25.0, 1e-6);
}

/* Current mode: |i_ref| <= i_max with the direction kept, unchanged
 * inside the circle, omega_ref = 0; every call (no decimation). */
static void test_current_mode_circle_limit(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(0xC1C1Eu);
    mc_outer_loop_f32_t o = make();
    for (int i = 0; i < 5000; ++i) {
        const double mag = test_rng_range(&rng, 0.0, 3.0 * I_MAX);
        const double ang = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        const float id = (float)(mag * cos(ang));
        const float iq = (float)(mag * sin(ang));
        const mc_command_t cmd = {
            .mode = MC_MODE_CURRENT, .i_d_ref_A = id, .i_q_ref_A = iq, .omega_m_ref_rad_s = 5.0f
        };
        o.omega_m_ref_rad_s = 7.0f;
        mc_outer_loop_current_f32(&o, &cmd);
        mc_telemetry_t t = { 0 };
        mc_outer_loop_publish_f32(&o, &t);
        const double m_in = hypot((double)id, (double)iq);
        const double m_out = hypot((double)t.i_d_ref_A, (double)t.i_q_ref_A);
        assert_near(t.omega_m_ref_rad_s, 0.0, 0.0);
        if (m_in <= I_MAX * (1.0 - 1e-6)) {
            assert_true(t.i_d_ref_A == id && t.i_q_ref_A == iq);
        } else {
            assert_true(m_out <= I_MAX * (1.0 + 1e-6));
            assert_near(m_out, fmin(m_in, I_MAX), 1e-5 * I_MAX);
            const double d_ang = remainder(atan2((double)t.i_q_ref_A, (double)t.i_d_ref_A) -
                                               atan2((double)iq, (double)id),
                                           MC_TEST_TWO_PI);
            assert_true(fabs(d_ang) <= 1e-6);
        }
    }
    /* 3-4-5: (-30, 40) -> (-6, 8). */
    const mc_command_t c345 = { .mode = MC_MODE_CURRENT, .i_d_ref_A = -30.0f, .i_q_ref_A = 40.0f };
    mc_outer_loop_current_f32(&o, &c345);
    assert_near(o.i_d_ref_A, -6.0, 1e-5);
    assert_near(o.i_q_ref_A, 8.0, 1e-5);
    /* NaN stays NaN. */
    const mc_command_t c_nan = { .mode = MC_MODE_CURRENT, .i_d_ref_A = NAN, .i_q_ref_A = 1.0f };
    mc_outer_loop_current_f32(&o, &c_nan);
    assert_true(isnan(o.i_d_ref_A) || isnan(o.i_q_ref_A));
}

/* Reset: references to zero (published so); the next tick sets them. */
static void test_reset(void **state)
{
    (void)state;
    mc_outer_loop_f32_t o = make();
    mc_command_t cmd = { .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = 12.0f };
    mc_telemetry_t t;
    step(&o, &cmd, 0.0f, &t, true);
    o.i_q_ref_A = 3.0f;
    mc_outer_loop_reset_f32(&o);
    assert_true(o.i_d_ref_A == 0.0f && o.i_q_ref_A == 0.0f && o.omega_m_ref_rad_s == 0.0f);
    mc_telemetry_t r = { .i_d_ref_A = 1.0f, .i_q_ref_A = 1.0f, .omega_m_ref_rad_s = 1.0f };
    mc_outer_loop_publish_f32(&o, &r);
    assert_true(r.i_d_ref_A == 0.0f && r.i_q_ref_A == 0.0f && r.omega_m_ref_rad_s == 0.0f);
    cmd.omega_m_ref_rad_s = -7.0f;
    step(&o, &cmd, 0.0f, &t, false);
    assert_near(t.omega_m_ref_rad_s, 0.0, 0.0);
    step(&o, &cmd, 0.0f, &t, true);
    assert_near(t.omega_m_ref_rad_s, -7.0, 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init_checks),
        cmocka_unit_test(test_slow_tick_and_hold),
        cmocka_unit_test(test_speed_clamp),
        cmocka_unit_test(test_position_loop_output_and_clamp),
        cmocka_unit_test(test_current_mode_circle_limit),
        cmocka_unit_test(test_reset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
