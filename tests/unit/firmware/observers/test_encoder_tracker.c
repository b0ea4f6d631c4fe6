/*
 * Encoder tracker (mc/encoder_tracker.h, firmware/observers/encoder_tracker.c)
 * against an independent double-precision reference: multi-turn position,
 * electrical angle and its change per sample, speed from the tracking PLL; the parameter ranges
 * (CPR in [4, 2^23], the float-exactness limit); the position's conversion to float.
 */
#include "mc_test.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "mc/encoder_tracker.h"

#define TS 5e-5
/* plausible count step (mc/encoder_tracker.h): 100 rad/s */
#define STEP_SPEED_MAX 100.0f

/* Constant speed through several turns, forward and back: the speed
 * estimate converges, the multi-turn position is exact, theta_e follows
 * n_p theta + offset. */
static void test_encoder_tracker(void **state)
{
    (void)state;
    const uint32_t cpr = 10000u, n_p = 3u;
    const double offset = 0.4, w_pll = 1000.0;
    mc_encoder_tracker_f32_t et;
    assert_int_equal(mc_encoder_tracker_init_f32(&et, cpr, n_p, (float)offset, (float)w_pll,
                                                 STEP_SPEED_MAX, (float)TS),
                     MC_OK);
    const double speeds[2] = { 37.0, -37.0 };
    double theta = 1.0; /* true mechanical angle */
    long c_prev = -1;   /* none before the priming sample */
    for (int leg = 0; leg < 2; ++leg) {
        for (int k = 0; k < 20000; ++k) { /* 1 s: ~6 turns */
            theta += speeds[leg] * TS;
            const double turns = floor(theta / (MC_TEST_TWO_PI));
            const uint32_t c =
                (uint32_t)floor((theta - turns * MC_TEST_TWO_PI) * cpr / (MC_TEST_TWO_PI)) % cpr;
            mc_encoder_estimate_t est;
            assert_int_equal(mc_encoder_tracker_update_f32(&et, c, &est), MC_OK);
            assert_false(est.count_jump); /* 37 rad/s < STEP_SPEED_MAX */
            /* position within one count (+ half-count centring) */
            assert_true(fabs((double)est.theta_m_rad - theta) <
                        MC_TEST_TWO_PI / cpr + 1e-5 * fabs(theta) + 1e-6);
            const double th_e = n_p * (c + 0.5) * MC_TEST_TWO_PI / cpr + offset;
            const double d = remainder((double)est.theta_e_rad - th_e, MC_TEST_TWO_PI);
            assert_true(fabs(d) < 2e-5);
            assert_true(est.theta_e_rad <= MC_TEST_PI && est.theta_e_rad > -MC_TEST_PI);
            /* the electrical angle's change: n_p times the count step
             * (wrapped to half a turn), to the float's rounding */
            const long dc = (c_prev < 0) ? 0 : lround(remainder((double)c - (double)c_prev, cpr));
            const double d_e = n_p * (double)dc * MC_TEST_TWO_PI / cpr;
            assert_true(fabs((double)est.d_theta_e_rad - d_e) <= 2e-7 * fabs(d_e));
            c_prev = (long)c;
            if (k > 200) { /* 10 / w_pll after the start / reversal */
                assert_true(fabs((double)est.omega_m_rad_s - speeds[leg]) <
                            0.01 * fabs(speeds[leg]));
            }
        }
    }
    mc_encoder_estimate_t est;
    assert_int_equal(mc_encoder_tracker_update_f32(&et, cpr, &est), MC_ERR_RANGE);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, 2u, 3u, 0.0f, 100.0f, STEP_SPEED_MAX, 5e-5f),
                     MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, cpr, 3u, 0.0f, 20000.0f, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_PARAM);
}

/* The electrical angle of every count, the whole turn in steps of one
 * count, for odd and even cpr, pole pairs up to the maximum and offsets
 * across [-2 pi, 2 pi]: n_p (count + 1/2) 2 pi / cpr + offset within
 * 1e-6 rad (the integer reduction leaves only the roundings of the sum
 * and the product, each below 4e-7 rad at cpr 10000), in (-pi, pi] (in
 * float). */
static void test_encoder_tracker_every_count(void **state)
{
    (void)state;
    const uint32_t cprs[] = { 10000u, 4095u };
    const uint32_t pole_pairs[] = { 1u, 3u, 7u, 64u };
    const double offsets[] = { -MC_TEST_TWO_PI, -3.1, -0.4, 0.0, 0.4, MC_TEST_PI, 6.0 };
    for (size_t i = 0; i < sizeof cprs / sizeof cprs[0]; ++i) {
        for (size_t j = 0; j < sizeof pole_pairs / sizeof pole_pairs[0]; ++j) {
            for (size_t k = 0; k < sizeof offsets / sizeof offsets[0]; ++k) {
                const uint32_t cpr = cprs[i];
                mc_encoder_tracker_f32_t et;
                assert_int_equal(mc_encoder_tracker_init_f32(&et, cpr, pole_pairs[j],
                                                             (float)offsets[k], 100.0f,
                                                             STEP_SPEED_MAX, (float)TS),
                                 MC_OK);
                const double offset = (double)(float)offsets[k];
                for (uint32_t c = 0u; c <= cpr; ++c) { /* back to count 0 */
                    const uint32_t count = c % cpr;
                    mc_encoder_estimate_t est;
                    assert_int_equal(mc_encoder_tracker_update_f32(&et, count, &est), MC_OK);
                    const double th_e =
                        pole_pairs[j] * (count + 0.5) * MC_TEST_TWO_PI / cpr + offset;
                    const double d = remainder((double)est.theta_e_rad - th_e, MC_TEST_TWO_PI);
                    assert_true(fabs(d) < 1e-6);
                    /* (-pi, pi] in float: MC_PI_F is the float nearest pi, above it */
                    assert_true(est.theta_e_rad <= MC_PI_F && est.theta_e_rad > -MC_PI_F);
                }
            }
        }
    }
}

