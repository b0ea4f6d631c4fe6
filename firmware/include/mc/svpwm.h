/*
 * Space-vector PWM by min-max (zero-sequence) injection, float32.
 *
 * Input: the stationary-frame voltage command (v_alpha_V, v_beta_V) in volts
 * (amplitude-invariant alpha/beta, i.e. phase-voltage amplitude) and the
 * measured DC-link voltage v_dc_V. Output: three duty cycles in [0, 1]
 * (fraction of the PWM period the high-side switch of phase a/b/c is on,
 * centre-aligned PWM assumed), so that the average leg voltage is
 * duty * v_dc (referred to the negative DC rail).
 *
 * Method: phase voltages v_x from the inverse Clarke transform, offset
 * v_0 = -(max(v_x) + min(v_x)) / 2, duty_x = 1/2 + (v_x + v_0) / v_dc.
 * Linear range: |v| <= v_dc / sqrt(3) (the inscribed circle of the
 * hexagon); there the line-to-line voltages are reproduced exactly.
 * Beyond it the command is reduced, keeping its angle:
 *   MC_SVPWM_LIMIT_CIRCLE : magnitude clamped to v_dc / sqrt(3);
 *   MC_SVPWM_LIMIT_HEXAGON: magnitude scaled to the hexagon boundary
 *                           (max - min phase spread = v_dc), i.e. the
 *                           largest voltage the inverter can make at that
 *                           angle (up to 2/3 v_dc at the hexagon vertices).
 * `overmodulated` tells that the command was reduced; v_alpha_V/v_beta_V
 * give the voltage actually applied (for observers and anti-windup).
 *
 * Sector convention: sector s (1..6) holds the voltage angle
 * atan2(v_beta, v_alpha) in [(s-1)*60 deg, s*60 deg), angles measured in
 * [0, 360) deg from the alpha (phase a) axis. Sector 1 spans the a-axis to
 * the ab-axis. On an exact boundary either neighbour may be reported (the
 * duties are continuous there). The zero vector reports sector 1.
 *
 * Errors: NaN/Inf in any input -> MC_ERR_NONFINITE; v_dc_V <= 0 (or below
 * FLT_MIN, the smallest normal float) -> MC_ERR_RANGE; *out is then left
 * untouched. A finite command so large that
 * the phase voltages overflow float also gives MC_ERR_RANGE; a `limit`
 * that is not one of the enum values gives MC_ERR_PARAM.
 *
 * Bounded time (at most one sqrt and five divisions), no state;
 * Interrupt context: yes. The common case, a command inside the linear
 * range but its edge (MC_SVPWM_INLINE_SQ), is inline with one division;
 * the others (the limit, the clamp of the duties) take a call.
 */
#ifndef MC_SVPWM_H
#define MC_SVPWM_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "mc/clarke.h"
#include "mc/compiler.h"
#include "mc/status.h"

typedef enum { MC_SVPWM_LIMIT_CIRCLE, MC_SVPWM_LIMIT_HEXAGON } mc_svpwm_limit_t;

typedef struct {
    float duty[3];      /* phases a, b, c, each in [0, 1] */
    uint8_t sector;     /* 1..6, see the convention above */
    bool overmodulated; /* true when the command was reduced */
    float v_alpha_V;    /* voltage actually applied, alpha axis, V */
    float v_beta_V;     /* voltage actually applied, beta axis, V */
} mc_svpwm_out_f32_t;

/* Compute the duties for one PWM period. Interrupt context: yes. */
mc_status_t mc_svpwm_f32(float v_alpha_V, float v_beta_V, float v_dc_V,
                         mc_svpwm_limit_t limit, mc_svpwm_out_f32_t *out);

/* The phase voltages of a command (inverse Clarke) and their extremes. */
typedef struct {
    float v_V[3];       /* phases a, b, c */
    float max_V, min_V; /* the largest and the smallest of them */
} mc_svpwm_phases_t;

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE mc_svpwm_phases_t mc_svpwm_phases_f32(float v_alpha_V,
                                                            float v_beta_V)
{
    mc_svpwm_phases_t p;
    mc_inv_clarke_f32(v_alpha_V, v_beta_V, &p.v_V[0], &p.v_V[1], &p.v_V[2]);
    /* b, c = -alpha/2 +- (sqrt(3)/2) beta: the larger of the two takes +|.|,
     * the smaller -|.|, bit for bit (the same sums; rounding is monotonic),
     * so only a is compared. A NaN b, c leaves a (no compare holds). */
    const float neg_half_alpha = -(0.5f * v_alpha_V);
    const float abs_beta_term = fabsf(MC_SQRT3_BY_2_F * v_beta_V);
    const float bc_max = neg_half_alpha + abs_beta_term;
    const float bc_min = neg_half_alpha - abs_beta_term;
    p.max_V = (bc_max > v_alpha_V) ? bc_max : v_alpha_V;
    p.min_V = (bc_min < v_alpha_V) ? bc_min : v_alpha_V;
    return p;
}

