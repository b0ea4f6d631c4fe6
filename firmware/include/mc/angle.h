/*
 * Angle utilities, float32: wrapping, fast sin/cos and atan2, and the unwrap
 * operator A of paper 001 (Appendix A).
 *
 * Units: radians. Electrical or mechanical is the caller's business; these
 * functions are pure geometry.
 *
 * Accepted input range of the range-reducing functions (mc_wrap_pi_f32,
 * mc_angle_diff_f32, mc_sincos_f32): |theta| <= MC_ANGLE_MAX_ABS_RAD. The
 * float input is treated as exact and reduced with a three-part (Cody-Waite)
 * 2*pi resp. pi/2, so the reduction error does not grow with |theta| inside
 * that range. Outside it, and for NaN/Inf input, the result is NaN (never a
 * finite fake value): callers keep angles wrapped, or reconstruct continuous
 * angles from the unwrap turn count.
 *
 * Measured maximum errors (tests/unit/math/test_angle.c, dense grid plus
 * seeded random inputs over the whole accepted range, against a double
 * reference): see the MC_*_MAX_ERR constants below, which the tests assert.
 *
 * Every function here is reentrant, bounded-time, allocation-free.
 * Interrupt context: yes (every function).
 */
#ifndef MC_ANGLE_H
#define MC_ANGLE_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "mc/compiler.h"
#include "mc/park.h"
#include "mc/status.h"

#define MC_PI_F      3.14159265358979323846f
#define MC_TWO_PI_F  6.28318530717958647692f
#define MC_HALF_PI_F 1.57079632679489661923f

/* Largest |theta| accepted by wrap/diff/sincos. */
#define MC_ANGLE_MAX_ABS_RAD 25000.0f

/* Documented (and tested) maximum absolute errors over the accepted range. */
#define MC_WRAP_PI_MAX_ERR_RAD 5.0e-7f /* vs exact theta - 2*pi*k */
#define MC_SINCOS_MAX_ABS_ERR  3.0e-7f /* |sin - sin_exact|, same for cos */
#define MC_ATAN2_MAX_ERR_RAD   1.0e-6f /* vs exact atan2 of the inputs */

/* 2*pi = MC_TWO_PI_1 + MC_TWO_PI_2 + MC_TWO_PI_3: 8, 11 and 24 significant
 * bits (the Cody-Waite split of mc/angle.c). */
#define MC_TWO_PI_1 0x1.92p+2f
#define MC_TWO_PI_2 0x1.fb4p-10f
#define MC_TWO_PI_3 0x1.4442d2p-22f

/* Minimax atan t = t (A0 + A1 t^2 + ... + A6 t^12) on 0 <= t <= 1
 * (mc/angle.c). */
#define MC_ATAN_A0 9.999961257e-01f
#define MC_ATAN_A1 -3.331736922e-01f
#define MC_ATAN_A2 1.980781555e-01f
#define MC_ATAN_A3 -1.323334128e-01f
#define MC_ATAN_A4 7.962366939e-02f
#define MC_ATAN_A5 -3.360421583e-02f
#define MC_ATAN_A6 6.811792031e-03f

/* theta - k_f 2 pi with the three-part 2 pi: k_f P1 and k_f P2 are exact
 * and so are the first two subtractions for an integer |k_f| < 2^12 (the
 * accepted range); only the last term rounds (mc/angle.c). k_f = +-1 folds
 * to three additions. Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_reduce_two_pi_f32(float theta_rad, float k_f)
{
    return ((theta_rad - k_f * MC_TWO_PI_1) - k_f * MC_TWO_PI_2) -
           k_f * MC_TWO_PI_3;
}

/*
 * Wrap theta to (-pi, pi]: returns theta - 2*pi*k for the integer k that
 * puts it there. Inputs already inside [-pi, pi] are returned bit-exactly.
 * The result r satisfies -MC_PI_F < r <= MC_PI_F (a value that would round
 * to -MC_PI_F is returned as +MC_PI_F, the same angle).
 * |theta| > MC_ANGLE_MAX_ABS_RAD or non-finite: returns NaN.
 * Interrupt context: yes.
 */