/* Parameter ranges: cpr in [4, 2^23] (the largest cpr for which count + 0.5
 * is exact in a float), pole pairs in [1, 64], |offset| <= 2 pi, w_pll Ts <= 0.5,
 * non-finite values. */
static void test_encoder_tracker_ranges(void **state)
{
    (void)state;
    mc_encoder_tracker_f32_t et;
    assert_int_equal(MC_ENCODER_CPR_MAX, 8388608u);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, 3u, 3u, 0.0f, 100.0f, STEP_SPEED_MAX, 5e-5f),
                     MC_ERR_PARAM);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, 4u, 3u, 0.0f, 100.0f, STEP_SPEED_MAX, 5e-5f),
                     MC_OK);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, MC_ENCODER_CPR_MAX, 3u, 0.0f, 100.0f,
                                                 STEP_SPEED_MAX, 5e-5f),
                     MC_OK);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, MC_ENCODER_CPR_MAX + 1u, 3u, 0.0f, 100.0f,
                                                 STEP_SPEED_MAX, 5e-5f),
                     MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 0u, 0.0f, 100.0f, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 65u, 0.0f, 100.0f, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 64u, 0.0f, 100.0f, STEP_SPEED_MAX, 5e-5f), MC_OK);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, 6.3f, 100.0f, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, -6.28f, 100.0f, STEP_SPEED_MAX, 5e-5f), MC_OK);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 0.0f, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 10000.0f, STEP_SPEED_MAX, 5e-5f),
        MC_OK); /* w Ts = 0.5 */
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 10100.0f, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 100.0f, STEP_SPEED_MAX, 0.0f),
        MC_ERR_PARAM);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, NAN, 100.0f, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_NONFINITE);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, INFINITY, STEP_SPEED_MAX, 5e-5f),
        MC_ERR_NONFINITE);
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 100.0f, STEP_SPEED_MAX, NAN),
        MC_ERR_NONFINITE);
    /* the plausible step: > 0, under half a turn per sample (pi / Ts =
     * 62832 rad/s) */
    assert_int_equal(mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 100.0f, NAN, 5e-5f),
                     MC_ERR_NONFINITE);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 100.0f, 0.0f, 5e-5f),
                     MC_ERR_PARAM);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 100.0f, 62800.0f, 5e-5f),
                     MC_OK);
    assert_int_equal(mc_encoder_tracker_init_f32(&et, 10000u, 3u, 0.0f, 100.0f, 62900.0f, 5e-5f),
                     MC_ERR_PARAM);
}

/* At the largest CPR (2^23) the counts near the top are still in range and
 * the angles are (c + 0.5) 2 pi / 2^23 to float rounding: c + 0.5 exact
 * below 2^23; 2 pi / cpr in float to 2^-24 relative, 3.7e-7 rad over a
 * turn; the product to half an ulp of ~2 pi, 2.4e-7 rad; the wrap to half an
 * ulp of pi, 1.2e-7 rad: 7.3e-7 rad in all, under one count (7.5e-7 rad).
 * The multi-turn position one count past a turn (2^23 + 0.5 rounds to an
 * even number) adds at most half a count: within 1.5 counts. */
static void test_encoder_tracker_cpr_max(void **state)
{
    (void)state;
    const uint32_t cpr = MC_ENCODER_CPR_MAX;
    mc_encoder_tracker_f32_t et;
    assert_int_equal(mc_encoder_tracker_init_f32(&et, cpr, 1u, 0.0f, 100.0f, STEP_SPEED_MAX, 5e-5f),
                     MC_OK);
    const uint32_t counts[] = { cpr - 1u, 0u, 1u, cpr / 2u - 1u, cpr / 2u, cpr / 4u + 3u };
    /* a jump of less than cpr/2 counts each time (the tracker's limit) */
    mc_encoder_estimate_t est;
    int64_t pos = -1; /* position in counts relative to the first */
    uint32_t prev = counts[0];
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; ++i) {
        const uint32_t c = counts[i];
        int64_t d = (int64_t)c - (int64_t)prev;
        if (d >= (int64_t)cpr / 2) {
            d -= cpr;
        } else if (d < -(int64_t)cpr / 2) {
            d += cpr;
        }
        pos = (i == 0u) ? (int64_t)c : pos + d;
        prev = c;
        assert_int_equal(mc_encoder_tracker_update_f32(&et, c, &est), MC_OK);
        const double th = ((double)c + 0.5) * MC_TEST_TWO_PI / cpr;
        const double e = remainder((double)est.theta_e_rad - th, MC_TEST_TWO_PI);
        assert_true(fabs(e) < 1.0 * MC_TEST_TWO_PI / cpr);
        const double th_m = ((double)pos + 0.5) * MC_TEST_TWO_PI / cpr;
        assert_true(fabs((double)est.theta_m_rad - th_m) < 1.5 * MC_TEST_TWO_PI / cpr);
    }
    assert_int_equal(mc_encoder_tracker_update_f32(&et, cpr, &est), MC_ERR_RANGE);
}

