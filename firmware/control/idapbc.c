/* IDA-PBC speed controller, paper 001 eq. (11). See mc/idapbc.h. */
#include "mc/idapbc.h"

#include <math.h>

float mc_idapbc_critical_damping_f32(uint32_t pole_pairs, float psi_Wb,
                                     float kt_Nm_per_A, float L_H, float J_kgm2)
{
    if (pole_pairs < 1u || !(psi_Wb > 0.0f) || !(kt_Nm_per_A > 0.0f) ||
        !(L_H > 0.0f) || !(J_kgm2 > 0.0f) || !isfinite(psi_Wb) ||
        !isfinite(kt_Nm_per_A) || !isfinite(L_H) || !isfinite(J_kgm2)) {
        return NAN;
    }
    /* a^2 = 4 b c with a = r/L, b c = n_p Phi kt / (L J); J > 0 checked,
     * the radicand is then positive (or +Inf/0 on overflow/underflow,
     * which the caller's init rejects) */
    return 2.0f *
           sqrtf((float)pole_pairs * psi_Wb * kt_Nm_per_A * L_H / J_kgm2);
}

mc_status_t mc_idapbc_init_f32(mc_idapbc_f32_t *ctl,
                               const mc_idapbc_params_t *p)
{
    if (!isfinite(p->R_ohm) || !isfinite(p->L_H) || !isfinite(p->psi_Wb) ||
        !isfinite(p->kt_Nm_per_A) || !isfinite(p->r_ohm)) {
        return MC_ERR_NONFINITE;
    }
    if (p->R_ohm < 0.0f || p->L_H <= 0.0f || p->psi_Wb <= 0.0f ||
        p->pole_pairs < 1u || p->kt_Nm_per_A <= 0.0f || p->r_ohm <= 0.0f) {
        return MC_ERR_PARAM;
    }
    const float np = (float)p->pole_pairs;
    const float inv_kt = 1.0f / p->kt_Nm_per_A; /* kt > 0 checked */
    if (!isfinite(inv_kt)) {
        return MC_ERR_PARAM;
    }
    ctl->R_minus_r_ohm = p->R_ohm - p->r_ohm;
    ctl->L_np_over_kt = p->L_H * np * inv_kt;
    ctl->np_psi_Wb = np * p->psi_Wb;
    ctl->r_over_kt = p->r_ohm * inv_kt;
    return MC_OK;
}

mc_status_t mc_idapbc_step_f32(const mc_idapbc_f32_t *ctl, float i_d_A,
                               float i_q_A, float omega_m_ref_rad_s,
                               float omega_m_hat_rad_s, float tau_L_hat_Nm,
                               float *v_d_V, float *v_q_V)
{
    const mc_idapbc_voltages_t v = mc_idapbc_voltages_unchecked_f32(
        ctl, i_d_A, i_q_A, omega_m_ref_rad_s, omega_m_hat_rad_s, tau_L_hat_Nm);
    /* any non-finite input propagates into v_d or v_q */
    if (!isfinite(v.v_d_V) || !isfinite(v.v_q_V)) {
        return MC_ERR_NONFINITE;
    }
    *v_d_V = v.v_d_V;
    *v_q_V = v.v_q_V;
    return MC_OK;
}

mc_status_t mc_idapbc_integral_design_f32(const mc_idapbc_params_t *p,
                                          float J_kgm2, float pole_rad_s,
                                          float *kp_Nms_per_rad,
                                          float *ki_Nm_per_rad)
{
    mc_idapbc_f32_t scratch;
    const mc_status_t st = mc_idapbc_init_f32(&scratch, p);
    if (st != MC_OK) {
        return st;
    }
    if (!isfinite(J_kgm2) || !isfinite(pole_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    if (!(J_kgm2 > 0.0f) || !(pole_rad_s > 0.0f)) {
        return MC_ERR_PARAM;
    }
    /* L > 0, J > 0 checked: a = r / L, bc = n_p Phi kt / (L J); a > 0 */
    const float a = p->r_ohm / p->L_H;
    const float bc =
        (float)p->pole_pairs * p->psi_Wb * p->kt_Nm_per_A / (p->L_H * J_kgm2);
    const float alpha = a - pole_rad_s;
    const float beta = alpha * alpha * bc / (a * a); /* damping ratio kept */
    const float kp = J_kgm2 * (beta + alpha * pole_rad_s - bc) / a;
    const float ki = J_kgm2 * beta * pole_rad_s / a;
    if (!isfinite(a) || !isfinite(bc) || !isfinite(beta) || !isfinite(kp) ||
        !isfinite(ki) || !(alpha > 0.0f)) {
        return MC_ERR_PARAM;
    }
    /* slowest rate of s^2 + alpha s + beta: alpha / 2 when complex,
     * (alpha - sqrt(alpha^2 - 4 beta)) / 2 when real (radicand >= 0 in
     * that branch) */
    const float disc = alpha * alpha - 4.0f * beta;
    const float slow =
        (disc > 0.0f) ? 0.5f * (alpha - sqrtf(disc)) : 0.5f * alpha;
    if (!(slow >= 2.0f * pole_rad_s) || kp < 0.0f || !(ki > 0.0f)) {
        return MC_ERR_PARAM;
    }
    *kp_Nms_per_rad = kp;
    *ki_Nm_per_rad = ki;
    return MC_OK;
}
