/*
 * Paper 002 regulator, analysis (mc/cdobc.h) at 500 rpm, Section IV
 * motor, 10 kHz:
 * - disturbance estimation error |D - D_hat| / |d| of the LITERAL design
 *   (every observer pole at -520): amplification over 25-67 Hz, HDOBC at
 *   DC; zeros at every modelled frequency;
 * - the same for the ROBUST default (harmonic pairs at their own
 *   frequency, zeta = 0.03): peak gain;
 * - closed-loop spectral radius with J, R, L, Kt errors: LITERAL loses
 *   stability for the stated errors, ROBUST is stable on the
 *   {0.8, 1, 1.2}^4 grid; per-parameter stability limits are measured
 *   and printed for both;
 * - CDOBC with the current-sensor models (1st and 2nd electrical) at
 *   damping 0.5, the default's 0.1 for the others (observer poles at
 *   -1000, the bench's): exact notches at 33.3 and 66.7 Hz, the nominal
 *   loop's spectral radius that of its slowest designed pole (separation,
 *   delay included; the sensor pairs decay at zeta w >= 105 / s, not 6 /
 *   s as at 0.03) and stable on the same grid.
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>

#include "eeo_test_linalg.h"
#include "mc/cdobc.h"

#define TS     1e-4f
#define RPM500 (500.0 * MC_TEST_RAD_S_PER_RPM)

static void design(mc_cdobc_kind_t kind, mc_cdobc_placement_t pl, mc_cdobc_design_t *d)
{
    mc_cdobc_params_t p;
    mc_cdobc_params_paper002(&p, TS, kind);
    p.placement = pl;
    assert_int_equal(mc_cdobc_design_f64(&p, RPM500, d), MC_OK);
}

static double gain_at(const mc_cdobc_design_t *d, double f)
{
    double g = -1.0;
    assert_int_equal(mc_cdobc_est_error_gain(d, 1u, &f, &g), MC_OK);
    return g;
}

/* largest gain over [f0, f1] in steps of df; *f_at where */
static double peak(const mc_cdobc_design_t *d, double f0, double f1, double df, double *f_at)
{
    double g_max = 0.0;
    for (double f = f0; f <= f1 + 1e-9; f += df) {
        const double g = gain_at(d, f);
        if (g > g_max) {
            g_max = g;
            *f_at = f;
        }
    }
    return g_max;
}

static double rho(const mc_cdobc_design_t *d, double fJ, double fR, double fL, double fK)
{
    const mc_cdobc_plant_factors_t f = { fJ, fR, fL, fK };
    double r = -1.0;
    assert_int_equal(mc_cdobc_loop_radius(d, &f, &r), MC_OK);
    return r;
}

/* DC (with a polynomial model), the 6th electrical and the Q-th
 * mechanical harmonic are cancelled exactly */
static void assert_cancels(const mc_cdobc_design_t *d, int dc)
{
    const double f6 = d->w_rad_s[0] / MC_TEST_TWO_PI, fq = d->w_rad_s[1] / MC_TEST_TWO_PI;
    if (dc) {
        assert_true(gain_at(d, 0.0) < 1e-9);
    }
    assert_true(gain_at(d, f6) < 1e-9);
    assert_true(gain_at(d, fq) < 1e-9);
}

static void test_literal_frequency_response(void **state)
{
    (void)state;
    mc_cdobc_design_t c, h, g;
    design(MC_CDOBC_KIND_CDOBC, MC_CDOBC_PLACE_LITERAL, &c);
    design(MC_CDOBC_KIND_HDOBC, MC_CDOBC_PLACE_LITERAL, &h);
    design(MC_CDOBC_KIND_GPIOBC, MC_CDOBC_PLACE_LITERAL, &g);
    const double f6 = c.w_rad_s[0] / MC_TEST_TWO_PI, fq = c.w_rad_s[1] / MC_TEST_TWO_PI;
    assert_cancels(&c, 1);
    assert_cancels(&h, 0);
    assert_true(gain_at(&g, 0.0) < 1e-9);
    /* the literal CDOBC amplifies what lies below the harmonics */
    double f_pk = 0.0;
    const double pk = peak(&c, 25.0, 67.0, 0.5, &f_pk);
    const double g25 = gain_at(&c, 25.0), g67 = gain_at(&c, 67.0);
    print_message("CDOBC literal: |E/d| 25 Hz %.1f, 67 Hz %.1f, peak %.1f at %.1f Hz; "
                  "%.0f Hz (6th el.) %.1e, %.1f Hz (Q-th mech.) %.1e\n",
                  g25, g67, pk, f_pk, f6, gain_at(&c, f6), fq, gain_at(&c, fq));
    assert_true(g25 > 20.0 && g25 < 40.0);
    assert_true(g67 > 30.0 && g67 < 50.0);
    assert_true(pk > 28.0 && pk < 60.0);
    /* HDOBC: no DC model: a constant disturbance is amplified ~300x */
    const double h0 = gain_at(&h, 0.0);
    print_message("HDOBC literal: |E/d| at DC %.1f, at 1 Hz %.1f\n", h0, gain_at(&h, 1.0));
    assert_true(h0 > 250.0 && h0 < 350.0);
    /* GPIOBC leaves the harmonics (gain about 1 there) */
    print_message("GPIOBC: |E/d| at %.0f Hz %.2f, at %.1f Hz %.2f\n", f6, gain_at(&g, f6), fq,
                  gain_at(&g, fq));
    assert_true(gain_at(&g, f6) > 0.9);
    assert_true(gain_at(&g, fq) > 0.9);
}

