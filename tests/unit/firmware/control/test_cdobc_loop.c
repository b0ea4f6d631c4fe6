/*
 * Paper 002 regulators in the loop with a double model of the Section IV
 * motor (mechanical + q axis, cdobc_test_plant.h), 10 kHz, one period of
 * delay between computing a voltage and applying it:
 * - open-loop observer: each internal model (6th and 1st/2nd electrical,
 *   Q-th mechanical harmonic, constant and ramp) estimates its own
 *   disturbance D of (5) exactly; GPIOBC does not estimate a harmonic;
 * - internal model principle in the closed loop (float32 steps, angle-
 *   locked disturbances): PID and GPIOBC leave the harmonics, HDOBC keeps
 *   an offset under a load, CDOBC removes both;
 * - float32 step against a double reference of the same equations
 *   (written here from the design, unfolded), reference step and load:
 *   speeds within 0.01 rpm; no estimate peaking on the reference step;
 *   the same on the four cases of the paper's Section IV (angle-locked
 *   disturbances in this plant: dead-time 6th electrical voltage,
 *   cogging, 1st/2nd electrical torque ripple for the sensor errors,
 *   load step, 25 Hz load) for each observer the bench runs in them;
 * - coefficient swap when the reference moves; the saturated voltage is
 *   what the observer sees; non-finite inputs.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cdobc_test_plant.h"
#include "mc/cdobc.h"
#include "test_rng.h"

#define RPM    MC_TEST_RAD_S_PER_RPM
#define RPM500 (500.0 * RPM)
#define SUB    8 /* RK4 substeps per period */

/* ---- double reference of the step, from the design (unfolded) ------- */

typedef struct {
    double w[MC_CDOBC_N_MAX];
    double nu_prev, v_prev, v_cur;
} ref_t;

static void ref_reset(ref_t *r, double omega)
{
    memset(r, 0, sizeof *r);
    r->nu_prev = -omega;
}

/* observer (8), discrete, with v_prev applied over the last period */
static void ref_observe(const mc_cdobc_design_t *d, ref_t *r, double nu)
{
    const int n = (int)d->n;
    double cw = 0.0, wn[MC_CDOBC_N_MAX];
    for (int j = 0; j < n; ++j) {
        cw += d->c[j] * r->w[j];
    }
    const double innov = nu - d->a_nn * r->nu_prev - cw - d->Bd1 * r->v_prev;
    for (int i = 0; i < n; ++i) {
        double s = d->a_wn[i] * r->nu_prev + d->Bd2[i] * r->v_prev + d->Ld[i] * innov;
        for (int j = 0; j < n; ++j) {
            s += d->Ad[i * n + j] * r->w[j];
        }
        wn[i] = s;
    }
    memcpy(r->w, wn, sizeof(double) * (size_t)n);
    r->nu_prev = nu;
}

static double ref_step(const mc_cdobc_design_t *d, ref_t *r, double omega, double omega_ref)
{
    const int n = (int)d->n;
    ref_observe(d, r, -omega);
    /* one-step prediction with v_cur, then (6) + (9) */
    const double nu = -omega;
    double nup = d->a_nn * nu + d->Bd1 * r->v_cur;
    double x2p = d->a_wn[0] * nu + d->Bd2[0] * r->v_cur;
    double ff = 0.0;
    for (int j = 0; j < n; ++j) {
        nup += d->c[j] * r->w[j];
        x2p += d->Ad[j] * r->w[j];
    }
    for (int m = 1; m < n; ++m) {
        double dp = 0.0;
        for (int j = 0; j < n; ++j) {
            dp += d->Ad[m * n + j] * r->w[j];
        }
        ff += -d->Ad[m] / d->Bd2[0] * dp;
    }
    const double u_qd = d->c_qd_V_s * (-nup);
    const double u_qi = d->k1 * (omega_ref + nup) + d->k2 * x2p + ff;
    const double v = fmax(-200.0, fmin(200.0, u_qd + u_qi));
    r->v_prev = r->v_cur;
    r->v_cur = v;
    return v;
}

static double h_dot_w(const mc_cdobc_design_t *d, const ref_t *r)
{
    double s = 0.0;
    for (int i = 0; i < (int)d->n; ++i) {
        s += d->h[i] * r->w[i];
    }
    return s;
}

/* ---- open-loop observer ------------------------------------------------ */

/* D of (5) for the time-locked disturbances at time t */
static double true_D(const p2_dist_t *ds, double t)
{
    const double w = ds->omega_t, L = P2_L, R = P2_R;
    const double th = w * t;
    const double Td = ds->T_load + ds->T_ramp * t + ds->T_cog * cos(P2_Q * th) +
                      ds->T_h1 * cos(P2_NP * th) + ds->T_h2 * cos(2.0 * P2_NP * th);
    const double dTd = ds->T_ramp - ds->T_cog * P2_Q * w * sin(P2_Q * th) -
                       ds->T_h1 * P2_NP * w * sin(P2_NP * th) -
                       ds->T_h2 * 2.0 * P2_NP * w * sin(2.0 * P2_NP * th);
    return -ds->U_6 * cos(6.0 * P2_NP * th) / L + (dTd + R / L * Td) / P2_KT;
}

/* run the observer alone on the plant under an open-loop voltage;
 * returns max |D_hat - D| / max |D| over the last 20 ms of 0.15 s */
