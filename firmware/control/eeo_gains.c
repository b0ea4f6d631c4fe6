/* Paper 000 regulator, design time (double): Appendix A recursion, Gamma
 * placement for (7), ZOH of the internal model, backward-Euler gains of
 * (13). See mc/eeo.h. */
#include "mc/eeo.h"
#include "mc/zoh.h"

#include <math.h>
#include <stddef.h>

static bool finite_pos(double x)
{
    return isfinite(x) && x > 0.0;
}

mc_status_t mc_eeo_gain_recursion(uint32_t n, const double *g_min,
                                  const double *g_max, const double *L,
                                  double *a, double *b)
{
    if (n < 2u || n > MC_EEO_REC_MAX) {
        return MC_ERR_PARAM;
    }
    for (uint32_t i = 0; i + 1u < n; ++i) {
        if (!isfinite(g_min[i]) || !isfinite(g_max[i + 1u]) ||
            !isfinite(L[i])) {
            return MC_ERR_NONFINITE;
        }
        if (!(g_min[i] > 0.0) || !(g_max[i + 1u] > 0.0) || !(L[i] > 0.0)) {
            return MC_ERR_PARAM;
        }
    }
    double bk[MC_EEO_REC_MAX];
    bk[0] = 1.0;
    double d = 1.0; /* b_{k-1} ... b_0 */
    for (uint32_t k = 1; k < n; ++k) {
        /* max{g_r^max, r = n-k+2 .. n}, 1-based r -> index r - 1 */
        double gr = 0.0;
        for (uint32_t r = n - k + 2u; r <= n; ++r) {
            gr = (g_max[r - 1u] > gr) ? g_max[r - 1u] : gr;
        }
        const double gnext = g_max[n - k]; /* g_{n-k+1}^max */
        const double kk = (double)k;
        /* Appendix A final condition with "much greater" taken as "=" */
        bk[k] = (L[k - 1u] * (gr * sqrt(kk) + d * kk * gnext) + d * gnext) /
                g_min[n - k - 1u]; /* g_{n-k}^min > 0 checked */
        if (!finite_pos(bk[k])) {
            return MC_ERR_PARAM;
        }
        d *= bk[k];
    }
    double ak[MC_EEO_REC_MAX];
    ak[n - 1u] = bk[n - 1u];
    for (uint32_t i = n - 1u; i-- > 0u;) {
        ak[i] = ak[i + 1u] * bk[i];
    }
    for (uint32_t i = 0; i < n; ++i) {
        if (!finite_pos(ak[i])) {
            return MC_ERR_PARAM;
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        a[i] = ak[i];
        if (b != NULL) {
            b[i] = bk[i];
        }
    }
    return MC_OK;
}

bool mc_eeo_poly_is_hurwitz(uint32_t n, const double *coef)
{
    if (n < 1u || n > MC_EEO_NW_MAX) {
        return false;
    }
    /* Routh array: row 0 = (1, c[n-2], c[n-4], ...),
     * row 1 = (c[n-1], c[n-3], ...); c_n = 1 */
    double r[MC_EEO_NW_MAX + 1u][MC_EEO_NW_MAX / 2u + 2u] = { { 0.0 } };
    for (uint32_t i = 0; i <= n; ++i) {
        const uint32_t pw = n - i; /* power of s */
        const double c = (pw == n) ? 1.0 : coef[pw];
        if (!isfinite(c)) {
            return false;
        }
        r[i % 2u][i / 2u] = c;
    }
    for (uint32_t row = 2; row <= n; ++row) {
        const double piv = r[row - 1u][0];
        if (!(piv > 0.0)) {
            return false;
        }
        for (uint32_t j = 0; j < MC_EEO_NW_MAX / 2u + 1u; ++j) {
            r[row][j] = (piv * r[row - 2u][j + 1u] -
                         r[row - 2u][0] * r[row - 1u][j + 1u]) /
                        piv;
        }
    }
    return r[n][0] > 0.0 && r[n - 1u][0] > 0.0;
}

mc_status_t mc_eeo_gamma_place(uint32_t n, const double *f_coef,
                               const double *s_coef, double *gamma)
{
    if (n < 1u || n > MC_EEO_NW_MAX) {
        return MC_ERR_PARAM;
    }
    for (uint32_t i = 0; i < n; ++i) {
        if (!isfinite(f_coef[i]) || !isfinite(s_coef[i])) {
            return MC_ERR_NONFINITE;
        }
    }
    if (!mc_eeo_poly_is_hurwitz(n, f_coef)) {
        return MC_ERR_PARAM;
    }
    /* companion rows: last row of F is -f, of F + G Gamma is -f + Gamma,
     * which must be -s (7) */
    for (uint32_t i = 0; i < n; ++i) {
        gamma[i] = f_coef[i] - s_coef[i];
    }
    return MC_OK;
}

mc_status_t mc_eeo_companion_zoh(uint32_t n, const double *coef, double Ts_s,
                                 double *D, double *E)
{
    if (n < 1u || n > MC_EEO_NW_MAX) {
        return MC_ERR_PARAM;
    }
    /* companion matrix of coef, g = e_n (mc/zoh.h does the rest) */
    double M[MC_EEO_NW_MAX * MC_EEO_NW_MAX] = { 0.0 };
    double g[MC_EEO_NW_MAX] = { 0.0 };
    for (uint32_t i = 0; i + 1u < n; ++i) {
        M[i * n + i + 1u] = 1.0;
    }
    for (uint32_t j = 0; j < n; ++j) {
        M[(n - 1u) * n + j] = -coef[j];
    }
    g[n - 1u] = 1.0;
    return mc_zoh_f64(n, M, g, Ts_s, D, E);
}

mc_status_t mc_eeo_be_gains(double Ts_s, double g2, double g3, const double *l,
                            double *m)
{
    if (!isfinite(Ts_s) || !isfinite(g2) || !isfinite(g3) || !isfinite(l[0]) ||
        !isfinite(l[1]) || !isfinite(l[2]) || !isfinite(l[3])) {
        return MC_ERR_NONFINITE;
    }
    if (!(Ts_s > 0.0) || !(g2 > 0.0) || !(g3 > 0.0) || !(l[0] > 0.0) ||
        !(l[1] > 0.0) || !(l[2] > 0.0) || !(l[3] > 0.0)) {
        return MC_ERR_PARAM;
    }
    /* w = h M^-1 l by back substitution (mc/eeo.h) */
    const double h = Ts_s;
    const double w4 = h * l[3];
    const double w3 = h * l[2] + h * w4;
    const double w2 = h * l[1] + h * g3 * w3;
    const double w1 = h * l[0] + h * g2 * w2;
    const double den = 1.0 + w1; /* > 1: every term positive */
    m[0] = w1 / den;
    m[1] = w2 / den;
    m[2] = w3 / den;
    m[3] = w4 / den;
    for (uint32_t i = 0; i < 4u; ++i) {
        if (!finite_pos(m[i])) {
            return MC_ERR_PARAM;
        }
    }
    return MC_OK;
}
