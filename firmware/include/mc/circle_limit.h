/*
 * Circular limit of a (d, q) vector, float32 (the voltage limit of the
 * current loops: |v_dq| <= r_max, e.g. r_max = v_dc / sqrt(3)).
 *
 * mc_circle_limit_f32 (policy: keep the angle): if |x| > r_max, both
 *   components are scaled by r_max / |x|, so the direction is kept and the
 *   result lies on the circle.
 * mc_circle_limit_d_priority_f32 (policy: d first): x_d is clamped to
 *   [-r_max, r_max] first, then x_q gets the remaining
 *   sqrt(r_max^2 - x_d^2) with its sign kept. Used when the d axis must be
 *   honoured (field weakening).
 *
 * Both return true when they changed the vector. Units: those of the inputs.
 * r_max must be finite and >= FLT_MIN (the smallest normal float); otherwise
 * (including NaN, 0, negative) both components are set to NaN and true is
 * returned (a configuration error becomes a visible fault, never a
 * silent zero). A vector with a NaN or Inf component is returned unchanged
 * with false (non-finite values are never replaced by finite ones).
 * Magnitudes up to FLT_MAX are handled without overflow.
 * Bounded time (at most one sqrt and four divisions).
 * Interrupt context: yes.
 */
#ifndef MC_CIRCLE_LIMIT_H
#define MC_CIRCLE_LIMIT_H

#include <float.h>
#include <stdbool.h>

#include "mc/compiler.h"

/* r_max finite and >= FLT_MIN (1 / r_max finite): the radius both limits
 * accept. Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_circle_radius_valid_f32(float r_max)
{
    return (r_max >= FLT_MIN) && (r_max <= FLT_MAX); /* false for NaN */
}

/* The keep-angle limit past its common case, for mc_circle_limit_f32:
 * mag2_n is |x|^2 / r_max^2 as that computed it when r_max is valid and
 * the vector finite (> 1 then), anything otherwise (false for a finite
 * vector with mag2_n <= 1). Interrupt context: yes. */
bool mc_circle_limit_outside_f32(float *x_d, float *x_q, float r_max,
                                 float mag2_n);

/* Keep-angle circular limit. The common case inline: a valid r_max and a
 * finite vector inside the circle (false, unchanged); the rest out of
 * line. Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_circle_limit_f32(float *x_d, float *x_q,
                                               float r_max)
{
    float mag2_n = 0.0f;
    if (mc_circle_radius_valid_f32(r_max)) {
        const float inv_r = 1.0f / r_max; /* guarded: r_max >= FLT_MIN */
        const float d_n = *x_d * inv_r;
        const float q_n = *x_q * inv_r;
        mag2_n = d_n * d_n + q_n * q_n;
        if (mag2_n <= 1.0f) { /* false for a non-finite vector */
            return false;
        }
    }
    return mc_circle_limit_outside_f32(x_d, x_q, r_max, mag2_n);
}

/* d-priority circular limit. Interrupt context: yes. */
bool mc_circle_limit_d_priority_f32(float *x_d, float *x_q, float r_max);

#endif /* MC_CIRCLE_LIMIT_H */
