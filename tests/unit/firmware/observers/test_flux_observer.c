/*
 * Gradient flux / position observer (paper 001 (12)-(14)):
 * - on exact motor trajectories (currents and applied mean voltages from the
 *   alpha-beta model (2)-(4), generated here in double), the position error
 *   in the rotor frame follows the linearised error dynamics (30)-(31),
 *   chi' = A22 chi, and decays at its slowest eigenvalue's rate;
 * - the Euler step's radial contraction is 1 - 2 gamma Phi^2 Ts per sample,
 *   so init's bound Ts < 1/(gamma Phi^2) is exactly the stability limit;
 * - aligned start, non-finite inputs;
 * - the ISR's unchecked step is the checked step's arithmetic, and its
 *   finiteness report covers inputs, fluxes and state.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mc/angle.h"
#include "mc/flux_observer.h"
#include "paper001_motor.h"
#include "test_expm2.h"
#include "test_rng.h"

#define GAMMA 5000.0
#define GPHI2 (GAMMA * P001_FLUX_WB * P001_FLUX_WB) /* gamma Phi^2, 1/s */

static mc_flux_obs_params_t paper_params(void)
{
    const mc_flux_obs_params_t p = {
        .R_ohm = (float)P001_R_OHM,
        .L_H = (float)P001_L_H,
        .psi_Wb = (float)P001_FLUX_WB,
        .gamma = (float)GAMMA,
        .Ts_s = (float)P001_TS_S,
    };
    return p;
}

/* Motor at constant electrical speed w_e with constant d/q currents:
 * theta(t) = th0 + w_e t, i_ab = e^{J theta} [id; iq]. Applied mean voltage
 * over [t0, t1] from (2): int v dt = lambda(t1) - lambda(t0) + R int i dt,
 * lambda = L i + Phi rho (26), int i dt in closed form. */
typedef struct {
    double th0, w_e, id, iq;
} traj_t;

static void traj_current(const traj_t *tr, double t, double i_ab[2])
{
    const double th = tr->th0 + tr->w_e * t;
    i_ab[0] = tr->id * cos(th) - tr->iq * sin(th);
    i_ab[1] = tr->id * sin(th) + tr->iq * cos(th);
}

static void traj_mean_voltage(const traj_t *tr, double t0, double t1, double v_ab[2])
{
    const double a0 = tr->th0 + tr->w_e * t0, a1 = tr->th0 + tr->w_e * t1;
    double i0[2], i1[2], int_i[2];
    traj_current(tr, t0, i0);
    traj_current(tr, t1, i1);
    const double ds = sin(a1) - sin(a0), dc = cos(a1) - cos(a0);
    int_i[0] = (tr->id * ds + tr->iq * dc) / tr->w_e;
    int_i[1] = (-tr->id * dc + tr->iq * ds) / tr->w_e;
    const double L = P001_L_H, R = P001_R_OHM, F = P001_FLUX_WB;
    v_ab[0] = (L * (i1[0] - i0[0]) + F * dc + R * int_i[0]) / (t1 - t0);
    v_ab[1] = (L * (i1[1] - i0[1]) + F * ds + R * int_i[1]) / (t1 - t0);
}

/* rotor-frame error chi45 = e^{-J theta}(rho_hat - rho) at time t */
static void rotor_frame_error(const mc_flux_obs_f32_t *obs, const traj_t *tr, double t,
                              double chi[2])
{
    float ra, rb;
    mc_flux_obs_rho_f32(obs, &ra, &rb);
    const double th = tr->th0 + tr->w_e * t;
    const double c = cos(th), s = sin(th);
    const double ea = (double)ra - c, eb = (double)rb - s;
    chi[0] = c * ea + s * eb;
    chi[1] = -s * ea + c * eb;
}

#define MAX_STEPS 60000 /* 3 s */
static double chi_pos[MAX_STEPS + 1][2], chi_neg[MAX_STEPS + 1][2];

/* Run the observer on the trajectory from an initial angle error delta
 * (aligned reset at th0 + delta); chi[k] = rotor-frame error at t_k. */
