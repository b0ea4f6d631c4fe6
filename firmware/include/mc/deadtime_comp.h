/*
 * Inverter dead-time and device-drop compensation (voltage feed-forward on
 * the duties).
 *
 * Over a PWM period a phase leg with dead time t_d and device drops v_f
 * delivers, to the period average, d v_dc - s(i) (t_d f_pwm v_dc + v_f)
 * with s(i) the sign of the phase current (the diode that conducts during
 * the dead time sets the terminal). The compensation adds the same
 * amount to the duty,
 *   d_x <- d_x + s_b(i_x) (t_d f_pwm + v_f / v_dc),
 *   s_b(i) = clamp(i / band, -1, 1),
 * with a linear band around zero current (inside it the current's ripple
 * changes sign within the period and the error shrinks; a hard sign
 * would chatter on the sampled current's noise there). i_x is the current
 * sampled at the start of the period the duties are computed in: one
 * period older than the period they apply to.
 *
 * The voltage the firmware reports as applied (telemetry v_alpha_V,
 * v_beta_V, the observers' mc/delay_comp.h history) stays the commanded
 * one: with the compensation the average terminal voltage is that
 * command; without it (disabled, or no dead time configured) the command
 * is what the drive believes it applies, as before.
 *
 * Units: s, V, A, Hz; duties in [0, 1].
 */
#ifndef MC_DEADTIME_COMP_H
#define MC_DEADTIME_COMP_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/compiler.h"
#include "mc/status.h"

/* Largest dead-time error per period, as a duty (t_d f + v_f / v_dc_min):
 * beyond it the inverter's dead time is not a small correction. */
#define MC_DEADTIME_DUTY_MAX 0.1f

/* The configuration block "deadtime". dead_time_s and device_drop_V are
 * the inverter's (a board property; the bench takes them from the
 * plant). */
typedef struct {
    float dead_time_s;    /* t_d, >= 0 */
    float device_drop_V;  /* v_f, >= 0 */
    float current_band_A; /* linear band of s_b, > 0 */
    bool compensation;    /* on: compensate when t_d or v_f > 0 */
} mc_deadtime_config_t;

typedef struct {
    bool active;          /* compensation on and something to compensate */
    float duty_time;      /* t_d f_pwm */
    float drop_V;         /* v_f */
    float inv_band_per_A; /* 1 / band */
} mc_deadtime_comp_f32_t;

/* Validate (finite; t_d, v_f >= 0, band > 0; t_d / Ts + v_f / v_dc_min_V
 * <= MC_DEADTIME_DUTY_MAX with v_dc_min_V the lowest bus the drive runs
 * on, > 0 when v_f > 0) and design. MC_ERR_NONFINITE / MC_ERR_PARAM (*dc
 * untouched). Interrupt context: no. */
mc_status_t mc_deadtime_comp_init_f32(mc_deadtime_comp_f32_t *dc,
                                      const mc_deadtime_config_t *c, float Ts_s,
                                      float v_dc_min_V);

/* Add the compensation to duty[3] for the phase currents i_abc_A on the
 * bus v_dc_V (> 0: checked by the modulator). A duty pushed outside
 * [0, 1] is limited there and reported (true): the command was not fully
 * applied. Inactive: duties untouched, false. Interrupt context: yes. */
/* The compensation proper (mc_deadtime_comp_apply_f32 on an active
 * block). Interrupt context: yes. */
bool mc_deadtime_comp_apply_active_f32(const mc_deadtime_comp_f32_t *dc,
                                       float i_a_A, float i_b_A, float i_c_A,
                                       float v_dc_V, float duty[3]);

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool
mc_deadtime_comp_apply_f32(const mc_deadtime_comp_f32_t *dc,
                           const float i_abc_A[3], float v_dc_V, float duty[3])
{
    if (MC_LIKELY(!dc->active)) { /* off by default */
        return false;
    }
    /* the currents by value, the duties through a local: the caller's
     * stay in registers on the common path (their addresses are not
     * taken) */
    float d[3] = { duty[0], duty[1], duty[2] };
    const bool limited = mc_deadtime_comp_apply_active_f32(
        dc, i_abc_A[0], i_abc_A[1], i_abc_A[2], v_dc_V, d);
    for (uint32_t k = 0u; k < 3u; ++k) {
        duty[k] = d[k];
    }
    return limited;
}

#endif /* MC_DEADTIME_COMP_H */
