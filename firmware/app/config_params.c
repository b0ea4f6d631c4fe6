/* The configuration's parameter table and the list names (mc/config.h,
 * mc/params.h). The controller and estimator blocks come from the lists. */
#include <stddef.h>

#include "mc/config.h"

#define OFFSET(member) ((uint32_t)offsetof(mc_config_t, member))

size_t mc_param_size(mc_param_type_t type)
{
    switch (type) {
    case MC_PARAM_F32: return sizeof(float);
    case MC_PARAM_U32: return sizeof(uint32_t);
    case MC_PARAM_BOOL: return sizeof(bool);
    case MC_PARAM_CONTROLLER: return sizeof(mc_controller_t);
    case MC_PARAM_ESTIMATOR: return sizeof(mc_estimator_t);
    }
    return 0u;
}

static const mc_param_t top_params[] = {
    { "controller", MC_PARAM_CONTROLLER, OFFSET(controller) },
    { "estimator", MC_PARAM_ESTIMATOR, OFFSET(estimator) },
    MC_PARAM_END,
};

static const mc_param_t motor_params[] = {
    MC_PARAM(mc_motor_params_t, R_ohm, MC_PARAM_F32),
    MC_PARAM(mc_motor_params_t, Ld_H, MC_PARAM_F32),
    MC_PARAM(mc_motor_params_t, Lq_H, MC_PARAM_F32),
    MC_PARAM(mc_motor_params_t, psi_Wb, MC_PARAM_F32),
    MC_PARAM(mc_motor_params_t, pole_pairs, MC_PARAM_U32),
    MC_PARAM(mc_motor_params_t, J_kgm2, MC_PARAM_F32),
    MC_PARAM(mc_motor_params_t, B_Nm_s_rad, MC_PARAM_F32),
    MC_PARAM_END,
};

static const mc_param_t timing_params[] = {
    MC_PARAM(mc_timing_config_t, f_pwm_Hz, MC_PARAM_F32),
    MC_PARAM(mc_timing_config_t, slow_loop_Hz, MC_PARAM_F32),
    MC_PARAM(mc_timing_config_t, calib_time_s, MC_PARAM_F32),
    MC_PARAM(mc_timing_config_t, isr_overrun_limit, MC_PARAM_U32),
    MC_PARAM(mc_timing_config_t, delay_periods, MC_PARAM_F32),
    MC_PARAM(mc_timing_config_t, delay_compensation, MC_PARAM_BOOL),
    MC_PARAM(mc_timing_config_t, telemetry_every_isr, MC_PARAM_BOOL),
    MC_PARAM_END,
};

static const mc_param_t limits_params[] = {
    MC_PARAM(mc_limits_config_t, i_max_A, MC_PARAM_F32),
    MC_PARAM(mc_limits_config_t, omega_max_rad_s, MC_PARAM_F32),
    MC_PARAM_END,
};

static const mc_param_t protection_params[] = {
    MC_PARAM(mc_fault_limits_t, i_trip_A, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, v_dc_max_V, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, v_dc_min_V, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, i_offset_max_A, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, estimate_omega_max_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, estimate_tau_max_Nm, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, overspeed_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, stall_current_A, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, stall_speed_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, stall_time_s, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, current_limit_A, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, current_limit_time_s, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, i2t_continuous_A, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, i2t_peak_A, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, i2t_peak_time_s, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, current_sum_max_A, MC_PARAM_F32),
    MC_PARAM(mc_fault_limits_t, current_sum_time_s, MC_PARAM_F32),
    MC_PARAM_END,
};

static const mc_param_t current_params[] = {
    MC_PARAM(mc_current_loop_config_t, bandwidth_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_current_loop_config_t, modulation_margin, MC_PARAM_F32),
    MC_PARAM_END,
};

static const mc_param_t position_params[] = {
    MC_PARAM(mc_position_config_t, kp_per_s, MC_PARAM_F32),
    MC_PARAM_END,
};