float mc_wrap_pi_f32(float theta_rad);

/*
 * mc_wrap_pi_f32 for the angles of a tracking loop: the same result for
 * every input (NaN for NaN), inline, and for |theta| <= 3 pi (the
 * difference of two wrapped angles, a wrapped angle plus less than 2 pi)
 * without the division by 2 pi: an angle inside (-pi, pi] is returned as
 * it is, one outside is reduced by k = +-1 with the three-part 2 pi of
 * mc_wrap_pi_f32 (the same operations, so the same float), and a result
 * still outside (|theta| > 3 pi, Inf, NaN) is left to mc_wrap_pi_f32.
 * Equality with mc_wrap_pi_f32: tests/unit/firmware/observers/
 * test_pll_observer.c (every float with pi <= |theta| <= 4 pi, a grid of
 * the rest). Interrupt context: yes.
 */
MC_STATIC_FORCEINLINE float mc_wrap_pi_near_f32(float theta_rad)
{
    if (MC_LIKELY(fabsf(theta_rad) < MC_PI_F)) {
        return theta_rad; /* the common case; false for NaN */
    }
    float r;
    if (theta_rad > MC_PI_F) {
        r = mc_reduce_two_pi_f32(theta_rad, 1.0f);
    } else if (theta_rad < -MC_PI_F) {
        r = mc_reduce_two_pi_f32(theta_rad, -1.0f);
    } else { /* +-pi (-pi is returned as +pi, the same angle), or NaN */
        return (theta_rad == -MC_PI_F) ? MC_PI_F : theta_rad;
    }
    if (r > -MC_PI_F && r <= MC_PI_F) {
        return r;
    }
    return mc_wrap_pi_f32(theta_rad); /* |theta| > 3 pi */
}

/* Signed shortest angle from b to a: wrap(a - b) in (-pi, pi].
 * Same range rules as mc_wrap_pi_f32 (applied to a - b). Interrupt context:
 * yes. */
static inline float mc_angle_diff_f32(float a_rad, float b_rad)
{
    return mc_wrap_pi_f32(a_rad - b_rad);
}

/* mc_angle_diff_f32 through mc_wrap_pi_near_f32: the same result, without
 * the division for two angles in (-pi, pi] (or less than 3 pi apart).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_angle_diff_near_f32(float a_rad, float b_rad)
{
    return mc_wrap_pi_near_f32(a_rad - b_rad);
}

/*
 * sin and cos of theta in one call (polynomials on [-pi/4, pi/4] after an
 * extended-precision reduction by pi/2). Max abs error MC_SINCOS_MAX_ABS_ERR
 * for |theta| <= MC_ANGLE_MAX_ABS_RAD. Outside that range or for non-finite
 * theta both outputs are NaN. Cost on a Cortex-M4F (gcc 12 -O2, static
 * count of the executed path): about 56 instructions, no division
 * (newlib sinf + cosf: about 115).
 * Interrupt context: yes.
 */
void mc_sincos_f32(float theta_rad, float *sin_out, float *cos_out);

/* Nearest integer of x for |x| < 2^23 (no rintf: the M4F has no VRINT). */
MC_STATIC_FORCEINLINE int32_t mc_round_to_i32_f32(float x)
{
    return (int32_t)(x + ((x >= 0.0f) ? 0.5f : -0.5f));
}

/* 1.5 * 2^23: a float of this magnitude has a unit last place. */
#define MC_ROUND_SHIFTER_F 0x1.8p23f

/* k = x rounded to the nearest integer (ties to even) for |x| < 2^22, as
 * a float (*k_f) and as k mod 4 (returned): x + 1.5 * 2^23 is rounded by
 * the FPU to a whole number, whose low mantissa bits are 2^22 + k, and
 * subtracting the shifter again is exact. 5 instructions on the M4F
 * against 10 of the conversions. Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_round_quadrant_f32(float x, float *k_f)
{
    const float shifted = x + MC_ROUND_SHIFTER_F;
    uint32_t bits;
    memcpy(&bits, &shifted, sizeof bits);
    *k_f = shifted - MC_ROUND_SHIFTER_F;
    return bits & 3u;
}

/* pi/2 = MC_HALF_PI_1 + MC_HALF_PI_2 + MC_HALF_PI_3: 8, 9 and 23
 * significant bits. |k| <= 25000*2/pi < 2^14, so k*MC_HALF_PI_1 and
 * k*MC_HALF_PI_2 are exact. Polynomials: angle.c's header comment. */
