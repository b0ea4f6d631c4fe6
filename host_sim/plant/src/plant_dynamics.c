#include "plant_dynamics.h"

#include <math.h>
#include <stddef.h>

#include "plant_frames.h"

double plant_cogging_torque(const plant_t *p, double theta_m_rad)
{
    const plant_cogging_t *cog = &p->cfg.motor.cogging;
    if (cog->n_harmonics == 0u) {
        return 0.0;
    }
    /* cos/sin(k Q theta) by the angle-addition recurrence from k = 1 */
    const double c1 = cos((double)cog->slots * theta_m_rad);
    const double s1 = sin((double)cog->slots * theta_m_rad);
    double ck = c1;
    double sk = s1;
    double tau = 0.0;
    for (uint32_t k = 0; k < cog->n_harmonics; ++k) {
        tau += cog->amplitude_Nm[k] * (ck * p->cog_cos_phi[k] - sk * p->cog_sin_phi[k]);
        const double c_next = ck * c1 - sk * s1;
        sk = sk * c1 + ck * s1;
        ck = c_next;
    }
    return tau;
}

static double friction_torque(const plant_motor_params_t *m, double omega)
{
    double tau = m->B_Nm_s_rad * omega;
    if (m->tau_coulomb_Nm > 0.0) {
        const double eps = m->coulomb_eps_rad_s;
        tau += m->tau_coulomb_Nm * omega / sqrt(omega * omega + eps * eps);
    }
    return tau;
}

/* Rotor-frame voltages and bus power of the source; also the phase
 * currents and voltages for the accumulators. */
static void source_voltages(const plant_source_t *src, double i_d, double i_q, double c, double s,
                            double i_abc[3], double v_abc[3], double *v_d, double *v_q,
                            double *p_bus)
{
    plant_dq_to_abc(i_d, i_q, c, s, i_abc);
    if (src->kind == PLANT_SRC_INVERTER || src->kind == PLANT_SRC_DISABLED) {
        plant_inverter_phase_voltages(src, i_abc, v_abc, p_bus);
        plant_abc_to_dq(v_abc, c, s, v_d, v_q);
        return;
    }
    *v_d = src->v_d_V;
    *v_q = src->v_q_V;
    plant_dq_to_abc(*v_d, *v_q, c, s, v_abc);
    *p_bus = 1.5 * (*v_d * i_d + *v_q * i_q);
}

void plant_derivatives(const plant_t *p, const plant_source_t *src, double t_s, double t_piece_s,
                       const double x[PX_LEN], double dx[PX_LEN], plant_aux_t *aux)
{
    const plant_motor_params_t *m = &p->cfg.motor;
    const double i_d = x[PX_ID];
    const double i_q = x[PX_IQ];
    const double omega_m = x[PX_OMEGA];
    const double theta_e = p->n_p * x[PX_THETA];
    const double omega_e = p->n_p * omega_m;
    const double c = cos(theta_e);
    const double s = sin(theta_e);

    double i_abc[3], v_abc[3], v_d, v_q, p_bus;
    if (src->kind == PLANT_SRC_OPEN) { /* i == 0: terminals show the back-EMF */
        v_d = 0.0;
        v_q = omega_e * p->psi_Wb;
        plant_dq_to_abc(0.0, 0.0, c, s, i_abc);
        plant_dq_to_abc(v_d, v_q, c, s, v_abc);
        p_bus = 0.0;
        dx[PX_ID] = 0.0;
        dx[PX_IQ] = 0.0;
    } else {
        source_voltages(src, i_d, i_q, c, s, i_abc, v_abc, &v_d, &v_q, &p_bus);
        dx[PX_ID] = (v_d - p->R_ohm * i_d + omega_e * p->Lq_H * i_q) / p->Ld_H;
        dx[PX_IQ] = (v_q - p->R_ohm * i_q - omega_e * (p->Ld_H * i_d + p->psi_Wb)) / p->Lq_H;
    }

    const double tau_e = 1.5 * p->n_p * (p->psi_Wb * i_q + (p->Ld_H - p->Lq_H) * i_d * i_q);
    const double tau_load = sim_profile_eval_on_piece(&p->cfg.load_torque_Nm, t_s, t_piece_s);
    const double tau_cog = plant_cogging_torque(p, x[PX_THETA]);
    const double tau_fric = friction_torque(m, omega_m);
    if (p->cfg.locked_rotor) {
        dx[PX_OMEGA] = 0.0;
        dx[PX_THETA] = 0.0;
    } else {
        double g3 = p->inv_J_per_kgm2;
        if (m->g3_amplitude_per_kgm2 != 0.0) {
            g3 += m->g3_amplitude_per_kgm2 * sin(m->g3_omega_rad_s * t_s);
        }
        dx[PX_OMEGA] = g3 * (tau_e - tau_fric - tau_load - tau_cog);
        dx[PX_THETA] = omega_m;
    }

    dx[PX_E_BUS] = p_bus;
    dx[PX_E_ELEC] = 1.5 * (v_d * i_d + v_q * i_q);
    dx[PX_E_CU] = 1.5 * p->R_ohm * (i_d * i_d + i_q * i_q);
    dx[PX_E_FRIC] = dx[PX_THETA] * tau_fric;
    dx[PX_E_LOAD] = dx[PX_THETA] * tau_load;
    dx[PX_E_COG] = dx[PX_THETA] * tau_cog;
    dx[PX_VA_INT] = v_abc[0];
    dx[PX_VB_INT] = v_abc[1];
    dx[PX_VC_INT] = v_abc[2];

    if (aux != NULL) {
        for (int k = 0; k < 3; ++k) {
            aux->i_abc_A[k] = i_abc[k];
            aux->v_abc_V[k] = v_abc[k];
        }
        aux->tau_e_Nm = tau_e;
        aux->tau_load_Nm = tau_load;
        aux->tau_cog_Nm = tau_cog;
        aux->tau_friction_Nm = tau_fric;
    }
}
