/* I&I speed and load-torque observer, paper 001 (15)-(16), incremental form.
 * See the header for the derivation. */
#include "mc/speed_load_observer.h"

#include <math.h>

#include "reset_angle.h"

/* Jury test: both eigenvalues of the Euler map I + Ts A33 inside the unit
 * circle. For z^2 - T z + D: |D| < 1, 1 - T + D > 0, 1 + T + D > 0. */
static int euler_step_is_stable(float np_Ts_a1, float Ts2_np_a2_over_J)
{
    const float trace = 2.0f - np_Ts_a1;
    const float det = 1.0f - np_Ts_a1 + Ts2_np_a2_over_J;
    return det < 1.0f && det > -1.0f && 1.0f - trace + det > 0.0f &&
           1.0f + trace + det > 0.0f;
}

mc_status_t mc_speed_load_obs_init_f32(mc_speed_load_obs_f32_t *obs,
                                       const mc_speed_load_obs_params_t *p)
{
    if (!isfinite(p->a1) || !isfinite(p->a2) || !isfinite(p->J_kgm2) ||
        !isfinite(p->kt_Nm_per_A) || !isfinite(p->Ts_s)) {
        return MC_ERR_NONFINITE;
    }
    if (p->a1 <= 0.0f || p->a2 <= 0.0f || p->J_kgm2 <= 0.0f ||
        p->kt_Nm_per_A <= 0.0f || p->Ts_s <= 0.0f || p->pole_pairs < 1u ||
        mc_estimate_bounds_validate(&p->bounds) != MC_OK) {
        return MC_ERR_PARAM;
    }
    const float np = (float)p->pole_pairs;
    const float Ts_over_J = p->Ts_s / p->J_kgm2; /* J > 0 checked */
    const float np_Ts = np * p->Ts_s;
    if (!isfinite(Ts_over_J) ||
        !euler_step_is_stable(np_Ts * p->a1, np_Ts * p->a2 * Ts_over_J)) {
        return MC_ERR_PARAM;
    }
    obs->a1 = p->a1;
    obs->a2 = p->a2;
    obs->np_Ts = np_Ts;
    obs->Ts_over_J = Ts_over_J;
    obs->kt_Nm_per_A = p->kt_Nm_per_A;
    obs->bounds = p->bounds;
    return mc_speed_load_obs_reset_f32(obs, 0.0f, 0.0f, 0.0f);
}

mc_status_t mc_speed_load_obs_reset_f32(mc_speed_load_obs_f32_t *obs,
                                        float theta_e_rad, float omega_m_rad_s,
                                        float tau_L_Nm)
{
    float theta;
    const mc_status_t st =
        mc_obs_reset_angle_f32(theta_e_rad, omega_m_rad_s, tau_L_Nm, &theta);
    if (st != MC_OK) {
        return st;
    }
    obs->theta_e_prev_rad = theta;
    obs->omega_m_rad_s = omega_m_rad_s;
    obs->omega_comp_rad_s = 0.0f;
    obs->tau_L_Nm = tau_L_Nm;
    return MC_OK;
}

mc_status_t mc_speed_load_obs_step_f32(mc_speed_load_obs_f32_t *obs,
                                       float theta_e_rad, float i_q_A)
{
    if (!isfinite(theta_e_rad) || !isfinite(i_q_A)) {
        return MC_ERR_NONFINITE;
    }
    /* the step on a copy, kept only if finite (state untouched otherwise) */
    mc_speed_load_obs_f32_t next = *obs;
    if (!(mc_speed_load_obs_update_f32(&next, theta_e_rad, i_q_A) == 0.0f)) {
        return MC_ERR_NONFINITE;
    }
    *obs = next;
    return MC_OK;
}
