/*
 * Paper 000 regulator, design (mc/eeo.h):
 * - the Appendix A recursion against the explicit Section 6 formulas for
 *   b1..b3, written out here independently (1e-9 relative), and the
 *   printed a = (33.61, 33.61, 135483, 48604) to their printed precision
 *   (Table 1 motor, j = 5.5367e-5 kg m^2, g3 = 1/j +- 1e4);
 * - Gamma placement: the characteristic polynomial of F + G Gamma,
 *   computed by Faddeev-LeVerrier (eeo_test_linalg.h), is the requested one; its
 *   eigenvalues are the requested roots;
 * - the internal model's ZOH against an independent matrix exponential;
 * - input validation, non-finite handling, the integer position helpers;
 * - the ISR's inline cores against the checked API, bit for bit.
 */
#include "mc_test.h"

#include <stdio.h>
#include <string.h>

#include "eeo_test_linalg.h"
#include "mc/eeo.h"

#define J_KGM2  5.5367e-5 /* Table 1: 0.55367 kg cm^2 */
#define NP      8u
#define TS_S    50e-6
#define RAD_CNT (MC_TEST_TWO_PI / 1048576.0)
#define G3_NOM  (1.0 / J_KGM2)
#define G3_MIN  (G3_NOM - 1e4)
#define G3_MAX  (G3_NOM + 1e4)

/* Section 6, typed out: b1, b2, b3 with L_k = 1, g1min = g4max = 1 */
static void section6_a(double g3min, double g3max, double np, double a[4])
{
    const double L1 = 1.0, L2 = 1.0, L3 = 1.0, g1min = 1.0, g4max = 1.0;
    const double g2min = np, g2max = np;
    const double b0 = 1.0;
    const double b1 = (L1 * b0 * g4max + b0 * g4max) / g3min;
    const double b2 = (L2 * (g4max * sqrt(2.0) + 2.0 * b1 * b0 * g3max) + b1 * b0 * g3max) / g2min;
    const double b3 =
        (L3 * (g3max * sqrt(3.0) + 3.0 * b2 * b1 * b0 * g2max) + b2 * b1 * b0 * g2max) / g1min;
    a[0] = b3 * b2 * b1 * b0;
    a[1] = b3 * b2 * b1;
    a[2] = b3 * b2;
    a[3] = b3;
}

static void test_recursion_matches_section6(void **state)
{
    (void)state;
    const double g_min[4] = { 1.0, NP, G3_MIN, 0.0 };
    const double g_max[4] = { 0.0, NP, G3_MAX, 1.0 };
    const double L[3] = { 1.0, 1.0, 1.0 };
    double a[4], b[4], ref[4];
    assert_int_equal(mc_eeo_gain_recursion(4u, g_min, g_max, L, a, b), MC_OK);
    section6_a(G3_MIN, G3_MAX, NP, ref);
    for (int i = 0; i < 4; ++i) {
        assert_near(a[i] / ref[i], 1.0, 1e-9);
    }
    /* g3min = 8061.3, g3max = 28061.3 with j in kg m^2 */
    assert_near(G3_MIN, 8061.3, 0.05);
    assert_near(G3_MAX, 28061.3, 0.05);
    /* printed values to one unit of their last printed digit (a2 comes
     * out as 135483.50: printed 135483, truncated) */
    assert_near(a[0], 33.61, 0.01);
    assert_near(a[1], 33.61, 0.01);
    assert_near(a[2], 135483.0, 1.0);
    assert_near(a[3], 48604.0, 1.0);
    assert_near(b[0], 1.0, 0.0);
    printf("# a = (%.6f, %.6f, %.3f, %.3f), b = (1, %.6e, %.6f, %.3f)\n", a[0], a[1], a[2], a[3],
           b[1], b[2], b[3]);

    /* n = 2: b1 = (L1 g2max + g2max) / g1min */
    const double gm2[2] = { 2.0, 0.0 }, gx2[2] = { 0.0, 5.0 }, L2[1] = { 3.0 };
    double a2[2];
    assert_int_equal(mc_eeo_gain_recursion(2u, gm2, gx2, L2, a2, NULL), MC_OK);
    assert_near(a2[1], (3.0 * 5.0 + 5.0) / 2.0, 1e-12);
    assert_near(a2[0], a2[1], 1e-12);

    /* validation */
    double bad_min[4] = { 1.0, NP, -1.0, 0.0 };
    double out[4] = { -7.0, -7.0, -7.0, -7.0 };
    assert_int_equal(mc_eeo_gain_recursion(4u, bad_min, g_max, L, out, NULL), MC_ERR_PARAM);
    bad_min[2] = NAN;
    assert_int_equal(mc_eeo_gain_recursion(4u, bad_min, g_max, L, out, NULL), MC_ERR_NONFINITE);
    assert_int_equal(mc_eeo_gain_recursion(1u, g_min, g_max, L, out, NULL), MC_ERR_PARAM);
    assert_near(out[0], -7.0, 0.0);
}

