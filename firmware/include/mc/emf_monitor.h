/*
 * Back-EMF monitor: the plausibility check of an angle/speed estimate
 * against the machine's voltage equation, for the estimators' supervision
 * (encoder slip or freeze, sensorless loss of lock).
 *
 * Measured back-EMF over the sample interval [t_{k-1}, t_k], stationary
 * frame, non-salient model (L = Lq; the same relation the alignment uses,
 * mc/align.h):
 *   e_meas = v_bar - R (i_k + i_{k-1}) / 2 - L (i_k - i_{k-1}) / Ts
 * with v_bar the mean voltage applied over the interval (mc/delay_comp.h).
 * Predicted from the estimate (angle theta_e at t_k, electrical speed
 * omega_e), at the middle of the interval:
 *   e_pred = psi omega_e [-sin(theta_mid); cos(theta_mid)],
 *   theta_mid = theta_e - delta,  delta = omega_e Ts / 2,
 * from the sine and cosine of theta_e the fast ISR already has (its Park
 * transform), rotated back by delta to first order: sin(theta - delta) =
 * s - delta c, cos(theta - delta) = c + delta s, error delta^2 / 2 (below
 * 1e-4 up to omega_e Ts = 0.03, 5 times the paper motors' overspeed).
 * Both pass the same first-order low-pass (time constant filter_s): the
 * L di/dt of current noise averages out (10 mA RMS at 20 kHz, L = 3.8 mH:
 * 1.1 V per sample, 0.04 V after a 20 ms filter), and equal filtering keeps
 * the two vectors comparable while the speed changes slowly.
 *
 * Decimation N (the application's slow tick): the monitor steps on every
 * N-th sample interval only, still measuring over that one interval (the
 * currents of the sample before it: mc_emf_monitor_remember_f32 on every
 * sample); the low-pass and the persistence run at the period N Ts.
 * Subsampling keeps both vectors sampled at the same instants, so the
 * filtering stays equal; the filtered magnitude of a vector turning at
 * omega_e is about 1 / (omega_e filter_s), independent of N Ts while
 * omega_e N Ts is small. The current noise averages over N times fewer
 * samples (0.13 V at N = 10 in the example above).
 *
 * What the estimators test (thresholds in the drive's protection block):
 *   angle between e_meas and e_pred above angle_max, the estimate turning
 *   (an encoder that slipped: 90 deg electrical shows as 90 deg; a
 *   sensorless observer out of lock);
 *   |e_meas| above ratio_high |e_pred| + e_min (the rotor turns, the
 *   estimate does not: a frozen encoder; encoder only: a sensorless
 *   estimate near standstill has no back-EMF to follow, paper 001
 *   Remark 5, and the paper's R +50 % case drifts there by design);
 *   |e_meas| below ratio_low |e_pred| above a speed floor (the estimate
 *   turns, the rotor does not: sensorless loss of lock).
 * Model errors move e_meas by (dR i) and (dpsi omega_e): the thresholds
 * must leave room for them (the defaults in firmware/app/config.c state
 * the measured margins).
 *
 * Units: V, A, ohm, H, Wb, rad (electrical), rad/s (electrical), s.
 */
#ifndef MC_EMF_MONITOR_H
#define MC_EMF_MONITOR_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/status.h"

typedef struct {
    float R_ohm;         /* nominal stator resistance, >= 0 */
    float L_H;           /* nominal inductance (Lq), > 0 */
    float psi_Wb;        /* nominal PM flux linkage, > 0 */
    float Ts_s;          /* sample period, > 0 */
    float filter_s;      /* low-pass time constant, >= N Ts */
    uint32_t decimation; /* N: a step every N-th sample, [1, 1000] */
} mc_emf_monitor_params_t;

typedef struct {
    float R_ohm, L_over_Ts_ohm, psi_Wb, half_Ts_s, lpf_a;
    float i_al_prev_A, i_be_prev_A;
    bool have_prev;
    float e_meas_V[2]; /* filtered, alpha / beta */
    float e_pred_V[2];
} mc_emf_monitor_f32_t;

/* Validate (finite, ranges above), design and reset. MC_ERR_NONFINITE /
 * MC_ERR_PARAM (*m untouched). Interrupt context: no. */
mc_status_t mc_emf_monitor_init_f32(mc_emf_monitor_f32_t *m,
                                    const mc_emf_monitor_params_t *p);

/* Forget the history and the filtered vectors (the estimate restarts).
 * Interrupt context: yes. */
void mc_emf_monitor_reset_f32(mc_emf_monitor_f32_t *m);

/* One sample: currents at t_k, the mean voltage over [t_{k-1}, t_k], the
 * sine and cosine of the estimate's electrical angle at t_k and its
 * electrical speed. Non-finite inputs propagate into the filtered vectors
 * (the caller's finiteness check of the estimate sees them first).
 * Interrupt context: yes. */
void mc_emf_monitor_step_f32(mc_emf_monitor_f32_t *m, float i_alpha_A,
                             float i_beta_A, float v_alpha_V, float v_beta_V,
                             float sin_theta_e, float cos_theta_e,
                             float omega_e_rad_s);

