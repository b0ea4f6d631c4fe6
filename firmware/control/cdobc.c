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
        ctl->w_buf[0][i] = 0.0f;
        ctl->w_buf[1][i] = 0.0f;
    }
    ctl->w_sel = 0u;
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

/* Row i up to its (Ad - I) w terms: w_i + Gn_i nu_prev + Gu_i v_prev
 * + Ld_i (dnu - c . w). */
MC_STATIC_FORCEINLINE float row_start(const mc_cdobc_coef_f32_t *k,
                                      const float *w, uint32_t i, float nu_prev,
                                      float v_prev, float e)
{
    return w[i] + k->Gn[i] * nu_prev + k->Gu[i] * v_prev + k->Ld[i] * e;
}

float mc_cdobc_observe_f32(const mc_cdobc_coef_f32_t *k, const float *w,
                           float *w_next, float nu_prev, float v_prev,
                           float dnu, float v)
{
    const uint32_t n = k->n;
    /* the rank-one part (one dot product) and row x2 of Ad - I */
    float cw = 0.0f;
    float y0 = 0.0f;
    for (uint32_t j = 0; j < n; ++j) {
        cw += k->c[j] * w[j];
        y0 += k->a0[j] * w[j];
    }
    const float e = dnu - cw;
    w_next[0] = row_start(k, w, 0u, nu_prev, v_prev, e) + y0;
    v += k->g[0] * w_next[0];
    /* the harmonic models' 2 x 2 blocks */
    uint32_t s = 1u;
    for (uint32_t b = 0; b < k->n_harm; ++b, s += 2u) {
        const float *m = k->harm[b];
        const float w0 = w[s];
        const float w1 = w[s + 1u];
        const float r0 =
            row_start(k, w, s, nu_prev, v_prev, e) + (m[0] * w0 + m[1] * w1);
        const float r1 = row_start(k, w, s + 1u, nu_prev, v_prev, e) +
                         (m[2] * w0 + m[3] * w1);
        w_next[s] = r0;
        w_next[s + 1u] = r1;
        v += k->g[s] * r0;
        v += k->g[s + 1u] * r1;
    }
    /* the polynomial's block */
    for (uint32_t i = 0; i < k->poly_order; ++i) {
        const float *row = &k->poly[i * MC_CDOBC_POLY_MAX];
        float y = 0.0f;
        for (uint32_t j = 0; j < k->poly_order; ++j) {
            y += row[j] * w[s + j];
        }
        const float r = row_start(k, w, s + i, nu_prev, v_prev, e) + y;
        w_next[s + i] = r;
        v += k->g[s + i] * r;
    }
    return v;
}

mc_status_t mc_cdobc_step_f32(mc_cdobc_f32_t *ctl, float omega_m_rad_s,
                              float omega_ref_rad_s, float i_d_A,
                              mc_cdobc_out_t *out)
{
    /* the core writes the spare half of w also when it fails: on a copy,
     * so that nothing of *ctl changes then */
    mc_cdobc_f32_t next = *ctl;
    mc_cdobc_out_t o;
    if (!mc_cdobc_step_core_f32(&next, omega_m_rad_s, omega_ref_rad_s, i_d_A,
                                &o)) {
        return MC_ERR_NONFINITE;
    }
    /* model outputs of the new state: D of (5) */
    const float *w = mc_cdobc_state_f32(&next);
    float d_hat = 0.0f;
    for (uint32_t i = 0; i < next.coef.n; ++i) {
        d_hat += next.coef.h[i] * w[i];
    }
    o.d_hat = d_hat;
    *ctl = next;
    *out = o;
    return MC_OK;
}
