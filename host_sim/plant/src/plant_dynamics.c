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

double plant_friction_torque(const plant_motor_params_t *m, double omega)
{
    double tau = m->B_Nm_s_rad * omega;
    if (m->tau_coulomb_Nm > 0.0) {
        const double eps = m->coulomb_eps_rad_s;
        tau += m->tau_coulomb_Nm * omega / sqrt(omega * omega + eps * eps);
    }
    return tau;
}

/* Rotor-frame voltages and bus power of a source with no floating phase
 * (switching or ideal dq): the original path, kept operation for
 * operation. Also the phase currents and voltages for the accumulators. */
static void source_voltages(const plant_source_t *src, double v_dc_V, double v_error_V, double i_d,
                            double i_q, double c, double s, double i_abc[3], double v_abc[3],
                            double *v_d, double *v_q, double *p_bus)
{
    plant_dq_to_abc(i_d, i_q, c, s, i_abc);
    if (src->kind == PLANT_SRC_INVERTER) {
        plant_inverter_phase_voltages(src, v_dc_V, v_error_V, i_abc, v_abc, p_bus);
        plant_abc_to_dq(v_abc, c, s, v_d, v_q);
        return;
    }
    *v_d = src->v_d_V;
    *v_q = src->v_q_V;
    plant_dq_to_abc(*v_d, *v_q, c, s, v_abc);
    *p_bus = 1.5 * (*v_d * i_d + *v_q * i_q);
}

/* Dead-time error magnitude of the switching model at the link voltage. */
static double dead_time_error_V(const plant_t *p, const plant_source_t *src, double v_dc_V)
{
    const plant_inverter_params_t *inv = &p->cfg.inverter;
    return p->link_dynamic ? p->faults.t_dead_s * inv->f_pwm_Hz * v_dc_V + inv->v_device_drop_V
                           : src->v_error_V;
}

/* cos and sin of theta_e - 2 pi k / 3 (phase k's axis) from c, s. */
static void phase_axis(int k, double c, double s, double *c_k, double *s_k)
{
    static const double cos_k[3] = { 1.0, -0.5, -0.5 };
    static const double sin_k[3] = { 0.0, 0.5 * PLANT_SQRT3, -0.5 * PLANT_SQRT3 };
    *c_k = c * cos_k[k] + s * sin_k[k];
    *s_k = s * cos_k[k] - c * sin_k[k];
}