static double open_loop_error(const mc_cdobc_design_t *d, const p2_dist_t *ds)
{
    p2_plant_t pl = { .omega = RPM500, .i_q = P2_B * RPM500 / P2_KT };
    ref_t r;
    ref_reset(&r, pl.omega);
    const int steps = 1500, tail = 200;
    double err = 0.0, mag = 0.0;
    for (int k = 0; k < steps; ++k) {
        ref_observe(d, &r, -pl.omega);
        if (k >= steps - tail) {
            const double D = true_D(ds, pl.t);
            err = fmax(err, fabs(h_dot_w(d, &r) - D));
            mag = fmax(mag, fabs(D));
        }
        /* open loop: back-EMF + friction voltage and a 30 Hz wobble */
        const double v = P2_CQD * RPM500 + 2.0 * sin(MC_TEST_TWO_PI * 30.0 * pl.t);
        r.v_prev = v; /* applied over [t_k, t_k+1): seen at the next update */
        p2_plant_step(&pl, ds, v, P2_TS, SUB);
    }
    return err / mag;
}

static void design_set(mc_cdobc_kind_t kind, int extra_sensor_harmonics, mc_cdobc_placement_t pl,
                       mc_cdobc_params_t *p, mc_cdobc_design_t *d, double omega_ref)
{
    mc_cdobc_params_paper002(p, (float)P2_TS, kind);
    p->placement = pl;
    if (extra_sensor_harmonics) {
        p->models.harm[p->models.n_harm++] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 1u, 0.0f };
        p->models.harm[p->models.n_harm++] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 2u, 0.0f };
    }
    assert_int_equal(mc_cdobc_design_f64(p, omega_ref, d), MC_OK);
}

static void test_open_loop_models_exact(void **state)
{
    (void)state;
    mc_cdobc_params_t p;
    mc_cdobc_design_t d, g;
    design_set(MC_CDOBC_KIND_CDOBC, 1, MC_CDOBC_PLACE_LITERAL, &p, &d, RPM500);
    design_set(MC_CDOBC_KIND_GPIOBC, 0, MC_CDOBC_PLACE_LITERAL, &p, &g, RPM500);
    const p2_dist_t base = { .omega_t = RPM500, .fJ = 1, .fR = 1, .fL = 1, .fK = 1 };
    static const char *const names[6] = {
        "6th el. (dead time) 3 V", "Q-th mech. (cogging) 0.02 N m", "1st el. (offset) 0.02 N m",
        "2nd el. (gain) 0.02 N m", "constant load 0.3 N m",         "ramp load 2 N m/s"
    };
    for (int c = 0; c < 6; ++c) {
        p2_dist_t ds = base;
        switch (c) {
        case 0: ds.U_6 = 3.0; break;
        case 1: ds.T_cog = 0.02; break;
        case 2: ds.T_h1 = 0.02; break;
        case 3: ds.T_h2 = 0.02; break;
        case 4: ds.T_load = 0.3; break;
        default: ds.T_ramp = 2.0; break;
        }
        const double e = open_loop_error(&d, &ds);
        print_message("open-loop observer, %-30s: |D_hat - D| / |D| = %.2e\n", names[c], e);
        assert_true(e < 1e-6);
    }
    p2_dist_t ds = base;
    ds.U_6 = 3.0;
    const double eg = open_loop_error(&g, &ds);
    print_message("GPIOBC on the 6th harmonic: %.2f\n", eg);
    assert_true(eg > 0.5);
}

/* ---- closed loop ------------------------------------------------------- */

typedef struct {
    double mean_rpm, ripple_rpm; /* of omega - omega* over the last 0.1 s */
    double early_mean_rpm;       /* mean over 0.15 .. 0.25 s */
} loop_res_t;

/* run a float32 controller (CDOBC family or PID) from 500 rpm steady
 * state with a load_Nm load from 50 ms, 3 V dead-time harmonic and
 * 0.01 N m cogging, angle-locked, for 0.6 s */
static loop_res_t run_closed(mc_cdobc_kind_t kind, int pid, double load_Nm)
{
    mc_cdobc_params_t p;
    mc_cdobc_params_paper002(&p, (float)P2_TS, kind);
    mc_cdobc_f32_t c;
    mc_cdobc_pid_f32_t q;
    if (pid) {
        assert_int_equal(
            mc_cdobc_pid_init_f32(&q, 23.0f, 10.0f, 0.0167f, (float)P2_TS, (float)P2_CQD, 200.0f),
            MC_OK);
        assert_int_equal(mc_cdobc_pid_reset_f32(&q, (float)RPM500), MC_OK);
    } else {
        assert_int_equal(mc_cdobc_init_f32(&c, &p, (float)RPM500), MC_OK);
        assert_int_equal(mc_cdobc_reset_f32(&c, (float)RPM500), MC_OK);
    }
    p2_plant_t pl = { .omega = RPM500, .i_q = P2_B * RPM500 / P2_KT };
    p2_dist_t ds = { .U_6 = 3.0, .T_cog = 0.01, .fJ = 1, .fR = 1, .fL = 1, .fK = 1 };
    double v_app = P2_CQD * RPM500;
    const int steps = 6000, tail = 1000;
    double lo = 1e9, hi = -1e9, sum = 0.0, early = 0.0;
    for (int k = 0; k < steps; ++k) {
        ds.T_load = (k >= 500) ? load_Nm : 0.0;
        float v_new;
        if (pid) {
            assert_int_equal(mc_cdobc_pid_step_f32(&q, (float)pl.omega, (float)RPM500, &v_new),
                             MC_OK);
        } else {
            mc_cdobc_out_t o;
            assert_int_equal(mc_cdobc_step_f32(&c, (float)pl.omega, (float)RPM500, 0.0f, &o),
                             MC_OK);
            v_new = o.v_q_V;
        }
        p2_plant_step(&pl, &ds, v_app, P2_TS, SUB);
        v_app = (double)v_new;
        const double e = (pl.omega - RPM500) / RPM;
        if (k >= 1500 && k < 2500) {
            early += e / 1000.0;
        }
        if (k >= steps - tail) {
            lo = fmin(lo, e);
            hi = fmax(hi, e);
            sum += e;
        }
    }
    return (loop_res_t){ sum / tail, 0.5 * (hi - lo), early };
}

