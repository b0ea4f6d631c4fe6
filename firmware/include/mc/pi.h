/*
 * Discrete PI controller with output limits and anti-windup, float32.
 *
 * Units: error in unit E, output in unit U (e.g. A -> V for a current loop,
 * rad/s -> A for a speed loop); kp in U/E, ki_per_s in U/(E*s), Ts_s in s.
 *
 * Discretisation (backward-Euler integrator, integrate then output):
 *   I_k = I_{k-1} + ki*Ts*e_k,   u_k = kp*e_k + I_k
 * so for a constant error e from I_{-1} = 0 and no saturation:
 *   u_k = kp*e + ki*Ts*e*(k+1).
 *
 * Anti-windup: conditional integration ("clamping") plus an integrator bound.
 *  1. If the unclamped output would exceed a limit AND the error pushes
 *     further into that limit, the integrator advances only up to the value
 *     that puts the output on the limit (out_max - kp*e resp.
 *     out_min - kp*e), and is never moved backwards by this rule. So the
 *     output does reach the limit, and the integrator holds no more than
 *     the limit needs.
 *  2. The integrator state is always kept inside [out_min, out_max].
 *  3. The output is clamped to [out_min, out_max].
 * Why this scheme: no extra tuning gain (back-calculation needs a tracking
 * time constant), a handful of compares, valid when the limits change every
 * sample (current loops with a DC-link-dependent voltage limit), and a hard
 * recovery bound: because the integrator never exceeds the limit, the first
 * sample whose error has the opposite sign (e < 0 after sitting at out_max,
 * e > 0 after out_min) already brings the output strictly inside the limits
 * (requires kp + ki*Ts > 0, guaranteed by init).
 *
 * Non-finite error: step returns NaN and leaves the state unchanged (the
 * caller's fault handling sees it); it is never mapped to a finite value.
 * The unchecked steps (ISR paths whose caller checks the result) skip the
 * test but keep the last point: a non-finite error gives a NaN output.
 */
#ifndef MC_PI_H
#define MC_PI_H

#include <math.h>
#include <stdbool.h>

#include "mc/compiler.h"
#include "mc/status.h"

typedef struct {
    float kp;         /* proportional gain, U/E */
    float ki_Ts;      /* integral gain times sample time, U/E per sample */
    float out_min;    /* lower output limit, U */
    float out_max;    /* upper output limit, U */
    float integrator; /* integrator state I, U */
} mc_pi_f32_t;

/* Set gains and limits, integrator to 0 clamped into the limits.
 * Rejects (MC_ERR_NONFINITE / MC_ERR_PARAM, *pi untouched): non-finite
 * argument, kp < 0, ki_per_s < 0, kp == ki_per_s*Ts_s == 0, Ts_s <= 0,
 * out_min >= out_max, ki_per_s*Ts_s not finite. Interrupt context: no by intent
 * (configuration), though it has no side effects beyond *pi. */
mc_status_t mc_pi_init_f32(mc_pi_f32_t *pi, float kp, float ki_per_s,
                           float Ts_s, float out_min, float out_max);

/* Set the integrator (bumpless start: pass the output you want now with
 * zero error). Clamped into [out_min, out_max] by the next step; a
 * non-finite value makes every later step return NaN until the next reset.
 * Interrupt context: yes. */
void mc_pi_reset_f32(mc_pi_f32_t *pi, float integrator);

/* Change the output limits (may be called every sample). Rejects non-finite
 * limits or out_min >= out_max (state untouched). Interrupt context: yes. */
mc_status_t mc_pi_set_limits_f32(mc_pi_f32_t *pi, float out_min, float out_max);

/* The same without the checks, for an ISR path whose limits are finite and
 * ordered by construction; a NaN limit leaves the output unlimited, so such
 * a path checks what it computes from the output. Interrupt context: yes. */
static inline void mc_pi_set_limits_unchecked_f32(mc_pi_f32_t *pi,
                                                  float out_min, float out_max)
{
    pi->out_min = out_min;
    pi->out_max = out_max;
}

