/*
 * Angle utilities against double-precision libm references:
 * wrap/diff, sincos and atan2 error bounds over the whole accepted range,
 * the rotation of a direction by a small angle and its renormalisation,
 * the tracking loops' near wrap (bit for bit the full wrap), and the unwrap
 * operator A on long ramps (exact turn count).
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "mc/angle.h"
#include "test_rng.h"

#define N_RANDOM 1000000
#define RANGE_D  ((double)MC_ANGLE_MAX_ABS_RAD)

/* Angular distance of two angles, modulo 2 pi, in double. */
static double angle_dist(double a, double b)
{
    return fabs(remainder(a - b, MC_TEST_TWO_PI));
}

/* Test inputs: a dense grid over the full accepted range, a dense grid
 * over [-4 pi, 4 pi], points next to multiples of pi/4 (range reduction and
 * quadrant edges) and seeded random values (small, up to 1e4, full range). */
typedef void (*angle_check_fn)(float theta, double *max_err);

static void for_each_test_angle(angle_check_fn check, double *max_err)
{
    for (double t = -RANGE_D; t <= RANGE_D; t += 0.0123) {
        check((float)t, max_err);
    }
    for (double t = -4.0 * MC_TEST_PI; t <= 4.0 * MC_TEST_PI; t += 1e-5) {
        check((float)t, max_err);
    }
    for (int k = -(int)(RANGE_D / (MC_TEST_PI / 4.0)); k <= (int)(RANGE_D / (MC_TEST_PI / 4.0));
         k++) {
        const float centre = (float)(k * MC_TEST_PI / 4.0);
        float t = centre;
        for (int i = 0; i < 4; i++) {
            t = nextafterf(t, -INFINITY);
        }
        for (int i = 0; i < 9; i++, t = nextafterf(t, INFINITY)) {
            if (fabsf(t) <= MC_ANGLE_MAX_ABS_RAD) {
                check(t, max_err);
            }
        }
    }
    test_rng_t rng = test_rng_seed(21);
    for (int n = 0; n < N_RANDOM; n++) {
        check((float)test_rng_range(&rng, -10.0, 10.0), max_err);
        check((float)test_rng_range(&rng, -1.0e4, 1.0e4), max_err);
        check((float)test_rng_range(&rng, -RANGE_D, RANGE_D), max_err);
    }
}

/* ---- wrap ---------------------------------------------------------------- */

static void check_wrap(float theta, double *max_err)
{
    const float r = mc_wrap_pi_f32(theta);
    assert_true(r > -MC_PI_F && r <= MC_PI_F);
    const double err = angle_dist(r, theta);
    if (err > *max_err) {
        *max_err = err;
    }
}

static void test_wrap_pi_range_and_error(void **state)
{
    (void)state;
    double max_err = 0.0;
    for_each_test_angle(check_wrap, &max_err);
    printf("wrap_pi: max error %.3g rad (bound %.3g)\n", max_err, (double)MC_WRAP_PI_MAX_ERR_RAD);
    assert_true(max_err <= MC_WRAP_PI_MAX_ERR_RAD);
}

/* Inputs already inside (-pi, pi] come back bit-exactly; the single float
 * below -pi's representation, -MC_PI_F, maps to +MC_PI_F. */
static void test_wrap_pi_is_exact_inside(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(22);
    for (int n = 0; n < N_RANDOM; n++) {
        const float t = (float)test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        if (t > -MC_PI_F) {
            const float r = mc_wrap_pi_f32(t);
            assert_memory_equal(&r, &t, sizeof r);
        }
    }
    const float edges[] = { 0.0f, -0.0f, MC_PI_F, nextafterf(-MC_PI_F, 0.0f), 1e-38f, -1e-45f };
    for (size_t i = 0; i < sizeof edges / sizeof edges[0]; i++) {
        const float r = mc_wrap_pi_f32(edges[i]);
        assert_memory_equal(&r, &edges[i], sizeof r);
    }
    assert_true(mc_wrap_pi_f32(-MC_PI_F) == MC_PI_F);
    /* whole turns (as far as the range allows) wrap to the float rounding
     * error of t itself */
    for (int k = -3978; k <= 3978; k++) {
        const float t = (float)(k * MC_TEST_TWO_PI);
        assert_true(fabs((double)mc_wrap_pi_f32(t) - ((double)t - k * MC_TEST_TWO_PI)) <=
                    MC_WRAP_PI_MAX_ERR_RAD);
    }
}

