/* Paper 000 regulator: init, start-up, per-period step (float32) of the
 * internal model (7), control (12) and backward-Euler observer (13).
 * See mc/eeo.h. */
#include "mc/eeo.h"
#include "mc/finite.h"

#include <math.h>
#include <stddef.h>

void mc_eeo_params_paper000(mc_eeo_params_t *p, float Ts_s, uint32_t pole_pairs,
                            float j_kgm2, float rad_per_count)
{
    /* Section 6; g3 = 1/j +- A_g with A_g = 1e4 (1/(kg m^2)) */
    const float g3 = 1.0f / j_kgm2; /* j <= 0 or NaN: init rejects */
    *p = (mc_eeo_params_t){
        .Ts_s = Ts_s,
        .pole_pairs = pole_pairs,
        .rad_per_count = rad_per_count,
        .g1_min = 1.0f,
        .g3_min_per_kgm2 = g3 - 1e4f,
        .g3_max_per_kgm2 = g3 + 1e4f,
        .g3_per_kgm2 = g3,
        .g4_max = 1.0f,
        .L_k = { 1.0f, 1.0f, 1.0f },
        .kappa = 1e3f,
        .b_bar_Nm_per_Vs = 20.0f,
        .K = { -1.0f, -3.0f, -3.0f },
        .N_V = 1e7f,
        .v_q_max_V = 0.0f, /* the caller's drive limit */
        .n_w = 3u,
        .f_coef = { 1.0f, 3.0f, 3.0f }, /* (s + 1)^3 */
        .s_coef = { 0.0f, 1.0f, 0.0f }, /* s (s^2 + 1) */
        .input_delay_steps = 0u,
    };
}