static void test_internal_model_principle(void **state)
{
    (void)state;
    const loop_res_t pid = run_closed(MC_CDOBC_KIND_CDOBC, 1, 0.3);
    const loop_res_t gp = run_closed(MC_CDOBC_KIND_GPIOBC, 0, 0.3);
    const loop_res_t hd = run_closed(MC_CDOBC_KIND_HDOBC, 0, 0.3);
    const loop_res_t hd0 = run_closed(MC_CDOBC_KIND_HDOBC, 0, 0.0);
    const loop_res_t cd = run_closed(MC_CDOBC_KIND_CDOBC, 0, 0.3);
    print_message("500 rpm, 3 V 6th-el. + 0.01 N m cogging, 0.3 N m load "
                  "(mean / ripple over 0.5-0.6 s, mean over 0.15-0.25 s; rpm):\n"
                  "  PID    %+.4f / %.4f  (%+.4f)\n  GPIOBC %+.4f / %.4f  (%+.4f)\n"
                  "  HDOBC  %+.4f / %.4f  (%+.4f); without load %+.4f / %.4f\n"
                  "  CDOBC  %+.4f / %.4f  (%+.4f)\n",
                  pid.mean_rpm, pid.ripple_rpm, pid.early_mean_rpm, gp.mean_rpm, gp.ripple_rpm,
                  gp.early_mean_rpm, hd.mean_rpm, hd.ripple_rpm, hd.early_mean_rpm, hd0.mean_rpm,
                  hd0.ripple_rpm, cd.mean_rpm, cd.ripple_rpm, cd.early_mean_rpm);
    /* PID: the integrator removes the offset, slowly (kp / ki = 2.3 s) */
    assert_true(fabs(pid.mean_rpm) < 0.9 * fabs(pid.early_mean_rpm));
    /* polynomial model: no offset */
    assert_true(fabs(gp.mean_rpm) < 0.05);
    assert_true(fabs(cd.mean_rpm) < 0.05);
    /* HDOBC: no constant model, keeps an offset under load; without
     * load (friction and back-EMF compensated by (6)) it has none */
    assert_true(fabs(hd.mean_rpm) > 10.0);
    assert_true(fabs(hd0.mean_rpm) < 0.05);
    /* harmonic models: ripple far below GPIOBC's and PID's */
    assert_true(cd.ripple_rpm < 0.01 * gp.ripple_rpm);
    assert_true(cd.ripple_rpm < 0.01 * pid.ripple_rpm);
    assert_true(hd0.ripple_rpm < 0.01 * gp.ripple_rpm);
}

/* The disturbances of a float-vs-double run at time t: case 0 the
 * single-run test's (6th electrical 3 V, cogging 0.01 N m, 0.3 N m from
 * 0.15 s); cases 1-4 Section IV's (test_float_vs_double_cases). */
static void fvd_disturbances(p2_dist_t *ds, int ccase, double t)
{
    *ds = (p2_dist_t){ .U_6 = 3.0, .fJ = 1, .fR = 1, .fL = 1, .fK = 1 };
    if (ccase == 0) {
        ds->T_cog = 0.01;
        ds->T_load = (t >= 0.15) ? 0.3 : 0.0;
        return;
    }
    ds->T_cog = 0.02;
    ds->T_h1 = ds->T_h2 = 0.002;
    if (ccase == 2 && t >= 0.2) {
        ds->U_6 = 7.0;
        ds->T_h1 = 0.1;
        ds->T_h2 = 0.05;
    }
    if (ccase >= 3) {
        ds->T_load = (t >= 0.1) ? 1.5 : 0.0;
    }
    if (ccase == 4 && t >= 0.2) {
        ds->T_sin = 1.0;
        ds->w_sin = 50.0 * 3.14159265358979323846;
    }
}

typedef struct {
    double worst_rpm; /* max |omega_f32 - omega_f64| */
    double worst_v;   /* max |v_q,f32 - v_q,f64| */
    double first_v;   /* the first command (float32) */
    double err_end;   /* omega_f32 - omega* at the end (rpm) */
    double e_tail;    /* max |omega_f64 - omega*| over the last quarter */
} fvd_t;

/* 0 -> 500 rpm from rest: the float32 step and the double reference of
 * the same design, each on its own double plant, `steps` periods */
