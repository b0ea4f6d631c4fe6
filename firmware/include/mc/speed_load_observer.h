/*
 * I&I speed and load-torque observer of paper 001, eqs. (15)-(16), float32,
 * in an incremental form that stays accurate for unbounded rotation.
 *
 * Paper form (theta_u = A(atan2(rho_hat)) the UNWRAPPED electrical angle,
 * k = [a1; -a2], u = [kt/J * i_q_hat; 0]):
 *   xi' = A33 xi + A33 k theta_u + u,    [w; tau] = xi + k theta_u     (15)
 *   A33 = [ -n_p a1   -1/J ]
 *         [  n_p a2    0   ]                                          (16)
 * (the printed input vector [a2/J - n_p a1^2; n_p a1 a2] of (15) is exactly
 * A33 k). Error dynamics with a known angle: chi67' = A33 chi67 (Section
 * 4.3): characteristic polynomial s^2 + n_p a1 s + n_p a2 / J. Paper gains
 * a1 = 20, a2 = 6 with n_p = 3, J = 0.012: s^2 + 60 s + 1500, poles
 * -30 +- j 24.5 1/s.
 *
 * Two traps of the paper form, both avoided here:
 * (1) Appendix A as printed (|dif| > 2 pi, reversed sign) never detects a
 *     wrap; the unwrapped increment needs the +-pi rule. Here the increment
 *     is mc_angle_diff_f32(e_k, e_{k-1}) = wrap(e_k - e_{k-1}), which equals
 *     theta_u,k - theta_u,k-1 exactly whenever the rotor turns by less than
 *     pi (electrical) per sample.
 * (2) xi carries -k theta_u, which grows without bound; in float32 the
 *     states lose their fractional part as the rotor turns (ulp(1e6 rad *
 *     a1) = 2 rad/s after 1e6 rad) and w_hat = xi1 + a1 theta_u becomes
 *     a difference of huge numbers. Measured with a float32 version of
 *     the paper form against double on the test trajectory (333 rad/s):
 *     1.7 rpm off after 1e3 rad, 25 rpm after 1e4, 1090 rpm after 1e6.
 *
 * Incremental form (derivation). Let z = [w_hat; tau_hat] = xi + k theta_u.
 * Then z' = xi' + k theta_u' = A33 (xi + k theta_u) + u + k theta_u'
 *         = A33 z + u + k theta_u'.
 * Discretising (15) by explicit Euler, xi_k = xi_{k-1} + Ts (A33 xi_{k-1} +
 * A33 k theta_u,k-1 + u), and substituting xi = z - k theta_u gives exactly
 *   z_k = z_{k-1} + Ts (A33 z_{k-1} + u) + k (theta_u,k - theta_u,k-1)
 *       = z_{k-1} + Ts (A33 z_{k-1} + u) + k wrap(e_k - e_{k-1}),
 * i.e. the Euler step of the paper's form, without any unbounded quantity.
 * Written with the innovation nu = wrap(e_k - e_{k-1}) - n_p Ts w_hat
 * (measured minus predicted electrical angle increment):
 *   w_hat   += a1 nu + Ts (kt i_q_hat - tau_hat) / J
 *   tau_hat -= a2 nu
 * Float32 accumulation: at speed the per-sample change of w_hat is far
 * below ulp(w_hat) (ulp(333 rad/s) = 3e-5 rad/s), and plain rounding acts
 * as a slowly varying disturbance worth several 1e-3 rad/s in w_hat and
 * 1e-3 N m in tau_hat (measured: 0.04 rpm after 1e6 rad at 333 rad/s).
 * w_hat is therefore accumulated with Kahan compensation (one extra float
 * state, three additions; valid without -ffast-math, which the project
 * does not use). With it: 5e-5 rad/s (5e-4 rpm) and 4e-5 N m from a double
 * implementation of the paper's form after 1e6 rad (unit test); tau_hat's
 * own rounding is below that and left uncompensated.
 * Euler stability: init checks that both eigenvalues of I + Ts A33 lie
 * inside the unit circle (Jury test on its trace and determinant).
 *
 * Torque constant: (3) has torque n_p Phi i_q (paper's scaling); with the
 * project's amplitude-invariant Clarke the torque is 1.5 n_p Phi i_q. The
 * observer takes the torque per ampere of q current, kt_Nm_per_A, so it
 * serves both (paper: kt = n_p Phi).
 *
 * Timing: step k is called with the flux observer's angle e_k at t_k and the
 * q current i_q_hat (A, mc_flux_obs_iq_f32) representing the interval
 * [t_{k-1}, t_k]; after the step, w_hat/tau_hat are the estimates at t_k.
 * Under constant acceleration alpha the Euler step settles at
 * w_hat = w(t_k) + alpha Ts / 2 (half a sample ahead) and tau_hat = tau_L
 * without bias (steady state of the error recursion; unit-tested).
 *
 * Units: rad (electrical angle), rad/s (MECHANICAL speed w_hat), N m, A,
 * kg m^2, s. a1 in (rad/s)/rad, a2 in N m/rad.
 */
