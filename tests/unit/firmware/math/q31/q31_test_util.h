/*
 * Shared helpers for the Q31 tests: a seeded PRNG (on test_rng.h), Q31 <->
 * real conversions done independently of the code under test, and the
 * float32 error model used to derive comparison bounds against the float
 * implementations.
 */
#ifndef Q31_TEST_UTIL_H
#define Q31_TEST_UTIL_H

#include <float.h>
#include <math.h>
#include <stdint.h>

#include "test_rng.h"

/* Exact references use long double: every int64, every product of two
 * int32 and every sum of two such products must be representable. */
_Static_assert(LDBL_MANT_DIG >= 64, "exact reference needs a 64-bit mantissa");

#define Q31_SCALE 2147483648.0 /* 2^31: one Q31 unit in LSB */
/* unit roundoff of float32 (round to nearest): |fl(x) - x| <= U_F32 |x| */
#define U_F32 (1.0 / 16777216.0)

/* Seeded per test: raw xorshift64* state, stepped by test_rng_next_u64
 * (test_rng.h). */

/* uniform int32 over the full range */
static inline int32_t prng_q31(uint64_t *state)
{
    return (int32_t)(uint32_t)(test_rng_next_u64(state) >> 32);
}

/* uniform real in [lo, hi) */
static inline double prng_uniform(uint64_t *state, double lo, double hi)
{
    return lo + (hi - lo) * (double)(test_rng_next_u64(state) >> 11) * 0x1.0p-53;
}

static inline double q31_to_real(int32_t x)
{
    return (double)x / Q31_SCALE;
}

/* nearest Q31 value of a real, saturated (the expected result of an exact
 * operation followed by saturation) */
static inline int32_t real_to_q31_sat(double x)
{
    const double lsb = nearbyint(x * Q31_SCALE);
    if (lsb >= 2147483647.0) {
        return INT32_MAX;
    }
    if (lsb <= -2147483648.0) {
        return INT32_MIN;
    }
    return (int32_t)lsb;
}

/* distance in LSB between a Q31 result and a real value (in per-unit) */
static inline double lsb_error(int32_t got, double want_pu)
{
    return fabs((double)got - want_pu * Q31_SCALE);
}

#endif /* Q31_TEST_UTIL_H */