/* The plausible count step: at STEP_SPEED_MAX = 100 rad/s, Ts = 50 us and
 * 10000 counts per turn a rotor moves 7.96 counts per sample: steps of
 * up to ceil(7.96) + 1 = 9 counts pass, 10 are a jump. A jump is flagged
 * in its sample only; the position follows the count exactly and the speed
 * estimate is not disturbed by it. */
static void test_encoder_tracker_count_jump(void **state)
{
    (void)state;
    const uint32_t cpr = 10000u;
    mc_encoder_tracker_f32_t et;
    assert_int_equal(
        mc_encoder_tracker_init_f32(&et, cpr, 3u, 0.0f, 1000.0f, STEP_SPEED_MAX, (float)TS), MC_OK);
    mc_encoder_estimate_t est;
    uint32_t c = 100u;
    int64_t pos = (int64_t)c;
    assert_int_equal(mc_encoder_tracker_update_f32(&et, c, &est), MC_OK);
    assert_false(est.count_jump);
    for (int k = 0; k < 2000; ++k) { /* 2 counts per sample: 63 rad/s */
        c += 2u;
        pos += 2;
        assert_int_equal(mc_encoder_tracker_update_f32(&et, c, &est), MC_OK);
        assert_false(est.count_jump);
    }
    const double w = 2.0 * MC_TEST_TWO_PI / cpr / TS;
    assert_true(fabs((double)est.omega_m_rad_s - w) < 1e-3 * w);
    const uint32_t steps[] = { 9u, 10u, 2u, 833u, 2u };
    const bool jumps[] = { false, true, false, true, false };
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; ++i) {
        const float w_before = est.omega_m_rad_s;
        c = (c + steps[i]) % cpr;
        pos += (int64_t)steps[i];
        assert_int_equal(mc_encoder_tracker_update_f32(&et, c, &est), MC_OK);
        assert_int_equal(est.count_jump, jumps[i]);
        if (jumps[i]) { /* the PLL angle follows: no error, no speed kick */
            assert_true(est.omega_m_rad_s == w_before);
        }
        const double th_m = ((double)pos + 0.5) * MC_TEST_TWO_PI / cpr;
        assert_true(fabs((double)est.theta_m_rad - th_m) < 1e-5 * th_m);
    }
    /* backwards too */
    c = (c + cpr - 10u) % cpr;
    assert_int_equal(mc_encoder_tracker_update_f32(&et, c, &est), MC_OK);
    assert_true(est.count_jump);
}

/* The position count's float (mc_encoder_counts_to_f32: the 32-bit
 * conversion while the count fits) is the 64-bit conversion's, bit for
 * bit, at the edges of the 32-bit range, of exact float integers, and on
 * a seeded random spread of magnitudes. */
static void test_counts_to_float(void **state)
{
    (void)state;
    const int64_t edges[] = { 0,
                              1,
                              -1,
                              (1 << 24) + 1,
                              -(1 << 24) - 1,
                              INT32_MAX,
                              INT32_MIN,
                              (int64_t)INT32_MAX + 1,
                              (int64_t)INT32_MIN - 1,
                              (int64_t)INT32_MAX - 63,
                              (int64_t)INT32_MAX - 64,
                              ((int64_t)1 << 40) + 12345,
                              INT64_MAX,
                              INT64_MIN };
    for (size_t k = 0; k < sizeof edges / sizeof edges[0]; k++) {
        const float a = mc_encoder_counts_to_f32(edges[k]);
        const float b = (float)edges[k];
        assert_memory_equal(&a, &b, sizeof a);
    }
    uint64_t x = 0x9E3779B97F4A7C15ull;
    for (int k = 0; k < 100000; k++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        const int64_t c = (int64_t)x >> (k % 60); /* all magnitudes */
        const float a = mc_encoder_counts_to_f32(c);
        const float b = (float)c;
        assert_memory_equal(&a, &b, sizeof a);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_encoder_tracker),
        cmocka_unit_test(test_encoder_tracker_every_count),
        cmocka_unit_test(test_encoder_tracker_ranges),
        cmocka_unit_test(test_encoder_tracker_cpr_max),
        cmocka_unit_test(test_encoder_tracker_count_jump),
        cmocka_unit_test(test_counts_to_float),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
