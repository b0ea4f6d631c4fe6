/* Gradient flux / position observer, paper 001 (12)-(14). See the header. */
#include "mc/flux_observer.h"

#include <math.h>

#include "mc/angle.h"
#include "mc/finite.h"

#include "reset_angle.h"

static bool all_finite4(float a, float b, float c, float d)
{
    const float x[] = { a, b, c, d };
    return mc_all_finite_f32(x, 4u);
}

mc_status_t mc_flux_obs_init_f32(mc_flux_obs_f32_t *obs,
                                 const mc_flux_obs_params_t *p)
{
    if (!all_finite4(p->R_ohm, p->L_H, p->psi_Wb, p->gamma) ||
        !isfinite(p->Ts_s)) {
        return MC_ERR_NONFINITE;
    }
    if (p->R_ohm < 0.0f || p->L_H <= 0.0f || p->psi_Wb <= 0.0f ||
        p->gamma <= 0.0f || p->Ts_s <= 0.0f) {
        return MC_ERR_PARAM;
    }
    /* Euler stability of the gradient correction: Ts * gamma * Phi^2 < 1
     * (see header). Written as a product: no division to guard. */
    const float flux_sq = p->psi_Wb * p->psi_Wb;
    if (!(p->Ts_s * p->gamma * flux_sq < 1.0f)) {
        return MC_ERR_PARAM;
    }
    obs->Ts_s = p->Ts_s;
    obs->R_ohm = p->R_ohm;
    obs->half_R_ohm = 0.5f * p->R_ohm;
    obs->L_H = p->L_H;
    obs->psi_Wb = p->psi_Wb;
    obs->psi_sq_Wb2 = flux_sq;
    obs->inv_psi_per_Wb = 1.0f / p->psi_Wb; /* Phi > 0 checked above */
    obs->gamma = p->gamma;
    return mc_flux_obs_reset_f32(obs, 0.0f, 0.0f, 0.0f);
}

mc_status_t mc_flux_obs_reset_f32(mc_flux_obs_f32_t *obs, float theta_e_rad,
                                  float i_alpha_A, float i_beta_A)
{
    float theta;
    const mc_status_t st =
        mc_obs_reset_angle_f32(theta_e_rad, i_alpha_A, i_beta_A, &theta);
    if (st != MC_OK) {
        return st;
    }
    float s, c;
    mc_sincos_f32(theta, &s, &c);
    obs->eta_alpha_Wb = obs->psi_Wb * c;
    obs->eta_beta_Wb = obs->psi_Wb * s;
    obs->lambda_alpha_Wb = obs->L_H * i_alpha_A + obs->eta_alpha_Wb;
    obs->lambda_beta_Wb = obs->L_H * i_beta_A + obs->eta_beta_Wb;
    obs->i_alpha_prev_A = i_alpha_A;
    obs->i_beta_prev_A = i_beta_A;
    obs->theta_e_rad = theta;
    obs->d_theta_e_rad = 0.0f;
    return MC_OK;
}

mc_status_t mc_flux_obs_step_f32(mc_flux_obs_f32_t *obs, float i_alpha_A,
                                 float i_beta_A, float v_alpha_V,
                                 float v_beta_V)
{
    if (!all_finite4(i_alpha_A, i_beta_A, v_alpha_V, v_beta_V)) {
        return MC_ERR_NONFINITE;
    }
    /* the step on a copy, kept only if finite (state untouched otherwise) */
    mc_flux_obs_f32_t next = *obs;
    if (!(mc_flux_obs_update_f32(&next, i_alpha_A, i_beta_A, v_alpha_V,
                                 v_beta_V, true) == 0.0f)) {
        return MC_ERR_NONFINITE;
    }
    *obs = next;
    return MC_OK;
}
