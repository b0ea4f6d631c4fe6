#include "plant.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "plant_dynamics.h"
#include "plant_exact.h"
#include "plant_frames.h"
#include "plant_rk4.h"
#include "plant_sensors.h"

/* Events (conduction and brake changes, plant.h) are located inside a
 * substep to EVENT_TIME_TOL of a substep, in at most EVENT_LOCATE_MAX_IT
 * re-integrations; a substep handles at most EVENTS_PER_SUBSTEP_MAX located
 * events (then the rest of it applies its changes at its end), an instant at
 * most SETTLE_MAX simultaneous changes. */
#define EVENT_TIME_TOL         1e-9
#define EVENT_LOCATE_MAX_IT    60
#define EVENTS_PER_SUBSTEP_MAX 16u
#define SETTLE_MAX             8
/* A conducting phase's current has crossed zero once it is below
 * -CURRENT_ZERO_REL (|i_d| + |i_q|) against its diode: the dq -> abc
 * rounding of a current that is exactly zero in the projected state. */
#define CURRENT_ZERO_REL (64.0 * DBL_EPSILON)

/* One RK4 step (plant_rk4.h); a function here, so its callers share one copy. */
static void rk4_step(const plant_t *p, const plant_source_t *src, double t_s, double h,
                     double x[PX_LEN])
{
    plant_rk4_step(p, src, t_s, h, x);
}

static double magnetic_energy_J(const plant_t *p)
{
    const double i_d = p->x[PX_ID];
    const double i_q = p->x[PX_IQ];
    return 0.75 * (p->Ld_H * i_d * i_d + p->Lq_H * i_q * i_q);
}

static bool conducting(plant_phase_state_t st)
{
    return st == PLANT_PHASE_UPPER_DIODE || st == PLANT_PHASE_LOWER_DIODE;
}

static bool floating(plant_phase_state_t st)
{
    return st == PLANT_PHASE_BLOCKING || st == PLANT_PHASE_OPEN;
}

/* The floating phase when exactly one floats. */
static int floating_phase(const plant_t *p)
{
    for (int k = 0; k < 3; ++k) {
        if (floating(p->phase_state[k])) {
            return k;
        }
    }
    return 0; /* not reached: callers check n_floating == 1 */
}

/* Phase currents of the state with the floating phases at exactly zero
 * and, with one floating, the other two at exactly +-I. */
static void phase_currents(const plant_t *p, double c, double s, double i_abc[3])
{
    plant_dq_to_abc(p->x[PX_ID], p->x[PX_IQ], c, s, i_abc);
    if (p->n_floating >= 2u) {
        i_abc[0] = i_abc[1] = i_abc[2] = 0.0;
    } else if (p->n_floating == 1u) {
        const int k = floating_phase(p);
        const int y = (k + 1) % 3;
        const int z = (k + 2) % 3;
        const double i_loop = 0.5 * (i_abc[y] - i_abc[z]);
        i_abc[k] = 0.0;
        i_abc[y] = i_loop;
        i_abc[z] = -i_loop;
    }
}

/* Puts the state on the constraint of the floating phases (their currents
 * zero); the magnetic energy this removes goes to constraint_J. */
static void project_currents(plant_t *p)
{
    if (p->n_floating == 0u) {
        return;
    }
    const double w0_J = magnetic_energy_J(p);
    if (p->n_floating >= 2u) {
        p->x[PX_ID] = 0.0;
        p->x[PX_IQ] = 0.0;
    } else {
        const double theta_e = p->n_p * p->x[PX_THETA];
        const double c = cos(theta_e);
        const double s = sin(theta_e);
        double i_abc[3];
        phase_currents(p, c, s, i_abc);
        plant_abc_to_dq(i_abc, c, s, &p->x[PX_ID], &p->x[PX_IQ]);
    }
    p->constraint_J += w0_J - magnetic_energy_J(p);
}

/* After conduction states changed: the floating count; in the diode
 * bridge two floating phases leave no path, so every connected phase
 * blocks; then the currents onto the constraint. */
