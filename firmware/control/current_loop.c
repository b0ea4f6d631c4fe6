/* Baseline d/q current loop (see mc/current_loop.h). */
#include "mc/current_loop.h"

#include <math.h>

mc_status_t mc_current_pi_design_f32(float R_ohm, float L_H, float w_c_rad_s,
                                     mc_current_pi_gains_t *out)
{
    if (!isfinite(R_ohm) || !isfinite(L_H) || !isfinite(w_c_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    if (R_ohm < 0.0f || L_H <= 0.0f || w_c_rad_s <= 0.0f) {
        return MC_ERR_PARAM;
    }
    /* Pole-zero cancellation: PI zero ki/kp = R/L = the plant pole. */
    out->kp_V_per_A = L_H * w_c_rad_s;
    out->ki_V_per_As = R_ohm * w_c_rad_s;
    return MC_OK;
}

mc_status_t mc_current_loop_init_f32(mc_current_loop_f32_t *cl,
                                     const mc_current_loop_params_t *p)
{
    const float m = p->cfg.modulation_margin;
    const float w_c = p->cfg.bandwidth_rad_s;
    if (!isfinite(p->psi_Wb) || !isfinite(m) || !isfinite(p->Ts_s) ||
        !isfinite(p->Lq_H) || !isfinite(w_c)) {
        return MC_ERR_NONFINITE;
    }
    if (p->psi_Wb < 0.0f || !(m > 0.0f) || m > 1.0f || !(p->Ts_s > 0.0f) ||
        w_c * p->Ts_s > MC_CURRENT_LOOP_WTS_MAX) {
        return MC_ERR_PARAM;
    }
    mc_current_pi_gains_t gd;
    mc_current_pi_gains_t gq;
    mc_status_t st = mc_current_pi_design_f32(p->R_ohm, p->Ld_H, w_c, &gd);
    if (st != MC_OK) {
        return st;
    }
    st = mc_current_pi_design_f32(p->R_ohm, p->Lq_H, w_c, &gq);
    if (st != MC_OK) {
        return st;
    }
    /* Placeholder limits: the step passes its own, from v_dc, every
     * sample (mc_current_loop_axis_f32). */
    st = mc_pi_init_f32(&cl->pi_d, gd.kp_V_per_A, gd.ki_V_per_As, p->Ts_s,
                        -1.0f, 1.0f);
    if (st != MC_OK) {
        return st;
    }
    st = mc_pi_init_f32(&cl->pi_q, gq.kp_V_per_A, gq.ki_V_per_As, p->Ts_s,
                        -1.0f, 1.0f);
    if (st != MC_OK) {
        return st;
    }
    cl->Ld_H = p->Ld_H;
    cl->Lq_H = p->Lq_H;
    cl->psi_Wb = p->psi_Wb;
    cl->v_max_per_V_dc = m * MC_INV_SQRT3_F;
    return MC_OK;
}

void mc_current_loop_reset_f32(mc_current_loop_f32_t *cl)
{
    mc_pi_reset_f32(&cl->pi_d, 0.0f);
    mc_pi_reset_f32(&cl->pi_q, 0.0f);
}

void mc_current_loop_preset_f32(mc_current_loop_f32_t *cl, float v_d_V,
                                float v_q_V, float i_d_A, float i_q_A,
                                float omega_e_rad_s)
{
    float ff_d;
    float ff_q;
    mc_current_loop_feed_forward_f32(cl, i_d_A, i_q_A, omega_e_rad_s, &ff_d,
                                     &ff_q);
    mc_pi_reset_f32(&cl->pi_d, v_d_V - ff_d);
    mc_pi_reset_f32(&cl->pi_q, v_q_V - ff_q);
}

mc_status_t mc_current_loop_step_f32(mc_current_loop_f32_t *cl, float i_d_A,
                                     float i_q_A, float i_d_ref_A,
                                     float i_q_ref_A, float omega_e_rad_s,
                                     float v_dc_V, mc_current_loop_out_t *out)
{
    out->v_d_V = 0.0f;
    out->v_q_V = 0.0f;
    out->saturated = false;
    if (!isfinite(v_dc_V)) {
        return MC_ERR_NONFINITE;
    }
    if (!(v_dc_V > 0.0f)) {
        return MC_ERR_RANGE;
    }
    const mc_current_loop_out_t o = mc_current_loop_step_unchecked_f32(
        cl, i_d_A, i_q_A, i_d_ref_A, i_q_ref_A, omega_e_rad_s, v_dc_V);
    if (!isfinite(o.v_d_V) || !isfinite(o.v_q_V)) {
        return MC_ERR_NONFINITE;
    }
    *out = o;
    return MC_OK;
}
