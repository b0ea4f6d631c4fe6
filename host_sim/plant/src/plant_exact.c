/*
 * plant_exact.c - exact (exponential) substeps of the switching plant; the
 * method, its approximation and error bound are in plant.h
 * ("Integrators"). Complex numbers are written out as (re, im) pairs:
 * alpha-beta (stator) and d-q (rotor) currents, the rotor unit vector
 * u = exp(j theta_e).
 *
 * Speed: the substeps of a part of a period run in one loop with the
 * state in locals (exact_state_t, never passed out of this file's inline
 * functions, so the compiler keeps it in registers); everything constant
 * over the part (the voltage, the load's linear piece, the constants of
 * p->exact) is computed before the loop, and nothing calls out of the loop
 * unless the configuration needs it (a load that is not linear there,
 * cogging, friction, g3 modulation, dead time, a turn beyond the series'
 * range, an RK4 fall-back substep).
 */
#include "plant_exact.h"

#include <math.h>

#include "plant_dynamics.h"
#include "plant_frames.h"
#include "plant_rk4.h"

/* |x| up to which exp(j x) comes from its Taylor series to x^5 (the rest
 * below 3e-22 relative) and to x^9 (below 3e-17), and R h / L up to which
 * (1 - exp(-x)) / x does (below 2e-18). */
#define ROTATION_SHORT_MAX_RAD  0x1p-10
#define ROTATION_SERIES_MAX_RAD 0.125
#define DECAY_SERIES_MAX        1e-3
/* |z|^2 up to which phi_1(z) = (exp(z) - 1) / z comes from its Taylor
 * series to z^4 (the rest below |z|^5 / 6! < 2e-18 relative), and the
 * terms summed for the coefficients of that series in j theta. */
#define PHI_SERIES_MAX_Z2 0x1p-20
#define PHI_COEFF_TERMS   8
#define PHI_SERIES_DEGREE 5

/* exact_step is inlined at its two call sites (the plain and the general
 * substep loop): its state then lives in registers, and the plain copy
 * loses the optional terms' tests. */
#if defined(__GNUC__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif

/* (psi / L) E phi_1^(n)(x) / n! = (psi / L) E sum_{m >= n} C(m, n)
 * x^(m - n) / (m + 1)!, n = 0..4: the coefficients of P's series in
 * j theta (back_emf_response). Only for x^2 <= PHI_SERIES_MAX_Z2: each
 * term is below x times the one before, so PHI_COEFF_TERMS terms leave
 * less than x^8 < 1e-24 of the sum. */
static void back_emf_coefficients(plant_exact_consts_t *k, double x)
{
    for (int n = 0; n < PHI_SERIES_DEGREE; ++n) {
        k->back_emf_A[n] = 0.0;
    }
    if (x * x > PHI_SERIES_MAX_Z2) {
        return;
    }
    double first = 1.0; /* 1 / (n + 1)! */
    for (int n = 0; n < PHI_SERIES_DEGREE; ++n) {
        first /= (double)(n + 1);
        double term = first;
        double sum = 0.0;
        for (int m = n; m < n + PHI_COEFF_TERMS; ++m) {
            sum += term;
            term *= (double)(m + 1) / (double)(m + 1 - n) * x / (double)(m + 2);
        }
        k->back_emf_A[n] = k->psi_per_L_A * k->decay * sum;
    }
}

void plant_exact_init(plant_t *p)
{
    plant_exact_consts_t *k = &p->exact;
    const double h = p->h_s;
    const double l = p->Ld_H; /* > 0: validated */
    k->usable = p->cfg.solver_method == PLANT_SOLVER_EXACT && p->Ld_H == p->Lq_H;
    const double x = p->R_ohm * h / l; /* >= 0 (R == 0 is allowed) */
    k->decay_arg = x;
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
    k->turn_per_speed_s = p->n_p * h;
    k->path_gain_A_s2 = p->n_p * h * k->quad_s2 * k->lambda_per_s * k->psi_per_L_A;
    k->path_q_factor = 1.0 - 0.5 * k->lambda_per_s * h;
    k->iq_end_weight_s = 0.5 * h + k->quad_s2 * k->lambda_per_s;
    back_emf_coefficients(k, x);
}

