/* Protection checks of one sample (see mc/faults.h). */
#include "mc/faults.h"

#include <math.h>

mc_status_t mc_fault_limits_validate(const mc_fault_limits_t *limits)
{
    const float f[] = { limits->i_trip_A,
                        limits->v_dc_max_V,
                        limits->v_dc_min_V,
                        limits->i_offset_max_A,
                        limits->estimate_omega_max_rad_s,
                        limits->estimate_tau_max_Nm,
                        limits->overspeed_rad_s,
                        limits->stall_current_A,
                        limits->stall_speed_rad_s,
                        limits->stall_time_s,
                        limits->current_limit_A,
                        limits->current_limit_time_s,
                        limits->i2t_continuous_A,
                        limits->i2t_peak_A,
                        limits->i2t_peak_time_s,
                        limits->current_sum_max_A,
                        limits->current_sum_time_s };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (!(limits->i_trip_A > 0.0f) || limits->v_dc_min_V < 0.0f ||
        !(limits->v_dc_min_V < limits->v_dc_max_V) ||
        !(limits->i_offset_max_A > 0.0f) ||
        !(limits->estimate_omega_max_rad_s > 0.0f) ||
        !(limits->estimate_tau_max_Nm > 0.0f) ||
        !(limits->overspeed_rad_s > 0.0f) ||
        !(limits->stall_current_A > 0.0f) ||
        !(limits->stall_speed_rad_s > 0.0f) || !(limits->stall_time_s > 0.0f) ||
        !(limits->current_limit_A > 0.0f) ||
        !(limits->current_limit_A < limits->i_trip_A) ||
        !(limits->current_limit_time_s > 0.0f) ||
        !(limits->i2t_continuous_A > 0.0f) ||
        !(limits->i2t_peak_A > limits->i2t_continuous_A) ||
        !(limits->i2t_peak_time_s > 0.0f) ||
        !(limits->current_sum_max_A > 0.0f) ||
        !(limits->current_sum_time_s > 0.0f)) {
        return MC_ERR_PARAM;
    }
    return MC_OK;
}

uint32_t mc_faults_check_sample(const mc_fault_limits_t *limits, float i_a_A,
                                float i_b_A, float i_c_A, float v_dc_V,
                                bool check_undervoltage)
{
    const float i_abc_A[3] = { i_a_A, i_b_A, i_c_A };
    uint32_t f = MC_FAULT_NONE;
    for (uint32_t k = 0u; k < 3u; ++k) {
        if (!isfinite(i_abc_A[k])) {
            f |= MC_FAULT_NONFINITE;
        } else if (fabsf(i_abc_A[k]) > limits->i_trip_A) {
            f |= MC_FAULT_OVERCURRENT;
        }
    }
    if (!isfinite(v_dc_V)) {
        f |= MC_FAULT_NONFINITE;
    } else {
        if (v_dc_V > limits->v_dc_max_V) {
            f |= MC_FAULT_DC_OVERVOLTAGE;
        }
        if (check_undervoltage && v_dc_V < limits->v_dc_min_V) {
            f |= MC_FAULT_DC_UNDERVOLTAGE;
        }
    }
    return f;
}