#ifndef MC_SPEED_LOAD_OBSERVER_H
#define MC_SPEED_LOAD_OBSERVER_H

#include <stdint.h>

#include "mc/angle.h"
#include "mc/compensated_sum.h"
#include "mc/compiler.h"
#include "mc/estimate_bounds.h"
#include "mc/status.h"

/* Paper 001, Section 5. */
#define MC_SPEED_LOAD_OBS_A1_DEFAULT 20.0f
#define MC_SPEED_LOAD_OBS_A2_DEFAULT 6.0f

typedef struct {
    float a1;                    /* > 0 */
    float a2;                    /* > 0 */
    uint32_t pole_pairs;         /* n_p >= 1 */
    float J_kgm2;                /* > 0 */
    float kt_Nm_per_A;           /* torque per A of q current, > 0 */
    float Ts_s;                  /* > 0, Euler-stable with A33 */
    mc_estimate_bounds_t bounds; /* plausibility of the estimates */
} mc_speed_load_obs_params_t;

typedef struct {
    /* configuration */
    float a1, a2;
    float np_Ts;     /* n_p Ts, rad per (rad/s) */
    float Ts_over_J; /* Ts / J */
    float kt_Nm_per_A;
    mc_estimate_bounds_t bounds;
    /* state */
    float omega_m_rad_s;    /* w_hat */
    float omega_comp_rad_s; /* rounding carried over to the next w_hat update */
    float tau_L_Nm;         /* tau_hat */
    float theta_e_prev_rad; /* e_{k-1}, wrapped */
} mc_speed_load_obs_f32_t;

/*
 * Validate (all finite, a1, a2, J, kt, Ts > 0, n_p >= 1, bounds valid,
 * Euler step stable) and reset to angle 0, zero speed and load.
 * MC_ERR_NONFINITE / MC_ERR_PARAM on invalid parameters (*obs untouched).
 * Interrupt context: no (configuration).
 */
mc_status_t mc_speed_load_obs_init_f32(mc_speed_load_obs_f32_t *obs,
                                       const mc_speed_load_obs_params_t *p);

/*
 * Restart from a known wrapped electrical angle (e.g. the flux observer's
 * angle after alignment) and initial estimates (paper: 0, 0).
 * Non-finite input: MC_ERR_NONFINITE, state untouched. |theta| beyond
 * MC_ANGLE_MAX_ABS_RAD: MC_ERR_RANGE. Interrupt context: yes.
 */
mc_status_t mc_speed_load_obs_reset_f32(mc_speed_load_obs_f32_t *obs,
                                        float theta_e_rad, float omega_m_rad_s,
                                        float tau_L_Nm);

/*
 * One sample: theta_e_rad = wrapped electrical angle estimate at t_k,
 * i_q_A = q current over [t_{k-1}, t_k] (see header text).
 * Non-finite input or result: MC_ERR_NONFINITE, state untouched.
 * Interrupt context: yes (bounded time, no division).
 */