bool plant_exact_applies(const plant_t *p, const plant_source_t *src)
{
    return p->exact.usable && src->kind == PLANT_SRC_INVERTER && p->n_floating == 0u &&
           !p->link_dynamic;
}

/* exp(j x) - 1 = (cos x - 1) + j sin x, without cancellation; x2 = x^2. */
static inline void rotation(double x, double x2, double *cos_m1, double *sin_x)
{
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

/* The back-EMF's particular solution over a substep in which the rotor
 * turns by th (= omega_e h; th2 = th^2, rotation exp(j th) = 1 + cm1 +
 * j sr), in d-q at the substep's end:
 *   P = -j omega_e psi (rot - E) / (R + j omega_e L)
 *     = -j th (psi / L) (rot - E) / z = -j th (psi / L) E phi_1(z),
 *   z = R h / L + j th. For |z| <= 2^-10 by phi_1's series (coefficients
 * in p->exact, no division), else by the division by z (|z|^2 > 2^-20
 * there). */
static inline void back_emf_response(const plant_exact_consts_t *k, double th, double th2,
                                     double cm1, double sr, double *p_d, double *p_q)
{
    const double x = k->decay_arg;
    const double z2 = x * x + th2;
    if (z2 <= PHI_SERIES_MAX_Z2) {
        const double *c = k->back_emf_A;
        /* E phi_1(z) = sum c_n (j th)^n: re c0 - c2 th^2 + c4 th^4, im th (c1 - c3 th^2) */
        *p_d = th2 * (c[1] - c[3] * th2);
        *p_q = -th * (c[0] - c[2] * th2 + c[4] * (th2 * th2));
        return;
    }
    const double w_re = cm1 + k->one_minus_decay; /* rot - E */
    const double f = th * k->psi_per_L_A / z2;    /* z2 > PHI_SERIES_MAX_Z2 > 0 */
    *p_d = f * (sr * x - w_re * th);
    *p_q = -f * (w_re * x + sr * th);
}

/* What is constant over one part of a period: the inverter's voltage
 * (alpha-beta and per phase, with the dead-time error for the current
 * directions it was computed for), the load when it is linear there, and
 * which optional torques the motor has. */
typedef struct {
    double v_bus_a_V, v_bus_b_V; /* d_x v_dc: the bridge's share (bus power) */
    double v_bus_phase_V[3];     /* the same as phase voltages */
    double v_error_V, band_A;    /* the dead-time model (v_error_V 0: none) */
    int dir[3];                  /* current directions of v_a_V.. (0: not computed) */
    double v_a_V, v_b_V;         /* applied voltage, alpha-beta */
    double v_phase_h_Vs[3];      /* applied phase voltages x h */
    bool load_linear;            /* load = load_Nm + load_slope_Nm_s (t - t0) */
    double load_t0_s, load_Nm, load_slope_Nm_s;
    bool friction, cogging, g3_modulated; /* the optional torques and inertia term */
    bool plain; /* none of them, no dead time, a linear load and a free rotor */
} segment_t;

/* Sums over a run of substeps under one voltage: the energies and
 * voltage integrals that are linear in the voltage, and the quadratures'
 * terms that telescope over the run, are taken at its end (run_flush). */
typedef struct {
    double i_a0_A, i_b0_A;     /* the run's start current, alpha-beta */
    double i_a_A, i_b_A;       /* sum of i_a, i_b at the substeps' ends */
    double sq_A2;              /* sum of |i|^2 at the substeps' ends */
    double ws_rad_s, wc_rad_s; /* sum of we1 s1 - we0 s0, we1 c1 - we0 c0 */
    double wq_A_rad_s;         /* sum of we0 i_q0 - we1 i_q1 */
    uint32_t substeps;
} run_t;

/* The state while exact substeps run (p->x's copy but for the energies
 * the run sums feed), the values a substep shares with the previous one's
 * end, and the run's sums. */
typedef struct {
    double i_d_A, i_q_A, omega_rad_s, theta_rad;
    double c, s;         /* cos, sin theta_e */
    double i_a_A, i_b_A; /* alpha-beta current */
    double a_q_A_s;      /* (v_q - R i_q) / L: di_q/dt = a_q - omega_e (psi / L + i_d) */
    double e_fric_J, e_load_J, e_cog_J;
    run_t run;
} exact_state_t;

static inline void state_load(const plant_t *p, exact_state_t *st)
{
    const double *x = p->x;
    st->i_d_A = x[PX_ID];
    st->i_q_A = x[PX_IQ];
    st->omega_rad_s = x[PX_OMEGA];
    st->theta_rad = x[PX_THETA];
    st->e_fric_J = x[PX_E_FRIC];
    st->e_load_J = x[PX_E_LOAD];
    st->e_cog_J = x[PX_E_COG];
}

/* A run that starts at the current (i_a, i_b). */
static inline run_t run_start(double i_a_A, double i_b_A)
{
    return (run_t){ .i_a0_A = i_a_A, .i_b0_A = i_b_A };
}

/* The sums of run into p's energies and voltage integrals at the voltage
 * of g; the run ended at the current (i_a1, i_b1), |i|^2 = sq1. Over a
 * substep (exact_step's quadratures: the trapezoid rule with its end
 * correction (h^2 / 12) (f'(0) - f'(h)), the derivatives from the ODE at
 * the start and end speeds we0, we1):
 *   int i_a = (h/2) (i_a0 + i_a1) + q (R (i_a1 - i_a0) - psi (we1 s1 - we0 s0)),
 *   int i_b = (h/2) (i_b0 + i_b1) + q (R (i_b1 - i_b0) + psi (we1 c1 - we0 c0)),
 *   int |i|^2 = (h/2) (sq0 + sq1) + 2 q ((pw0 - pw1) - R (sq0 - sq1)
 *               - psi (we0 i_q0 - we1 i_q1)),
 * q = h^2 / (12 L), pw = v_ab . i_ab; summed over the run the differences
 * of start and end values telescope. The run comes by value: the caller's
 * state stays in registers. */
static void run_flush(plant_t *p, const segment_t *g, run_t run, double i_a1, double i_b1,
                      double sq1)
{
    const plant_exact_consts_t *k = &p->exact;
    const double h = p->h_s;
    const double r = p->R_ohm;
    const double q = k->quad_s2 * k->inv_L_per_H;
    const double i_a0 = run.i_a0_A;
    const double i_b0 = run.i_b0_A;
    const double sq0 = i_a0 * i_a0 + i_b0 * i_b0;
    const double pw0 = g->v_a_V * i_a0 + g->v_b_V * i_b0;
    const double pw1 = g->v_a_V * i_a1 + g->v_b_V * i_b1;
    const double int_i_a = h * run.i_a_A + 0.5 * h * (i_a0 - i_a1) +
                           q * (r * (i_a1 - i_a0) - p->psi_Wb * run.ws_rad_s);
    const double int_i_b = h * run.i_b_A + 0.5 * h * (i_b0 - i_b1) +
                           q * (r * (i_b1 - i_b0) + p->psi_Wb * run.wc_rad_s);
    const double int_sq = h * run.sq_A2 + 0.5 * h * (sq0 - sq1) +
                          2.0 * q * ((pw0 - pw1) - r * (sq0 - sq1) - p->psi_Wb * run.wq_A_rad_s);
    const double n = (double)run.substeps;
    double *x = p->x;
    x[PX_E_BUS] += 1.5 * (g->v_bus_a_V * int_i_a + g->v_bus_b_V * int_i_b);
    x[PX_E_ELEC] += 1.5 * (g->v_a_V * int_i_a + g->v_b_V * int_i_b);
    x[PX_E_CU] += 1.5 * r * int_sq;
    x[PX_VA_INT] += n * g->v_phase_h_Vs[0];
    x[PX_VB_INT] += n * g->v_phase_h_Vs[1];
    x[PX_VC_INT] += n * g->v_phase_h_Vs[2];
}

/* Ends run at the current (i_d, i_q; alpha-beta i_a, i_b) and returns the
 * next one, which starts there. Values only: the caller's state stays in
 * registers. */
static run_t run_next(plant_t *p, const segment_t *g, run_t run, double i_d, double i_q, double i_a,
                      double i_b)
{
    run_flush(p, g, run, i_a, i_b, i_d * i_d + i_q * i_q);
    return run_start(i_a, i_b);
}

static inline void state_store(plant_t *p, const segment_t *g, exact_state_t *st)
{
    st->run = run_next(p, g, st->run, st->i_d_A, st->i_q_A, st->i_a_A, st->i_b_A);
    double *x = p->x;
    x[PX_ID] = st->i_d_A;
    x[PX_IQ] = st->i_q_A;
    x[PX_OMEGA] = st->omega_rad_s;
    x[PX_THETA] = st->theta_rad;
    x[PX_E_FRIC] = st->e_fric_J;
    x[PX_E_LOAD] = st->e_load_J;
    x[PX_E_COG] = st->e_cog_J;
}

/* The start value that depends on the voltage. */
static inline void voltage_terms(const plant_t *p, const segment_t *g, exact_state_t *st)
{
    const double v_q = st->c * g->v_b_V - st->s * g->v_a_V;
    st->a_q_A_s = (v_q - p->R_ohm * st->i_q_A) * p->exact.inv_L_per_H;
}

/* The start values from the state and the rotor vector st->c, st->s. */
static inline void start_values(const plant_t *p, const segment_t *g, exact_state_t *st)
{
    const double i_d = st->i_d_A;
    const double i_q = st->i_q_A;
    st->i_a_A = st->c * i_d - st->s * i_q;
    st->i_b_A = st->s * i_d + st->c * i_q;
    voltage_terms(p, g, st);
}

/* The part of a period from substep j0 to j1 - 1: its voltage, its load if
 * linear, its optional torques. */
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
    const plant_motor_params_t *m = &p->cfg.motor;
    g->friction = m->B_Nm_s_rad != 0.0 || m->tau_coulomb_Nm != 0.0;
    g->cogging = m->cogging.n_harmonics > 0u;
    g->g3_modulated = m->g3_amplitude_per_kgm2 != 0.0;
    g->plain = !g->friction && !g->cogging && !g->g3_modulated && g->load_linear &&
               !(g->v_error_V > 0.0) && !p->faults.rotor_locked;
}