static uint32_t count_floating(const plant_t *p)
{
    uint32_t n = 0u;
    for (int k = 0; k < 3; ++k) {
        n += floating(p->phase_state[k]) ? 1u : 0u;
    }
    return n;
}

static void conduction_changed(plant_t *p)
{
    if (p->diode_mode && count_floating(p) >= 2u) {
        for (int k = 0; k < 3; ++k) {
            if (p->phase_state[k] != PLANT_PHASE_OPEN) {
                p->phase_state[k] = PLANT_PHASE_BLOCKING;
            }
        }
    }
    p->n_floating = count_floating(p);
    project_currents(p);
}

/* ---- Events ---------------------------------------------------------------
 * g < 0: the change is due. EV_CURRENT + k: conducting phase k's current
 * against its diode; EV_FLOAT_HIGH / LOW: the one blocking phase's terminal
 * above v_dc + v_f / below -v_f; EV_PAIR + j: pair j's line back-EMF above
 * v_dc + 2 v_f (all currents zero); EV_BRAKE: the chopper threshold;
 * EV_CLAMP: the link below -v_f, or (clamped) the legs' current i_clamp. */
enum {
    EV_CURRENT = 0,
    EV_FLOAT_HIGH = 3,
    EV_FLOAT_LOW,
    EV_PAIR,
    EV_BRAKE = EV_PAIR + 3,
    EV_CLAMP,
    EV_COUNT
};

static const int pair_first[3] = { 0, 1, 2 };  /* pairs (a, b), (b, c), (c, a) */
static const int pair_second[3] = { 1, 2, 0 }; /* pairs (a, b), (b, c), (c, a) */

typedef struct {
    double g[EV_COUNT];
    bool active[EV_COUNT];
    bool pair_first_high[3]; /* e_first > e_second */
} plant_events_t;

static void bridge_event_values(const plant_t *p, const plant_source_t *src, const double x[PX_LEN],
                                plant_events_t *ev)
{
    const double theta_e = p->n_p * x[PX_THETA];
    const double c = cos(theta_e);
    const double s = sin(theta_e);
    plant_elec_t el;
    plant_electrical(p, src, x, c, s, &el);
    const double v_dc = plant_link_voltage(p, src, x);
    const double v_f = p->cfg.inverter.v_device_drop_V;
    const double i_tol = CURRENT_ZERO_REL * (fabs(x[PX_ID]) + fabs(x[PX_IQ]));
    for (int k = 0; k < 3; ++k) {
        const plant_phase_state_t st = p->phase_state[k];
        if (conducting(st)) {
            const double i = el.i_abc_A[k];
            ev->g[EV_CURRENT + k] = (st == PLANT_PHASE_UPPER_DIODE ? -i : i) + i_tol;
            ev->active[EV_CURRENT + k] = true;
        }
    }
    if (p->n_floating == 1u) {
        if (p->phase_state[floating_phase(p)] == PLANT_PHASE_BLOCKING) {
            ev->g[EV_FLOAT_HIGH] = v_dc + v_f - el.u_float_V;
            ev->g[EV_FLOAT_LOW] = el.u_float_V + v_f;
            ev->active[EV_FLOAT_HIGH] = ev->active[EV_FLOAT_LOW] = true;
        }
    } else if (p->n_floating >= 2u) {
        for (int j = 0; j < 3; ++j) {
            const int y = pair_first[j];
            const int z = pair_second[j];
            if (p->phase_state[y] == PLANT_PHASE_OPEN || p->phase_state[z] == PLANT_PHASE_OPEN) {
                continue;
            }
            const double e_line_V = el.e_abc_V[y] - el.e_abc_V[z];
            ev->g[EV_PAIR + j] = v_dc + 2.0 * v_f - fabs(e_line_V);
            ev->active[EV_PAIR + j] = true;
            ev->pair_first_high[j] = e_line_V > 0.0;
        }
    }
}

static bool has_brake(const plant_t *p)
{
    return p->link_dynamic && p->cfg.dc_link.brake_resistance_ohm > 0.0;
}

