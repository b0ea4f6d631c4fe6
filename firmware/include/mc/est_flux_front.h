/*
 * The front end shared by the sensorless estimators "flux_ii" and
 * "flux_pll": the gradient flux observer of paper 001 (12)-(14)
 * (mc/flux_observer.h) on the offset-corrected currents and the voltage
 * applied over the last interval, its plausibility check |rho_hat| in
 * [ratio_min, ratio_max] (MC_FAULT_ESTIMATE outside), the q current over
 * the interval (trapezoid of i_q_hat at both samples) for the speed
 * estimator, and the multi-turn position from the electrical-angle
 * increments / n_p (the absolute mechanical angle is known only modulo
 * 2 pi / n_p after the alignment).
 *
 * Outside RUN the observer is held and the ALIGN vector's angle is
 * reported (mc/align.h: the rotor is pulled to it).
 */
#ifndef MC_EST_FLUX_FRONT_H
#define MC_EST_FLUX_FRONT_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/drive_io.h"
#include "mc/estimator.h"
#include "mc/faults.h"
#include "mc/flux_observer.h"
#include "mc/params.h"
#include "mc/timing.h"

typedef struct {
    float gamma;     /* gamma of (12) as the paper gives it, in its
                        two-phase (power-invariant) variables (mc/motor.h),
                        1/(Wb^2 s), > 0 */
    float ratio_min; /* |rho_hat| (= |eta| / psi) outside */
    float ratio_max; /* [min, max]: MC_FAULT_ESTIMATE;
                        0 < min < 1 < max */
} mc_flux_obs_config_t;

typedef struct {
    mc_flux_obs_f32_t obs;
    float ratio_min_sq, ratio_max_sq;
    float n_p;
    float kt_Nm_per_A;      /* torque per A of q current */
    float i_q_hat_prev_A;   /* i_q_hat at the previous sample */
    float theta_e_prev_rad; /* for the multi-turn position */
    float theta_m_rad;      /* multi-turn position estimate */
} mc_flux_front_t;

extern const mc_param_t mc_flux_obs_params[];

/* Interrupt context: no. */
void mc_flux_obs_config_default(mc_flux_obs_config_t *c);

/* Design from cfg->flux_obs and the nominal motor (non-salient model of
 * the paper: L = Lq). Interrupt context: no. */
mc_status_t mc_flux_front_init(mc_flux_front_t *f, const mc_config_t *cfg,
                               const mc_timing_t *tm);

/* ALIGN starts: the position is theta_e_rad / n_p. Interrupt context: yes. */
void mc_flux_front_hold(mc_flux_front_t *f, float theta_e_rad);

/* ALIGN ends at theta_e_rad: restart the observer there with this
 * sample's currents (eta = psi [cos; sin]). Fault bits (NONFINITE).
 * Interrupt context: yes. */
uint32_t mc_flux_front_start(mc_flux_front_t *f, float theta_e_rad,
                             const mc_est_input_t *in);

/* One sample. Held (not running): the hold angle, the position, zero
 * speed and load into *t, returns false. Running: one observer step,
 * *theta_obs_rad its angle, *i_q_mean_A the q current over the interval,
 * returns true; *faults gets ESTIMATE (|rho_hat| implausible) or
 * NONFINITE (then false). t->flux_ratio_sq either way.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool
mc_flux_front_step(mc_flux_front_t *f, const mc_est_input_t *in,
                   mc_telemetry_t *t, float *theta_obs_rad, float *i_q_mean_A,
                   uint32_t *faults)
{
    t->flux_ratio_sq = mc_flux_obs_rho_sq_f32(&f->obs);
    *faults = MC_FAULT_NONE;
    if (!in->running) {
        t->theta_e_rad = in->theta_e_hold_rad;
        t->theta_m_rad = f->theta_m_rad;
        t->omega_m_rad_s = 0.0f;
        t->tau_L_hat_Nm = 0.0f;
        return false;
    }
    float v_al;
    float v_be;
    mc_applied_voltage_last_f32(in->v_applied, &v_al, &v_be);
    if (mc_flux_obs_step_f32(&f->obs, in->i_alpha_A, in->i_beta_A, v_al,
                             v_be) != MC_OK) {
        *faults = MC_FAULT_NONFINITE;
        return false;
    }
    *theta_obs_rad = mc_flux_obs_theta_e_f32(&f->obs);
    const float rho_sq = mc_flux_obs_rho_sq_f32(&f->obs);
    t->flux_ratio_sq = rho_sq;
    if (!(rho_sq >= f->ratio_min_sq && rho_sq <= f->ratio_max_sq)) {
        *faults = MC_FAULT_ESTIMATE;
    }
    /* i_q over [t_{k-1}, t_k]: trapezoid of the two samples. */
    const float i_q_hat =
        mc_flux_obs_iq_f32(&f->obs, in->i_alpha_A, in->i_beta_A);
    *i_q_mean_A = 0.5f * (i_q_hat + f->i_q_hat_prev_A);
    f->i_q_hat_prev_A = i_q_hat;
    return true;
}

/* After the speed estimator set t->theta_e_rad: the multi-turn position
 * into t->theta_m_rad. Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_flux_front_track(mc_flux_front_t *f,
                                               mc_telemetry_t *t)
{
    f->theta_m_rad +=
        mc_angle_diff_f32(t->theta_e_rad, f->theta_e_prev_rad) / f->n_p;
    f->theta_e_prev_rad = t->theta_e_rad;
    t->theta_m_rad = f->theta_m_rad;
}

/* Fault bits of a speed estimator's status: ESTIMATE for an estimate out
 * of its bounds (MC_ERR_RANGE), NONFINITE for anything else.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_flux_front_bounds_fault(mc_status_t st)
{
    if (st == MC_ERR_RANGE) {
        return MC_FAULT_ESTIMATE;
    }
    return (st == MC_OK) ? MC_FAULT_NONE : MC_FAULT_NONFINITE;
}

#endif /* MC_EST_FLUX_FRONT_H */
