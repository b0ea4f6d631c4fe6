/*
 * Park and inverse Park transforms, Q31 fixed point.
 *
 * Scaling: alpha/beta and d/q are Q31 per-unit of the same caller-chosen full
 * scale (the rotation preserves it). sin_theta and cos_theta are Q31 values of
 * sin(theta_e) and cos(theta_e) supplied by the caller (CMSIS style, e.g. from
 * a table or polynomial); +1.0 is represented by INT32_MAX. The outputs can
 * exceed the full scale by up to sqrt(2) (e.g. alpha = beta = 1 at 45 deg);
 * such results saturate to INT32_MIN / INT32_MAX, they never wrap.
 *
 * Accuracy: each output is the exact sum of two Q62 products, rounded once,
 * so |error| <= 1/2 LSB relative to the given Q31 inputs.
 *
 * Same semantics as mc_park_f32 / mc_inv_park_f32 in mc/park.h.
 * Integer only. Interrupt context: yes (pure, bounded time).
 */
#ifndef MC_PARK_Q31_H
#define MC_PARK_Q31_H

#include "mc/q31.h"

/* d =  alpha cos + beta sin,  q = -alpha sin + beta cos.
 * Interrupt context: yes. */
static inline void mc_park_q31(mc_q31_t alpha, mc_q31_t beta,
                               mc_q31_t sin_theta, mc_q31_t cos_theta,
                               mc_q31_t *d, mc_q31_t *q)
{
    *d = mc_mac2_sat_q31(alpha, cos_theta, beta, sin_theta);
    *q = mc_msub2_sat_q31(beta, cos_theta, alpha, sin_theta);
}

/* alpha = d cos - q sin,  beta = d sin + q cos.
 * Interrupt context: yes. */
static inline void mc_inv_park_q31(mc_q31_t d, mc_q31_t q, mc_q31_t sin_theta,
                                   mc_q31_t cos_theta, mc_q31_t *alpha,
                                   mc_q31_t *beta)
{
    *alpha = mc_msub2_sat_q31(d, cos_theta, q, sin_theta);
    *beta = mc_mac2_sat_q31(d, sin_theta, q, cos_theta);
}

#endif /* MC_PARK_Q31_H */
