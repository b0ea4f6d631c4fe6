/*
 * Paper 000 regulator in closed loop with a double-precision model of the
 * paper's plant (2) in the rotor frame (v_d = 0 through the Park transform
 * with xi1 = n_p theta: the electrical and mechanical equations of the
 * Table 1 motor, two-phase torque n_p lambda_m i_q, RK4 with 10 substeps
 * per period, v_q held over the period), theta* = 1 rad from theta(0) = 0,
 * load 0.2 N m from t = 0, Ts = 50 us, encoder 2^20 counts/turn:
 * - float32 firmware vs a double reference implementation written here
 *   (implicit backward-Euler observer solved by elimination, internal
 *   model by its own matrix exponential): angles within 1e-6 rad;
 * - convergence below 1e-3 rad within 3 s;
 * - start-up: peak |v_q| with the matched start xi1_hat(0) = n_p
 *   (theta(0) - theta*) (<= 12 V) vs all-zero observer states (hundreds
 *   of kV), and both under the drive limit v_dc / sqrt(3), v_dc = 48 V;
 * - time-varying g3 (plant inertia 1/(1/j + 1e4 sin t)): observer told
 *   g3(t) vs the constant 1/j.
 * Measured numbers are printed ("# ...").
 */
#include "mc_test.h"

#include <stdbool.h>
#include <stdio.h>

#include "eeo_test_linalg.h"
#include "mc/eeo.h"

#define J_KGM2  5.5367e-5
#define NP      8.0
#define L_H     20e-3
#define R_OHM   7.2
#define B_NMS   0.006
#define LAM_WB  0.06
#define G3      (1.0 / J_KGM2)
#define BBAR    20.0
#define TS      50e-6
#define NSUB    10
#define CPR     1048576.0
#define RPC     (MC_TEST_TWO_PI / CPR)
#define THREF   1.0
#define TLOAD   0.2
#define T_END   3.0
#define VDC_LIM (48.0 / 1.7320508075688772)

/* ---- plant -------------------------------------------------------------- */

typedef struct {
    double id, iq, w, th;
} plant_t;

static double g3_of_t(double t, bool varying)
{
    return varying ? G3 + 1e4 * sin(t) : G3;
}

static void plant_f(const plant_t *x, double vq, double g3, plant_t *dx)
{
    const double we = NP * x->w;
    dx->id = (-R_OHM * x->id + L_H * we * x->iq) / L_H;
    dx->iq = (-R_OHM * x->iq - L_H * we * x->id - LAM_WB * we + vq) / L_H;
    dx->w = g3 * (-B_NMS * x->w + NP * LAM_WB * x->iq - TLOAD);
    dx->th = x->w;
}

static void plant_step(plant_t *x, double vq, double t, bool varying)
{
    const double h = TS / NSUB;
    for (int s = 0; s < NSUB; ++s) {
        const double ts = t + s * h;
        plant_t k1, k2, k3, k4, y;
        plant_f(x, vq, g3_of_t(ts, varying), &k1);
        y = (plant_t){ x->id + 0.5 * h * k1.id, x->iq + 0.5 * h * k1.iq, x->w + 0.5 * h * k1.w,
                       x->th + 0.5 * h * k1.th };
        plant_f(&y, vq, g3_of_t(ts + 0.5 * h, varying), &k2);
        y = (plant_t){ x->id + 0.5 * h * k2.id, x->iq + 0.5 * h * k2.iq, x->w + 0.5 * h * k2.w,
                       x->th + 0.5 * h * k2.th };
        plant_f(&y, vq, g3_of_t(ts + 0.5 * h, varying), &k3);
        y = (plant_t){ x->id + h * k3.id, x->iq + h * k3.iq, x->w + h * k3.w, x->th + h * k3.th };
        plant_f(&y, vq, g3_of_t(ts + h, varying), &k4);
        x->id += h / 6.0 * (k1.id + 2.0 * k2.id + 2.0 * k3.id + k4.id);
        x->iq += h / 6.0 * (k1.iq + 2.0 * k2.iq + 2.0 * k3.iq + k4.iq);
        x->w += h / 6.0 * (k1.w + 2.0 * k2.w + 2.0 * k3.w + k4.w);
        x->th += h / 6.0 * (k1.th + 2.0 * k2.th + 2.0 * k3.th + k4.th);
    }
}

