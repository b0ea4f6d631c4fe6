/*
 * Discrete PI controller with output limits and anti-windup, Q31 fixed point.
 * Same discretisation and anti-windup scheme as mc_pi_f32 (mc/pi.h):
 *   I_k = I_{k-1} + ki*Ts*e_k,   u_k = kp*e_k + I_k   (backward Euler)
 *   1. if kp*e + I_{k-1} + ki*Ts*e is beyond a limit and e pushes further
 *      into it, the integrator advances only up to the value that puts the
 *      output on the limit (out_max - kp*e resp. out_min - kp*e) and is never
 *      moved backwards by this rule;
 *   2. the integrator is kept inside [out_min, out_max];
 *   3. the output is clamped to [out_min, out_max].
 * Recovery bound: the first sample whose error has the opposite sign brings
 * the output strictly inside the limits, provided (kp + ki*Ts)*|e| is at
 * least one LSB of the Q31 output (smaller changes round away).
 *
 * Scaling (integer only, for MCUs without an FPU):
 *   error: Q31 per-unit of an error full scale E_fs (e.g. A);
 *   output, out_min, out_max, reset value: Q31 per-unit of an output full
 *   scale U_fs (e.g. V);
 *   gains: dimensionless kp * E_fs / U_fs and ki * Ts * E_fs / U_fs, each
 *   given as gain = frac * 2^shift / 2^31 with frac in [0, INT32_MAX] (Q31)
 *   and shift in [0, MC_PI_Q31_MAX_SHIFT], i.e. below 2^14 with 31
 *   significant bits. Convert at configuration time, e.g. on the host.
 * The integrator and the sum kp*e + I are held in int64_t with
 * MC_PI_Q31_GUARD_BITS extra fractional bits (Q47); the products are exact
 * and each is rounded once to Q47, the output once to Q31, so a step
 * response matches the exact discrete solution for the quantised gains to
 * 1/2 LSB + (k + 2) 2^-17 LSB at sample k (k = 0 first). Nothing wraps:
 * each gain product is below 2^61 in magnitude (|e| <= 2^31, frac < 2^31, shift
 * <= 14, moved down to Q47), the integrator below 2^47, so every sum stays
 * below 2^63; the output is within the limits.
 */
#ifndef MC_PI_Q31_H
#define MC_PI_Q31_H

#include <stdint.h>

#include "mc/q31.h"
#include "mc/status.h"

#define MC_PI_Q31_GUARD_BITS 16U /* integrator: Q31 + 16 fractional bits */
#define MC_PI_Q31_MAX_SHIFT  14U /* largest gain exponent */

typedef struct {
    mc_q31_t kp_frac; /* kp = kp_frac * 2^kp_shift, Q31 */
    uint8_t kp_shift;
    mc_q31_t ki_ts_frac; /* ki*Ts = ki_ts_frac * 2^ki_ts_shift, Q31 */
    uint8_t ki_ts_shift;
    int64_t out_min_q47;    /* lower output limit, Q47 */
    int64_t out_max_q47;    /* upper output limit, Q47 */
    int64_t integrator_q47; /* integrator state I, Q47 (Q31 * 2^16) */
} mc_pi_q31_t;

/* Set gains and limits, integrator to 0 clamped into the limits.
 * Rejects with MC_ERR_PARAM (*pi untouched): a negative frac, a shift above
 * MC_PI_Q31_MAX_SHIFT, both gains zero, out_min >= out_max.
 * Configuration (no side effects beyond *pi). Interrupt context: no. */
mc_status_t mc_pi_init_q31(mc_pi_q31_t *pi, mc_q31_t kp_frac, uint8_t kp_shift,
                           mc_q31_t ki_ts_frac, uint8_t ki_ts_shift,
                           mc_q31_t out_min, mc_q31_t out_max);

/* Set the integrator (bumpless start: the output wanted now at zero error),
 * Q31 of U_fs; clamped into the limits by the next step.
 * Interrupt context: yes. */
void mc_pi_reset_q31(mc_pi_q31_t *pi, mc_q31_t integrator);

/* Change the output limits (may be called every sample). Rejects
 * out_min >= out_max with MC_ERR_PARAM (state untouched).
 * Interrupt context: yes. */
mc_status_t mc_pi_set_limits_q31(mc_pi_q31_t *pi, mc_q31_t out_min,
                                 mc_q31_t out_max);

/* round(x * frac * 2^shift / 2^31) in Q47, shift <= 14: the Q62 product
 * |x * frac| <= 2^62 is moved to Q47 by a right shift of 15 - shift >= 1.
 * Interrupt context: yes. */
static inline int64_t mc_pi_gain_q47(mc_q31_t x, mc_q31_t frac, uint8_t shift)
{
    const int64_t product_q62 = (int64_t)x * frac;
    return mc_round_shift_q63(product_q62,
                              31U - MC_PI_Q31_GUARD_BITS - (unsigned)shift);
}

/* x limited to [lo, hi] (lo <= hi). Interrupt context: yes. */
static inline int64_t mc_pi_clamp_q31(int64_t x, int64_t lo, int64_t hi)
{
    return x > hi ? hi : (x < lo ? lo : x);
}

/* One controller sample; returns the limited output u_k, Q31 of U_fs.
 * Interrupt context: yes (bounded time, no division). */
static inline mc_q31_t mc_pi_step_q31(mc_pi_q31_t *pi, mc_q31_t error)
{
    const int64_t p_term = mc_pi_gain_q47(error, pi->kp_frac, pi->kp_shift);
    int64_t integ = pi->integrator_q47 +
                    mc_pi_gain_q47(error, pi->ki_ts_frac, pi->ki_ts_shift);
    /* 1. conditional integration: stop where the output meets the limit */
    if (error > 0 && p_term + integ > pi->out_max_q47) {
        const int64_t to_limit = pi->out_max_q47 - p_term;
        integ = to_limit > pi->integrator_q47 ? to_limit : pi->integrator_q47;
    } else if (error < 0 && p_term + integ < pi->out_min_q47) {
        const int64_t to_limit = pi->out_min_q47 - p_term;
        integ = to_limit < pi->integrator_q47 ? to_limit : pi->integrator_q47;
    }
    integ = mc_pi_clamp_q31(integ, pi->out_min_q47, pi->out_max_q47); /* 2. */
    pi->integrator_q47 = integ;
    const int64_t u = mc_pi_clamp_q31(p_term + integ, pi->out_min_q47,
                                      pi->out_max_q47); /* 3. */
    /* limits are multiples of 2^16 in Q47, so rounding stays inside them */
    return (mc_q31_t)mc_round_shift_q63(u, MC_PI_Q31_GUARD_BITS);
}

#endif /* MC_PI_Q31_H */