/* The event functions at (t_s, x). */
static void event_values(const plant_t *p, const plant_source_t *src, double t_s,
                         const double x[PX_LEN], plant_events_t *ev)
{
    memset(ev, 0, sizeof *ev);
    if (src->kind == PLANT_SRC_DIODES) {
        bridge_event_values(p, src, x, ev);
    }
    if (!p->link_dynamic) {
        return;
    }
    const plant_dc_link_t *link = &p->cfg.dc_link;
    if (has_brake(p)) {
        ev->g[EV_BRAKE] =
            p->brake_on ? x[PX_VDC] - link->brake_off_V : link->brake_on_V - x[PX_VDC];
        ev->active[EV_BRAKE] = true;
    }
    if (p->link_clamped) { /* i_clamp = i_bridge + i_brake - i_source */
        plant_aux_t aux;
        double dx[PX_LEN];
        plant_derivatives(p, src, t_s, t_s, x, dx, &aux);
        ev->g[EV_CLAMP] = aux.i_bridge_A + aux.i_brake_A - aux.i_source_A;
    } else {
        ev->g[EV_CLAMP] = x[PX_VDC] + p->cfg.inverter.v_device_drop_V;
    }
    ev->active[EV_CLAMP] = true;
}

/* The change due now (g < 0), or -1: zero currents first, then the
 * floating terminal, then the pair with the largest line back-EMF, then
 * the brake, the link clamp. */
static int due_event(const plant_events_t *ev)
{
    int pair = -1;
    for (int e = 0; e < EV_COUNT; ++e) {
        if (!ev->active[e] || !(ev->g[e] < 0.0)) {
            continue;
        }
        if (e >= EV_PAIR && e < EV_PAIR + 3) {
            if (pair < 0 || ev->g[e] < ev->g[pair]) {
                pair = e;
            }
            continue;
        }
        if (e >= EV_BRAKE && pair >= 0) {
            return pair;
        }
        return e;
    }
    return pair;
}

/* The event a step from g0 to g1 crosses first (linear estimate), or -1. */
static int first_crossing(const plant_events_t *g0, const plant_events_t *g1)
{
    int first = -1;
    double first_frac = 2.0;
    for (int e = 0; e < EV_COUNT; ++e) {
        if (!g1->active[e] || !(g1->g[e] < 0.0)) {
            continue;
        }
        const double frac = g0->g[e] > 0.0 ? g0->g[e] / (g0->g[e] - g1->g[e]) : 1.0;
        if (frac < first_frac) {
            first = e;
            first_frac = frac;
        }
    }
    return first;
}

static void apply_event(plant_t *p, int e, const plant_events_t *ev)
{
    if (e == EV_BRAKE) {
        p->brake_on = !p->brake_on;
        return;
    }
    if (e == EV_CLAMP) {
        p->link_clamped = !p->link_clamped;
        return;
    }
    if (e < EV_FLOAT_HIGH) {
        p->phase_state[e - EV_CURRENT] = PLANT_PHASE_BLOCKING;
    } else if (e == EV_FLOAT_HIGH || e == EV_FLOAT_LOW) {
        p->phase_state[floating_phase(p)] =
            e == EV_FLOAT_HIGH ? PLANT_PHASE_UPPER_DIODE : PLANT_PHASE_LOWER_DIODE;
    } else {
        const int j = e - EV_PAIR;
        const int hi = ev->pair_first_high[j] ? pair_first[j] : pair_second[j];
        const int lo = ev->pair_first_high[j] ? pair_second[j] : pair_first[j];
        p->phase_state[hi] = PLANT_PHASE_UPPER_DIODE;
        p->phase_state[lo] = PLANT_PHASE_LOWER_DIODE;
    }
    conduction_changed(p);
}

/* Applies the changes already due at the current state, time t_s (no time
 * passes). */
static void settle(plant_t *p, const plant_source_t *src, double t_s)
{
    for (int n = 0; n < SETTLE_MAX; ++n) {
        plant_events_t ev;
        event_values(p, src, t_s, p->x, &ev);
        const int e = due_event(&ev);
        if (e < 0) {
            return;
        }
        apply_event(p, e, &ev);
    }
}