static int32_t err_counts(const plant_t *x)
{
    const double pos = floor(x->th / RPC);
    const double ref = floor(THREF / RPC + 0.5);
    return (int32_t)(pos - ref);
}

/* ---- double reference controller ------------------------------------- */

typedef struct {
    double l[4], Phi[9], Gd[3], x[4], eta[3], u_prev, vmax;
} ref_t;

static void ref_init(ref_t *r, double vmax, bool matched, int32_t e0)
{
    const double g3min = G3 - 1e4, g3max = G3 + 1e4;
    const double b1 = 2.0 / g3min;
    const double b2 = (sqrt(2.0) + 3.0 * b1 * g3max) / NP;
    const double b3 = g3max * sqrt(3.0) + 4.0 * b2 * b1 * NP;
    r->l[0] = 1e3 * b3;
    r->l[1] = 1e6 * b3 * b2;
    r->l[2] = 1e9 * b3 * b2 * b1;
    r->l[3] = 1e12 * b3 * b2 * b1;
    double Y[16] = { 0 }, eY[16];
    Y[0 * 4 + 1] = TS;
    Y[1 * 4 + 2] = TS;
    Y[2 * 4 + 1] = -TS;
    Y[2 * 4 + 3] = TS;
    la_expm(4, Y, eY);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r->Phi[i * 3 + j] = eY[i * 4 + j];
        }
        r->Gd[i] = eY[i * 4 + 3];
        r->eta[i] = 0.0;
    }
    for (int i = 0; i < 4; ++i) {
        r->x[i] = 0.0;
    }
    r->x[0] = matched ? NP * RPC * (double)e0 : 0.0;
    r->u_prev = 0.0;
    r->vmax = vmax;
}

static double ref_step(ref_t *r, int32_t e, double g3)
{
    const double h = TS;
    const double y = NP * RPC * (double)e;
    double M[16] = { 1, -h * NP, 0, 0, 0, 1, -h * g3, 0, 0, 0, 1, -h, 0, 0, 0, 1 };
    double rhs[4];
    for (int i = 0; i < 4; ++i) {
        M[i * 4] += h * r->l[i];
        rhs[i] = r->x[i] + h * r->l[i] * y;
    }
    rhs[2] += h * r->u_prev;
    assert_int_equal(la_solve(4, M, 1, rhs, r->x), 0);
    double ubar = (-r->x[3] - r->x[0] - 3.0 * r->x[1] - 3.0 * r->x[2]) / BBAR;
    ubar = fmax(-1e7, fmin(1e7, ubar));
    const double ge = r->eta[0] + 2.0 * r->eta[1] + 3.0 * r->eta[2];
    const double v = fmax(-r->vmax, fmin(r->vmax, ge + ubar));
    const double uapp = v - ge;
    double en[3];
    for (int i = 0; i < 3; ++i) {
        en[i] = r->Phi[i * 3] * r->eta[0] + r->Phi[i * 3 + 1] * r->eta[1] +
                r->Phi[i * 3 + 2] * r->eta[2] + r->Gd[i] * uapp;
    }
    for (int i = 0; i < 3; ++i) {
        r->eta[i] = en[i];
    }
    r->u_prev = BBAR * uapp;
    return v;
}

/* ---- runs --------------------------------------------------------------- */

typedef struct {
    bool matched, plant_g3_varying, obs_knows_g3, with_ref;
    double vmax;
} run_cfg_t;

typedef struct {
    double max_diff_rad; /* float vs double loop */
    double t_settle_s;   /* last time |theta - theta*| >= 1e-3 */
    double peak_v;       /* float loop */
    double max_err_late; /* max |theta - theta*| over the last second */
    int n_limited;
} run_res_t;

