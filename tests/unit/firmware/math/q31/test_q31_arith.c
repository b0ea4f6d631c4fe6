/*
 * mc/q31.h saturating helpers against an exact reference.
 *
 * Reference: long double with a mantissa of at least 64 bits holds every
 * int64 and every product of two int32 (62 bits) or sum of two such products
 * (63 bits) exactly, and division by a power of two is exact, so
 * floorl(x / 2^n + 1/2) is the exactly rounded value. Expected results are
 * that exact value clamped to [INT32_MIN, INT32_MAX]: bit-exact equality.
 */
#include "mc_test.h"

#include <math.h>

#include "mc/q31.h"
#include "q31_test_util.h"

static const int32_t k_edges[] = {
    INT32_MIN,     INT32_MIN + 1,     INT32_MIN / 2, -3,        -2, -1, 0, 1, 2, 3,
    INT32_MAX / 2, INT32_MAX / 2 + 1, INT32_MAX - 1, INT32_MAX,
};
#define N_EDGES  (sizeof k_edges / sizeof k_edges[0])
#define N_RANDOM 200000

static int32_t clamp_exact(long double x)
{
    if (x > (long double)INT32_MAX) {
        return INT32_MAX;
    }
    if (x < (long double)INT32_MIN) {
        return INT32_MIN;
    }
    return (int32_t)x;
}

/* exactly rounded x / 2^n, ties towards +inf */
static long double round_div_pow2(long double x, unsigned n)
{
    return floorl(ldexpl(x, -(int)n) + 0.5L);
}

static void test_asr_and_round_shift(void **state)
{
    (void)state;
    uint64_t seed = 0x51A7E5EEDULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const unsigned n = 1U + (unsigned)(test_rng_next_u64(&seed) % 63U); /* 1..63 */
        /* any int64 for asr; |x| <= 2^62 for round_shift's precondition */
        const int64_t x = (int64_t)test_rng_next_u64(&seed);
        const int64_t x62 = x / 2;
        assert_true(mc_asr_q63(x, n) == (int64_t)floorl(ldexpl((long double)x, -(int)n)));
        if (n <= 62U) {
            assert_true(mc_round_shift_q63(x62, n) == (int64_t)round_div_pow2((long double)x62, n));
        }
    }
    assert_true(mc_asr_q63(INT64_MIN, 62U) == -2);
    assert_true(mc_asr_q63(-1, 62U) == -1);
    assert_true(mc_asr_q63(INT64_MAX, 62U) == 1);
    assert_true(mc_asr_q63(INT64_MIN, 63U) == -1);
    assert_true(mc_asr_q63(INT64_MAX, 63U) == 0);
    assert_true(mc_asr_q63(-1, 1U) == -1);
    assert_true(mc_asr_q63(-2, 1U) == -1);
    assert_true(mc_asr_q63(-3, 1U) == -2);
    assert_true(mc_round_shift_q63(-3, 1U) == -1); /* -1.5 -> -1 (ties up) */
    assert_true(mc_round_shift_q63(3, 1U) == 2);   /*  1.5 ->  2 */
}

static void test_add_sub_neg_abs_saturate(void **state)
{
    (void)state;
    for (size_t i = 0; i < N_EDGES; ++i) {
        const int32_t a = k_edges[i];
        assert_int_equal(mc_neg_sat_q31(a), clamp_exact(-(long double)a));
        assert_int_equal(mc_abs_sat_q31(a), clamp_exact(fabsl((long double)a)));
        for (size_t j = 0; j < N_EDGES; ++j) {
            const int32_t b = k_edges[j];
            assert_int_equal(mc_add_sat_q31(a, b), clamp_exact((long double)a + b));
            assert_int_equal(mc_sub_sat_q31(a, b), clamp_exact((long double)a - b));
        }
    }
    /* the classic wrap cases, spelled out */
    assert_int_equal(mc_neg_sat_q31(INT32_MIN), INT32_MAX);
    assert_int_equal(mc_abs_sat_q31(INT32_MIN), INT32_MAX);
    assert_int_equal(mc_add_sat_q31(INT32_MAX, 1), INT32_MAX);
    assert_int_equal(mc_sub_sat_q31(INT32_MIN, 1), INT32_MIN);
    assert_int_equal(mc_sub_sat_q31(0, INT32_MIN), INT32_MAX);

    uint64_t seed = 0xADD5ULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const int32_t a = prng_q31(&seed);
        const int32_t b = prng_q31(&seed);
        assert_int_equal(mc_add_sat_q31(a, b), clamp_exact((long double)a + b));
        assert_int_equal(mc_sub_sat_q31(a, b), clamp_exact((long double)a - b));
        assert_int_equal(mc_neg_sat_q31(a), clamp_exact(-(long double)a));
        assert_int_equal(mc_abs_sat_q31(a), clamp_exact(fabsl((long double)a)));
    }
}

static int32_t ref_mul(int32_t a, int32_t b)
{
    return clamp_exact(round_div_pow2((long double)a * b, 31U));
}