static void simulate(const traj_t *tr, double delta, long n, double chi[][2])
{
    mc_flux_obs_f32_t obs;
    const mc_flux_obs_params_t p = paper_params();
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_OK);
    double i_ab[2];
    traj_current(tr, 0.0, i_ab);
    assert_int_equal(
        mc_flux_obs_reset_f32(&obs, (float)(tr->th0 + delta), (float)i_ab[0], (float)i_ab[1]),
        MC_OK);
    rotor_frame_error(&obs, tr, 0.0, chi[0]);
    for (long k = 1; k <= n; k++) {
        const double t = (double)k * P001_TS_S;
        double v[2];
        traj_mean_voltage(tr, t - P001_TS_S, t, v);
        traj_current(tr, t, i_ab);
        assert_int_equal(
            mc_flux_obs_step_f32(&obs, (float)i_ab[0], (float)i_ab[1], (float)v[0], (float)v[1]),
            MC_OK);
        rotor_frame_error(&obs, tr, t, chi[k]);
    }
}

/* Odd part in delta of the error, (chi(+delta) - chi(-delta)) / 2: the
 * linear response survives, the quadratic terms of (28) cancel. */
static void odd_part(long k, double out[2])
{
    out[0] = 0.5 * (chi_pos[k][0] - chi_neg[k][0]);
    out[1] = 0.5 * (chi_pos[k][1] - chi_neg[k][1]);
}

typedef struct {
    double max_dev_rel; /* max |odd - exp(A22 t) odd0| / |odd0| */
    double rate_meas;   /* ln(|odd(t_a + T)| / |odd(t_a)|) / T */
} flux_run_t;

static flux_run_t measure(const traj_t *tr, double delta, double t_end, double t_a, double T_rate)
{
    const long n = lround(t_end / P001_TS_S);
    assert_true(n <= MAX_STEPS);
    simulate(tr, delta, n, chi_pos);
    simulate(tr, -delta, n, chi_neg);
    const mat2_t A22 = { -2.0 * GPHI2, tr->w_e, -tr->w_e, 0.0 };
    double o0[2];
    odd_part(0, o0);
    const double n0 = hypot(o0[0], o0[1]);
    flux_run_t r = { 0.0, 0.0 };
    for (long k = 1; k <= n; k++) {
        double o[2], lin[2];
        odd_part(k, o);
        expm2_apply(A22, (double)k * P001_TS_S, o0, lin);
        r.max_dev_rel = fmax(r.max_dev_rel, hypot(o[0] - lin[0], o[1] - lin[1]) / n0);
    }
    const long k_a = lround(t_a / P001_TS_S);
    const long k_b = lround((t_a + T_rate) / P001_TS_S);
    double oa[2], ob[2];
    odd_part(k_a, oa);
    odd_part(k_b, ob);
    r.rate_meas =
        log(hypot(ob[0], ob[1]) / hypot(oa[0], oa[1])) / ((double)(k_b - k_a) * P001_TS_S);
    return r;
}

/* Eigenvalues (as continuous rates ln(z)/Ts) of the Euler-discretised
 * linearisation: the sampled trajectory rotates the rotor-frame error
 * exactly, the explicit correction contracts its d component:
 * chi_k = Rot(-w_e Ts) diag(1 - 2 gamma Phi^2 Ts, 1) chi_{k-1}.
 * Returns the slowest real part. */
static double euler_slow_rate(double w_e)
{
    const double c = 2.0 * GPHI2 * P001_TS_S, ph = w_e * P001_TS_S;
    const double tr = (2.0 - c) * cos(ph), det = 1.0 - c;
    const double disc = tr * tr / 4.0 - det;
    const double mag = disc >= 0.0 ? tr / 2.0 + sqrt(disc) : sqrt(det);
    return log(mag) / P001_TS_S;
}

/* Low speed, 120 rpm (the paper's top benchmark speed): w_e = 37.7 rad/s
 * < gamma Phi^2, two real poles; the angle error decays at the slow one,
 * about -w_e^2 / (2 gamma Phi^2) = -5.0 1/s. Seeded random initial angle
 * and load current, both directions. delta = +-0.01 rad; the odd part
 * removes the quadratic terms (they are large here: relative size
 * gamma Phi^2 |chi| / |w_e| = 4 % at 0.01 rad). Tolerances: explicit Euler
 * moves the slow pole by 0.75 % (euler_slow_rate: -4.967 vs -5.004 1/s),
 * measured within 0.2 % of that; trajectory within 1 % of |chi0|. */
