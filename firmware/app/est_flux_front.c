/* Flux-observer front end of the sensorless estimators
 * (mc/est_flux_front.h). */
#include "mc/est_flux_front.h"

#include "mc/config.h"

const mc_param_t mc_flux_obs_params[] = {
    MC_PARAM(mc_flux_obs_config_t, gamma, MC_PARAM_F32),
    MC_PARAM(mc_flux_obs_config_t, ratio_min, MC_PARAM_F32),
    MC_PARAM(mc_flux_obs_config_t, ratio_max, MC_PARAM_F32),
    MC_PARAM_END,
};

void mc_flux_obs_config_default(mc_flux_obs_config_t *c)
{
    /* Paper 001, Section 5 gain; |rho_hat| within a factor 2 of 1. */
    *c = (mc_flux_obs_config_t){
        .gamma = MC_FLUX_OBS_GAMMA_DEFAULT,
        .ratio_min = 0.5f,
        .ratio_max = 1.5f,
    };
}

mc_status_t mc_flux_front_init(mc_flux_front_t *f, const mc_config_t *cfg,
                               const mc_timing_t *tm)
{
    const mc_flux_obs_config_t *c = &cfg->flux_obs;
    if (!(c->ratio_min > 0.0f) || !(c->ratio_min < 1.0f) ||
        !(c->ratio_max > 1.0f)) {
        return MC_ERR_PARAM;
    }
    const mc_motor_params_t *m = &cfg->motor;
    /* gamma is (12)'s, in the paper's two-phase variables; in the
     * firmware's amplitude-invariant ones the same observer has the gain
     * MC_POWER_INVARIANT_SQ gamma (mc/motor.h). */
    const mc_flux_obs_params_t fp = {
        .R_ohm = m->R_ohm,
        .L_H = m->Lq_H,
        .psi_Wb = m->psi_Wb,
        .gamma = MC_POWER_INVARIANT_SQ * c->gamma,
        .Ts_s = tm->Ts_s,
    };
    const mc_status_t st = mc_flux_obs_init_f32(&f->obs, &fp);
    if (st != MC_OK) {
        return st;
    }
    f->ratio_min_sq = c->ratio_min * c->ratio_min;
    f->ratio_max_sq = c->ratio_max * c->ratio_max;
    f->inv_n_p = 1.0f / (float)m->pole_pairs; /* >= 1: validated */
    f->kt_Nm_per_A = mc_motor_kt_f32(m);
    f->i_q_hat_prev_A = 0.0f;
    f->theta_m_rad = 0.0f;
    return MC_OK;
}

void mc_flux_front_hold(mc_flux_front_t *f, float theta_e_rad)
{
    f->theta_m_rad = theta_e_rad * f->inv_n_p;
}

uint32_t mc_flux_front_start(mc_flux_front_t *f, float theta_e_rad,
                             const mc_est_input_t *in)
{
    if (mc_flux_obs_reset_f32(&f->obs, theta_e_rad, in->i_alpha_A,
                              in->i_beta_A) != MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    f->i_q_hat_prev_A =
        mc_flux_obs_iq_f32(&f->obs, in->i_alpha_A, in->i_beta_A);
    return MC_FAULT_NONE;
}

uint32_t mc_flux_front_fault(const mc_flux_front_t *f, float rho_sq,
                             float obs_finite, float speed_finite,
                             float theta_m_rad, float omega_m_rad_s,
                             float tau_L_Nm, const mc_estimate_bounds_t *b)
{
    const uint32_t rho_fault =
        (rho_sq >= f->ratio_min_sq && rho_sq <= f->ratio_max_sq)
            ? MC_FAULT_NONE
            : MC_FAULT_ESTIMATE;
    if (!(obs_finite + speed_finite + theta_m_rad * 0.0f == 0.0f)) {
        /* as the checked steps: the observer's first, the speed
         * estimator's only after a finite observer step */
        return (obs_finite == 0.0f) ? (rho_fault | MC_FAULT_NONFINITE)
                                    : MC_FAULT_NONFINITE;
    }
    return rho_fault | (mc_estimate_bounds_hold(b, omega_m_rad_s, tau_L_Nm)
                            ? MC_FAULT_NONE
                            : MC_FAULT_ESTIMATE);
}
