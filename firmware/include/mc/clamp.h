/*
 * Symmetric limit of a float, for the per-sample paths.
 */
#ifndef MC_CLAMP_H
#define MC_CLAMP_H

#include <math.h>

#include "mc/compiler.h"

/* x limited to [-limit, limit] (limit >= 0) with one comparison on the
 * common path: |x| > limit gives +-limit with x's sign (an infinite x
 * too); a NaN x stays NaN (no comparison holds: the caller's finiteness
 * test sees it). The same result as two one-sided comparisons.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_clamp_sym_f32(float x, float limit)
{
    return MC_UNLIKELY(fabsf(x) > limit) ? copysignf(limit, x) : x;
}

#endif /* MC_CLAMP_H */
