/*
 * Circular (d, q) limits. See mc/circle_limit.h.
 *
 * Both work on the vector normalised by r_max (|x|/r_max compared with 1),
 * so r_max^2 never overflows or underflows; the keep-angle limit has a
 * second normalisation for |x|/r_max^2 beyond float range.
 */
#include "mc/circle_limit.h"

#include <float.h>
#include <math.h>

/* The input contract both limits share (see the header). Returns true when
 * the limit is to be applied to the finite vector (*x_d, *x_q); otherwise
 * *changed is the limit's result: true after an invalid r_max set both
 * components to NaN, false for a non-finite vector (left unchanged). */
static bool limit_applies(float *x_d, float *x_q, float r_max, bool *changed)
{
    if (!mc_circle_radius_valid_f32(r_max)) {
        *x_d = NAN;
        *x_q = NAN;
        *changed = true;
        return false;
    }
    *changed = false;
    return isfinite(*x_d) && isfinite(*x_q);
}

bool mc_circle_limit_outside_f32(float *x_d, float *x_q, float r_max,
                                 float mag2_n)
{
    bool changed;
    if (!limit_applies(x_d, x_q, r_max, &changed)) {
        return changed;
    }
    /* mag2_n = |x|^2 / r_max^2 as mc_circle_limit_f32 computed it
     * (normalised by r_max): > 1 there, or beyond float range */
    if (!(mag2_n > 1.0f)) {
        return false;
    }
    const float d = *x_d;
    const float q = *x_q;
    float scale;
    if (isfinite(mag2_n)) {
        scale = 1.0f / sqrtf(mag2_n); /* guarded: mag2_n > 1 */
    } else {
        /* |x| / r_max beyond float range: normalise by the larger
         * component (> 0 here) instead. */
        const float m = (fabsf(d) >= fabsf(q)) ? fabsf(d) : fabsf(q);
        const float d_m = d / m;
        const float q_m = q / m;
        scale = (r_max / m) / sqrtf(d_m * d_m + q_m * q_m); /* arg >= 1 */
    }
    *x_d = d * scale;
    *x_q = q * scale;
    return true;
}

bool mc_circle_limit_d_priority_f32(float *x_d, float *x_q, float r_max)
{
    bool changed;
    if (!limit_applies(x_d, x_q, r_max, &changed)) {
        return changed;
    }
    const float d = *x_d;
    const float q = *x_q;
    const float inv_r = 1.0f / r_max; /* guarded: r_max >= FLT_MIN */
    bool limited = false;
    float abs_d = fabsf(d);
    if (abs_d > r_max) {
        abs_d = r_max;
        *x_d = copysignf(r_max, d);
        limited = true;
    }
    /* (r^2 - d^2) / r^2 = ((r - |d|) / r) (1 + |d| / r): r - |d| is exact
     * near the circle (Sterbenz), so the room for q keeps full relative
     * precision where 1 - (d/r)^2 would cancel. */
    const float q_room2_n = ((r_max - abs_d) * inv_r) * (1.0f + abs_d * inv_r);
    const float q_n = q * inv_r;
    if (q_n * q_n > q_room2_n) {
        *x_q = copysignf(sqrtf(q_room2_n) * r_max, q); /* arg >= 0 */
        limited = true;
    }
    return limited;
}