static void test_error_decays_at_linearised_rate_low_speed(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(120);
    for (int trial = 0; trial < 4; trial++) {
        const double sign = (trial % 2) ? 1.0 : -1.0;
        const traj_t tr = { test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI),
                            sign * 120.0 * MC_TEST_RAD_S_PER_RPM * P001_NP, 0.0,
                            test_rng_range(&rng, -3.0, 3.0) };
        const mat2_t A22 = { -2.0 * GPHI2, tr.w_e, -tr.w_e, 0.0 };
        double re[2], im;
        eig2(A22, re, &im);
        assert_true(im == 0.0);
        const double slow = re[1];
        assert_true(fabs(slow - (-tr.w_e * tr.w_e / (2.0 * GPHI2))) < 0.02 * fabs(slow));
        const double slow_euler = euler_slow_rate(tr.w_e);
        const flux_run_t r = measure(&tr, 0.01, 0.6, 0.1, 0.5);
        printf("  w_e = %.1f rad/s: slow pole %.4f 1/s (Euler %.4f), "
               "measured %.4f 1/s, max dev from linear %.3g of |chi0|\n",
               tr.w_e, slow, slow_euler, r.rate_meas, r.max_dev_rel);
        assert_true(r.max_dev_rel < 0.01);
        assert_true(fabs(slow_euler - slow) < 0.008 * fabs(slow));
        assert_true(fabs(r.rate_meas - slow_euler) < 0.002 * fabs(slow));
    }
}

/* Higher speeds, w_e > gamma Phi^2: complex poles with real part
 * -gamma Phi^2 = -144.5 1/s (Euler: ln(1 - 2 gamma Phi^2 Ts)/(2 Ts) =
 * -145.55 1/s). |chi| is exp(sigma t) times a function of period
 * pi / w_d, so the rate is measured over exactly that period. */
static void test_error_decays_at_linearised_rate_high_speed(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(300);
    const double speeds_e[3] = { 300.0, -650.0, 1500.0 };
    for (int i = 0; i < 3; i++) {
        const traj_t tr = { test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI), speeds_e[i],
                            test_rng_range(&rng, -1.0, 1.0), test_rng_range(&rng, -5.0, 5.0) };
        const mat2_t A22 = { -2.0 * GPHI2, tr.w_e, -tr.w_e, 0.0 };
        double re[2], im;
        eig2(A22, re, &im);
        assert_true(im > 0.0);
        assert_near(re[0], -GPHI2, 1e-9);
        const double sigma_euler = euler_slow_rate(tr.w_e);
        const double period = MC_TEST_PI / im;
        const flux_run_t r = measure(&tr, 0.01, 0.06, 0.005, period);
        printf("  w_e = %.0f rad/s: sigma %.2f 1/s (Euler %.2f), measured "
               "%.2f 1/s, max dev %.3g of |chi0|\n",
               tr.w_e, re[0], sigma_euler, r.rate_meas, r.max_dev_rel);
        assert_true(r.max_dev_rel < 0.01);
        assert_true(fabs(r.rate_meas - re[0]) < 0.015 * GPHI2);
    }
}

/* After convergence the estimate is exact to float32 accuracy: from a
 * 0.01 rad error, over the last 0.5 s of 3 s, at 120 rpm (decay
 * 0.01 e^{-4.97 * 2.5} = 4e-8 left) and at w_e = 300 rad/s. The floor is
 * float32 rounding of the flux integration (~1e-6 relative). */
static void test_converged_estimate_accuracy(void **state)
{
    (void)state;
    const traj_t trs[2] = { { 0.3, 120.0 * MC_TEST_RAD_S_PER_RPM * P001_NP, 0.0, 2.0 },
                            { -1.0, 300.0, 0.5, -4.0 } };
    for (int i = 0; i < 2; i++) {
        const long n = MAX_STEPS;
        simulate(&trs[i], 0.01, n, chi_pos);
        double max_err = 0.0;
        for (long k = n - 10000; k <= n; k++) {
            max_err = fmax(max_err, hypot(chi_pos[k][0], chi_pos[k][1]));
        }
        printf("  w_e = %.1f rad/s: max |rho_hat - rho| over the last 0.5 s "
               "%.3g\n",
               trs[i].w_e, max_err);
        assert_true(max_err < 1e-5);
    }
}

