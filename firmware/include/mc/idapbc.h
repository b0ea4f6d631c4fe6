/*
 * IDA-PBC output-feedback speed controller of paper 001, eq. (11), float32.
 *
 *   v_hat = (R - r) i + [ -L n_p w_hat tau_hat / kt         ]
 *                       [  n_p Phi w_ref + r tau_hat / kt     ]
 * in the estimated rotor frame: i = (i_d, i_q) is the measured current
 * rotated by the estimated angle, and the caller rotates v_hat back
 * (inverse Park with the delay-compensated angle, mc/delay_comp.h), which
 * is (11)'s v_ab = (rho_a I + rho_b Jcal) v_hat with rho_hat normalised.
 * w_hat, tau_hat come from the speed/load observer (15).
 *
 * kt is the torque per A of q current. The paper's model (3) has
 * kt = n_p Phi, which turns the first component into -(L/Phi) tau_hat w_hat
 * as printed in (11). Its full-information version (22) prints
 * -(L/(J Phi)) tau_L w: that extra 1/J is a notation slip. Check against
 * the port-Hamiltonian target (40): row 1 of x' = F_d grad(H_d) reads
 * L i_d' = -r i_d + L n_p w (i_q - i_q*), while (7) gives
 * L i_d' = -R i_d + n_p w L i_q + v_d, hence
 * v_d = (R - r) i_d - L n_p w i_q* with i_q* = tau_L / kt (Remark 2):
 * no 1/J (dimensionally, (L/Phi) tau w is a voltage; (L/(J Phi)) tau w is
 * not). We use (11) / (40). Row 2 likewise gives the q component. The
 * project's amplitude-invariant plant has kt = 1.5 n_p Phi; the target
 * system then stays passive with H_d = (kt/(n_p Phi)) L |i - i*|^2 / 2
 * + J (w - w*)^2 / 2, dH_d/dt = -(kt/(n_p Phi)) r |i - i*|^2.
 *
 * Closed-loop poles (full information, linearised at w*, Section 3.2
 * matrix A11 with the same slip removed): with a = r/L, w_e* = n_p w*,
 * and b c = n_p Phi kt / (L J),
 *   s^3 + 2 a s^2 + (a^2 + b c + w_e*^2) s + a b c.
 * At w* = 0 it factors as (s + a)(s^2 + a s + b c); choosing
 *   r = 2 sqrt(n_p Phi kt L / J)      (= 2 n_p Phi sqrt(L/J) for kt = n_p Phi)
 * makes a^2 = 4 b c: poles -r/L and a double pole -r/(2L), critically
 * damped (mc_idapbc_critical_damping_f32). Paper motor: r = 0.574 ohm, poles
 * -151 and -75.5 (double) 1/s. At speed the w_e*^2 term adds mild
 * oscillation (120 rpm: w_e*^2 = 1421 vs b c = 5704 1/s^2). The observer
 * blocks A22, A33 add their own poles (the closed loop is block triangular,
 * proof of Proposition 1).
 *
 * Optional integral action (beyond the paper; mc_idapbc_integral_design_f32).
 * Under a plant/model mismatch (R, Phi) (11) leaves a steady speed offset:
 * it has no integrator. The correction enters where (11) already carries
 * the torque the loop must produce, the reference i_q* = tau_c / kt of
 * Remark 2 (both components of (11)): tau_c = tau_hat + tau_I with
 *   tau_I = K_P e + K_I integral(e dt),   e = w_ref - w_hat,
 * so (11) keeps its structure and, at the nominal point in steady state
 * (e = 0 on average, integrator at its reset value 0 there), is exactly the
 * paper's law. Linearised full-information loop at w* = 0 (q current,
 * speed, integrator; row 2 of (40) with i_q* moved by tau_I / kt, and
 * J w' = kt i_q - tau_L):
 *   (L s + r) J s / kt + r C(s) / kt + n_p Phi = 0,  C = K_P + K_I / s
 *   =>  s^3 + a s^2 + (b c + a K_P / J) s + a K_I / J = 0
 * (the d axis keeps its pole -a). A pure integrator (K_P = 0) would split
 * the designed critically damped pair (project motor, kt = 1.5 n_p Phi,
 * critical r = 0.703 ohm, a = 185 1/s, pair -92.5 twice: for p = 10 1/s
 * it moves to -58 and -117); with K_P the cubic is placed at
 *   (s + p)(s^2 + (a - p) s + beta),  beta = (a - p)^2 b c / a^2,
 * i.e. one slow real pole p (the integrator's; "a slow pole well below the
 * IDA-PBC poles") and the IDA-PBC pair at the damping ratio it was designed
 * with (a / (2 sqrt(b c)); 1 for the critical r), its rate reduced by p/2:
 *   K_P = J (beta + (a - p) p - b c) / a,   K_I = J beta p / a.
 * Required: the pair's slowest rate >= 2 p, K_P >= 0 (damping ratio of the
 * design above about 0.71 for small p). Project motor, p = 10 1/s: pair
 * -87.5 (double), K_P = 0.0551 N m s/rad, K_I = 4.97 N m/rad (the PI's
 * zero K_I / K_P = 90 1/s sits at the pair, whose damping it supplies;
 * the integrator's pole is the slow one). Discrete (Ts = 50 us) and
 * sensorless (w_hat from (15)) effects: measured, tests/sim.
 *
 * No voltage limit here: the modulator limits and reports saturation.
 * Units: A, V, ohm, H, Wb, N m, kg m^2, rad/s (MECHANICAL speeds).
 */
