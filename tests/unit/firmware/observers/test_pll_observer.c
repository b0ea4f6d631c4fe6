/*
 * PLL speed / load estimator (the "NAM" baseline of paper 001):
 * - a speed ramp without torque feed-forward is tracked with the designed
 *   triple pole at -w_b: the error follows exp(M t) e0 of the continuous
 *   design, converges to zero in angle and speed (type-3 loop), and the
 *   load estimate absorbs -J * acceleration;
 * - with torque feed-forward the load estimate converges to the true load;
 * - configuration checks, non-finite inputs, plausibility bounds;
 * - the ISR's step (the cross-product detector, the angle held as a
 *   direction) against the same equations in double;
 * - the cross-product phase detector: the designed poles for small errors,
 *   its analytic steady-state angle offset, independent of the direction's
 *   length.
 */
#include "mc_test.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "mc/angle.h"
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

/* The drive renormalises the PLL's direction on its slow tick: every
 * 10th sample at the default decimation. */
#define RENORMALISE_EVERY 10

/* Step k of the cross-product detector as the drive's estimator runs it:
 * the observed direction r [cos theta; sin theta]. */
static float vector_step(mc_pll_obs_f32_t *pll, long k, double r, double theta, float tau_ff)
{
    return mc_pll_obs_update_vector_f32(pll, (float)(r * cos(theta)), (float)(r * sin(theta)),
                                        tau_ff, k % RENORMALISE_EVERY == 0);
}

/* The ramp below (w0 in +-w0_max, alpha in +-alpha_max, theta0 any, drawn
 * from rng) from the estimates (theta0, 0, 0), 25 / w_b long, through the
 * checked step (the angle detector) or the cross-product detector
 * (vector): each error component against the design response, within the
 * tolerance below of its peak. The PLL is left at the end. */
typedef struct {
    double w0, alpha, t_end;
    double peak[3], max_dev[3];
} ramp_t;