static void test_wrap_pi_rejects_out_of_range(void **state)
{
    (void)state;
    assert_true(isnan(mc_wrap_pi_f32(NAN)));
    assert_true(isnan(mc_wrap_pi_f32(INFINITY)));
    assert_true(isnan(mc_wrap_pi_f32(-INFINITY)));
    assert_true(isnan(mc_wrap_pi_f32(nextafterf(MC_ANGLE_MAX_ABS_RAD, INFINITY))));
    assert_true(isnan(mc_wrap_pi_f32(-1e30f)));
    assert_false(isnan(mc_wrap_pi_f32(MC_ANGLE_MAX_ABS_RAD)));
    assert_false(isnan(mc_wrap_pi_f32(-MC_ANGLE_MAX_ABS_RAD)));
}

static void test_angle_diff(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(23);
    for (int n = 0; n < N_RANDOM; n++) {
        const float a = (float)test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        const float b = (float)test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        const float d = mc_angle_diff_f32(a, b);
        assert_true(d > -MC_PI_F && d <= MC_PI_F);
        /* a - b itself rounds once (half an ulp of |a - b| <= 2 pi) */
        assert_true(angle_dist(d, (double)a - (double)b) <= MC_WRAP_PI_MAX_ERR_RAD + 2.4e-7);
    }
    assert_true(isnan(mc_angle_diff_f32(NAN, 0.0f)));
}

/* ---- sincos -------------------------------------------------------------- */

static void check_sincos(float theta, double *max_err)
{
    float s, c;
    mc_sincos_f32(theta, &s, &c);
    const double es = fabs(s - sin((double)theta));
    const double ec = fabs(c - cos((double)theta));
    if (es > *max_err) {
        *max_err = es;
    }
    if (ec > *max_err) {
        *max_err = ec;
    }
}

static void test_sincos_error_bound(void **state)
{
    (void)state;
    double max_err = 0.0;
    for_each_test_angle(check_sincos, &max_err);
    printf("sincos: max abs error %.3g (bound %.3g)\n", max_err, (double)MC_SINCOS_MAX_ABS_ERR);
    assert_true(max_err <= MC_SINCOS_MAX_ABS_ERR);
}

static void test_sincos_exact_points_and_non_finite(void **state)
{
    (void)state;
    float s, c;
    mc_sincos_f32(0.0f, &s, &c);
    assert_true(s == 0.0f && c == 1.0f);
    const float bad[] = { NAN, INFINITY, -INFINITY, nextafterf(MC_ANGLE_MAX_ABS_RAD, INFINITY),
                          -3e38f };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s = 0.0f;
        c = 0.0f;
        mc_sincos_f32(bad[i], &s, &c);
        assert_true(isnan(s) && isnan(c));
    }
}

/* ---- atan2 --------------------------------------------------------------- */

static void check_atan2(float y, float x, double *max_err)
{
    const float a = mc_atan2_f32(y, x);
    assert_true(a >= -MC_PI_F && a <= MC_PI_F);
    const double err = angle_dist(a, atan2((double)y, (double)x));
    if (err > *max_err) {
        *max_err = err;
    }
}

static void test_atan2_error_bound(void **state)
{
    (void)state;
    double max_err = 0.0;
    /* dense angle grid at many magnitudes, including denormal and huge */
    const double mags[] = { 1e-40, 1e-30, 1e-6, 1.0, 7.3, 1e6, 1e30, 3e38 };
    for (size_t m = 0; m < sizeof mags / sizeof mags[0]; m++) {
        for (double phi = -MC_TEST_PI; phi <= MC_TEST_PI; phi += 2e-5) {
            check_atan2((float)(mags[m] * sin(phi)), (float)(mags[m] * cos(phi)), &max_err);
        }
    }
    test_rng_t rng = test_rng_seed(24);
    for (int n = 0; n < N_RANDOM; n++) {
        check_atan2((float)test_rng_range(&rng, -1.0, 1.0), (float)test_rng_range(&rng, -1.0, 1.0),
                    &max_err);
        /* independent log-uniform magnitudes of x and y */
        const double ly = test_rng_range(&rng, -38.0, 38.0);
        const double lx = test_rng_range(&rng, -38.0, 38.0);
        const double sy = test_rng_unit(&rng) < 0.5 ? -1.0 : 1.0;
        const double sx = test_rng_unit(&rng) < 0.5 ? -1.0 : 1.0;
        check_atan2((float)(sy * pow(10.0, ly)), (float)(sx * pow(10.0, lx)), &max_err);
    }
    /* axes and diagonals */
    const float v[] = { 0.0f, -0.0f, 1.0f, -1.0f, FLT_MAX, -FLT_MAX, FLT_MIN };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        for (size_t j = 0; j < sizeof v / sizeof v[0]; j++) {
            if (v[i] != 0.0f || v[j] != 0.0f) {
                check_atan2(v[i], v[j], &max_err);
            }
        }
    }
    printf("atan2: max error %.3g rad (bound %.3g)\n", max_err, (double)MC_ATAN2_MAX_ERR_RAD);
    assert_true(max_err <= MC_ATAN2_MAX_ERR_RAD);
}