static fvd_t float_vs_double(const mc_cdobc_params_t *p, const mc_cdobc_design_t *d, int ccase,
                             int steps)
{
    mc_cdobc_f32_t c;
    assert_int_equal(mc_cdobc_init_f32(&c, p, (float)RPM500), MC_OK);
    assert_int_equal(mc_cdobc_reset_f32(&c, 0.0f), MC_OK);
    ref_t r;
    ref_reset(&r, 0.0);
    p2_plant_t pf = { 0 }, pd = { 0 };
    p2_dist_t ds;
    double vf = 0.0, vd = 0.0;
    fvd_t res = { 0 };
    for (int k = 0; k < steps; ++k) {
        const double t = k * P2_TS;
        fvd_disturbances(&ds, ccase, t);
        mc_cdobc_out_t o;
        assert_int_equal(mc_cdobc_step_f32(&c, (float)pf.omega, (float)RPM500, 0.0f, &o), MC_OK);
        const double v_ref = ref_step(d, &r, pd.omega, RPM500);
        if (k == 0) {
            res.first_v = (double)o.v_q_V;
        }
        res.worst_v = fmax(res.worst_v, fabs((double)o.v_q_V - v_ref));
        p2_plant_step(&pf, &ds, vf, P2_TS, SUB);
        p2_plant_step(&pd, &ds, vd, P2_TS, SUB);
        vf = (double)o.v_q_V;
        vd = v_ref;
        res.worst_rpm = fmax(res.worst_rpm, fabs(pf.omega - pd.omega) / RPM);
        if (4 * k >= 3 * steps) {
            res.e_tail = fmax(res.e_tail, fabs(pd.omega - RPM500) / RPM);
        }
    }
    res.err_end = (pf.omega - RPM500) / RPM;
    return res;
}

static void test_float_vs_double(void **state)
{
    (void)state;
    mc_cdobc_params_t p;
    mc_cdobc_design_t d;
    design_set(MC_CDOBC_KIND_CDOBC, 0, MC_CDOBC_PLACE_ROBUST, &p, &d, RPM500);
    const fvd_t f = float_vs_double(&p, &d, 0, 3000);
    /* had the observer been driven by x1 = omega* - omega, as (8)
     * writes it, the step would have entered as an innovation of 500 rpm:
     * first command k1 dx1 + g . Ld dx1 (w jumps by Ld dx1) */
    double gl = 0.0;
    for (int i = 0; i < (int)d.n; ++i) {
        gl += d.g[i] * d.Ld[i];
    }
    const double v_x1 = (d.k1 + gl) * RPM500;
    print_message("0 -> 500 rpm step, load at 0.15 s: float vs double max |d omega| %.2e rpm, "
                  "max |d v_q| %.2e V; first command %.2f V (driven by x1: %.0f V); "
                  "error at 0.3 s %.4f rpm\n",
                  f.worst_rpm, f.worst_v, f.first_v, v_x1, f.err_end);
    assert_true(fabs(v_x1) > 200.0);
    assert_true(f.worst_rpm < 0.01);
    /* driven by -omega: the step enters through k1 x1 only (k1 = 0.28) */
    assert_true(fabs(f.first_v) < 20.0);
    assert_true(fabs(f.err_end) < 1.0);
}

/* Section IV's cases in this plant, 0 -> 500 rpm at t = 0, 0.4 s: I
 * dead time (6th electrical, 3 V on v_q), cogging 0.02 N m, small sensor
 * ripple (1st / 2nd electrical, 2 mN m); II as I and from 0.2 s 7 V, 0.1
 * / 0.05 N m; III as I and 1.5 N m from 0.1 s; IV as III and sin(50 pi t)
 * N m from 0.2 s. Observers: CDOBC, GPIOBC in all, HDOBC in I-II (its
 * unmodelled load drives it far off in III-IV, as on the bench), CDOBC
 * with the sensor models (zeta 0.5) in II. Max |omega_f32 - omega_f64|
 * over the run < 0.01 rpm. */
static void test_float_vs_double_cases(void **state)
{
    (void)state;
    typedef struct {
        int ccase;
        mc_cdobc_kind_t kind;
        int sensors;
    } run_t;
    static const run_t runs[] = {
        { 1, MC_CDOBC_KIND_CDOBC, 0 },  { 1, MC_CDOBC_KIND_GPIOBC, 0 },
        { 1, MC_CDOBC_KIND_HDOBC, 0 },  { 2, MC_CDOBC_KIND_CDOBC, 0 },
        { 2, MC_CDOBC_KIND_CDOBC, 1 },  { 2, MC_CDOBC_KIND_GPIOBC, 0 },
        { 2, MC_CDOBC_KIND_HDOBC, 0 },  { 3, MC_CDOBC_KIND_CDOBC, 0 },
        { 3, MC_CDOBC_KIND_GPIOBC, 0 }, { 4, MC_CDOBC_KIND_CDOBC, 0 },
        { 4, MC_CDOBC_KIND_GPIOBC, 0 },
    };
    static const char *kinds[] = { "CDOBC", "GPIOBC", "HDOBC" };
    for (size_t i = 0; i < sizeof runs / sizeof runs[0]; ++i) {
        const run_t *u = &runs[i];
        mc_cdobc_params_t p;
        mc_cdobc_params_paper002(&p, (float)P2_TS, u->kind);
        if (u->sensors) {
            p.models.harm[p.models.n_harm++] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 1u, 0.5f };
            p.models.harm[p.models.n_harm++] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 2u, 0.5f };
        }
        mc_cdobc_design_t d;
        assert_int_equal(mc_cdobc_design_f64(&p, RPM500, &d), MC_OK);
        const fvd_t f = float_vs_double(&p, &d, u->ccase, 4000);
        print_message("case %d %-6s%s: float32 vs double max |d omega| %.2e rpm (double: "
                      "max |error| %.3g rpm over 0.3-0.4 s)\n",
                      u->ccase, kinds[u->kind], u->sensors ? " + sensor models" : "", f.worst_rpm,
                      f.e_tail);
        assert_true(f.worst_rpm < 0.01);
    }
}

