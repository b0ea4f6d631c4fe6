#include "p001_double_reference.h"

#include <math.h>

#include "mc_test.h"

void p001d_flux_obs_init(p001d_flux_obs_t *o, double R_ohm, double L_H, double Phi_Wb, double gamma,
                         double Ts_s)
{
    o->R_ohm = R_ohm;
    o->L_H = L_H;
    o->Phi_Wb = Phi_Wb;
    o->gamma = gamma;
    o->Ts_s = Ts_s;
    p001d_flux_obs_reset(o, 0.0, 0.0, 0.0);
}

void p001d_flux_obs_reset(p001d_flux_obs_t *o, double theta_e, double i_alpha, double i_beta)
{
    o->eta[0] = o->Phi_Wb * cos(theta_e);
    o->eta[1] = o->Phi_Wb * sin(theta_e);
    o->lambda[0] = o->L_H * i_alpha + o->eta[0];
    o->lambda[1] = o->L_H * i_beta + o->eta[1];
    o->i_prev[0] = i_alpha;
    o->i_prev[1] = i_beta;
    o->theta_e = atan2(o->eta[1], o->eta[0]);
}

void p001d_flux_obs_step(p001d_flux_obs_t *o, double i_alpha, double i_beta, double v_alpha,
                         double v_beta)
{
    const double i[2] = { i_alpha, i_beta };
    const double v[2] = { v_alpha, v_beta };
    const double e2 = o->eta[0] * o->eta[0] + o->eta[1] * o->eta[1];
    const double g = o->gamma * (o->Phi_Wb * o->Phi_Wb - e2);
    for (unsigned j = 0u; j < 2u; ++j) {
        /* (12) */
        o->lambda[j] +=
            o->Ts_s * (v[j] - o->R_ohm * 0.5 * (o->i_prev[j] + i[j])) + o->Ts_s * g * o->eta[j];
    }
    for (unsigned j = 0u; j < 2u; ++j) {
        o->eta[j] = o->lambda[j] - o->L_H * i[j]; /* (14) */
        o->i_prev[j] = i[j];
    }
    o->theta_e = atan2(o->eta[1], o->eta[0]); /* (13) */
}

double p001d_flux_obs_iq(const p001d_flux_obs_t *o, double i_alpha, double i_beta)
{
    const double ra = o->eta[0] / o->Phi_Wb;
    const double rb = o->eta[1] / o->Phi_Wb;
    return -i_alpha * rb + i_beta * ra;
}

void p001d_unwrap_reset(p001d_unwrap_t *u, double e0)
{
    u->e_prev = e0;
    u->n = 0;
}

double p001d_unwrap_step(p001d_unwrap_t *u, double e)
{
    const double dif = e - u->e_prev;
    if (dif < -MC_TEST_PI) {
        u->n += 1; /* crossed +pi going forward */
    } else if (dif > MC_TEST_PI) {
        u->n -= 1; /* crossed -pi going backward */
    }
    u->e_prev = e;
    return e + MC_TEST_TWO_PI * (double)u->n;
}

void p001d_speed_obs_init(p001d_speed_obs_t *o, double a1, double a2, double np, double J,
                          double kt, double Ts_s)
{
    o->a1 = a1;
    o->a2 = a2;
    o->np = np;
    o->J = J;
    o->kt = kt;
    o->Ts_s = Ts_s;
    p001d_speed_obs_reset(o, 0.0, 0.0, 0.0);
}

void p001d_speed_obs_reset(p001d_speed_obs_t *o, double theta_e, double omega_m, double tau_L)
{
    p001d_unwrap_reset(&o->unwrap, theta_e);
    o->theta_u = theta_e;
    o->xi[0] = omega_m - o->a1 * o->theta_u;
    o->xi[1] = tau_L + o->a2 * o->theta_u;
    o->omega_m = omega_m;
    o->tau_L = tau_L;
}

void p001d_speed_obs_step(p001d_speed_obs_t *o, double theta_e, double i_q)
{
    /* A33 and the input vector A33 k of (15)-(16) */
    const double A11 = -o->np * o->a1;
    const double A12 = -1.0 / o->J;
    const double A21 = o->np * o->a2;
    const double b1 = o->a2 / o->J - o->np * o->a1 * o->a1;
    const double b2 = o->np * o->a1 * o->a2;
    const double u1 = o->kt / o->J * i_q;
    const double x1 = o->xi[0];
    const double x2 = o->xi[1];
    const double th = o->theta_u; /* A(theta) at t_{k-1} */
    o->xi[0] = x1 + o->Ts_s * (A11 * x1 + A12 * x2 + b1 * th + u1);
    o->xi[1] = x2 + o->Ts_s * (A21 * x1 + b2 * th);
    o->theta_u = p001d_unwrap_step(&o->unwrap, theta_e);
    o->omega_m = o->xi[0] + o->a1 * o->theta_u;
    o->tau_L = o->xi[1] - o->a2 * o->theta_u;
}