mc_status_t mc_speed_load_obs_step_f32(mc_speed_load_obs_f32_t *obs,
                                       float theta_e_rad, float i_q_A);

/*
 * The step of (15) from the electrical angle's increment d_theta_e_rad =
 * theta_u,k - theta_u,k-1 (below) without checks, inline, for a caller
 * that knows the increment (e.g. mc_flux_obs_d_theta_e_f32) and checks a
 * whole sample once: written into *obs whatever it gives (NaN and Inf
 * propagate into the state; theta_e_prev_rad is not touched: such a
 * caller keeps the angle). Returns the sum of x * 0 over the three new
 * estimator states: +-0 if all are finite, NaN otherwise (the aggregate
 * of mc/finite.h; a non-finite input reaches w_hat through nu).
 * Interrupt context: yes (no division).
 */
MC_STATIC_FORCEINLINE float
mc_speed_load_obs_advance_f32(mc_speed_load_obs_f32_t *obs, float d_theta_e_rad,
                              float i_q_A)
{
    const float w = obs->omega_m_rad_s;
    const float tau = obs->tau_L_Nm;
    /* innovation: measured minus predicted electrical angle increment */
    const float nu = d_theta_e_rad - obs->np_Ts * w;
    /* Euler step of (15) on z = [w; tau] (derivation in the header) */
    const float dw =
        obs->a1 * nu + obs->Ts_over_J * (obs->kt_Nm_per_A * i_q_A - tau);
    /* compensated accumulation of w_hat (see the header) */
    float comp_new;
    const float w_new =
        mc_kahan_add_f32(w, obs->omega_comp_rad_s, dw, &comp_new);
    const float tau_new = tau - obs->a2 * nu;
    obs->omega_m_rad_s = w_new;
    obs->omega_comp_rad_s = comp_new;
    obs->tau_L_Nm = tau_new;
    return w_new * 0.0f + comp_new * 0.0f + tau_new * 0.0f;
}

/*
 * The step of mc_speed_load_obs_step_f32 without its checks, inline: the
 * same operations (the increment's wrap is mc_wrap_pi_f32's result, then
 * mc_speed_load_obs_advance_f32), written into *obs whatever they give.
 * Returns as mc_speed_load_obs_advance_f32. Interrupt context: yes (no
 * division).
 */
MC_STATIC_FORCEINLINE float
mc_speed_load_obs_update_f32(mc_speed_load_obs_f32_t *obs, float theta_e_rad,
                             float i_q_A)
{
    /* Appendix A, corrected: the unwrapped increment theta_u,k - theta_u,k-1
     * with the +-pi rule, never the unbounded unwrapped angle itself. */
    const float d_theta =
        mc_angle_diff_near_f32(theta_e_rad, obs->theta_e_prev_rad);
    obs->theta_e_prev_rad = theta_e_rad;
    return mc_speed_load_obs_advance_f32(obs, d_theta, i_q_A);
}

/* Mechanical speed estimate w_hat, rad/s. Interrupt context: yes. */
static inline float
mc_speed_load_obs_omega_m_f32(const mc_speed_load_obs_f32_t *obs)
{
    return obs->omega_m_rad_s;
}

/* Load-torque estimate tau_hat, N m. Interrupt context: yes. */
static inline float
mc_speed_load_obs_tau_L_f32(const mc_speed_load_obs_f32_t *obs)
{
    return obs->tau_L_Nm;
}

/* MC_OK if the estimates are inside the configured bounds, MC_ERR_RANGE
 * otherwise (an implausible, probably diverged, estimate). Interrupt context:
 * yes. */
static inline mc_status_t
mc_speed_load_obs_check_f32(const mc_speed_load_obs_f32_t *obs)
{
    return mc_estimate_bounds_check(&obs->bounds, obs->omega_m_rad_s,
                                    obs->tau_L_Nm);
}

#endif /* MC_SPEED_LOAD_OBSERVER_H */
