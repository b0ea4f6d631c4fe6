/*
 * Computation / PWM delay of the drive: the two consequences of "duties
 * computed in ISR k take effect in the next PWM period" for a sensorless
 * observer-based controller, float32.
 *
 * Timing parameter d (delay_periods, the drive's timing record
 * mc/timing.h, which takes it from the HAL backend, hal/pwm.h): the voltage
 * commanded in ISR k (which runs right after the current sample at t_k) is
 * applied over the interval [t_k + (d - 1/2) Ts, t_k + (d + 1/2) Ts], i.e.
 * centred d periods after the sample. Valid range 1/2 <= d <= 3/2:
 *   d = 1.5  duties latched a full period after the sample (the textbook
 *            "1.5 Ts" delay: one update event per period, at the sample);
 *   d = 1.0  duties latched half a period after the sample (an update
 *            event at the opposite end of the carrier);
 *   d = 0.5  no computation delay (duties apply right after the sample).
 *
 * 1) Voltage angle advance (switchable). The dq voltage is meant for the
 *    rotor angle at which it acts; over the applied interval the rotor turns
 *    by omega_e Ts, and the interval's mean rotation is that of its centre
 *    (the averaged rotor-frame voltage is the centre's times
 *    sinc(omega_e Ts / 2) ~ 1). So the inverse Park uses
 *      theta_v = theta_e_hat + omega_e_hat * d * Ts.
 *    Disabled: theta_v = theta_e_hat (its closed-loop effect is measured
 *    later on the bench). The advance's sine and cosine are held between
 *    updates (mc_delay_comp_track_f32): the drive updates them on its slow
 *    tick, so the advance lags the speed by at most a slow period, an
 *    angle error of n_p |d omega_m| d Ts (e.g. 2.7e-5 rad for a change of
 *    1 rad/s over that period with the paper 001 motor at 20 kHz, d =
 *    1.5), and the fast ISR between ticks only rotates.
 * 2) Voltage applied over the last sample interval [t_{k-1}, t_k], needed by
 *    the flux observer (mc/flux_observer.h): commands v_j hold on
 *    [t_j + (d - 1/2) Ts, t_{j+1} + (d - 1/2) Ts], so with w = d - 1/2
 *      v_bar_k = w * v_{k-2} + (1 - w) * v_{k-1}.
 *    (HAL timing d = 1: the mean of the last two commands; centre-aligned
 *    PWM spends equal volt-seconds in each half period.) Record the voltage
 *    the inverter really produces (after the modulator's limit), in the
 *    stationary alpha-beta frame.
 *
 * Units: rad (electrical), rad/s (electrical), V, s.
 * Non-finite inputs: the angle function returns NaN (the caller's fault
 * check sees it); the voltage history rejects them (MC_ERR_NONFINITE,
 * state untouched).
 */
#ifndef MC_DELAY_COMP_H
#define MC_DELAY_COMP_H

#include <math.h>
#include <stdbool.h>

#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/park.h"
#include "mc/status.h"

/* Valid sample-to-apply delays d, periods. */
#define MC_DELAY_PERIODS_MIN 0.5f
#define MC_DELAY_PERIODS_MAX 1.5f

typedef struct {
    float advance_s; /* d * Ts */
    bool enabled;
    /* sine and cosine of the advance omega_e d Ts at the last
     * mc_delay_comp_track_f32 */
    float sin_advance, cos_advance;
} mc_delay_comp_f32_t;

/* Validate Ts_s > 0 and 0.5 <= delay_periods <= 1.5 (finite), store
 * d * Ts, hold a zero advance. MC_ERR_NONFINITE / MC_ERR_PARAM (*dc
 * untouched). Interrupt context: no. */
mc_status_t mc_delay_comp_init_f32(mc_delay_comp_f32_t *dc, float Ts_s,
                                   float delay_periods, bool enabled);

/* Switch the advance on or off (the held advance: the last
 * mc_delay_comp_track_f32's). Interrupt context: yes. */
static inline void mc_delay_comp_enable_f32(mc_delay_comp_f32_t *dc,
                                            bool enabled)
{
    dc->enabled = enabled;
}

