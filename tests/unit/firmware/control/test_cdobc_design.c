/*
 * Paper 002 regulator, design (mc/cdobc.h), checked against independent
 * double computations (eeo_test_linalg.h, cdobc_test_plant.h):
 * - the exact ZOH of the (nu, w) model against la_expm, for several model
 *   sets (CDOBC, GPIOBC, HDOBC, CDOBC + 1st/2nd electrical, the largest);
 * - observer poles: the characteristic polynomial of Ad - Ld c (delta form,
 *   diagonally scaled here, Faddeev-LeVerrier) equals the requested one,
 *   and the simple (harmonic) poles of ROBUST are found by la_eig;
 * - controller poles: trace and determinant of the (nu, x2) closed loop;
 * - nominal closed loop (plant ZOH, delay, observer, control): spectral
 *   radius by la_eig = the slowest requested pole (separation) and the
 *   firmware's Gelfand estimate;
 * - Ackermann and the solver on a hand example; input validation.
 */
#include "mc_test.h"

#include <stdio.h>

#include "cdobc_test_plant.h"
#include "mc/cdobc.h"

#define RPM500 (500.0 * MC_TEST_RAD_S_PER_RPM)

/* test-side view of a firmware model list */
static p2_models_t to_test(const mc_cdobc_models_t *m)
{
    p2_models_t t = { .n_harm = (int)m->n_harm, .N = (int)m->poly_order };
    for (uint32_t i = 0; i < m->n_harm; ++i) {
        t.mult[i] = (double)m->harm[i].order * (m->harm[i].axis == MC_CDOBC_ELEC ? P2_NP : 1.0);
    }
    return t;
}

static void set_models(mc_cdobc_params_t *p, int case_id)
{
    mc_cdobc_kind_t kind = MC_CDOBC_KIND_CDOBC;
    if (case_id == 1) {
        kind = MC_CDOBC_KIND_GPIOBC;
    } else if (case_id == 2) {
        kind = MC_CDOBC_KIND_HDOBC;
    }
    mc_cdobc_params_paper002(p, (float)P2_TS, kind);
    if (case_id == 3 || case_id == 4) { /* + current-sensor harmonics */
        p->models.n_harm = 4u;
        p->models.harm[2] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 1u, 0.0f };
        p->models.harm[3] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 2u, 0.0f };
    }
    if (case_id == 4) {
        p->models.poly_order = MC_CDOBC_POLY_MAX;
    }
}
#define N_CASES 5

/* delta-form polynomial of the requested observer poles, scaled by W */
static void desired_delta_poly(const mc_cdobc_design_t *d, double W, double *coef)
{
    const int n = (int)d->n;
    double p[LA_NMAX + 1] = { 1.0 };
    int deg = 0;
    for (int i = 0; i < n;) {
        const double zr = exp(d->obs_re[i] * P2_TS) * cos(d->obs_im[i] * P2_TS);
        const double zi = exp(d->obs_re[i] * P2_TS) * sin(d->obs_im[i] * P2_TS);
        const double dr = (zr - 1.0) / (P2_TS * W), di = zi / (P2_TS * W);
        double q[LA_NMAX + 1] = { 0.0 };
        if (d->obs_im[i] == 0.0) { /* (s - dr) */
            for (int k = 0; k <= deg; ++k) {
                q[k + 1] += p[k];
                q[k] -= dr * p[k];
            }
            deg += 1;
            i += 1;
        } else { /* s^2 - 2 dr s + dr^2 + di^2 */
            for (int k = 0; k <= deg; ++k) {
                q[k + 2] += p[k];
                q[k + 1] -= 2.0 * dr * p[k];
                q[k] += (dr * dr + di * di) * p[k];
            }
            deg += 2;
            i += 2;
        }
        for (int k = 0; k <= deg; ++k) {
            p[k] = q[k];
        }
    }
    for (int k = 0; k < n; ++k) {
        coef[k] = p[k];
    }
}