static void test_atan2_special_inputs(void **state)
{
    (void)state;
    assert_true(mc_atan2_f32(0.0f, 0.0f) == 0.0f);
    assert_true(mc_atan2_f32(-0.0f, -0.0f) == 0.0f);
    assert_true(isnan(mc_atan2_f32(NAN, 1.0f)));
    assert_true(isnan(mc_atan2_f32(1.0f, NAN)));
    assert_true(isnan(mc_atan2_f32(INFINITY, 1.0f)));
    assert_true(isnan(mc_atan2_f32(1.0f, -INFINITY)));
}

/* The small-angle arctangent (the angle between two successive samples of
 * a turning vector): on both sides of its series' limit |y/x| = 1/8 and at
 * any magnitude, within 3e-8 rad of the exact atan2 of its float inputs
 * where it sums the series (t^9/9 = 1.5e-9 plus the roundings) and within
 * atan2's bound elsewhere; atan2's answers for x <= 0 and zero; NaN
 * for a NaN or an infinity but x = +Inf (0, the series). */
static void test_atan2_small(void **state)
{
    (void)state;
    double max_series = 0.0;
    double max_other = 0.0;
    const double mags[] = { 1e-30, 1e-6, 1.0, 7.3, 1e6, 1e30 };
    for (size_t m = 0; m < sizeof mags / sizeof mags[0]; m++) {
        for (double phi = -0.3; phi <= 0.3; phi += 1e-5) {
            const float y = (float)(mags[m] * sin(phi));
            const float x = (float)(mags[m] * cos(phi));
            const double err = fabs((double)mc_atan2_small_f32(y, x) - atan2((double)y, (double)x));
            if (fabs((double)y) < 0.125 * (double)x) {
                max_series = fmax(max_series, err);
            } else {
                max_other = fmax(max_other, err);
            }
        }
    }
    printf("atan2_small: max error %.3g rad (series), %.3g rad (atan2)\n", max_series, max_other);
    assert_true(max_series <= 3e-8);
    assert_true(max_other > 0.0 && max_other <= MC_ATAN2_MAX_ERR_RAD);
    assert_true(fabsf(mc_atan2_small_f32(0.01f, -1.0f) - (float)(MC_TEST_PI - atan(0.01))) <=
                1e-6f);
    assert_true(fabsf(mc_atan2_small_f32(-1.0f, 0.0f) + (float)(MC_TEST_PI / 2.0)) <= 1e-6f);
    assert_true(mc_atan2_small_f32(0.0f, 0.0f) == 0.0f);
    assert_true(mc_atan2_small_f32(0.0f, 2.0f) == 0.0f);
    assert_true(isnan(mc_atan2_small_f32(NAN, 1.0f)));
    assert_true(isnan(mc_atan2_small_f32(0.01f, NAN)));
    assert_true(mc_atan2_small_f32(0.01f, INFINITY) == 0.0f);
    assert_true(isnan(mc_atan2_small_f32(INFINITY, 1.0f)));
    assert_true(isnan(mc_atan2_small_f32(0.01f, -INFINITY)));
}

/* The small-angle series against double sin and cos of the same float
 * angle: float32 rounding of a few operations (the remainders, 1.2e-8 and
 * 4e-10, are below it); outside its range or non-finite: false, the
 * outputs untouched. */
