/*
 * Baseline speed loop: PI from the mechanical speed error to the q-axis
 * current reference, with the current limit as output limit (anti-windup
 * by the PI's clamping).
 *
 * Design from the nominal mechanics J, torque constant k_t = 1.5 * n_p * psi
 * (surface PMSM, i_d = 0) and a bandwidth w_s:
 *   kp = J * w_s / k_t,   ki = kp * w_s / 4.
 * With an ideal current loop the plant i_q -> omega_m is k_t / (J s), so the
 * closed-loop characteristic polynomial is s^2 + w_s s + w_s^2 / 4: a double
 * pole at -w_s/2 (critically damped), and a load-torque step T_L gives the
 * speed deviation -(T_L / J) * t * exp(-w_s t / 2), peak at t = 2 / w_s.
 * Viscous friction B (nominal) is fed forward: i_q += B * omega_ref / k_t.
 *
 * Units: rad/s (mechanical), A, kg m^2, N m s/rad, s.
 */
#ifndef MC_SPEED_LOOP_H
#define MC_SPEED_LOOP_H

#include "mc/pi.h"
#include "mc/status.h"

/* Largest w_s Ts of the speed loop's own sample period (the discrete PI
 * then stays within a few percent of the continuous design). */
#define MC_SPEED_LOOP_WTS_MAX 0.2f

typedef struct {
    float J_kgm2;          /* nominal inertia, > 0 */
    float B_Nm_s_rad;      /* nominal viscous friction, >= 0 */
    float kt_Nm_per_A;     /* torque constant 1.5 * n_p * psi, > 0 */
    float bandwidth_rad_s; /* w_s, > 0, w_s Ts <= MC_SPEED_LOOP_WTS_MAX */
    float i_q_max_A;       /* output limit |i_q_ref| <= i_q_max_A, > 0 */
    float Ts_s;            /* sample period of the speed loop, > 0 */
} mc_speed_loop_params_t;

typedef struct {
    mc_pi_f32_t pi;
    float B_over_kt; /* friction feed-forward gain, A s/rad */
    float i_q_max_A;
} mc_speed_loop_f32_t;

/* Validate, design the gains (see above) and reset. MC_ERR_PARAM /
 * MC_ERR_NONFINITE on invalid parameters. Interrupt context: no. */
mc_status_t mc_speed_loop_init_f32(mc_speed_loop_f32_t *sl,
                                   const mc_speed_loop_params_t *p);

/* Zero the integrator. Interrupt context: yes. */
void mc_speed_loop_reset_f32(mc_speed_loop_f32_t *sl);

/* One sample: returns the q-axis current reference in A, limited to
 * +-i_q_max_A. Non-finite inputs give a non-finite output, which the
 * application turns into a fault (a NaN speed error also leaves the
 * integrator NaN until the next reset). Interrupt context: yes. */
float mc_speed_loop_step_f32(mc_speed_loop_f32_t *sl, float omega_m_ref_rad_s,
                             float omega_m_rad_s);

#endif /* MC_SPEED_LOOP_H */