static run_res_t run(const run_cfg_t *cfg)
{
    mc_eeo_params_t p;
    mc_eeo_params_paper000(&p, (float)TS, 8u, (float)J_KGM2, (float)RPC);
    p.v_q_max_V = (float)cfg->vmax;
    mc_eeo_f32_t c;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_OK);
    plant_t pf = { 0 }, pd = { 0 };
    const int32_t e0 = err_counts(&pf);
    assert_int_equal(mc_eeo_reset_f32(&c, e0, cfg->matched), MC_OK);
    ref_t r;
    ref_init(&r, cfg->vmax, cfg->matched, e0);
    run_res_t res = { 0 };
    const int n = (int)(T_END / TS + 0.5);
    for (int k = 0; k < n; ++k) {
        const double t = k * TS;
        const double g3 = cfg->obs_knows_g3 ? g3_of_t(t, cfg->plant_g3_varying) : G3;
        if (cfg->obs_knows_g3) {
            assert_int_equal(mc_eeo_set_g3_f32(&c, (float)g3), MC_OK);
        }
        mc_eeo_out_t o;
        assert_int_equal(mc_eeo_step_f32(&c, err_counts(&pf), &o), MC_OK);
        res.peak_v = fmax(res.peak_v, fabs((double)o.v_q_V));
        res.n_limited += o.v_limited ? 1 : 0;
        plant_step(&pf, (double)o.v_q_V, t, cfg->plant_g3_varying);
        if (cfg->with_ref) {
            const double vd = ref_step(&r, err_counts(&pd), g3);
            plant_step(&pd, vd, t, cfg->plant_g3_varying);
            res.max_diff_rad = fmax(res.max_diff_rad, fabs(pf.th - pd.th));
        }
        const double err = fabs(pf.th - THREF);
        if (err >= 1e-3 || !isfinite(err)) {
            res.t_settle_s = t + TS;
        }
        if (t + TS > T_END - 1.0) {
            res.max_err_late = fmax(res.max_err_late, err);
        }
    }
    return res;
}

static void test_float_vs_double_and_convergence(void **state)
{
    (void)state;
    const run_cfg_t cfg = { .matched = true, .with_ref = true, .vmax = VDC_LIM };
    const run_res_t r = run(&cfg);
    printf("# matched start, 48 V bus: max |theta_f32 - theta_f64| = %.3g rad, "
           "|theta - theta*| < 1e-3 rad from t = %.4f s, peak |v_q| = %.4g V, "
           "max error over the last second %.3g rad\n",
           r.max_diff_rad, r.t_settle_s, r.peak_v, r.max_err_late);
    assert_true(r.max_diff_rad <= 1e-6);
    assert_true(r.t_settle_s < 3.0);
}

static void test_startup_peaking(void **state)
{
    (void)state;
    const run_cfg_t m_unl = { .matched = true, .vmax = 1e9 };
    const run_cfg_t z_unl = { .matched = false, .vmax = 1e9 };
    const run_cfg_t z_lim = { .matched = false, .vmax = VDC_LIM };
    const run_res_t a = run(&m_unl), b = run(&z_unl), d = run(&z_lim);
    printf("# no voltage limit: peak |v_q| matched start %.4g V (settled %.4f s), "
           "all-zero start %.4g V (settled %.4f s)\n",
           a.peak_v, a.t_settle_s, b.peak_v, b.t_settle_s);
    printf("# limit %.2f V (48 V bus): all-zero start peak %.4g V, clamped in %d periods, "
           "settled %.4f s, late error %.3g rad\n",
           VDC_LIM, d.peak_v, d.n_limited, d.t_settle_s, d.max_err_late);
    assert_true(a.peak_v <= 12.0);
    assert_true(b.peak_v > 1e4);
    assert_true(d.peak_v <= VDC_LIM + 1e-3);
}

static void test_time_varying_g3(void **state)
{
    (void)state;
    const run_cfg_t known = {
        .matched = true, .plant_g3_varying = true, .obs_knows_g3 = true, .vmax = VDC_LIM
    };
    const run_cfg_t fixed = {
        .matched = true, .plant_g3_varying = true, .obs_knows_g3 = false, .vmax = VDC_LIM
    };
    const run_res_t a = run(&known), b = run(&fixed);
    printf("# g3(t) = 1/j + 1e4 sin t: observer with g3(t): settled %.4f s, late error %.3g "
           "rad, peak %.4g V; observer with 1/j: settled %.4f s, late error %.3g rad, "
           "peak %.4g V\n",
           a.t_settle_s, a.max_err_late, a.peak_v, b.t_settle_s, b.max_err_late, b.peak_v);
    assert_true(a.max_err_late < 1e-2);
    assert_true(b.max_err_late < 1e-2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_vs_double_and_convergence),
        cmocka_unit_test(test_startup_peaking),
        cmocka_unit_test(test_time_varying_g3),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