/* The Euler bound. A voltage kick moves eta off the circle |eta| = Phi at
 * standstill; the radial error then shrinks by the factor
 * 1 - 2 gamma Phi^2 Ts per sample (linearisation), which reaches -1 at
 * Ts = 1/(gamma Phi^2): init must accept below and reject at and above. */
static void test_euler_radial_factor_and_bound(void **state)
{
    (void)state;
    const double bound = 1.0 / GPHI2; /* 6.92 ms */
    const double fractions[4] = { 0.007, 0.25, 0.6, 0.95 };
    for (int i = 0; i < 4; i++) {
        mc_flux_obs_params_t p = paper_params();
        const double Ts = fractions[i] * bound;
        p.Ts_s = (float)Ts;
        mc_flux_obs_f32_t obs;
        assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_OK);
        assert_int_equal(mc_flux_obs_reset_f32(&obs, 0.4f, 0.0f, 0.0f), MC_OK);
        /* radial kick of 1e-4 Wb along the flux direction */
        const float kick_V = (float)(1e-4 / Ts);
        assert_int_equal(
            mc_flux_obs_step_f32(&obs, 0.0f, 0.0f, kick_V * cosf(0.4f), kick_V * sinf(0.4f)),
            MC_OK);
        double prev = sqrt((double)mc_flux_obs_rho_sq_f32(&obs)) - 1.0;
        double ratio = 0.0;
        for (int k = 0; k < 3; k++) {
            assert_int_equal(mc_flux_obs_step_f32(&obs, 0.0f, 0.0f, 0.0f, 0.0f), MC_OK);
            const double now = sqrt((double)mc_flux_obs_rho_sq_f32(&obs)) - 1.0;
            ratio = now / prev;
            prev = now;
        }
        const double expect = 1.0 - 2.0 * GPHI2 * Ts;
        assert_true(fabs(ratio - expect) < 2e-3);
        /* and the angle is not disturbed by a radial kick */
        assert_near(mc_flux_obs_theta_e_f32(&obs), 0.4f, 1e-5f);
    }
    /* init: accept iff Ts gamma Phi^2 < 1, over random gamma, Phi, Ts */
    test_rng_t rng = test_rng_seed(6900);
    int n_acc = 0, n_rej = 0;
    for (int i = 0; i < 5000; i++) {
        mc_flux_obs_params_t p = paper_params();
        const double g = exp(test_rng_range(&rng, log(10.0), log(1e6)));
        const double phi = test_rng_range(&rng, 0.005, 1.0);
        const double Ts = exp(test_rng_range(&rng, log(1e-6), log(0.1)));
        p.gamma = (float)g;
        p.psi_Wb = (float)phi;
        p.Ts_s = (float)Ts;
        const double margin = Ts * g * phi * phi;
        if (fabs(margin - 1.0) < 1e-5) {
            continue;
        }
        mc_flux_obs_f32_t obs;
        const mc_status_t st = mc_flux_obs_init_f32(&obs, &p);
        assert_int_equal(st, margin < 1.0 ? MC_OK : MC_ERR_PARAM);
        n_acc += (st == MC_OK);
        n_rej += (st != MC_OK);
    }
    assert_true(n_acc > 500 && n_rej > 500);
    /* paper values: bound 6.920 ms */
    mc_flux_obs_params_t p = paper_params();
    mc_flux_obs_f32_t obs;
    p.Ts_s = (float)(bound * 0.999);
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_OK);
    p.Ts_s = (float)bound;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_PARAM);
    p.Ts_s = 7.0e-3f;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_PARAM);
}

static void test_init_rejects_invalid_params(void **state)
{
    (void)state;
    mc_flux_obs_f32_t obs;
    mc_flux_obs_params_t p = paper_params();
    p.L_H = 0.0f;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_PARAM);
    p = paper_params();
    p.R_ohm = -0.1f;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_PARAM);
    p = paper_params();
    p.psi_Wb = -0.17f;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_PARAM);
    p = paper_params();
    p.gamma = 0.0f;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_PARAM);
    p = paper_params();
    p.Ts_s = INFINITY;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_NONFINITE);
    p = paper_params();
    p.R_ohm = NAN;
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_ERR_NONFINITE);
}

