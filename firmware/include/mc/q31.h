/*
 * Q31 fixed-point helpers for MCUs without an FPU.
 *
 * Format: a Q31 value x represents x / 2^31, range [-1, 1 - 2^-31].
 * Every helper saturates to [INT32_MIN, INT32_MAX] instead of wrapping, and
 * none relies on signed overflow or on the implementation-defined right
 * shift of a negative value: wide arithmetic is done in int64_t and
 * arithmetic right shifts use mc_asr_q63() (a floor division by 2^n written
 * with well-defined unsigned operations only).
 *
 * Rounding: products and rescalings round to nearest, ties towards +inf
 * (floor(x + 1/2)), so each rounded operation contributes at most 1/2 LSB.
 *
 * Integer only; no floats. All functions are pure and bounded-time.
 * Interrupt context: yes (every function). Library: mc_math_q31.
 */
#ifndef MC_Q31_H
#define MC_Q31_H

#include <stdint.h>

typedef int32_t mc_q31_t;

/* floor(x / 2^n) for 1 <= n <= 63, without right-shifting a negative value:
 * in offset binary, x + 2^63 is in [0, 2^64) as a uint64_t, and since 2^n
 * divides 2^63, floor((x + 2^63) / 2^n) = floor(x / 2^n) + 2^(63-n); that
 * quotient is below 2^63, so the conversion back to int64_t is exact.
 * Branch-free. Interrupt context: yes. */
static inline int64_t mc_asr_q63(int64_t x, unsigned n)
{
    const uint64_t offset = (uint64_t)x + ((uint64_t)1 << 63);
    return (int64_t)(offset >> n) - (int64_t)((uint64_t)1 << (63U - n));
}

/* round(x / 2^n) = floor((x + 2^(n-1)) / 2^n) for 1 <= n <= 62.
 * Precondition: x + 2^(n-1) does not overflow (|x| <= 2^63 - 2^62 suffices).
 * Interrupt context: yes. */
static inline int64_t mc_round_shift_q63(int64_t x, unsigned n)
{
    return mc_asr_q63(x + ((int64_t)1 << (n - 1U)), n);
}

/* Saturate a wide integer to the Q31 range. Interrupt context: yes. */
static inline mc_q31_t mc_sat_q31(int64_t x)
{
    if (x > INT32_MAX) {
        return INT32_MAX;
    }
    if (x < INT32_MIN) {
        return INT32_MIN;
    }
    return (mc_q31_t)x;
}

/* a + b, saturated. Interrupt context: yes. */
static inline mc_q31_t mc_add_sat_q31(mc_q31_t a, mc_q31_t b)
{
    return mc_sat_q31((int64_t)a + (int64_t)b);
}

/* a - b, saturated. Interrupt context: yes. */
static inline mc_q31_t mc_sub_sat_q31(mc_q31_t a, mc_q31_t b)
{
    return mc_sat_q31((int64_t)a - (int64_t)b);
}

/* -a, saturated: -INT32_MIN gives INT32_MAX.
 * Interrupt context: yes. */
static inline mc_q31_t mc_neg_sat_q31(mc_q31_t a)
{
    return mc_sat_q31(-(int64_t)a);
}

/* |a|, saturated: |INT32_MIN| gives INT32_MAX.
 * Interrupt context: yes. */
static inline mc_q31_t mc_abs_sat_q31(mc_q31_t a)
{
    return mc_sat_q31(a < 0 ? -(int64_t)a : (int64_t)a);
}

/* a * b in Q31, rounded to nearest (<= 1/2 LSB), saturated:
 * INT32_MIN * INT32_MIN (= +1.0) gives INT32_MAX. Callable from interrupt
 * context. */
static inline mc_q31_t mc_mul_sat_q31(mc_q31_t a, mc_q31_t b)
{
    return mc_sat_q31(mc_round_shift_q63((int64_t)a * (int64_t)b, 31U));
}

/* (p1 + p2) / 2^31 rounded to nearest and saturated, for two Q62 products
 * with |p1|, |p2| <= 2^62 (any product of two int32_t, or its negation).
 * The sum itself may reach 2^63 and overflow int64_t, so both terms are
 * halved first and their dropped low bits added back exactly:
 * p = 2h + l (l in {0, 1}), (p1 + p2) / 2 = h1 + h2 + (l1 + l2) / 2, and a
 * half-integer remainder never changes floor((s + 2^29) / 2^30).
 * Interrupt context: yes. */
static inline mc_q31_t mc_round_sum_q31(int64_t p1, int64_t p2)
{
    const int64_t h1 = mc_asr_q63(p1, 1U);
    const int64_t h2 = mc_asr_q63(p2, 1U);
    const int64_t low = ((p1 - 2 * h1) + (p2 - 2 * h2)) / 2;
    return mc_sat_q31(mc_round_shift_q63(h1 + h2 + low, 30U));
}

/* a*b + c*d in Q31, rounded once (<= 1/2 LSB), saturated.
 * Interrupt context: yes. */
static inline mc_q31_t mc_mac2_sat_q31(mc_q31_t a, mc_q31_t b, mc_q31_t c,
                                       mc_q31_t d)
{
    return mc_round_sum_q31((int64_t)a * b, (int64_t)c * d);
}

/* a*b - c*d in Q31, rounded once (<= 1/2 LSB), saturated.
 * -(c*d) is within [-2^62, 2^62 - 2^31], so the negation cannot overflow.
 * Interrupt context: yes. */
static inline mc_q31_t mc_msub2_sat_q31(mc_q31_t a, mc_q31_t b, mc_q31_t c,
                                        mc_q31_t d)
{
    return mc_round_sum_q31((int64_t)a * b, -((int64_t)c * d));
}

/* floor(sqrt(x)) for any uint64_t x (result < 2^32). Bit-by-bit, exactly 32
 * iterations: bounded time, no division. Interrupt context: yes. */
uint32_t mc_isqrt_u64(uint64_t x);

#endif /* MC_Q31_H */
