/* PLL-type speed / load-torque estimator (baseline of paper 001, ref. [4]).
 * See the header for the design. */
#include "mc/pll_observer.h"

#include <math.h>

#include "reset_angle.h"

mc_status_t mc_pll_obs_init_f32(mc_pll_obs_f32_t *pll,
                                const mc_pll_obs_params_t *p)
{
    if (!isfinite(p->bandwidth_rad_s) || !isfinite(p->J_kgm2) ||
        !isfinite(p->Ts_s)) {
        return MC_ERR_NONFINITE;
    }
    if (p->bandwidth_rad_s <= 0.0f || p->J_kgm2 <= 0.0f || p->Ts_s <= 0.0f ||
        p->pole_pairs < 1u ||
        p->bandwidth_rad_s * p->Ts_s > MC_PLL_OBS_MAX_BANDWIDTH_TS ||
        mc_estimate_bounds_validate(&p->bounds) != MC_OK) {
        return MC_ERR_PARAM;
    }
    const float wb = p->bandwidth_rad_s;
    const float inv_np = 1.0f / (float)p->pole_pairs; /* n_p >= 1 */
    /* triple pole at -w_b: s^3 + 3 w_b s^2 + 3 w_b^2 s + w_b^3 */
    const float l1 = 3.0f * wb;
    const float l2 = 3.0f * wb * wb * inv_np;
    const float l3 = p->J_kgm2 * wb * wb * wb * inv_np;
    const float Ts_over_J = p->Ts_s / p->J_kgm2; /* J > 0 checked */
    if (!isfinite(l3) || !isfinite(Ts_over_J)) {
        return MC_ERR_PARAM;
    }
    pll->l1_Ts = l1 * p->Ts_s;
    pll->l2_Ts = l2 * p->Ts_s;
    pll->l3_Ts = l3 * p->Ts_s;
    pll->np_Ts = (float)p->pole_pairs * p->Ts_s;
    pll->Ts_over_J = Ts_over_J;
    pll->bounds = p->bounds;
    return mc_pll_obs_reset_f32(pll, 0.0f, 0.0f, 0.0f);
}

mc_status_t mc_pll_obs_reset_f32(mc_pll_obs_f32_t *pll, float theta_e_rad,
                                 float omega_m_rad_s, float tau_L_Nm)
{
    float theta;
    const mc_status_t st =
        mc_obs_reset_angle_f32(theta_e_rad, omega_m_rad_s, tau_L_Nm, &theta);
    if (st != MC_OK) {
        return st;
    }
    mc_sincos_f32(theta, &pll->sin_e, &pll->cos_e);
    pll->d_theta_e_rad = 0.0f;
    pll->omega_m_rad_s = omega_m_rad_s;
    pll->omega_comp_rad_s = 0.0f;
    pll->tau_L_Nm = tau_L_Nm;
    return MC_OK;
}

mc_status_t mc_pll_obs_step_f32(mc_pll_obs_f32_t *pll, float theta_obs_e_rad,
                                float tau_e_ff_Nm)
{
    if (!isfinite(theta_obs_e_rad) || !isfinite(tau_e_ff_Nm)) {
        return MC_ERR_NONFINITE;
    }
    /* the step on a copy, kept only if finite (state untouched otherwise) */
    mc_pll_obs_f32_t next = *pll;
    const float eps =
        mc_angle_diff_f32(theta_obs_e_rad, mc_pll_obs_theta_e_f32(&next) +
                                               next.np_Ts * next.omega_m_rad_s);
    if (!(mc_pll_obs_correct_f32(&next, eps, tau_e_ff_Nm, true) == 0.0f)) {
        return MC_ERR_NONFINITE;
    }
    *pll = next;
    return MC_OK;
}