/* Aligned start: eta = Phi [cos; sin] exactly, whatever the current. */
static void test_reset_to_aligned_angle(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(5);
    mc_flux_obs_f32_t obs;
    const mc_flux_obs_params_t p = paper_params();
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_OK);
    assert_near(mc_flux_obs_theta_e_f32(&obs), 0.0f, 0.0f);
    for (int i = 0; i < 1000; i++) {
        const double th = test_rng_range(&rng, -50.0, 50.0);
        const float ia = (float)test_rng_range(&rng, -10.0, 10.0);
        const float ib = (float)test_rng_range(&rng, -10.0, 10.0);
        assert_int_equal(mc_flux_obs_reset_f32(&obs, (float)th, ia, ib), MC_OK);
        const double err = remainder((double)mc_flux_obs_theta_e_f32(&obs) - th, MC_TEST_TWO_PI);
        assert_true(fabs(err) < 2e-5);
        assert_near(mc_flux_obs_rho_sq_f32(&obs), 1.0f, 1e-5f);
        float ra, rb;
        mc_flux_obs_rho_f32(&obs, &ra, &rb);
        assert_near(ra, cos(th), 3e-6);
        assert_near(rb, sin(th), 3e-6);
        /* i^T Jcal rho_hat is the q current for the true angle */
        const double iq = -(double)ia * sin(th) + (double)ib * cos(th);
        assert_near(mc_flux_obs_iq_f32(&obs, ia, ib), iq, 1e-4);
    }
}

static void test_nonfinite_inputs_leave_state_untouched(void **state)
{
    (void)state;
    mc_flux_obs_f32_t obs;
    const mc_flux_obs_params_t p = paper_params();
    assert_int_equal(mc_flux_obs_init_f32(&obs, &p), MC_OK);
    assert_int_equal(mc_flux_obs_reset_f32(&obs, 1.0f, 0.5f, -0.2f), MC_OK);
    assert_int_equal(mc_flux_obs_step_f32(&obs, 0.5f, -0.2f, 3.0f, 1.0f), MC_OK);
    mc_flux_obs_f32_t before;
    memcpy(&before, &obs, sizeof obs);
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    for (int b = 0; b < 3; b++) {
        for (int pos = 0; pos < 4; pos++) {
            float in[4] = { 0.5f, -0.2f, 3.0f, 1.0f };
            in[pos] = bad[b];
            assert_int_equal(mc_flux_obs_step_f32(&obs, in[0], in[1], in[2], in[3]),
                             MC_ERR_NONFINITE);
            assert_memory_equal(&before, &obs, sizeof obs);
        }
        assert_int_equal(mc_flux_obs_reset_f32(&obs, bad[b], 0.0f, 0.0f), MC_ERR_NONFINITE);
        assert_memory_equal(&before, &obs, sizeof obs);
    }
    /* finite inputs whose flux update overflows: reported, untouched */
    assert_int_equal(mc_flux_obs_step_f32(&obs, 0.5f, -0.2f, FLT_MAX, 0.0f),
                     MC_OK); /* Ts * FLT_MAX is finite */
    memcpy(&before, &obs, sizeof obs);
    assert_int_equal(mc_flux_obs_step_f32(&obs, -FLT_MAX, -0.2f, 0.0f, 0.0f), MC_ERR_NONFINITE);
    assert_memory_equal(&before, &obs, sizeof obs);
}

/* An observer with the paper's parameters on trajectory *tr, started at
 * its t = 0 with 1.5 rad of angle error (about a quarter turn). */
static void start_with_error(const traj_t *tr, mc_flux_obs_f32_t *obs)
{
    const mc_flux_obs_params_t p = paper_params();
    assert_int_equal(mc_flux_obs_init_f32(obs, &p), MC_OK);
    double i_ab[2];
    traj_current(tr, 0.0, i_ab);
    assert_int_equal(
        mc_flux_obs_reset_f32(obs, (float)(tr->th0 + 1.5), (float)i_ab[0], (float)i_ab[1]), MC_OK);
}

/* Sample k of *tr: the currents at k Ts and the mean voltage over the
 * interval before, in float. */
