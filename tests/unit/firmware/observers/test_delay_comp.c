/*
 * PWM / computation delay helpers (mc/delay_comp.h):
 * - the advanced angle (a rotation by the advance, whose sine and cosine,
 *   from a series for small advances and mc_sincos_f32 beyond, are held
 *   from the last track) makes the voltage,
 *   averaged over the interval where it is really applied and seen in the
 *   true rotor frame, point where it was commanded (analytic average of the
 *   rotation over the interval); without the advance it lags by
 *   omega_e d Ts;
 * - the applied-voltage history returns the exact mean over the last
 *   sample interval of the piecewise-constant applied voltage (integrated
 *   independently here on a fine grid), for the documented timings;
 * - configuration and non-finite handling.
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/delay_comp.h"
#include "paper001_motor.h"
#include "test_rng.h"

#define TS P001_TS_S

/* Mean over [t0, t0 + Ts] of e^{-J theta(t)} e^{J theta_v} [vd; vq] with
 * theta(t) = theta0 + w t: the rotor-frame voltage the motor sees. The
 * mean of e^{-J w t} over the interval is
 * [[S, C], [-C, S]] with S = (sin(w t1) - sin(w t0)) / (w Ts),
 * C = (cos(w t0) - cos(w t1)) / (w Ts) ... applied to e^{J (theta_v -
 * theta0)} [vd; vq]. */
static void mean_rotor_frame_voltage(double theta0, double w, double t0, double theta_v, double vd,
                                     double vq, double out[2])
{
    const double t1 = t0 + TS;
    const double S = (sin(w * t1) - sin(w * t0)) / (w * TS); /* mean cos */
    const double C = (cos(w * t0) - cos(w * t1)) / (w * TS); /* mean sin */
    const double a = theta_v - theta0;
    const double x = cos(a) * vd - sin(a) * vq;
    const double y = sin(a) * vd + cos(a) * vq;
    /* e^{-J phi} = [[cos, sin], [-sin, cos]], averaged */
    out[0] = S * x + C * y;
    out[1] = -C * x + S * y;
}

/* theta_v of the advance tracked at w from its sine and cosine (double). */
static double advanced_angle(mc_delay_comp_f32_t *dc, float theta, float w)
{
    float s_v;
    float c_v;
    mc_delay_comp_track_f32(dc, w);
    mc_delay_comp_sincos_f32(dc, sinf(theta), cosf(theta), &s_v, &c_v);
    assert_near(hypot(s_v, c_v), 1.0, 1e-6);
    return atan2((double)s_v, (double)c_v);
}

static void test_advance_aligns_applied_voltage(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(15);
    for (int i = 0; i < 4000; i++) {
        const double d = (i % 4 == 0) ? 1.5 : (i % 4 == 1) ? 1.0 : test_rng_range(&rng, 0.5, 1.5);
        const double theta = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        /* rad/s el.: advances up to 0.75 rad, both sides of the series' limit */
        const double w = test_rng_range(&rng, -10000.0, 10000.0);
        const double vd = test_rng_range(&rng, -50.0, 50.0);
        const double vq = test_rng_range(&rng, -50.0, 50.0);
        for (int en = 0; en <= 1; en++) {
            mc_delay_comp_f32_t dc;
            assert_int_equal(mc_delay_comp_init_f32(&dc, (float)TS, (float)d, en), MC_OK);
            const double theta_v = advanced_angle(&dc, (float)theta, (float)w);
            /* the command computed at the sample t = 0 acts over
             * [(d - 1/2) Ts, (d + 1/2) Ts] */
            double seen[2];
            mean_rotor_frame_voltage(theta, w, (d - 0.5) * TS, theta_v, vd, vq, seen);
            const double err = remainder(atan2(seen[1], seen[0]) - atan2(vq, vd), MC_TEST_TWO_PI);
            if (en) {
                /* float32 sine and cosine: about 1e-6 rad */
                assert_true(fabs(err) < 2e-6);
                /* magnitude: sinc(w Ts / 2) */
                const double sinc = sin(w * TS / 2.0) / (w * TS / 2.0);
                assert_near(hypot(seen[0], seen[1]), sinc * hypot(vd, vq), 1e-4 * hypot(vd, vq));
            } else {
                assert_near(remainder(theta_v - (double)(float)theta, MC_TEST_TWO_PI), 0.0, 2e-7);
                assert_near(err, -w * d * TS, 2e-6);
            }
        }
    }
    /* switchable at run time; disabled, the given sine and cosine as they are */
    mc_delay_comp_f32_t dc;
    assert_int_equal(mc_delay_comp_init_f32(&dc, (float)TS, 1.5f, false), MC_OK);
    float s_v;
    float c_v;
    mc_delay_comp_track_f32(&dc, 1000.0f);
    mc_delay_comp_sincos_f32(&dc, 0.25f, 0.5f, &s_v, &c_v);
    assert_true(s_v == 0.25f && c_v == 0.5f);
    mc_delay_comp_enable_f32(&dc, true);
    assert_near(advanced_angle(&dc, 1.0f, 1000.0f), 1.0 + 1000.0 * 1.5 * TS, 1e-6);
    /* past pi */
    assert_near(advanced_angle(&dc, 3.14f, 1000.0f), 3.14 + 0.075 - MC_TEST_TWO_PI, 1e-6);
    /* held: the advance of the last track, whatever the angle */
    mc_delay_comp_track_f32(&dc, -2000.0f);
    for (int k = 0; k < 3; k++) {
        mc_delay_comp_sincos_f32(&dc, sinf(0.5f * (float)k), cosf(0.5f * (float)k), &s_v, &c_v);
        assert_near(atan2((double)s_v, (double)c_v), 0.5 * k - 2000.0 * 1.5 * TS, 1e-6);
    }
    /* non-finite: a speed (in the series and beyond it) or an angle */
    const float bad_w[] = { INFINITY, NAN };
    for (size_t k = 0; k < sizeof bad_w / sizeof bad_w[0]; k++) {
        mc_delay_comp_track_f32(&dc, bad_w[k]);
        mc_delay_comp_sincos_f32(&dc, 0.0f, 1.0f, &s_v, &c_v);
        assert_true(isnan(s_v) && isnan(c_v));
    }
    mc_delay_comp_track_f32(&dc, 1000.0f);
    mc_delay_comp_sincos_f32(&dc, NAN, NAN, &s_v, &c_v);
    assert_true(isnan(s_v) && isnan(c_v));
}