/* paper CDOBC designed at 500 rpm, started at omega */
static void start_cdobc(mc_cdobc_params_t *p, mc_cdobc_f32_t *c, double omega)
{
    mc_cdobc_params_paper002(p, (float)P2_TS, MC_CDOBC_KIND_CDOBC);
    assert_int_equal(mc_cdobc_init_f32(c, p, (float)RPM500), MC_OK);
    assert_int_equal(mc_cdobc_reset_f32(c, (float)omega), MC_OK);
}

static void test_redesign_on_reference_change(void **state)
{
    (void)state;
    mc_cdobc_params_t p;
    mc_cdobc_f32_t c;
    start_cdobc(&p, &c, RPM500);
    p2_plant_t pl = { .omega = RPM500, .i_q = P2_B * RPM500 / P2_KT };
    p2_dist_t ds = { .U_6 = 3.0, .T_cog = 0.01, .T_load = 0.1, .fJ = 1, .fR = 1, .fL = 1, .fK = 1 };
    double v_app = P2_CQD * RPM500, lo = 1e9, hi = -1e9;
    const double ref2 = 750.0 * RPM;
    for (int k = 0; k < 8000; ++k) {
        const double ref = (k >= 2000) ? ref2 : RPM500;
        assert_true(mc_cdobc_needs_redesign_f32(&c, (float)ref, 1e-3f) == (k == 2000));
        if (k == 2000) { /* the slow loop re-designs and swaps */
            mc_cdobc_design_t d;
            mc_cdobc_coef_f32_t cf;
            assert_int_equal(mc_cdobc_design_f64(&p, ref2, &d), MC_OK);
            assert_int_equal(mc_cdobc_coef_f32(&d, &cf), MC_OK);
            assert_int_equal(mc_cdobc_set_coef_f32(&c, &cf), MC_OK);
        }
        mc_cdobc_out_t o;
        assert_int_equal(mc_cdobc_step_f32(&c, (float)pl.omega, (float)ref, 0.0f, &o), MC_OK);
        p2_plant_step(&pl, &ds, v_app, P2_TS, SUB);
        v_app = (double)o.v_q_V;
        if (k >= 7000) {
            const double e = (pl.omega - ref2) / RPM;
            lo = fmin(lo, e);
            hi = fmax(hi, e);
        }
    }
    print_message("after 500 -> 750 rpm with re-design: error in [%.4f, %.4f] rpm\n", lo, hi);
    assert_true(hi < 0.05 && lo > -0.05);
    /* a coefficient set of another model set is refused */
    mc_cdobc_params_t g;
    mc_cdobc_design_t dg;
    mc_cdobc_coef_f32_t cg;
    design_set(MC_CDOBC_KIND_GPIOBC, 0, MC_CDOBC_PLACE_ROBUST, &g, &dg, RPM500);
    assert_int_equal(mc_cdobc_coef_f32(&dg, &cg), MC_OK);
    assert_int_equal(mc_cdobc_set_coef_f32(&c, &cg), MC_ERR_PARAM);
}

static void test_saturation_fed_back(void **state)
{
    (void)state;
    /* 500 rpm, 25 V limit, a 0.6 N m load pulse (20-150 ms) that needs
     * 29 V: the voltage saturates and the speed drops. The observer sees
     * the applied voltage, so during saturation D_hat still converges to
     * the load's D = R T / (L Kt) (fed the unclamped command it would be
     * off by the clamped excess / L_q); after the pulse no wind-up. */
    mc_cdobc_params_t p;
    mc_cdobc_params_paper002(&p, (float)P2_TS, MC_CDOBC_KIND_CDOBC);
    p.v_max_V = 25.0f;
    mc_cdobc_f32_t c;
    assert_int_equal(mc_cdobc_init_f32(&c, &p, (float)RPM500), MC_OK);
    assert_int_equal(mc_cdobc_reset_f32(&c, (float)RPM500), MC_OK);
    p2_plant_t pl = { .omega = RPM500, .i_q = P2_B * RPM500 / P2_KT };
    p2_dist_t ds = { .fJ = 1, .fR = 1, .fL = 1, .fK = 1 };
    const double T = 0.6, D_true = P2_R / P2_L * T / P2_KT;
    double v_app = P2_CQD * RPM500, d_err = 0.0, excess = 0.0, low = 1e9, high = 0.0;
    int n_sat = 0;
    for (int k = 0; k < 4000; ++k) {
        ds.T_load = (k >= 200 && k < 1500) ? T : 0.0;
        mc_cdobc_out_t o;
        assert_int_equal(mc_cdobc_step_f32(&c, (float)pl.omega, (float)RPM500, 0.0f, &o), MC_OK);
        n_sat += o.q_limited ? 1 : 0;
        if (k >= 1400 && k < 1500) { /* last 10 ms of the pulse */
            d_err = fmax(d_err, fabs((double)o.d_hat - D_true));
            excess = fmax(excess, fabs((double)(o.v_q_unsat_V - o.v_q_V)) / P2_L);
        }
        p2_plant_step(&pl, &ds, v_app, P2_TS, SUB);
        v_app = (double)o.v_q_V;
        low = fmin(low, pl.omega / RPM);
        if (k >= 1600) {
            high = fmax(high, pl.omega / RPM);
        }
    }
    print_message("25 V limit, 0.6 N m pulse: %d saturated periods, |D_hat - D| %.2e of D = "
                  "%.0f A/s (clamped excess / L up to %.0f A/s); speed down to %.1f rpm, "
                  "after the pulse at most %.2f rpm, final %.4f rpm\n",
                  n_sat, d_err / D_true, D_true, excess, low, high, pl.omega / RPM);
    assert_true(n_sat > 100);
    assert_true(excess > 0.2 * D_true);
    assert_true(d_err < 0.01 * D_true);
    assert_true(high < 510.0);
    assert_near(pl.omega / RPM, 500.0, 0.01);
}