/* The Section 6 instance on the Table 1 motor with the drive limit
 * v_q_max_V. */
static void init_instance(mc_eeo_f32_t *c, float v_q_max_V)
{
    mc_eeo_params_t p;
    mc_eeo_params_paper000(&p, (float)TS_S, NP, (float)J_KGM2, (float)RAD_CNT);
    p.v_q_max_V = v_q_max_V;
    assert_int_equal(mc_eeo_init_f32(c, &p), MC_OK);
}

static void test_instance_gains(void **state)
{
    (void)state;
    mc_eeo_f32_t c;
    init_instance(&c, 1e9f);
    double a[4];
    section6_a(G3_MIN, G3_MAX, NP, a);
    const double k = 1e3;
    assert_near(c.l[0] / (k * a[3]), 1.0, 1e-6);
    assert_near(c.l[1] / (k * k * a[2]), 1.0, 1e-6);
    assert_near(c.l[2] / (k * k * k * a[1]), 1.0, 1e-6);
    assert_near(c.l[3] / (k * k * k * k * a[0]), 1.0, 1e-6);
    assert_near(c.gamma[0], 1.0, 0.0);
    assert_near(c.gamma[1], 2.0, 0.0);
    assert_near(c.gamma[2], 3.0, 0.0);
}

static void companion(int n, const double *coef, double *m)
{
    for (int i = 0; i < n * n; ++i) {
        m[i] = 0.0;
    }
    for (int i = 0; i + 1 < n; ++i) {
        m[i * n + i + 1] = 1.0;
    }
    for (int j = 0; j < n; ++j) {
        m[(n - 1) * n + j] = -coef[j];
    }
}

static void check_placement(int n, const double *f, const double *s)
{
    double gam[MC_EEO_NW_MAX];
    assert_int_equal(mc_eeo_gamma_place((uint32_t)n, f, s, gam), MC_OK);
    /* F (companion of f) + G Gamma, G = e_n */
    double Phi[LA_NMAX * LA_NMAX], c[LA_NMAX];
    companion(n, f, Phi);
    for (int j = 0; j < n; ++j) {
        Phi[(n - 1) * n + j] += gam[j];
    }
    la_charpoly(n, Phi, c);
    for (int i = 0; i < n; ++i) {
        assert_near(c[i], s[i], 1e-12 * (1.0 + fabs(s[i])));
    }
}

