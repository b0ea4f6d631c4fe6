/*
 * CSV trace of a closed-loop run, one row per recorded PWM period.
 *
 * Columns (SI; "_true" = plant state, the others as the firmware sees them):
 *   t_s, omega_m_rad_s (true), omega_m_est_rad_s, omega_m_ref_rad_s,
 *   theta_m_rad (true), theta_m_ref_rad, angle_error_e_rad (firmware theta_e
 *   minus true theta_e, wrapped to [-pi, pi)), i_d_A, i_q_A (true),
 *   i_d_ref_A, i_q_ref_A, i_a_A, i_b_A, i_c_A (true), v_d_ref_V, v_q_ref_V,
 *   v_a_V, v_b_V, v_c_V (plant phase voltages, period averages), v_dc_V,
 *   tau_e_Nm, tau_load_Nm (true), tau_load_est_Nm (firmware estimate, 0 with
 *   the encoder), state (mc_state_t), faults (mc_fault_t bits, latched),
 *   outputs_on (1 if the inverter switched during the period that starts
 *   at t_s, 0 if its outputs were off)
 */
#ifndef PMSM_SIM_TRACE_CSV_H
#define PMSM_SIM_TRACE_CSV_H

#include <stdio.h>

#include "sim_engine.h"

void trace_csv_header(FILE *f);

void trace_csv_row(FILE *f, const sim_trace_sample_t *smp);

#endif /* PMSM_SIM_TRACE_CSV_H */