/* Step length in (0, rem] at which event e's g crosses zero (Illinois
 * regula falsi on the RK4 step from x0, bracket [a, b] with g(a) >= 0 >
 * g(b)); leaves the state at the end of that step (the crossed side). */
static double locate(plant_t *p, const plant_source_t *src, double t_s, const double x0[PX_LEN],
                     double rem, int e, double g_a, double g_b)
{
    double a = 0.0;
    double b = rem;
    double x_b[PX_LEN];
    memcpy(x_b, p->x, sizeof x_b);
    int side = 0;
    for (int it = 0; it < EVENT_LOCATE_MAX_IT && b - a > EVENT_TIME_TOL * p->h_s; ++it) {
        double m = b - g_b * (b - a) / (g_b - g_a);
        if (!(m > a && m < b)) {
            m = 0.5 * (a + b);
        }
        double x_m[PX_LEN];
        memcpy(x_m, x0, sizeof x_m);
        rk4_step(p, src, t_s, m, x_m);
        plant_events_t ev;
        event_values(p, src, t_s + m, x_m, &ev);
        if (ev.g[e] < 0.0) {
            b = m;
            g_b = ev.g[e];
            memcpy(x_b, x_m, sizeof x_b);
            if (side < 0) {
                g_a *= 0.5;
            }
            side = -1;
        } else {
            a = m;
            g_a = ev.g[e];
            if (side > 0) {
                g_b *= 0.5;
            }
            side = 1;
        }
    }
    memcpy(p->x, x_b, sizeof x_b);
    return b;
}

/* One substep of length h_s from t_s with its events located. */
static void substep_with_events(plant_t *p, const plant_source_t *src, double t_s, double h_s)
{
    double rem = h_s;
    for (uint32_t n_events = 0u;; ++n_events) {
        double x0[PX_LEN];
        plant_events_t g0, g1;
        memcpy(x0, p->x, sizeof x0);
        event_values(p, src, t_s, x0, &g0);
        rk4_step(p, src, t_s, rem, p->x);
        event_values(p, src, t_s + rem, p->x, &g1);
        const int e = first_crossing(&g0, &g1);
        if (e < 0 || n_events >= EVENTS_PER_SUBSTEP_MAX) {
            project_currents(p);
            if (e >= 0) {
                settle(p, src, t_s + rem);
            }
            return;
        }
        const double h1 = g0.g[e] > 0.0 ? locate(p, src, t_s, x0, rem, e, g0.g[e], g1.g[e]) : rem;
        project_currents(p);
        plant_events_t now;
        event_values(p, src, t_s + h1, p->x, &now);
        apply_event(p, e, &now);
        settle(p, src, t_s + h1);
        if (!(h1 < rem)) {
            return;
        }
        t_s += h1;
        rem -= h1;
    }
}

/* Substeps j0 .. j1 - 1 of the current period under src: exact where it
 * applies (plant_exact.h), else RK4. */
static void integrate_substeps(plant_t *p, const plant_source_t *src, uint32_t j0, uint32_t j1)
{
    if (plant_exact_applies(p, src)) {
        plant_exact_substeps(p, src, j0, j1);
        return;
    }
    p->exact_carry = false;
    const double t0 = p->t_s;
    if (p->n_floating == 0u && src->kind != PLANT_SRC_DIODES && !p->link_dynamic) {
        for (uint32_t j = j0; j < j1; ++j) {
            rk4_step(p, src, t0 + (double)j * p->h_s, p->h_s, p->x);
        }
        return;
    }
    for (uint32_t j = j0; j < j1; ++j) {
        substep_with_events(p, src, t0 + (double)j * p->h_s, p->h_s);
    }
}

