/* Paper 002 regulator: parameters, exact ZOH discretisation of (5)/(7) at
 * the speed reference, observer and controller gains, folding of (9) into
 * the step's coefficients. Design time (double). See mc/cdobc.h. */
#include "mc/cdobc.h"
#include "mc/finite.h"

#include <math.h>
#include <stddef.h>

#include "mc/zoh.h"

enum { NM = MC_CDOBC_N_MAX, NF = MC_CDOBC_N_MAX + 1 };

void mc_cdobc_params_paper002(mc_cdobc_params_t *p, float Ts_s,
                              mc_cdobc_kind_t kind)
{
    *p = (mc_cdobc_params_t){
        .Ts_s = Ts_s,
        .pole_pairs = 4u,
        .psi_f_Wb = 0.084f,
        .L_q_H = 26e-3f,
        .L_d_H = 26e-3f,
        .R_ohm = 9.7f,
        .J_kgm2 = 1.35e-4f,
        .B_Nms_rad = 7.4e-5f,
        .placement = MC_CDOBC_PLACE_ROBUST,
        .ctl_pole_rad_s = 200.0f,
        .obs_pole_rad_s = 520.0f,
        .harm_zeta = 0.03f,
        .omega_min_rad_s = 10.0f,
        .v_max_V = 200.0f,
        .kp_d_V_A = 120.0f,
        .ki_d_V_As = 240.0f,
    };
    const mc_cdobc_harm_t dead = { MC_CDOBC_ELEC, 6u, 0.0f }; /* dead time */
    const mc_cdobc_harm_t cog = { MC_CDOBC_MECH, 32u, 0.0f }; /* Q = 32 */
    if (kind != MC_CDOBC_KIND_GPIOBC) {
        p->models.n_harm = 2u;
        p->models.harm[0] = dead;
        p->models.harm[1] = cog;
    }
    if (kind != MC_CDOBC_KIND_HDOBC) {
        p->models.poly_order = 2u;
    }
}

mc_status_t mc_cdobc_params_check(const mc_cdobc_params_t *p)
{
    const float v[] = { p->Ts_s,      p->psi_f_Wb,        p->L_q_H,
                        p->L_d_H,     p->R_ohm,           p->J_kgm2,
                        p->B_Nms_rad, p->ctl_pole_rad_s,  p->obs_pole_rad_s,
                        p->harm_zeta, p->omega_min_rad_s, p->v_max_V,
                        p->kp_d_V_A,  p->ki_d_V_As };
    for (uint32_t i = 0; i < (uint32_t)(sizeof v / sizeof v[0]); ++i) {
        if (!isfinite(v[i])) {
            return MC_ERR_NONFINITE;
        }
    }
    if (!(p->Ts_s > 0.0f) || !(p->Ts_s <= 1e-2f) || !(p->psi_f_Wb > 0.0f) ||
        !(p->L_q_H > 0.0f) || !(p->L_d_H > 0.0f) || !(p->R_ohm > 0.0f) ||
        !(p->J_kgm2 > 0.0f) || !(p->B_Nms_rad >= 0.0f) ||
        !(p->ctl_pole_rad_s > 0.0f) || !(p->obs_pole_rad_s > 0.0f) ||
        !(p->omega_min_rad_s > 0.0f) || !(p->v_max_V > 0.0f) ||
        !(p->kp_d_V_A >= 0.0f) || !(p->ki_d_V_As >= 0.0f) ||
        !(p->kp_d_V_A + p->ki_d_V_As > 0.0f) ||
        (p->placement != MC_CDOBC_PLACE_LITERAL &&
         p->placement != MC_CDOBC_PLACE_ROBUST)) {
        return MC_ERR_PARAM;
    }
    if (p->placement == MC_CDOBC_PLACE_ROBUST &&
        (!(p->harm_zeta > 0.0f) || !(p->harm_zeta < 1.0f))) {
        return MC_ERR_PARAM;
    }
    return mc_cdobc_models_check(&p->models, p->pole_pairs);
}

