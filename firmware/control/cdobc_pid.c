/* Paper 002 noncascade PID baseline (Section IV: 23, 10, 0.0167), float32.
 * See mc/cdobc.h. */
#include "mc/cdobc.h"

#include <math.h>

mc_status_t mc_cdobc_pid_init_f32(mc_cdobc_pid_f32_t *pid, float kp_V_s,
                                  float ki_V, float kd_V_s2, float Ts_s,
                                  float c_qd_V_s, float v_max_V)
{
    if (!isfinite(kp_V_s) || !isfinite(ki_V) || !isfinite(kd_V_s2) ||
        !isfinite(Ts_s) || !isfinite(c_qd_V_s) || !isfinite(v_max_V)) {
        return MC_ERR_NONFINITE;
    }
    if (!(kp_V_s >= 0.0f) || !(ki_V >= 0.0f) || !(kd_V_s2 >= 0.0f) ||
        !(Ts_s > 0.0f) || !(Ts_s <= 1e-2f) || !(v_max_V > 0.0f)) {
        return MC_ERR_PARAM;
    }
    const float kd_Ts = kd_V_s2 / Ts_s; /* Ts > 0 */
    if (!isfinite(kd_Ts)) {
        return MC_ERR_PARAM;
    }
    *pid = (mc_cdobc_pid_f32_t){ .kp_V_s = kp_V_s,
                                 .ki_Ts_V = ki_V * Ts_s,
                                 .kd_Ts_V_s = kd_Ts,
                                 .c_qd_V_s = c_qd_V_s,
                                 .v_max_V = v_max_V };
    return MC_OK;
}

mc_status_t mc_cdobc_pid_reset_f32(mc_cdobc_pid_f32_t *pid, float omega_m_rad_s)
{
    if (!isfinite(omega_m_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    pid->integ_V = 0.0f;
    pid->omega_prev = omega_m_rad_s;
    return MC_OK;
}

mc_status_t mc_cdobc_pid_step_f32(mc_cdobc_pid_f32_t *pid, float omega_m_rad_s,
                                  float omega_ref_rad_s, float *v_q_V)
{
    const float e = omega_ref_rad_s - omega_m_rad_s;
    const float dw = omega_m_rad_s - pid->omega_prev;
    const float p_ff =
        pid->kp_V_s * e - pid->kd_Ts_V_s * dw + pid->c_qd_V_s * omega_m_rad_s;
    float integ = pid->integ_V + pid->ki_Ts_V * e;
    const float v = p_ff + integ;
    if (!isfinite(v)) {
        return MC_ERR_NONFINITE;
    }
    /* conditional integration: hold while pushing into the limit */
    if ((v > pid->v_max_V && e > 0.0f) || (v < -pid->v_max_V && e < 0.0f)) {
        integ = pid->integ_V;
    }
    const float u = p_ff + integ;
    pid->integ_V = integ;
    pid->omega_prev = omega_m_rad_s;
    *v_q_V = (u > pid->v_max_V) ? pid->v_max_V
                                : ((u < -pid->v_max_V) ? -pid->v_max_V : u);
    return MC_OK;
}