static void test_gamma_placement(void **state)
{
    (void)state;
    /* paper: F = (s+1)^3, S: s (s^2 + 1) -> Gamma = (1 2 3) */
    const double f3[3] = { 1.0, 3.0, 3.0 }, s3[3] = { 0.0, 1.0, 0.0 };
    double gam[3];
    assert_int_equal(mc_eeo_gamma_place(3u, f3, s3, gam), MC_OK);
    assert_near(gam[0], 1.0, 0.0);
    assert_near(gam[1], 2.0, 0.0);
    assert_near(gam[2], 3.0, 0.0);
    check_placement(3, f3, s3);
    /* the eigenvalues of F + G Gamma are {0, +j, -j} */
    double Phi[9], wr[3], wi[3];
    companion(3, f3, Phi);
    for (int j = 0; j < 3; ++j) {
        Phi[6 + j] += gam[j];
    }
    assert_int_equal(la_eig(3, Phi, wr, wi), 0);
    int n0 = 0, npj = 0, nmj = 0;
    for (int i = 0; i < 3; ++i) {
        n0 += (hypot(wr[i], wi[i]) < 1e-9);
        npj += (hypot(wr[i], wi[i] - 1.0) < 1e-9);
        nmj += (hypot(wr[i], wi[i] + 1.0) < 1e-9);
    }
    assert_int_equal(n0 + npj + nmj, 3);
    assert_int_equal(n0 * npj * nmj, 1);
    /* two sinusoids (2 and 3 rad/s) with F = (s+2)^4 */
    const double f4[4] = { 16.0, 32.0, 24.0, 8.0 }, s4[4] = { 36.0, 0.0, 13.0, 0.0 };
    check_placement(4, f4, s4);
    /* bias, ramp, parabola + sinusoid at 50 rad/s: s^3 (s^2 + 2500);
     * F = (s+10)^4 (s+5) */
    const double f5[5] = { 50000.0, 30000.0, 7000.0, 800.0, 45.0 };
    const double s5[5] = { 0.0, 0.0, 0.0, 2500.0, 0.0 };
    check_placement(5, f5, s5);
    /* F not Hurwitz: rejected */
    const double fbad[3] = { 1.0, 0.1, 3.0 }; /* 3 * 0.1 < 1 */
    assert_int_equal(mc_eeo_gamma_place(3u, fbad, s3, gam), MC_ERR_PARAM);
    assert_false(mc_eeo_poly_is_hurwitz(2u, (const double[]){ 1.0, 0.0 }));
    assert_true(mc_eeo_poly_is_hurwitz(1u, (const double[]){ 0.5 }));
}

static void test_internal_model_zoh(void **state)
{
    (void)state;
    const double s3[3] = { 0.0, 1.0, 0.0 };
    const double hs[3] = { 10e-6, 50e-6, 5e-3 };
    for (int t = 0; t < 3; ++t) {
        double D[9], E[3];
        assert_int_equal(mc_eeo_companion_zoh(3u, s3, hs[t], D, E), MC_OK);
        /* augmented [S e3; 0 0] h, exponential here */
        double X[16] = { 0.0 }, eX[16];
        X[0 * 4 + 1] = hs[t];
        X[1 * 4 + 2] = hs[t];
        X[2 * 4 + 1] = -1.0 * hs[t];
        X[2 * 4 + 3] = hs[t];
        la_expm(4, X, eX);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_near(D[i * 3 + j], eX[i * 4 + j] - (i == j ? 1.0 : 0.0), 1e-15);
            }
            assert_near(E[i] / eX[i * 4 + 3], 1.0, 1e-10);
        }
        /* the bias mode stays exactly at 1: D e1 = 0 */
        assert_near(D[0] + D[3] + D[6], 0.0, 0.0);
    }
}