static void test_nonfinite_and_validation(void **state)
{
    (void)state;
    mc_cdobc_params_t p;
    mc_cdobc_f32_t c;
    start_cdobc(&p, &c, 10.0);
    mc_cdobc_out_t o = { .v_q_V = 7.0f }, o0 = o;
    mc_cdobc_f32_t keep = c;
    assert_int_equal(mc_cdobc_step_f32(&c, NAN, 1.0f, 0.0f, &o), MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_step_f32(&c, 1.0f, INFINITY, 0.0f, &o), MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_step_f32(&c, 1.0f, 1.0f, NAN, &o), MC_ERR_NONFINITE);
    assert_memory_equal(&c, &keep, sizeof c);
    assert_memory_equal(&o, &o0, sizeof o);
    assert_int_equal(mc_cdobc_reset_f32(&c, NAN), MC_ERR_NONFINITE);
    assert_true(mc_cdobc_needs_redesign_f32(&c, NAN, 1e-3f));
    assert_false(mc_cdobc_needs_redesign_f32(&c, (float)-RPM500, 1e-3f));
    assert_true(mc_cdobc_needs_redesign_f32(&c, 0.0f, 1e-3f));
    /* a non-finite state reaching the step is reported, not used */
    mc_cdobc_state_f32(&c)[0] = INFINITY;
    assert_int_equal(mc_cdobc_step_f32(&c, 1.0f, 1.0f, 0.0f, &o), MC_ERR_NONFINITE);
    /* init errors leave the instance untouched */
    keep = c;
    mc_cdobc_params_t q = p;
    q.v_max_V = 0.0f;
    assert_int_equal(mc_cdobc_init_f32(&c, &q, (float)RPM500), MC_ERR_PARAM);
    q = p;
    q.kp_d_V_A = NAN;
    assert_int_equal(mc_cdobc_init_f32(&c, &q, (float)RPM500), MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_init_f32(&c, &p, NAN), MC_ERR_NONFINITE);
    assert_memory_equal(&c, &keep, sizeof c);
    /* d axis: PI on -i_d, clamped */
    assert_int_equal(mc_cdobc_init_f32(&c, &p, (float)RPM500), MC_OK);
    assert_int_equal(mc_cdobc_reset_f32(&c, 0.0f), MC_OK);
    assert_int_equal(mc_cdobc_step_f32(&c, 0.0f, 0.0f, 0.5f, &o), MC_OK);
    assert_near(o.v_d_V, -(120.0 * 0.5 + 240.0 * P2_TS * 0.5), 1e-4);
    assert_int_equal(mc_cdobc_step_f32(&c, 0.0f, 0.0f, 10.0f, &o), MC_OK);
    assert_near(o.v_d_V, -200.0, 0.0);
    assert_true(o.d_limited);
    /* PID */
    mc_cdobc_pid_f32_t pid;
    assert_int_equal(mc_cdobc_pid_init_f32(&pid, -1.0f, 10.0f, 0.0f, 1e-4f, 0.0f, 200.0f),
                     MC_ERR_PARAM);
    assert_int_equal(mc_cdobc_pid_init_f32(&pid, 23.0f, NAN, 0.0f, 1e-4f, 0.0f, 200.0f),
                     MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_pid_init_f32(&pid, 23.0f, 10.0f, 0.0167f, 1e-4f, 0.0f, 200.0f),
                     MC_OK);
    assert_int_equal(mc_cdobc_pid_reset_f32(&pid, 0.0f), MC_OK);
    float v = 0.0f;
    assert_int_equal(mc_cdobc_pid_step_f32(&pid, 0.0f, 1.0f, &v), MC_OK);
    assert_near(v, 23.0 + 10.0 * 1e-4, 1e-5);
    assert_int_equal(mc_cdobc_pid_step_f32(&pid, 0.0f, 100.0f, &v), MC_OK);
    assert_near(v, 200.0, 0.0);
    const float integ = pid.integ_V;
    assert_int_equal(mc_cdobc_pid_step_f32(&pid, 0.0f, 100.0f, &v), MC_OK);
    assert_near(pid.integ_V, integ, 0.0); /* no wind-up */
    assert_int_equal(mc_cdobc_pid_step_f32(&pid, NAN, 100.0f, &v), MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_pid_reset_f32(&pid, INFINITY), MC_ERR_NONFINITE);
}

