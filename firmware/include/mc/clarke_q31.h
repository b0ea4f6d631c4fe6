/*
 * Clarke transform (amplitude invariant), Q31 fixed point.
 *
 * Scaling: phase quantities are Q31 per-unit of a full scale chosen by the
 * caller (for currents e.g. i / I_fs with I_fs the ADC full scale); alpha and
 * beta come out in the same full scale. Being linear, the transform does not
 * care which full scale that is. Results outside [-1, 1) saturate to
 * INT32_MIN / INT32_MAX; they never wrap.
 *
 * Accuracy: each output is one rounding of an exact int64 expression times a
 * Q31 constant c (|c - exact| <= 1/2 LSB), so
 *   |error| <= 1/2 LSB + |X| / 2^32 LSB, X the integer expression below
 * (at most 2.5 LSB over the whole input range).
 *
 * Same semantics as mc_clarke_f32, mc_clarke2_f32 and mc_inv_clarke_f32 in
 * mc/clarke.h.
 * Integer only. Interrupt context: yes (pure, bounded time).
 */
#ifndef MC_CLARKE_Q31_H
#define MC_CLARKE_Q31_H

#include "mc/q31.h"

#define MC_Q31_ONE_THIRD  ((int64_t)715827883)  /* round(2^31 / 3) */
#define MC_Q31_INV_SQRT3  ((int64_t)1239850262) /* round(2^31 / sqrt(3)) */
#define MC_Q31_SQRT3_BY_2 ((int64_t)1859775393) /* round(2^31 sqrt(3) / 2) */

/* Three-phase input, no assumption a + b + c = 0:
 *   alpha = (2 a - b - c) / 3,  beta = (b - c) / sqrt(3).
 * |2a - b - c| <= 2^33 and |b - c| <= 2^32, so the products with the
 * constants stay below 2^63. Interrupt context: yes. */
static inline void mc_clarke_q31(mc_q31_t i_a, mc_q31_t i_b, mc_q31_t i_c,
                                 mc_q31_t *i_alpha, mc_q31_t *i_beta)
{
    const int64_t x_alpha = 2 * (int64_t)i_a - (int64_t)i_b - (int64_t)i_c;
    const int64_t x_beta = (int64_t)i_b - (int64_t)i_c;
    *i_alpha = mc_sat_q31(mc_round_shift_q63(x_alpha * MC_Q31_ONE_THIRD, 31U));
    *i_beta = mc_sat_q31(mc_round_shift_q63(x_beta * MC_Q31_INV_SQRT3, 31U));
}

/* Two-phase input, assuming i_c = -(i_a + i_b):
 *   alpha = a,  beta = (a + 2 b) / sqrt(3).
 * |a + 2b| <= 3 * 2^31, times the constant < 8.0e18 < 2^63.
 * Interrupt context: yes. */
static inline void mc_clarke2_q31(mc_q31_t i_a, mc_q31_t i_b, mc_q31_t *i_alpha,
                                  mc_q31_t *i_beta)
{
    const int64_t x_beta = (int64_t)i_a + 2 * (int64_t)i_b;
    *i_alpha = i_a;
    *i_beta = mc_sat_q31(mc_round_shift_q63(x_beta * MC_Q31_INV_SQRT3, 31U));
}

/* Inverse Clarke without saturation: phase values in Q31 units held in
 * int64_t, because they reach (1 + sqrt(3)) / 2 = 1.37 of full scale for
 * full-scale alpha and beta (used by SVPWM, which must keep the angle).
 *   a = alpha,  b = -alpha/2 + sqrt(3)/2 beta,  c = -alpha/2 - sqrt(3)/2 beta,
 * b and c each rounded once: |error| <= 1/2 + |beta| / 2^32 <= 1 LSB.
 * Interrupt context: yes. */
static inline void mc_inv_clarke_wide_q31(mc_q31_t alpha, mc_q31_t beta,
                                          int64_t abc[3])
{
    const int64_t half_alpha_q62 = (int64_t)alpha * ((int64_t)1 << 30);
    const int64_t beta_q62 = (int64_t)beta * MC_Q31_SQRT3_BY_2;
    abc[0] = alpha;
    abc[1] = mc_round_shift_q63(beta_q62 - half_alpha_q62, 31U);
    abc[2] = mc_round_shift_q63(-beta_q62 - half_alpha_q62, 31U);
}

/* Inverse Clarke, saturated to Q31 (same semantics as mc_inv_clarke_f32).
 * Interrupt context: yes. */
static inline void mc_inv_clarke_q31(mc_q31_t alpha, mc_q31_t beta, mc_q31_t *a,
                                     mc_q31_t *b, mc_q31_t *c)
{
    int64_t abc[3];
    mc_inv_clarke_wide_q31(alpha, beta, abc);
    *a = alpha;
    *b = mc_sat_q31(abc[1]);
    *c = mc_sat_q31(abc[2]);
}

#endif /* MC_CLARKE_Q31_H */