static void test_validation(void **state)
{
    (void)state;
    mc_eeo_params_t p0;
    mc_eeo_params_paper000(&p0, (float)TS_S, NP, (float)J_KGM2, (float)RAD_CNT);
    p0.v_q_max_V = 27.7f;
    mc_eeo_f32_t c;
    memset(&c, 0x5a, sizeof c);
    const mc_eeo_f32_t before = c;
    mc_eeo_params_t p = p0;
    p.Ts_s = NAN;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_NONFINITE);
    p = p0;
    p.f_coef[1] = INFINITY;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_NONFINITE);
    p = p0;
    p.Ts_s = 0.0f;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.g3_per_kgm2 = (float)G3_MAX * 1.01f;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.K[0] = 1.0f; /* chain polynomial not Hurwitz */
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.v_q_max_V = 0.0f;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.b_bar_Nm_per_Vs = 0.0f;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.n_w = MC_EEO_NW_MAX + 1u;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.f_coef[0] = 20.0f; /* (s^3 + 3 s^2 + 3 s + 20): 9 < 20 */
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.input_delay_steps = 2u;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    p = p0;
    p.pole_pairs = 0u;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_ERR_PARAM);
    assert_memory_equal(&c, &before, sizeof c);
    /* n_w = 0: no internal model, accepted */
    p = p0;
    p.n_w = 0u;
    assert_int_equal(mc_eeo_init_f32(&c, &p), MC_OK);

    assert_int_equal(mc_eeo_init_f32(&c, &p0), MC_OK);
    assert_int_equal(mc_eeo_set_g3_f32(&c, NAN), MC_ERR_NONFINITE);
    assert_int_equal(mc_eeo_set_g3_f32(&c, (float)G3_MIN * 0.9f), MC_ERR_RANGE);
    const float m0 = c.m[3];
    assert_int_equal(mc_eeo_set_g3_f32(&c, (float)G3_NOM), MC_OK);
    assert_near(c.m[3], m0, 1e-6 * m0);
    /* m from set_g3 (float) vs design (double) at g3max */
    assert_int_equal(mc_eeo_set_g3_f32(&c, (float)G3_MAX), MC_OK);
    double m[4];
    const double l[4] = { c.l[0], c.l[1], c.l[2], c.l[3] };
    assert_int_equal(mc_eeo_be_gains(TS_S, NP, (double)(float)G3_MAX, l, m), MC_OK);
    for (int i = 0; i < 4; ++i) {
        assert_near(c.m[i] / m[i], 1.0, 1e-6);
    }

    /* non-finite state: status, state and output untouched */
    assert_int_equal(mc_eeo_reset_f32(&c, 1000, true), MC_OK);
    c.x[3] = NAN;
    mc_eeo_out_t out = { .v_q_V = 123.0f };
    assert_int_equal(mc_eeo_step_f32(&c, 1000, &out), MC_ERR_NONFINITE);
    assert_near(out.v_q_V, 123.0, 0.0);
    assert_true(isnan(c.x[3]));
}

static void test_integer_position(void **state)
{
    (void)state;
    mc_eeo_counts_t cnt;
    const uint32_t cpr = 1u << 20;
    assert_int_equal(mc_eeo_counts_init(&cnt, cpr, cpr - 10u), MC_OK);
    /* 1000 turns forward in steps of cpr/8 + 3, then back */
    for (int i = 0; i < 8000; ++i) {
        const uint32_t raw = (uint32_t)(((uint64_t)cnt.last_raw + cpr / 8u + 3u) % cpr);
        assert_int_equal(mc_eeo_counts_update(&cnt, raw), MC_OK);
    }
    const int64_t expect = (int64_t)(cpr - 10u) + 8000 * (int64_t)(cpr / 8u + 3u);
    assert_true(cnt.pos_counts == expect);
    /* the error against a reference 1000 turns away is exact in int */
    int32_t err;
    const int64_t ref = expect - 5;
    assert_int_equal(mc_eeo_count_error(cnt.pos_counts, ref, &err), MC_OK);
    assert_int_equal(err, 5);
    /* float32 of the position itself: 1e9 counts -> steps of 64 counts */
    const float pos_f = (float)cnt.pos_counts;
    assert_true(fabs((double)pos_f - (double)cnt.pos_counts) > 1.0);
    assert_int_equal(mc_eeo_count_error(INT64_MAX, -1, &err), MC_ERR_RANGE);
    assert_int_equal(err, INT32_MAX);
    assert_int_equal(mc_eeo_count_error(0, (int64_t)INT32_MAX + 10, &err), MC_ERR_RANGE);
    assert_int_equal(err, INT32_MIN);
    assert_int_equal(mc_eeo_counts_update(&cnt, cpr), MC_ERR_RANGE);
    assert_int_equal(mc_eeo_counts_init(&cnt, 2u, 0u), MC_ERR_PARAM);
}

/* The ISR's pieces (mc/eeo.h): the step core is the checked step and
 * leaves the state when it fails; the g3 core's guard; the internal
 * model's update unrolled for the drive's order 3 against the loop, bit
 * for bit. */