/* ---- View ----------------------------------------------------------------- */

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
    const double theta_e_cont = p->n_p * p->x[PX_THETA];
    const double theta_e = fmod(theta_e_cont, PLANT_TWO_PI);
    v->theta_e_rad = theta_e < 0.0 ? theta_e + PLANT_TWO_PI : theta_e;
    for (int k = 0; k < 3; ++k) {
        v->i_abc_A[k] = aux.i_abc_A[k];
        v->v_abc_V[k] = p->x[PX_VA_INT + k] / p->period_s;
    }
    if (p->n_floating > 0u) {
        phase_currents(p, cos(theta_e_cont), sin(theta_e_cont), v->i_abc_A);
    }
    v->tau_e_Nm = aux.tau_e_Nm;
    v->tau_load_Nm = aux.tau_load_Nm;
    v->tau_cog_Nm = aux.tau_cog_Nm;
    v->tau_friction_Nm = aux.tau_friction_Nm;
    v->v_dc_V = aux.v_dc_V;
    v->v_source_V = aux.v_source_V;
    v->i_source_A = aux.i_source_A;
    v->i_bridge_A = aux.i_bridge_A;
    v->i_brake_A = aux.i_brake_A;
    v->brake_on = p->brake_on;
    v->link_clamped = p->link_clamped;
    v->outputs_enabled = (src->kind == PLANT_SRC_INVERTER || src->kind == PLANT_SRC_IDEAL_DQ);
    bool any_conducting = false;
    for (int k = 0; k < 3; ++k) {
        v->phase_state[k] = p->phase_state[k];
        v->phase_open[k] = p->faults.phase_open[k];
        any_conducting = any_conducting || conducting(p->phase_state[k]);
    }
    v->rectifying = !v->outputs_enabled && any_conducting;
    v->open_circuit = !v->outputs_enabled && !any_conducting;
    v->rotor_locked = p->faults.rotor_locked;
    v->source_connected = p->faults.source_connected;
    plant_energy_t *e = &v->energy;
    *e = (plant_energy_t){ .bus_J = p->x[PX_E_BUS],
                           .electrical_J = p->x[PX_E_ELEC],
                           .copper_J = p->x[PX_E_CU],
                           .friction_J = p->x[PX_E_FRIC],
                           .load_J = p->x[PX_E_LOAD],
                           .cogging_J = p->x[PX_E_COG],
                           .source_J = p->x[PX_E_BUS],
                           .constraint_J = p->constraint_J };
    if (p->link_dynamic) {
        const double v_link = p->x[PX_VDC];
        e->source_J = p->x[PX_E_SRC];
        e->source_resistor_J = p->x[PX_E_RSRC];
        e->capacitor_J =
            0.5 * p->cfg.dc_link.capacitance_F * (v_link * v_link - p->v0_link_V * p->v0_link_V);
        e->brake_J = p->x[PX_E_BRAKE];
        e->link_clamp_J = p->x[PX_E_CLAMP];
    }
}

/* ---- Set-up, faults, modes ------------------------------------------------ */

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
    plant_exact_init(p);
    p->x[PX_THETA] = cfg->theta_m0_rad;
    p->x[PX_OMEGA] = cfg->locked_rotor ? 0.0 : cfg->omega_m0_rad_s;
    p->faults = (plant_faults_t){ .rotor_locked = cfg->locked_rotor,
                                  .source_connected = true,
                                  .t_dead_s = cfg->inverter.t_dead_s };
    p->requested = p->faults;
    p->link_dynamic = cfg->dc_link.capacitance_F > 0.0;

    if (p->link_dynamic) {
        const plant_dc_link_t *link = &cfg->dc_link;
        p->v0_link_V = link->v0_given ? link->v0_V : bus_voltage_at(p, 0.0);
        p->x[PX_VDC] = p->v0_link_V;
        p->brake_on = link->brake_resistance_ohm > 0.0 && p->v0_link_V > link->brake_on_V;
    }
    p->rng_state = cfg->sensors.seed;
    p->encoder_turns = plant_encoder_turn(cfg->theta_m0_rad, cfg->sensors.encoder.offset_rad);
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

static int refuse(plant_t *p, int code, const char *msg)
{
    p->err_msg = msg;
    return code;
}

