/*
 * Reference prefilter of the paper 002 regulator (mc_cdobc_prefilter_f32_t,
 * mc/cdobc.h):
 * - against a double direct form of F(z) = g (z - a)^2 / (z - a_m)^2
 *   written here from the poles (steps, ramps and a sine of omega*); a
 *   step's first output is g times the step; a constant omega* comes out
 *   exactly;
 * - in the loop with the double model of the Section IV motor
 *   (cdobc_test_plant.h, no disturbance): the regulator designed with its
 *   poles at -200 behind the prefilter to -230 answers a reference step
 *   as the regulator designed with its poles at -230 (state feedback does
 *   not move the plant's zeros, and the observer does not see omega*),
 *   and not as the plain -200 design;
 * - parameter validation.
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cdobc_test_plant.h"
#include "mc/cdobc.h"

#define RPM    MC_TEST_RAD_S_PER_RPM
#define RPM500 (500.0 * RPM)
#define SUB    8 /* RK4 substeps per period */

/* double F(z) = g (z - a)^2 / (z - a_m)^2 at rest at x0 */
typedef struct {
    double g, a, a_m;
    double x1, x2, y1, y2;
} dref_t;

static void dref_init(dref_t *r, double Ts, double p_ctl, double p_ref, double x0)
{
    r->a = exp(-p_ctl * Ts);
    r->a_m = exp(-p_ref * Ts);
    r->g = pow((1.0 - r->a_m) / (1.0 - r->a), 2.0);
    r->x1 = r->x2 = r->y1 = r->y2 = x0;
}

static double dref_step(dref_t *r, double x)
{
    const double y = r->g * (x - 2.0 * r->a * r->x1 + r->a * r->a * r->x2) + 2.0 * r->a_m * r->y1 -
                     r->a_m * r->a_m * r->y2;
    r->x2 = r->x1;
    r->x1 = x;
    r->y2 = r->y1;
    r->y1 = y;
    return y;
}

static void test_prefilter_against_double(void **state)
{
    (void)state;
    const float Ts = (float)P2_TS;
    mc_cdobc_prefilter_f32_t f;
    assert_int_equal(mc_cdobc_prefilter_init_f32(&f, Ts, 200.0f, 230.0f), MC_OK);
    mc_cdobc_prefilter_reset_f32(&f, 0.0f);
    dref_t r;
    dref_init(&r, (double)Ts, 200.0, 230.0, 0.0);
    /* a step's first output: g times the step (1.32 for -230 / -200) */
    const float y0 = mc_cdobc_prefilter_step_f32(&f, (float)RPM500);
    const double y0_d = dref_step(&r, (double)(float)RPM500);
    assert_true(fabs(y0_d / RPM500 - pow(230.0 / 200.0, 2.0)) < 0.01);
    double worst = fabs((double)y0 - y0_d);
    /* steps, a ramp and a sine, 0.3 s */
    for (int k = 1; k < 3000; ++k) {
        const double t = k * (double)Ts;
        double x = RPM500;
        if (t >= 0.1) {
            x = -200.0 * RPM + 2000.0 * RPM * (t - 0.1); /* ramp */
        }
        if (t >= 0.2) {
            x = 300.0 * RPM * sin(2.0 * 3.14159265358979 * 20.0 * t);
        }
        const float xf = (float)x;
        const float y = mc_cdobc_prefilter_step_f32(&f, xf);
        worst = fmax(worst, fabs((double)y - dref_step(&r, (double)xf)));
    }
    printf("prefilter against double: worst %.3g rad/s (step %.4g rad/s)\n", worst, RPM500);
    /* float32 states of a filter with poles at 0.977: a few hundred
     * roundings of the 52 rad/s signal (ulp 3.8e-6) */
    assert_true(worst < 2e-3);

    /* constant omega*: d decays to exactly 0, omega*_f = omega* */
    const float c = 123.456f;
    float y = 0.0f;
    for (int k = 0; k < 20000; ++k) {
        y = mc_cdobc_prefilter_step_f32(&f, c);
    }
    assert_memory_equal(&y, &c, sizeof y);
}

/* The p2 plant at rest, a 0 -> 500 rpm step at k = 0, 0.1 s; the speed
 * trajectory into w_out[steps]. ctl_pole of the design, ref_pole of the
 * prefilter (0: none). */