static void test_robust_frequency_response(void **state)
{
    (void)state;
    mc_cdobc_design_t c, h;
    design(MC_CDOBC_KIND_CDOBC, MC_CDOBC_PLACE_ROBUST, &c);
    design(MC_CDOBC_KIND_HDOBC, MC_CDOBC_PLACE_ROBUST, &h);
    assert_cancels(&c, 1);
    assert_cancels(&h, 0);
    double f_pk = 0.0;
    const double pk = peak(&c, 0.5, 4000.0, 0.5, &f_pk);
    double f_band = 0.0;
    const double band = peak(&c, 25.0, 67.0, 0.5, &f_band);
    print_message("CDOBC robust: peak |E/d| %.2f at %.1f Hz; over 25-67 Hz at most %.2f; "
                  "HDOBC robust at DC %.2f\n",
                  pk, f_pk, band, gain_at(&h, 0.0));
    assert_true(pk < 3.0);
    assert_true(band < 2.5);
}

static void test_literal_loses_stability(void **state)
{
    (void)state;
    mc_cdobc_design_t c;
    design(MC_CDOBC_KIND_CDOBC, MC_CDOBC_PLACE_LITERAL, &c);
    const double r0 = rho(&c, 1, 1, 1, 1);
    const double rJm = rho(&c, 0.9, 1, 1, 1), rJp = rho(&c, 1.1, 1, 1, 1);
    const double rR = rho(&c, 1, 1.2, 1, 1), rL = rho(&c, 1, 1, 0.9, 1);
    const double rK = rho(&c, 1, 1, 1, 0.95);
    print_message("CDOBC literal rho: nominal %.5f, J-10%% %.5f, J+10%% %.5f, R+20%% %.5f, "
                  "L-10%% %.5f, Kt-5%% %.5f\n",
                  r0, rJm, rJp, rR, rL, rK);
    assert_true(r0 < 1.0);
    assert_true(rJm > 1.0 && rJp > 1.0 && rR > 1.0 && rL > 1.0 && rK > 1.0);
    /* the Gelfand estimate agrees with la_eig */
    const mc_cdobc_plant_factors_t f = { 1.0, 1.0, 1.0, 0.95 };
    double A[LA_NMAX * LA_NMAX];
    uint32_t dim = 0;
    assert_int_equal(mc_cdobc_loop_matrix(&c, &f, &dim, A), MC_OK);
    assert_near(la_spectral_radius((int)dim, A), rK, 3e-4);
}

/* first factor (step 0.01 from 1) where rho >= 1, going up or down */
static double limit(const mc_cdobc_design_t *d, int which, double dir)
{
    for (int k = 1; k <= 100; ++k) {
        double f[4] = { 1.0, 1.0, 1.0, 1.0 };
        f[which] = 1.0 + dir * 0.01 * k;
        if (f[which] <= 0.0 || rho(d, f[0], f[1], f[2], f[3]) >= 1.0) {
            return f[which];
        }
    }
    return (dir > 0.0) ? INFINITY : 0.0; /* none within +-100 % */
}

static void print_limits(const char *name, const mc_cdobc_design_t *d)
{
    static const char *const nm[4] = { "J", "R", "L", "Kt" };
    char line[256];
    int pos = snprintf(line, sizeof line, "%s unstable from:", name);
    for (int w = 0; w < 4 && pos > 0 && pos < (int)sizeof line; ++w) {
        pos += snprintf(line + pos, sizeof line - (size_t)pos, " %s %.2f / %.2f;", nm[w],
                        limit(d, w, -1.0), limit(d, w, 1.0));
    }
    print_message("%s\n", line);
}