static void test_sincos_small(void **state)
{
    (void)state;
    double max_err = 0.0;
    for (double d = -0.25; d <= 0.25; d += 1e-5) {
        const float delta = (float)d;
        float s = NAN;
        float c = NAN;
        assert_true(mc_sincos_small_f32(delta, &s, &c));
        max_err = fmax(max_err, fabs((double)s - sin((double)delta)));
        max_err = fmax(max_err, fabs((double)c - cos((double)delta)));
    }
    printf("sincos_small: max error %.3g\n", max_err);
    assert_true(max_err <= 1.5e-7);
    const float outside[] = { 0.2501f, -0.2501f, 3.0f, NAN, INFINITY, -INFINITY };
    for (size_t k = 0; k < sizeof outside / sizeof outside[0]; k++) {
        float s = 2.0f;
        float c = 3.0f;
        assert_false(mc_sincos_small_f32(outside[k], &s, &c));
        assert_true(s == 2.0f && c == 3.0f);
    }
}

/* mc_rotate_unit_f32 against the exact rotation in double, from
 * directions all round: the series for |delta| <= MC_ROTATE_SERIES_MAX_RAD
 * (the angle error of the result within |delta|^5 / 30 plus float
 * rounding, 1.5e-7 rad; its length short of 1 by at most delta^4 / 24 plus
 * rounding), the sine and cosine beyond (angle within 3e-7 rad, length
 * within 3e-7); NaN and Inf give NaN. mc_renormalise_unit_f32 brings a
 * length within 1e-3 of 1 to 1 within its (3 / 8) (n - 1)^2 plus
 * rounding. */
static void test_rotate_unit(void **state)
{
    (void)state;
    double max_series_err = 0.0;
    double max_exact_err = 0.0;
    for (int a = 0; a < 64; a++) {
        const double alpha = -MC_TEST_PI + (double)a * (MC_TEST_TWO_PI / 64.0) + 0.01;
        for (double d = -0.5; d <= 0.5; d += 1.7e-4) {
            const float delta = (float)d;
            float s = (float)sin(alpha);
            float c = (float)cos(alpha);
            const double a_in = atan2((double)s, (double)c);
            mc_rotate_unit_f32(delta, &s, &c);
            const double len = hypot((double)s, (double)c);
            const double ang_err =
                fabs(remainder(atan2((double)s, (double)c) - a_in - (double)delta, MC_TEST_TWO_PI));
            if (fabs((double)delta) <= (double)MC_ROTATE_SERIES_MAX_RAD) {
                const double d4 = pow((double)delta, 4.0);
                const double err = ang_err - fabs(pow((double)delta, 5.0)) / 30.0;
                max_series_err = fmax(max_series_err, err);
                assert_true(err <= 1.5e-7);
                assert_true(len <= 1.0 + 2e-7 && len >= 1.0 - d4 / 24.0 - 2e-7);
            } else {
                max_exact_err = fmax(max_exact_err, ang_err);
                assert_true(ang_err <= 3e-7);
                assert_true(fabs(len - 1.0) <= 3e-7);
            }
        }
    }
    printf("rotate_unit: series angle error beyond its bound %.3g rad, exact %.3g rad\n",
           max_series_err, max_exact_err);
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        float s = 0.6f;
        float c = 0.8f;
        mc_rotate_unit_f32(bad[k], &s, &c);
        assert_true(isnan(s) && isnan(c));
    }
    for (double l = 0.999; l <= 1.001; l += 1e-5) {
        float s = (float)(l * sin(0.7));
        float c = (float)(l * cos(0.7));
        mc_renormalise_unit_f32(&s, &c);
        assert_true(fabs(hypot((double)s, (double)c) - 1.0) <=
                    0.375 * pow(l * l - 1.0, 2.0) + 2e-7);
        assert_near(atan2((double)s, (double)c), 0.7, 2e-7);
    }
}