/* Entry (i, j) of Ad - I as the float32 coefficients hold it (0 outside
 * their structure, mc_cdobc_coef_f32_t), in double. */
static double coef_a_minus_i(const mc_cdobc_coef_f32_t *k, uint32_t i, uint32_t j)
{
    const uint32_t s_poly = 1u + 2u * k->n_harm;
    if (i == 0u) {
        return k->a0[j];
    }
    if (i < s_poly) {
        const uint32_t s = 1u + 2u * ((i - 1u) / 2u);
        return (j == s || j == s + 1u) ? k->harm[(i - 1u) / 2u][2u * (i - s) + (j - s)] : 0.0;
    }
    return (j >= s_poly) ? k->poly[(i - s_poly) * MC_CDOBC_POLY_MAX + (j - s_poly)] : 0.0;
}

/* The float32 coefficients of real designs (CDOBC with the sensor models,
 * n = 13; GPIOBC; HDOBC; both placements) are the design's Ad - I and c
 * rounded to float, entry by entry (the structure loses nothing: every
 * entry outside it is exactly zero in the design), and a design with a
 * nonzero entry outside the structure is refused. */
static void test_coef_structure(void **state)
{
    (void)state;
    const mc_cdobc_kind_t kinds[3] = { MC_CDOBC_KIND_CDOBC, MC_CDOBC_KIND_GPIOBC,
                                       MC_CDOBC_KIND_HDOBC };
    for (int kd = 0; kd < 3; kd++) {
        for (int pl = 0; pl < 2; pl++) {
            mc_cdobc_params_t p;
            mc_cdobc_design_t d;
            design_set(kinds[kd], kd == 0, pl ? MC_CDOBC_PLACE_ROBUST : MC_CDOBC_PLACE_LITERAL, &p,
                       &d, RPM500);
            mc_cdobc_coef_f32_t k;
            assert_int_equal(mc_cdobc_coef_f32(&d, &k), MC_OK);
            const uint32_t n = d.n;
            for (uint32_t i = 0; i < n; ++i) {
                for (uint32_t j = 0; j < n; ++j) {
                    const double a = d.Ad[i * n + j] - ((i == j) ? 1.0 : 0.0);
                    assert_true(coef_a_minus_i(&k, i, j) == (double)(float)a);
                }
                assert_true(k.c[i] == (float)d.c[i]);
            }
            const uint32_t s_poly = 1u + 2u * d.n_harm;
            if (s_poly < n) { /* a polynomial row's x2 entry */
                mc_cdobc_design_t bad = d;
                bad.Ad[s_poly * n] = 1e-3;
                assert_int_equal(mc_cdobc_coef_f32(&bad, &k), MC_ERR_PARAM);
            }
            if (d.n_harm >= 2u) { /* between two harmonic blocks */
                mc_cdobc_design_t bad = d;
                bad.Ad[1u * n + 3u] = 1e-3;
                assert_int_equal(mc_cdobc_coef_f32(&bad, &k), MC_ERR_PARAM);
            }
        }
    }
}

/* The observer update by its structure (mc_cdobc_observe_f32) against the
 * dense update w + Gn nu_prev + Gu v_prev + Ld dnu + (Ad - I - Ld c) w in
 * double, with random coefficients of every layout (n_harm 0 .. 4, N 0 ..
 * 3): within a few float roundings of the terms' magnitudes. */