/* The rotor vector where the last exact part of this period stopped
 * (plant_advance_split continues plant_advance's rotation bit for bit),
 * else from theta_m; then the start values. */
static inline void state_begin(const plant_t *p, const segment_t *g, exact_state_t *st)
{
    if (p->exact_carry) {
        st->c = p->exact_cos;
        st->s = p->exact_sin;
    } else {
        const double theta_e = p->n_p * st->theta_rad;
        st->c = cos(theta_e);
        st->s = sin(theta_e);
    }
    start_values(p, g, st);
    st->run = run_start(st->i_a_A, st->i_b_A);
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

/* True when the current (i_a, i_b) at a substep's end has the directions
 * the voltage was computed for. */
static bool directions_kept(const segment_t *g, double i_a, double i_b)
{
    int dir[3];
    return directions(g, i_a, i_b, dir) && same_directions(dir, g->dir);
}

/* The current directions at the substep start (i_a, i_b) into dir:
 * -1 if one is 0, 1 if they differ from those of the voltage, 0 if not. */
static int dead_time_directions(const segment_t *g, double i_a, double i_b, int dir[3])
{
    if (!directions(g, i_a, i_b, dir)) {
        return -1;
    }
    return same_directions(dir, g->dir) ? 0 : 1;
}

/* The applied voltage for the current directions dir:
 * v_term_x = d_x v_dc - dir_x v_error (plant.h, "Inverter"). */
static void dead_time_voltage(const plant_t *p, segment_t *g, const int dir[3])
{
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
}

static inline double friction(const plant_t *p, const segment_t *g, bool plain, double w)
{
    return !plain && g->friction ? plant_friction_torque(&p->cfg.motor, w) : 0.0;
}

/* The torques held over a substep: load, cogging and g3 at its middle
 * (time t_mid_s, angle theta_mid_rad). */
typedef struct {
    double tau_load_Nm, tau_cog_Nm, g3_per_kgm2;
} mid_torques_t;

static inline mid_torques_t mid_torques(const plant_t *p, const segment_t *g, bool plain,
                                        double t_mid_s, double theta_mid_rad)
{
    const plant_motor_params_t *m = &p->cfg.motor;
    mid_torques_t w;
    w.tau_load_Nm = plain || g->load_linear
                        ? g->load_Nm + g->load_slope_Nm_s * (t_mid_s - g->load_t0_s)
                        : sim_profile_eval(&p->cfg.load_torque_Nm, t_mid_s);
    w.tau_cog_Nm = !plain && g->cogging ? plant_cogging_torque(p, theta_mid_rad) : 0.0;
    w.g3_per_kgm2 = p->inv_J_per_kgm2;
    if (!plain && g->g3_modulated) {
        w.g3_per_kgm2 += m->g3_amplitude_per_kgm2 * sin(m->g3_omega_rad_s * t_mid_s);
    }
    return w;
}

/* The mechanics of one substep: the speed's mean (it sets the rotor's
 * turn), its slope at the middle and its end value (for the end
 * derivatives of the quadratures). */
typedef struct {
    double mean_rad_s, acc_rad_s2, end_rad_s;
} mech_plan_t;

/* The mechanics of the substep (*w) with the other torques t at its
 * middle and i_q(t) = i_q + i_q' t + i_q'' t^2 / 2, i_q' and i_q'' from
 * the ODE at its start (d-q, v_ab held): the mean speed w + (h/2) a(h/3),
 * the end w + h a(h/2) and the slope at the middle, a(t) the acceleration
 * with i_q at t's integral weights (exact for a quadratic i_q), so the
 * speed's error is O(h^4) over a substep, the order of the electrical
 * step's own. v_d: the voltage in d at the start; fric: the friction at
 * the start speed. */
static inline mech_plan_t plan_mechanics(const plant_t *p, const exact_state_t *st,
                                         const mid_torques_t *t, double v_d, double fric)
{
    const plant_exact_consts_t *k = &p->exact;
    const double h = p->h_s;
    const double r = p->R_ohm;
    const double i_d = st->i_d_A;
    const double i_q = st->i_q_A;
    const double w_m = st->omega_rad_s;
    const double w_e = p->n_p * w_m;
    const double b = k->psi_per_L_A + i_d;
    const double di_q = st->a_q_A_s - w_e * b;
    const double g3 = t->g3_per_kgm2;
    const double n_g3_b = p->n_p * g3 * b;
    const double base = k->torque_const_Nm_per_A * i_q - t->tau_load_Nm - t->tau_cog_Nm - fric;
    /* v_d / L + i_d' */
    const double v_l_di_d = (2.0 * v_d - r * i_d) * k->inv_L_per_H + w_e * i_q;
    /* i_q'' = -omega_e (v_d / L + i_d') - (R / L) i_q' - n_p g3 base (psi / L + i_d) */
    const double d2i_q = -w_e * v_l_di_d - k->lambda_per_s * di_q - n_g3_b * base;
    const double half = k->kt_h_2 * di_q;
    const double a_mean = 0.5 * h * g3;
    mech_plan_t w;
    /* w + (h g3 / 2) (base + kt h / 3 i_q' + kt h^2 / 12 i_q'') */
    w.mean_rad_s = w_m + a_mean * (base + k->kt_h_3 * di_q + k->kt_h2_12 * d2i_q);
    w.acc_rad_s2 = g3 * (base + half + k->kt_h2_8 * d2i_q);
    w.end_rad_s = w_m + h * g3 * (base + half + k->kt_h2_6 * d2i_q);
    return w;
}

/* One exact substep of length h_s from t_s. False (nothing changed) when
 * the dead-time error is not constant over it: a phase current is in the
 * linear zone (or zero) at its start or changes direction by its end.
 * plain: g->plain (a constant where it is inlined, so that the common case
 * has none of the optional terms' tests). */
static ALWAYS_INLINE bool exact_step(plant_t *p, segment_t *g, exact_state_t *st, double t_s,
                                     bool plain)
{
    const plant_exact_consts_t *k = &p->exact;
    const double h = p->h_s;
    const double r = p->R_ohm;
    const double n_p = p->n_p;
    const bool dead_time = !plain && g->v_error_V > 0.0;
    if (dead_time) {
        int dir[3];
        const int changed = dead_time_directions(g, st->i_a_A, st->i_b_A, dir);
        if (changed < 0) {
            return false;
        }
        if (changed > 0) {
            st->run = run_next(p, g, st->run, st->i_d_A, st->i_q_A, st->i_a_A, st->i_b_A);
            dead_time_voltage(p, g, dir);
            voltage_terms(p, g, st);
        }
    }
    const double i_d0 = st->i_d_A;
    const double i_q0 = st->i_q_A;
    const double w0 = st->omega_rad_s;
    const double c0 = st->c;
    const double s0 = st->s;
    const double v_a = g->v_a_V;
    const double v_b = g->v_b_V;
    const double v_d0 = c0 * v_a + s0 * v_b;
    const double v_q0 = c0 * v_b - s0 * v_a;
    const bool free = plain || !p->faults.rotor_locked;
    const mid_torques_t t =
        mid_torques(p, g, plain, t_s + 0.5 * h, st->theta_rad + (free ? 0.5 * h * w0 : 0.0));
    mech_plan_t w = { 0.0, 0.0, 0.0 };
    if (free) {
        w = plan_mechanics(p, st, &t, v_d0, friction(p, g, plain, w0));
    }

    /* Rotor vector at the end: u1 = u0 exp(j th), th = omega_e h. */
    const double th = k->turn_per_speed_s * w.mean_rad_s;
    const double th2 = th * th;
    double cm1, sr;
    rotation(th, th2, &cm1, &sr);
    const double cr = 1.0 + cm1;
    const double c1 = c0 * cr - s0 * sr;
    const double s1 = s0 * cr + c0 * sr;

    /* Electrical, exact for omega_e (the mean) and v_ab held: in d-q,
     *   i1 = conj(rot) (E i0 + P + ((1 - E) / R) conj(u0) v_ab),
     * P the back-EMF's response (back_emf_response). */
    double p_d, p_q;
    back_emf_response(k, th, th2, cm1, sr, &p_d, &p_q);
    const double y_d = k->decay * i_d0 + k->input_gain_A_per_V * v_d0 + p_d;
    const double y_q = k->decay * i_q0 + k->input_gain_A_per_V * v_q0 + p_q;
    /* The speed varies over the substep, omega_mean + acc (t - h/2) + ...:
     * the rotor angle leaves the straight line by n_p acc (t^2 - h t) / 2
     * (0 at both ends). In alpha-beta the back-EMF is psi du/dt, so the
     * current depends on the angle's path only through R / L times the
     * integral of exp(-(R / L)(h - t)) u(t); that moves the end current by
     * -j c (R / L) (psi / L) (1 - (R / L) h / 2 - j omega_e h / 2) (d-q,
     * c = n_p acc h^3 / 12; plant.h, "Integrators"). */
    const double kk = k->path_gain_A_s2 * w.acc_rad_s2;
    const double i_d1 = cr * y_d + sr * y_q - kk * 0.5 * th;
    const double i_q1 = cr * y_q - sr * y_d - kk * k->path_q_factor;
    const double i_a1 = c1 * i_d1 - s1 * i_q1;
    const double i_b1 = s1 * i_d1 + c1 * i_q1;
    if (dead_time && !directions_kept(g, i_a1, i_b1)) {
        return false;
    }

    /* Integrals over the substep by the trapezoid rule with its end
     * correction (h^2 / 12) (f'(0) - f'(h)) (exact for cubics), the
     * derivatives from the ODE at the start and end speeds. */
    const double q2 = k->quad_s2;
    const double q2_l = q2 * k->inv_L_per_H;
    const double we0 = n_p * w0;
    const double we1 = n_p * w.end_rad_s;
    const double v_q1 = c1 * v_b - s1 * v_a;
    const double a_q1 = (v_q1 - r * i_q1) * k->inv_L_per_H;
    /* int i_q = (h / 2) (i_q0 + i_q1) + q2 ((a_q0 - a_q1) - we0 (psi / L + i_d0)
     * + we1 (psi / L + i_d1)), a_q1 written out: the speed's chain from the
     * end current is short */
    const double int_i_q =
        (0.5 * h * i_q0 + q2 * (st->a_q_A_s - we0 * (k->psi_per_L_A + i_d0)) - q2_l * v_q1) +
        (k->iq_end_weight_s * i_q1 + (q2 * we1) * (k->psi_per_L_A + i_d1));

    /* Mechanics, corrector: the mean electrical torque of the substep, the
     * others at the middle (time, angle) and mean speed. */
    double w1 = w0;
    double dtheta = 0.0;
    double tau_fric = 0.0;
    if (free) {
        tau_fric = friction(p, g, plain, w.mean_rad_s);
        w1 = w0 + ((t.g3_per_kgm2 * k->torque_const_Nm_per_A) * int_i_q -
                   t.g3_per_kgm2 * h * (tau_fric + t.tau_load_Nm + t.tau_cog_Nm));
        dtheta = h * w.mean_rad_s;
    }

    st->i_d_A = i_d1;
    st->i_q_A = i_q1;
    st->omega_rad_s = w1;
    st->theta_rad += dtheta;
    run_t *run = &st->run;
    run->i_a_A += i_a1;
    run->i_b_A += i_b1;
    run->sq_A2 += i_d1 * i_d1 + i_q1 * i_q1;
    run->ws_rad_s += we1 * s1 - we0 * s0;
    run->wc_rad_s += we1 * c1 - we0 * c0;
    run->wq_A_rad_s += we0 * i_q0 - we1 * i_q1;
    run->substeps += 1u;
    st->e_load_J += dtheta * t.tau_load_Nm;
    if (!plain && g->friction) {
        st->e_fric_J += dtheta * tau_fric;
    }
    if (!plain && g->cogging) {
        st->e_cog_J += dtheta * t.tau_cog_Nm;
    }
    st->c = c1;
    st->s = s1;
    st->i_a_A = i_a1;
    st->i_b_A = i_b1;
    st->a_q_A_s = a_q1;
    return true;
}

/* Substeps j0 .. j1 - 1: runs of exact substeps with the state in locals;
 * a substep the exact step refuses is an RK4 substep on p->x, after which
 * the next run restarts the rotor vector from theta_m. */
void plant_exact_substeps(plant_t *p, const plant_source_t *src, uint32_t j0, uint32_t j1)
{
    const double t0 = p->t_s;
    segment_t g;
    segment_begin(p, src, j0, j1, &g);
    /* A run also ends at the period's middle, where plant_advance_split
     * may change the voltage: a period split into equal halves sums the
     * same terms in the same order as plant_advance. */
    const uint32_t j_mid = p->cfg.substeps_per_period / 2u;
    uint32_t j = j0;
    while (j < j1) {
        exact_state_t st;
        state_load(p, &st);
        state_begin(p, &g, &st);
        for (; j < j1; ++j) {
            if (j == j_mid) {
                st.run = run_next(p, &g, st.run, st.i_d_A, st.i_q_A, st.i_a_A, st.i_b_A);
            }
            const double t_s = t0 + (double)j * p->h_s;
            const bool done =
                g.plain ? exact_step(p, &g, &st, t_s, true) : exact_step(p, &g, &st, t_s, false);
            if (!done) {
                break;
            }
        }
        state_store(p, &g, &st);
        p->exact_cos = st.c;
        p->exact_sin = st.s;
        p->exact_carry = true;
        if (j < j1) {
            plant_rk4_step(p, src, t0 + (double)j * p->h_s, p->h_s, p->x);
            p->exact_carry = false;
            ++j;
        }
    }
}