static void check_case(int case_id, mc_cdobc_placement_t pl)
{
    mc_cdobc_params_t p;
    set_models(&p, case_id);
    p.placement = pl;
    mc_cdobc_design_t d;
    assert_int_equal(mc_cdobc_design_f64(&p, RPM500, &d), MC_OK);
    const p2_models_t tm = to_test(&p.models);
    const int n = p2_order(&tm), nf = n + 1;
    assert_int_equal((int)d.n, n);

    /* ZOH against la_expm, in physical units, entry by entry relative
     * to the row's largest entry */
    double Af[LA_NMAX * LA_NMAX], gf[LA_NMAX], h[LA_NMAX], Phi[LA_NMAX * LA_NMAX], Gam[LA_NMAX];
    p2_cont_model(&tm, RPM500, Af, gf, h);
    p2_zoh(nf, Af, gf, P2_TS, Phi, Gam);
    double worst = 0.0;
    for (int i = 0; i < nf; ++i) {
        double rs = fabs(Gam[i]);
        for (int j = 0; j < nf; ++j) {
            rs = fmax(rs, fabs(Phi[i * nf + j]));
        }
        for (int j = 0; j < nf; ++j) {
            double fw;
            if (i == 0) {
                fw = (j == 0) ? d.a_nn : d.c[j - 1];
            } else {
                fw = (j == 0) ? d.a_wn[i - 1] : d.Ad[(i - 1) * n + j - 1];
            }
            worst = fmax(worst, fabs(fw - Phi[i * nf + j]) / rs);
        }
        const double gw = (i == 0) ? d.Bd1 : d.Bd2[i - 1];
        worst = fmax(worst, fabs(gw - Gam[i]) / rs);
        if (i > 0) {
            assert_near(d.h[i - 1], h[i - 1], 0.0);
        }
    }
    assert_true(worst < 1e-10);

    /* observer: char. polynomial of T^-1 (Phi_e - I) T / (Ts W) with the
     * test's own diagonal scaling T = diag(W^k) by chain depth */
    double W = 520.0;
    for (int i = 0; i < tm.n_harm; ++i) {
        W = fmax(W, tm.mult[i] * RPM500);
    }
    int depth[LA_NMAX];
    depth[0] = 0;
    int s = 1;
    for (int i = 0; i < tm.n_harm; ++i, s += 2) {
        depth[s] = 1;
        depth[s + 1] = 2;
    }
    for (int j = 0; j < tm.N; ++j) {
        depth[s + j] = j + 1;
    }
    double Md[LA_NMAX * LA_NMAX], cp[LA_NMAX], want[LA_NMAX];
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const double e = d.Ad[i * n + j] - d.Ld[i] * d.c[j] - (i == j ? 1.0 : 0.0);
            Md[i * n + j] = e * pow(W, depth[j] - depth[i]) / (P2_TS * W);
        }
    }
    la_charpoly(n, Md, cp);
    desired_delta_poly(&d, W, want);
    double cworst = 0.0;
    for (int k = 0; k < n; ++k) {
        cworst = fmax(cworst, fabs(cp[k] - want[k]) / (1.0 + fabs(want[k])));
    }
    print_message("case %d %s: n = %d, ZOH rel err %.2e, observer char-poly rel err %.2e\n",
                  case_id, pl == MC_CDOBC_PLACE_ROBUST ? "robust" : "literal", n, worst, cworst);
    assert_true(cworst < 1e-7);

    if (pl == MC_CDOBC_PLACE_ROBUST) {
        /* each (simple) harmonic pole is an eigenvalue of Ad - Ld c */
        double Pe[LA_NMAX * LA_NMAX], wr[LA_NMAX], wi[LA_NMAX];
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                Pe[i * n + j] = d.Ad[i * n + j] - d.Ld[i] * d.c[j];
            }
        }
        assert_int_equal(la_eig(n, Pe, wr, wi), 0);
        for (int i = 0; i < 2 * tm.n_harm; ++i) {
            const double zr = exp(d.obs_re[i] * P2_TS) * cos(d.obs_im[i] * P2_TS);
            const double zi = exp(d.obs_re[i] * P2_TS) * sin(d.obs_im[i] * P2_TS);
            double best = 1.0;
            for (int k = 0; k < n; ++k) {
                best = fmin(best, hypot(wr[k] - zr, wi[k] - zi));
            }
            assert_true(best < 1e-9);
            /* requested: s^2 + 2 zeta w s + w^2 at the model frequency */
            const double w = tm.mult[i / 2] * RPM500;
            assert_near(hypot(d.obs_re[i], d.obs_im[i]), w, 1e-9 * w);
            assert_near(-d.obs_re[i] / w, (double)p.harm_zeta, 1e-6);
        }
    }

    /* controller: (nu, x2) block with v = c_qd omega* - K (x1, x2),
     * K1 = c_qd - k1, K2 = -k2 */
    const double K1 = P2_CQD - d.k1, K2 = -d.k2;
    const double a11 = Phi[0] - Gam[0] * K1, a12 = Phi[1] - Gam[0] * K2;
    const double a21 = Phi[nf] - Gam[1] * K1, a22 = Phi[nf + 1] - Gam[1] * K2;
    const double zc = exp(-200.0 * P2_TS);
    assert_near(a11 + a22, 2.0 * zc, 1e-10);
    assert_near(a11 * a22 - a12 * a21, zc * zc, 1e-10);

    /* nominal closed loop: spectral radius = the controller's pole */
    const mc_cdobc_plant_factors_t one = { 1.0, 1.0, 1.0, 1.0 };
    double Acl[LA_NMAX * LA_NMAX];
    uint32_t dim = 0;
    assert_int_equal(mc_cdobc_loop_matrix(&d, &one, &dim, Acl), MC_OK);
    assert_int_equal((int)dim, n + 5);
    const double rho_la = la_spectral_radius((int)dim, Acl);
    double rho_g = 0.0;
    assert_int_equal(mc_cdobc_loop_radius(&d, &one, &rho_g), MC_OK);
    /* separation: the slowest of the controller and observer poles */
    double rho_want = zc;
    for (int i = 0; i < n; ++i) {
        rho_want = fmax(rho_want, exp(d.obs_re[i] * P2_TS));
    }
    print_message("  nominal loop: rho (la_eig) %.8f, Gelfand %.8f, expected %.8f\n", rho_la, rho_g,
                  rho_want);
    if (pl == MC_CDOBC_PLACE_ROBUST) {
        assert_near(rho_la, rho_want, 1e-6);
    } else {
        assert_near(rho_la, rho_want, 1e-3); /* defective multiple pole */
    }
    assert_near(rho_g, rho_want, 5e-4);
}

