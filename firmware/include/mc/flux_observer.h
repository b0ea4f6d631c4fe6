/*
 * Gradient flux / rotor-position observer of paper 001, eqs. (12)-(14)
 * (Ortega et al., its reference [9]), float32.
 *
 * Continuous form, stationary alpha-beta frame:
 *   d(lambda_hat)/dt = -R i + v + gamma * eta * (Phi^2 - |eta|^2)   (12)
 *   eta = lambda_hat - L i                                           (14)
 *   rho_hat = eta / Phi,   theta_e_hat = atan2(eta_beta, eta_alpha)  (13)
 * lambda is the stator flux linkage (26): lambda = L i + Phi [cos; sin].
 *
 * Discretisation (sample period Ts, step k at the current sample t_k):
 *   lambda_k = lambda_{k-1} + Ts * (v_bar - R * (i_{k-1} + i_k) / 2)
 *            + Ts * gamma * eta_{k-1} * (Phi^2 - |eta_{k-1}|^2)
 *   eta_k    = lambda_k - L i_k
 * The measurable part (v - R i) is integrated over [t_{k-1}, t_k]: v_bar is
 * the MEAN voltage actually applied over that interval (the caller's job, see
 * mc/delay_comp.h, mc_applied_voltage_*: with the HAL's timing the duties of
 * ISR k take effect one PWM period later, so v_bar is a blend of the commands
 * of ISRs k-2 and k-1, never the command computed now), and R i by the
 * trapezoid rule. The gradient correction is explicit Euler.
 *
 * Euler stability bound: linearising the correction about |eta| = Phi, the
 * radial error obeys d(delta)/dt = -2 gamma Phi^2 delta, whose Euler map is
 * delta_k = (1 - 2 gamma Phi^2 Ts) delta_{k-1}: stable iff
 *   Ts < 1 / (gamma Phi^2)
 * (monotone, no sign flipping, for Ts < 1/(2 gamma Phi^2)). Paper values
 * gamma = 5000, Phi = 0.17 Wb: 1/(gamma Phi^2) = 6.92 ms, so 50 us (20 kHz)
 * has a factor 138 margin. init rejects Ts >= 1/(gamma Phi^2). The tangential
 * (angle) error is rotated exactly by the sampled trajectory and contracted
 * by the same factor, so no speed-dependent bound arises. Far from the
 * circle (|eta|^2 > Phi^2 + 2/(gamma Ts), i.e. > 2.8 Wb at 20 kHz) the
 * explicit step would overshoot; physical flux linkages never get there from
 * an aligned start (reset).
 *
 * Error dynamics (paper (27)-(31)): lambda_tilde = lambda_hat - lambda obeys
 * (27) independently of the trajectory; in the rotor frame the linearisation
 * is chi' = A22 chi with
 *   A22 = [ -2 gamma Phi^2   omega_e ]
 *         [ -omega_e         0       ],     omega_e = n_p omega_m,
 * (the printed "n_p/J omega*" in (31) is a notation slip: the frame turns at
 * n_p omega). Characteristic polynomial s^2 + 2 gamma Phi^2 s + omega_e^2:
 * for |omega_e| < gamma Phi^2 two real poles, the slow one about
 * -omega_e^2 / (2 gamma Phi^2) (angle error decays slowly at low speed:
 * -5.0 1/s at 120 rpm with the paper's motor, -4.97 1/s after Euler);
 * above, a complex pair with real part -gamma Phi^2 (-145.5 1/s after
 * Euler). At standstill the angle is not observable (paper Remark 5).
 * Converged float32 accuracy on exact data: |rho_hat - rho| ~ 1e-6
 * (unit test).
 *
 * Units: A, V, ohm, H, Wb, s, rad (ELECTRICAL angle theta_e). gamma in
 * 1/(Wb^2 s).
 * Non-finite inputs or results: MC_ERR_NONFINITE, state untouched.
 */
#ifndef MC_FLUX_OBSERVER_H
#define MC_FLUX_OBSERVER_H

#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/status.h"

/* Paper 001, Section 5. */
#define MC_FLUX_OBS_GAMMA_DEFAULT 5000.0f

typedef struct {
    float R_ohm;  /* stator resistance, >= 0 */
    float L_H;    /* stator inductance, > 0 */
    float psi_Wb; /* PM flux linkage Phi, > 0 */
    float gamma;  /* observer gain, > 0, 1/(Wb^2 s) */
    float Ts_s;   /* sample period, 0 < Ts < 1/(gamma Phi^2) */
} mc_flux_obs_params_t;

