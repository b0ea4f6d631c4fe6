/*
 * The CDOBC regulator's encoder speed (mc_ctl_cdobc_count_speed,
 * mc/ctl_cdobc.h) against an encoder turning at a known constant speed,
 * sampled every period: the count over the window quantises the speed to
 * one count per window; with the edge ages of the window's first and last
 * samples (M/T) the counts over the time between those edges recover the
 * speed to float32 rounding. No motion over the window is 0 either way,
 * and a missing age (-1: the HAL keeps no edge times) falls back to the
 * count.
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>

#include "mc/ctl_cdobc.h"

#define CPR   10000u
#define TS_S  1e-4
#define N_WIN 4u

static mc_ctl_cdobc_t window_ctl(void)
{
    mc_ctl_cdobc_t ctl = { 0 };
    ctl.cpr = CPR;
    ctl.n_count = N_WIN;
    ctl.count_rad_s = (float)(MC_TEST_TWO_PI / (CPR * N_WIN * TS_S));
    ctl.rad_per_count = (float)(MC_TEST_TWO_PI / CPR);
    ctl.window_s = (float)(N_WIN * TS_S);
    return ctl;
}

/* Count and edge age of the encoder at t for theta(t) = theta0 + w t. */
static void encoder_at(double theta0, double w, double t, int64_t *count, double *age)
{
    const double counts = (theta0 + w * t) * CPR / MC_TEST_TWO_PI;
    const double c = floor(counts);
    const double counts_per_s = w * CPR / MC_TEST_TWO_PI;
    *count = (int64_t)c;
    *age = (w > 0.0) ? (counts - c) / counts_per_s : (1.0 - (counts - c)) / -counts_per_s;
}

static void test_mt_recovers_the_speed(void **state)
{
    (void)state;
    const double speeds[] = { 52.36, -52.36, 3.0, 1000.0 };
    for (size_t i = 0; i < sizeof speeds / sizeof speeds[0]; ++i) {
        const double w = speeds[i];
        double err_mt = 0.0;
        double err_count = 0.0;
        for (uint32_t k = N_WIN; k < 400u; ++k) {
            int64_t c_old, c_new;
            double a_old, a_new;
            encoder_at(0.1234, w, (k - N_WIN) * TS_S, &c_old, &a_old);
            encoder_at(0.1234, w, k * TS_S, &c_new, &a_new);
            mc_ctl_cdobc_t ctl = window_ctl();
            ctl.count_sum = (int32_t)(c_new - c_old);
            if (ctl.count_sum == 0) {
                continue; /* slower than a count per window */
            }
            const float mt = mc_ctl_cdobc_count_speed(&ctl, (float)a_old, (float)a_new);
            const float count = mc_ctl_cdobc_count_speed(&ctl, -1.0f, (float)a_new);
            err_mt = fmax(err_mt, fabs(mt - w));
            err_count = fmax(err_count, fabs(count - w));
            /* the count alone: within one count per window */
            assert_true(fabs(count - w) <= ctl.count_rad_s * 1.0001);
        }
        printf("w %8.2f rad/s: |M/T - w| <= %.3g, |count - w| <= %.3g rad/s\n", w, err_mt,
               err_count);
        /* M/T: float32 rounding of the ages (1e-7 relative of 1 s at most)
         * and of the quotient */
        assert_true(err_mt <= 2e-6 * fabs(w) + 1e-4);
        assert_true(err_mt < 0.01 * err_count);
    }
}

static void test_no_motion_and_no_ages(void **state)
{
    (void)state;
    mc_ctl_cdobc_t ctl = window_ctl();
    ctl.count_sum = 0;
    assert_true(mc_ctl_cdobc_count_speed(&ctl, 0.5f, 0.5004f) == 0.0f);
    assert_true(mc_ctl_cdobc_count_speed(&ctl, -1.0f, -1.0f) == 0.0f);
    ctl.count_sum = 33;
    assert_true(mc_ctl_cdobc_count_speed(&ctl, -1.0f, -1.0f) == 33.0f * ctl.count_rad_s);
    assert_true(mc_ctl_cdobc_count_speed(&ctl, 1e-5f, -1.0f) == 33.0f * ctl.count_rad_s);
}

/* The ring behind it (mc_ctl_cdobc_observer_speed), sample by sample: the
 * estimator's speed until the window holds n_count steps, then M/T equal
 * to the true speed; after a restart in mid-run (a mode change), at a
 * new speed, the same from the restart sample on: the first window
 * starts at the restart sample, no age of the earlier run enters it. */
static void test_window_across_a_restart(void **state)
{
    (void)state;
    mc_ctl_cdobc_t ctl = window_ctl();
    ctl.half_cpr = (int32_t)(CPR / 2u);
    const double speeds[] = { 52.36, 20.0 };
    double theta0 = 0.1234;
    for (size_t r = 0; r < 2; ++r) {
        const double w = speeds[r];
        ctl.restart = true;
        for (uint32_t k = 0; k < 40u; ++k) {
            int64_t c;
            double age;
            encoder_at(theta0, w, k * TS_S, &c, &age);
            mc_telemetry_t t = { 0 };
            t.encoder_count = (uint32_t)(((c % CPR) + CPR) % CPR);
            t.encoder_edge_age_s = (float)age;
            t.omega_m_rad_s = -1.0f; /* the estimator's: marks "not yet" */
            const float w_obs = mc_ctl_cdobc_observer_speed(&ctl, &t);
            ctl.restart = false;
            if (k < N_WIN) {
                assert_true(w_obs == -1.0f);
            } else {
                assert_near(w_obs, w, 2e-6 * w + 1e-4);
            }
        }
        /* the next run goes on from where this one ended */
        theta0 += w * 40u * TS_S;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mt_recovers_the_speed),
        cmocka_unit_test(test_no_motion_and_no_ages),
        cmocka_unit_test(test_window_across_a_restart),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
