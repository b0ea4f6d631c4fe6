/*
 * PLL speed / load estimator (the "NAM" baseline of paper 001):
 * - a speed ramp without torque feed-forward is tracked with the designed
 *   triple pole at -w_b: the error follows exp(M t) e0 of the continuous
 *   design, converges to zero in angle and speed (type-3 loop), and the
 *   load estimate absorbs -J * acceleration;
 * - with torque feed-forward the load estimate converges to the true load;
 * - configuration checks, non-finite inputs, plausibility bounds.
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mc/pll_observer.h"
#include "paper001_motor.h"
#include "test_rng.h"

#define NP ((double)P001_NP)

static mc_pll_obs_params_t params(double wb)
{
    const mc_pll_obs_params_t p = {
        .bandwidth_rad_s = (float)wb,
        .pole_pairs = P001_NP,
        .J_kgm2 = (float)P001_J_KGM2,
        .Ts_s = (float)P001_TS_S,
        .bounds = { .omega_m_max_rad_s = 1000.0f, .tau_max_Nm = 50.0f },
    };
    return p;
}

/* exp(M t) e0 for the designed error matrix
 *   M = [-l1 n_p 0; -l2 0 -1/J; l3 0 0],  l1 = 3 wb, l2 = 3 wb^2/n_p,
 *   l3 = J wb^3 / n_p,
 * which has the triple eigenvalue -wb: N = M + wb I is nilpotent and
 * exp(M t) = exp(-wb t) (I + N t + N^2 t^2 / 2). */
static void design_response(double wb, double t, const double e0[3], double e[3])
{
    const double J = P001_J_KGM2;
    const double N[3][3] = { { -3.0 * wb + wb, NP, 0.0 },
                             { -3.0 * wb * wb / NP, wb, -1.0 / J },
                             { J * wb * wb * wb / NP, 0.0, wb } };
    double Ne[3], NNe[3];
    for (int i = 0; i < 3; i++) {
        Ne[i] = N[i][0] * e0[0] + N[i][1] * e0[1] + N[i][2] * e0[2];
    }
    for (int i = 0; i < 3; i++) {
        NNe[i] = N[i][0] * Ne[0] + N[i][1] * Ne[1] + N[i][2] * Ne[2];
    }
    const double g = exp(-wb * t);
    for (int i = 0; i < 3; i++) {
        e[i] = g * (e0[i] + t * Ne[i] + 0.5 * t * t * NNe[i]);
    }
}

/* The closed form equals the solution of e' = M e with M built from the
 * gains (RK4 in double, 1e-5 s steps): this confirms that the gain
 * formulas place a triple pole at -w_b (otherwise N would not be nilpotent
 * and the closed form would be wrong). */
