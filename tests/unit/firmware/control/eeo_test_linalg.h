/*
 * Small dense linear algebra in double for the paper-000 and paper-002
 * regulator tests, written independently of the firmware: linear solve
 * (Gauss with partial pivoting), matrix exponential (plain Taylor with
 * scaling and squaring of exp itself), characteristic polynomial
 * (Faddeev-LeVerrier) and the eigenvalues of a real matrix (balancing,
 * reduction to Hessenberg form, shifted QR: the classic EISPACK
 * balanc/elmhes/hqr sequence).
 */
#ifndef EEO_TEST_LINALG_H
#define EEO_TEST_LINALG_H

#include <math.h>
#include <string.h>

#define LA_NMAX 20

/* y = a b, (n x n) row major */
static inline void la_mul(int n, const double *a, const double *b, double *y)
{
    double t[LA_NMAX * LA_NMAX];
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            double s = 0.0;
            for (int k = 0; k < n; ++k) {
                s += a[i * n + k] * b[k * n + j];
            }
            t[i * n + j] = s;
        }
    }
    memcpy(y, t, sizeof(double) * (size_t)(n * n));
}

/* Solve a X = b for X (n x nr), a (n x n); 0 on success */
static inline int la_solve(int n, const double *a_in, int nr, const double *b_in, double *x)
{
    double a[LA_NMAX * LA_NMAX], b[LA_NMAX * LA_NMAX];
    memcpy(a, a_in, sizeof(double) * (size_t)(n * n));
    memcpy(b, b_in, sizeof(double) * (size_t)(n * nr));
    for (int c = 0; c < n; ++c) {
        int piv = c;
        for (int r = c + 1; r < n; ++r) {
            if (fabs(a[r * n + c]) > fabs(a[piv * n + c])) {
                piv = r;
            }
        }
        if (a[piv * n + c] == 0.0) {
            return -1;
        }
        for (int j = 0; j < n; ++j) {
            const double t = a[c * n + j];
            a[c * n + j] = a[piv * n + j];
            a[piv * n + j] = t;
        }
        for (int j = 0; j < nr; ++j) {
            const double t = b[c * nr + j];
            b[c * nr + j] = b[piv * nr + j];
            b[piv * nr + j] = t;
        }
        for (int r = c + 1; r < n; ++r) {
            const double f = a[r * n + c] / a[c * n + c];
            for (int j = c; j < n; ++j) {
                a[r * n + j] -= f * a[c * n + j];
            }
            for (int j = 0; j < nr; ++j) {
                b[r * nr + j] -= f * b[c * nr + j];
            }
        }
    }
    for (int j = 0; j < nr; ++j) {
        for (int r = n - 1; r >= 0; --r) {
            double s = b[r * nr + j];
            for (int k = r + 1; k < n; ++k) {
                s -= a[r * n + k] * x[k * nr + j];
            }
            x[r * nr + j] = s / a[r * n + r];
        }
    }
    return 0;
}

/* y = exp(a) by Taylor (30 terms) on a / 2^s, ||a / 2^s|| <= 0.25, then
 * squaring of exp itself */
