/* Baseline speed PI (see mc/speed_loop.h). */
#include "mc/speed_loop.h"

#include <math.h>

/* PI zero at w_s / MC_SPEED_ZERO_RATIO gives the critically damped double
 * pole at -w_s/2 with an ideal current loop (see the header). */
#define MC_SPEED_ZERO_RATIO 4.0f

mc_status_t mc_speed_loop_init_f32(mc_speed_loop_f32_t *sl,
                                   const mc_speed_loop_params_t *p)
{
    if (!isfinite(p->J_kgm2) || !isfinite(p->B_Nm_s_rad) ||
        !isfinite(p->kt_Nm_per_A) || !isfinite(p->bandwidth_rad_s) ||
        !isfinite(p->i_q_max_A) || !isfinite(p->Ts_s)) {
        return MC_ERR_NONFINITE;
    }
    if (!(p->J_kgm2 > 0.0f) || p->B_Nm_s_rad < 0.0f ||
        !(p->kt_Nm_per_A > 0.0f) || !(p->bandwidth_rad_s > 0.0f) ||
        !(p->i_q_max_A > 0.0f) || !(p->Ts_s > 0.0f) ||
        p->bandwidth_rad_s * p->Ts_s > MC_SPEED_LOOP_WTS_MAX) {
        return MC_ERR_PARAM;
    }
    const float B_over_kt = p->B_Nm_s_rad / p->kt_Nm_per_A;
    if (!isfinite(B_over_kt)) {
        return MC_ERR_PARAM; /* friction feed-forward gain overflows */
    }
    const float kp = p->J_kgm2 * p->bandwidth_rad_s / p->kt_Nm_per_A;
    const float ki = kp * p->bandwidth_rad_s / MC_SPEED_ZERO_RATIO;
    const mc_status_t st =
        mc_pi_init_f32(&sl->pi, kp, ki, p->Ts_s, -p->i_q_max_A, p->i_q_max_A);
    if (st != MC_OK) {
        return st;
    }
    sl->B_over_kt = B_over_kt;
    sl->i_q_max_A = p->i_q_max_A;
    return MC_OK;
}

void mc_speed_loop_reset_f32(mc_speed_loop_f32_t *sl)
{
    mc_pi_reset_f32(&sl->pi, 0.0f);
}

float mc_speed_loop_step_f32(mc_speed_loop_f32_t *sl, float omega_m_ref_rad_s,
                             float omega_m_rad_s)
{
    /* Friction feed-forward; the PI gets the room left within +-i_q_max.
     * Limits that are not ordered (a non-finite ff, or one beyond the
     * float resolution of i_q_max) give NaN, as mc_pi_set_limits_f32
     * rejects them; a non-finite error gives NaN from the PI itself. */
    const float ff = sl->B_over_kt * omega_m_ref_rad_s;
    const float lo = -sl->i_q_max_A - ff;
    const float hi = sl->i_q_max_A - ff;
    if (!(lo < hi)) {
        return NAN;
    }
    mc_pi_set_limits_unchecked_f32(&sl->pi, lo, hi);
    return ff +
           mc_pi_step_unchecked_f32(&sl->pi, omega_m_ref_rad_s - omega_m_rad_s);
}