#ifndef MC_IDAPBC_H
#define MC_IDAPBC_H

#include <stdint.h>

#include "mc/compiler.h"
#include "mc/status.h"

typedef struct {
    float R_ohm;         /* >= 0 */
    float L_H;           /* > 0 */
    float psi_Wb;        /* Phi > 0 */
    uint32_t pole_pairs; /* n_p >= 1 */
    float kt_Nm_per_A;   /* torque per A of q current, > 0 */
    float r_ohm;         /* damping injection r > 0 */
} mc_idapbc_params_t;

typedef struct {
    float R_minus_r_ohm; /* R - r */
    float L_np_over_kt;  /* L n_p / kt, V s / (N m rad) */
    float np_psi_Wb;     /* n_p Phi, V s/rad */
    float r_over_kt;     /* r / kt, V / (N m) */
} mc_idapbc_f32_t;

typedef struct {
    float v_d_V, v_q_V;
} mc_idapbc_voltages_t;

/* Damping giving critically damped poles at w* = 0 (see above):
 * r = 2 sqrt(n_p Phi kt L / J). NaN for non-finite or non-positive
 * arguments. Interrupt context: no (design time). */
float mc_idapbc_critical_damping_f32(uint32_t pole_pairs, float psi_Wb,
                                     float kt_Nm_per_A, float L_H,
                                     float J_kgm2);

/* Validate (finite, ranges above) and store the gains.
 * MC_ERR_NONFINITE / MC_ERR_PARAM (*ctl untouched). Not for interrupt
 * context. The controller is static: nothing to reset. */
mc_status_t mc_idapbc_init_f32(mc_idapbc_f32_t *ctl,
                               const mc_idapbc_params_t *p);

/* The voltages of (11) without checks, inline, for an ISR path that
 * checks what it computes from them: any non-finite input propagates
 * into v_d or v_q. Interrupt context: yes. */
MC_STATIC_FORCEINLINE mc_idapbc_voltages_t mc_idapbc_voltages_unchecked_f32(
    const mc_idapbc_f32_t *ctl, float i_d_A, float i_q_A,
    float omega_m_ref_rad_s, float omega_m_hat_rad_s, float tau_L_hat_Nm)
{
    /* (11) with kt general (kt = n_p Phi in the paper) */
    const mc_idapbc_voltages_t v = {
        .v_d_V = ctl->R_minus_r_ohm * i_d_A -
                 ctl->L_np_over_kt * omega_m_hat_rad_s * tau_L_hat_Nm,
        .v_q_V = ctl->R_minus_r_ohm * i_q_A +
                 ctl->np_psi_Wb * omega_m_ref_rad_s +
                 ctl->r_over_kt * tau_L_hat_Nm,
    };
    return v;
}

/* One sample of (11): currents in the estimated rotor frame, speed
 * reference w_ref and estimates w_hat (mechanical rad/s), tau_hat (N m);
 * writes v_d, v_q (V). Non-finite input or result: MC_ERR_NONFINITE,
 * outputs untouched. Interrupt context: yes. */
mc_status_t mc_idapbc_step_f32(const mc_idapbc_f32_t *ctl, float i_d_A,
                               float i_q_A, float omega_m_ref_rad_s,
                               float omega_m_hat_rad_s, float tau_L_hat_Nm,
                               float *v_d_V, float *v_q_V);

/* Integral-action gains (see above) for the slow pole p = pole_rad_s
 * (1/s) with this controller's parameters and the nominal inertia J:
 * *kp_Nms_per_rad = K_P (N m per rad/s), *ki_Nm_per_rad = K_I (N m per
 * rad/s per s). MC_ERR_NONFINITE / MC_ERR_PARAM (outputs untouched) for
 * invalid parameters, p <= 0, or a p the design cannot place (pair slower
 * than 2 p, K_P < 0). Interrupt context: no (design time). */
mc_status_t mc_idapbc_integral_design_f32(const mc_idapbc_params_t *p,
                                          float J_kgm2, float pole_rad_s,
                                          float *kp_Nms_per_rad,
                                          float *ki_Nm_per_rad);

#endif /* MC_IDAPBC_H */