static inline void la_expm(int n, const double *a, double *y)
{
    double norm = 0.0;
    for (int i = 0; i < n; ++i) {
        double s = 0.0;
        for (int j = 0; j < n; ++j) {
            s += fabs(a[i * n + j]);
        }
        norm = fmax(norm, s);
    }
    int sq = 0;
    while (norm > 0.25) {
        norm *= 0.5;
        ++sq;
    }
    const double sc = ldexp(1.0, -sq);
    double term[LA_NMAX * LA_NMAX], as[LA_NMAX * LA_NMAX], e[LA_NMAX * LA_NMAX];
    for (int i = 0; i < n * n; ++i) {
        as[i] = a[i] * sc;
        term[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;
        e[i] = term[i];
    }
    for (int k = 1; k <= 30; ++k) {
        la_mul(n, term, as, term);
        for (int i = 0; i < n * n; ++i) {
            term[i] /= (double)k;
            e[i] += term[i];
        }
    }
    for (int s = 0; s < sq; ++s) {
        la_mul(n, e, e, e);
    }
    memcpy(y, e, sizeof(double) * (size_t)(n * n));
}

/* Faddeev-LeVerrier: characteristic polynomial of a (n x n), monic, low
 * order first: c[0..n-1] */
static inline void la_charpoly(int n, const double *a, double *c)
{
    double Mk[LA_NMAX * LA_NMAX] = { 0.0 }, AM[LA_NMAX * LA_NMAX];
    double ck = 1.0; /* c_n */
    for (int k = 1; k <= n; ++k) {
        /* M_k = A M_{k-1} + c_{n-k+1} I */
        la_mul(n, a, Mk, AM);
        for (int i = 0; i < n * n; ++i) {
            Mk[i] = AM[i];
        }
        for (int i = 0; i < n; ++i) {
            Mk[i * n + i] += ck;
        }
        la_mul(n, a, Mk, AM);
        double tr = 0.0;
        for (int i = 0; i < n; ++i) {
            tr += AM[i * n + i];
        }
        ck = -tr / (double)k;
        c[n - k] = ck;
    }
}

/* Eigenvalues of a (n x n, row major; copied): wr + i wi. 0 on success. */
static inline int la_eig(int n, const double *a_in, double *wr_out, double *wi_out)
{
    /* 1-based copy for the EISPACK-style code below */
    double a[LA_NMAX + 1][LA_NMAX + 1];
    double wr[LA_NMAX + 1], wi[LA_NMAX + 1];
    for (int i = 1; i <= n; ++i) {
        for (int j = 1; j <= n; ++j) {
            a[i][j] = a_in[(i - 1) * n + (j - 1)];
        }
    }
    /* balance */
    int last = 0;
    while (!last) {
        last = 1;
        for (int i = 1; i <= n; ++i) {
            double r = 0.0, c = 0.0;
            for (int j = 1; j <= n; ++j) {
                if (j != i) {
                    c += fabs(a[j][i]);
                    r += fabs(a[i][j]);
                }
            }
            if (c != 0.0 && r != 0.0) {
                double g = r / 2.0, f = 1.0;
                const double s = c + r;
                while (c < g) {
                    f *= 2.0;
                    c *= 4.0;
                }
                g = r * 2.0;
                while (c > g) {
                    f /= 2.0;
                    c /= 4.0;
                }
                if ((c + r) / f < 0.95 * s) {
                    last = 0;
                    g = 1.0 / f;
                    for (int j = 1; j <= n; ++j) {
                        a[i][j] *= g;
                    }
                    for (int j = 1; j <= n; ++j) {
                        a[j][i] *= f;
                    }
                }
            }
        }
    }
    /* Hessenberg by elimination with pivoting */
    for (int m = 2; m < n; ++m) {
        double x = 0.0;
        int i = m;
        for (int j = m; j <= n; ++j) {
            if (fabs(a[j][m - 1]) > fabs(x)) {
                x = a[j][m - 1];
                i = j;
            }
        }
        if (i != m) {
            for (int j = m - 1; j <= n; ++j) {
                const double t = a[i][j];
                a[i][j] = a[m][j];
                a[m][j] = t;
            }
            for (int j = 1; j <= n; ++j) {
                const double t = a[j][i];
                a[j][i] = a[j][m];
                a[j][m] = t;
            }
        }
        if (x != 0.0) {
            for (i = m + 1; i <= n; ++i) {
                double y = a[i][m - 1];
                if (y != 0.0) {
                    y /= x;
                    a[i][m - 1] = y;
                    for (int j = m; j <= n; ++j) {
                        a[i][j] -= y * a[m][j];
                    }
                    for (int j = 1; j <= n; ++j) {
                        a[j][m] += y * a[j][i];
                    }
                }
            }
        }
    }
    for (int i = 1; i <= n; ++i) {
        for (int j = 1; j < i - 1; ++j) {
            a[i][j] = 0.0;
        }
    }
    /* shifted QR (hqr) */
    double anorm = 0.0;
    for (int i = 1; i <= n; ++i) {
        for (int j = (i > 1 ? i - 1 : 1); j <= n; ++j) {
            anorm += fabs(a[i][j]);
        }
    }
    int nn = n, l = 1;
    double t = 0.0, p = 0.0, q = 0.0, r = 0.0, s, w, x, y, z;
    while (nn >= 1) {
        int its = 0;
        do {
            for (l = nn; l >= 2; l--) {
                s = fabs(a[l - 1][l - 1]) + fabs(a[l][l]);
                if (s == 0.0) {
                    s = anorm;
                }
                if (fabs(a[l][l - 1]) + s == s) {
                    a[l][l - 1] = 0.0;
                    break;
                }
            }
            x = a[nn][nn];
            if (l == nn) {
                wr[nn] = x + t;
                wi[nn--] = 0.0;
            } else {
                y = a[nn - 1][nn - 1];
                w = a[nn][nn - 1] * a[nn - 1][nn];
                if (l == nn - 1) {
                    p = 0.5 * (y - x);
                    q = p * p + w;
                    z = sqrt(fabs(q));
                    x += t;
                    if (q >= 0.0) {
                        z = p + (p >= 0.0 ? fabs(z) : -fabs(z));
                        wr[nn - 1] = wr[nn] = x + z;
                        if (z != 0.0) {
                            wr[nn] = x - w / z;
                        }
                        wi[nn - 1] = wi[nn] = 0.0;
                    } else {
                        wr[nn - 1] = wr[nn] = x + p;
                        wi[nn - 1] = -(wi[nn] = z);
                    }
                    nn -= 2;
                } else {
                    if (its == 60) {
                        return -1;
                    }
                    if (its == 10 || its == 20 || its == 40) {
                        t += x;
                        for (int i = 1; i <= nn; ++i) {
                            a[i][i] -= x;
                        }
                        s = fabs(a[nn][nn - 1]) + fabs(a[nn - 1][nn - 2]);
                        y = x = 0.75 * s;
                        w = -0.4375 * s * s;
                    }
                    ++its;
                    int m;
                    for (m = nn - 2; m >= l; m--) {
                        z = a[m][m];
                        r = x - z;
                        s = y - z;
                        p = (r * s - w) / a[m + 1][m] + a[m][m + 1];
                        q = a[m + 1][m + 1] - z - r - s;
                        r = a[m + 2][m + 1];
                        s = fabs(p) + fabs(q) + fabs(r);
                        p /= s;
                        q /= s;
                        r /= s;
                        if (m == l) {
                            break;
                        }
                        const double u = fabs(a[m][m - 1]) * (fabs(q) + fabs(r));
                        const double v =
                            fabs(p) * (fabs(a[m - 1][m - 1]) + fabs(z) + fabs(a[m + 1][m + 1]));
                        if (u + v == v) {
                            break;
                        }
                    }
                    for (int i = m + 2; i <= nn; ++i) {
                        a[i][i - 2] = 0.0;
                        if (i != m + 2) {
                            a[i][i - 3] = 0.0;
                        }
                    }
                    for (int k = m; k <= nn - 1; ++k) {
                        if (k != m) {
                            p = a[k][k - 1];
                            q = a[k + 1][k - 1];
                            r = 0.0;
                            if (k != nn - 1) {
                                r = a[k + 2][k - 1];
                            }
                            if ((x = fabs(p) + fabs(q) + fabs(r)) != 0.0) {
                                p /= x;
                                q /= x;
                                r /= x;
                            }
                        }
                        const double sq = sqrt(p * p + q * q + r * r);
                        if ((s = (p >= 0.0 ? sq : -sq)) != 0.0) {
                            if (k == m) {
                                if (l != m) {
                                    a[k][k - 1] = -a[k][k - 1];
                                }
                            } else {
                                a[k][k - 1] = -s * x;
                            }
                            p += s;
                            x = p / s;
                            y = q / s;
                            z = r / s;
                            q /= p;
                            r /= p;
                            for (int j = k; j <= nn; ++j) {
                                p = a[k][j] + q * a[k + 1][j];
                                if (k != nn - 1) {
                                    p += r * a[k + 2][j];
                                    a[k + 2][j] -= p * z;
                                }
                                a[k + 1][j] -= p * y;
                                a[k][j] -= p * x;
                            }
                            const int mmin = nn < k + 3 ? nn : k + 3;
                            for (int i = l; i <= mmin; ++i) {
                                p = x * a[i][k] + y * a[i][k + 1];
                                if (k != nn - 1) {
                                    p += z * a[i][k + 2];
                                    a[i][k + 2] -= p * r;
                                }
                                a[i][k + 1] -= p * q;
                                a[i][k] -= p;
                            }
                        }
                    }
                }
            }
        } while (l < nn - 1);
    }
    for (int i = 1; i <= n; ++i) {
        wr_out[i - 1] = wr[i];
        wi_out[i - 1] = wi[i];
    }
    return 0;
}

/* spectral radius; -1 if the QR iteration failed */
static inline double la_spectral_radius(int n, const double *a)
{
    double wr[LA_NMAX], wi[LA_NMAX];
    if (la_eig(n, a, wr, wi) != 0) {
        return -1.0;
    }
    double rho = 0.0;
    for (int i = 0; i < n; ++i) {
        rho = fmax(rho, hypot(wr[i], wi[i]));
    }
    return rho;
}

#endif /* EEO_TEST_LINALG_H */
