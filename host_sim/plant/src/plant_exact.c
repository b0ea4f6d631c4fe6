/*
 * plant_exact.c - exact (exponential) substeps of the switching plant; the
 * method, its approximation and error bound are in plant.h
 * ("Integrators"). Complex numbers are written out as (re, im) pairs:
 * alpha-beta (stator) and d-q (rotor) currents, the rotor unit vector
 * u = exp(j theta_e).
 */
#include "plant_exact.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "plant_dynamics.h"
#include "plant_frames.h"
#include "plant_rk4.h"

/* |x| up to which exp(j x) comes from its Taylor series to x^5 (the rest
 * below 3e-22 relative) and to x^9 (below 3e-17), and R h / L up to which
 * (1 - exp(-x)) / x does (below 2e-18). */
#define ROTATION_SHORT_MAX_RAD  0x1p-10
#define ROTATION_SERIES_MAX_RAD 0.125
#define DECAY_SERIES_MAX        1e-3

void plant_exact_init(plant_t *p)
{
    plant_exact_consts_t *k = &p->exact;
    const double h = p->h_s;
    const double l = p->Ld_H; /* > 0: validated */
    k->usable = p->cfg.solver_method == PLANT_SOLVER_EXACT && p->Ld_H == p->Lq_H;
    const double x = p->R_ohm * h / l; /* >= 0 */
    k->decay = exp(-x);
    k->one_minus_decay = -expm1(-x);
    const double ratio = x < DECAY_SERIES_MAX
                             ? 1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x / 120.0)))
                             : k->one_minus_decay / x;
    k->input_gain_A_per_V = h / l * ratio; /* (1 - E) / R, also for R == 0 */
    k->quad_s2 = h * h / 12.0;
    k->inv_L_per_H = 1.0 / l;
    k->lambda_per_s = p->R_ohm / l;
    k->psi_per_L_A = p->psi_Wb / l;
    k->torque_const_Nm_per_A = 1.5 * p->n_p * p->psi_Wb;
    k->kt_h_2 = k->torque_const_Nm_per_A * h / 2.0;
    k->kt_h_3 = k->torque_const_Nm_per_A * h / 3.0;
    k->kt_h2_6 = k->torque_const_Nm_per_A * h * h / 6.0;
    k->kt_h2_8 = k->torque_const_Nm_per_A * h * h / 8.0;
    k->kt_h2_12 = k->torque_const_Nm_per_A * h * h / 12.0;
}

bool plant_exact_applies(const plant_t *p, const plant_source_t *src)
{
    return p->exact.usable && src->kind == PLANT_SRC_INVERTER && p->n_floating == 0u &&
           !p->link_dynamic;
}

/* exp(j x) - 1 = (cos x - 1) + j sin x, without cancellation. */
static inline void rotation(double x, double *cos_m1, double *sin_x)
{
    const double x2 = x * x;
    if (fabs(x) <= ROTATION_SHORT_MAX_RAD) { /* every substep of the benchmarks */
        const double x4 = x2 * x2;
        *sin_x = x * (1.0 - x2 * (1.0 / 6.0) + x4 * (1.0 / 120.0));
        *cos_m1 = x2 * (-0.5 + x2 * (1.0 / 24.0) - x4 * (1.0 / 720.0));
        return;
    }
    if (fabs(x) <= ROTATION_SERIES_MAX_RAD) {
        *sin_x = x * (1.0 - x2 * (1.0 / 6.0) *
                                (1.0 - x2 * (1.0 / 20.0) *
                                           (1.0 - x2 * (1.0 / 42.0) * (1.0 - x2 * (1.0 / 72.0)))));
        *cos_m1 = -0.5 * x2 *
                  (1.0 - x2 * (1.0 / 12.0) *
                             (1.0 - x2 * (1.0 / 30.0) *
                                        (1.0 - x2 * (1.0 / 56.0) * (1.0 - x2 * (1.0 / 90.0)))));
        return;
    }
    const double s_half = sin(0.5 * x);
    *sin_x = sin(x);
    *cos_m1 = -2.0 * s_half * s_half;
}

/* The mechanics of one substep: the speed's mean (it sets the rotor's
 * turn), its slope at the middle and its end value (for the end
 * derivatives of the quadratures), and the other torques and g3 at the
 * middle (held over the substep). */
typedef struct {
    double mean_rad_s, acc_rad_s2, end_rad_s;
    double tau_load_Nm, tau_cog_Nm, g3_per_kgm2;
} mech_plan_t;

