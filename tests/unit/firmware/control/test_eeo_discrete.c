/*
 * Paper 000 regulator, discretisation of the observer (13) (mc/eeo.h):
 * - the closed-form backward-Euler gains m equal the solution of the
 *   implicit system (I - h A + h l C) x = h l solved here by elimination;
 * - spectral radius of the discrete observer error matrix
 *   (I - h (A - l C))^-1, built and analysed here in double, below 1 for
 *   every period from 10 us to 5 ms, and equal to max 1/|1 - h lambda_i|
 *   over the continuous eigenvalues (the A-stability argument);
 * - forward Euler at 50 us (I + h (A - l C)) is unstable (the negative
 *   control);
 * - the full linear loop (linearised plant (6) at rest, exact ZOH;
 *   backward-Euler observer; (12) unsaturated; internal model (7)),
 *   built here from a double implementation of one period: spectral
 *   radius per period.
 * Table 1 motor, Section 6 gains (a from the explicit formulas, kappa =
 * 1e3), g3 = 1/j.
 */
#include "mc_test.h"

#include <stdio.h>

#include "eeo_test_linalg.h"
#include "mc/eeo.h"

#define J_KGM2 5.5367e-5
#define NP     8.0
#define L_H    20e-3
#define R_OHM  7.2
#define B_NMS  0.006
#define LAM_WB 0.06
#define G3     (1.0 / J_KGM2)
#define BBAR   20.0

static const double kPeriods[] = { 10e-6, 20e-6, 50e-6, 100e-6, 200e-6, 500e-6, 1e-3, 2e-3, 5e-3 };
#define N_PERIODS ((int)(sizeof kPeriods / sizeof kPeriods[0]))

/* Section 6 a (explicit formulas), then l = (k a3, k^2 a2, k^3 a1, k^4 a0) */
static void gains_l(double l[4])
{
    const double g3min = G3 - 1e4, g3max = G3 + 1e4;
    const double b1 = 2.0 / g3min;
    const double b2 = (sqrt(2.0) + 2.0 * b1 * g3max + b1 * g3max) / NP;
    const double b3 = g3max * sqrt(3.0) + 3.0 * b2 * b1 * NP + b2 * b1 * NP;
    const double k = 1e3;
    l[0] = k * b3;
    l[1] = k * k * b3 * b2;
    l[2] = k * k * k * b3 * b2 * b1;
    l[3] = k * k * k * k * b3 * b2 * b1;
}

/* A - l C of the error dynamics, 4 x 4 */
static void obs_matrix(const double l[4], double *Ae)
{
    const double A[16] = { 0, NP, 0, 0, 0, 0, G3, 0, 0, 0, 0, 1, 0, 0, 0, 0 };
    for (int i = 0; i < 16; ++i) {
        Ae[i] = A[i];
    }
    for (int i = 0; i < 4; ++i) {
        Ae[i * 4] -= l[i];
    }
}

static void test_be_gains_closed_form(void **state)
{
    (void)state;
    double l[4], Ae[16];
    gains_l(l);
    obs_matrix(l, Ae);
    for (int t = 0; t < N_PERIODS; ++t) {
        const double h = kPeriods[t];
        double M[16], rhs[4], m_ref[4], m[4];
        for (int i = 0; i < 16; ++i) {
            M[i] = (i % 5 == 0 ? 1.0 : 0.0) - h * Ae[i];
        }
        for (int i = 0; i < 4; ++i) {
            rhs[i] = h * l[i];
        }
        assert_int_equal(la_solve(4, M, 1, rhs, m_ref), 0);
        assert_int_equal(mc_eeo_be_gains(h, NP, G3, l, m), MC_OK);
        for (int i = 0; i < 4; ++i) {
            /* elimination on entries up to 1e13: agreement to 1e-6 */
            assert_near(m[i] / m_ref[i], 1.0, 1e-6);
            /* the closed form solves the implicit system: row residual
             * relative to the row's terms */
            double res = -rhs[i], mag = fabs(rhs[i]);
            for (int j = 0; j < 4; ++j) {
                res += M[i * 4 + j] * m[j];
                mag += fabs(M[i * 4 + j] * m[j]);
            }
            assert_true(fabs(res) <= 1e-14 * mag);
        }
        /* the float32 instance */
        mc_eeo_params_t p;
        mc_eeo_params_paper000(&p, (float)h, 8u, (float)J_KGM2, 1e-6f);
        p.v_q_max_V = 1e9f;
        mc_eeo_f32_t c;
        assert_int_equal(mc_eeo_init_f32(&c, &p), MC_OK);
        for (int i = 0; i < 4; ++i) {
            assert_near(c.m[i] / m_ref[i], 1.0, 2e-6);
        }
        if (t == 2) {
            printf("# Ts = 50 us: m = (%.9f, %.6g, %.6g, %.6g)\n", m[0], m[1], m[2], m[3]);
        }
    }
}