/* Initialised, the held advance is zero until the first track. */
static void test_initial_advance_is_zero(void **state)
{
    (void)state;
    mc_delay_comp_f32_t dc;
    assert_int_equal(mc_delay_comp_init_f32(&dc, (float)TS, 1.5f, true), MC_OK);
    float s_v;
    float c_v;
    mc_delay_comp_sincos_f32(&dc, 0.6f, 0.8f, &s_v, &c_v);
    assert_true(s_v == 0.6f && c_v == 0.8f);
}

/* Applied voltage: commands v_j (one per ISR j, at t_j = j Ts) hold on
 * [t_j + (d - 1/2) Ts, t_{j+1} + (d - 1/2) Ts). The exact mean over
 * [t_{k-1}, t_k] is computed here on a grid of 1000 midpoints per
 * interval (exact for interval boundaries on the grid: d in steps of
 * 1/1000), independently of the blend formula. */
#define N_CMD 200
static void test_applied_voltage_is_interval_mean(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(33);
    double cmd[N_CMD][2];
    for (int j = 0; j < N_CMD; j++) {
        cmd[j][0] = test_rng_range(&rng, -300.0, 300.0);
        cmd[j][1] = test_rng_range(&rng, -300.0, 300.0);
    }
    const double ds[5] = { 0.5, 1.0, 1.5, 0.731, 1.204 };
    for (int di = 0; di < 5; di++) {
        const double d = ds[di];
        mc_applied_voltage_f32_t av;
        assert_int_equal(mc_applied_voltage_init_f32(&av, (float)d), MC_OK);
        /* before ISR 0 nothing was commanded: 0 V (the reset value) */
        for (int k = 0; k < N_CMD; k++) {
            float va, vb;
            mc_applied_voltage_last_f32(&av, &va, &vb); /* over [t_{k-1}, t_k] */
            if (k >= 2) {
                double mean[2] = { 0.0, 0.0 };
                const int n_sub = 1000;
                for (int s = 0; s < n_sub; s++) {
                    const double t = (k - 1 + (s + 0.5) / n_sub) * TS;
                    /* the command active at t: the latest j with
                     * t_j + (d - 1/2) Ts <= t */
                    const int j = (int)floor(t / TS - (d - 0.5));
                    mean[0] += cmd[j][0] / n_sub;
                    mean[1] += cmd[j][1] / n_sub;
                }
                assert_near(va, mean[0], 1e-4);
                assert_near(vb, mean[1], 1e-4);
            }
            assert_int_equal(mc_applied_voltage_push_f32(&av, (float)cmd[k][0], (float)cmd[k][1]),
                             MC_OK);
        }
    }
}

static void test_config_and_nonfinite(void **state)
{
    (void)state;
    mc_delay_comp_f32_t dc;
    assert_int_equal(mc_delay_comp_init_f32(&dc, (float)TS, 0.49f, true), MC_ERR_PARAM);
    assert_int_equal(mc_delay_comp_init_f32(&dc, (float)TS, 1.51f, true), MC_ERR_PARAM);
    assert_int_equal(mc_delay_comp_init_f32(&dc, 0.0f, 1.0f, true), MC_ERR_PARAM);
    assert_int_equal(mc_delay_comp_init_f32(&dc, NAN, 1.0f, true), MC_ERR_NONFINITE);
    assert_int_equal(mc_delay_comp_init_f32(&dc, (float)TS, INFINITY, true), MC_ERR_NONFINITE);
    mc_applied_voltage_f32_t av;
    assert_int_equal(mc_applied_voltage_init_f32(&av, 0.4f), MC_ERR_PARAM);
    assert_int_equal(mc_applied_voltage_init_f32(&av, NAN), MC_ERR_NONFINITE);
    assert_int_equal(mc_applied_voltage_init_f32(&av, 1.0f), MC_OK);
    assert_int_equal(mc_applied_voltage_reset_f32(&av, 3.0f, -4.0f), MC_OK);
    float va, vb;
    mc_applied_voltage_last_f32(&av, &va, &vb);
    assert_near(va, 3.0f, 0.0f);
    assert_near(vb, -4.0f, 0.0f);
    mc_applied_voltage_f32_t before;
    memcpy(&before, &av, sizeof av);
    assert_int_equal(mc_applied_voltage_push_f32(&av, NAN, 0.0f), MC_ERR_NONFINITE);
    assert_int_equal(mc_applied_voltage_push_f32(&av, 0.0f, -INFINITY), MC_ERR_NONFINITE);
    assert_int_equal(mc_applied_voltage_reset_f32(&av, INFINITY, 0.0f), MC_ERR_NONFINITE);
    assert_memory_equal(&before, &av, sizeof av);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_advance_aligns_applied_voltage),
        cmocka_unit_test(test_initial_advance_is_zero),
        cmocka_unit_test(test_applied_voltage_is_interval_mean),
        cmocka_unit_test(test_config_and_nonfinite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