#define MC_HALF_PI_1 0x1.92p+0f
#define MC_HALF_PI_2 0x1.fbp-12f
#define MC_HALF_PI_3 0x1.5110b4p-22f
#define MC_TWO_BY_PI 0.636619772367581343076f
#define MC_SINCOS_S1 -1.666665524e-01f
#define MC_SINCOS_S2 8.332100697e-03f
#define MC_SINCOS_S3 -1.950396254e-04f
#define MC_SINCOS_C1 -4.999989569e-01f
#define MC_SINCOS_C2 4.165629297e-02f
#define MC_SINCOS_C3 -1.359782298e-03f

/* mc_sincos_inline_f32 without its range test, for an angle its caller
 * knows finite and within MC_ANGLE_MAX_ABS_RAD (e.g. an estimate wrapped
 * to (-pi, pi] and checked): the same results. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void
mc_sincos_in_range_f32(float theta_rad, float *sin_out, float *cos_out)
{
    float k_f;
    const uint32_t quadrant =
        mc_round_quadrant_f32(theta_rad * MC_TWO_BY_PI, &k_f);
    const float x = ((theta_rad - k_f * MC_HALF_PI_1) - k_f * MC_HALF_PI_2) -
                    k_f * MC_HALF_PI_3;
    const float x2 = x * x;
    const float s =
        x + x * x2 * (MC_SINCOS_S1 + x2 * (MC_SINCOS_S2 + x2 * MC_SINCOS_S3));
    const float c =
        1.0f + x2 * (MC_SINCOS_C1 + x2 * (MC_SINCOS_C2 + x2 * MC_SINCOS_C3));
    /* theta = k*pi/2 + x: rotate (s, c) by the quadrant k mod 4. */
    switch (quadrant) {
    case 0u:
        *sin_out = s;
        *cos_out = c;
        break;
    case 1u:
        *sin_out = c;
        *cos_out = -s;
        break;
    case 2u:
        *sin_out = -s;
        *cos_out = -c;
        break;
    default:
        *sin_out = -c;
        *cos_out = s;
        break;
    }
}

/* mc_sincos_f32 inline (its body: the same results), for the fast ISR. */
MC_STATIC_FORCEINLINE void mc_sincos_inline_f32(float theta_rad, float *sin_out,
                                                float *cos_out)
{
    if (!(fabsf(theta_rad) <= MC_ANGLE_MAX_ABS_RAD)) { /* also NaN */
        *sin_out = NAN;
        *cos_out = NAN;
        return;
    }
    mc_sincos_in_range_f32(theta_rad, sin_out, cos_out);
}

/* |delta| up to which mc_sincos_small_f32 sums its series, rad. */
#define MC_SINCOS_SERIES_MAX_RAD 0.25f

/* sin, cos of a small angle delta, |delta| <= MC_SINCOS_SERIES_MAX_RAD:
 * their Taylor series to the 5th and 6th power (remainders below 1.2e-8
 * and 4e-10, under float32's resolution). Returns false (outputs
 * untouched) for a larger or a non-finite delta: the caller takes
 * mc_sincos_f32. Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_sincos_small_f32(float delta, float *sin_out,
                                               float *cos_out)
{
    if (!(fabsf(delta) <= MC_SINCOS_SERIES_MAX_RAD)) { /* also NaN */
        return false;
    }
    const float d2 = delta * delta;
    *sin_out = delta * (1.0f - d2 * (1.0f / 6.0f - d2 * (1.0f / 120.0f)));
    *cos_out = 1.0f - d2 * (0.5f - d2 * (1.0f / 24.0f - d2 * (1.0f / 720.0f)));
    return true;
}