static void test_design_all_sets(void **state)
{
    (void)state;
    for (int c = 0; c < N_CASES; ++c) {
        check_case(c, MC_CDOBC_PLACE_ROBUST);
        check_case(c, MC_CDOBC_PLACE_LITERAL);
    }
}

static void test_paper_gains(void **state)
{
    (void)state;
    /* continuous limit of the controller (5): s^2 + (a + k2/L) s + b1 k1/L
     * with a, k1 in the paper's sense ((6) cancelling back-EMF) =
     * (s + 200)^2: k1 = 4e4 L / b1, k2 = L (400 - a); the exact discrete
     * placement differs by O(Ts) */
    mc_cdobc_params_t p;
    mc_cdobc_params_paper002(&p, (float)P2_TS, MC_CDOBC_KIND_CDOBC);
    mc_cdobc_design_t d;
    assert_int_equal(mc_cdobc_design_f64(&p, RPM500, &d), MC_OK);
    const double k1c = 4e4 * P2_L / P2_B1, k2c = P2_L * (400.0 - P2_A);
    print_message("k1 %.5f (continuous %.5f), k2 %.5f (continuous %.5f)\n", d.k1, k1c, d.k2, k2c);
    assert_near(d.k1 / k1c, 1.0, 0.05);
    assert_near(d.k2, k2c, 0.1);
    assert_near(d.b1, P2_B1, 1e-9 * P2_B1);
    assert_near(d.c_qd_V_s, P2_CQD, 1e-12);
    /* model frequencies at 500 rpm: 6 n_p w = 1256.6, Q w = 1675.5 */
    assert_near(d.w_rad_s[0], 24.0 * RPM500, 1e-3);
    assert_near(d.w_rad_s[1], 32.0 * RPM500, 1e-3);
}

static void test_ackermann_solver(void **state)
{
    (void)state;
    /* double integrator, c = (1 0): A - l c has s^2 + l1 s + l2 */
    const double A[4] = { 0.0, 1.0, 0.0, 0.0 }, c[2] = { 1.0, 0.0 };
    const double coef[2] = { 6.0, 5.0 }; /* s^2 + 5 s + 6 */
    double l[2];
    assert_int_equal(mc_cdobc_ackermann_f64(2u, A, c, coef, l), MC_OK);
    assert_near(l[0], 5.0, 1e-12);
    assert_near(l[1], 6.0, 1e-12);
    /* unobservable pair */
    const double c0[2] = { 0.0, 1.0 };
    assert_int_equal(mc_cdobc_ackermann_f64(2u, A, c0, coef, l), MC_ERR_PARAM);
    /* roots -> polynomial */
    const double re[3] = { -1.0, -2.0, -2.0 }, im[3] = { 0.0, 3.0, -3.0 };
    double pc[3];
    assert_int_equal(mc_cdobc_poly_from_roots(3u, re, im, pc), MC_OK);
    /* (s + 1)(s^2 + 4 s + 13) = s^3 + 5 s^2 + 17 s + 13 */
    assert_near(pc[0], 13.0, 1e-12);
    assert_near(pc[1], 17.0, 1e-12);
    assert_near(pc[2], 5.0, 1e-12);
    const double im_bad[3] = { 0.0, 3.0, 3.0 };
    assert_int_equal(mc_cdobc_poly_from_roots(3u, re, im_bad, pc), MC_ERR_PARAM);
    double S[4] = { 1.0, 2.0, 2.0, 4.0 }, b[2] = { 1.0, 1.0 };
    assert_int_equal(mc_cdobc_solve_f64(2u, S, b), MC_ERR_PARAM);
}