static const mc_param_t deadtime_params[] = {
    MC_PARAM(mc_deadtime_config_t, dead_time_s, MC_PARAM_F32),
    MC_PARAM(mc_deadtime_config_t, device_drop_V, MC_PARAM_F32),
    MC_PARAM(mc_deadtime_config_t, current_band_A, MC_PARAM_F32),
    MC_PARAM(mc_deadtime_config_t, compensation, MC_PARAM_BOOL),
    MC_PARAM_END,
};

static const mc_param_t align_params[] = {
    MC_PARAM(mc_align_config_t, current_A, MC_PARAM_F32),
    MC_PARAM(mc_align_config_t, ramp_s, MC_PARAM_F32),
    MC_PARAM(mc_align_config_t, timeout_s, MC_PARAM_F32),
    MC_PARAM(mc_align_config_t, angle_e_rad, MC_PARAM_F32),
    MC_PARAM(mc_align_config_t, damping_ratio, MC_PARAM_F32),
    MC_PARAM(mc_align_config_t, i_q_max_A, MC_PARAM_F32),
    MC_PARAM(mc_align_config_t, settle_speed_e_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_align_config_t, settle_time_s, MC_PARAM_F32),
    MC_PARAM_END,
};

static const mc_param_t emf_check_params[] = {
    MC_PARAM(mc_emf_check_config_t, filter_s, MC_PARAM_F32),
    MC_PARAM(mc_emf_check_config_t, check_time_s, MC_PARAM_F32),
    MC_PARAM(mc_emf_check_config_t, min_V, MC_PARAM_F32),
    MC_PARAM(mc_emf_check_config_t, min_speed_e_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_emf_check_config_t, angle_max_rad, MC_PARAM_F32),
    MC_PARAM(mc_emf_check_config_t, ratio_low, MC_PARAM_F32),
    MC_PARAM(mc_emf_check_config_t, ratio_high, MC_PARAM_F32),
    MC_PARAM_END,
};

static const mc_param_block_t blocks[] = {
    { "", 0u, top_params },
    { "motor", OFFSET(motor), motor_params },
    { "timing", OFFSET(timing), timing_params },
    { "limits", OFFSET(limits), limits_params },
    { "protection", OFFSET(protection), protection_params },
    { "current", OFFSET(current), current_params },
    { "deadtime", OFFSET(deadtime), deadtime_params },
    { "position", OFFSET(position), position_params },
    { "align", OFFSET(align), align_params },
    { "flux_obs", OFFSET(flux_obs), mc_flux_obs_params },
    { "emf_check", OFFSET(emf_check), emf_check_params },
#define MC_X_BLOCK(name, NAME) { #name, OFFSET(name), mc_ctl_##name##_params },
    MC_CONTROLLERS(MC_X_BLOCK)
#undef MC_X_BLOCK
#define MC_X_BLOCK(name, NAME) { #name, OFFSET(name), mc_est_##name##_params },
        MC_ESTIMATORS(MC_X_BLOCK)
#undef MC_X_BLOCK
            { NULL, 0u, NULL },
};

const mc_param_block_t *mc_config_params(void)
{
    return blocks;
}

static const char *const controller_names[] = {
#define MC_X_NAME(name, NAME) #name,
    MC_CONTROLLERS(MC_X_NAME)
#undef MC_X_NAME
};

static const char *const estimator_names[] = {
#define MC_X_NAME(name, NAME) #name,
    MC_ESTIMATORS(MC_X_NAME)
#undef MC_X_NAME
};

const char *mc_controller_name(mc_controller_t id)
{
    return ((uint32_t)id < (uint32_t)MC_CONTROLLER_COUNT) ? controller_names[id]
                                                          : NULL;
}

const char *mc_estimator_name(mc_estimator_t id)
{
    return ((uint32_t)id < (uint32_t)MC_ESTIMATOR_COUNT) ? estimator_names[id]
                                                         : NULL;
}
