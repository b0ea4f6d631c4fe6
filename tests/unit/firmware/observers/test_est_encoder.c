/*
 * The encoder estimator's step (mc/est_encoder.h): in RUN between slow
 * ticks its sine and cosine are the last sample's, rotated by the count's
 * step; on the slow tick and outside RUN they are the polynomial's of the
 * angle it reports. Against double sin and cos of that angle, at 0.02 and
 * 0.1 rad per sample in both directions: within the polynomial's error
 * plus, per rotation since the last slow tick, the series' angle error
 * |d|^5 / 30, its shortening d^4 / 24 and three float roundings of the
 * products and sums (1.8e-7); bit for bit the polynomial's on the slow
 * tick and outside RUN. A rotation before any step gives NaN.
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mc/config.h"
#include "mc/est_encoder.h"
#include "mc/timing.h"

#define SLOW_EVERY 10

typedef struct {
    mc_est_encoder_t est;
    mc_est_input_t in;
} fixture_t;

static void init(fixture_t *fx)
{
    mc_config_t cfg;
    mc_config_init_default(&cfg);
    /* the plausible count step: 2x this, above the 0.1 rad per sample */
    cfg.protection.overspeed_rad_s = 1000.0f;
    mc_timing_t tm;
    assert_int_equal(mc_timing_init(&tm, &cfg.timing, 1.0f / cfg.timing.f_pwm_Hz, 1.5f), MC_OK);
    assert_int_equal(mc_est_encoder_init(&fx->est, &cfg, &tm), MC_OK);
    memset(&fx->in, 0, sizeof fx->in);
}

static void test_rotation_between_slow_ticks(void **state)
{
    (void)state;
    const double d_e[2] = { 0.02, 0.1 }; /* electrical rad per sample */
    for (int i = 0; i < 2; i++) {
        for (int dir = -1; dir <= 1; dir += 2) {
            fixture_t fx;
            init(&fx);
            const uint32_t cpr = fx.est.tracker.cpr;
            const double counts_per_sample =
                d_e[i] * cpr / (MC_TEST_TWO_PI * (double)fx.est.tracker.pole_pairs);
            double pos = 1234.25; /* counts */
            int rotations = 0;
            double worst = 0.0;
            for (int k = 0; k < 2000; k++) {
                pos += dir * counts_per_sample;
                fx.in.encoder_count = (uint32_t)fmod(floor(pos) + 100.0 * cpr, (double)cpr);
                fx.in.running = k >= 3; /* three samples before RUN */
                fx.in.slow_tick = (k % SLOW_EVERY) == 0;
                mc_telemetry_t t;
                memset(&t, 0, sizeof t);
                mc_est_sincos_t sc;
                assert_int_equal(mc_est_encoder_step(&fx.est, &fx.in, &t, &sc), MC_FAULT_NONE);
                const double th = (double)t.theta_e_rad;
                if (fx.in.running && !fx.in.slow_tick) {
                    rotations++;
                } else {
                    rotations = 0;
                    float s;
                    float c;
                    mc_sincos_in_range_f32(t.theta_e_rad, &s, &c);
                    assert_true(memcmp(&s, &sc.sin_e, sizeof s) == 0);
                    assert_true(memcmp(&c, &sc.cos_e, sizeof c) == 0);
                }
                /* the largest step a sample's count makes (whole counts) */
                const double d = (floor(counts_per_sample) + 1.0) * MC_TEST_TWO_PI *
                                 (double)fx.est.tracker.pole_pairs / (double)cpr;
                const double per_rot = pow(d, 4.0) / 24.0 + pow(d, 5.0) / 30.0 + 1.8e-7;
                const double tol = MC_SINCOS_MAX_ABS_ERR + rotations * per_rot;
                const double err =
                    fmax(fabs((double)sc.sin_e - sin(th)), fabs((double)sc.cos_e - cos(th)));
                worst = fmax(worst, err / tol);
                assert_true(err <= tol);
            }
            printf("  %.2f rad per sample, direction %+d: worst error / bound %.3f\n", d_e[i], dir,
                   worst);
        }
    }
    /* a rotation before any step: NaN */
    fixture_t fx;
    init(&fx);
    fx.in.encoder_count = 17u;
    fx.in.running = true;
    fx.in.slow_tick = false;
    mc_telemetry_t t;
    memset(&t, 0, sizeof t);
    mc_est_sincos_t sc;
    assert_int_equal(mc_est_encoder_step(&fx.est, &fx.in, &t, &sc), MC_FAULT_NONE);
    assert_true(isnan(sc.sin_e) && isnan(sc.cos_e));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rotation_between_slow_ticks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