/* desired continuous observer poles (mc/cdobc.h, placements) */
static void observer_poles(const mc_cdobc_params_t *p, const double *w,
                           double *re, double *im)
{
    const mc_cdobc_models_t *m = &p->models;
    const uint32_t n = mc_cdobc_models_order(m);
    const double po = -(double)p->obs_pole_rad_s;
    for (uint32_t i = 0; i < n; ++i) {
        re[i] = po;
        im[i] = 0.0;
    }
    if (p->placement == MC_CDOBC_PLACE_ROBUST) {
        for (uint32_t i = 0; i < m->n_harm; ++i) {
            /* (0, 1) checked */
            const double z = (double)((m->harm[i].zeta > 0.0f) ? m->harm[i].zeta
                                                               : p->harm_zeta);
            re[2u * i] = -z * w[i];
            re[2u * i + 1u] = -z * w[i];
            im[2u * i] = w[i] * sqrt(1.0 - z * z);
            im[2u * i + 1u] = -im[2u * i];
        }
    }
}

/* the poles of s mapped to the scaled delta plane: (exp(p Ts) - 1) /
 * (Ts W), then the monic polynomial with those roots */
static mc_status_t delta_poly(uint32_t n, const double *re, const double *im,
                              double Ts, double W, double *coef)
{
    double dr[NM], di[NM];
    for (uint32_t i = 0; i < n; ++i) {
        const double e = exp(re[i] * Ts);
        /* expm1 keeps the small real part exact */
        dr[i] = (expm1(re[i] * Ts) * cos(im[i] * Ts) -
                 2.0 * pow(sin(0.5 * im[i] * Ts), 2.0)) /
                (Ts * W);
        di[i] = e * sin(im[i] * Ts) / (Ts * W);
    }
    return mc_cdobc_poly_from_roots(n, dr, di, coef);
}