int plant_set_phase_open(plant_t *p, unsigned phase, bool open)
{
    if (p == NULL) {
        return PLANT_ERR_NULL;
    }
    if (!p->initialised) {
        return PLANT_ERR_STATE;
    }
    if (phase > 2u) {
        return refuse(p, PLANT_ERR_ARGUMENT, "plant_set_phase_open: phase must be 0, 1 or 2");
    }
    p->requested.phase_open[phase] = open;
    return PLANT_OK;
}

int plant_set_rotor_locked(plant_t *p, bool locked)
{
    if (p == NULL) {
        return PLANT_ERR_NULL;
    }
    if (!p->initialised) {
        return PLANT_ERR_STATE;
    }
    p->requested.rotor_locked = locked;
    return PLANT_OK;
}

int plant_set_source_connected(plant_t *p, bool connected)
{
    if (p == NULL) {
        return PLANT_ERR_NULL;
    }
    if (!p->initialised) {
        return PLANT_ERR_STATE;
    }
    if (!p->link_dynamic) {
        return refuse(p, PLANT_ERR_DC_LINK,
                      "plant_set_source_connected needs dc_link.capacitance_F > 0 (a stiff bus "
                      "is its source)");
    }
    p->requested.source_connected = connected;
    return PLANT_OK;
}

int plant_set_dead_time(plant_t *p, double t_dead_s)
{
    if (p == NULL) {
        return PLANT_ERR_NULL;
    }
    if (!p->initialised) {
        return PLANT_ERR_STATE;
    }
    if (!(t_dead_s >= 0.0) || !(t_dead_s * p->cfg.inverter.f_pwm_Hz < 0.5)) {
        return refuse(p, PLANT_ERR_ARGUMENT,
                      "plant_set_dead_time: dead time must be >= 0 and below half a PWM period");
    }
    p->requested.t_dead_s = t_dead_s;
    return PLANT_OK;
}

/* The requested faults take effect: a rotor that locks stops at once. */
static void apply_faults(plant_t *p)
{
    if (p->requested.rotor_locked && !p->faults.rotor_locked) {
        const double omega = p->x[PX_OMEGA];
        p->constraint_J += 0.5 * omega * omega / p->inv_J_per_kgm2;
        p->x[PX_OMEGA] = 0.0;
    }
    p->faults = p->requested;
}

/* New conduction states for the part of the period that starts: a change
 * takes effect (conduction_changed); the same states again leave the state
 * untouched, so a period split in two equal halves is one period. */
static void set_conduction(plant_t *p, const plant_phase_state_t states[3], bool diode_mode)
{
    if (diode_mode == p->diode_mode && memcmp(states, p->phase_state, sizeof p->phase_state) == 0) {
        return;
    }
    memcpy(p->phase_state, states, sizeof p->phase_state);
    p->diode_mode = diode_mode;
    conduction_changed(p);
}

/* Outputs on (or the ideal source): connected phases driven. */
static void enter_driven(plant_t *p)
{
    plant_phase_state_t states[3];
    for (int k = 0; k < 3; ++k) {
        states[k] = p->faults.phase_open[k] ? PLANT_PHASE_OPEN : PLANT_PHASE_DRIVEN;
    }
    set_conduction(p, states, false);
}

/* Outputs off: on entry each phase takes the diode of its current's sign
 * (a zero current blocks); later the conduction states carry over, with
 * the phases opened or reconnected since. */
static void enter_diodes(plant_t *p)
{
    plant_phase_state_t states[3];
    memcpy(states, p->phase_state, sizeof states);
    if (!p->diode_mode) {
        const double theta_e = p->n_p * p->x[PX_THETA];
        double i_abc[3];
        phase_currents(p, cos(theta_e), sin(theta_e), i_abc);
        const double i_tol = CURRENT_ZERO_REL * (fabs(p->x[PX_ID]) + fabs(p->x[PX_IQ]));
        for (int k = 0; k < 3; ++k) {
            states[k] = i_abc[k] > i_tol    ? PLANT_PHASE_LOWER_DIODE
                        : i_abc[k] < -i_tol ? PLANT_PHASE_UPPER_DIODE
                                            : PLANT_PHASE_BLOCKING;
        }
    }
    for (int k = 0; k < 3; ++k) {
        if (p->faults.phase_open[k]) {
            states[k] = PLANT_PHASE_OPEN;
        } else if (states[k] == PLANT_PHASE_OPEN) {
            states[k] = PLANT_PHASE_BLOCKING;
        }
    }
    set_conduction(p, states, true);
}