static void test_design_gains_give_triple_pole(void **state)
{
    (void)state;
    const double J = P001_J_KGM2;
    const double wbs[2] = { 40.0, 150.0 };
    for (int w = 0; w < 2; w++) {
        const double wb = wbs[w];
        const double l1 = 3.0 * wb, l2 = 3.0 * wb * wb / NP;
        const double l3 = J * wb * wb * wb / NP;
        const double M[3][3] = { { -l1, NP, 0.0 }, { -l2, 0.0, -1.0 / J }, { l3, 0.0, 0.0 } };
        const double e0[3] = { 0.3, -2.0, 0.1 };
        double x[3] = { e0[0], e0[1], e0[2] };
        const double h = 1e-5;
        const long n = lround(3.0 / wb / h);
        for (long k = 0; k < n; k++) {
            double k1[3], k2[3], k3[3], k4[3], y[3];
            for (int i = 0; i < 3; i++)
                k1[i] = M[i][0] * x[0] + M[i][1] * x[1] + M[i][2] * x[2];
            for (int i = 0; i < 3; i++)
                y[i] = x[i] + 0.5 * h * k1[i];
            for (int i = 0; i < 3; i++)
                k2[i] = M[i][0] * y[0] + M[i][1] * y[1] + M[i][2] * y[2];
            for (int i = 0; i < 3; i++)
                y[i] = x[i] + 0.5 * h * k2[i];
            for (int i = 0; i < 3; i++)
                k3[i] = M[i][0] * y[0] + M[i][1] * y[1] + M[i][2] * y[2];
            for (int i = 0; i < 3; i++)
                y[i] = x[i] + h * k3[i];
            for (int i = 0; i < 3; i++)
                k4[i] = M[i][0] * y[0] + M[i][1] * y[1] + M[i][2] * y[2];
            for (int i = 0; i < 3; i++)
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        double e[3];
        design_response(wb, (double)n * h, e0, e);
        for (int i = 0; i < 3; i++) {
            assert_near(e[i], x[i], 1e-9 * (1.0 + fabs(x[i])));
        }
    }
}

/* Speed ramp w(t) = w0 + alpha t, no torque feed-forward: in the model the
 * ramp is an effective load tau = -J alpha. From estimates (theta0, 0, 0)
 * the error e = [theta - theta_hat; w - w_hat; tau - tau_hat] starts at
 * [0; w0; -J alpha] and must follow the design response. Tolerance: the
 * outputs are read after the correction, which scales the angle error by
 * (1 - l1 Ts) = 1 - 3 w_b Ts against the continuous loop, and the Euler
 * poles move by O(w_b Ts): deviation <= (3 w_b Ts + 0.2 %) of each
 * component's peak (0.8 % at the default 40 rad/s, 2.5 % at 150 rad/s). */
static void test_tracks_speed_ramp_with_designed_poles(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(4040);
    const double bws[3] = { MC_PLL_OBS_BANDWIDTH_DEFAULT_RAD_S, 15.0, 150.0 };
    for (int trial = 0; trial < 6; trial++) {
        const double wb = bws[trial % 3];
        const double theta0 = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        const double w0 = test_rng_range(&rng, -60.0, 60.0);
        const double alpha = test_rng_range(&rng, -200.0, 200.0);
        const double e0[3] = { 0.0, w0, -P001_J_KGM2 * alpha };
        mc_pll_obs_f32_t pll;
        const mc_pll_obs_params_t p = params(wb);
        assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_OK);
        assert_int_equal(mc_pll_obs_reset_f32(&pll, (float)theta0, 0.0f, 0.0f), MC_OK);
        const long n = lround(25.0 / wb / P001_TS_S); /* e^-25 left */
        double peak[3] = { 0.0, 0.0, 0.0 }, max_dev[3] = { 0.0, 0.0, 0.0 };
        for (long k = 1; k <= n; k++) {
            const double t = (double)k * P001_TS_S;
            const double theta = theta0 + NP * (w0 * t + 0.5 * alpha * t * t);
            assert_int_equal(mc_pll_obs_step_f32(&pll, (float)p001_wrap_rad(theta), 0.0f), MC_OK);
            const double e[3] = { p001_wrap_rad(theta - (double)mc_pll_obs_theta_e_f32(&pll)),
                                  w0 + alpha * t - (double)mc_pll_obs_omega_m_f32(&pll),
                                  -P001_J_KGM2 * alpha - (double)mc_pll_obs_tau_L_f32(&pll) };
            double pred[3];
            design_response(wb, t, e0, pred);
            for (int i = 0; i < 3; i++) {
                peak[i] = fmax(peak[i], fabs(pred[i]));
                max_dev[i] = fmax(max_dev[i], fabs(e[i] - pred[i]));
            }
        }
        if (trial < 3) {
            printf("  w_b = %.0f rad/s: max dev / peak: angle %.3g, speed %.3g, "
                   "load %.3g\n",
                   wb, max_dev[0] / peak[0], max_dev[1] / peak[1], max_dev[2] / peak[2]);
        }
        const double tol = 3.0 * wb * P001_TS_S + 0.002;
        for (int i = 0; i < 3; i++) {
            assert_true(max_dev[i] <= tol * peak[i] + 1e-5);
        }
        /* converged on the ramp: zero steady-state error (type 3) up to
         * the Euler half-sample offset alpha Ts / 2 in speed */
        const double t_end = (double)n * P001_TS_S;
        assert_true(fabs(mc_pll_obs_omega_m_f32(&pll) - (w0 + alpha * t_end)) <
                    fabs(alpha) * P001_TS_S + 1e-4);
        assert_near(mc_pll_obs_tau_L_f32(&pll), -P001_J_KGM2 * alpha,
                    1e-3 * P001_J_KGM2 * fabs(alpha) + 1e-5);
    }
}

/* Torque feed-forward: J w' = tau_e - tau_L with a constant load; the load
 * estimate converges to tau_L and the speed to the true speed. */
