/*
 * Circular (d, q) limits against polar geometry in double; the keep-angle
 * limit bit for bit as before its common case went inline.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>

#include "mc/circle_limit.h"
#include "test_rng.h"

#define N_RANDOM 300000
#define REL_TOL  4e-7 /* a few float roundings of the magnitude */

static void test_keep_angle_random(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(61);
    for (int n = 0; n < N_RANDOM; n++) {
        const double r = test_rng_range(&rng, 1e-3, 1e3);
        const double mag = test_rng_range(&rng, 0.0, 10.0) * r;
        const double psi = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        const float d0 = (float)(mag * cos(psi));
        const float q0 = (float)(mag * sin(psi));
        const double mag0 = hypot(d0, q0);
        float d = d0, q = q0;
        const bool limited = mc_circle_limit_f32(&d, &q, (float)r);
        if (mag0 <= r * (1.0 - 1e-6)) {
            assert_false(limited);
            assert_true(d == d0 && q == q0);
        } else if (mag0 > r * (1.0 + 1e-6)) {
            assert_true(limited);
            assert_true(fabs(hypot(d, q) - r) <= REL_TOL * r);
            assert_true(fabs(remainder(atan2(q, d) - atan2(q0, d0), MC_TEST_TWO_PI)) <= 1e-6);
        }
        assert_true(hypot(d, q) <= r * (1.0 + REL_TOL));
    }
}

static void test_d_priority_random(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(62);
    for (int n = 0; n < N_RANDOM; n++) {
        const double r = test_rng_range(&rng, 1e-3, 1e3);
        const float d0 = (float)(test_rng_range(&rng, -2.0, 2.0) * r);
        const float q0 = (float)(test_rng_range(&rng, -4.0, 4.0) * r);
        float d = d0, q = q0;
        const bool limited = mc_circle_limit_d_priority_f32(&d, &q, (float)r);
        /* d: kept when it fits, else +-r with its sign */
        const double d_expect = (fabs(d0) <= (float)r) ? d0 : copysign((float)r, d0);
        assert_true(d == d_expect);
        /* q: kept when it fits in the remaining room, else on the circle */
        const double room = sqrt(fmax(0.0, (double)(float)r * (float)r - d_expect * d_expect));
        if (fabs(q0) <= room * (1.0 - 1e-6)) {
            assert_true(q == q0);
            assert_int_equal(limited, fabs(d0) > (float)r);
        } else if (fabs(q0) > room * (1.0 + 1e-6) + 1e-30) {
            assert_true(limited);
            assert_true(fabs(fabs(q) - room) <= REL_TOL * r);
            assert_true(signbit(q) == signbit(q0));
        }
        assert_true(hypot(d, q) <= r * (1.0 + REL_TOL));
    }
}

/* Extreme magnitudes: no overflow to a zero or NaN result. */
static void test_extreme_magnitudes(void **state)
{
    (void)state;
    float d = 3e38f, q = -3e38f;
    assert_true(mc_circle_limit_f32(&d, &q, 1.0f));
    assert_true(fabs(hypot(d, q) - 1.0) <= REL_TOL);
    assert_true(fabs(atan2(q, d) + MC_TEST_PI / 4.0) <= 1e-6);

    d = 1e35f;
    q = 0.0f;
    assert_true(mc_circle_limit_f32(&d, &q, 1e30f));
    assert_true(fabs(d - 1e30) <= REL_TOL * 1e30 && q == 0.0f);

    d = 1e-30f; /* r_max at the smallest normal float */
    q = 1e-30f;
    assert_false(mc_circle_limit_f32(&d, &q, FLT_MIN * 1e9f));
    d = 1e-30f;
    q = -1e-30f;
    assert_true(mc_circle_limit_f32(&d, &q, FLT_MIN));
    assert_true(fabs(hypot(d, q) - FLT_MIN) <= 1e-6 * FLT_MIN);

    d = -3e38f;
    q = 3e38f;
    assert_true(mc_circle_limit_d_priority_f32(&d, &q, 2.0f));
    assert_true(d == -2.0f && q == 0.0f);
    d = 1.0f;
    q = -3e38f;
    assert_true(mc_circle_limit_d_priority_f32(&d, &q, 2.0f));
    assert_true(d == 1.0f && fabs(q + sqrt(3.0)) <= REL_TOL * 2.0);
}