static void test_robust_grid(void **state)
{
    (void)state;
    mc_cdobc_design_t c, lit, g, h;
    design(MC_CDOBC_KIND_CDOBC, MC_CDOBC_PLACE_ROBUST, &c);
    design(MC_CDOBC_KIND_CDOBC, MC_CDOBC_PLACE_LITERAL, &lit);
    design(MC_CDOBC_KIND_GPIOBC, MC_CDOBC_PLACE_ROBUST, &g);
    design(MC_CDOBC_KIND_HDOBC, MC_CDOBC_PLACE_ROBUST, &h);
    static const double lv[3] = { 0.8, 1.0, 1.2 };
    double worst = 0.0, at[4] = { 0 };
    for (int a = 0; a < 81; ++a) {
        const double f[4] = { lv[a % 3], lv[(a / 3) % 3], lv[(a / 9) % 3], lv[a / 27] };
        const double r = rho(&c, f[0], f[1], f[2], f[3]);
        if (r > worst) {
            worst = r;
            for (int i = 0; i < 4; ++i) {
                at[i] = f[i];
            }
        }
    }
    print_message("CDOBC robust, grid {0.8,1,1.2}^4 of (J,R,L,Kt): max rho %.5f at "
                  "(%.1f, %.1f, %.1f, %.1f)\n",
                  worst, at[0], at[1], at[2], at[3]);
    assert_true(worst < 1.0);
    /* one parameter at a time, 5 % steps over +-20 % */
    for (int w = 0; w < 4; ++w) {
        for (int k = -4; k <= 4; ++k) {
            double f[4] = { 1.0, 1.0, 1.0, 1.0 };
            f[w] = 1.0 + 0.05 * k;
            assert_true(rho(&c, f[0], f[1], f[2], f[3]) < 1.0);
        }
    }
    print_limits("CDOBC literal", &lit);
    print_limits("CDOBC robust ", &c);
    print_limits("GPIOBC       ", &g);
    print_limits("HDOBC robust ", &h);
}

static void test_sensor_models(void **state)
{
    (void)state;
    mc_cdobc_params_t p;
    mc_cdobc_params_paper002(&p, TS, MC_CDOBC_KIND_CDOBC);
    p.obs_pole_rad_s = 1000.0f;
    p.models.n_harm = 4u;
    p.models.harm[2] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 1u, 0.5f };
    p.models.harm[3] = (mc_cdobc_harm_t){ MC_CDOBC_ELEC, 2u, 0.5f };
    mc_cdobc_design_t d;
    assert_int_equal(mc_cdobc_design_f64(&p, RPM500, &d), MC_OK);
    /* 500 rpm: f_e = 4 x 8.333 = 33.33 Hz */
    const double g1 = gain_at(&d, 100.0 / 3.0), g2 = gain_at(&d, 200.0 / 3.0);
    const double r1 = rho(&d, 1.0, 1.0, 1.0, 1.0);
    print_message("sensor models at zeta 0.5: |e/d| %.2g at 33.3 Hz, %.2g at 66.7 Hz, "
                  "nominal rho %.5f\n",
                  g1, g2, r1);
    assert_true(g1 < 1e-4 && g2 < 1e-4);
    double slowest = 0.0;
    for (uint32_t i = 0; i < d.n; ++i) {
        slowest = (i == 0u || d.obs_re[i] > slowest) ? d.obs_re[i] : slowest;
    }
    slowest = (slowest > -(double)p.ctl_pole_rad_s) ? slowest : -(double)p.ctl_pole_rad_s;
    print_message("slowest designed pole %.2f / s\n", slowest);
    assert_near(r1, exp(slowest * (double)TS), 1e-4);
    assert_true(-d.obs_re[4] >= 100.0 && -d.obs_re[6] >= 100.0); /* the sensor pairs */
    static const double lv[3] = { 0.8, 1.0, 1.2 };
    double worst = 0.0;
    for (int a = 0; a < 81; ++a) {
        const double r = rho(&d, lv[a % 3], lv[(a / 3) % 3], lv[(a / 9) % 3], lv[a / 27]);
        worst = (r > worst) ? r : worst;
    }
    print_message("sensor models at zeta 0.5, grid {0.8,1,1.2}^4: max rho %.5f\n", worst);
    assert_true(worst < 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_literal_frequency_response),
        cmocka_unit_test(test_robust_frequency_response),
        cmocka_unit_test(test_literal_loses_stability),
        cmocka_unit_test(test_robust_grid),
        cmocka_unit_test(test_sensor_models),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