/* What is constant over one part of a period: the inverter's voltage
 * (alpha-beta and per phase, with the dead-time error for the current
 * directions it was computed for) and the load when it is linear there;
 * and what the next substep starts from (the rotor unit vector and values
 * of the state it shares with the previous substep's end). */
typedef struct {
    double v_bus_a_V, v_bus_b_V; /* d_x v_dc: the bridge's share (bus power) */
    double v_bus_phase_V[3];     /* the same as phase voltages */
    double v_error_V, band_A;    /* the dead-time model (v_error_V 0: none) */
    int dir[3];                  /* current directions of v_a_V.. (0: not computed) */
    double v_a_V, v_b_V;         /* applied voltage, alpha-beta */
    double v_phase_h_Vs[3];      /* applied phase voltages x h */
    bool load_linear;            /* load = load_Nm + load_slope_Nm_s (t - t0) */
    double load_t0_s, load_Nm, load_slope_Nm_s;
    double c, s;            /* cos, sin theta_e */
    double i_a_A, i_b_A;    /* alpha-beta current */
    double a_q_A_s;         /* (v_q - R i_q) / L: di_q/dt = a_q - omega_e (psi / L + i_d) */
    double sq_A2;           /* |i|^2 */
    double pw_W;            /* v . i = (2/3) electrical power */
    double x[PX_STIFF_LEN]; /* the state (p->x's copy while exact substeps run) */
} segment_t;

/* The start values that depend on the voltage. */
static void voltage_terms(const plant_t *p, segment_t *g)
{
    const double v_q = g->c * g->v_b_V - g->s * g->v_a_V;
    g->a_q_A_s = (v_q - p->R_ohm * g->x[PX_IQ]) * p->exact.inv_L_per_H;
    g->pw_W = g->v_a_V * g->i_a_A + g->v_b_V * g->i_b_A;
}

/* The start values from the state and the rotor vector g->c, g->s. */
static void start_values(const plant_t *p, segment_t *g)
{
    const double i_d = g->x[PX_ID];
    const double i_q = g->x[PX_IQ];
    g->i_a_A = g->c * i_d - g->s * i_q;
    g->i_b_A = g->s * i_d + g->c * i_q;
    g->sq_A2 = i_d * i_d + i_q * i_q;
    voltage_terms(p, g);
}

/* The rotor vector from theta_m (at the start of a period and after an
 * RK4 substep) and the start values. */
static void start_from_angle(const plant_t *p, segment_t *g)
{
    const double theta_e = p->n_p * g->x[PX_THETA];
    g->c = cos(theta_e);
    g->s = sin(theta_e);
    start_values(p, g);
}

/* The part of a period from substep j0 to j1 - 1: its voltage, its load if
 * linear, and the rotor vector where the last exact part of this period
 * stopped (plant_advance_split continues plant_advance's rotation bit for
 * bit), else from theta_m. */
static void segment_begin(const plant_t *p, const plant_source_t *src, uint32_t j0, uint32_t j1,
                          segment_t *g)
{
    double v_term[3];
    for (int k = 0; k < 3; ++k) {
        v_term[k] = src->duty[k] * src->v_dc_V;
    }
    const double common = (v_term[0] + v_term[1] + v_term[2]) / 3.0;
    for (int k = 0; k < 3; ++k) {
        g->v_bus_phase_V[k] = v_term[k] - common;
        g->v_phase_h_Vs[k] = g->v_bus_phase_V[k] * p->h_s;
        g->dir[k] = 0;
    }
    plant_abc_to_dq(v_term, 1.0, 0.0, &g->v_bus_a_V, &g->v_bus_b_V); /* Clarke */
    g->v_a_V = g->v_bus_a_V;
    g->v_b_V = g->v_bus_b_V;
    g->v_error_V = src->v_error_V;
    g->band_A = src->i_band_A;
    /* the load at the substeps' middles (the RK4 path's piece) */
    g->load_t0_s = p->t_s + ((double)j0 + 0.5) * p->h_s;
    const double t_last_s = p->t_s + ((double)j1 - 0.5) * p->h_s;
    g->load_linear = sim_profile_linear_on(&p->cfg.load_torque_Nm, g->load_t0_s, t_last_s,
                                           &g->load_Nm, &g->load_slope_Nm_s);
    if (p->exact_carry) {
        g->c = p->exact_cos;
        g->s = p->exact_sin;
        start_values(p, g);
    } else {
        start_from_angle(p, g);
    }
}

/* Direction of a phase current for the dead-time error: +-1 where the
 * error is constant (outside the linear zone; nonzero with the hard sign),
 * 0 where it depends on the current. */