/* |delta| up to which mc_rotate_unit_f32 rotates by its short series, rad
 * (0.125 rad per sample: 400 Hz electrical at 20 kHz). */
#define MC_ROTATE_SERIES_MAX_RAD 0.125f

/*
 * Rotate the direction (*cos_io, *sin_io) by the angle delta (rad): for
 * |delta| <= MC_ROTATE_SERIES_MAX_RAD by sin delta ~ delta - delta^3 / 6,
 * cos delta ~ 1 - delta^2 / 2 (the angle rotated by exceeds delta by at
 * most |delta|^5 / 30, 1.0e-6 rad at the bound and 2.6e-8 rad at 0.06;
 * the length shrinks by at most delta^4 / 24, 1.0e-5 at the bound, which
 * mc_renormalise_unit_f32 removes), else (and for a non-finite delta) by
 * mc_sincos_f32's sine and cosine of delta (NaN beyond its range or for
 * NaN/Inf: the outputs are NaN). About 17 instructions on the M4F with its
 * range test (gcc -O2, the NAM image), against about 40 for the polynomial
 * sine and cosine of an angle. Interrupt context: yes.
 */
MC_STATIC_FORCEINLINE void mc_rotate_unit_f32(float delta, float *sin_io,
                                              float *cos_io)
{
    float s_d;
    float c_d;
    const float d2 = delta * delta; /* NaN for NaN, Inf for Inf */
    if (MC_LIKELY(d2 <= MC_ROTATE_SERIES_MAX_RAD * MC_ROTATE_SERIES_MAX_RAD)) {
        s_d = delta - delta * (d2 * (1.0f / 6.0f));
        c_d = 1.0f - 0.5f * d2;
    } else {
        mc_sincos_f32(delta, &s_d, &c_d);
    }
    /* the rotation by delta of the vector (c, s): mc_inv_park_f32's */
    float c_new;
    float s_new;
    mc_inv_park_f32(*cos_io, *sin_io, s_d, c_d, &c_new, &s_new);
    *sin_io = s_new;
    *cos_io = c_new;
}

/* Scale the direction (*cos_io, *sin_io) of length near 1 to length 1 by
 * one Newton step of 1 / sqrt(n), n = c^2 + s^2: the factor (3 - n) / 2
 * leaves a relative length error of (3 / 8) (n - 1)^2 (1.5e-10 for a
 * length 1 +- 1e-5). Interrupt context: yes (no division, no sqrt). */
MC_STATIC_FORCEINLINE void mc_renormalise_unit_f32(float *sin_io, float *cos_io)
{
    const float s = *sin_io;
    const float c = *cos_io;
    const float k = 1.5f - 0.5f * (s * s + c * c);
    *sin_io = s * k;
    *cos_io = c * k;
}

/*
 * Four-quadrant arctangent of y/x (octant reduction, one guarded division,
 * odd minimax polynomial). Result in [-MC_PI_F, MC_PI_F], max error
 * MC_ATAN2_MAX_ERR_RAD for all finite inputs (any magnitudes, no overflow).
 * x = y = 0 returns 0 (the C library convention for +0,+0; the angle of a
 * zero vector is undefined, callers that care check the magnitude).
 * NaN or Inf in either input returns NaN. Cost on a Cortex-M4F (gcc 12
 * -O2, static count of the executed path): about 58 instructions including
 * one VDIV (14 cycles) (newlib atan2f: about 91). Interrupt context: yes.
 */
float mc_atan2_f32(float y, float x);

/* mc_atan2_f32 without its finiteness check, inline: the same result for
 * finite inputs. A NaN or an infinity gives NaN or some angle (e.g. 0 for
 * y = 0 and x = NaN): the caller checks the inputs, or values that imply
 * them. One guarded division. Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_atan2_unchecked_f32(float y, float x)
{
    const float abs_x = fabsf(x);
    const float abs_y = fabsf(y);
    const bool steep = abs_y > abs_x; /* second octant */
    const float big = steep ? abs_y : abs_x;
    const float small = steep ? abs_x : abs_y;
    if (big == 0.0f) {
        return 0.0f; /* documented convention for the zero vector */
    }
    const float t = small / big; /* guarded: big > 0 (or NaN); t in [0, 1] */
    const float t2 = t * t;
    float a =
        t * (MC_ATAN_A0 +
             t2 * (MC_ATAN_A1 +
                   t2 * (MC_ATAN_A2 +
                         t2 * (MC_ATAN_A3 +
                               t2 * (MC_ATAN_A4 +
                                     t2 * (MC_ATAN_A5 + t2 * MC_ATAN_A6))))));
    if (steep) {
        a = MC_HALF_PI_F - a;
    }
    if (x < 0.0f) {
        a = MC_PI_F - a; /* left half plane */
    }
    return (y < 0.0f) ? -a : a;
}

