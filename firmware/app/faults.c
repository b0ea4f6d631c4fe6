/* Protection checks of one sample (see mc/faults.h). */
#include "mc/faults.h"

#include <math.h>

mc_status_t mc_fault_limits_validate(const mc_fault_limits_t *limits)
{
    if (!isfinite(limits->i_trip_A) || !isfinite(limits->v_dc_max_V) ||
        !isfinite(limits->v_dc_min_V)) {
        return MC_ERR_NONFINITE;
    }
    if (!(limits->i_trip_A > 0.0f) || limits->v_dc_min_V < 0.0f ||
        !(limits->v_dc_min_V < limits->v_dc_max_V)) {
        return MC_ERR_PARAM;
    }
    return MC_OK;
}

uint32_t mc_faults_check_sample(const mc_fault_limits_t *limits,
                                const float i_abc_A[3], float v_dc_V,
                                bool check_undervoltage)
{
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

bool mc_all_finite_f32(const float *x, uint32_t n)
{
    bool ok = true;
    for (uint32_t k = 0u; k < n; ++k) {
        ok = ok && isfinite(x[k]);
    }
    return ok;
}