/* The currents of this sample, for a step at the next one (every sample
 * when the monitor is decimated; the step itself also keeps them).
 * Interrupt context: yes. */
static inline void mc_emf_monitor_remember_f32(mc_emf_monitor_f32_t *m,
                                               float i_alpha_A, float i_beta_A)
{
    m->i_al_prev_A = i_alpha_A;
    m->i_be_prev_A = i_beta_A;
    m->have_prev = true;
}

/* Squared magnitudes of the filtered measured and predicted vectors, V^2,
 * and their dot product. Interrupt context: yes. */
static inline float mc_emf_monitor_meas_sq_f32(const mc_emf_monitor_f32_t *m)
{
    return m->e_meas_V[0] * m->e_meas_V[0] + m->e_meas_V[1] * m->e_meas_V[1];
}

static inline float mc_emf_monitor_pred_sq_f32(const mc_emf_monitor_f32_t *m)
{
    return m->e_pred_V[0] * m->e_pred_V[0] + m->e_pred_V[1] * m->e_pred_V[1];
}

static inline float mc_emf_monitor_dot_f32(const mc_emf_monitor_f32_t *m)
{
    return m->e_meas_V[0] * m->e_pred_V[0] + m->e_meas_V[1] * m->e_pred_V[1];
}

/* The thresholds of the checks (the configuration block "emf_check"). */
typedef struct {
    float filter_s;          /* low-pass time constant, [N Ts, 1] s */
    float check_time_s;      /* a check must hold this long to fault,
                                >= N Ts */
    float min_V;             /* e_min: signal floor, > 0 */
    float min_speed_e_rad_s; /* checks of a turning estimate only above
                                this |omega_e|, > 0 */
    float angle_max_rad;     /* encoder: e_meas vs e_pred, (0, pi/2] */
    float ratio_low;         /* sensorless: |e_meas| below ratio_low |e_pred|,
                                (0, 1) */
    float ratio_high;        /* encoder: |e_meas| above ratio_high |e_pred|
                                + e_min, > 1 */
} mc_emf_check_config_t;

/* The angle between e_meas and e_pred exceeds the angle whose cosine is
 * cos_max (both vectors above e_min; no square root, no division).
 * Interrupt context: yes. */
static inline bool
mc_emf_monitor_angle_exceeds_f32(const mc_emf_monitor_f32_t *m, float cos_max,
                                 float e_min_sq_V2)
{
    const float mm = mc_emf_monitor_meas_sq_f32(m);
    const float pp = mc_emf_monitor_pred_sq_f32(m);
    if (!(mm > e_min_sq_V2 && pp > e_min_sq_V2)) {
        return false;
    }
    const float dot = mc_emf_monitor_dot_f32(m);
    return dot < 0.0f || dot * dot < cos_max * cos_max * mm * pp;
}

/* The monitor with its thresholds and the persistence of the checks. */
typedef struct {
    mc_emf_monitor_f32_t mon;
    float e_min_sq_V2, cos_max, ratio_low_sq, ratio_high_sq;
    float min_speed_e_rad_s;
    uint32_t n_required; /* consecutive steps that make a fault */
    uint32_t count;
} mc_emf_check_f32_t;

/* Validate the thresholds (ranges above) and the motor / timing of p
 * (p->filter_s is taken from c), design and reset. MC_ERR_NONFINITE /
 * MC_ERR_PARAM. Interrupt context: no. */
mc_status_t mc_emf_check_init_f32(mc_emf_check_f32_t *chk,
                                  const mc_emf_check_config_t *c,
                                  const mc_emf_monitor_params_t *p);

/* Restart (history, filters, persistence). Interrupt context: yes. */
void mc_emf_check_reset_f32(mc_emf_check_f32_t *chk);

/* One sample of an encoder's check (arguments as mc_emf_monitor_step_f32,
 * the encoder's angle and speed): true once, for check_time, the angle
 * between e_meas and e_pred exceeded angle_max at |omega_e| above the
 * speed floor (a slip), or |e_meas|^2 exceeded ratio_high^2 |e_pred|^2 +
 * e_min^2 (the rotor turns, the encoder does not). Interrupt context: yes. */
bool mc_emf_check_encoder_f32(mc_emf_check_f32_t *chk, float i_alpha_A,
                              float i_beta_A, float v_alpha_V, float v_beta_V,
                              float sin_theta_e, float cos_theta_e,
                              float omega_e_rad_s);

/* One sample of a sensorless estimate's check: true once, for check_time,
 * with the estimate above the speed floor, |e_meas|^2 stayed below
 * ratio_low^2 |e_pred|^2 (the estimate turns, the rotor does not) or the
 * angle between them above angle_max (the estimate turns elsewhere): loss
 * of lock. Interrupt context: yes. */
bool mc_emf_check_sensorless_f32(mc_emf_check_f32_t *chk, float i_alpha_A,
                                 float i_beta_A, float v_alpha_V,
                                 float v_beta_V, float sin_theta_e,
                                 float cos_theta_e, float omega_e_rad_s);

#endif /* MC_EMF_MONITOR_H */