static void test_isr_cores(void **state)
{
    (void)state;
    mc_eeo_f32_t a;
    init_instance(&a, 27.7f);
    assert_int_equal(mc_eeo_reset_f32(&a, 3000, true), MC_OK);
    mc_eeo_f32_t b = a;
    for (int k = 0; k < 2000; ++k) {
        const int32_t err = 3000 - 2 * k;
        const float g3 = (float)(G3_NOM + 5e3 * sin(1e-2 * k));
        assert_int_equal(mc_eeo_set_g3_f32(&a, g3), MC_OK);
        assert_true(mc_eeo_set_g3_core_f32(&b, g3));
        mc_eeo_out_t oa, ob;
        assert_int_equal(mc_eeo_step_f32(&a, err, &oa), MC_OK);
        assert_true(mc_eeo_step_core_f32(&b, err, &ob));
        assert_memory_equal(&oa.v_q_V, &ob.v_q_V, sizeof oa.v_q_V);
        assert_memory_equal(&oa.u_bar_V, &ob.u_bar_V, sizeof oa.u_bar_V);
        assert_int_equal(oa.sat_N, ob.sat_N);
        assert_int_equal(oa.v_limited, ob.v_limited);
        assert_memory_equal(&a, &b, sizeof a);
    }
    /* g3 core: a NaN fails the division's guard, nothing changes */
    mc_eeo_f32_t keep = b;
    assert_false(mc_eeo_set_g3_core_f32(&b, NAN));
    assert_memory_equal(&b, &keep, sizeof b);
    /* step core: a non-finite state is reported, the state in use and
     * *out stay */
    b.x[2] = INFINITY;
    keep = b;
    mc_eeo_out_t o;
    memset(&o, 0x5a, sizeof o);
    mc_eeo_out_t o0 = o;
    assert_false(mc_eeo_step_core_f32(&b, 10, &o));
    assert_memory_equal(&o, &o0, sizeof o);
    assert_memory_equal(b.x, keep.x, sizeof b.x);
    assert_int_equal(b.im_sel, keep.im_sel);
    assert_memory_equal(b.eta[b.im_sel], keep.eta[keep.im_sel], sizeof b.eta[0]);
    assert_memory_equal(b.eta_c[b.im_sel], keep.eta_c[keep.im_sel], sizeof b.eta_c[0]);
    assert_memory_equal(b.u_hist, keep.u_hist, sizeof b.u_hist);
    assert_true(b.r1 == keep.r1 && b.last_err_counts == keep.last_err_counts);
    /* order 3 unrolled (a constant) and as the loop (a run-time value) */
    volatile uint32_t n_run = 3u;
    mc_eeo_f32_t c = a, d = a;
    for (uint32_t i = 0; i < 3u; ++i) {
        c.eta[c.im_sel][i] = (float)(0.3 * i - 0.4);
        c.eta_c[c.im_sel][i] = (float)(1e-8 * i);
    }
    d = c;
    const float gc = mc_eeo_gamma_eta_f32(&c, 3u);
    const float gd = mc_eeo_gamma_eta_f32(&d, n_run);
    assert_memory_equal(&gc, &gd, sizeof gc);
    const float ac = mc_eeo_im_step_f32(&c, 0.7f, 3u);
    const float ad = mc_eeo_im_step_f32(&d, 0.7f, n_run);
    assert_true(ac == 0.0f && ad == 0.0f);
    assert_memory_equal(&c, &d, sizeof c);
    /* a restart clears both halves */
    assert_int_equal(mc_eeo_reset_f32(&c, 0, true), MC_OK);
    for (uint32_t i = 0; i < MC_EEO_NW_MAX; ++i) {
        assert_true(c.eta[0][i] == 0.0f && c.eta[1][i] == 0.0f);
        assert_true(c.eta_c[0][i] == 0.0f && c.eta_c[1][i] == 0.0f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_recursion_matches_section6),
        cmocka_unit_test(test_instance_gains),
        cmocka_unit_test(test_gamma_placement),
        cmocka_unit_test(test_internal_model_zoh),
        cmocka_unit_test(test_validation),
        cmocka_unit_test(test_integer_position),
        cmocka_unit_test(test_isr_cores),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