mc_status_t mc_eeo_init_f32(mc_eeo_f32_t *ctl, const mc_eeo_params_t *p)
{
    const float scalars[] = { p->Ts_s,
                              p->rad_per_count,
                              p->g1_min,
                              p->g3_min_per_kgm2,
                              p->g3_max_per_kgm2,
                              p->g3_per_kgm2,
                              p->g4_max,
                              p->L_k[0],
                              p->L_k[1],
                              p->L_k[2],
                              p->kappa,
                              p->b_bar_Nm_per_Vs,
                              p->K[0],
                              p->K[1],
                              p->K[2],
                              p->N_V,
                              p->v_q_max_V };
    if (!mc_all_finite_f32(scalars,
                           (uint32_t)(sizeof scalars / sizeof scalars[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (p->n_w > MC_EEO_NW_MAX || p->input_delay_steps > 1u) {
        return MC_ERR_PARAM;
    }
    if (!mc_all_finite_f32(p->f_coef, p->n_w) ||
        !mc_all_finite_f32(p->s_coef, p->n_w)) {
        return MC_ERR_NONFINITE;
    }
    if (!(p->Ts_s > 0.0f) || !(p->Ts_s <= 0.1f) || p->pole_pairs < 1u ||
        p->pole_pairs > 1000u || !(p->rad_per_count > 0.0f) ||
        !(p->g1_min > 0.0f) || !(p->g3_min_per_kgm2 > 0.0f) ||
        !(p->g3_max_per_kgm2 >= p->g3_min_per_kgm2) ||
        !(p->g3_per_kgm2 >= p->g3_min_per_kgm2) ||
        !(p->g3_per_kgm2 <= p->g3_max_per_kgm2) || !(p->g4_max > 0.0f) ||
        !(p->L_k[0] > 0.0f) || !(p->L_k[1] > 0.0f) || !(p->L_k[2] > 0.0f) ||
        !(p->kappa > 0.0f) || p->b_bar_Nm_per_Vs == 0.0f || !(p->N_V > 0.0f) ||
        !(p->v_q_max_V > 0.0f)) {
        return MC_ERR_PARAM;
    }
    const double h = (double)p->Ts_s;
    const double g2 = (double)p->pole_pairs;
    /* (12) with ideal estimates gives xi3' = K xi: the chain polynomial
     * s^3 - K3 s^2 - K2 g3 s - K1 g2 g3 must be Hurwitz over [g3min,
     * g3max] (linear in g3: the ends suffice for these Routh terms) */
    const double g3_ends[2] = { (double)p->g3_min_per_kgm2,
                                (double)p->g3_max_per_kgm2 };
    for (uint32_t i = 0; i < 2u; ++i) {
        const double c[3] = { -(double)p->K[0] * g2 * g3_ends[i],
                              -(double)p->K[1] * g3_ends[i], -(double)p->K[2] };
        if (!mc_eeo_poly_is_hurwitz(3u, c)) {
            return MC_ERR_PARAM;
        }
    }
    /* Appendix A: chain g1..g4 = (1, n_p, g3, 1) */
    const double g_min[4] = { (double)p->g1_min, g2, (double)p->g3_min_per_kgm2,
                              0.0 };
    const double g_max[4] = { 0.0, g2, (double)p->g3_max_per_kgm2,
                              (double)p->g4_max };
    const double Lk[3] = { (double)p->L_k[0], (double)p->L_k[1],
                           (double)p->L_k[2] };
    double a[4];
    mc_status_t st = mc_eeo_gain_recursion(4u, g_min, g_max, Lk, a, NULL);
    if (st != MC_OK) {
        return st;
    }
    /* (13): l = (kappa a3, kappa^2 a2, kappa^3 a1, kappa^4 a0) */
    const double kap = (double)p->kappa;
    const double l[4] = { kap * a[3], kap * kap * a[2], kap * kap * kap * a[1],
                          kap * kap * kap * kap * a[0] };
    double m[4];
    st = mc_eeo_be_gains(h, g2, (double)p->g3_per_kgm2, l, m);
    if (st != MC_OK) {
        return st;
    }
    /* internal model (7) */
    double fc[MC_EEO_NW_MAX], sc[MC_EEO_NW_MAX], gam[MC_EEO_NW_MAX];
    double Dd[MC_EEO_NW_MAX * MC_EEO_NW_MAX], Ed[MC_EEO_NW_MAX];
    for (uint32_t i = 0; i < p->n_w; ++i) {
        fc[i] = (double)p->f_coef[i];
        sc[i] = (double)p->s_coef[i];
    }
    if (p->n_w > 0u) {
        st = mc_eeo_gamma_place(p->n_w, fc, sc, gam);
        if (st != MC_OK) {
            return st;
        }
        st = mc_eeo_companion_zoh(p->n_w, sc, h, Dd, Ed);
        if (st != MC_OK) {
            return st;
        }
    }
    mc_eeo_f32_t c = { 0 };
    bool ok = true;
    for (uint32_t i = 0; i < 4u; ++i) {
        ok = ok && mc_f64_to_f32(l[i], &c.l[i]) && mc_f64_to_f32(m[i], &c.m[i]);
    }
    for (uint32_t i = 0; i < p->n_w; ++i) {
        ok = ok && mc_f64_to_f32(gam[i], &c.gamma[i]) &&
             mc_f64_to_f32(Ed[i], &c.E[i]);
        for (uint32_t j = 0; j < p->n_w; ++j) {
            ok = ok && mc_f64_to_f32(Dd[i * p->n_w + j], &c.D[i * p->n_w + j]);
        }
    }
    /* 1 - m1 = 1 / (1 + w1) = m4 / w4 (mc/eeo.h), without cancellation */
    ok = ok && mc_f64_to_f32(m[3] / (h * l[3]), &c.m1c);
    const double inv_b = 1.0 / (double)p->b_bar_Nm_per_Vs; /* b_bar != 0 */
    ok = ok && mc_f64_to_f32(inv_b, &c.inv_b_bar) &&
         mc_f64_to_f32(g2 * (double)p->rad_per_count, &c.y_per_count);
    if (!ok) {
        return MC_ERR_PARAM;
    }
    c.h_s = p->Ts_s;
    c.g2 = (float)p->pole_pairs;
    c.g3_per_kgm2 = p->g3_per_kgm2;
    /* the float32 products the step and mc_eeo_set_g3_f32 use, once */
    c.h_g2 = c.h_s * c.g2;
    c.h_g3 = c.h_s * c.g3_per_kgm2;
    c.h_l[0] = c.h_s * c.l[0];
    c.h_l[1] = c.h_s * c.l[1];
    c.w34[1] = c.h_s * c.l[3];
    c.w34[0] = c.h_s * c.l[2] + c.h_s * c.w34[1];
    c.g3_min_per_kgm2 = p->g3_min_per_kgm2;
    c.g3_max_per_kgm2 = p->g3_max_per_kgm2;
    c.b_bar = p->b_bar_Nm_per_Vs;
    c.K[0] = p->K[0];
    c.K[1] = p->K[1];
    c.K[2] = p->K[2];
    c.N_V = p->N_V;
    c.v_q_max_V = p->v_q_max_V;
    c.n_w = p->n_w;
    c.delay = p->input_delay_steps;
    *ctl = c;
    return MC_OK;
}

mc_status_t mc_eeo_reset_f32(mc_eeo_f32_t *ctl, int32_t err_counts,
                             bool matched)
{
    const float y = (float)err_counts * ctl->y_per_count;
    if (!isfinite(y)) {
        return MC_ERR_NONFINITE;
    }
    for (uint32_t i = 0; i < MC_EEO_N_CHAIN; ++i) {
        ctl->x[i] = 0.0f;
    }
    for (uint32_t i = 0; i < MC_EEO_NW_MAX; ++i) {
        ctl->eta[0][i] = 0.0f; /* both halves */
        ctl->eta[1][i] = 0.0f;
        ctl->eta_c[0][i] = 0.0f;
        ctl->eta_c[1][i] = 0.0f;
    }
    ctl->im_sel = 0u;
    ctl->u_hist[0] = 0.0f;
    ctl->u_hist[1] = 0.0f;
    /* xi1_hat(0) = n_p (theta(0) - theta*): no first innovation */
    ctl->x[0] = matched ? y : 0.0f;
    ctl->r1 = ctl->x[0] - y;
    ctl->last_err_counts = err_counts;
    return MC_OK;
}

mc_status_t mc_eeo_set_g3_f32(mc_eeo_f32_t *ctl, float g3_per_kgm2)
{
    if (!isfinite(g3_per_kgm2)) {
        return MC_ERR_NONFINITE;
    }
    if (!(g3_per_kgm2 >= ctl->g3_min_per_kgm2) ||
        !(g3_per_kgm2 <= ctl->g3_max_per_kgm2)) {
        return MC_ERR_RANGE;
    }
    return mc_eeo_set_g3_core_f32(ctl, g3_per_kgm2) ? MC_OK : MC_ERR_RANGE;
}

mc_status_t mc_eeo_step_f32(mc_eeo_f32_t *ctl, int32_t err_counts,
                            mc_eeo_out_t *out)
{
    /* the core writes the spare half of eta also when it fails: on a
     * copy, so that nothing of *ctl changes then */
    mc_eeo_f32_t next = *ctl;
    mc_eeo_out_t o;
    if (!mc_eeo_step_core_f32(&next, err_counts, &o)) {
        return MC_ERR_NONFINITE;
    }
    *ctl = next;
    *out = o;
    return MC_OK;
}

mc_status_t mc_eeo_counts_init(mc_eeo_counts_t *c, uint32_t cpr, uint32_t raw)
{
    if (cpr < 4u || raw >= cpr) {
        return MC_ERR_PARAM;
    }
    c->pos_counts = (int64_t)raw;
    c->last_raw = raw;
    c->cpr = cpr;
    return MC_OK;
}
