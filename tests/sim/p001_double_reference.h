/*
 * Independent DOUBLE-precision reference of paper 001's observers, for
 * test_p001_float_vs_double (host only; shares no code with the firmware).
 *
 * Flux observer (12)-(14), stationary alpha-beta frame:
 *   lambda_k = lambda_{k-1} + Ts (v_bar_k - R (i_{k-1} + i_k) / 2)
 *            + Ts gamma eta_{k-1} (Phi^2 - |eta_{k-1}|^2)
 *   eta_k = lambda_k - L i_k,  rho_k = eta_k / Phi,
 *   theta_k = atan2(eta_beta, eta_alpha)   (libm double atan2)
 * i.e. the sampled form documented in mc/flux_observer.h (mean applied
 * voltage over [t_{k-1}, t_k], trapezoidal R i, explicit-Euler gradient
 * term).
 *
 * Speed / load observer (15)-(16) in the paper's ORIGINAL form: states xi,
 * the UNWRAPPED angle theta_u = A(theta_k) (Appendix A operator with the
 * correct +-pi jump rule and a counter n, y = e + 2 pi n), outputs
 *   [w; tau] = xi + k theta_u,    k = [a1; -a2],
 * and explicit Euler on
 *   xi' = A33 xi + A33 k theta_u + [kt/J i_q; 0],
 *   A33 = [-n_p a1, -1/J; n_p a2, 0]
 * (A33 k = [a2/J - n_p a1^2; n_p a1 a2], the paper's printed input vector):
 *   xi_k = xi_{k-1} + Ts (A33 xi_{k-1} + A33 k theta_u,k-1 + u_k),
 *   u_k = [kt/J * i_q,k; 0] with i_q,k the q current over [t_{k-1}, t_k].
 * kt is the torque per ampere of q current (paper: n_p Phi; the project's
 * amplitude-invariant Clarke: 1.5 n_p Phi).
 *
 * Units: SI, angles electrical (rad), speed mechanical (rad/s).
 */
#ifndef P001_DOUBLE_REFERENCE_H
#define P001_DOUBLE_REFERENCE_H

#include <stdint.h>

typedef struct {
    double R_ohm, L_H, Phi_Wb, gamma, Ts_s;
    double lambda[2]; /* lambda_hat_k (alpha, beta), Wb */
    double eta[2];    /* eta_k, Wb */
    double i_prev[2]; /* i_k, A */
    double theta_e;   /* atan2(eta_beta, eta_alpha), (-pi, pi] */
} p001d_flux_obs_t;

/* Parameters; the state starts like p001d_flux_obs_reset(0, 0, 0). */
void p001d_flux_obs_init(p001d_flux_obs_t *o, double R_ohm, double L_H, double Phi_Wb, double gamma,
                         double Ts_s);
/* Known angle and currents now: eta = Phi [cos; sin], lambda = L i + eta. */
void p001d_flux_obs_reset(p001d_flux_obs_t *o, double theta_e, double i_alpha, double i_beta);
/* One sample: i at t_k, v_bar the mean voltage over [t_{k-1}, t_k]. */
void p001d_flux_obs_step(p001d_flux_obs_t *o, double i_alpha, double i_beta, double v_alpha,
                         double v_beta);
/* i^T Jcal rho_hat = -i_alpha rho_beta + i_beta rho_alpha (A). */
double p001d_flux_obs_iq(const p001d_flux_obs_t *o, double i_alpha, double i_beta);

/* Appendix A unwrap operator: y_k = e_k + 2 pi n_k. */
typedef struct {
    double e_prev;
    int64_t n;
} p001d_unwrap_t;

void p001d_unwrap_reset(p001d_unwrap_t *u, double e0);
/* e in (-pi, pi]; a jump of more than pi between samples is a wrap. */
double p001d_unwrap_step(p001d_unwrap_t *u, double e);

typedef struct {
    double a1, a2, np, J, kt, Ts_s;
    double xi[2];
    double theta_u; /* A(theta) at the last sample */
    p001d_unwrap_t unwrap;
    double omega_m; /* outputs of (15) at the last sample */
    double tau_L;
} p001d_speed_obs_t;

void p001d_speed_obs_init(p001d_speed_obs_t *o, double a1, double a2, double np, double J,
                          double kt, double Ts_s);
/* Start from the wrapped angle theta_e (A's counter at 0) and estimates
 * omega_m, tau_L: xi = [omega_m; tau_L] - k theta_u. */
void p001d_speed_obs_reset(p001d_speed_obs_t *o, double theta_e, double omega_m, double tau_L);
/* One sample: wrapped angle at t_k, q current over [t_{k-1}, t_k]. */
void p001d_speed_obs_step(p001d_speed_obs_t *o, double theta_e, double i_q);

#endif /* P001_DOUBLE_REFERENCE_H */
