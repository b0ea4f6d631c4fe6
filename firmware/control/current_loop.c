/* Baseline d/q current loop (see mc/current_loop.h). */
#include "mc/current_loop.h"

#include <math.h>

#include "mc/clarke.h"

/* Smallest q-axis room, as a fraction of v_max, when the d axis takes the
 * whole voltage circle: keeps the q PI limits a proper interval
 * (out_min < out_max). The resulting |v_dq| exceeds v_max by at most
 * 5e-9 v_max (relative), far below float resolution of the duties. */
#define MC_CL_Q_ROOM_MIN 1.0e-4f

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
    /* Placeholder limits; the step sets them from v_dc every sample. */
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
    cl->modulation_margin = m;
    return MC_OK;
}

void mc_current_loop_reset_f32(mc_current_loop_f32_t *cl)
{
    mc_pi_reset_f32(&cl->pi_d, 0.0f);
    mc_pi_reset_f32(&cl->pi_q, 0.0f);
}

/* Decoupling feed-forward (rotor-frame voltage equations):
 * ff_d = -omega_e Lq i_q, ff_q = omega_e (Ld i_d + psi). */
static void feed_forward(const mc_current_loop_f32_t *cl, float i_d_A,
                         float i_q_A, float omega_e_rad_s, float *ff_d_V,
                         float *ff_q_V)
{
    *ff_d_V = -omega_e_rad_s * cl->Lq_H * i_q_A;
    *ff_q_V = omega_e_rad_s * (cl->Ld_H * i_d_A + cl->psi_Wb);
}

void mc_current_loop_preset_f32(mc_current_loop_f32_t *cl, float v_d_V,
                                float v_q_V, float i_d_A, float i_q_A,
                                float omega_e_rad_s)
{
    float ff_d;
    float ff_q;
    feed_forward(cl, i_d_A, i_q_A, omega_e_rad_s, &ff_d, &ff_q);
    mc_pi_reset_f32(&cl->pi_d, v_d_V - ff_d);
    mc_pi_reset_f32(&cl->pi_q, v_q_V - ff_q);
}

/* One axis: the PI output is limited to the room the feed-forward leaves
 * within +-v_lim_V (anti-windup, mc/pi.h), *v_V = PI(error) + ff. *sat
 * tells that the PI sits on a limit. The limits are finite and ordered
 * whenever the inputs are finite (v_lim_V > 0); a non-finite input
 * reaches *v_V, which the caller checks. */
static void axis_step(mc_pi_f32_t *pi, float v_lim_V, float ff_V, float error_A,
                      float *v_V, bool *sat)
{
    const float lo = -v_lim_V - ff_V;
    const float hi = v_lim_V - ff_V;
    mc_pi_set_limits_unchecked_f32(pi, lo, hi);
    const float u = mc_pi_step_f32(pi, error_A);
    *v_V = u + ff_V;
    *sat = (u <= lo) || (u >= hi);
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
    const float v_max = cl->modulation_margin * v_dc_V * MC_INV_SQRT3_F;

    float ff_d;
    float ff_q;
    feed_forward(cl, i_d_A, i_q_A, omega_e_rad_s, &ff_d, &ff_q);

    /* d axis first: the PI may use what the feed-forward leaves. */
    float v_d;
    bool sat_d;
    axis_step(&cl->pi_d, v_max, ff_d, i_d_ref_A - i_d_A, &v_d, &sat_d);

    /* q axis: the rest of the circle. */
    const float room_sq = v_max * v_max - v_d * v_d;
    const float room_min = MC_CL_Q_ROOM_MIN * v_max;
    const float v_q_max =
        (room_sq > room_min * room_min) ? sqrtf(room_sq) : room_min;
    float v_q;
    bool sat_q;
    axis_step(&cl->pi_q, v_q_max, ff_q, i_q_ref_A - i_q_A, &v_q, &sat_q);

    if (!isfinite(v_d) || !isfinite(v_q)) {
        return MC_ERR_NONFINITE;
    }
    out->v_d_V = v_d;
    out->v_q_V = v_q;
    out->saturated = sat_d || sat_q;
    return MC_OK;
}
