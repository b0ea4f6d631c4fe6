/*
 * PI controller configuration. The per-sample step is inline in mc/pi.h.
 */
#include "mc/pi.h"

mc_status_t mc_pi_init_f32(mc_pi_f32_t *pi, float kp, float ki_per_s,
                           float Ts_s, float out_min, float out_max)
{
    if (!isfinite(kp) || !isfinite(ki_per_s) || !isfinite(Ts_s) ||
        !isfinite(out_min) || !isfinite(out_max)) {
        return MC_ERR_NONFINITE;
    }
    const float ki_Ts = ki_per_s * Ts_s;
    if (kp < 0.0f || ki_per_s < 0.0f || !(Ts_s > 0.0f) ||
        (kp == 0.0f && ki_Ts == 0.0f) || !isfinite(ki_Ts) ||
        !(out_min < out_max)) {
        return MC_ERR_PARAM;
    }
    pi->kp = kp;
    pi->ki_Ts = ki_Ts;
    pi->out_min = out_min;
    pi->out_max = out_max;
    pi->integrator =
        (out_min > 0.0f) ? out_min : ((out_max < 0.0f) ? out_max : 0.0f);
    return MC_OK;
}

void mc_pi_reset_f32(mc_pi_f32_t *pi, float integrator)
{
    pi->integrator = integrator;
}

mc_status_t mc_pi_set_limits_f32(mc_pi_f32_t *pi, float out_min, float out_max)
{
    if (!isfinite(out_min) || !isfinite(out_max)) {
        return MC_ERR_NONFINITE;
    }
    if (!(out_min < out_max)) {
        return MC_ERR_PARAM;
    }
    mc_pi_set_limits_unchecked_f32(pi, out_min, out_max);
    return MC_OK;
}
