/*
 * Sensorless start: rotor alignment from ANY initial angle, with active
 * damping and a settle check (the ALIGN state of mc/app.h).
 *
 * Why: the paper-001 observers start from the alignment angle and stall if
 * the rotor is 0.1 rad or more away from it. A plain d-axis current at a
 * fixed angle (1) produces no torque when the rotor sits 180 deg
 * electrical away (dead point) and (2) with no friction makes the rotor
 * swing undamped around the angle.
 *
 * Sequence: phase 1 holds the current vector at theta_a + pi/2 (the d
 * current ramped 0 -> I_a over ramp_s), phase 2 at theta_a (I_a at once).
 * Each phase lasts until the rotor has settled; then phase 2 ends ALIGN.
 * A settled phase 1 leaves the rotor at theta_a + pi/2 (its stable point)
 * or at theta_a - pi/2 (its dead point): either way 90 deg from theta_a,
 * where phase 2's torque is largest, so phase 2 never starts at its own
 * dead point.
 *
 * Rotor-angle model in the frame of the current vector (fixed angle
 * theta_v; delta = theta_e - theta_v; non-salient, L = Lq):
 *   v_q = R i_q + L di_q/dt + psi omega_e cos(delta)        (no omega L i
 *   v_d = R i_d + L di_d/dt - psi omega_e sin(delta)         terms: the
 *   tau = kt (i_q cos(delta) - i_d sin(delta))               frame is fixed)
 * Speed estimate from the q axis, exact for a constant back-EMF over one
 * sample interval [t_{k-1}, t_k] (v = the mean voltage applied over it,
 * mc/delay_comp.h; i_q at both ends):
 *   e_q = v_q - R (i_q,k + i_q,k-1) / 2 - L (i_q,k - i_q,k-1) / Ts
 *   omega_e_hat = LPF(e_q / psi) ~= omega_e cos(delta)
 * The L di/dt term is kept (it costs one multiply): without it a 1 A step
 * of the current loop (rise ~ 1 ms) would read as L di/dt / psi ~ 22 rad/s
 * for a millisecond. First-order low-pass, time constant 0.1 / omega_n
 * (phase lag 5.7 deg at omega_n): it smooths the L di/dt of current noise.
 *
 * Damping: i_q_ref = -k_d omega_e_hat (limited to i_q_max), a torque
 * -kt k_d omega_e cos^2(delta). With delta'' = n_p omega_m':
 *   delta'' + (n_p kt k_d / J) cos^2(delta) delta' + (n_p kt I_a / J)
 *   sin(delta) = 0,
 * linearised at delta = 0: omega_n^2 = n_p kt I_a / J (alignment stiffness
 * kt I_a per electrical rad, inertia J, n_p pole pairs), and
 *   k_d = 2 zeta omega_n J / (n_p kt)   [A per electrical rad/s]
 * gives the damping ratio zeta (damping_ratio). Paper-001 motor, 2 A:
 * omega_n = 19.6 rad/s (3.1 Hz), zeta = 1 -> k_d = 0.204 A s/rad.
 *
 * Settle check: after the ramp, a phase ends once |omega_e_hat| stayed
 * below settle_speed for settle_time. A rotor held that long below that
 * speed by the spring torque kt I_a sin(delta) must sit within
 * |sin(delta)| <~ 2 settle_speed / (omega_n^2 settle_time) of an
 * equilibrium (2.1e-4 with the defaults; phase 1, whose threshold is 10x
 * higher, 2.1e-3). The bound uses the configured J:
 * a plant inertia m times larger loosens it m times (measured: J x100
 * passes the check at a slow turning point 0.17 rad off), so set J_kgm2 to
 * the largest inertia expected (or lengthen settle_time). A constant load
 * torque tau_L < kt I_a during ALIGN shifts the equilibrium to
 * sin(delta) = tau_L / (kt I_a), which no standstill measurement reveals
 * (non-salient motor): start unloaded. No settling within timeout_s (from
 * the start of phase 1): MC_ALIGN_TIMEOUT (the app's fault).
 *
 * Plain struct, caller-owned; init validates; step is bounded (no loops).
 */