/* duty_x = 1/2 + (v_x + v_0) / v_dc, v_0 = -(max + min) / 2, on the
 * phases p and inv_v_dc = 1 / v_dc; `clamp`: into [0, 1] against the
 * float noise of a full modulation (a constant: the common case needs
 * none). Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_svpwm_duties_f32(const mc_svpwm_phases_t *p,
                                               float inv_v_dc, bool clamp,
                                               float duty[3])
{
    const float v_offset_V = -0.5f * (p->max_V + p->min_V);
#pragma GCC unroll 3
    for (uint32_t i = 0u; i < 3u; i++) {
        float d = 0.5f + (p->v_V[i] + v_offset_V) * inv_v_dc;
        if (clamp) {
            d = (d < 0.0f) ? 0.0f : ((d > 1.0f) ? 1.0f : d);
        }
        duty[i] = d;
    }
}

/* (|v| / v_dc)^2 below which the inline modulator works: (1 - 1e-4) / 3,
 * i.e. |v| up to 0.99995 v_dc/sqrt(3), the whole linear range but its
 * edge. The margin (5e-5) is far above the rounding of the circle test
 * and of the duties (a few 1e-7): no command below it is limited, no
 * duty leaves [0, 1]. */
#define MC_SVPWM_INLINE_SQ 0.3333f

/* The modulator for the other commands (out of line: rare), at or beyond
 * the edge of the linear range, or non-finite: the limit, the duties
 * clamped against float noise. For any command what
 * mc_svpwm_unchecked_f32 makes (same preconditions), with sector 0.
 * Returned by value, so that the caller's output can stay in registers.
 * Interrupt context: yes. */
mc_svpwm_out_f32_t mc_svpwm_edge_f32(float v_alpha_V, float v_beta_V,
                                     float v_dc_V, mc_svpwm_limit_t limit);

/* The same as mc_svpwm_f32 without the argument checks and the sector
 * (out->sector is not written), for an ISR path that checks the bus
 * voltage before (finite, >= FLT_MIN) and the duties after: a non-finite
 * or overflowing command gives non-finite duties there instead of an
 * error here. Returns true for a command strictly inside the linear range
 * (the inline case: the command and the duties are finite, nothing was
 * limited), false for the others (mc_svpwm_edge_f32). Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE bool mc_svpwm_unchecked_f32(float v_alpha_V,
                                                  float v_beta_V, float v_dc_V,
                                                  mc_svpwm_limit_t limit,
                                                  mc_svpwm_out_f32_t *out)
{
    const float inv_v_dc = 1.0f / v_dc_V; /* guarded: v_dc >= FLT_MIN */
    /* |v| / v_dc: no overflow of |v|^2 (a huge ratio is Inf, NaN stays
     * NaN: both fail the test), an underflow only where |v| << v_dc. */
    const float a_n = v_alpha_V * inv_v_dc;
    const float b_n = v_beta_V * inv_v_dc;
    if (!(a_n * a_n + b_n * b_n < MC_SVPWM_INLINE_SQ)) {
        const mc_svpwm_out_f32_t o =
            mc_svpwm_edge_f32(v_alpha_V, v_beta_V, v_dc_V, limit);
        for (uint32_t i = 0u; i < 3u; i++) {
            out->duty[i] = o.duty[i];
        }
        out->overmodulated = o.overmodulated;
        out->v_alpha_V = o.v_alpha_V;
        out->v_beta_V = o.v_beta_V;
        return false;
    }
    /* Inside the circle and the hexagon (either limit): unchanged; the
     * phase spread (<= sqrt(3) |v| < v_dc) keeps every duty in (0, 1). */
    const mc_svpwm_phases_t p = mc_svpwm_phases_f32(v_alpha_V, v_beta_V);
    mc_svpwm_duties_f32(&p, inv_v_dc, false, out->duty);
    out->overmodulated = false;
    out->v_alpha_V = v_alpha_V;
    out->v_beta_V = v_beta_V;
    return true;
}

#endif /* MC_SVPWM_H */
