/* Current-limit loop on the measured current (mc/current_limit.h). */
#include "mc/current_limit.h"

#include <math.h>

#include "mc/current_loop.h"
#include "mc/finite.h"

mc_status_t mc_current_limit_init_f32(mc_current_limit_f32_t *cl,
                                      const mc_current_limit_params_t *p)
{
    const float f[] = { p->limit_A, p->R_ohm, p->L_H, p->bandwidth_rad_s,
                        p->Ts_s };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (!(p->limit_A > 0.0f) || !(p->Ts_s > 0.0f) ||
        p->bandwidth_rad_s * p->Ts_s > MC_CURRENT_LOOP_WTS_MAX) {
        return MC_ERR_PARAM;
    }
    mc_current_pi_gains_t g;
    const mc_status_t st =
        mc_current_pi_design_f32(p->R_ohm, p->L_H, p->bandwidth_rad_s, &g);
    if (st != MC_OK) {
        return st;
    }
    *cl = (mc_current_limit_f32_t){
        .limit_A = p->limit_A,
        .limit_sq_A2 = p->limit_A * p->limit_A,
        .kp_V_per_A = g.kp_V_per_A,
        .ki_Ts_V_per_A = g.ki_V_per_As * p->Ts_s,
    };
    return MC_OK;
}

bool mc_current_limit_act_f32(mc_current_limit_f32_t *cl, float i_sq_A2,
                              float i_d_A, float i_q_A, float *v_d_V,
                              float *v_q_V)
{
    const float i_mag = sqrtf(i_sq_A2); /* >= 0 (or NaN: propagates) */
    const float e = i_mag - cl->limit_A;
    float u_int = cl->u_int_V + cl->ki_Ts_V_per_A * e;
    if (u_int < 0.0f) { /* wound back (a NaN is not clamped away) */
        u_int = 0.0f;
    }
    cl->u_int_V = u_int;
    const float u = ((e > 0.0f) ? cl->kp_V_per_A * e : 0.0f) + u_int;
    if (u == 0.0f || i_mag == 0.0f) {
        return false; /* nothing to correct, or no direction to correct */
    }
    const float g = u / i_mag; /* i_mag != 0 checked */
    *v_d_V -= g * i_d_A;
    *v_q_V -= g * i_q_A;
    return true;
}