mc_status_t mc_cdobc_design_f64(const mc_cdobc_params_t *p,
                                double omega_ref_rad_s, mc_cdobc_design_t *d)
{
    if (!isfinite(omega_ref_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    mc_status_t st = mc_cdobc_params_check(p);
    if (st != MC_OK) {
        return st;
    }
    const mc_cdobc_models_t *m = &p->models;
    const uint32_t n = mc_cdobc_models_order(m);
    const uint32_t nf = n + 1u;
    mc_cdobc_design_t r = { 0 };
    r.n = n;
    r.n_harm = m->n_harm;
    r.poly_order = m->poly_order;
    r.Ts_s = (double)p->Ts_s;
    r.n_p = (double)p->pole_pairs;
    r.J_kgm2 = (double)p->J_kgm2;
    r.R_ohm = (double)p->R_ohm;
    r.L_q_H = (double)p->L_q_H;
    r.psi_f_Wb = (double)p->psi_f_Wb;
    r.B_Nms_rad = (double)p->B_Nms_rad;
    r.omega_design_rad_s =
        fmax(fabs(omega_ref_rad_s), (double)p->omega_min_rad_s);
    r.b1 = 1.5 * r.n_p * r.psi_f_Wb / r.J_kgm2;             /* (5) */
    r.a_per_s = r.B_Nms_rad / r.J_kgm2 + r.R_ohm / r.L_q_H; /* (5) */
    r.c_qd_V_s = 2.0 * r.B_Nms_rad * r.R_ohm / (3.0 * r.n_p * r.psi_f_Wb) +
                 r.n_p * r.psi_f_Wb; /* (6), i_d term added per step */
    const double Ts = r.Ts_s;

    double A[NM * NM];
    uint32_t level[NM];
    mc_cdobc_models_build(m, p->pole_pairs, r.omega_design_rad_s, r.a_per_s, A,
                          level, r.h, r.w_rad_s);
    for (uint32_t i = 0; i < m->n_harm; ++i) {
        /* a model at or above a quarter of the sampling rate: the glue
         * must drop it at this speed */
        if (!(r.w_rad_s[i] * Ts < 0.5 * 3.14159265358979323846)) {
            return MC_ERR_RANGE;
        }
    }
    observer_poles(p, r.w_rad_s, r.obs_re, r.obs_im);

    /* scale W: largest rate of the problem */
    double W = fmax((double)p->obs_pole_rad_s, (double)p->ctl_pole_rad_s);
    for (uint32_t i = 0; i < m->n_harm; ++i) {
        W = fmax(W, r.w_rad_s[i]);
    }
    /* augmented (nu, w), nu = -omega (x1 = omega* + nu), x = T xs:
     * t(nu) = b1 / W, t(w_i) = W^level, t(v) = L W; scaled entries are
     * O(W) (mc/cdobc.h) */
    double t[NF] = { 0.0 }, Af[NF * NF] = { 0.0 }, gf[NF] = { 0.0 };
    t[0] = r.b1 / W;
    for (uint32_t i = 0; i < n; ++i) {
        t[1u + i] = pow(W, (double)level[i]);
    }
    const double tu = r.L_q_H * W;
    Af[1] = r.b1 * t[1] / t[0]; /* nu' = b1 x2 */
    /* x2' = -a x2 + D - (v - c_qd omega) / L, omega = -nu */
    Af[nf] = -(r.c_qd_V_s / r.L_q_H) * t[0] / t[1];
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            Af[(1u + i) * nf + 1u + j] = A[i * n + j] * t[1u + j] / t[1u + i];
        }
    }
    gf[1] = -(1.0 / r.L_q_H) * tu / t[1];
    for (uint32_t i = 0; i < nf * nf; ++i) {
        r.Acs[i] = Af[i];
    }
    for (uint32_t i = 0; i < nf; ++i) {
        r.t[i] = t[i];
    }
    double Ds[NF * NF], Es[NF];
    st = mc_zoh_f64(nf, Af, gf, Ts, Ds, Es);
    if (st != MC_OK) {
        return st;
    }
    /* physical discrete model */
    r.a_nn = 1.0 + Ds[0];
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            r.Ad[i * n + j] =
                ((i == j) ? 1.0 : 0.0) +
                Ds[(1u + i) * nf + 1u + j] * t[1u + i] / t[1u + j];
        }
        r.Bd2[i] = Es[1u + i] * t[1u + i] / tu;
        r.c[i] = Ds[1u + i] * t[0] / t[1u + i];
        r.a_wn[i] = Ds[(1u + i) * nf] * t[1u + i] / t[0];
    }
    r.Bd1 = Es[0] * t[0] / tu;

    /* observer: Ackermann in the scaled delta form */
    double Am[NM * NM], cm[NM], coef[NM], ls[NM];
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            Am[i * n + j] = Ds[(1u + i) * nf + 1u + j] / (Ts * W);
        }
        cm[i] = Ds[1u + i] / (Ts * W);
    }
    st = delta_poly(n, r.obs_re, r.obs_im, Ts, W, coef);
    if (st == MC_OK) {
        st = mc_cdobc_ackermann_f64(n, Am, cm, coef, ls);
    }
    if (st != MC_OK) {
        return st;
    }
    for (uint32_t i = 0; i < n; ++i) {
        r.Ld[i] = ls[i] * t[1u + i] / t[0]; /* w_i += Ld_i dnu */
    }

    /* controller: dual Ackermann on the scaled delta (nu, x2) block,
     * transposed (back-EMF and friction coupling included) */
    const double Ax[4] = { Ds[0] / (Ts * W), Ds[nf] / (Ts * W),
                           Ds[1] / (Ts * W), Ds[nf + 1u] / (Ts * W) };
    const double bx[2] = { Es[0] / (Ts * W), Es[1] / (Ts * W) };
    const double cre[2] = { -(double)p->ctl_pole_rad_s,
                            -(double)p->ctl_pole_rad_s };
    const double cim[2] = { 0.0, 0.0 };
    double ccoef[2], ks[2];
    st = delta_poly(2u, cre, cim, Ts, W, ccoef);
    if (st == MC_OK) {
        st = mc_cdobc_ackermann_f64(2u, Ax, bx, ccoef, ks);
    }
    if (st != MC_OK) {
        return st;
    }
    /* v = c_qd omega* - K (x1p, x2p) + f . dp; with u_qd = c_qd omega_p
     * (6) and u_qi = k1 x1p + k2 x2p + f . dp (9): k1 = c_qd - K1,
     * k2 = -K2 */
    const double K1 = ks[0] * tu / t[0], K2 = ks[1] * tu / t[1];
    r.k1 = r.c_qd_V_s - K1;
    r.k2 = -K2;

    /* (9) on the one-step prediction, folded (mc/cdobc.h) */
    const double b20 = r.Bd2[0];
    if (!(fabs(b20) > 0.0)) {
        return MC_ERR_PARAM;
    }
    double f[NM] = { 0.0 };
    for (uint32_t j = 1; j < n; ++j) {
        f[j] = -r.Ad[j] / b20; /* Ad[0][j] */
    }
    r.g_nu = -K1 * r.a_nn - K2 * r.a_wn[0];
    for (uint32_t j = 0; j < n; ++j) {
        double s = -K1 * r.c[j] - K2 * r.Ad[j];
        for (uint32_t i = 1; i < n; ++i) {
            s += f[i] * r.Ad[i * n + j];
        }
        r.g[j] = s;
        r.g_nu += f[j] * r.a_wn[j];
    }
    r.gu = -K1 * r.Bd1 - K2 * b20;
    for (uint32_t i = 0; i < n; ++i) {
        if (!isfinite(r.g[i]) || !isfinite(r.Ld[i])) {
            return MC_ERR_PARAM;
        }
    }
    if (!isfinite(r.gu) || !isfinite(r.k1) || !isfinite(r.k2) ||
        !isfinite(r.g_nu)) {
        return MC_ERR_PARAM;
    }
    *d = r;
    return MC_OK;
}