/* A sample before any limit: *p_term = kp error, *integ = integrator +
 * ki_Ts error; returns u = p_term + integ. Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_pi_unlimited_f32(const mc_pi_f32_t *pi,
                                                float error, float *p_term,
                                                float *integ)
{
    *p_term = pi->kp * error;
    *integ = pi->integrator + pi->ki_Ts * error;
    return *p_term + *integ;
}

/* The uncommon case of the steps below: the output or the integrator
 * not strictly inside [out_min, out_max] (or a non-finite error), with
 * the step's p_term = kp error, integ = integrator + ki_Ts error and u =
 * p_term + integ: conditional integration, the integrator's bound and the
 * output limit (mc_pi_step_within_unchecked_f32); on a sample inside the
 * limits it changes nothing (returns u, stores integ). Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE float
mc_pi_limit_unchecked_f32(mc_pi_f32_t *pi, float error, float p_term,
                          float integ, float u, float out_min, float out_max,
                          bool *at_limit)
{
    *at_limit = false;
    /* 1. conditional integration: stop where the output meets the limit */
    if (error > 0.0f && u > out_max) {
        const float to_limit = out_max - p_term;
        integ = (to_limit > pi->integrator) ? to_limit : pi->integrator;
    } else if (error < 0.0f && u < out_min) {
        const float to_limit = out_min - p_term;
        integ = (to_limit < pi->integrator) ? to_limit : pi->integrator;
    }
    /* 2. integrator bound (explicit compares so that NaN propagates) */
    if (integ > out_max) {
        integ = out_max;
    } else if (integ < out_min) {
        integ = out_min;
    }
    pi->integrator = integ;
    u = p_term + integ;
    /* 3. output limit (u already on a limit stays there: the same u) */
    if (u >= out_max) {
        u = out_max;
        *at_limit = true;
    } else if (u <= out_min) {
        u = out_min;
        *at_limit = true;
    }
    /* An infinite error would end on a limit, finite: error - error is +0
     * for a finite error (u - +0 is u, bit for bit, -0 included) and NaN
     * for NaN or an infinity, which so reaches the output. */
    return u - (error - error);
}

/* One controller sample on the limits [out_min, out_max] given here (a
 * caller that recomputes them every sample passes them instead of storing
 * them in *pi); returns the limited output u_k, *at_limit tells that it
 * sits on a limit (u_k <= out_min or u_k >= out_max). No finiteness
 * checks, for an ISR path that checks what it computes from the output: a
 * NaN or infinite error gives a NaN output (a NaN error also a NaN
 * integrator until the next reset); NaN limits leave the output
 * unlimited. Interrupt context: yes, bounded time, no division. */
MC_STATIC_FORCEINLINE float
mc_pi_step_within_unchecked_f32(mc_pi_f32_t *pi, float error, float out_min,
                                float out_max, bool *at_limit)
{
    float p_term;
    float integ;
    const float u = mc_pi_unlimited_f32(pi, error, &p_term, &integ);
    if (u > out_min && u < out_max && integ >= out_min && integ <= out_max) {
        /* The common case: output strictly and integrator inside the
         * limits, where mc_pi_limit_unchecked_f32 changes nothing. (The
         * error is finite here: an infinite one makes u infinite or NaN.) */
        *at_limit = false;
        pi->integrator = integ;
        return u;
    }
    return mc_pi_limit_unchecked_f32(pi, error, p_term, integ, u, out_min,
                                     out_max, at_limit);
}

/* mc_pi_step_within_unchecked_f32 on the limits [centre - half,
 * centre + half] (half > 0), its common case tested as |u - centre| <
 * half and |integrator - centre| <= half: two comparisons instead of
 * four, the limits formed only when the test fails. The result differs
 * from mc_pi_step_within_unchecked_f32's only where the rounding of
 * centre -+ half puts u or the integrator on the other side of a limit
 * (by at most an ulp of the limit). Interrupt context: yes. */
MC_STATIC_FORCEINLINE float
mc_pi_step_centred_unchecked_f32(mc_pi_f32_t *pi, float error, float centre,
                                 float half, bool *at_limit)
{
    float p_term;
    float integ;
    const float u = mc_pi_unlimited_f32(pi, error, &p_term, &integ);
    if (MC_LIKELY(fabsf(u - centre) < half && fabsf(integ - centre) <= half)) {
        pi->integrator = integ;
        *at_limit = false;
        return u;
    }
    /* (a sample this test puts outside by a rounding of centre -+ half is
     * inside for the limit stage, which then changes nothing) */
    return mc_pi_limit_unchecked_f32(pi, error, p_term, integ, u, centre - half,
                                     centre + half, at_limit);
}

/* The same on the limits stored in *pi. Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_pi_step_unchecked_f32(mc_pi_f32_t *pi,
                                                     float error)
{
    bool at_limit;
    return mc_pi_step_within_unchecked_f32(pi, error, pi->out_min, pi->out_max,
                                           &at_limit);
}

/* One controller sample; returns the limited output u_k, or NaN for a
 * non-finite error (state untouched). Interrupt context: yes, bounded
 * time, no division. */
static inline float mc_pi_step_f32(mc_pi_f32_t *pi, float error)
{
    if (!isfinite(error)) {
        return NAN;
    }
    return mc_pi_step_unchecked_f32(pi, error);
}

#endif /* MC_PI_H */