static void test_observe_structured(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(2002);
    double worst = 0.0;
    for (uint32_t nh = 0u; nh <= MC_CDOBC_HARM_MAX; ++nh) {
        for (uint32_t np = 0u; np <= MC_CDOBC_POLY_MAX; ++np) {
            const uint32_t n = 1u + 2u * nh + np;
            for (int rep = 0; rep < 200; ++rep) {
                mc_cdobc_coef_f32_t k = { .n = n, .n_harm = nh, .poly_order = np };
                float w[MC_CDOBC_N_MAX];
                for (uint32_t i = 0; i < n; ++i) {
                    k.a0[i] = (float)test_rng_range(&rng, -0.1, 0.1);
                    k.c[i] = (float)test_rng_range(&rng, -0.1, 0.1);
                    k.Gn[i] = (float)test_rng_range(&rng, -1.0, 1.0);
                    k.Gu[i] = (float)test_rng_range(&rng, -1.0, 1.0);
                    k.Ld[i] = (float)test_rng_range(&rng, -10.0, 10.0);
                    k.g[i] = (float)test_rng_range(&rng, -5.0, 5.0);
                    w[i] = (float)test_rng_range(&rng, -100.0, 100.0);
                }
                for (uint32_t b = 0; b < nh; ++b) {
                    for (int e = 0; e < 4; ++e) {
                        k.harm[b][e] = (float)test_rng_range(&rng, -0.1, 0.1);
                    }
                }
                for (uint32_t e = 0; e < MC_CDOBC_POLY_MAX * MC_CDOBC_POLY_MAX; ++e) {
                    k.poly[e] = (float)test_rng_range(&rng, -0.1, 0.1);
                }
                const float nu_prev = (float)test_rng_range(&rng, -60.0, 60.0);
                const float v_prev = (float)test_rng_range(&rng, -200.0, 200.0);
                const float dnu = (float)test_rng_range(&rng, -2.0, 2.0);
                const float v0 = (float)test_rng_range(&rng, -50.0, 50.0);
                double cw = 0.0, cw_mag = 0.0;
                for (uint32_t j = 0; j < n; ++j) {
                    cw += (double)k.c[j] * w[j];
                    cw_mag += fabs((double)k.c[j] * w[j]);
                }
                double ref[MC_CDOBC_N_MAX], mag[MC_CDOBC_N_MAX];
                double v_ref = v0, v_mag = fabs((double)v0);
                for (uint32_t i = 0; i < n; ++i) {
                    const double t[5] = { w[i], (double)k.Gn[i] * nu_prev, (double)k.Gu[i] * v_prev,
                                          (double)k.Ld[i] * dnu, -(double)k.Ld[i] * cw };
                    ref[i] = 0.0;
                    mag[i] = fabs((double)k.Ld[i]) * cw_mag;
                    for (int e = 0; e < 5; ++e) {
                        ref[i] += t[e];
                        mag[i] += fabs(t[e]);
                    }
                    for (uint32_t j = 0; j < n; ++j) {
                        const double a = coef_a_minus_i(&k, i, j) * w[j];
                        ref[i] += a;
                        mag[i] += fabs(a);
                    }
                    v_ref += (double)k.g[i] * ref[i];
                    v_mag += fabs((double)k.g[i]) * mag[i];
                }
                float out[MC_CDOBC_N_MAX];
                const float v = mc_cdobc_observe_f32(&k, w, out, nu_prev, v_prev, dnu, v0);
                for (uint32_t i = 0; i < n; ++i) {
                    const double r = fabs(out[i] - ref[i]) / (mag[i] * FLT_EPSILON);
                    worst = fmax(worst, r);
                    assert_true(r <= 2.0 * (double)n);
                }
                assert_true(fabs(v - v_ref) <= 4.0 * (double)n * v_mag * FLT_EPSILON);
            }
        }
    }
    printf("structured observer update: worst error %.2f float roundings of the terms\n", worst);
}

/* The ISR's step (mc_cdobc_step_core_f32) is the checked step without
 * d_hat, and leaves the state as it was when it fails. */
static void test_step_core(void **state)
{
    (void)state;
    mc_cdobc_params_t p;
    mc_cdobc_f32_t a, b;
    start_cdobc(&p, &a, 10.0);
    b = a;
    for (int k = 0; k < 500; ++k) {
        const float w = 10.0f + 0.01f * (float)k;
        mc_cdobc_out_t oa, ob;
        assert_int_equal(mc_cdobc_step_f32(&a, w, (float)RPM500, 0.1f, &oa), MC_OK);
        assert_true(mc_cdobc_step_core_f32(&b, w, (float)RPM500, 0.1f, &ob));
        assert_memory_equal(&oa.v_q_V, &ob.v_q_V, sizeof oa.v_q_V);
        assert_memory_equal(&oa.v_d_V, &ob.v_d_V, sizeof oa.v_d_V);
        assert_memory_equal(&oa.v_q_unsat_V, &ob.v_q_unsat_V, sizeof oa.v_q_unsat_V);
        assert_int_equal(oa.q_limited, ob.q_limited);
        assert_int_equal(oa.d_limited, ob.d_limited);
        assert_memory_equal(mc_cdobc_state_f32(&a), mc_cdobc_state_f32(&b),
                            a.coef.n * sizeof(float));
    }
    /* non-finite: false, the state in use and *out as they were */
    const float bad[][3] = { { NAN, 1.0f, 0.0f }, { 1.0f, -INFINITY, 0.0f }, { 1.0f, 1.0f, NAN } };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        const mc_cdobc_f32_t keep = b;
        mc_cdobc_out_t o;
        memset(&o, 0x5a, sizeof o);
        const mc_cdobc_out_t o0 = o;
        assert_false(mc_cdobc_step_core_f32(&b, bad[i][0], bad[i][1], bad[i][2], &o));
        assert_memory_equal(&o, &o0, sizeof o);
        assert_int_equal(b.w_sel, keep.w_sel);
        assert_memory_equal(b.w_buf[b.w_sel], keep.w_buf[keep.w_sel], sizeof b.w_buf[0]);
        assert_memory_equal(&b.pi_d, &keep.pi_d, sizeof b.pi_d);
        assert_true(b.nu_prev == keep.nu_prev && b.v_prev == keep.v_prev && b.v_cur == keep.v_cur);
    }
    /* a restart clears both halves */
    assert_int_equal(mc_cdobc_reset_f32(&b, 0.0f), MC_OK);
    for (uint32_t i = 0; i < MC_CDOBC_N_MAX; ++i) {
        assert_true(b.w_buf[0][i] == 0.0f && b.w_buf[1][i] == 0.0f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_loop_models_exact),
        cmocka_unit_test(test_internal_model_principle),
        cmocka_unit_test(test_float_vs_double),
        cmocka_unit_test(test_float_vs_double_cases),
        cmocka_unit_test(test_redesign_on_reference_change),
        cmocka_unit_test(test_saturation_fed_back),
        cmocka_unit_test(test_nonfinite_and_validation),
        cmocka_unit_test(test_coef_structure),
        cmocka_unit_test(test_observe_structured),
        cmocka_unit_test(test_step_core),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
