/* Estimator "flux_pll": the NAM baseline's estimator (mc/est_flux_pll.h). */
#include "mc/est_flux_pll.h"

#include "mc/config.h"

const mc_param_t mc_est_flux_pll_params[] = {
    MC_PARAM(mc_est_flux_pll_config_t, bandwidth_rad_s, MC_PARAM_F32),
    MC_PARAM_END,
};

void mc_est_flux_pll_config_default(mc_est_flux_pll_config_t *c)
{
    /* 2x the default speed loop (the rule of a speed estimate feeding a
     * speed loop). */
    *c = (mc_est_flux_pll_config_t){ .bandwidth_rad_s = 100.0f };
}

mc_estimator_info_t mc_est_flux_pll_info(const mc_config_t *cfg)
{
    return (mc_estimator_info_t){
        .sensorless = true,
        .provides_load = true,
        .speed_bandwidth_rad_s = cfg->flux_pll.bandwidth_rad_s,
    };
}

mc_status_t mc_est_flux_pll_init(mc_est_flux_pll_t *est, const mc_config_t *cfg,
                                 const mc_timing_t *tm)
{
    const mc_status_t st = mc_flux_front_init(&est->front, cfg, tm);
    if (st != MC_OK) {
        return st;
    }
    const mc_pll_obs_params_t pp = {
        .bandwidth_rad_s = cfg->flux_pll.bandwidth_rad_s,
        .pole_pairs = cfg->motor.pole_pairs,
        .J_kgm2 = cfg->motor.J_kgm2,
        .Ts_s = tm->Ts_s,
        .bounds = mc_config_estimate_bounds(cfg),
    };
    return mc_pll_obs_init_f32(&est->pll, &pp);
}

void mc_est_flux_pll_hold(mc_est_flux_pll_t *est, float theta_e_rad)
{
    mc_flux_front_hold(&est->front, theta_e_rad);
}

uint32_t mc_est_flux_pll_start(mc_est_flux_pll_t *est, float theta_e_rad,
                               const mc_est_input_t *in)
{
    if (mc_pll_obs_reset_f32(&est->pll, theta_e_rad, 0.0f, 0.0f) != MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    return mc_flux_front_start(&est->front, theta_e_rad, in);
}