static void traj_sample(const traj_t *tr, long k, float i_ab[2], float v_ab[2])
{
    const double t = (double)k * P001_TS_S;
    double v[2], i[2];
    traj_mean_voltage(tr, t - P001_TS_S, t, v);
    traj_current(tr, t, i);
    for (int j = 0; j < 2; j++) {
        i_ab[j] = (float)i[j];
        v_ab[j] = (float)v[j];
    }
}

/* The ISR's step (mc_flux_obs_update_f32, unchecked) is the checked
 * step's arithmetic: along a motor trajectory (a quarter turn of error at
 * the start, so the observer converges through every octant of its atan2)
 * both leave the same state, bit for bit, and the update reports +-0.
 * Its report is NaN for a non-finite current or voltage (also with R = 0,
 * where 0 * Inf is the NaN) and for a flux that overflows; the NaN
 * reaches the state, and a reset clears it. */
static void test_update_is_the_checked_step(void **state)
{
    (void)state;
    const traj_t tr = { 0.3, 2.0 * MC_TEST_PI * 20.0, 1.0, 4.0 };
    mc_flux_obs_f32_t checked, isr;
    start_with_error(&tr, &checked);
    memcpy(&isr, &checked, sizeof isr);
    for (long k = 1; k <= 8000; k++) {
        float i[2], v[2];
        traj_sample(&tr, k, i, v);
        assert_int_equal(mc_flux_obs_step_f32(&checked, i[0], i[1], v[0], v[1]), MC_OK);
        assert_true(mc_flux_obs_update_f32(&isr, i[0], i[1], v[0], v[1], true) == 0.0f);
        assert_memory_equal(&checked, &isr, sizeof isr);
    }
    const float bad[3] = { NAN, INFINITY, -INFINITY };
    for (int zero_r = 0; zero_r < 2; zero_r++) {
        mc_flux_obs_f32_t base = isr;
        if (zero_r) {
            base.R_ohm = 0.0f;
            base.half_R_ohm = 0.0f;
        }
        for (int b = 0; b < 3; b++) {
            for (int pos = 0; pos < 4; pos++) {
                float in[4] = { 0.5f, -0.2f, 3.0f, 1.0f };
                in[pos] = bad[b];
                mc_flux_obs_f32_t x = base;
                assert_true(isnan(mc_flux_obs_update_f32(&x, in[0], in[1], in[2], in[3], true)));
                assert_false(isfinite(x.eta_alpha_Wb) && isfinite(x.eta_beta_Wb));
                assert_int_equal(mc_flux_obs_reset_f32(&x, 1.0f, 0.5f, -0.2f), MC_OK);
                assert_true(mc_flux_obs_update_f32(&x, 0.5f, -0.2f, 3.0f, 1.0f, true) == 0.0f);
            }
        }
    }
    /* finite inputs, a flux that overflows (as in the test above) */
    mc_flux_obs_f32_t x = isr;
    assert_true(mc_flux_obs_update_f32(&x, 0.5f, -0.2f, FLT_MAX, 0.0f, true) == 0.0f);
    assert_true(isnan(mc_flux_obs_update_f32(&x, -FLT_MAX, -0.2f, 0.0f, 0.0f, true)));
}