/* |y / x| below which mc_atan2_small_f32 sums its series. */
#define MC_ATAN_SERIES_MAX_RATIO 0.125f

/* atan2(y, x) of a small angle, e.g. between two successive samples of a
 * turning vector (y = cross, x = dot product): for x > 0 and |y| <
 * MC_ATAN_SERIES_MAX_RATIO x the series t - t^3/3 + t^5/5 - t^7/7 of
 * t = y / x (remainder below t^9/9 = 1.5e-9 rad), otherwise the
 * out-of-line mc_atan2_f32. A NaN input gives NaN; x = +Inf with a
 * finite y gives 0 (the series), any other infinity NaN: the caller
 * checks its inputs, or values that imply them. One guarded division.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_atan2_small_f32(float y, float x)
{
    if (fabsf(y) < MC_ATAN_SERIES_MAX_RATIO * x) { /* false for NaN */
        const float t = y / x;                     /* guarded: x > 0 */
        const float t2 = t * t;
        return t * (1.0f - t2 * (1.0f / 3.0f -
                                 t2 * (1.0f / 5.0f - t2 * (1.0f / 7.0f))));
    }
    return mc_atan2_f32(y, x);
}

/*
 * Unwrap operator A (paper 001, Appendix A): turns a sequence of wrapped
 * angles e_k in (-pi, pi] (e.g. atan2 outputs) into a continuous angle
 * y_k = e_k + 2*pi*n_k.
 *
 * Deviation from the paper, on purpose: Appendix A as printed forms
 * dif = e[k] - e[k+1] and changes n only when |dif| > 2*pi, which can never
 * happen for wrapped inputs, and its signs are reversed (a forward crossing
 * from +pi to -pi gives dif ~ +2*pi and must INCREASE n). The operator
 * implemented here uses the standard +-pi threshold on the sample-to-sample
 * difference d = e[k+1] - e[k]:  d < -pi -> n += 1;  d > pi -> n -= 1.
 * It is exact (integer turn count) as long as the true angle moves by less
 * than pi per sample.
 *
 * The float output loses absolute resolution as |y| grows (ulp of y); for
 * long runs take the exact integer count from mc_unwrap_turns_f32() and form
 * e + 2*pi*n in the precision you need.
 */
typedef struct {
    float prev_wrapped_rad; /* last accepted input e_k */
    int32_t turns;          /* n_k */
} mc_unwrap_f32_t;

/* Start at theta_wrapped_rad with zero turns. Non-finite input: the state is
 * set to (0, 0 turns) and MC_ERR_NONFINITE returned. Not for ISR use while
 * another context steps the same instance; otherwise Interrupt context: yes. */
mc_status_t mc_unwrap_init_f32(mc_unwrap_f32_t *u, float theta_wrapped_rad);

/* One sample: returns the continuous angle e + 2*pi*n (float).
 * Non-finite input: returns NaN and leaves the state unchanged.
 * Turn counter at INT32_MAX/INT32_MIN and asked to go further: returns NaN
 * and leaves the state unchanged (a fault, never a silent wrap). Interrupt
 * context: yes. */
float mc_unwrap_step_f32(mc_unwrap_f32_t *u, float theta_wrapped_rad);

/* Exact integer turn count n of the last step. Interrupt context: yes. */
static inline int32_t mc_unwrap_turns_f32(const mc_unwrap_f32_t *u)
{
    return u->turns;
}

#endif /* MC_ANGLE_H */
