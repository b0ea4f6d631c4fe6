/* Estimator "flux_ii": paper 001 (12)-(16) (mc/est_flux_ii.h). */
#include "mc/est_flux_ii.h"

#include "mc/config.h"

const mc_param_t mc_est_flux_ii_params[] = {
    MC_PARAM(mc_est_flux_ii_config_t, a1, MC_PARAM_F32),
    MC_PARAM(mc_est_flux_ii_config_t, a2, MC_PARAM_F32),
    MC_PARAM_END,
};

void mc_est_flux_ii_config_default(mc_est_flux_ii_config_t *c)
{
    /* Paper 001, Section 5. */
    *c = (mc_est_flux_ii_config_t){
        .a1 = MC_SPEED_LOAD_OBS_A1_DEFAULT,
        .a2 = MC_SPEED_LOAD_OBS_A2_DEFAULT,
    };
}

mc_estimator_info_t mc_est_flux_ii_info(const mc_config_t *cfg)
{
    (void)cfg; /* the I&I poles are not a single bandwidth */
    return (mc_estimator_info_t){ .sensorless = true, .provides_load = true };
}

mc_status_t mc_est_flux_ii_init(mc_est_flux_ii_t *est, const mc_config_t *cfg,
                                const mc_timing_t *tm)
{
    const mc_status_t st = mc_flux_front_init(&est->front, cfg, tm);
    if (st != MC_OK) {
        return st;
    }
    const mc_speed_load_obs_params_t sp = {
        .a1 = cfg->flux_ii.a1,
        .a2 = cfg->flux_ii.a2,
        .pole_pairs = cfg->motor.pole_pairs,
        .J_kgm2 = cfg->motor.J_kgm2,
        .kt_Nm_per_A = mc_motor_kt_f32(&cfg->motor),
        .Ts_s = tm->Ts_s,
        .bounds = mc_config_estimate_bounds(cfg),
    };
    return mc_speed_load_obs_init_f32(&est->ii, &sp);
}

void mc_est_flux_ii_hold(mc_est_flux_ii_t *est, float theta_e_rad)
{
    mc_flux_front_hold(&est->front, theta_e_rad);
}

uint32_t mc_est_flux_ii_start(mc_est_flux_ii_t *est, float theta_e_rad,
                              const mc_est_input_t *in)
{
    if (mc_speed_load_obs_reset_f32(&est->ii, theta_e_rad, 0.0f, 0.0f) !=
        MC_OK) {
        return MC_FAULT_NONFINITE;
    }
    return mc_flux_front_start(&est->front, theta_e_rad, in);
}
