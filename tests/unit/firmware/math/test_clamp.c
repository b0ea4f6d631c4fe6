/*
 * mc_clamp_sym_f32 (mc/clamp.h) against the two one-sided comparisons it
 * replaced, x > l ? l : (x < -l ? -l : x), bit for bit: over awkward
 * values (+-0, subnormals, +-FLT_MAX, +-Inf, NaN, the limit itself and
 * its neighbours) and random values and limits; a NaN stays NaN.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "mc/clamp.h"
#include "test_rng.h"

static float two_sided(float x, float l)
{
    return (x > l) ? l : ((x < -l) ? -l : x);
}

static uint32_t bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static void check(float x, float l)
{
    const float got = mc_clamp_sym_f32(x, l);
    if (isnan(x)) {
        assert_true(isnan(got));
        return;
    }
    assert_int_equal(bits(got), bits(two_sided(x, l)));
}

static void test_clamp_matches_two_sided(void **state)
{
    (void)state;
    const float limits[] = { 0.0f, FLT_TRUE_MIN, FLT_MIN, 1.0f, 2.5f, 1e30f, FLT_MAX, INFINITY };
    for (size_t i = 0; i < sizeof limits / sizeof limits[0]; ++i) {
        const float l = limits[i];
        const float xs[] = { 0.0f,
                             -0.0f,
                             FLT_TRUE_MIN,
                             -FLT_TRUE_MIN,
                             FLT_MIN,
                             -FLT_MIN,
                             1.0f,
                             -1.0f,
                             l,
                             -l,
                             nextafterf(l, INFINITY),
                             -nextafterf(l, INFINITY),
                             nextafterf(l, 0.0f),
                             -nextafterf(l, 0.0f),
                             FLT_MAX,
                             -FLT_MAX,
                             INFINITY,
                             -INFINITY,
                             NAN,
                             -NAN };
        for (size_t k = 0; k < sizeof xs / sizeof xs[0]; ++k) {
            check(xs[k], l);
        }
    }
    test_rng_t rng = test_rng_seed(41);
    for (int n = 0; n < 100000; ++n) {
        const float l = (float)test_rng_range(&rng, 0.0, 100.0);
        const float x = (float)test_rng_range(&rng, -200.0, 200.0);
        check(x, l);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clamp_matches_two_sided),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
