/* Sensorless estimation and the paper-001 controller inside the app
 * (MC_ANGLE_SOURCE_FLUX_OBSERVER, MC_CONTROLLER_IDAPBC; see mc/app.h). */
#include <math.h>

#include "app_internal.h"
#include "mc/angle.h"

/* Integral action of the IDA-PBC (mc/idapbc.h): a PI on w_ref - w_hat
 * whose output tau_I is limited to +-idapbc_integral_tau_max_Nm (the
 * integrator too: mc/pi.h's clamping anti-windup). Disabled: kp = ki = 0
 * is not a valid mc_pi (and never stepped), the instance is zeroed. */
static mc_status_t idapbc_integral_init(mc_app_t *app, const mc_config_t *c,
                                        const mc_idapbc_params_t *ip)
{
    app->idapbc_int = (mc_pi_f32_t){ 0 };
    if (!c->idapbc_integral_enabled) {
        return MC_OK;
    }
    float kp;
    float ki;
    const mc_status_t st = mc_idapbc_integral_design_f32(
        ip, c->J_kgm2, c->idapbc_integral_pole_rad_s, &kp, &ki);
    if (st != MC_OK) {
        return st;
    }
    const float lim = c->idapbc_integral_tau_max_Nm;
    return mc_pi_init_f32(&app->idapbc_int, kp, ki, app->Ts_s, -lim, lim);
}

mc_status_t mc_app_sensorless_init(mc_app_t *app, const mc_config_t *c)
{
    const float Ts = app->Ts_s;
    const mc_estimate_bounds_t bounds = {
        .omega_m_max_rad_s = c->est_omega_max_rad_s,
        .tau_max_Nm = c->est_tau_max_Nm,
    };
    app->kt_Nm_per_A = 1.5f * (float)c->pole_pairs * c->psi_Wb;
    /* Non-salient model of the paper: L = Lq (the torque-producing axis). */
    const mc_flux_obs_params_t fp = {
        .R_ohm = c->R_ohm, .L_H = c->Lq_H, .flux_Wb = c->psi_Wb,
        .gamma = c->flux_obs_gamma, .Ts_s = Ts,
    };
    mc_status_t st = mc_flux_obs_init_f32(&app->flux_obs, &fp);
    if (st != MC_OK) {
        return st;
    }
    const mc_speed_load_obs_params_t sp = {
        .a1 = c->speed_obs_a1, .a2 = c->speed_obs_a2,
        .pole_pairs = c->pole_pairs, .J_kgm2 = c->J_kgm2,
        .kt_Nm_per_A = app->kt_Nm_per_A, .Ts_s = Ts, .bounds = bounds,
    };
    st = mc_speed_load_obs_init_f32(&app->speed_obs, &sp);
    if (st != MC_OK) {
        return st;
    }
    const mc_pll_obs_params_t pp = {
        .bandwidth_rad_s = c->sensorless_pll_bandwidth_rad_s,
        .pole_pairs = c->pole_pairs, .J_kgm2 = c->J_kgm2, .Ts_s = Ts,
        .bounds = bounds,
    };
    st = mc_pll_obs_init_f32(&app->pll_obs, &pp);
    if (st != MC_OK) {
        return st;
    }
    float r = c->idapbc_r_ohm;
    if (r == 0.0f) {
        r = mc_idapbc_critical_damping_f32(c->pole_pairs, c->psi_Wb,
                                           app->kt_Nm_per_A, c->Lq_H,
                                           c->J_kgm2);
    }
    const mc_idapbc_params_t ip = {
        .R_ohm = c->R_ohm, .L_H = c->Lq_H, .flux_Wb = c->psi_Wb,
        .pole_pairs = c->pole_pairs, .kt_Nm_per_A = app->kt_Nm_per_A,
        .r_ohm = r,
    };
    st = mc_idapbc_init_f32(&app->idapbc, &ip);
    if (st != MC_OK) {
        return st;
    }
    st = idapbc_integral_init(app, c, &ip);
    if (st != MC_OK) {
        return st;
    }
    st = mc_delay_comp_init_f32(&app->delay_comp, Ts, c->delay_periods,
                                c->delay_comp_enabled);
    if (st != MC_OK) {
        return st;
    }
    st = mc_applied_voltage_init_f32(&app->v_applied, c->delay_periods);
    if (st != MC_OK) {
        return st;
    }
    const mc_align_params_t ap = {
        .i_align_A = c->align_current_A, .ramp_s = c->align_ramp_s,
        .timeout_s = c->align_time_s, .angle_e_rad = c->align_angle_e_rad,
        .damping_ratio = c->align_damping_ratio,
        .i_q_max_A = c->align_i_q_max_A,
        .settle_speed_e_rad_s = c->align_settle_speed_e_rad_s,
        .settle_time_s = c->align_settle_time_s, .R_ohm = c->R_ohm,
        .L_H = c->Lq_H, .psi_Wb = c->psi_Wb, .J_kgm2 = c->J_kgm2,
        .kt_Nm_per_A = app->kt_Nm_per_A, .pole_pairs = c->pole_pairs,
        .Ts_s = Ts,
    };
    return mc_align_init_f32(&app->align, &ap);
}

