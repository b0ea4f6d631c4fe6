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
 * Bounded time (at most one sqrt and three divisions), no state;
 * Interrupt context: yes.
 */
#ifndef MC_SVPWM_H
#define MC_SVPWM_H

#include <stdbool.h>
#include <stdint.h>

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

/* The same without the argument checks and the sector (out->sector is not
 * written), for an ISR path that checks the bus voltage before (finite,
 * >= FLT_MIN) and the duties after: a non-finite or overflowing command
 * gives non-finite duties there instead of an error here. Interrupt
 * context: yes. */
void mc_svpwm_unchecked_f32(float v_alpha_V, float v_beta_V, float v_dc_V,
                            mc_svpwm_limit_t limit, mc_svpwm_out_f32_t *out);

#endif /* MC_SVPWM_H */