/* Hold the sine and cosine of the advance omega_e_rad_s * d * Ts (used
 * only while enabled: mc_delay_comp_sincos_f32): the short series of
 * mc_sincos_small_f32 up to MC_SINCOS_SERIES_MAX_RAD (3300 rad/s electrical at
 * 20 kHz with d = 1.5), beyond it mc_sincos_f32. NaN for a non-finite speed.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_delay_comp_track_f32(mc_delay_comp_f32_t *dc,
                                                   float omega_e_rad_s)
{
    const float delta = omega_e_rad_s * dc->advance_s;
    float s;
    float c;
    if (!mc_sincos_small_f32(delta, &s, &c)) {
        mc_sincos_f32(delta, &s, &c);
    }
    dc->sin_advance = s;
    dc->cos_advance = c;
}

/* Sine and cosine of the angle for the inverse Park of the voltage computed
 * now, theta_v = theta_e + the held advance (theta_e if disabled), given
 * s_e, c_e = sin, cos of theta_e: (s_e, c_e) rotated by the advance. NaN
 * for a non-finite input or advance when enabled. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void
mc_delay_comp_sincos_f32(const mc_delay_comp_f32_t *dc, float s_e, float c_e,
                         float *s_v, float *c_v)
{
    if (MC_UNLIKELY(!dc->enabled)) { /* on by default */
        *s_v = s_e;
        *c_v = c_e;
        return;
    }
    /* the rotation by the advance of the vector (c_e, s_e) */
    mc_inv_park_f32(c_e, s_e, dc->sin_advance, dc->cos_advance, c_v, s_v);
}

typedef struct {
    float w_older;      /* d - 1/2, weight of v_{k-2} */
    float w_newer;      /* 1 - w_older, weight of v_{k-1} */
    float v_older_V[2]; /* v_{k-2} (alpha, beta) */
    float v_newer_V[2]; /* v_{k-1} (alpha, beta) */
} mc_applied_voltage_f32_t;

/* Validate 0.5 <= delay_periods <= 1.5 (finite) and reset the history to
 * zero volts. MC_ERR_NONFINITE / MC_ERR_PARAM (*av untouched).
 * Interrupt context: no. */
mc_status_t mc_applied_voltage_init_f32(mc_applied_voltage_f32_t *av,
                                        float delay_periods);

/* Fill the history with one voltage (e.g. 0 V with the outputs off).
 * Non-finite: MC_ERR_NONFINITE, state untouched. Interrupt context: yes. */
mc_status_t mc_applied_voltage_reset_f32(mc_applied_voltage_f32_t *av,
                                         float v_alpha_V, float v_beta_V);

/* Mean voltage applied over [t_{k-1}, t_k]; call in ISR k BEFORE pushing
 * this ISR's command. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void
mc_applied_voltage_last_f32(const mc_applied_voltage_f32_t *av,
                            float *v_alpha_V, float *v_beta_V)
{
    const float w_old = av->w_older;
    const float w_new = av->w_newer;
    *v_alpha_V = w_old * av->v_older_V[0] + w_new * av->v_newer_V[0];
    *v_beta_V = w_old * av->v_older_V[1] + w_new * av->v_newer_V[1];
}

/* Record the voltage commanded in ISR k (as the inverter will produce it),
 * finite: the caller has checked it. Interrupt context: yes. */
static inline void
mc_applied_voltage_push_unchecked_f32(mc_applied_voltage_f32_t *av,
                                      float v_alpha_V, float v_beta_V)
{
    av->v_older_V[0] = av->v_newer_V[0];
    av->v_older_V[1] = av->v_newer_V[1];
    av->v_newer_V[0] = v_alpha_V;
    av->v_newer_V[1] = v_beta_V;
}

/* The same for any value: non-finite gives MC_ERR_NONFINITE, state
 * untouched. Interrupt context: yes. */
static inline mc_status_t
mc_applied_voltage_push_f32(mc_applied_voltage_f32_t *av, float v_alpha_V,
                            float v_beta_V)
{
    if (!isfinite(v_alpha_V) || !isfinite(v_beta_V)) {
        return MC_ERR_NONFINITE;
    }
    mc_applied_voltage_push_unchecked_f32(av, v_alpha_V, v_beta_V);
    return MC_OK;
}

#endif /* MC_DELAY_COMP_H */