void plant_electrical(const plant_t *p, const plant_source_t *src, const double x[PX_LEN], double c,
                      double s, plant_elec_t *el)
{
    const double i_d = x[PX_ID];
    const double i_q = x[PX_IQ];
    const double omega_e = p->n_p * x[PX_OMEGA];
    const double v_dc = plant_link_voltage(p, src, x);
    const double v_f = p->cfg.inverter.v_device_drop_V;
    plant_dq_to_abc(i_d, i_q, c, s, el->i_abc_A);
    el->u_float_V = 0.0;
    el->i_bridge_A = 0.0;
    if (p->n_floating >= 2u) { /* all currents zero: the phases show the back-EMF */
        el->v_d_V = 0.0;
        el->v_q_V = omega_e * p->psi_Wb;
        plant_dq_to_abc(el->v_d_V, el->v_q_V, c, s, el->e_abc_V);
        for (int k = 0; k < 3; ++k) {
            el->v_abc_V[k] = el->e_abc_V[k];
        }
        el->di_d_A_s = 0.0;
        el->di_q_A_s = 0.0;
        el->p_bus_W = 0.0;
        return;
    }
    double v_ideal[3] = { 0.0, 0.0, 0.0 };
    if (src->kind == PLANT_SRC_IDEAL_DQ) {
        plant_dq_to_abc(src->v_d_V, src->v_q_V, c, s, v_ideal);
    }
    const double v_err = dead_time_error_V(p, src, v_dc);
    double v_term[3] = { 0.0, 0.0, 0.0 }; /* a floating terminal: 0 until solved */
    double i_bridge = 0.0;
    int k_float = -1;
    for (int k = 0; k < 3; ++k) {
        switch (p->phase_state[k]) {
        case PLANT_PHASE_DRIVEN:
            if (src->kind == PLANT_SRC_INVERTER) {
                v_term[k] = plant_inverter_terminal_V(src, k, el->i_abc_A[k], v_dc, v_err);
                i_bridge += src->duty[k] * el->i_abc_A[k];
            } else {
                v_term[k] = v_ideal[k];
            }
            break;
        case PLANT_PHASE_UPPER_DIODE:
            v_term[k] = v_dc + v_f;
            i_bridge += el->i_abc_A[k];
            break;
        case PLANT_PHASE_LOWER_DIODE: v_term[k] = -v_f; break;
        case PLANT_PHASE_BLOCKING:
        case PLANT_PHASE_OPEN:
        default: k_float = k; break;
        }
    }
    double v_d, v_q;
    plant_abc_to_dq(v_term, c, s, &v_d, &v_q);
    if (k_float >= 0) {
        /* v_dq = v_dq0 + u (2/3) (c_x, -s_x); solve di_x/dt = 0 for u */
        double c_x, s_x;
        phase_axis(k_float, c, s, &c_x, &s_x);
        const double a_d = v_d - p->R_ohm * i_d + omega_e * p->Lq_H * i_q;
        const double a_q = v_q - p->R_ohm * i_q - omega_e * (p->Ld_H * i_d + p->psi_Wb);
        const double num =
            omega_e * (s_x * i_d + c_x * i_q) - c_x * a_d / p->Ld_H + s_x * a_q / p->Lq_H;
        const double den = (2.0 / 3.0) * (c_x * c_x / p->Ld_H + s_x * s_x / p->Lq_H);
        const double u = num / den;
        v_d += (2.0 / 3.0) * c_x * u;
        v_q -= (2.0 / 3.0) * s_x * u;
        v_term[k_float] = u;
        el->u_float_V = u;
    }
    const double common = (v_term[0] + v_term[1] + v_term[2]) / 3.0;
    for (int k = 0; k < 3; ++k) {
        el->v_abc_V[k] = v_term[k] - common;
    }
    el->v_d_V = v_d;
    el->v_q_V = v_q;
    el->di_d_A_s = (v_d - p->R_ohm * i_d + omega_e * p->Lq_H * i_q) / p->Ld_H;
    el->di_q_A_s = (v_q - p->R_ohm * i_q - omega_e * (p->Ld_H * i_d + p->psi_Wb)) / p->Lq_H;
    if (src->kind == PLANT_SRC_IDEAL_DQ) {
        el->p_bus_W = 1.5 * (v_d * i_d + v_q * i_q);
    } else {
        el->i_bridge_A = i_bridge;
        el->p_bus_W = v_dc * i_bridge;
    }
}

/* Bridge current of a source with no floating phase: switching, the
 * average sum d_x i_x; the ideal dq source has no bridge. */
static double plain_bridge_current_A(const plant_source_t *src, const double i_abc[3])
{
    if (src->kind != PLANT_SRC_INVERTER) {
        return 0.0;
    }
    return src->duty[0] * i_abc[0] + src->duty[1] * i_abc[1] + src->duty[2] * i_abc[2];
}

/* Source, brake and capacitor of a dynamic link: d/dt of v and of the link
 * energies; the currents for the view. */
static void link_derivatives(const plant_t *p, double t_s, double t_piece_s, const double x[PX_LEN],
                             double i_bridge_A, double dx[PX_LEN], plant_aux_t *aux)
{
    const plant_dc_link_t *link = &p->cfg.dc_link;
    const double v = x[PX_VDC];
    const double v_s = sim_profile_eval_on_piece(&p->cfg.inverter.v_dc_V, t_s, t_piece_s);
    double i_src = 0.0;
    if (p->faults.source_connected && v_s > v) { /* the series diode */
        i_src = (v_s - v) / link->source_resistance_ohm;
    }
    const double i_brake = p->brake_on ? v / link->brake_resistance_ohm : 0.0;
    const double i_net = i_src - i_bridge_A - i_brake;
    dx[PX_VDC] = p->link_clamped ? 0.0 : i_net / link->capacitance_F;
    dx[PX_E_SRC] = v_s * i_src;
    dx[PX_E_RSRC] = link->source_resistance_ohm * i_src * i_src;
    dx[PX_E_BRAKE] = v * i_brake;
    dx[PX_E_CLAMP] = p->link_clamped ? v * i_net : 0.0; /* -v i_clamp, i_clamp = -i_net */
    if (aux != NULL) {
        aux->v_source_V = v_s;
        aux->i_source_A = i_src;
        aux->i_brake_A = i_brake;
    }
}