static int32_t ref_dot2(int32_t a, int32_t b, int32_t c, int32_t d, int sign)
{
    return clamp_exact(
        round_div_pow2((long double)a * b + (long double)sign * ((long double)c * d), 31U));
}

static void test_mul_exact_rounding_and_saturation(void **state)
{
    (void)state;
    for (size_t i = 0; i < N_EDGES; ++i) {
        for (size_t j = 0; j < N_EDGES; ++j) {
            assert_int_equal(mc_mul_sat_q31(k_edges[i], k_edges[j]),
                             ref_mul(k_edges[i], k_edges[j]));
        }
    }
    assert_int_equal(mc_mul_sat_q31(INT32_MIN, INT32_MIN), INT32_MAX);
    assert_int_equal(mc_mul_sat_q31(INT32_MIN, INT32_MAX), -INT32_MAX);
    assert_int_equal(mc_mul_sat_q31(INT32_MAX, INT32_MAX), INT32_MAX - 1);
    uint64_t seed = 0x3A11ULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const int32_t a = prng_q31(&seed);
        const int32_t b = prng_q31(&seed);
        assert_int_equal(mc_mul_sat_q31(a, b), ref_mul(a, b));
    }
}

static void test_mac2_msub2_exact_no_overflow(void **state)
{
    (void)state;
    /* every edge quadruple: includes a*b + c*d = 2^63 (all INT32_MIN), which
     * does not fit int64_t */
    for (size_t i = 0; i < N_EDGES; ++i) {
        for (size_t j = 0; j < N_EDGES; ++j) {
            for (size_t k = 0; k < N_EDGES; ++k) {
                for (size_t l = 0; l < N_EDGES; ++l) {
                    const int32_t a = k_edges[i], b = k_edges[j];
                    const int32_t c = k_edges[k], d = k_edges[l];
                    assert_int_equal(mc_mac2_sat_q31(a, b, c, d), ref_dot2(a, b, c, d, 1));
                    assert_int_equal(mc_msub2_sat_q31(a, b, c, d), ref_dot2(a, b, c, d, -1));
                }
            }
        }
    }
    assert_int_equal(mc_mac2_sat_q31(INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN), INT32_MAX);
    assert_int_equal(mc_msub2_sat_q31(INT32_MIN, INT32_MIN, INT32_MIN, INT32_MAX), INT32_MAX);
    uint64_t seed = 0xD072ULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const int32_t a = prng_q31(&seed), b = prng_q31(&seed);
        const int32_t c = prng_q31(&seed), d = prng_q31(&seed);
        assert_int_equal(mc_mac2_sat_q31(a, b, c, d), ref_dot2(a, b, c, d, 1));
        assert_int_equal(mc_msub2_sat_q31(a, b, c, d), ref_dot2(a, b, c, d, -1));
    }
    /* ties: a*b + c*d = (2k + 1) 2^30 must round up */
    assert_int_equal(mc_mac2_sat_q31(1 << 15, 1 << 15, 0, 0), 1);    /* 0.5 -> 1 */
    assert_int_equal(mc_mac2_sat_q31(-(1 << 15), 1 << 15, 0, 0), 0); /* -0.5 -> 0 */
}

/* floor(sqrt(x)) characterised by r^2 <= x < (r + 1)^2, checked exactly in
 * long double (r + 1 <= 2^32, so (r + 1)^2 <= 2^64 is exact). */
static void assert_isqrt(uint64_t x)
{
    const long double r = (long double)mc_isqrt_u64(x);
    assert_true(r * r <= (long double)x);
    assert_true((r + 1.0L) * (r + 1.0L) > (long double)x);
}

static void test_isqrt_exact(void **state)
{
    (void)state;
    const uint64_t edges[] = { 0U,
                               1U,
                               2U,
                               3U,
                               4U,
                               15U,
                               16U,
                               17U,
                               UINT64_MAX,
                               UINT64_MAX - 1U,
                               (uint64_t)UINT32_MAX * UINT32_MAX,
                               (uint64_t)UINT32_MAX * UINT32_MAX - 1U,
                               (uint64_t)1 << 62,
                               (uint64_t)1 << 63 };
    for (size_t i = 0; i < sizeof edges / sizeof edges[0]; ++i) {
        assert_isqrt(edges[i]);
    }
    assert_int_equal(mc_isqrt_u64(UINT64_MAX), UINT32_MAX);
    uint64_t seed = 0x5147ULL;
    for (int i = 0; i < N_RANDOM; ++i) {
        const uint64_t x = test_rng_next_u64(&seed) >> (test_rng_next_u64(&seed) % 64U);
        assert_isqrt(x);
        const uint64_t r = x >> 32; /* perfect squares and their neighbours */
        assert_isqrt(r * r);
        assert_isqrt(r * r - 1U + (r == 0U ? 1U : 0U));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_asr_and_round_shift),
        cmocka_unit_test(test_add_sub_neg_abs_saturate),
        cmocka_unit_test(test_mul_exact_rounding_and_saturation),
        cmocka_unit_test(test_mac2_msub2_exact_no_overflow),
        cmocka_unit_test(test_isqrt_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