typedef struct {
    /* configuration (from init) */
    float Ts_s, R_ohm, L_H;
    float half_R_ohm;     /* R/2 (trapezoid) */
    float psi_Wb;         /* Phi */
    float psi_sq_Wb2;     /* Phi^2 */
    float inv_psi_per_Wb; /* 1/Phi */
    float gamma;
    /* state */
    float lambda_alpha_Wb, lambda_beta_Wb; /* lambda_hat_k */
    float eta_alpha_Wb, eta_beta_Wb;       /* eta_k */
    float i_alpha_prev_A, i_beta_prev_A;   /* i_k (for the next trapezoid) */
    float theta_e_rad;   /* the angle of eta, [-pi, pi] (see update) */
    float d_theta_e_rad; /* its increment over the last step, (-pi, pi] */
} mc_flux_obs_f32_t;

/*
 * Validate the parameters (all finite, L, Phi, gamma, Ts > 0, R >= 0,
 * Ts < 1/(gamma Phi^2)) and reset to theta_e = 0 with zero current.
 * MC_ERR_NONFINITE / MC_ERR_PARAM on invalid parameters (*obs untouched).
 * Interrupt context: no (configuration).
 */
mc_status_t mc_flux_obs_init_f32(mc_flux_obs_f32_t *obs,
                                 const mc_flux_obs_params_t *p);

/*
 * Start from a known rotor angle (e.g. after d-axis alignment) and the
 * currents measured now: lambda_hat = L i + Phi [cos theta_e; sin theta_e],
 * so eta = Phi [cos; sin] exactly. The paper's start (Section 5) is
 * theta_e = 0. Non-finite input: MC_ERR_NONFINITE, state untouched.
 * Interrupt context: yes.
 */
mc_status_t mc_flux_obs_reset_f32(mc_flux_obs_f32_t *obs, float theta_e_rad,
                                  float i_alpha_A, float i_beta_A);

/*
 * One sample at t_k: i_*_A measured at t_k, v_*_V the mean voltage applied
 * over [t_{k-1}, t_k] (see above). Updates the flux estimate and the angle
 * (atan2 of eta). Non-finite input or result: MC_ERR_NONFINITE, state
 * untouched. Interrupt context: yes (bounded time, one atan2, no
 * division, no sqrt).
 */
mc_status_t mc_flux_obs_step_f32(mc_flux_obs_f32_t *obs, float i_alpha_A,
                                 float i_beta_A, float v_alpha_V,
                                 float v_beta_V);

/*
 * The flux part of the step ((12) and (14)), unchecked: lambda_hat and eta
 * advanced, the angle state left as it was (for a caller that does not
 * use (13), or that forms it next: mc_flux_obs_update_f32). Returns eta_alpha
 * * 0 + eta_beta * 0 (below). Interrupt context: yes (no division).
 */
MC_STATIC_FORCEINLINE float
mc_flux_obs_advance_f32(mc_flux_obs_f32_t *obs, float i_alpha_A, float i_beta_A,
                        float v_alpha_V, float v_beta_V)
{
    const float Ts = obs->Ts_s;
    const float half_R = obs->half_R_ohm;
    /* gradient term of (12) at the previous sample (explicit Euler) */
    const float ea = obs->eta_alpha_Wb;
    const float eb = obs->eta_beta_Wb;
    const float corr = obs->gamma * (obs->psi_sq_Wb2 - (ea * ea + eb * eb));
    /* (12): measurable flux increment (mean v, trapezoid R i) + correction */
    const float la =
        obs->lambda_alpha_Wb +
        Ts * (v_alpha_V - half_R * (obs->i_alpha_prev_A + i_alpha_A) +
              corr * ea);
    const float lb =
        obs->lambda_beta_Wb +
        Ts * (v_beta_V - half_R * (obs->i_beta_prev_A + i_beta_A) + corr * eb);
    obs->lambda_alpha_Wb = la;
    obs->lambda_beta_Wb = lb;
    obs->i_alpha_prev_A = i_alpha_A; /* for the next trapezoid */
    obs->i_beta_prev_A = i_beta_A;
    /* (14) */
    const float na = la - obs->L_H * i_alpha_A;
    const float nb = lb - obs->L_H * i_beta_A;
    obs->eta_alpha_Wb = na;
    obs->eta_beta_Wb = nb;
    return na * 0.0f + nb * 0.0f;
}

