/*
 * mc_all_finite_f32 (mc/finite.h, firmware/math/finite.c: the sum of
 * x * 0 over the batch) against isfinite() element by element: a NaN,
 * +Inf or -Inf at any position of a batch is found, whatever the other
 * elements; finite batches pass, including -0, subnormals, FLT_MAX,
 * -FLT_MAX (x * 0 must stay 0, not overflow to NaN) and n = 0; elements
 * beyond n are not read into the verdict.
 * mc_f64_to_f32: finite, representable values convert; overflow, a
 * nonzero value rounding to 0 and non-finite values are refused and
 * leave the output untouched.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "mc/finite.h"
#include "test_rng.h"

#define N_MAX 40u

/* The finite values of every batch: the awkward ones first. */
static const float awkward[] = {
    0.0f,     -0.0f,     FLT_MAX, -FLT_MAX, FLT_MIN, -FLT_MIN, FLT_TRUE_MIN,     -FLT_TRUE_MIN,
    1.0e-40f, -1.0e-40f, 1.0f,    -1.0f,    3.0e38f, -3.0e38f, 0x1.fffffep-127f, 16777217.0f,
};
#define N_AWKWARD (sizeof awkward / sizeof awkward[0])

static void fill_finite(float *x, uint32_t n, test_rng_t *rng)
{
    for (uint32_t k = 0; k < n; ++k) {
        if (k < N_AWKWARD) {
            x[k] = awkward[k];
        } else {
            const double e = test_rng_range(rng, -120.0, 120.0);
            const double s = test_rng_unit(rng) < 0.5 ? -1.0 : 1.0;
            x[k] = (float)(s * pow(2.0, e));
        }
    }
}

static bool reference(const float *x, uint32_t n)
{
    for (uint32_t k = 0; k < n; ++k) {
        if (!isfinite(x[k])) {
            return false;
        }
    }
    return true;
}

static void test_finite_batches_pass(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(0xF1E1Eu);
    float x[N_MAX];
    for (uint32_t n = 0; n <= N_MAX; ++n) {
        fill_finite(x, n, &rng);
        assert_true(reference(x, n));
        assert_true(mc_all_finite_f32(x, n));
    }
    /* Every awkward value alone and as a whole batch of it. */
    for (size_t i = 0; i < N_AWKWARD; ++i) {
        for (uint32_t k = 0; k < N_MAX; ++k) {
            x[k] = awkward[i];
        }
        assert_true(mc_all_finite_f32(&awkward[i], 1u));
        assert_true(mc_all_finite_f32(x, N_MAX));
    }
    /* Subnormals are really subnormal here (no flush to zero). */
    assert_true(fpclassify(FLT_TRUE_MIN) == FP_SUBNORMAL);
    assert_true(fpclassify(awkward[8]) == FP_SUBNORMAL);
}

/* n = 0 is true whatever the pointer holds; elements at and beyond n
 * do not enter the verdict. */
static void test_only_n_elements(void **state)
{
    (void)state;
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    assert_true(mc_all_finite_f32(bad, 0u));
    float x[8] = { 1.0f, 2.0f, 3.0f, NAN, INFINITY, -INFINITY, NAN, NAN };
    assert_true(mc_all_finite_f32(x, 3u));
    assert_false(mc_all_finite_f32(x, 4u));
}

/* NaN (quiet, negative, other payloads), +Inf, -Inf at every position of
 * batches of every length up to N_MAX, the rest finite (awkward values and
 * random magnitudes): always found. Also two non-finite values of
 * opposite kinds (+Inf and -Inf, whose x * 0 are both NaN). */
static void test_non_finite_at_every_position(void **state)
{
    (void)state;
    float nans[4];
    nans[0] = NAN;
    nans[1] = -NAN;
    const uint32_t payload1 = 0x7FC00001u; /* quiet NaN, payload 1 */
    const uint32_t payload2 = 0xFFFFFFFFu; /* negative, all ones */
    memcpy(&nans[2], &payload1, sizeof(float));
    memcpy(&nans[3], &payload2, sizeof(float));
    const float bad[] = { nans[0], nans[1], nans[2], nans[3], INFINITY, -INFINITY };
    test_rng_t rng = test_rng_seed(0xBADF00Du);
    float x[N_MAX];
    uint32_t checked = 0u;
    for (uint32_t n = 1; n <= N_MAX; ++n) {
        for (uint32_t pos = 0; pos < n; ++pos) {
            for (size_t b = 0; b < sizeof bad / sizeof bad[0]; ++b) {
                fill_finite(x, n, &rng);
                x[pos] = bad[b];
                assert_false(reference(x, n));
                if (mc_all_finite_f32(x, n)) {
                    fail_msg("n %u: value %zu at %u not found", n, b, pos);
                }
                ++checked;
            }
            if (n >= 2u) {
                fill_finite(x, n, &rng);
                x[pos] = INFINITY;
                x[(pos + 1u) % n] = -INFINITY;
                assert_false(mc_all_finite_f32(x, n));
            }
        }
    }
    assert_int_equal(checked, 6u * N_MAX * (N_MAX + 1u) / 2u);
}

static void test_f64_to_f32(void **state)
{
    (void)state;
    float y = 5.0f;
    assert_true(mc_f64_to_f32(0.1, &y));
    assert_true(y == 0.1f);
    assert_true(mc_f64_to_f32(0.0, &y));
    assert_true(y == 0.0f);
    assert_true(mc_f64_to_f32(-3e38, &y));
    y = 5.0f;
    assert_false(mc_f64_to_f32(1e39, &y));  /* overflow */
    assert_false(mc_f64_to_f32(1e-50, &y)); /* nonzero rounds to zero */
    assert_false(mc_f64_to_f32(NAN, &y));
    assert_false(mc_f64_to_f32(-INFINITY, &y));
    assert_true(y == 5.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_finite_batches_pass),
        cmocka_unit_test(test_only_n_elements),
        cmocka_unit_test(test_non_finite_at_every_position),
        cmocka_unit_test(test_f64_to_f32),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
