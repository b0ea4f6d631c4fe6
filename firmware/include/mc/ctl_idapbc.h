/*
 * Controller "idapbc": the output-feedback speed controller (11) of paper
 * 001 (mc/idapbc.h) in speed and position modes, with the optional
 * integral action on w_ref - w_hat (beyond the paper, off by default); in
 * current mode the d/q current loop (mc/current_loop.h), bumpless both
 * ways. Needs an estimator with a load-torque estimate (tau_hat of (11)).
 * Interface: mc/drive.h.
 */
#ifndef MC_CTL_IDAPBC_H
#define MC_CTL_IDAPBC_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "mc/clamp.h"
#include "mc/compiler.h"
#include "mc/drive.h"
#include "mc/estimator.h"
#include "mc/faults.h"
#include "mc/idapbc.h"
#include "mc/params.h"
#include "mc/pi.h"
#include "mc/timing.h"

typedef struct {
    float r_ohm;               /* damping r of (11), >= 0; 0 =
                                  critically damped
                                  (mc_idapbc_critical_damping_f32) */
    bool integral_enabled;     /* integral action tau_I added to the
                                  torque reference of (11) (mc/idapbc.h;
                                  false = the paper's scheme) */
    float integral_pole_rad_s; /* its slow closed-loop pole p, 1/s, > 0
                                  (mc_idapbc_integral_design_f32) */
    float integral_tau_max_Nm; /* anti-windup: |tau_I| limit, > 0 */
    bool paper_rotation;       /* rotate with rho_hat itself, (11) as
                                  printed: v_ab = (rho_a I + rho_b Jcal)
                                  v_hat, and i = (rho_a I + rho_b
                                  Jcal)^T i_ab, i.e. both scaled by
                                  |rho_hat|; false (the default): with the
                                  unit vector of its angle */
} mc_ctl_idapbc_config_t;

typedef struct {
    mc_idapbc_f32_t law;  /* (11) */
    mc_pi_f32_t integral; /* tau_I (zeroed when disabled) */
    bool integral_enabled;
    bool paper_rotation;
    float inv_kt_A_per_Nm; /* 1 / kt */
    float tau_max_Nm;      /* kt i_max: limit of tau_c */
} mc_ctl_idapbc_t;

MC_CONTROLLER_INTERFACE(idapbc);

/* (11): the current the controller steers to is i_q* = tau_c / kt (Remark
 * 2), tau_c = tau_hat (+ tau_I with the integral action, mc/idapbc.h; a
 * non-finite speed makes tau_I NaN, which (11) passes on to the voltages,
 * the output check's MC_FAULT_NONFINITE): limited to i_max
 * here (a documented limit, not a clamp of a fault: tau_hat beyond the
 * estimator's bound is MC_FAULT_ESTIMATE). */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_idapbc_voltages(mc_ctl_idapbc_t *ctl,
                                                      mc_telemetry_t *t)
{
    const float tau_lim = ctl->tau_max_Nm;
    float tau = t->tau_L_hat_Nm;
    if (MC_UNLIKELY(ctl->integral_enabled)) { /* off by default */
        /* unchecked: NaN for a non-finite speed all the same (mc/pi.h);
         * start and mode changes reset the integrator */
        tau += mc_pi_step_unchecked_f32(&ctl->integral, t->omega_m_ref_rad_s -
                                                            t->omega_m_rad_s);
    }
    tau = mc_clamp_sym_f32(tau, tau_lim); /* NaN goes on: the output check */
    t->i_d_ref_A = 0.0f;
    t->i_q_ref_A = tau * ctl->inv_kt_A_per_Nm;
    /* The rotations into and out of the estimated frame: by the unit
     * vector of rho_hat's angle (t->i_d_A, t->i_q_A and the inverse Park
     * of the control path), or, as printed, by rho_hat itself: both scaled
     * by |rho_hat| (|rho_hat|^2 from the flux front end, within its
     * plausibility bounds or already a fault). */
    /* unchecked: a non-finite voltage is the application's output check's
     * MC_FAULT_NONFINITE */
    if (MC_LIKELY(!ctl->paper_rotation)) { /* the default */
        const mc_idapbc_voltages_t v = mc_idapbc_voltages_unchecked_f32(
            &ctl->law, t->i_d_A, t->i_q_A, t->omega_m_ref_rad_s,
            t->omega_m_rad_s, tau);
        t->v_d_V = v.v_d_V;
        t->v_q_V = v.v_q_V;
        return MC_FAULT_NONE;
    }
    const float rho = sqrtf(t->flux_ratio_sq);
    const mc_idapbc_voltages_t v = mc_idapbc_voltages_unchecked_f32(
        &ctl->law, rho * t->i_d_A, rho * t->i_q_A, t->omega_m_ref_rad_s,
        t->omega_m_rad_s, tau);
    t->v_d_V = v.v_d_V * rho;
    t->v_q_V = v.v_q_V * rho;
    return MC_FAULT_NONE;
}

/* Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_ctl_idapbc_step(mc_ctl_idapbc_t *ctl,
                                                  mc_drive_t *d,
                                                  const mc_command_t *cmd,
                                                  mc_telemetry_t *t)
{
    mc_outer_loop_f32_t *o = &d->outer;
    if (cmd->mode == MC_MODE_CURRENT) {
        mc_outer_loop_current_f32(o, cmd);
        mc_outer_loop_publish_f32(o, t);
        mc_drive_current_step(d, t);
        return MC_FAULT_NONE;
    }
    /* The speed reference enters (11) directly. */
    (void)mc_outer_loop_speed_f32(o, cmd, t);
    mc_outer_loop_publish_f32(o, t);
    return mc_ctl_idapbc_voltages(ctl, t);
}

#endif /* MC_CTL_IDAPBC_H */
