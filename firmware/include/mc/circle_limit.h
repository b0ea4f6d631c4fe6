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

#include <stdbool.h>

/* Keep-angle circular limit. Interrupt context: yes. */
bool mc_circle_limit_f32(float *x_d, float *x_q, float r_max);

/* d-priority circular limit. Interrupt context: yes. */
bool mc_circle_limit_d_priority_f32(float *x_d, float *x_q, float r_max);

#endif /* MC_CIRCLE_LIMIT_H */