uint32_t mc_app_sensorless_start(mc_app_t *app, float i_alpha_A, float i_beta_A)
{
    const float theta = app->cfg.align_angle_e_rad;
    if (mc_flux_obs_reset_f32(&app->flux_obs, theta, i_alpha_A, i_beta_A) != MC_OK ||
        mc_speed_load_obs_reset_f32(&app->speed_obs, theta, 0.0f, 0.0f) !=
            MC_OK ||
        mc_pll_obs_reset_f32(&app->pll_obs, theta, 0.0f, 0.0f) != MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    app->i_q_hat_prev_A = mc_flux_obs_iq_f32(&app->flux_obs, i_alpha_A, i_beta_A);
    app->theta_e_hat_prev_rad = mc_flux_obs_theta_e_f32(&app->flux_obs);
    return MC_FAULT_NONE;
}

/* Plausibility of the flux estimate: |rho_hat| in [min, max]. */
static uint32_t check_flux(const mc_app_t *app, float rho_sq)
{
    const float lo = app->cfg.est_flux_ratio_min;
    const float hi = app->cfg.est_flux_ratio_max;
    return (rho_sq >= lo * lo && rho_sq <= hi * hi) ? MC_FAULT_NONE
                                                    : MC_FAULT_ESTIMATE;
}

static uint32_t bounds_fault(mc_status_t st)
{
    if (st == MC_ERR_RANGE) {
        return MC_FAULT_ESTIMATE;
    }
    return (st == MC_OK) ? MC_FAULT_NONE : MC_FAULT_NONFINITE;
}

uint32_t mc_app_sensorless_estimate(mc_app_t *app, float i_alpha_A, float i_beta_A,
                                    mc_telemetry_t *t)
{
    t->flux_ratio_sq = mc_flux_obs_rho_sq_f32(&app->flux_obs);
    if (app->state != MC_STATE_RUN) {
        /* Observers held: the controller uses the angle of the ALIGN
         * current vector (mc/align.h). */
        t->theta_e_rad = mc_align_theta_e_f32(&app->align);
        t->theta_m_rad = app->theta_m_hat_rad;
        t->omega_m_rad_s = 0.0f;
        t->tau_L_hat_Nm = 0.0f;
        return MC_FAULT_NONE;
    }
    float v_al;
    float v_be;
    mc_applied_voltage_last_f32(&app->v_applied, &v_al, &v_be);
    if (mc_flux_obs_step_f32(&app->flux_obs, i_alpha_A, i_beta_A, v_al, v_be) !=
        MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    const float theta_obs = mc_flux_obs_theta_e_f32(&app->flux_obs);
    t->flux_ratio_sq = mc_flux_obs_rho_sq_f32(&app->flux_obs);
    uint32_t faults = check_flux(app, t->flux_ratio_sq);
    /* i_q over [t_{k-1}, t_k]: trapezoid of the two samples. */
    const float i_q_hat = mc_flux_obs_iq_f32(&app->flux_obs, i_alpha_A, i_beta_A);
    const float i_q_mean = 0.5f * (i_q_hat + app->i_q_hat_prev_A);
    app->i_q_hat_prev_A = i_q_hat;
    mc_status_t st;
    switch (app->cfg.controller) {
    case MC_CONTROLLER_IDAPBC: /* paper 001: I&I observer (15)-(16) */
        st = mc_speed_load_obs_step_f32(&app->speed_obs, theta_obs, i_q_mean);
        if (st == MC_OK) {
            st = mc_speed_load_obs_check_f32(&app->speed_obs);
        }
        t->theta_e_rad = theta_obs;
        t->omega_m_rad_s = mc_speed_load_obs_omega_m_f32(&app->speed_obs);
        t->tau_L_hat_Nm = mc_speed_load_obs_tau_L_f32(&app->speed_obs);
        break;
    case MC_CONTROLLER_FOC_PI: /* NAM baseline: PLL angle, speed, load */
    default:
        st = mc_pll_obs_step_f32(&app->pll_obs, theta_obs,
                                 app->kt_Nm_per_A * i_q_mean);
        if (st == MC_OK) {
            st = mc_pll_obs_check_f32(&app->pll_obs);
        }
        t->theta_e_rad = mc_pll_obs_theta_e_f32(&app->pll_obs);
        t->omega_m_rad_s = mc_pll_obs_omega_m_f32(&app->pll_obs);
        t->tau_L_hat_Nm = mc_pll_obs_tau_L_f32(&app->pll_obs);
        break;
    }
    faults |= bounds_fault(st);
    /* Multi-turn position: electrical increments / n_p (the absolute
     * mechanical angle is known only modulo 2 pi / n_p after alignment). */
    app->theta_m_hat_rad +=
        mc_angle_diff_f32(t->theta_e_rad, app->theta_e_hat_prev_rad) /
        (float)app->cfg.pole_pairs;
    app->theta_e_hat_prev_rad = t->theta_e_rad;
    t->theta_m_rad = app->theta_m_hat_rad;
    return faults;
}

uint32_t mc_app_sensorless_align(mc_app_t *app, float i_alpha_A, float i_beta_A,
                                 mc_telemetry_t *t, mc_align_state_t *state)
{
    float v_al;
    float v_be;
    mc_applied_voltage_last_f32(&app->v_applied, &v_al, &v_be);
    mc_align_out_t o;
    if (mc_align_step_f32(&app->align, i_alpha_A, i_beta_A, v_al, v_be, &o) !=
        MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    t->i_d_ref_A = o.i_d_ref_A;
    t->i_q_ref_A = o.i_q_ref_A;
    *state = o.state;
    return (o.state == MC_ALIGN_TIMEOUT) ? MC_FAULT_ESTIMATE : MC_FAULT_NONE;
}

void mc_app_idapbc_reset(mc_app_t *app)
{
    mc_pi_reset_f32(&app->idapbc_int, 0.0f);
}

uint32_t mc_app_idapbc_voltages(mc_app_t *app, mc_telemetry_t *t)
{
    /* The current the controller steers to is i_q* = tau_c / kt (Remark
     * 2), tau_c = tau_hat (+ tau_I with the integral action, mc/idapbc.h;
     * a non-finite speed makes tau_I NaN, which (11) reports): limited to
     * i_max here (a documented limit, not a clamp of a fault: tau_hat
     * beyond est_tau_max_Nm is MC_FAULT_ESTIMATE). */
    const float tau_lim = app->kt_Nm_per_A * app->cfg.i_max_A;
    float tau = t->tau_L_hat_Nm;
    if (app->cfg.idapbc_integral_enabled) {
        tau += mc_pi_step_f32(&app->idapbc_int,
                              t->omega_m_ref_rad_s - t->omega_m_rad_s);
    }
    tau = (tau > tau_lim) ? tau_lim : ((tau < -tau_lim) ? -tau_lim : tau);
    t->i_d_ref_A = 0.0f;
    t->i_q_ref_A = tau / app->kt_Nm_per_A;
    if (mc_idapbc_step_f32(&app->idapbc, t->i_d_A, t->i_q_A,
                           t->omega_m_ref_rad_s, t->omega_m_rad_s, tau,
                           &t->v_d_V, &t->v_q_V) != MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    return MC_FAULT_NONE;
}
