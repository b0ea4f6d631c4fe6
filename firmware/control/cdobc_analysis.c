/* Paper 002 regulator, design-time analysis (double): frequency response
 * of the disturbance estimation error and the spectral radius of the
 * discrete closed loop with a mismatched plant. See mc/cdobc.h. */
#include "mc/cdobc.h"

#include <math.h>
#include <stddef.h>

#include "mc/zoh.h"

enum { NM = MC_CDOBC_N_MAX, NL = MC_CDOBC_LOOP_MAX };

mc_status_t mc_cdobc_est_error_gain(const mc_cdobc_design_t *d, uint32_t n_f,
                                    const double *f_Hz, double *gain)
{
    const uint32_t n = d->n;
    if (n < 1u || n > NM || n_f > 1000u || !(d->Ts_s > 0.0)) {
        return MC_ERR_PARAM;
    }
    const double nyq = 0.5 / d->Ts_s;
    for (uint32_t k = 0; k < n_f; ++k) {
        if (!isfinite(f_Hz[k])) {
            return MC_ERR_NONFINITE;
        }
        if (!(f_Hz[k] >= 0.0) || !(f_Hz[k] < nyq)) {
            return MC_ERR_RANGE;
        }
    }
    const uint32_t nf = n + 1u, ne = n + 3u;
    for (uint32_t k = 0; k < n_f; ++k) {
        const double wk = 2.0 * 3.14159265358979323846 * f_Hz[k];
        /* exact effect of d = cos(wk t) over one period (scaled model;
         * d enters x2' with 1 and t(x2) = 1) */
        double M[(NM + 3) * (NM + 3)] = { 0.0 }, Dm[(NM + 3) * (NM + 3)];
        double g0[NM + 3] = { 0.0 }, E0[NM + 3];
        for (uint32_t i = 0; i < nf; ++i) {
            for (uint32_t j = 0; j < nf; ++j) {
                M[i * ne + j] = d->Acs[i * nf + j];
            }
        }
        M[ne + nf] = 1.0; /* into x2' (t(x2) = 1) */
        M[nf * ne + nf + 1u] = -wk;
        M[(nf + 1u) * ne + nf] = wk;
        mc_status_t st = mc_zoh_f64(ne, M, g0, d->Ts_s, Dm, E0);
        if (st != MC_OK) {
            return st;
        }
        const double th = wk * d->Ts_s;
        const double zr = cos(th), zi = sin(th);
        /* (zI - Phi) v = b as the real system [Zr -Zi; Zi Zr] */
        const uint32_t m2 = 2u * n;
        double A2[4 * NM * NM] = { 0.0 }, b[2 * NM] = { 0.0 };
        const double gnc = Dm[nf] * d->t[0], gns = Dm[nf + 1u] * d->t[0];
        for (uint32_t i = 0; i < n; ++i) {
            for (uint32_t j = 0; j < n; ++j) {
                const double re = ((i == j) ? zr : 0.0) -
                                  (d->Ad[i * n + j] - d->Ld[i] * d->c[j]);
                A2[i * m2 + j] = re;
                A2[(n + i) * m2 + n + j] = re;
            }
            A2[i * m2 + n + i] = -zi;
            A2[(n + i) * m2 + i] = zi;
            const double gc = Dm[(1u + i) * ne + nf] * d->t[1u + i];
            const double gs = Dm[(1u + i) * ne + nf + 1u] * d->t[1u + i];
            b[i] = gc - d->Ld[i] * gnc;        /* phasor (1, -j): real */
            b[n + i] = -(gs - d->Ld[i] * gns); /* imaginary */
        }
        st = mc_cdobc_solve_f64(m2, A2, b);
        if (st != MC_OK) {
            return st;
        }
        double gr = 1.0, gi = 0.0;
        for (uint32_t i = 0; i < n; ++i) {
            gr += d->h[i] * b[i];
            gi += d->h[i] * b[n + i];
        }
        gain[k] = hypot(gr, gi);
    }
    return MC_OK;
}

