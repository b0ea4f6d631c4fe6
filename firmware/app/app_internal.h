/* Private helpers shared by the files of firmware/app. */
#ifndef MC_APP_INTERNAL_H
#define MC_APP_INTERNAL_H

#include "mc/app.h"

/* Publish a telemetry snapshot (sequence counter odd while writing).
 * Called from init and at the end of the fast ISR. */
void mc_app_publish_telemetry(mc_app_t *app, const mc_telemetry_t *t);

/* Sensorless blocks (sensorless.c). */

/* Initialise the flux, I&I and PLL observers, the IDA-PBC gains (r from
 * mc_idapbc_critical_damping_f32 when cfg r is 0), the delay compensation
 * and the ALIGN sequence (mc/align.h) from cfg; app->Ts_s must be set.
 * Status of the first block that rejects its parameters. Not for interrupt
 * context. */
mc_status_t mc_app_sensorless_init(mc_app_t *app, const mc_config_t *c);

/* End of ALIGN: restart the observers at align_angle_e_rad with the
 * offset-corrected currents of this sample, i_alpha_A / i_beta_A (Clarke,
 * computed once per ISR by the caller) (eta = psi [cos; sin], zero speed
 * and load, as in paper 001 Section 5). Fault bits (NONFINITE).
 * Interrupt context: yes. */
uint32_t mc_app_sensorless_start(mc_app_t *app, float i_alpha_A,
                                 float i_beta_A);

/* In RUN: one step of the flux observer (12)-(14) with the offset-corrected
 * currents of this sample (i_alpha_A, i_beta_A) and the voltage applied
 * over the last interval, then the I&I observer (IDA-PBC) or the PLL
 * (FOC_PI, the NAM baseline); fills theta_e, theta_m, omega_m, tau_L_hat,
 * flux_ratio_sq of *t. Outside RUN the observers are held and the
 * alignment angle is reported. Fault bits: ESTIMATE for an implausible
 * estimate, NONFINITE. Interrupt context: yes. */
uint32_t mc_app_sensorless_estimate(mc_app_t *app, float i_alpha_A,
                                    float i_beta_A, mc_telemetry_t *t);

/* One ALIGN sample (mc/align.h) from the offset-corrected currents of this
 * sample (i_alpha_A, i_beta_A) and the voltage applied over the last
 * interval: sets the i_d/i_q references of *t (frame of the ALIGN vector,
 * t->theta_e_rad) and *state. Fault bits: ESTIMATE on the settle timeout,
 * NONFINITE. Interrupt context: yes. */
uint32_t mc_app_sensorless_align(mc_app_t *app, float i_alpha_A,
                                 float i_beta_A, mc_telemetry_t *t,
                                 mc_align_state_t *state);

/* IDA-PBC (11): v_d, v_q of *t from its measured i_d, i_q (estimated
 * frame), omega_m_ref, omega_m and tau_c = tau_L_hat (+ the integral
 * action tau_I when idapbc_integral_enabled; tau_c limited to kt i_max);
 * sets the i_d/i_q reference telemetry to (0, tau_c / kt). Fault bits
 * (NONFINITE). Interrupt context: yes. */
uint32_t mc_app_idapbc_voltages(mc_app_t *app, mc_telemetry_t *t);

/* Zero the IDA-PBC integral action (start of RUN, mode change).
 * Interrupt context: yes. */
void mc_app_idapbc_reset(mc_app_t *app);

#endif /* MC_APP_INTERNAL_H */
