/*
 * Circular (d, q) limits against polar geometry in double.
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_keep_angle_random),
        cmocka_unit_test(test_d_priority_random),
        cmocka_unit_test(test_extreme_magnitudes),
        cmocka_unit_test(test_invalid_radius_gives_nan),
        cmocka_unit_test(test_non_finite_components_pass_through),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
