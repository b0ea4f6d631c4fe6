/*
 * Angle utilities: wrap, sin/cos, atan2, unwrap operator A. See mc/angle.h.
 *
 * Range reduction (Cody-Waite): the period P (2*pi for wrapping, pi/2 for
 * sin/cos) is split as P = P1 + P2 + P3 where P1 and P2 have so few
 * significant bits that k*P1 and k*P2 are exact floats for every k the
 * accepted range can produce, and P3 is the float nearest the remainder.
 * theta - k*P1 is then exact (Sterbenz), the next subtraction is exact by
 * the quantum argument (both operands are multiples of the last bit of P2
 * and the result is below 2^24 such quanta), and only the final k*P3 term
 * rounds: the reduction error is about one ulp of the result, independent of
 * |theta| inside the accepted range.
 *
 * Polynomial coefficients: minimax (Remez, double precision) fits, rounded
 * to float:
 *   sin x = x + x^3 (S1 + S2 x^2 + S3 x^4)     on |x| <= pi/4, err 3.5e-9
 *   cos x = 1 + x^2 (C1 + C2 x^2 + C3 x^4)     on |x| <= pi/4, err 3.2e-8
 *   atan t = t (A0 + A1 t^2 + ... + A6 t^12)   on 0 <= t <= 1, err 2.5e-7
 * The float evaluation adds a few 1e-8; the totals are asserted in
 * tests/unit/math/test_angle.c against MC_*_MAX_ERR in the header.
 */
#include "mc/angle.h"

#include <math.h>

/* 2*pi = MC_TWO_PI_1 + MC_TWO_PI_2 + MC_TWO_PI_3 (mc/angle.h): 8, 11 and
 * 24 significant bits. |k| <= 25000/(2*pi) < 2^12, so k*MC_TWO_PI_1 and
 * k*MC_TWO_PI_2 are exact. */
#define INV_TWO_PI 0.159154943091895335769f

/* atan: MC_ATAN_A0..A6 in mc/angle.h (mc_atan2_unchecked_f32). */

static float reduce_two_pi(float theta_rad, int32_t k)
{
    return mc_reduce_two_pi_f32(theta_rad, (float)k);
}

float mc_wrap_pi_f32(float theta_rad)
{
    if (!(fabsf(theta_rad) <= MC_ANGLE_MAX_ABS_RAD)) { /* also NaN */
        return NAN;
    }
    if (fabsf(theta_rad) <= MC_PI_F) {
        return (theta_rad == -MC_PI_F) ? MC_PI_F : theta_rad;
    }
    int32_t k = mc_round_to_i32_f32(theta_rad * INV_TWO_PI);
    float r = reduce_two_pi(theta_rad, k);
    /* The product theta/(2 pi) rounds, so k can be one off next to an odd
     * multiple of pi: correct once (the reduction itself is exact). */
    if (r > MC_PI_F) {
        r = reduce_two_pi(theta_rad, k + 1);
    } else if (r < -MC_PI_F) {
        r = reduce_two_pi(theta_rad, k - 1);
    }
    return (r <= -MC_PI_F) ? MC_PI_F : r;
}

void mc_sincos_f32(float theta_rad, float *sin_out, float *cos_out)
{
    mc_sincos_inline_f32(theta_rad, sin_out, cos_out);
}

float mc_atan2_f32(float y, float x)
{
    if (!isfinite(x) || !isfinite(y)) {
        return NAN;
    }
    return mc_atan2_unchecked_f32(y, x);
}

mc_status_t mc_unwrap_init_f32(mc_unwrap_f32_t *u, float theta_wrapped_rad)
{
    u->turns = 0;
    if (!isfinite(theta_wrapped_rad)) {
        u->prev_wrapped_rad = 0.0f;
        return MC_ERR_NONFINITE;
    }
    u->prev_wrapped_rad = theta_wrapped_rad;
    return MC_OK;
}

float mc_unwrap_step_f32(mc_unwrap_f32_t *u, float theta_wrapped_rad)
{
    if (!isfinite(theta_wrapped_rad)) {
        return NAN;
    }
    /* Operator A, corrected (see mc/angle.h): a sample-to-sample jump of
     * more than pi is a crossing of the +-pi cut. */
    const float step_rad = theta_wrapped_rad - u->prev_wrapped_rad;
    int32_t turns = u->turns;
    if (step_rad < -MC_PI_F) {
        if (turns == INT32_MAX) {
            return NAN;
        }
        turns += 1;
    } else if (step_rad > MC_PI_F) {
        if (turns == INT32_MIN) {
            return NAN;
        }
        turns -= 1;
    }
    u->turns = turns;
    u->prev_wrapped_rad = theta_wrapped_rad;
    return theta_wrapped_rad + MC_TWO_PI_F * (float)turns;
}
