/*
 * Park transform (alpha/beta -> d/q) and its inverse, CMSIS-DSP convention:
 * the caller supplies sin and cos of the ELECTRICAL angle theta_e (for
 * example from mc_sincos_f32), so one sincos serves both directions.
 *
 *   d =  alpha*cos + beta*sin        alpha = d*cos - q*sin
 *   q = -alpha*sin + beta*cos        beta  = d*sin + q*cos
 *
 * A pure rotation: preserves the vector length when sin^2 + cos^2 = 1.
 * Units are those of the inputs. Pure arithmetic, no state, no division,
 * bounded time. Interrupt context: yes (every function). Non-finite inputs
 * propagate.
 */
#ifndef MC_PARK_H
#define MC_PARK_H

#include "mc/compiler.h"

/* Park: rotate (alpha, beta) by -theta_e. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_park_f32(float alpha, float beta, float sin_theta,
                                       float cos_theta, float *d, float *q)
{
    *d = alpha * cos_theta + beta * sin_theta;
    *q = -alpha * sin_theta + beta * cos_theta;
}

/* Inverse Park: rotate (d, q) by +theta_e. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_inv_park_f32(float d, float q, float sin_theta,
                                           float cos_theta, float *alpha,
                                           float *beta)
{
    *alpha = d * cos_theta - q * sin_theta;
    *beta = d * sin_theta + q * cos_theta;
}

#endif /* MC_PARK_H */