static void test_load_estimate_with_torque_feedforward(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(11);
    for (int trial = 0; trial < 5; trial++) {
        const double tau_e = test_rng_range(&rng, -2.0, 2.0);
        const double tau_L = test_rng_range(&rng, -2.0, 2.0);
        const double alpha = (tau_e - tau_L) / P001_J_KGM2;
        const double w0 = test_rng_range(&rng, -50.0, 50.0);
        mc_pll_obs_f32_t pll;
        const mc_pll_obs_params_t p = params(MC_PLL_OBS_BANDWIDTH_DEFAULT_RAD_S);
        assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_OK);
        assert_int_equal(mc_pll_obs_reset_f32(&pll, 0.0f, 0.0f, 0.0f), MC_OK);
        const long n = 20000; /* 1 s: w_b t = 40 */
        for (long k = 1; k <= n; k++) {
            const double t = (double)k * P001_TS_S;
            const double theta = NP * (w0 * t + 0.5 * alpha * t * t);
            assert_int_equal(mc_pll_obs_step_f32(&pll, (float)p001_wrap_rad(theta), (float)tau_e),
                             MC_OK);
        }
        const double t_end = (double)n * P001_TS_S;
        assert_near(mc_pll_obs_tau_L_f32(&pll), tau_L, 1e-3 * fabs(tau_e - tau_L) + 1e-5);
        assert_true(fabs(mc_pll_obs_omega_m_f32(&pll) - (w0 + alpha * t_end)) <
                    fabs(alpha) * P001_TS_S + 1e-4);
        assert_int_equal(mc_pll_obs_check_f32(&pll), MC_OK);
    }
}

static void test_init_rejects_invalid_params(void **state)
{
    (void)state;
    mc_pll_obs_f32_t pll;
    mc_pll_obs_params_t p = params(40.0);
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_OK);
    p.bandwidth_rad_s = 0.0f;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_ERR_PARAM);
    /* w_b Ts bound: 2000 rad/s at 20 kHz accepted, above rejected */
    p.bandwidth_rad_s = 1999.0f;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_OK);
    p.bandwidth_rad_s = 2001.0f;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_ERR_PARAM);
    p = params(40.0);
    p.pole_pairs = 0u;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_ERR_PARAM);
    p = params(40.0);
    p.J_kgm2 = -1.0f;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_ERR_PARAM);
    p = params(40.0);
    p.Ts_s = NAN;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_ERR_NONFINITE);
    p = params(40.0);
    p.bounds.omega_m_max_rad_s = -1.0f;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_ERR_PARAM);
}

static void test_nonfinite_and_bounds(void **state)
{
    (void)state;
    mc_pll_obs_params_t p = params(40.0);
    p.bounds.omega_m_max_rad_s = 100.0f;
    p.bounds.tau_max_Nm = 1.0f;
    mc_pll_obs_f32_t pll;
    assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_OK);
    assert_int_equal(mc_pll_obs_reset_f32(&pll, 2.0f, 50.0f, 0.5f), MC_OK);
    assert_int_equal(mc_pll_obs_step_f32(&pll, 2.01f, 0.1f), MC_OK);
    mc_pll_obs_f32_t before;
    memcpy(&before, &pll, sizeof pll);
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    for (int b = 0; b < 3; b++) {
        assert_int_equal(mc_pll_obs_step_f32(&pll, bad[b], 0.0f), MC_ERR_NONFINITE);
        assert_int_equal(mc_pll_obs_step_f32(&pll, 1.0f, bad[b]), MC_ERR_NONFINITE);
        assert_int_equal(mc_pll_obs_reset_f32(&pll, 0.0f, bad[b], 0.0f), MC_ERR_NONFINITE);
        assert_memory_equal(&before, &pll, sizeof pll);
    }
    assert_int_equal(mc_pll_obs_check_f32(&pll), MC_OK);
    assert_int_equal(mc_pll_obs_reset_f32(&pll, 0.0f, 100.5f, 0.0f), MC_OK);
    assert_int_equal(mc_pll_obs_check_f32(&pll), MC_ERR_RANGE);
    assert_int_equal(mc_pll_obs_reset_f32(&pll, 0.0f, 0.0f, -1.5f), MC_OK);
    assert_int_equal(mc_pll_obs_check_f32(&pll), MC_ERR_RANGE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_design_gains_give_triple_pole),
        cmocka_unit_test(test_tracks_speed_ramp_with_designed_poles),
        cmocka_unit_test(test_load_estimate_with_torque_feedforward),
        cmocka_unit_test(test_init_rejects_invalid_params),
        cmocka_unit_test(test_nonfinite_and_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