/* Bit equality; any NaN equals any NaN. */
static bool same_float(float a, float b)
{
    return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

static float float_of_bits(uint32_t u)
{
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static uint32_t bits_of_float(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* Both signs of every step-th float of [lo, hi] (lo, hi >= 0): the number of
 * inputs where mc_wrap_pi_near_f32 and mc_wrap_pi_f32 differ. */
static long wrap_mismatches(float lo, float hi, uint32_t step, long *checked)
{
    long bad = 0;
    for (uint32_t u = bits_of_float(lo); u <= bits_of_float(hi); u += step) {
        for (int sign = 0; sign < 2; sign++) {
            const float x = float_of_bits(u | (sign ? 0x80000000u : 0u));
            if (!same_float(mc_wrap_pi_near_f32(x), mc_wrap_pi_f32(x))) {
                if (bad < 5) {
                    printf("wrap near %a: %a, wrap %a\n", (double)x, (double)mc_wrap_pi_near_f32(x),
                           (double)mc_wrap_pi_f32(x));
                }
                bad++;
            }
            (*checked)++;
        }
    }
    return bad;
}

/* mc_wrap_pi_near_f32, the wrap of the tracking loops (the I&I
 * increment, the flux front end's position, the encoder tracker), returns
 * mc_wrap_pi_f32's float for every input: EVERY float with
 * pi <= |theta| <= 4 pi (the loops' angles stay within 3 pi; there the
 * reduction by +-2 pi is the same three subtractions), every 1009th float
 * inside (-pi, pi) (returned as they are by both), every 4099th up to
 * beyond the accepted range (left to mc_wrap_pi_f32), and the edges. */
static void test_wrap_near_equals_wrap(void **state)
{
    (void)state;
    long checked = 0;
    long bad = wrap_mismatches(MC_PI_F, 4.0f * MC_PI_F, 1u, &checked);
    bad += wrap_mismatches(0.0f, MC_PI_F, 1009u, &checked);
    bad += wrap_mismatches(4.0f * MC_PI_F, 2.0f * MC_ANGLE_MAX_ABS_RAD, 4099u, &checked);
    /* the edges: each value, its neighbours, both signs */
    const float base[] = { 0.0f,
                           FLT_TRUE_MIN,
                           FLT_MIN,
                           MC_PI_F,
                           MC_TWO_PI_F,
                           (float)(3.0 * MC_TEST_PI),
                           MC_ANGLE_MAX_ABS_RAD,
                           1e30f,
                           FLT_MAX,
                           INFINITY,
                           NAN };
    for (size_t k = 0; k < sizeof base / sizeof base[0]; k++) {
        const float x[3] = { base[k], nextafterf(base[k], 0.0f), nextafterf(base[k], INFINITY) };
        for (int m = 0; m < 6; m++) {
            const float e = (m < 3) ? x[m] : -x[m - 3];
            assert_true(same_float(mc_wrap_pi_near_f32(e), mc_wrap_pi_f32(e)));
        }
    }
    printf("wrap near: %ld inputs, %ld differ\n", checked, bad);
    assert_int_equal(bad, 0);
    /* and the diff of two wrapped angles, on a grid with both ends */
    for (int i = 0; i <= 1000; i++) {
        const float a = (i == 1000) ? MC_PI_F : -MC_PI_F + (float)i * (MC_TWO_PI_F / 1000.0f);
        for (int j = 0; j <= 1000; j++) {
            const float b = (j == 1000) ? MC_PI_F : -MC_PI_F + (float)j * (MC_TWO_PI_F / 1000.0f);
            assert_true(same_float(mc_angle_diff_near_f32(a, b), mc_angle_diff_f32(a, b)));
        }
    }
}

/* ---- unwrap (operator A) ------------------------------------------------- */

/* Feed the wrapped (float) version of a double angle sequence and check
 * that the turn count is exact at every sample and that e + 2 pi n equals
 * the true angle within the float quantisation of the wrapped input. */
typedef double (*step_fn)(test_rng_t *rng);

static void run_unwrap(double theta0, long n_samples, step_fn next_step, uint64_t seed,
                       double *final_theta)
{
    test_rng_t rng = test_rng_seed(seed);
    double theta = theta0;
    mc_unwrap_f32_t u;
    assert_int_equal(mc_unwrap_init_f32(&u, (float)remainder(theta, MC_TEST_TWO_PI)), MC_OK);
    const long turns0 = lround((theta - remainder(theta, MC_TEST_TWO_PI)) / MC_TEST_TWO_PI);
    for (long k = 0; k < n_samples; k++) {
        theta += next_step(&rng);
        const double e_exact = remainder(theta, MC_TEST_TWO_PI);
        const float e = (float)e_exact;
        const float y = mc_unwrap_step_f32(&u, e);
        const long turns_true = lround((theta - e_exact) / MC_TEST_TWO_PI) - turns0;
        assert_int_equal(mc_unwrap_turns_f32(&u), turns_true);
        const double y_exact = (double)e + MC_TEST_TWO_PI * (double)mc_unwrap_turns_f32(&u);
        /* only the float rounding of the wrapped input (half an ulp of pi) */
        assert_true(fabs(y_exact - (theta - MC_TEST_TWO_PI * turns0)) <= 1.2e-7);
        /* the float output is e + 2 pi n rounded to float */
        assert_true(fabs(y - y_exact) <= 2.0 * FLT_EPSILON * fabs(y_exact) + 1e-6);
    }
    *final_theta = theta;
}

static double step_forward(test_rng_t *rng)
{
    return test_rng_range(rng, 0.05, 3.1); /* < pi per sample */
}

static double step_backward(test_rng_t *rng)
{
    return -test_rng_range(rng, 0.05, 3.1);
}

static double step_random_walk(test_rng_t *rng)
{
    return test_rng_range(rng, -3.1, 3.1);
}

static double step_slow_forward(test_rng_t *rng)
{
    return test_rng_range(rng, 0.0, 2e-3); /* 1 kHz electrical at 20 kHz */
}

static void test_unwrap_10000_turns_forward_and_backward(void **state)
{
    (void)state;
    double theta_end;
    /* mean step 1.575 rad: 41,000 samples make about 10,280 turns */
    run_unwrap(0.3, 41000, step_forward, 31, &theta_end);
    assert_true(theta_end >= 10000.0 * MC_TEST_TWO_PI);
    run_unwrap(-2.0, 41000, step_backward, 32, &theta_end);
    assert_true(theta_end <= -10000.0 * MC_TEST_TWO_PI);
    run_unwrap(MC_TEST_PI, 200000, step_random_walk, 33, &theta_end);
    run_unwrap(-3.0, 200000, step_slow_forward, 34, &theta_end);
}

/* A constant-speed ramp through exactly +-pi on the samples. */
static void test_unwrap_uniform_ramp_through_pi(void **state)
{
    (void)state;
    mc_unwrap_f32_t u;
    assert_int_equal(mc_unwrap_init_f32(&u, 0.0f), MC_OK);
    const int samples_per_turn = 8; /* step pi/4, hits +-pi exactly */
    for (long k = 1; k <= 10000L * samples_per_turn; k++) {
        const double theta = k * (MC_TEST_TWO_PI / samples_per_turn);
        const float e = mc_wrap_pi_f32((float)remainder(theta, MC_TEST_TWO_PI));
        (void)mc_unwrap_step_f32(&u, e);
        const double y = (double)e + MC_TEST_TWO_PI * mc_unwrap_turns_f32(&u);
        assert_true(fabs(y - theta) <= 1e-6);
    }
    assert_int_equal(mc_unwrap_turns_f32(&u), 10000);
}

static void test_unwrap_non_finite_and_counter_limit(void **state)
{
    (void)state;
    mc_unwrap_f32_t u;
    assert_int_equal(mc_unwrap_init_f32(&u, NAN), MC_ERR_NONFINITE);
    assert_int_equal(mc_unwrap_init_f32(&u, 3.0f), MC_OK);
    mc_unwrap_f32_t before = u;
    assert_true(isnan(mc_unwrap_step_f32(&u, NAN)));
    assert_true(isnan(mc_unwrap_step_f32(&u, -INFINITY)));
    assert_memory_equal(&u, &before, sizeof u);
    /* the next good sample still sees the crossing from 3.0 */
    (void)mc_unwrap_step_f32(&u, -3.0f);
    assert_int_equal(mc_unwrap_turns_f32(&u), 1);

    u.turns = INT32_MAX;
    u.prev_wrapped_rad = 3.0f;
    before = u;
    assert_true(isnan(mc_unwrap_step_f32(&u, -3.0f)));
    assert_memory_equal(&u, &before, sizeof u);
    u.turns = INT32_MIN;
    u.prev_wrapped_rad = -3.0f;
    before = u;
    assert_true(isnan(mc_unwrap_step_f32(&u, 3.0f)));
    assert_memory_equal(&u, &before, sizeof u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wrap_pi_range_and_error),
        cmocka_unit_test(test_wrap_pi_is_exact_inside),
        cmocka_unit_test(test_wrap_pi_rejects_out_of_range),
        cmocka_unit_test(test_angle_diff),
        cmocka_unit_test(test_sincos_error_bound),
        cmocka_unit_test(test_sincos_exact_points_and_non_finite),
        cmocka_unit_test(test_atan2_error_bound),
        cmocka_unit_test(test_atan2_special_inputs),
        cmocka_unit_test(test_atan2_small),
        cmocka_unit_test(test_sincos_small),
        cmocka_unit_test(test_rotate_unit),
        cmocka_unit_test(test_wrap_near_equals_wrap),
        cmocka_unit_test(test_unwrap_10000_turns_forward_and_backward),
        cmocka_unit_test(test_unwrap_uniform_ramp_through_pi),
        cmocka_unit_test(test_unwrap_non_finite_and_counter_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
