#include "plant.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "plant_dynamics.h"
#include "plant_frames.h"

/* Classic RK4 step of length h from (t_s, x), in place. */
static void rk4_step(const plant_t *p, const plant_source_t *src, double t_s, double h,
                     double x[PX_LEN])
{
    double k1[PX_LEN], k2[PX_LEN], k3[PX_LEN], k4[PX_LEN], xs[PX_LEN];
    const double t_mid = t_s + 0.5 * h;
    plant_derivatives(p, src, t_s, t_mid, x, k1, NULL);
    for (int j = 0; j < PX_LEN; ++j)
        xs[j] = x[j] + 0.5 * h * k1[j];
    plant_derivatives(p, src, t_mid, t_mid, xs, k2, NULL);
    for (int j = 0; j < PX_LEN; ++j)
        xs[j] = x[j] + 0.5 * h * k2[j];
    plant_derivatives(p, src, t_mid, t_mid, xs, k3, NULL);
    for (int j = 0; j < PX_LEN; ++j)
        xs[j] = x[j] + h * k3[j];
    plant_derivatives(p, src, t_s + h, t_mid, xs, k4, NULL);
    for (int j = 0; j < PX_LEN; ++j) {
        x[j] += (h / 6.0) * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]);
    }
}

static void update_view(plant_t *p, const plant_source_t *src)
{
    plant_aux_t aux;
    double dx[PX_LEN];
    plant_derivatives(p, src, p->t_s, p->t_s, p->x, dx, &aux);
    plant_true_state_t *v = &p->view;
    v->t_s = p->t_s;
    v->i_d_A = p->x[PX_ID];
    v->i_q_A = p->x[PX_IQ];
    v->omega_m_rad_s = p->x[PX_OMEGA];
    v->theta_m_rad = p->x[PX_THETA];
    double theta_e = fmod(p->n_p * p->x[PX_THETA], PLANT_TWO_PI);
    v->theta_e_rad = theta_e < 0.0 ? theta_e + PLANT_TWO_PI : theta_e;
    for (int k = 0; k < 3; ++k) {
        v->i_abc_A[k] = aux.i_abc_A[k];
        v->v_abc_V[k] = p->x[PX_VA_INT + k] / p->period_s;
    }
    v->tau_e_Nm = aux.tau_e_Nm;
    v->tau_load_Nm = aux.tau_load_Nm;
    v->tau_cog_Nm = aux.tau_cog_Nm;
    v->tau_friction_Nm = aux.tau_friction_Nm;
    v->v_dc_V = src->v_dc_V;
    v->outputs_enabled = (src->kind == PLANT_SRC_INVERTER || src->kind == PLANT_SRC_IDEAL_DQ);
    v->open_circuit = p->open_circuit;
    v->rectification_unmodelled = p->rectification_unmodelled;
    v->energy = (plant_energy_t){ .bus_J = p->x[PX_E_BUS],
                                  .electrical_J = p->x[PX_E_ELEC],
                                  .copper_J = p->x[PX_E_CU],
                                  .friction_J = p->x[PX_E_FRIC],
                                  .load_J = p->x[PX_E_LOAD],
                                  .cogging_J = p->x[PX_E_COG] };
}

static double bus_voltage_at(const plant_t *p, double t_s)
{
    const double v = sim_profile_eval(&p->cfg.inverter.v_dc_V, t_s);
    return v > 0.0 ? v : 0.0;
}

int plant_init(plant_t *p, const plant_config_t *cfg)
{
    if (p == NULL) {
        return PLANT_ERR_NULL;
    }
    memset(p, 0, sizeof *p);
    const int rc = plant_config_validate(cfg, &p->err_msg);
    if (rc != PLANT_OK) {
        return rc;
    }
    p->cfg = *cfg;
    const plant_motor_params_t *m = &cfg->motor;
    p->R_ohm = m->R_ohm * cfg->mismatch.R;
    p->Ld_H = m->Ld_H * cfg->mismatch.L;
    p->Lq_H = m->Lq_H * cfg->mismatch.L;
    p->psi_Wb = m->psi_Wb * cfg->mismatch.psi;
    p->inv_J_per_kgm2 = 1.0 / (m->J_kgm2 * cfg->mismatch.J);
    p->n_p = (double)m->pole_pairs;
    for (uint32_t k = 0; k < m->cogging.n_harmonics; ++k) {
        p->cog_cos_phi[k] = cos(m->cogging.phase_rad[k]);
        p->cog_sin_phi[k] = sin(m->cogging.phase_rad[k]);
    }
    p->period_s = 1.0 / cfg->inverter.f_pwm_Hz;
    p->h_s = p->period_s / (double)cfg->substeps_per_period;
    p->x[PX_THETA] = cfg->theta_m0_rad;
    p->x[PX_OMEGA] = cfg->locked_rotor ? 0.0 : cfg->omega_m0_rad_s;
    p->rng_state = cfg->sensors.seed;
    p->encoder_turns =
        (int64_t)floor((cfg->theta_m0_rad + cfg->sensors.encoder.offset_rad) / PLANT_TWO_PI);
    const plant_source_t src = { .kind = PLANT_SRC_INVERTER,
                                 .duty = { 0.5, 0.5, 0.5 },
                                 .v_dc_V = bus_voltage_at(p, 0.0) };
    update_view(p, &src);
    p->initialised = true;
    return PLANT_OK;
}

const char *plant_error_message(const plant_t *p)
{
    return (p == NULL || p->err_msg == NULL) ? "plant is NULL" : p->err_msg;
}

