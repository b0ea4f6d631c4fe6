/*
 * Space-vector PWM by min-max (zero-sequence) injection, Q31 fixed point.
 * Same method, sector convention and overmodulation policy as mc_svpwm_f32
 * (mc/svpwm.h), whose limit enum this header reuses.
 *
 * Scaling (integer only, for MCUs without an FPU):
 *   v_alpha_pu, v_beta_pu: stationary-frame command (amplitude invariant) in
 *     Q31 per-unit of the DC-link voltage, v / v_dc. The linear range is
 *     |v| <= 1/sqrt(3) (0.577), the hexagon reaches 2/3 at its vertices, so
 *     the Q31 range [-1, 1) covers every meaningful command. The caller
 *     normalises by v_dc (e.g. with a reciprocal updated in the slow loop).
 *   duty[k]: Q31 fraction of the PWM period, [0, INT32_MAX]; INT32_MAX
 *     stands for 100 % (1 - 2^-31). Timer compare value:
 *     (int64_t)duty * period >> 31.
 *   v_alpha_pu, v_beta_pu (out): the command actually applied, Q31 of v_dc.
 *
 * Method: phase voltages v_x by inverse Clarke (kept in int64, they exceed
 * full scale for large commands), duty_x = 1/2 + v_x - (max + min) / 2.
 *   MC_SVPWM_LIMIT_CIRCLE : if v_alpha^2 + v_beta^2 > 1/3 (exact integer
 *     comparison) the command is scaled to magnitude 1/sqrt(3);
 *   MC_SVPWM_LIMIT_HEXAGON: if max - min > 1 the command is scaled by
 *     1 / (max - min), onto the hexagon boundary.
 * `overmodulated` is true when the command was reduced.
 * Sector: 1..6, sector s holds atan2(v_beta, v_alpha) in [(s-1)60, s 60) deg;
 * on a boundary (within rounding) either neighbour may be reported; the zero
 * vector reports 1.
 *
 * Accuracy: within the linear range each duty is within 2.5 LSB of the exact
 * value for the given Q31 inputs (phase voltages within 1 LSB each from the
 * inverse-Clarke constant and rounding; max and min move by at most as much;
 * one final rounding). A reduced command is within a few LSB of the exact
 * reduction (one reciprocal, one product per component); the duties of the
 * largest and smallest phase are then 1 and 0 up to that rounding, and any
 * rounding excess beyond [0, 1] saturates (0 or INT32_MAX), never wraps.
 *
 * Errors: an invalid `limit` gives MC_ERR_PARAM and leaves *out untouched.
 * Bounded time: at most one 32-step integer square root and one 64-bit
 * division, no state. Interrupt context: yes.
 */
#ifndef MC_SVPWM_Q31_H
#define MC_SVPWM_Q31_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/q31.h"
#include "mc/status.h"
#include "mc/svpwm.h"

typedef struct {
    mc_q31_t duty[3];    /* phases a, b, c, Q31 in [0, INT32_MAX] */
    uint8_t sector;      /* 1..6, see the convention above */
    bool overmodulated;  /* true when the command was reduced */
    mc_q31_t v_alpha_pu; /* command actually applied, alpha, Q31 of v_dc */
    mc_q31_t v_beta_pu;  /* command actually applied, beta, Q31 of v_dc */
} mc_svpwm_out_q31_t;

/* Compute the duties for one PWM period. Interrupt context: yes. */
mc_status_t mc_svpwm_q31(mc_q31_t v_alpha_pu, mc_q31_t v_beta_pu,
                         mc_svpwm_limit_t limit, mc_svpwm_out_q31_t *out);

#endif /* MC_SVPWM_Q31_H */
