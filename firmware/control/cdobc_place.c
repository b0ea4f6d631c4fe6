/* Paper 002 regulator: pole placement for the single-output observer
 * chain and the 2-state controller (Remark 6), design time (double).
 * See mc/cdobc.h. */
#include "mc/cdobc.h"

#include <math.h>

enum { NS = 2 * MC_CDOBC_N_MAX };

mc_status_t mc_cdobc_solve_f64(uint32_t n, double *A, double *b)
{
    if (n < 1u || n > (uint32_t)NS) {
        return MC_ERR_PARAM;
    }
    for (uint32_t c = 0; c < n; ++c) {
        uint32_t piv = c;
        double colmax = 0.0;
        for (uint32_t r = c; r < n; ++r) {
            const double v = fabs(A[r * n + c]);
            if (v > colmax) {
                colmax = v;
                piv = r;
            }
        }
        double scale = 0.0; /* largest entry of column c overall */
        for (uint32_t r = 0; r < n; ++r) {
            scale = fmax(scale, fabs(A[r * n + c]));
        }
        if (!(colmax > 1e-13 * scale) || !isfinite(colmax)) {
            return MC_ERR_PARAM;
        }
        for (uint32_t j = 0; j < n; ++j) {
            const double t = A[c * n + j];
            A[c * n + j] = A[piv * n + j];
            A[piv * n + j] = t;
        }
        const double tb = b[c];
        b[c] = b[piv];
        b[piv] = tb;
        for (uint32_t r = c + 1u; r < n; ++r) {
            const double f = A[r * n + c] / A[c * n + c]; /* pivot > 0 */
            for (uint32_t j = c; j < n; ++j) {
                A[r * n + j] -= f * A[c * n + j];
            }
            b[r] -= f * b[c];
        }
    }
    for (uint32_t r = n; r-- > 0u;) {
        double s = b[r];
        for (uint32_t k = r + 1u; k < n; ++k) {
            s -= A[r * n + k] * b[k];
        }
        b[r] = s / A[r * n + r]; /* nonzero pivot checked above */
    }
    for (uint32_t r = 0; r < n; ++r) {
        if (!isfinite(b[r])) {
            return MC_ERR_PARAM;
        }
    }
    return MC_OK;
}

mc_status_t mc_cdobc_poly_from_roots(uint32_t n, const double *re,
                                     const double *im, double *coef)
{
    if (n < 1u || n > MC_CDOBC_N_MAX) {
        return MC_ERR_PARAM;
    }
    /* p[0..deg], p[deg] = 1, multiplied out factor by factor */
    double p[MC_CDOBC_N_MAX + 1u] = { 1.0 };
    uint32_t deg = 0u;
    for (uint32_t i = 0; i < n;) {
        if (!isfinite(re[i]) || !isfinite(im[i])) {
            return MC_ERR_PARAM;
        }
        double f1, f0; /* factor s^2 + f1 s + f0 or s + f0 */
        uint32_t fd;
        if (im[i] == 0.0) {
            f1 = 0.0;
            f0 = -re[i];
            fd = 1u;
        } else {
            if (i + 1u >= n || re[i + 1u] != re[i] || im[i + 1u] != -im[i]) {
                return MC_ERR_PARAM;
            }
            f1 = -2.0 * re[i];
            f0 = re[i] * re[i] + im[i] * im[i];
            fd = 2u;
        }
        double q[MC_CDOBC_N_MAX + 1u] = { 0.0 };
        for (uint32_t k = 0; k <= deg; ++k) {
            q[k + fd] += p[k];
            if (fd == 2u) {
                q[k + 1u] += f1 * p[k];
            }
            q[k] += f0 * p[k];
        }
        deg += fd;
        for (uint32_t k = 0; k <= deg; ++k) {
            p[k] = q[k];
        }
        i += fd;
    }
    for (uint32_t k = 0; k < n; ++k) {
        coef[k] = p[k];
    }
    return MC_OK;
}

mc_status_t mc_cdobc_ackermann_f64(uint32_t n, const double *A, const double *c,
                                   const double *coef, double *l)
{
    if (n < 1u || n > MC_CDOBC_N_MAX) {
        return MC_ERR_PARAM;
    }
    enum { NM = MC_CDOBC_N_MAX };
    /* O = [c; c A; ...], rows built by r_{k+1} = r_k A */
    double O[NM * NM], v[NM];
    for (uint32_t j = 0; j < n; ++j) {
        O[j] = c[j];
    }
    for (uint32_t k = 1; k < n; ++k) {
        for (uint32_t j = 0; j < n; ++j) {
            double s = 0.0;
            for (uint32_t i = 0; i < n; ++i) {
                s += O[(k - 1u) * n + i] * A[i * n + j];
            }
            O[k * n + j] = s;
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        v[i] = (i + 1u == n) ? 1.0 : 0.0;
    }
    const mc_status_t st = mc_cdobc_solve_f64(n, O, v);
    if (st != MC_OK) {
        return st;
    }
    /* Horner: r = v; r = A r + coef[k] v, k = n-1 .. 0 -> p(A) v */
    double r[NM], t[NM];
    for (uint32_t i = 0; i < n; ++i) {
        r[i] = v[i];
    }
    for (uint32_t k = n; k-- > 0u;) {
        for (uint32_t i = 0; i < n; ++i) {
            double s = 0.0;
            for (uint32_t j = 0; j < n; ++j) {
                s += A[i * n + j] * r[j];
            }
            t[i] = s + coef[k] * v[i];
        }
        for (uint32_t i = 0; i < n; ++i) {
            r[i] = t[i];
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        if (!isfinite(r[i])) {
            return MC_ERR_PARAM;
        }
        l[i] = r[i];
    }
    return MC_OK;
}