static ramp_t run_ramp(mc_pll_obs_f32_t *pll, test_rng_t *rng, double wb, double w0_max,
                       double alpha_max, bool vector)
{
    const double theta0 = test_rng_range(rng, -MC_TEST_PI, MC_TEST_PI);
    ramp_t r = { .w0 = test_rng_range(rng, -w0_max, w0_max) };
    r.alpha = test_rng_range(rng, -alpha_max, alpha_max); /* drawn in order */
    const double e0[3] = { 0.0, r.w0, -P001_J_KGM2 * r.alpha };
    const mc_pll_obs_params_t p = params(wb);
    assert_int_equal(mc_pll_obs_init_f32(pll, &p), MC_OK);
    assert_int_equal(mc_pll_obs_reset_f32(pll, (float)theta0, 0.0f, 0.0f), MC_OK);
    const long n = lround(25.0 / wb / P001_TS_S); /* e^-25 left */
    for (long k = 1; k <= n; k++) {
        const double t = (double)k * P001_TS_S;
        const double theta = theta0 + NP * (r.w0 * t + 0.5 * r.alpha * t * t);
        if (vector) {
            assert_true(vector_step(pll, k, 1.0, theta, 0.0f) == 0.0f);
        } else {
            assert_int_equal(mc_pll_obs_step_f32(pll, (float)p001_wrap_rad(theta), 0.0f), MC_OK);
        }
        const double e[3] = { p001_wrap_rad(theta - (double)mc_pll_obs_theta_e_f32(pll)),
                              r.w0 + r.alpha * t - (double)mc_pll_obs_omega_m_f32(pll),
                              -P001_J_KGM2 * r.alpha - (double)mc_pll_obs_tau_L_f32(pll) };
        double pred[3];
        design_response(wb, t, e0, pred);
        for (int i = 0; i < 3; i++) {
            r.peak[i] = fmax(r.peak[i], fabs(pred[i]));
            r.max_dev[i] = fmax(r.max_dev[i], fabs(e[i] - pred[i]));
        }
    }
    const double tol = 3.0 * wb * P001_TS_S + 0.002;
    for (int i = 0; i < 3; i++) {
        assert_true(r.max_dev[i] <= tol * r.peak[i] + 1e-5);
    }
    r.t_end = (double)n * P001_TS_S;
    return r;
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
        mc_pll_obs_f32_t pll;
        const ramp_t r = run_ramp(&pll, &rng, wb, 60.0, 200.0, false);
        if (trial < 3) {
            printf("  w_b = %.0f rad/s: max dev / peak: angle %.3g, speed %.3g, "
                   "load %.3g\n",
                   wb, r.max_dev[0] / r.peak[0], r.max_dev[1] / r.peak[1],
                   r.max_dev[2] / r.peak[2]);
        }
        /* converged on the ramp: zero steady-state error (type 3) up to
         * the Euler half-sample offset alpha Ts / 2 in speed */
        assert_true(fabs(mc_pll_obs_omega_m_f32(&pll) - (r.w0 + r.alpha * r.t_end)) <
                    fabs(r.alpha) * P001_TS_S + 1e-4);
        assert_near(mc_pll_obs_tau_L_f32(&pll), -P001_J_KGM2 * r.alpha,
                    1e-3 * P001_J_KGM2 * fabs(r.alpha) + 1e-5);
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

/* The ISR's step (mc_pll_obs_update_vector_f32, renormalised every 10th
 * sample as on the drive's slow tick) against the same discrete equations
 * in double with the exact rotation (the float gains): on a trajectory
 * over many turns with a noisy observed direction of varying length and a
 * torque feed-forward, at 0.06 and 0.2 rad per sample (the series
 * rotation and the exact one, MC_ROTATE_SERIES_MAX_RAD = 0.125), for 1 s.
 * The float loop's own errors (rounding, 1e-7 rad per sample; the
 * series, <= 8e-9 rad per sample at 0.06) are corrected by the loop like
 * any angle disturbance: the angle stays within 2e-5 rad of the
 * reference, the speed within 2e-3 rad/s and the load within 1e-3 N m;
 * the increment each step reports within 1e-6 rad of the reference's; the
 * direction's length within 1e-5 of 1. A non-finite input or state
 * reaches the report (NaN); a reset clears it. */
static void test_update_against_double(void **state)
{
    (void)state;
    const mc_pll_obs_params_t p = params(40.0);
    const double steps[2] = { 0.06, 0.2 };
    for (int i = 0; i < 2; i++) {
        mc_pll_obs_f32_t pll;
        assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_OK);
        const double w_m = steps[i] / (NP * P001_TS_S);
        assert_int_equal(mc_pll_obs_reset_f32(&pll, 1.0f, (float)w_m, 0.0f), MC_OK);
        double th = 1.0, w = (double)pll.omega_m_rad_s, tau = 0.0;
        const double l1 = pll.l1_Ts, l2 = pll.l2_Ts, l3 = pll.l3_Ts, np_ts = pll.np_Ts,
                     ts_j = pll.Ts_over_J;
        test_rng_t rng = test_rng_seed(7u);
        double max_err[4] = { 0.0, 0.0, 0.0, 0.0 };
        for (long k = 1; k <= 20000; k++) {
            const double th_obs = 1.0 + steps[i] * (double)k + test_rng_range(&rng, -0.01, 0.01);
            const double r = test_rng_range(&rng, 0.9, 1.1);
            const float r_al = (float)(r * cos(th_obs));
            const float r_be = (float)(r * sin(th_obs));
            const float tau_ff = (float)test_rng_range(&rng, -2.0, 2.0);
            assert_true(mc_pll_obs_update_vector_f32(&pll, r_al, r_be, tau_ff,
                                                     k % RENORMALISE_EVERY == 0) == 0.0f);
            const double d = np_ts * w;
            const double eps =
                (double)r_be * (cos(th) - d * sin(th)) - (double)r_al * (sin(th) + d * cos(th));
            const double d_th = d + l1 * eps;
            th += d_th;
            w += ts_j * ((double)tau_ff - tau) + l2 * eps;
            tau -= l3 * eps;
            const double err[4] = {
                fabs(remainder((double)mc_pll_obs_theta_e_f32(&pll) - th, 2.0 * MC_TEST_PI)),
                fabs((double)mc_pll_obs_omega_m_f32(&pll) - w),
                fabs((double)mc_pll_obs_tau_L_f32(&pll) - tau),
                fabs((double)mc_pll_obs_d_theta_e_f32(&pll) - d_th),
            };
            for (int m = 0; m < 4; m++) {
                max_err[m] = fmax(max_err[m], err[m]);
            }
            assert_true(fabs(hypot((double)pll.sin_e, (double)pll.cos_e) - 1.0) <= 1e-5);
        }
        printf("  %.2f rad per sample: max error angle %.3g rad, speed %.3g rad/s, load %.3g "
               "N m, increment %.3g rad\n",
               steps[i], max_err[0], max_err[1], max_err[2], max_err[3]);
        assert_true(max_err[0] <= 2e-5);
        assert_true(max_err[1] <= 2e-3);
        assert_true(max_err[2] <= 1e-3);
        assert_true(max_err[3] <= 1e-6);
    }
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    for (int b = 0; b < 3; b++) {
        for (int pos = 0; pos < 4; pos++) {
            mc_pll_obs_f32_t x;
            assert_int_equal(mc_pll_obs_init_f32(&x, &p), MC_OK);
            assert_int_equal(mc_pll_obs_reset_f32(&x, 0.5f, 10.0f, 0.0f), MC_OK);
            float in[3] = { 1.0f, 0.0f, 0.0f };
            if (pos < 3) {
                in[pos] = bad[b];
            } else {
                x.sin_e = bad[b]; /* a non-finite state */
            }
            const float fin = mc_pll_obs_update_vector_f32(&x, in[0], in[1], in[2], false);
            assert_true(isnan(fin));
            assert_int_equal(mc_pll_obs_reset_f32(&x, 0.5f, 0.0f, 0.0f), MC_OK);
            assert_true(mc_pll_obs_update_vector_f32(&x, 0.8f, 0.5f, 0.0f, false) == 0.0f);
        }
    }
}