/* At the start of a period part the changes already due (diodes that
 * conduct at once, a link clamp that a reconnected source releases). */
static void settle_at_start(plant_t *p, const plant_source_t *src, double t_s)
{
    if (src->kind == PLANT_SRC_DIODES || p->link_dynamic) {
        settle(p, src, t_s);
    }
}

static double clamp01(double d)
{
    if (!(d >= 0.0))
        return 0.0; /* also maps NaN to 0 */
    return d > 1.0 ? 1.0 : d;
}

/* The inverter as a source with these duties / outputs (v_dc_V: the stiff
 * bus held over the period); enters its conduction states. */
static plant_source_t inverter_source(plant_t *p, const double duty_abc[3], bool outputs_enabled,
                                      double v_dc_V, double t_s)
{
    plant_source_t src = { 0 };
    src.v_dc_V = v_dc_V;
    if (outputs_enabled) {
        src.kind = PLANT_SRC_INVERTER;
        for (int k = 0; k < 3; ++k) {
            src.duty[k] = clamp01(duty_abc[k]);
        }
        const plant_inverter_params_t *inv = &p->cfg.inverter;
        src.v_error_V = p->faults.t_dead_s * inv->f_pwm_Hz * src.v_dc_V + inv->v_device_drop_V;
        src.i_band_A = inv->dead_time_current_band_A;
        enter_driven(p);
    } else {
        src.kind = PLANT_SRC_DIODES;
        enter_diodes(p);
    }
    settle_at_start(p, &src, t_s);
    return src;
}

/* Start of a period: faults take effect, the voltage integrals restart;
 * returns the stiff bus voltage held over the period (at its middle). */
static double start_period(plant_t *p)
{
    apply_faults(p);
    p->exact_carry = false; /* the exact integrator restarts from theta_m */
    p->x[PX_VA_INT] = p->x[PX_VB_INT] = p->x[PX_VC_INT] = 0.0;
    return bus_voltage_at(p, p->t_s + 0.5 * p->period_s);
}

/* End of the period: time and the true-state view (with the source of the
 * period's last part). */
static void finish_period(plant_t *p, const plant_source_t *src)
{
    p->n_periods += 1u;
    p->t_s = (double)p->n_periods * p->period_s;
    update_view(p, src);
}

void plant_advance(plant_t *p, const double duty_abc[3], bool outputs_enabled)
{
    if (!p->initialised) {
        return;
    }
    const double v_dc_V = start_period(p);
    const plant_source_t src = inverter_source(p, duty_abc, outputs_enabled, v_dc_V, p->t_s);
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
    const double v_dc_V = start_period(p);
    plant_source_t src = inverter_source(p, duty_first, outputs_first, v_dc_V, p->t_s);
    integrate_substeps(p, &src, 0u, n / 2u);
    src =
        inverter_source(p, duty_second, outputs_second, v_dc_V, p->t_s + (double)(n / 2u) * p->h_s);
    integrate_substeps(p, &src, n / 2u, n);
    finish_period(p, &src);
}

void plant_advance_vdq(plant_t *p, double v_d_V, double v_q_V)
{
    if (!p->initialised) {
        return;
    }
    plant_source_t src = { .kind = PLANT_SRC_IDEAL_DQ, .v_d_V = v_d_V, .v_q_V = v_q_V };
    src.v_dc_V = start_period(p);
    enter_driven(p);
    settle_at_start(p, &src, p->t_s);
    integrate_substeps(p, &src, 0u, p->cfg.substeps_per_period);
    finish_period(p, &src);
}
