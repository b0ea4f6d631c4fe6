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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mt_recovers_the_speed),
        cmocka_unit_test(test_no_motion_and_no_ages),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
