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

static bool all_finite(const float *x, uint32_t n)
{
    for (uint32_t i = 0; i < n; ++i) {
        if (!isfinite(x[i])) {
            return false;
        }
    }
    return true;
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
    if (!all_finite(scalars, (uint32_t)(sizeof scalars / sizeof scalars[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (p->n_w > MC_EEO_NW_MAX || p->input_delay_steps > 1u) {
        return MC_ERR_PARAM;
    }
    if (!all_finite(p->f_coef, p->n_w) || !all_finite(p->s_coef, p->n_w)) {
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
        ctl->eta[i] = 0.0f;
        ctl->eta_c[i] = 0.0f;
    }
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
    /* backward-Euler gains (mc/eeo.h): w = h M^-1 l, m = w / (1 + w1) */
    const float h = ctl->h_s;
    const float w4 = h * ctl->l[3];
    const float w3 = h * ctl->l[2] + h * w4;
    const float w2 = h * ctl->l[1] + h * g3_per_kgm2 * w3;
    const float w1 = h * ctl->l[0] + h * ctl->g2 * w2;
    const float den = 1.0f + w1; /* > 1 for the positive terms above */
    if (!isfinite(den) || !(den >= 1.0f)) {
        return MC_ERR_RANGE;
    }
    const float inv = 1.0f / den;
    ctl->m[0] = w1 * inv;
    ctl->m[1] = w2 * inv;
    ctl->m[2] = w3 * inv;
    ctl->m[3] = w4 * inv;
    ctl->m1c = inv;
    ctl->g3_per_kgm2 = g3_per_kgm2;
    return MC_OK;
}

static float clampf(float x, float lim, bool *hit)
{
    if (x > lim) {
        *hit = true;
        return lim;
    }
    if (x < -lim) {
        *hit = true;
        return -lim;
    }
    *hit = false;
    return x;
}

mc_status_t mc_eeo_step_f32(mc_eeo_f32_t *ctl, int32_t err_counts,
                            mc_eeo_out_t *out)
{
    const float h = ctl->h_s;
    /* y_k = g2 (theta - theta*), exact integer error times the scale */
    const float y = (float)err_counts * ctl->y_per_count;
    /* (13), backward Euler: predict the chain with the input of the last
     * interval ... */
    const float u_p = ctl->u_hist[ctl->delay];
    const float p4 = ctl->x[3];
    const float p3 = ctl->x[2] + h * (u_p + p4);
    const float p2 = ctl->x[1] + h * ctl->g3_per_kgm2 * p3;
    /* p1 = xi1_{k-1} + dp1; the innovation y_k - p1 is formed from the
     * exact integer increment of y and the small stored residual
     * r = xi1_hat - y (no difference of two large float32 numbers, whose
     * rounding the gain m4 ~ 3e5 would amplify) */
    const float dp1 = h * ctl->g2 * p2;
    const int64_t dc = (int64_t)err_counts - (int64_t)ctl->last_err_counts;
    const float dy = (float)dc * ctl->y_per_count;
    /* ... then correct every state by its gain times one innovation */
    const float e = dy - ctl->r1 - dp1;
    const float r1 = -ctl->m1c * e; /* xi1_k - y_k = (m1 - 1) e */
    float x[MC_EEO_N_CHAIN];
    x[0] = y + r1;
    x[1] = p2 + ctl->m[1] * e;
    x[2] = p3 + ctl->m[2] * e;
    x[3] = p4 + ctl->m[3] * e;
    /* (12): u_bar = sat_N((-sigma + K xi) / b_bar) */
    const float u_hat = ctl->inv_b_bar * (-x[3] + ctl->K[0] * x[0] +
                                          ctl->K[1] * x[1] + ctl->K[2] * x[2]);
    if (!isfinite(u_hat)) { /* also catches non-finite x */
        return MC_ERR_NONFINITE;
    }
    bool sat_n = false;
    bool lim = false;
    const float u_bar = clampf(u_hat, ctl->N_V, &sat_n);
    /* (7): v_q = Gamma eta + u_bar, clamped to the drive's limit */
    float gamma_eta = 0.0f;
    for (uint32_t i = 0; i < ctl->n_w; ++i) {
        gamma_eta += ctl->gamma[i] * ctl->eta[i];
    }
    const float v_q = clampf(gamma_eta + u_bar, ctl->v_q_max_V, &lim);
    const float u_app = v_q - gamma_eta; /* what the plant really got */
    /* eta_{k+1} = eta_k + D eta_k + E u_bar_app (exact ZOH) */
    float eta[MC_EEO_NW_MAX], eta_c[MC_EEO_NW_MAX];
    for (uint32_t i = 0; i < ctl->n_w; ++i) {
        float d = ctl->E[i] * u_app;
        for (uint32_t j = 0; j < ctl->n_w; ++j) {
            d += ctl->D[i * ctl->n_w + j] * ctl->eta[j];
        }
        /* compensated sum: the increments are O(Ts) of eta, so plain
         * float32 accumulation would drift (the bias mode integrates) */
        const float y_c = d - ctl->eta_c[i];
        const float t_c = ctl->eta[i] + y_c;
        eta_c[i] = (t_c - ctl->eta[i]) - y_c;
        eta[i] = t_c;
    }
    const float bu = ctl->b_bar * u_app;
    if (!isfinite(v_q) || !isfinite(bu) || !isfinite(r1) ||
        !all_finite(eta, ctl->n_w) || !all_finite(eta_c, ctl->n_w)) {
        return MC_ERR_NONFINITE;
    }
    for (uint32_t i = 0; i < MC_EEO_N_CHAIN; ++i) {
        ctl->x[i] = x[i];
    }
    ctl->r1 = r1;
    ctl->last_err_counts = err_counts;
    for (uint32_t i = 0; i < ctl->n_w; ++i) {
        ctl->eta[i] = eta[i];
        ctl->eta_c[i] = eta_c[i];
    }
    ctl->u_hist[1] = ctl->u_hist[0];
    ctl->u_hist[0] = bu;
    out->v_q_V = v_q;
    out->u_bar_V = u_bar;
    out->sat_N = sat_n;
    out->v_limited = lim;
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

mc_status_t mc_eeo_counts_update(mc_eeo_counts_t *c, uint32_t raw)
{
    if (raw >= c->cpr) {
        return MC_ERR_RANGE;
    }
    int64_t d = (int64_t)raw - (int64_t)c->last_raw;
    const int64_t cpr = (int64_t)c->cpr;
    /* shortest signed step: d in [-cpr/2, cpr/2) */
    if (d >= cpr / 2) {
        d -= cpr;
    } else if (d < -(cpr / 2)) {
        d += cpr;
    }
    c->pos_counts += d;
    c->last_raw = raw;
    return MC_OK;
}

mc_status_t mc_eeo_count_error(int64_t pos_counts, int64_t ref_counts,
                               int32_t *err_counts)
{
    /* pos - ref without int64 overflow: compare before subtracting */
    if ((ref_counts < 0 && pos_counts > INT64_MAX + ref_counts) ||
        (ref_counts > 0 && pos_counts < INT64_MIN + ref_counts)) {
        *err_counts = (pos_counts > ref_counts) ? INT32_MAX : INT32_MIN;
        return MC_ERR_RANGE;
    }
    const int64_t d = pos_counts - ref_counts;
    if (d > (int64_t)INT32_MAX || d < (int64_t)INT32_MIN) {
        *err_counts = (d > 0) ? INT32_MAX : INT32_MIN;
        return MC_ERR_RANGE;
    }
    *err_counts = (int32_t)d;
    return MC_OK;
}