static void run_step(float ctl_pole, float ref_pole, double *w_out, int steps)
{
    mc_cdobc_params_t p;
    mc_cdobc_params_paper002(&p, (float)P2_TS, MC_CDOBC_KIND_CDOBC);
    p.ctl_pole_rad_s = ctl_pole;
    mc_cdobc_f32_t c;
    assert_int_equal(mc_cdobc_init_f32(&c, &p, (float)RPM500), MC_OK);
    assert_int_equal(mc_cdobc_reset_f32(&c, 0.0f), MC_OK);
    mc_cdobc_prefilter_f32_t f;
    if (ref_pole > 0.0f) {
        assert_int_equal(mc_cdobc_prefilter_init_f32(&f, (float)P2_TS, ctl_pole, ref_pole), MC_OK);
        mc_cdobc_prefilter_reset_f32(&f, 0.0f);
    }
    p2_plant_t pl = { 0 };
    const p2_dist_t ds = { .fJ = 1, .fR = 1, .fL = 1, .fK = 1 };
    double v_app = 0.0;
    for (int k = 0; k < steps; ++k) {
        const float ref =
            (ref_pole > 0.0f) ? mc_cdobc_prefilter_step_f32(&f, (float)RPM500) : (float)RPM500;
        mc_cdobc_out_t o;
        assert_int_equal(mc_cdobc_step_f32(&c, (float)pl.omega, ref, 0.0f, &o), MC_OK);
        assert_false(o.q_limited);
        p2_plant_step(&pl, &ds, v_app, P2_TS, SUB);
        v_app = (double)o.v_q_V;
        w_out[k] = pl.omega;
    }
}

/* first k after which |w - 500 rpm| stays within 2 % */
static int settle_index(const double *w, int steps)
{
    int last_out = -1;
    for (int k = 0; k < steps; ++k) {
        if (fabs(w[k] - RPM500) > 0.02 * RPM500) {
            last_out = k;
        }
    }
    return last_out + 1;
}

static void test_prefilter_replaces_reference_poles(void **state)
{
    (void)state;
    enum { STEPS = 1000 };
    static double w_pf[STEPS], w_230[STEPS], w_200[STEPS];
    run_step(200.0f, 230.0f, w_pf, STEPS);
    run_step(230.0f, 0.0f, w_230, STEPS);
    run_step(200.0f, 0.0f, w_200, STEPS);
    double d_230 = 0.0, d_200 = 0.0;
    for (int k = 0; k < STEPS; ++k) {
        d_230 = fmax(d_230, fabs(w_pf[k] - w_230[k]));
        d_200 = fmax(d_200, fabs(w_pf[k] - w_200[k]));
    }
    const int s_pf = settle_index(w_pf, STEPS), s_230 = settle_index(w_230, STEPS),
              s_200 = settle_index(w_200, STEPS);
    printf("step 0 -> 500 rpm: -200 + prefilter -230 vs the -230 design: %.3g rad/s, vs the "
           "-200 design: %.3g rad/s; settling (2 %%) %d / %d / %d periods\n",
           d_230, d_200, s_pf, s_230, s_200);
    /* float32 regulators and prefilter on a 52 rad/s step: 0.01 rpm */
    assert_true(d_230 < 0.01 * RPM);
    assert_true(d_200 > 100.0 * 0.01 * RPM);
    assert_int_equal(s_pf, s_230);
    assert_true(s_pf < s_200);
}

static void test_prefilter_validation(void **state)
{
    (void)state;
    mc_cdobc_prefilter_f32_t f;
    memset(&f, 0x5a, sizeof f);
    const mc_cdobc_prefilter_f32_t keep = f;
    assert_int_equal(mc_cdobc_prefilter_init_f32(&f, NAN, 200.0f, 230.0f), MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_prefilter_init_f32(&f, 1e-4f, INFINITY, 230.0f), MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_prefilter_init_f32(&f, 1e-4f, 200.0f, NAN), MC_ERR_NONFINITE);
    const float bad[][3] = {
        { 0.0f, 200.0f, 230.0f },   { -1e-4f, 200.0f, 230.0f }, { 1e-4f, 0.0f, 230.0f },
        { 1e-4f, 200.0f, -230.0f }, { 1e-4f, 2e4f, 230.0f },    { 1e-4f, 200.0f, 1.1e4f },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(mc_cdobc_prefilter_init_f32(&f, bad[i][0], bad[i][1], bad[i][2]),
                         MC_ERR_PARAM);
    }
    assert_memory_equal(&f, &keep, sizeof f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_prefilter_against_double),
        cmocka_unit_test(test_prefilter_replaces_reference_poles),
        cmocka_unit_test(test_prefilter_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