double plant_period_s(const plant_t *p)
{
    return p->period_s;
}

const plant_true_state_t *plant_true_state(const plant_t *p)
{
    return &p->view;
}

/* Disabled outputs: once no phase current exceeds what one substep at the
 * full bus voltage can change, the diodes have stopped conducting. */
static bool currents_extinguished(const plant_t *p, double v_dc_V)
{
    const double l_min = p->Ld_H < p->Lq_H ? p->Ld_H : p->Lq_H;
    const double i_min_A = 2.0 * v_dc_V * p->h_s / l_min;
    const double theta_e = p->n_p * p->x[PX_THETA];
    double i_abc[3];
    plant_dq_to_abc(p->x[PX_ID], p->x[PX_IQ], cos(theta_e), sin(theta_e), i_abc);
    return fabs(i_abc[0]) <= i_min_A && fabs(i_abc[1]) <= i_min_A && fabs(i_abc[2]) <= i_min_A;
}

/* RK4 substeps j0 .. j1 - 1 of the current period under src (a disabled
 * inverter becomes an open circuit once the diodes stop conducting). */
static void integrate_substeps(plant_t *p, plant_source_t *src, uint32_t j0, uint32_t j1)
{
    const double t0 = p->t_s;
    for (uint32_t j = j0; j < j1; ++j) {
        rk4_step(p, src, t0 + (double)j * p->h_s, p->h_s, p->x);
        if (src->kind == PLANT_SRC_DISABLED && currents_extinguished(p, src->v_dc_V)) {
            p->x[PX_ID] = p->x[PX_IQ] = 0.0;
            p->open_circuit = true;
            src->kind = PLANT_SRC_OPEN;
        }
    }
}

/* End of the period: time, the rectification flag, the true-state view
 * (with the source of the period's last part). */
static void finish_period(plant_t *p, const plant_source_t *src)
{
    p->n_periods += 1u;
    p->t_s = (double)p->n_periods * p->period_s;
    if (src->kind == PLANT_SRC_OPEN) {
        const double e_line_peak_V = PLANT_SQRT3 * p->psi_Wb * fabs(p->n_p * p->x[PX_OMEGA]);
        if (e_line_peak_V > src->v_dc_V) {
            p->rectification_unmodelled = true;
        }
    }
    update_view(p, src);
}

static double clamp01(double d)
{
    if (!(d >= 0.0))
        return 0.0; /* also maps NaN to 0 */
    return d > 1.0 ? 1.0 : d;
}

/* The inverter as a source with these duties / outputs on the bus v_dc. */
static plant_source_t inverter_source(plant_t *p, const double duty_abc[3], bool outputs_enabled,
                                      double v_dc_V)
{
    plant_source_t src = { 0 };
    src.v_dc_V = v_dc_V;
    if (outputs_enabled) {
        p->open_circuit = false;
        src.kind = PLANT_SRC_INVERTER;
        for (int k = 0; k < 3; ++k) {
            src.duty[k] = clamp01(duty_abc[k]);
        }
        const plant_inverter_params_t *inv = &p->cfg.inverter;
        src.v_error_V = inv->t_dead_s * inv->f_pwm_Hz * src.v_dc_V + inv->v_device_drop_V;
        src.i_band_A = inv->dead_time_current_band_A;
    } else {
        if (!p->open_circuit && currents_extinguished(p, src.v_dc_V)) {
            p->x[PX_ID] = p->x[PX_IQ] = 0.0;
            p->open_circuit = true;
        }
        src.kind = p->open_circuit ? PLANT_SRC_OPEN : PLANT_SRC_DISABLED;
    }
    return src;
}

static void start_period(plant_t *p)
{
    p->x[PX_VA_INT] = p->x[PX_VB_INT] = p->x[PX_VC_INT] = 0.0;
}

void plant_advance(plant_t *p, const double duty_abc[3], bool outputs_enabled)
{
    if (!p->initialised) {
        return;
    }
    const double v_dc_V = bus_voltage_at(p, p->t_s + 0.5 * p->period_s);
    plant_source_t src = inverter_source(p, duty_abc, outputs_enabled, v_dc_V);
    start_period(p);
    integrate_substeps(p, &src, 0u, p->cfg.substeps_per_period);
    finish_period(p, &src);
}

void plant_advance_split(plant_t *p, const double duty_first[3], bool outputs_first,
                         const double duty_second[3], bool outputs_second)
{
    if (!p->initialised) {
        return;
    }
    const uint32_t n = p->cfg.substeps_per_period;
    const double v_dc_V = bus_voltage_at(p, p->t_s + 0.5 * p->period_s);
    start_period(p);
    plant_source_t src = inverter_source(p, duty_first, outputs_first, v_dc_V);
    integrate_substeps(p, &src, 0u, n / 2u);
    src = inverter_source(p, duty_second, outputs_second, v_dc_V);
    integrate_substeps(p, &src, n / 2u, n);
    finish_period(p, &src);
}

void plant_advance_vdq(plant_t *p, double v_d_V, double v_q_V)
{
    if (!p->initialised) {
        return;
    }
    p->open_circuit = false;
    plant_source_t src = { .kind = PLANT_SRC_IDEAL_DQ, .v_d_V = v_d_V, .v_q_V = v_q_V };
    src.v_dc_V = bus_voltage_at(p, p->t_s + 0.5 * p->period_s);
    start_period(p);
    integrate_substeps(p, &src, 0u, p->cfg.substeps_per_period);
    finish_period(p, &src);
}