/* The cross-product detector (mc_pll_obs_update_vector_f32):
 * - small errors: the error trajectory of a speed ramp follows the
 *   designed triple pole (design_response) as the angle detector's does,
 *   the sine's e^3 / 6 below the tolerance of that test;
 * - constant speed, direction length r = 0.8 .. 1.2 (the loop's gain
 *   times r; type 3, so no steady error from it): the angle settles at
 *   atan(d) - d behind the true one, d = n_p Ts w (the first-order
 *   advance of the detector's reference; analytic), the speed on the
 *   true speed, the load estimate at 0
 * (the non-finite inputs: test_update_against_double). */
static void test_vector_detector(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(99);
    for (int trial = 0; trial < 4; trial++) {
        mc_pll_obs_f32_t pll;
        const ramp_t r = run_ramp(&pll, &rng, MC_PLL_OBS_BANDWIDTH_DEFAULT_RAD_S, 2.0, 40.0, true);
        printf("  vector detector, ramp %d: peak angle error %.3g rad, max dev / peak: angle "
               "%.3g, speed %.3g, load %.3g\n",
               trial, r.peak[0], r.max_dev[0] / r.peak[0], r.max_dev[1] / r.peak[1],
               r.max_dev[2] / r.peak[2]);
    }
    const double ds[2] = { 0.02, 0.1 }, rs[3] = { 0.8, 1.0, 1.2 };
    for (int i = 0; i < 2; i++) {
        for (int j = 0; j < 3; j++) {
            const double w = ds[i] / (NP * P001_TS_S);
            mc_pll_obs_f32_t pll;
            const mc_pll_obs_params_t p = params(MC_PLL_OBS_BANDWIDTH_DEFAULT_RAD_S);
            assert_int_equal(mc_pll_obs_init_f32(&pll, &p), MC_OK);
            assert_int_equal(mc_pll_obs_reset_f32(&pll, 0.3f, (float)(0.95 * w), 0.0f), MC_OK);
            double theta = 0.3;
            for (long k = 1; k <= 40000; k++) { /* 2 s: w_b t = 80 */
                theta = p001_wrap_rad(theta + ds[i]);
                assert_true(vector_step(&pll, k, rs[j], theta, 0.0f) == 0.0f);
            }
            const double lag = p001_wrap_rad(theta - (double)mc_pll_obs_theta_e_f32(&pll));
            const double expect = atan(ds[i]) - ds[i];
            printf("  d = %.2f, r = %.1f: angle lag %.4g rad (atan(d) - d = %.4g)\n", ds[i], rs[j],
                   lag, expect);
            assert_true(fabs(lag - expect) <= 2e-6);
            assert_true(fabs((double)mc_pll_obs_omega_m_f32(&pll) - w) <= 1e-4 * w);
            assert_true(fabs((double)mc_pll_obs_tau_L_f32(&pll)) <= 1e-4);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_design_gains_give_triple_pole),
        cmocka_unit_test(test_tracks_speed_ramp_with_designed_poles),
        cmocka_unit_test(test_load_estimate_with_torque_feedforward),
        cmocka_unit_test(test_init_rejects_invalid_params),
        cmocka_unit_test(test_nonfinite_and_bounds),
        cmocka_unit_test(test_update_against_double),
        cmocka_unit_test(test_vector_detector),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