static void test_invalid_radius_gives_nan(void **state)
{
    (void)state;
    const float bad[] = { NAN, INFINITY, 0.0f, -0.0f, -1.0f, FLT_MIN / 2.0f };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        float d = 1.0f, q = 1.0f;
        assert_true(mc_circle_limit_f32(&d, &q, bad[i]));
        assert_true(isnan(d) && isnan(q));
        d = 1.0f;
        q = 1.0f;
        assert_true(mc_circle_limit_d_priority_f32(&d, &q, bad[i]));
        assert_true(isnan(d) && isnan(q));
    }
}

static void test_non_finite_components_pass_through(void **state)
{
    (void)state;
    const float vals[][2] = {
        { NAN, 0.0f }, { 0.0f, NAN }, { INFINITY, 0.0f }, { 1.0f, -INFINITY }
    };
    for (size_t i = 0; i < sizeof vals / sizeof vals[0]; i++) {
        float d = vals[i][0], q = vals[i][1];
        assert_false(mc_circle_limit_f32(&d, &q, 1.0f));
        assert_memory_equal(&d, &vals[i][0], sizeof d);
        assert_memory_equal(&q, &vals[i][1], sizeof q);
        assert_false(mc_circle_limit_d_priority_f32(&d, &q, 1.0f));
        assert_memory_equal(&d, &vals[i][0], sizeof d);
        assert_memory_equal(&q, &vals[i][1], sizeof q);
    }
}

/* The keep-angle limit as it was before its common case went inline
 * (one function): the inline check and the out-of-line rest must give
 * the same bits. */
static bool keep_angle_before(float *x_d, float *x_q, float r_max)
{
    if (!((r_max >= FLT_MIN) && (r_max <= FLT_MAX))) {
        *x_d = NAN;
        *x_q = NAN;
        return true;
    }
    if (!isfinite(*x_d) || !isfinite(*x_q)) {
        return false;
    }
    const float d = *x_d;
    const float q = *x_q;
    const float inv_r = 1.0f / r_max;
    const float d_n = d * inv_r;
    const float q_n = q * inv_r;
    const float mag2_n = d_n * d_n + q_n * q_n;
    if (!(mag2_n > 1.0f)) {
        return false;
    }
    float scale;
    if (isfinite(mag2_n)) {
        scale = 1.0f / sqrtf(mag2_n);
    } else {
        const float m = (fabsf(d) >= fabsf(q)) ? fabsf(d) : fabsf(q);
        const float d_m = d / m;
        const float q_m = q / m;
        scale = (r_max / m) / sqrtf(d_m * d_m + q_m * q_m);
    }
    *x_d = d * scale;
    *x_q = q * scale;
    return true;
}

static void test_keep_angle_bits_as_before(void **state)
{
    (void)state;
    const float special[] = { 0.0f,  -0.0f,    1.0f,      -1.0f,   0.70710677f, 1e-30f,
                              1e30f, 3e38f,    -3e38f,    FLT_MIN, 1e-45f,      FLT_MAX,
                              NAN,   INFINITY, -INFINITY, 0.5f };
    const size_t n_s = sizeof special / sizeof special[0];
    test_rng_t rng = test_rng_seed(63);
    for (size_t k = 0; k < n_s * n_s * n_s + N_RANDOM; ++k) {
        float d, q, r;
        if (k < n_s * n_s * n_s) {
            d = special[k % n_s];
            q = special[(k / n_s) % n_s];
            r = special[k / (n_s * n_s)];
        } else {
            const double scale = (k % 7u == 0u) ? 1e37 : 1.0;
            r = (float)test_rng_range(&rng, 0.0, 2.0);
            d = (float)(test_rng_range(&rng, -2.0, 2.0) * scale);
            q = (float)(test_rng_range(&rng, -2.0, 2.0) * scale);
        }
        float d0 = d, q0 = q;
        const bool before = keep_angle_before(&d0, &q0, r);
        const bool now = mc_circle_limit_f32(&d, &q, r);
        assert_int_equal(now, before);
        assert_memory_equal(&d, &d0, sizeof d);
        assert_memory_equal(&q, &q0, sizeof q);
    }
    /* the rest on its own: a finite vector inside is left */
    float d = 0.3f, q = 0.4f;
    assert_false(mc_circle_limit_outside_f32(&d, &q, 1.0f, 0.25f));
    assert_true(d == 0.3f && q == 0.4f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_keep_angle_random),
        cmocka_unit_test(test_d_priority_random),
        cmocka_unit_test(test_extreme_magnitudes),
        cmocka_unit_test(test_invalid_radius_gives_nan),
        cmocka_unit_test(test_non_finite_components_pass_through),
        cmocka_unit_test(test_keep_angle_bits_as_before),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