mc_status_t mc_cdobc_loop_matrix(const mc_cdobc_design_t *d,
                                 const mc_cdobc_plant_factors_t *f,
                                 uint32_t *dim, double *Acl)
{
    const uint32_t n = d->n;
    if (n < 1u || n > NM) {
        return MC_ERR_PARAM;
    }
    if (!isfinite(f->J) || !isfinite(f->R) || !isfinite(f->L) ||
        !isfinite(f->Kt)) {
        return MC_ERR_NONFINITE;
    }
    if (!(f->J > 0.0) || !(f->R > 0.0) || !(f->L > 0.0) || !(f->Kt > 0.0)) {
        return MC_ERR_PARAM;
    }
    /* true plant (omega, i_q), input v_q */
    const double J = d->J_kgm2 * f->J, R = d->R_ohm * f->R;
    const double L = d->L_q_H * f->L, psi = d->psi_f_Wb * f->Kt;
    const double Mp[4] = { -d->B_Nms_rad / J, 1.5 * d->n_p * psi / J,
                           -d->n_p * psi / L, -R / L };
    const double gp[2] = { 0.0, 1.0 / L };
    double Dp[4], Ep[2];
    const mc_status_t st = mc_zoh_f64(2u, Mp, gp, d->Ts_s, Dp, Ep);
    if (st != MC_OK) {
        return st;
    }
    /* state (omega, i_q, v_prev, v_cur, nu_prev, w_0 .. w_n-1) */
    const uint32_t N = n + 5u;
    enum { OM = 0, IQ = 1, UP = 2, UC = 3, YP = 4, W0 = 5 };
    for (uint32_t i = 0; i < N * N; ++i) {
        Acl[i] = 0.0;
    }
    /* plant, input v_cur */
    for (uint32_t i = 0; i < 2u; ++i) {
        Acl[i * N + OM] = ((i == 0u) ? 1.0 : 0.0) + Dp[i * 2u];
        Acl[i * N + IQ] = ((i == 1u) ? 1.0 : 0.0) + Dp[i * 2u + 1u];
        Acl[i * N + UC] = Ep[i];
    }
    Acl[UP * N + UC] = 1.0;  /* v_prev+ = v_cur */
    Acl[YP * N + OM] = -1.0; /* nu_prev+ = -omega */
    /* w+ = Phi w + Gu v_prev + a_wn nu_prev + Ld (nu - a_nn nu_prev) */
    for (uint32_t i = 0; i < n; ++i) {
        double *row = &Acl[(W0 + i) * N];
        for (uint32_t j = 0; j < n; ++j) {
            row[W0 + j] = d->Ad[i * n + j] - d->Ld[i] * d->c[j];
        }
        row[UP] = d->Bd2[i] - d->Ld[i] * d->Bd1;
        row[OM] = -d->Ld[i];
        row[YP] = d->a_wn[i] - d->Ld[i] * d->a_nn;
    }
    /* v_cur+ = g_nu (-omega) + g . w+ + gu v_cur  (omega* = 0) */
    double *u = &Acl[UC * N];
    u[OM] = -d->g_nu;
    u[UC] = d->gu;
    for (uint32_t i = 0; i < n; ++i) {
        const double *row = &Acl[(W0 + i) * N];
        for (uint32_t j = 0; j < N; ++j) {
            u[j] += d->g[i] * row[j];
        }
    }
    *dim = N;
    return MC_OK;
}

static double norm_inf(uint32_t n, const double *a)
{
    double m = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        double s = 0.0;
        for (uint32_t j = 0; j < n; ++j) {
            s += fabs(a[i * n + j]);
        }
        m = fmax(m, s);
    }
    return m;
}

mc_status_t mc_cdobc_loop_radius(const mc_cdobc_design_t *d,
                                 const mc_cdobc_plant_factors_t *f, double *rho)
{
    double A[NL * NL], T[NL * NL];
    uint32_t N = 0u;
    const mc_status_t st = mc_cdobc_loop_matrix(d, f, &N, A);
    if (st != MC_OK) {
        return st;
    }
    /* A^(2^i) = A_i exp(lg_i), A_i normalised: ||A_i|| = 1 */
    double lg = 0.0;
    double s = norm_inf(N, A);
    for (uint32_t it = 0; it <= 24u; ++it) {
        if (!(s > 0.0) || !isfinite(s)) {
            if (s == 0.0) {
                *rho = 0.0; /* nilpotent */
                return MC_OK;
            }
            return MC_ERR_PARAM;
        }
        for (uint32_t i = 0; i < N * N; ++i) {
            A[i] /= s; /* s > 0 */
        }
        lg += log(s);
        if (it == 24u) {
            break;
        }
        mc_mat_mul_f64(N, A, A, T);
        lg *= 2.0;
        for (uint32_t i = 0; i < N * N; ++i) {
            A[i] = T[i];
        }
        s = norm_inf(N, A);
    }
    /* ||A^k|| = exp(lg) with k = 2^24 */
    *rho = exp(lg / 16777216.0);
    return MC_OK;
}
