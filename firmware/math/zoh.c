/* Exact ZOH discretisation, design time (double). See mc/zoh.h. */
#include "mc/zoh.h"

#include <math.h>

enum { NA = MC_ZOH_NMAX + 1 };

void mc_mat_mul_f64(uint32_t n, const double *a, const double *b, double *y)
{
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            double s = 0.0;
            for (uint32_t k = 0; k < n; ++k) {
                s += a[i * n + k] * b[k * n + j];
            }
            y[i * n + j] = s;
        }
    }
}

mc_status_t mc_zoh_f64(uint32_t n, const double *M, const double *g,
                       double Ts_s, double *D, double *E)
{
    if (n < 1u || n > MC_ZOH_NMAX) {
        return MC_ERR_PARAM;
    }
    if (!isfinite(Ts_s)) {
        return MC_ERR_NONFINITE;
    }
    if (!(Ts_s > 0.0)) {
        return MC_ERR_PARAM;
    }
    /* augmented X = [M g; 0 0] Ts, size na */
    const uint32_t na = n + 1u;
    double X[NA * NA] = { 0.0 };
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            if (!isfinite(M[i * n + j])) {
                return MC_ERR_NONFINITE;
            }
            X[i * na + j] = M[i * n + j] * Ts_s;
        }
        if (!isfinite(g[i])) {
            return MC_ERR_NONFINITE;
        }
        X[i * na + n] = g[i] * Ts_s;
    }
    double norm = 0.0; /* max abs row sum */
    for (uint32_t i = 0; i < na; ++i) {
        double s = 0.0;
        for (uint32_t j = 0; j < na; ++j) {
            s += fabs(X[i * na + j]);
        }
        norm = (s > norm) ? s : norm;
    }
    if (!(norm <= 1e3)) {
        return MC_ERR_PARAM;
    }
    uint32_t sq = 0;
    double scale = 1.0;
    while (norm * scale > 0.5) {
        scale *= 0.5;
        ++sq;
    }
    /* Dm = exp(X scale) - I by Taylor, 20 terms */
    double Xs[NA * NA], term[NA * NA], tmp[NA * NA], Dm[NA * NA];
    for (uint32_t i = 0; i < na * na; ++i) {
        Xs[i] = X[i] * scale;
        term[i] = Xs[i];
        Dm[i] = Xs[i];
    }
    for (uint32_t k = 2; k <= 20u; ++k) {
        mc_mat_mul_f64(na, term, Xs, tmp);
        for (uint32_t i = 0; i < na * na; ++i) {
            term[i] = tmp[i] / (double)k;
            Dm[i] += term[i];
        }
    }
    /* (I + Dm)^2 - I = 2 Dm + Dm^2 */
    for (uint32_t s = 0; s < sq; ++s) {
        mc_mat_mul_f64(na, Dm, Dm, tmp);
        for (uint32_t i = 0; i < na * na; ++i) {
            Dm[i] = 2.0 * Dm[i] + tmp[i];
        }
    }
    for (uint32_t i = 0; i < na * na; ++i) {
        if (!isfinite(Dm[i])) {
            return MC_ERR_PARAM;
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            D[i * n + j] = Dm[i * na + j];
        }
        E[i] = Dm[i * na + n];
    }
    return MC_OK;
}