static inline int current_direction(double i_A, double band_A)
{
    if (band_A > 0.0) {
        return i_A >= band_A ? 1 : (i_A <= -band_A ? -1 : 0);
    }
    return i_A > 0.0 ? 1 : (i_A < 0.0 ? -1 : 0);
}

/* Directions of the alpha-beta current (i_a, i_b) into dir; false if one
 * is 0. */
static bool directions(const segment_t *g, double i_a, double i_b, int dir[3])
{
    double i_abc[3];
    plant_dq_to_abc(i_a, i_b, 1.0, 0.0, i_abc); /* inverse Clarke */
    for (int k = 0; k < 3; ++k) {
        dir[k] = current_direction(i_abc[k], g->band_A);
        if (dir[k] == 0) {
            return false;
        }
    }
    return true;
}

static bool same_directions(const int a[3], const int b[3])
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* The applied voltage for the current directions at the substep start:
 * v_term_x = d_x v_dc - dir_x v_error (plant.h, "Inverter"). False if a
 * direction is 0. */
static bool dead_time_voltage(const plant_t *p, segment_t *g)
{
    int dir[3];
    if (!directions(g, g->i_a_A, g->i_b_A, dir)) {
        return false;
    }
    if (same_directions(dir, g->dir)) {
        return true;
    }
    double err[3];
    for (int k = 0; k < 3; ++k) {
        err[k] = -(double)dir[k] * g->v_error_V;
    }
    const double common = (err[0] + err[1] + err[2]) / 3.0;
    double e_a, e_b;
    plant_abc_to_dq(err, 1.0, 0.0, &e_a, &e_b);
    g->v_a_V = g->v_bus_a_V + e_a;
    g->v_b_V = g->v_bus_b_V + e_b;
    for (int k = 0; k < 3; ++k) {
        g->v_phase_h_Vs[k] = (g->v_bus_phase_V[k] + err[k] - common) * p->h_s;
        g->dir[k] = dir[k];
    }
    voltage_terms(p, g);
    return true;
}

static inline double friction(const plant_motor_params_t *m, double w)
{
    return (m->B_Nm_s_rad != 0.0 || m->tau_coulomb_Nm != 0.0) ? plant_friction_torque(m, w) : 0.0;
}

/* The load, cogging and g3 at the middle of the substep from t_s, the
 * cogging at the angle theta_mid_rad. */
static void mid_torques(const plant_t *p, const segment_t *g, double t_s, double theta_mid_rad,
                        mech_plan_t *w)
{
    const plant_motor_params_t *m = &p->cfg.motor;
    const double t_mid = t_s + 0.5 * p->h_s;
    w->tau_load_Nm = g->load_linear ? g->load_Nm + g->load_slope_Nm_s * (t_mid - g->load_t0_s)
                                    : sim_profile_eval(&p->cfg.load_torque_Nm, t_mid);
    w->tau_cog_Nm = m->cogging.n_harmonics > 0u ? plant_cogging_torque(p, theta_mid_rad) : 0.0;
    w->g3_per_kgm2 = p->inv_J_per_kgm2;
    if (m->g3_amplitude_per_kgm2 != 0.0) {
        w->g3_per_kgm2 += m->g3_amplitude_per_kgm2 * sin(m->g3_omega_rad_s * t_mid);
    }
}

/* The mechanics of the substep from t_s (*w) with the other torques at
 * its middle and i_q(t) = i_q + i_q' t + i_q'' t^2 / 2, i_q' and i_q''
 * from the ODE at its start (d-q, v_ab held): the mean speed
 * w + (h/2) a(h/3), the end w + h a(h/2) and the slope at the middle,
 * a(t) the acceleration with i_q at t's integral weights (exact for a
 * quadratic i_q), so the speed's error is O(h^4) over a substep, the
 * order of the electrical step's own. */
