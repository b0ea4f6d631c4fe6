/*
 * Paper 002 regulator tests: the Section IV motor, an independent double
 * model of the observer's plant (5)/(7) in (nu, w), and a double
 * simulation of the mechanical + q-axis plant with its disturbances.
 * Nothing here calls the firmware's design code.
 */
#ifndef CDOBC_TEST_PLANT_H
#define CDOBC_TEST_PLANT_H

#include <math.h>

#include "eeo_test_linalg.h"

/* Section IV motor, as the float32 parameters hold it */
#define P2_NP  4.0
#define P2_Q   32.0
#define P2_PSI ((double)0.084f)
#define P2_L   ((double)26e-3f)
#define P2_R   ((double)9.7f)
#define P2_J   ((double)1.35e-4f)
#define P2_B   ((double)7.4e-5f)
#define P2_KT  (1.5 * P2_NP * P2_PSI) /* N m / A */
#define P2_TS  ((double)1e-4f)
#define P2_B1  (P2_KT / P2_J)
#define P2_A   (P2_B / P2_J + P2_R / P2_L)
#define P2_CQD (P2_R * P2_B / P2_KT + P2_NP * P2_PSI) /* (6), V s/rad */

/* A model list as the tests see it: harmonic frequencies as mechanical
 * multiples of the speed, polynomial order N */
typedef struct {
    int n_harm;
    double mult[4];
    int N;
} p2_models_t;

static inline int p2_order(const p2_models_t *m)
{
    return 1 + 2 * m->n_harm + m->N;
}

/* Continuous (nu, w) model, nf = n + 1 states, input v:
 * nu' = b1 x2, x2' = -a x2 + D - (v - c_qd omega) / L (omega = -nu),
 * harmonic pairs [0 1; -w^2 0], integrator chain; h marks the model
 * outputs (indices of w, i.e. without nu). */
static inline void p2_cont_model(const p2_models_t *m, double omega, double *Af, double *gf,
                                 double *h)
{
    const int n = p2_order(m), nf = n + 1;
    for (int i = 0; i < nf * nf; ++i) {
        Af[i] = 0.0;
    }
    for (int i = 0; i < nf; ++i) {
        gf[i] = 0.0;
    }
    for (int i = 0; i < n; ++i) {
        h[i] = 0.0;
    }
    Af[0 * nf + 1] = P2_B1;
    Af[1 * nf + 0] = -P2_CQD / P2_L;
    Af[1 * nf + 1] = -P2_A;
    gf[1] = -1.0 / P2_L;
    int s = 2; /* index in (nu, w) */
    for (int i = 0; i < m->n_harm; ++i, s += 2) {
        const double w = m->mult[i] * omega;
        Af[1 * nf + s] = 1.0;
        Af[s * nf + s + 1] = 1.0;
        Af[(s + 1) * nf + s] = -w * w;
        h[s - 1] = 1.0;
    }
    for (int j = 0; j < m->N; ++j) {
        if (j == 0) {
            Af[1 * nf + s] = 1.0;
            h[s - 1] = 1.0;
        } else {
            Af[(s + j - 1) * nf + s + j] = 1.0;
        }
    }
}

/* Exact ZOH by la_expm of [Af gf; 0 0] Ts: Phi (nf x nf), Gam (nf) */
static inline void p2_zoh(int nf, const double *Af, const double *gf, double Ts, double *Phi,
                          double *Gam)
{
    const int na = nf + 1;
    double X[LA_NMAX * LA_NMAX] = { 0.0 }, E[LA_NMAX * LA_NMAX];
    for (int i = 0; i < nf; ++i) {
        for (int j = 0; j < nf; ++j) {
            X[i * na + j] = Af[i * nf + j] * Ts;
        }
        X[i * na + nf] = gf[i] * Ts;
    }
    la_expm(na, X, E);
    for (int i = 0; i < nf; ++i) {
        for (int j = 0; j < nf; ++j) {
            Phi[i * nf + j] = E[i * na + j];
        }
        Gam[i] = E[i * na + nf];
    }
}

/* The physical plant with disturbances, integrated by RK4 with fixed
 * substeps:  J omega' = Kt i_q - B omega - T_d,
 *            L i_q' = v + u_d - R i_q - n_p psi omega,
 * theta_m' = omega, t' = 1. T_d = T_load + T_ramp t + T_cog cos(Q th)
 * + T_h1 cos(n_p th) + T_h2 cos(2 n_p th) + T_sin sin(w_sin t); u_d =
 * U_6 cos(6 n_p th), with
 * th = theta_m (angle-locked, as in the machine) or, if omega_t > 0,
 * th = omega_t t (time-locked at a fixed speed: Remark 3's steady state).
 * J, R, L, psi scaled by fJ, fR, fL, fK (1 = nominal). */
typedef struct {
    double T_load, T_ramp, T_cog, T_h1, T_h2, U_6;
    double T_sin, w_sin; /* time-locked sinusoidal load (N m, rad/s) */
    double omega_t;
    double fJ, fR, fL, fK;
} p2_dist_t;

typedef struct {
    double omega, i_q, theta_m, t;
} p2_plant_t;

/* the disturbance torque and voltage at state x = (omega, i_q, th, t) */
static inline void p2_dist_at(const p2_dist_t *d, const double *x, double *Td, double *ud)
{
    const double th = (d->omega_t > 0.0) ? d->omega_t * x[3] : x[2];
    *Td = d->T_load + d->T_ramp * x[3] + d->T_cog * cos(P2_Q * th) + d->T_h1 * cos(P2_NP * th) +
          d->T_h2 * cos(2.0 * P2_NP * th) + d->T_sin * sin(d->w_sin * x[3]);
    *ud = d->U_6 * cos(6.0 * P2_NP * th);
}

static inline void p2_deriv(const p2_dist_t *d, const double *x, double v, double *dx)
{
    const double J = P2_J * d->fJ, R = P2_R * d->fR, L = P2_L * d->fL;
    const double psi = P2_PSI * d->fK, kt = 1.5 * P2_NP * psi;
    double Td, ud;
    p2_dist_at(d, x, &Td, &ud);
    dx[0] = (kt * x[1] - P2_B * x[0] - Td) / J;
    dx[1] = (v + ud - R * x[1] - P2_NP * psi * x[0]) / L;
    dx[2] = x[0];
    dx[3] = 1.0;
}

static inline void p2_plant_step(p2_plant_t *p, const p2_dist_t *d, double v, double Ts, int sub)
{
    double x[4] = { p->omega, p->i_q, p->theta_m, p->t };
    const double h = Ts / (double)sub;
    for (int s = 0; s < sub; ++s) {
        double k1[4], k2[4], k3[4], k4[4], t[4];
        p2_deriv(d, x, v, k1);
        for (int i = 0; i < 4; ++i) {
            t[i] = x[i] + 0.5 * h * k1[i];
        }
        p2_deriv(d, t, v, k2);
        for (int i = 0; i < 4; ++i) {
            t[i] = x[i] + 0.5 * h * k2[i];
        }
        p2_deriv(d, t, v, k3);
        for (int i = 0; i < 4; ++i) {
            t[i] = x[i] + h * k3[i];
        }
        p2_deriv(d, t, v, k4);
        for (int i = 0; i < 4; ++i) {
            x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    p->omega = x[0];
    p->i_q = x[1];
    p->theta_m = x[2];
    p->t = x[3];
}

#endif /* CDOBC_TEST_PLANT_H */
