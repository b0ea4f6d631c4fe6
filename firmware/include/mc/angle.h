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

#include <stdint.h>

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

/*
 * Wrap theta to (-pi, pi]: returns theta - 2*pi*k for the integer k that
 * puts it there. Inputs already inside [-pi, pi] are returned bit-exactly.
 * The result r satisfies -MC_PI_F < r <= MC_PI_F (a value that would round
 * to -MC_PI_F is returned as +MC_PI_F, the same angle).
 * |theta| > MC_ANGLE_MAX_ABS_RAD or non-finite: returns NaN.
 * Interrupt context: yes.
 */
float mc_wrap_pi_f32(float theta_rad);

/* Signed shortest angle from b to a: wrap(a - b) in (-pi, pi].
 * Same range rules as mc_wrap_pi_f32 (applied to a - b). Interrupt context:
 * yes. */
static inline float mc_angle_diff_f32(float a_rad, float b_rad)
{
    return mc_wrap_pi_f32(a_rad - b_rad);
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