static void test_validation(void **state)
{
    (void)state;
    mc_cdobc_params_t p;
    mc_cdobc_design_t d;
    mc_cdobc_params_paper002(&p, (float)P2_TS, MC_CDOBC_KIND_CDOBC);
    assert_int_equal(mc_cdobc_params_check(&p), MC_OK);
    assert_int_equal(mc_cdobc_design_f64(&p, NAN, &d), MC_ERR_NONFINITE);
    /* standstill: frequencies floored at omega_min */
    assert_int_equal(mc_cdobc_design_f64(&p, 0.0, &d), MC_OK);
    assert_near(d.omega_design_rad_s, 10.0, 1e-6);
    assert_int_equal(mc_cdobc_design_f64(&p, -RPM500, &d), MC_OK);
    assert_near(d.omega_design_rad_s, RPM500, 1e-4);
    /* Q = 32 at 5000 rpm: 16755 rad/s, w Ts > pi / 2 */
    assert_int_equal(mc_cdobc_design_f64(&p, 10.0 * RPM500, &d), MC_ERR_RANGE);
    assert_int_equal(mc_cdobc_design_f64(&p, RPM500, &d), MC_OK);

    mc_cdobc_params_t q = p;
    q.J_kgm2 = NAN;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_NONFINITE);
    q = p;
    q.R_ohm = -1.0f;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q = p;
    q.harm_zeta = 1.0f;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q.placement = MC_CDOBC_PLACE_LITERAL; /* zeta unused */
    assert_int_equal(mc_cdobc_params_check(&q), MC_OK);
    q = p;
    q.placement = (mc_cdobc_placement_t)7;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q = p;
    q.models.poly_order = MC_CDOBC_POLY_MAX + 1u;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q = p;
    q.models.n_harm = 0u;
    q.models.poly_order = 0u;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    /* 1st electrical = 4th mechanical with n_p = 4: same frequency */
    q = p;
    q.models.n_harm = 3u;
    q.models.harm[0] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 1u, 0.0f };
    q.models.harm[2] = (mc_cdobc_harm_t){ MC_CDOBC_MECH, 4u, 0.0f };
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q.models.harm[2].order = 0u;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q = p;
    q.models.harm[0].axis = (mc_cdobc_axis_t)5;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    /* a pair's own damping: 0 (the parameters') or in (0, 1) */
    q = p;
    q.models.harm[1].zeta = 0.5f;
    assert_int_equal(mc_cdobc_params_check(&q), MC_OK);
    q.models.harm[1].zeta = 1.0f;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q.models.harm[1].zeta = -0.1f;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    q.models.harm[1].zeta = NAN;
    assert_int_equal(mc_cdobc_params_check(&q), MC_ERR_PARAM);
    /* design errors leave *d untouched */
    mc_cdobc_design_t keep = d;
    q = p;
    q.Ts_s = 0.0f;
    assert_int_equal(mc_cdobc_design_f64(&q, RPM500, &d), MC_ERR_PARAM);
    assert_memory_equal(&keep, &d, sizeof d);
    /* analysis inputs */
    const mc_cdobc_plant_factors_t bad = { 1.0, NAN, 1.0, 1.0 }, neg = { 1.0, 1.0, 0.0, 1.0 };
    double rho, g, f = 6000.0;
    assert_int_equal(mc_cdobc_loop_radius(&d, &bad, &rho), MC_ERR_NONFINITE);
    assert_int_equal(mc_cdobc_loop_radius(&d, &neg, &rho), MC_ERR_PARAM);
    assert_int_equal(mc_cdobc_est_error_gain(&d, 1u, &f, &g), MC_ERR_RANGE);
    f = NAN;
    assert_int_equal(mc_cdobc_est_error_gain(&d, 1u, &f, &g), MC_ERR_NONFINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_design_all_sets),
        cmocka_unit_test(test_paper_gains),
        cmocka_unit_test(test_ackermann_solver),
        cmocka_unit_test(test_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