/* Where entry (i, j) of Ad - I goes in the float32 coefficients
 * (mc_cdobc_coef_f32_t): row x2, a harmonic model's block or the
 * polynomial's block; NULL outside the structure. */
static float *structured_entry(mc_cdobc_coef_f32_t *r, uint32_t i, uint32_t j)
{
    const uint32_t s_poly = 1u + 2u * r->n_harm;
    if (i == 0u) {
        return &r->a0[j];
    }
    if (i < s_poly) {
        const uint32_t b = (i - 1u) / 2u;
        const uint32_t s = 1u + 2u * b;
        return (j == s || j == s + 1u) ? &r->harm[b][2u * (i - s) + (j - s)]
                                       : NULL;
    }
    return (j >= s_poly)
               ? &r->poly[(i - s_poly) * MC_CDOBC_POLY_MAX + (j - s_poly)]
               : NULL;
}

mc_status_t mc_cdobc_coef_f32(const mc_cdobc_design_t *d,
                              mc_cdobc_coef_f32_t *c)
{
    const uint32_t n = d->n;
    if (n < 1u || n > MC_CDOBC_N_MAX || d->n_harm > MC_CDOBC_HARM_MAX ||
        d->poly_order > MC_CDOBC_POLY_MAX ||
        n != 1u + 2u * d->n_harm + d->poly_order) {
        return MC_ERR_PARAM;
    }
    mc_cdobc_coef_f32_t r = { 0 };
    r.n = n;
    r.n_harm = d->n_harm;
    r.poly_order = d->poly_order;
    bool ok = true;
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            /* Ad - I, exact for the model blocks */
            const double v = d->Ad[i * n + j] - ((i == j) ? 1.0 : 0.0);
            float *dst = structured_entry(&r, i, j);
            ok = ok && (v == 0.0 || (dst != NULL && mc_f64_to_f32(v, dst)));
        }
        ok = ok && (d->c[i] == 0.0 || mc_f64_to_f32(d->c[i], &r.c[i]));
        const double gu = d->Bd2[i] - d->Ld[i] * d->Bd1;
        ok = ok && (gu == 0.0 || mc_f64_to_f32(gu, &r.Gu[i]));
        /* nu_{k-1} term of the update written with dnu = nu_k - nu_{k-1}:
         * a_wn - Ld a_nn + Ld = a_wn - Ld (a_nn - 1) */
        const double gn = d->a_wn[i] - d->Ld[i] * (d->a_nn - 1.0);
        ok = ok && (gn == 0.0 || mc_f64_to_f32(gn, &r.Gn[i]));
        ok = ok && (d->Ld[i] == 0.0 || mc_f64_to_f32(d->Ld[i], &r.Ld[i]));
        ok = ok && (d->g[i] == 0.0 || mc_f64_to_f32(d->g[i], &r.g[i]));
        r.h[i] = (float)d->h[i]; /* 0 or 1 */
    }
    ok = ok && mc_f64_to_f32(d->gu, &r.gu) && mc_f64_to_f32(d->k1, &r.k1) &&
         mc_f64_to_f32(d->g_nu, &r.g_nu) &&
         mc_f64_to_f32(d->omega_design_rad_s, &r.omega_design_rad_s);
    if (!ok) {
        return MC_ERR_PARAM;
    }
    *c = r;
    return MC_OK;
}