static void test_observer_error_stability(void **state)
{
    (void)state;
    double l[4], Ae[16], wr[4], wi[4];
    gains_l(l);
    obs_matrix(l, Ae);
    assert_int_equal(la_eig(4, Ae, wr, wi), 0);
    double fastest = 0.0;
    printf("# continuous observer eigenvalues (rad/s):");
    for (int i = 0; i < 4; ++i) {
        printf(" %.6g%+.6gi", wr[i], wi[i]);
        fastest = fmin(fastest, wr[i]);
        assert_true(wr[i] < 0.0);
    }
    printf("\n");
    assert_near(fastest, -4.86e7, 0.01e7);
    /* forward Euler bound 2 / |lambda_fast| */
    printf("# forward Euler stable only below %.4g ns\n", 2.0 / -fastest * 1e9);

    for (int t = 0; t < N_PERIODS; ++t) {
        const double h = kPeriods[t];
        double M[16], I4[16] = { 0 }, Ebe[16];
        for (int i = 0; i < 16; ++i) {
            I4[i] = (i % 5 == 0) ? 1.0 : 0.0;
            M[i] = I4[i] - h * Ae[i];
        }
        assert_int_equal(la_solve(4, M, 4, I4, Ebe), 0);
        const double rho = la_spectral_radius(4, Ebe);
        double pred = 0.0;
        for (int i = 0; i < 4; ++i) {
            pred = fmax(pred, 1.0 / hypot(1.0 - h * wr[i], h * wi[i]));
        }
        printf("# Ts = %7.0f us: backward-Euler observer rho = %.12f (1 - rho = %.3g), "
               "max 1/|1 - h lambda| = %.12f\n",
               h * 1e6, rho, 1.0 - rho, pred);
        assert_true(rho > 0.0 && rho < 1.0);
        assert_near(rho, pred, 1e-9);
    }
    /* negative control: forward Euler at 50 us */
    const double h = 50e-6;
    double Efe[16];
    for (int i = 0; i < 16; ++i) {
        Efe[i] = ((i % 5 == 0) ? 1.0 : 0.0) + h * Ae[i];
    }
    const double rho_fe = la_spectral_radius(4, Efe);
    printf("# Ts = 50 us: forward-Euler observer rho = %.6g\n", rho_fe);
    assert_true(rho_fe > 1.0);
}

/* ---- full linear loop ----------------------------------------------- */

typedef struct {
    double h, l[4];
    double Ad[9], Bd[3];  /* plant ZOH */
    double Phi[9], Gd[3]; /* internal model ZOH of u_bar */
    double gam[3];
} loop_t;

