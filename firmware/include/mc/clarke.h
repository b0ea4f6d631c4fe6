/*
 * Clarke transform (abc -> alpha/beta), amplitude-invariant form.
 *
 *   alpha = (2a - b - c) / 3,   beta = (b - c) / sqrt(3)
 *
 * Amplitude-invariant: a balanced set of amplitude A maps to a vector of
 * length A. Consequence for power: p = va*ia + vb*ib + vc*ic
 * = 1.5 * (v_alpha*i_alpha + v_beta*i_beta) for zero-sequence-free sets.
 * Units are whatever the caller passes (A, V); float32, no scaling.
 * All functions: pure arithmetic, no state, no division, bounded time.
 * Interrupt context: yes (every function). Non-finite inputs propagate to the
 * outputs (never replaced by a finite value).
 */
#ifndef MC_CLARKE_H
#define MC_CLARKE_H

#include "mc/compiler.h"

#define MC_INV_SQRT3_F  0.577350269189625764509f /* 1/sqrt(3) */
#define MC_SQRT3_F      1.732050807568877293527f /* sqrt(3) */
#define MC_SQRT3_BY_2_F 0.866025403784438646764f /* sqrt(3)/2 */

/* Three-input Clarke; removes any zero-sequence component. Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE void mc_clarke_f32(float i_a, float i_b, float i_c,
                                         float *i_alpha, float *i_beta)
{
    *i_alpha = (2.0f * i_a - i_b - i_c) * (1.0f / 3.0f);
    *i_beta = (i_b - i_c) * MC_INV_SQRT3_F;
}

/* Two-input Clarke; assumes i_a + i_b + i_c = 0 (no neutral current).
 * alpha = a, beta = (a + 2b)/sqrt(3). Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_clarke2_f32(float i_a, float i_b, float *i_alpha,
                                          float *i_beta)
{
    *i_alpha = i_a;
    *i_beta = (i_a + 2.0f * i_b) * MC_INV_SQRT3_F;
}

/* Inverse Clarke; produces a zero-sequence-free set:
 * a = alpha, b = -alpha/2 + sqrt(3)/2 beta, c = -alpha/2 - sqrt(3)/2 beta.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_inv_clarke_f32(float alpha, float beta, float *a,
                                             float *b, float *c)
{
    const float half_alpha = 0.5f * alpha;
    const float beta_term = MC_SQRT3_BY_2_F * beta;
    *a = alpha;
    *b = -half_alpha + beta_term;
    *c = -half_alpha - beta_term;
}

#endif /* MC_CLARKE_H */