/* Bit equality; any NaN equals any NaN. */
static int same_float(float a, float b)
{
    return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

/* The advanced angle (exact_angle false: the last angle plus the angle
 * between the last two eta), with an exact step every 10th sample as the
 * drive takes one on every slow tick: along motor trajectories at 126 and
 * 3000 rad/s electrical (6.3e-3 and 0.15 rad per sample: the small-angle
 * series and its atan2 fallback), from a quarter turn of error, the flux
 * is the exact steps' bit for bit (the angle does not feed back), the
 * angle stays within atan2's own bound (1e-6 rad, at the anchor) plus
 * nine advances of at most 2e-7 rad each (the sum's rounding, half an ulp
 * of pi, and the increment's) of the double atan2 of eta, and the
 * increment is the angle's wrapped difference. Never anchored, the angle
 * drifts by the additions' rounding: reported. */
static void test_advanced_angle(void **state)
{
    (void)state;
    const double speeds_e[2] = { 2.0 * MC_TEST_PI * 20.0, 3000.0 };
    for (int sp = 0; sp < 2; sp++) {
        const traj_t tr = { 0.3, speeds_e[sp], 1.0, 4.0 };
        mc_flux_obs_f32_t exact, adv, never;
        start_with_error(&tr, &exact);
        adv = exact;
        never = exact;
        double max_err = 0.0, max_err_never = 0.0, max_d_err = 0.0;
        for (long k = 1; k <= 20000; k++) {
            float i[2], v[2];
            traj_sample(&tr, k, i, v);
            const float th_prev = adv.theta_e_rad;
            assert_true(mc_flux_obs_update_f32(&exact, i[0], i[1], v[0], v[1], true) == 0.0f);
            assert_true(mc_flux_obs_update_f32(&adv, i[0], i[1], v[0], v[1], k % 10 == 0) == 0.0f);
            assert_true(mc_flux_obs_update_f32(&never, i[0], i[1], v[0], v[1], false) == 0.0f);
            assert_true(adv.eta_alpha_Wb == exact.eta_alpha_Wb &&
                        adv.eta_beta_Wb == exact.eta_beta_Wb);
            const double th_eta = atan2((double)adv.eta_beta_Wb, (double)adv.eta_alpha_Wb);
            max_err =
                fmax(max_err, fabs(remainder((double)adv.theta_e_rad - th_eta, MC_TEST_TWO_PI)));
            max_err_never = fmax(
                max_err_never, fabs(remainder((double)never.theta_e_rad - th_eta, MC_TEST_TWO_PI)));
            assert_true(adv.theta_e_rad > -MC_PI_F && adv.theta_e_rad <= MC_PI_F);
            max_d_err =
                fmax(max_d_err,
                     fabs(remainder((double)adv.theta_e_rad - (double)th_prev, MC_TEST_TWO_PI) -
                          (double)mc_flux_obs_d_theta_e_f32(&adv)));
        }
        printf("w_e %.0f rad/s: advanced angle max error %.3g rad (anchored every 10th), %.3g rad "
               "(never), increment %.3g rad\n",
               speeds_e[sp], max_err, max_err_never, max_d_err);
        assert_true(max_err <= MC_ATAN2_MAX_ERR_RAD + 9.0 * 2e-7);
        assert_true(max_d_err <= 5e-7);
    }
}

/* The observer's angle (13) comes from mc_atan2_unchecked_f32: for finite
 * inputs mc_atan2_f32's float (signed zeros, both axes, the diagonals,
 * subnormal to huge magnitudes, a seeded random cloud). */
static void test_unchecked_atan2_is_atan2(void **state)
{
    (void)state;
    const float v[] = { 0.0f, -0.0f, FLT_TRUE_MIN, -FLT_TRUE_MIN, FLT_MIN, 1e-20f,   0.17f,  -0.17f,
                        1.0f, -1.0f, 3.0f,         -7.5f,         1e30f,   -FLT_MAX, FLT_MAX };
    const size_t n = sizeof v / sizeof v[0];
    for (size_t i = 0; i < n; i++) {
        for (size_t j = 0; j < n; j++) {
            assert_true(same_float(mc_atan2_unchecked_f32(v[i], v[j]), mc_atan2_f32(v[i], v[j])));
        }
    }
    test_rng_t rng = test_rng_seed(11u);
    for (int k = 0; k < 1000000; k++) {
        const float y = (float)test_rng_range(&rng, -0.3, 0.3);
        const float x = (float)test_rng_range(&rng, -0.3, 0.3);
        assert_true(same_float(mc_atan2_unchecked_f32(y, x), mc_atan2_f32(y, x)));
        assert_true(same_float(mc_atan2_unchecked_f32(y, y), mc_atan2_f32(y, y)));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_error_decays_at_linearised_rate_low_speed),
        cmocka_unit_test(test_error_decays_at_linearised_rate_high_speed),
        cmocka_unit_test(test_converged_estimate_accuracy),
        cmocka_unit_test(test_euler_radial_factor_and_bound),
        cmocka_unit_test(test_init_rejects_invalid_params),
        cmocka_unit_test(test_reset_to_aligned_angle),
        cmocka_unit_test(test_nonfinite_inputs_leave_state_untouched),
        cmocka_unit_test(test_update_is_the_checked_step),
        cmocka_unit_test(test_advanced_angle),
        cmocka_unit_test(test_unchecked_atan2_is_atan2),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