static void loop_design(loop_t *lp, double h)
{
    lp->h = h;
    gains_l(lp->l);
    const double c2 = (R_OHM * B_NMS + LAM_WB * LAM_WB * NP * NP) / L_H;
    const double c3 = B_NMS / J_KGM2 + R_OHM / L_H;
    const double b = LAM_WB * NP / L_H;
    double X[16] = { 0 }, eX[16];
    X[0 * 4 + 1] = NP * h;
    X[1 * 4 + 2] = G3 * h;
    X[2 * 4 + 1] = -c2 * h;
    X[2 * 4 + 2] = -c3 * h;
    X[2 * 4 + 3] = b * h;
    la_expm(4, X, eX);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            lp->Ad[i * 3 + j] = eX[i * 4 + j];
        }
        lp->Bd[i] = eX[i * 4 + 3];
    }
    /* internal model: F + G Gamma = companion of s (s^2 + 1) */
    double Y[16] = { 0 }, eY[16];
    Y[0 * 4 + 1] = h;
    Y[1 * 4 + 2] = h;
    Y[2 * 4 + 1] = -h;
    Y[2 * 4 + 3] = h;
    la_expm(4, Y, eY);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            lp->Phi[i * 3 + j] = eY[i * 4 + j];
        }
        lp->Gd[i] = eY[i * 4 + 3];
    }
    lp->gam[0] = 1.0;
    lp->gam[1] = 2.0;
    lp->gam[2] = 3.0;
}

/* One period, linear: X = (xi[3], xhat[4] of step k-1, eta[3], u_prev) */
static void loop_step(const loop_t *lp, const double *X, double *Xn)
{
    const double h = lp->h;
    const double *xi = X, *xp = X + 3, *eta = X + 7;
    const double u_prev = X[10];
    /* backward Euler of (13) by elimination:
     * (I - h A + h l C) x = x_prev + h e3 u_prev + h l y */
    double M[16] = { 1, -h * NP, 0, 0, 0, 1, -h * G3, 0, 0, 0, 1, -h, 0, 0, 0, 1 };
    double rhs[4], x[4];
    for (int i = 0; i < 4; ++i) {
        M[i * 4] += h * lp->l[i];
        rhs[i] = xp[i] + h * lp->l[i] * xi[0];
    }
    rhs[2] += h * u_prev;
    assert_int_equal(la_solve(4, M, 1, rhs, x), 0);
    const double ubar = (-x[3] - x[0] - 3.0 * x[1] - 3.0 * x[2]) / BBAR;
    const double v = lp->gam[0] * eta[0] + lp->gam[1] * eta[1] + lp->gam[2] * eta[2] + ubar;
    for (int i = 0; i < 3; ++i) {
        Xn[i] = lp->Ad[i * 3] * xi[0] + lp->Ad[i * 3 + 1] * xi[1] + lp->Ad[i * 3 + 2] * xi[2] +
                lp->Bd[i] * v;
        Xn[7 + i] = lp->Phi[i * 3] * eta[0] + lp->Phi[i * 3 + 1] * eta[1] +
                    lp->Phi[i * 3 + 2] * eta[2] + lp->Gd[i] * ubar;
    }
    for (int i = 0; i < 4; ++i) {
        Xn[3 + i] = x[i];
    }
    Xn[10] = BBAR * ubar;
}

static void test_full_loop_stability(void **state)
{
    (void)state;
    enum { NX = 11 };
    for (int t = 0; t < N_PERIODS; ++t) {
        loop_t lp;
        loop_design(&lp, kPeriods[t]);
        double Acl[NX * NX];
        for (int j = 0; j < NX; ++j) {
            double e[NX] = { 0 }, col[NX];
            e[j] = 1.0;
            loop_step(&lp, e, col);
            for (int i = 0; i < NX; ++i) {
                Acl[i * NX + j] = col[i];
            }
        }
        double wr[NX], wi[NX];
        assert_int_equal(la_eig(NX, Acl, wr, wi), 0);
        double rho = 0.0, slow_s = 0.0;
        for (int i = 0; i < NX; ++i) {
            const double r = hypot(wr[i], wi[i]);
            if (r > rho) {
                rho = r;
                /* equivalent continuous decay rate log(|z|) / h */
                slow_s = log(r) / kPeriods[t];
            }
        }
        printf("# Ts = %7.0f us: full linear loop rho = %.12f (slowest rate %.4g 1/s)\n",
               kPeriods[t] * 1e6, rho, slow_s);
        assert_true(rho < 1.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_be_gains_closed_form),
        cmocka_unit_test(test_observer_error_stability),
        cmocka_unit_test(test_full_loop_stability),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
