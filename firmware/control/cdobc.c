/* Paper 002 regulator: init, start-up, coefficient swap and the float32
 * per-period step of (6), (8) (discrete), (9), (10) and the d-axis PI.
 * See mc/cdobc.h. */
#include "mc/cdobc.h"

#include <math.h>
#include <stddef.h>

mc_status_t mc_cdobc_init_f32(mc_cdobc_f32_t *ctl, const mc_cdobc_params_t *p,
                              float omega_ref0_rad_s)
{
    if (ctl == NULL || p == NULL) {
        return MC_ERR_PARAM;
    }
    mc_cdobc_design_t d;
    mc_status_t st = mc_cdobc_design_f64(p, (double)omega_ref0_rad_s, &d);
    if (st != MC_OK) {
        return st;
    }
    mc_cdobc_f32_t c = { 0 };
    st = mc_cdobc_coef_f32(&d, &c.coef);
    if (st != MC_OK) {
        return st;
    }
    st = mc_pi_init_f32(&c.pi_d, p->kp_d_V_A, p->ki_d_V_As, p->Ts_s,
                        -p->v_max_V, p->v_max_V);
    if (st != MC_OK) {
        return st;
    }
    c.np_Ld_H = (float)(d.n_p * (double)p->L_d_H);
    c.omega_min_rad_s = p->omega_min_rad_s;
    c.v_max_V = p->v_max_V;
    *ctl = c;
    return MC_OK;
}

mc_status_t mc_cdobc_reset_f32(mc_cdobc_f32_t *ctl, float omega_m_rad_s)
{
    if (!isfinite(omega_m_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    for (uint32_t i = 0; i < MC_CDOBC_N_MAX; ++i) {
        ctl->w[i] = 0.0f;
    }
    ctl->nu_prev = -omega_m_rad_s;
    ctl->v_prev = 0.0f;
    ctl->v_cur = 0.0f;
    mc_pi_reset_f32(&ctl->pi_d, 0.0f);
    return MC_OK;
}

mc_status_t mc_cdobc_set_coef_f32(mc_cdobc_f32_t *ctl,
                                  const mc_cdobc_coef_f32_t *c)
{
    if (c->n != ctl->coef.n) {
        return MC_ERR_PARAM;
    }
    ctl->coef = *c;
    return MC_OK;
}

bool mc_cdobc_needs_redesign_f32(const mc_cdobc_f32_t *ctl,
                                 float omega_ref_rad_s, float rel_tol)
{
    const float a = fabsf(omega_ref_rad_s);
    const float w = (a > ctl->omega_min_rad_s) ? a : ctl->omega_min_rad_s;
    /* |w - w_design| > tol w, false only when every value is finite */
    return !(fabsf(w - ctl->coef.omega_design_rad_s) <= rel_tol * w);
}

static float clampf(float x, float lim, bool *hit)
{
    *hit = (x > lim) || (x < -lim);
    return (x > lim) ? lim : ((x < -lim) ? -lim : x);
}

mc_status_t mc_cdobc_step_f32(mc_cdobc_f32_t *ctl, float omega_m_rad_s,
                              float omega_ref_rad_s, float i_d_A,
                              mc_cdobc_out_t *out)
{
    const mc_cdobc_coef_f32_t *k = &ctl->coef;
    const uint32_t n = k->n;
    /* finiteness of the inputs: x * 0 is +-0 for finite x, NaN else */
    if (!((omega_m_rad_s * 0.0f + omega_ref_rad_s * 0.0f + i_d_A * 0.0f) ==
          0.0f)) {
        return MC_ERR_NONFINITE;
    }
    /* observer (8), discrete: w += dPhi w + Gn nu_prev + Gu v_prev
     * + Ld (nu - nu_prev) */
    const float nu = -omega_m_rad_s;
    const float dnu = nu - ctl->nu_prev;
    float w[MC_CDOBC_N_MAX];
    float acc = 0.0f; /* finiteness accumulator */
    for (uint32_t i = 0; i < n; ++i) {
        float s = ctl->w[i] + k->Gn[i] * ctl->nu_prev + k->Gu[i] * ctl->v_prev +
                  k->Ld[i] * dnu;
        const float *row = &k->dPhi[i * n];
        for (uint32_t j = 0; j < n; ++j) {
            s += row[j] * ctl->w[j];
        }
        w[i] = s;
        acc += s * 0.0f;
    }
    /* (6) + (9) on the prediction, folded (mc/cdobc.h) */
    float v = k->k1 * omega_ref_rad_s + k->g_nu * nu + k->gu * ctl->v_cur;
    float d_hat = 0.0f;
    for (uint32_t i = 0; i < n; ++i) {
        v += k->g[i] * w[i];
        d_hat += k->h[i] * w[i]; /* model outputs: D of (5) */
    }
    /* (6) d-q coupling, (10) saturation */
    const float u_c = ctl->np_Ld_H * i_d_A * omega_m_rad_s;
    bool q_lim;
    const float v_q = clampf(v + u_c, ctl->v_max_V, &q_lim);
    /* d axis: PI on i_d* - i_d = -i_d (its own clamp) */
    mc_pi_f32_t pi = ctl->pi_d;
    const float v_d = mc_pi_step_f32(&pi, -i_d_A);
    const bool d_lim = !(v_d < ctl->v_max_V) || !(v_d > -ctl->v_max_V);
    acc += v * 0.0f + v_q * 0.0f + v_d * 0.0f;
    if (!(acc == 0.0f)) {
        return MC_ERR_NONFINITE;
    }
    /* commit; the observer sees the voltage actually applied */
    for (uint32_t i = 0; i < n; ++i) {
        ctl->w[i] = w[i];
    }
    ctl->pi_d = pi;
    ctl->v_prev = ctl->v_cur;
    ctl->v_cur = v_q - u_c;
    ctl->nu_prev = nu;
    out->v_q_V = v_q;
    out->v_d_V = v_d;
    out->v_q_unsat_V = v + u_c;
    out->d_hat = d_hat;
    out->q_limited = q_lim;
    out->d_limited = d_lim;
    return MC_OK;
}