static void plan_mechanics(const plant_t *p, const segment_t *g, double t_s, mech_plan_t *w)
{
    const plant_exact_consts_t *k = &p->exact;
    const double h = p->h_s;
    const double r = p->R_ohm;
    const double i_d = g->x[PX_ID];
    const double i_q = g->x[PX_IQ];
    const double w_m = g->x[PX_OMEGA];
    const double w_e = p->n_p * w_m;
    const double b = k->psi_per_L_A + i_d;
    const double di_q = g->a_q_A_s - w_e * b;
    mid_torques(p, g, t_s, g->x[PX_THETA] + 0.5 * h * w_m, w);
    const double g3 = w->g3_per_kgm2;
    const double base = k->torque_const_Nm_per_A * i_q - w->tau_load_Nm - w->tau_cog_Nm -
                        friction(&p->cfg.motor, w_m);
    const double v_d = g->c * g->v_a_V + g->s * g->v_b_V;
    const double di_d = (v_d - r * i_d) * k->inv_L_per_H + w_e * i_q;
    const double d2i_q =
        (-w_e * v_d - r * di_q) * k->inv_L_per_H - p->n_p * g3 * base * b - w_e * di_d;
    const double half = k->kt_h_2 * di_q;
    w->mean_rad_s = w_m + 0.5 * h * g3 * (base + k->kt_h_3 * di_q + k->kt_h2_12 * d2i_q);
    w->acc_rad_s2 = g3 * (base + half + k->kt_h2_8 * d2i_q);
    w->end_rad_s = w_m + h * g3 * (base + half + k->kt_h2_6 * d2i_q);
}

/* One exact substep of length h_s from t_s. False (nothing changed) when
 * the dead-time error is not constant over it: a phase current is in the
 * linear zone (or zero) at its start or changes direction by its end. */