#ifndef MC_ALIGN_H
#define MC_ALIGN_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/status.h"

#define MC_ALIGN_TIMEOUT_MAX_S 10.0f

/* The tunable part (the configuration block "align"). */
typedef struct {
    float current_A;            /* d current I_a, > 0 */
    float ramp_s;               /* phase-1 ramp, [0, timeout_s] */
    float timeout_s;            /* whole alignment (both phases): not
                                   settled by then = MC_ALIGN_TIMEOUT;
                                   (0, MC_ALIGN_TIMEOUT_MAX_S], at most
                                   2^30 Ts */
    float angle_e_rad;          /* theta_a, |.| <= 2 pi */
    float damping_ratio;        /* zeta, (0, 10] */
    float i_q_max_A;            /* damping current limit, > 0 */
    float settle_speed_e_rad_s; /* |omega_e_hat| threshold, > 0 */
    float settle_time_s;        /* hold time, [Ts, timeout_s) */
} mc_align_config_t;

typedef struct {
    mc_align_config_t cfg;
    float R_ohm, L_H, psi_Wb; /* nominal motor: R >= 0, L, psi > 0 */
    float J_kgm2;             /* > 0 */
    float kt_Nm_per_A;        /* 1.5 n_p psi, > 0 */
    uint32_t pole_pairs;      /* >= 1 */
    float Ts_s;               /* sample period, > 0 */
} mc_align_params_t;

typedef enum {
    MC_ALIGN_BUSY = 0,
    MC_ALIGN_DONE,   /* phase 2 settled: rotor at theta_a */
    MC_ALIGN_TIMEOUT /* not settled within timeout_s */
} mc_align_state_t;

typedef struct {
    float i_d_ref_A, i_q_ref_A; /* in the frame of the vector angle */
    float omega_e_hat_rad_s;    /* ~ omega_e cos(delta) */
    mc_align_state_t state;
} mc_align_out_t;

typedef struct {
    /* design */
    float theta_e_rad[2], sin_e[2], cos_e[2]; /* phase 1, phase 2 */
    float current_A, i_q_max_A, k_d_A_s_per_rad;
    float R_ohm, L_over_Ts_ohm, inv_psi_per_Wb, lpf_a;
    float settle_speed_e_rad_s;
    uint32_t ramp_n, timeout_n, settle_n;
    /* state */
    uint32_t phase; /* 0 = phase 1, 1 = phase 2 */
    uint32_t n_total, n_phase, n_settled;
    float i_al_prev_A, i_be_prev_A;
    bool have_prev;
    float omega_e_hat_rad_s;
    mc_align_state_t state;
} mc_align_f32_t;

/* Validate p (finite, ranges above), design k_d, the filter and the
 * counts (whole periods, rounded), and reset. MC_ERR_NONFINITE or
 * MC_ERR_PARAM (*a untouched) or MC_OK. Interrupt context: no. */
mc_status_t mc_align_init_f32(mc_align_f32_t *a, const mc_align_params_t *p);

/* Start again at phase 1, ramp from zero, no history. Interrupt context:
 * yes. */
void mc_align_reset_f32(mc_align_f32_t *a);

/* Angle of the current vector this sample (theta_a + pi/2 in phase 1,
 * theta_a in phase 2), wrapped to [-pi, pi]. Interrupt context: yes. */
static inline float mc_align_theta_e_f32(const mc_align_f32_t *a)
{
    return a->theta_e_rad[a->phase];
}

/* One sample: currents at t_k and the mean voltage applied over
 * [t_{k-1}, t_k] (stationary frame, A and V) -> the current references in
 * the frame of mc_align_theta_e_f32() as read BEFORE this call, the speed
 * estimate and the state (the phase may advance for the next sample).
 * After DONE or TIMEOUT the state stays. MC_ERR_NONFINITE for a non-finite
 * input or estimate (state untouched). Interrupt context: yes; bounded. */
mc_status_t mc_align_step_f32(mc_align_f32_t *a, float i_alpha_A,
                              float i_beta_A, float v_alpha_V, float v_beta_V,
                              mc_align_out_t *out);

#endif /* MC_ALIGN_H */