void plant_derivatives(const plant_t *p, const plant_source_t *src, double t_s, double t_piece_s,
                       const double x[PX_LEN], double dx[PX_LEN], plant_aux_t *aux)
{
    const plant_motor_params_t *m = &p->cfg.motor;
    const double i_d = x[PX_ID];
    const double i_q = x[PX_IQ];
    const double omega_m = x[PX_OMEGA];
    const double theta_e = p->n_p * x[PX_THETA];
    const double c = cos(theta_e);
    const double s = sin(theta_e);

    double i_abc[3], v_abc[3], v_d, v_q, p_bus;
    double i_bridge = 0.0; /* the plain path computes it only when needed */
    const bool plain = src->kind != PLANT_SRC_DIODES && p->n_floating == 0u;
    if (plain) {
        const double omega_e = p->n_p * omega_m;
        double v_dc = src->v_dc_V;
        double v_err = src->v_error_V;
        if (p->link_dynamic) {
            v_dc = x[PX_VDC];
            v_err = dead_time_error_V(p, src, v_dc);
        }
        source_voltages(src, v_dc, v_err, i_d, i_q, c, s, i_abc, v_abc, &v_d, &v_q, &p_bus);
        dx[PX_ID] = (v_d - p->R_ohm * i_d + omega_e * p->Lq_H * i_q) / p->Ld_H;
        dx[PX_IQ] = (v_q - p->R_ohm * i_q - omega_e * (p->Ld_H * i_d + p->psi_Wb)) / p->Lq_H;
    } else {
        plant_elec_t el;
        plant_electrical(p, src, x, c, s, &el);
        for (int k = 0; k < 3; ++k) {
            i_abc[k] = el.i_abc_A[k];
            v_abc[k] = el.v_abc_V[k];
        }
        v_d = el.v_d_V;
        v_q = el.v_q_V;
        p_bus = el.p_bus_W;
        i_bridge = el.i_bridge_A;
        dx[PX_ID] = el.di_d_A_s;
        dx[PX_IQ] = el.di_q_A_s;
    }

    const double tau_e = 1.5 * p->n_p * (p->psi_Wb * i_q + (p->Ld_H - p->Lq_H) * i_d * i_q);
    const double tau_load = sim_profile_eval_on_piece(&p->cfg.load_torque_Nm, t_s, t_piece_s);
    const double tau_cog = plant_cogging_torque(p, x[PX_THETA]);
    const double tau_fric = plant_friction_torque(m, omega_m);
    if (p->faults.rotor_locked) {
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
    if (p->link_dynamic) {
        if (plain) {
            i_bridge = plain_bridge_current_A(src, i_abc);
        }
        link_derivatives(p, t_s, t_piece_s, x, i_bridge, dx, aux);
    }

    if (aux != NULL) {
        for (int k = 0; k < 3; ++k) {
            aux->i_abc_A[k] = i_abc[k];
            aux->v_abc_V[k] = v_abc[k];
        }
        aux->tau_e_Nm = tau_e;
        aux->tau_load_Nm = tau_load;
        aux->tau_cog_Nm = tau_cog;
        aux->tau_friction_Nm = tau_fric;
        aux->v_dc_V = plant_link_voltage(p, src, x);
        aux->i_bridge_A = plain ? plain_bridge_current_A(src, i_abc) : i_bridge;
        if (!p->link_dynamic) { /* the stiff bus is the source */
            aux->v_source_V = aux->v_dc_V;
            aux->i_source_A = i_bridge;
            aux->i_brake_A = 0.0;
        }
    }
}
