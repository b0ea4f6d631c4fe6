/*
 * Closed-form exponential of a real 2x2 matrix, double precision: the
 * analytic reference for linear error dynamics chi' = A chi in the observer
 * tests.
 *
 * With m = tr(A)/2 and B = A - m I, Cayley-Hamilton gives B^2 = q I,
 * q = m^2 - det(A), hence
 *   exp(A t) = exp(m t) (C(t) I + S(t) B),
 *   q > 0: C = cosh(sqrt(q) t), S = sinh(sqrt(q) t)/sqrt(q)
 *   q < 0: C = cos(sqrt(-q) t), S = sin(sqrt(-q) t)/sqrt(-q)
 *   q = 0: C = 1, S = t.
 */
#ifndef TEST_EXPM2_H
#define TEST_EXPM2_H

#include <math.h>

typedef struct {
    double a11, a12, a21, a22;
} mat2_t;

/* y = exp(A t) x */
static inline void expm2_apply(mat2_t A, double t, const double x[2], double y[2])
{
    const double m = 0.5 * (A.a11 + A.a22);
    const double det = A.a11 * A.a22 - A.a12 * A.a21;
    const double q = m * m - det;
    double C, S;
    if (q > 0.0) {
        const double w = sqrt(q);
        C = cosh(w * t);
        S = sinh(w * t) / w;
    } else if (q < 0.0) {
        const double w = sqrt(-q);
        C = cos(w * t);
        S = sin(w * t) / w;
    } else {
        C = 1.0;
        S = t;
    }
    const double e = exp(m * t);
    const double b11 = A.a11 - m, b22 = A.a22 - m;
    y[0] = e * ((C + S * b11) * x[0] + S * A.a12 * x[1]);
    y[1] = e * (S * A.a21 * x[0] + (C + S * b22) * x[1]);
}

/* Eigenvalues of A: real parts re[0] <= re[1] and |imaginary part| im. */
static inline void eig2(mat2_t A, double re[2], double *im)
{
    const double m = 0.5 * (A.a11 + A.a22);
    const double q = m * m - (A.a11 * A.a22 - A.a12 * A.a21);
    if (q >= 0.0) {
        re[0] = m - sqrt(q);
        re[1] = m + sqrt(q);
        *im = 0.0;
    } else {
        re[0] = re[1] = m;
        *im = sqrt(-q);
    }
}

#endif /* TEST_EXPM2_H */