/*
 * The step of mc_flux_obs_step_f32 without its checks, inline, for a
 * caller that checks a whole sample once: the same operations, written
 * into *obs whatever they give (NaN and Inf propagate into the state).
 * Returns eta_alpha * 0 + eta_beta * 0, +-0 if the step's inputs and
 * results are all finite and NaN otherwise (the aggregate of mc/finite.h:
 * eta = lambda - L i is non-finite whenever a current, a voltage, a flux
 * or the previous state is, so the two new eta decide).
 * The angle (13): exact_angle, atan2(eta) (as the checked step); else the
 * last angle advanced by the angle between the last two eta
 * (mc_atan2_small_f32 of their cross and dot products: 18 instructions
 * on the M4 instead of atan2's 42), wrapped. Each such step adds its
 * roundings, the increment's and the addition's (at most 2e-7 rad, unit
 * test), to the angle: a caller that advances it takes an exact step
 * every few samples (the drive: on every slow tick, mc/estimator.h).
 * Interrupt context: yes (one division, no sqrt).
 */
MC_STATIC_FORCEINLINE float
mc_flux_obs_update_f32(mc_flux_obs_f32_t *obs, float i_alpha_A, float i_beta_A,
                       float v_alpha_V, float v_beta_V, bool exact_angle)
{
    const float ea = obs->eta_alpha_Wb;
    const float eb = obs->eta_beta_Wb;
    const float finite =
        mc_flux_obs_advance_f32(obs, i_alpha_A, i_beta_A, v_alpha_V, v_beta_V);
    const float na = obs->eta_alpha_Wb;
    const float nb = obs->eta_beta_Wb;
    /* (13): angle of eta (finite for a finite eta) */
    const float theta_prev = obs->theta_e_rad;
    float theta;
    float d_theta;
    if (exact_angle) {
        theta = mc_atan2_unchecked_f32(nb, na);
        d_theta = mc_angle_diff_near_f32(theta, theta_prev);
    } else {
        d_theta = mc_atan2_small_f32(ea * nb - eb * na, ea * na + eb * nb);
        theta = mc_wrap_pi_near_f32(theta_prev + d_theta);
    }
    obs->theta_e_rad = theta;
    obs->d_theta_e_rad = d_theta;
    return finite;
}

/* The angle's increment over the last step, (-pi, pi]. Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE float
mc_flux_obs_d_theta_e_f32(const mc_flux_obs_f32_t *obs)
{
    return obs->d_theta_e_rad;
}

/* Estimated electrical angle theta_e_hat of the last step, [-pi, pi].
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE float
mc_flux_obs_theta_e_f32(const mc_flux_obs_f32_t *obs)
{
    return obs->theta_e_rad;
}

/* rho_hat = eta / Phi of (13) (unit length once converged).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE void mc_flux_obs_rho_f32(const mc_flux_obs_f32_t *obs,
                                               float *rho_alpha,
                                               float *rho_beta)
{
    *rho_alpha = obs->eta_alpha_Wb * obs->inv_psi_per_Wb;
    *rho_beta = obs->eta_beta_Wb * obs->inv_psi_per_Wb;
}

/* |rho_hat|^2 = |eta|^2 / Phi^2: 1 on the observer's circle; a value far
 * from 1 (say outside [0.25, 4]) means the observer lost the flux.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_flux_obs_rho_sq_f32(const mc_flux_obs_f32_t *obs)
{
    const float ra = obs->eta_alpha_Wb * obs->inv_psi_per_Wb;
    const float rb = obs->eta_beta_Wb * obs->inv_psi_per_Wb;
    return ra * ra + rb * rb;
}

/* Torque-producing current seen through the estimate, i^T Jcal rho_hat =
 * -i_alpha rho_beta + i_beta rho_alpha (the input term of (15)), in A.
 * Equals i_q when rho_hat is exact. Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_flux_obs_iq_f32(const mc_flux_obs_f32_t *obs,
                                               float i_alpha_A, float i_beta_A)
{
    float ra, rb;
    mc_flux_obs_rho_f32(obs, &ra, &rb);
    return -i_alpha_A * rb + i_beta_A * ra;
}

#endif /* MC_FLUX_OBSERVER_H */