static bool exact_step(plant_t *p, segment_t *g, double t_s)
{
    const plant_exact_consts_t *k = &p->exact;
    const plant_motor_params_t *m = &p->cfg.motor;
    const double h = p->h_s;
    const double r = p->R_ohm;
    const double n_p = p->n_p;
    double *x = g->x;
    if (g->v_error_V > 0.0 && !dead_time_voltage(p, g)) {
        return false;
    }
    const double i_d0 = x[PX_ID];
    const double i_q0 = x[PX_IQ];
    const double w0 = x[PX_OMEGA];
    const double c0 = g->c;
    const double s0 = g->s;
    const double v_a = g->v_a_V;
    const double v_b = g->v_b_V;
    const bool free = !p->faults.rotor_locked;
    mech_plan_t w = { 0 };
    if (free) {
        plan_mechanics(p, g, t_s, &w);
    } else {
        mid_torques(p, g, t_s, x[PX_THETA], &w);
    }
    const double w_e = n_p * w.mean_rad_s;

    /* Rotor vector at the end: u1 = u0 exp(j omega_e h). */
    double cm1, sr;
    rotation(w_e * h, &cm1, &sr);
    const double cr = 1.0 + cm1;
    const double c1 = c0 * cr - s0 * sr;
    const double s1 = s0 * cr + c0 * sr;

    /* Electrical, exact for omega_e (the mean) and v_ab held: in d-q,
     *   i1 = conj(rot) (E i0 + P) + ((1 - E) / R) conj(u1) v_ab,
     *   P = -j omega_e psi (rot - E) / (R + j omega_e L). */
    double p_d = 0.0;
    double p_q = 0.0;
    if (w_e != 0.0) {
        const double w_re = cm1 + k->one_minus_decay; /* rot - E */
        const double wl = w_e * p->Ld_H;
        const double den = r * r + wl * wl;
        if (den >= DBL_MIN) {
            const double f = w_e * p->psi_Wb / den;
            p_d = f * (sr * r - w_re * wl);
            p_q = -f * (w_re * r + sr * wl);
        } else { /* R == 0 and omega_e tiny: (rot - E) / (j omega_e L) -> h / L */
            p_q = -w_e * h * k->psi_per_L_A;
        }
    }
    const double z_d = k->decay * i_d0 + p_d;
    const double z_q = k->decay * i_q0 + p_q;
    const double v_d1 = c1 * v_a + s1 * v_b;
    const double v_q1 = c1 * v_b - s1 * v_a;
    /* The speed varies over the substep, omega_mean + acc (t - h/2) + ...:
     * the rotor angle leaves the straight line by n_p acc (t^2 - h t) / 2
     * (0 at both ends). In alpha-beta the back-EMF is psi du/dt, so the
     * current depends on the angle's path only through R / L times the
     * integral of exp(-(R / L)(h - t)) u(t); that moves the end current by
     * -j c (R / L) (psi / L) (1 - (R / L) h / 2 - j omega_e h / 2) (d-q,
     * c = n_p acc h^3 / 12; plant.h, "Integrators"). */
    const double kk = n_p * w.acc_rad_s2 * h * k->quad_s2 * k->lambda_per_s * k->psi_per_L_A;
    const double i_d1 = cr * z_d + sr * z_q + k->input_gain_A_per_V * v_d1 - kk * 0.5 * w_e * h;
    const double i_q1 =
        cr * z_q - sr * z_d + k->input_gain_A_per_V * v_q1 - kk * (1.0 - 0.5 * k->lambda_per_s * h);
    const double i_a1 = c1 * i_d1 - s1 * i_q1;
    const double i_b1 = s1 * i_d1 + c1 * i_q1;
    if (g->v_error_V > 0.0) {
        int dir[3];
        if (!directions(g, i_a1, i_b1, dir) || !same_directions(dir, g->dir)) {
            return false;
        }
    }

    /* Integrals over the substep by the trapezoid rule with its end
     * correction (h^2 / 12) (f'(0) - f'(h)) (exact for cubics), the
     * derivatives from the ODE at the start and end speeds. */
    const double q2 = k->quad_s2;
    const double q2_l = q2 * k->inv_L_per_H;
    const double we0 = n_p * w0;
    const double we1 = n_p * w.end_rad_s;
    const double i_a0 = g->i_a_A;
    const double i_b0 = g->i_b_A;
    const double a_q1 = (v_q1 - r * i_q1) * k->inv_L_per_H;
    const double int_i_q =
        0.5 * h * (i_q0 + i_q1) +
        q2 * ((g->a_q_A_s - a_q1) - we0 * (k->psi_per_L_A + i_d0) + we1 * (k->psi_per_L_A + i_d1));
    const double int_i_a =
        0.5 * h * (i_a0 + i_a1) + q2_l * (r * (i_a1 - i_a0) - p->psi_Wb * (we1 * s1 - we0 * s0));
    const double int_i_b =
        0.5 * h * (i_b0 + i_b1) + q2_l * (r * (i_b1 - i_b0) + p->psi_Wb * (we1 * c1 - we0 * c0));
    const double sq0 = g->sq_A2;
    const double sq1 = i_d1 * i_d1 + i_q1 * i_q1;
    const double pw1 = v_a * i_a1 + v_b * i_b1;
    const double int_sq =
        0.5 * h * (sq0 + sq1) +
        2.0 * q2_l * ((g->pw_W - pw1) - r * (sq0 - sq1) - p->psi_Wb * (we0 * i_q0 - we1 * i_q1));

    /* Mechanics, corrector: the mean electrical torque of the substep, the
     * others at the middle (time, angle) and mean speed. */
    double w1 = w0;
    double dtheta = 0.0;
    double tau_fric = 0.0;
    if (free) {
        tau_fric = friction(m, w.mean_rad_s);
        w1 = w0 + w.g3_per_kgm2 * (k->torque_const_Nm_per_A * int_i_q -
                                   h * (tau_fric + w.tau_load_Nm + w.tau_cog_Nm));
        dtheta = h * w.mean_rad_s;
    }

    x[PX_ID] = i_d1;
    x[PX_IQ] = i_q1;
    x[PX_OMEGA] = w1;
    x[PX_THETA] += dtheta;
    x[PX_E_BUS] += 1.5 * (g->v_bus_a_V * int_i_a + g->v_bus_b_V * int_i_b);
    x[PX_E_ELEC] += 1.5 * (v_a * int_i_a + v_b * int_i_b);
    x[PX_E_CU] += 1.5 * r * int_sq;
    x[PX_E_FRIC] += dtheta * tau_fric;
    x[PX_E_LOAD] += dtheta * w.tau_load_Nm;
    x[PX_E_COG] += dtheta * w.tau_cog_Nm;
    x[PX_VA_INT] += g->v_phase_h_Vs[0];
    x[PX_VB_INT] += g->v_phase_h_Vs[1];
    x[PX_VC_INT] += g->v_phase_h_Vs[2];
    g->c = c1;
    g->s = s1;
    g->i_a_A = i_a1;
    g->i_b_A = i_b1;
    g->a_q_A_s = a_q1;
    g->sq_A2 = sq1;
    g->pw_W = pw1;
    return true;
}

void plant_exact_substeps(plant_t *p, const plant_source_t *src, uint32_t j0, uint32_t j1)
{
    const double t0 = p->t_s;
    segment_t g;
    memcpy(g.x, p->x, sizeof g.x);
    segment_begin(p, src, j0, j1, &g);
    for (uint32_t j = j0; j < j1; ++j) {
        const double t_s = t0 + (double)j * p->h_s;
        if (!exact_step(p, &g, t_s)) {
            memcpy(p->x, g.x, sizeof g.x);
            plant_rk4_step(p, src, t_s, p->h_s, p->x);
            memcpy(g.x, p->x, sizeof g.x);
            start_from_angle(p, &g);
        }
    }
    memcpy(p->x, g.x, sizeof g.x);
    p->exact_cos = g.c;
    p->exact_sin = g.s;
    p->exact_carry = true;
}
