/* CSV trace rows (columns in trace_csv.h). */
#include "trace_csv.h"

#include "angle_diff.h"

void trace_csv_header(FILE *f)
{
    fputs("t_s,omega_m_rad_s,omega_m_est_rad_s,omega_m_ref_rad_s,theta_m_rad,theta_m_ref_rad,"
          "angle_error_e_rad,i_d_A,i_q_A,i_d_ref_A,i_q_ref_A,i_a_A,i_b_A,i_c_A,v_d_ref_V,"
          "v_q_ref_V,v_a_V,v_b_V,v_c_V,v_dc_V,tau_e_Nm,tau_load_Nm,tau_load_est_Nm,state,faults,"
          "outputs_on\n",
          f);
}

void trace_csv_row(FILE *f, const sim_trace_sample_t *smp)
{
    const plant_true_state_t *p = &smp->plant;
    const mc_telemetry_t *fw = &smp->fw;
    fprintf(f,
            "%.9g,%.7g,%.7g,%.7g,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,"
            "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%u,%d\n",
            p->t_s, p->omega_m_rad_s, (double)fw->omega_m_rad_s, (double)fw->omega_m_ref_rad_s,
            p->theta_m_rad, (double)fw->theta_m_ref_rad,
            angle_diff_rad((double)fw->theta_e_rad, p->theta_e_rad), p->i_d_A, p->i_q_A,
            (double)fw->i_d_ref_A, (double)fw->i_q_ref_A, p->i_abc_A[0], p->i_abc_A[1],
            p->i_abc_A[2], (double)fw->v_d_V, (double)fw->v_q_V, p->v_abc_V[0], p->v_abc_V[1],
            p->v_abc_V[2], p->v_dc_V, p->tau_e_Nm, p->tau_load_Nm, (double)fw->tau_L_hat_Nm,
            (int)fw->state,
            (unsigned)fw->faults_latched, smp->outputs_applied ? 1 : 0);
}
