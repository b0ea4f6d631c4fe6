/*
 * Current-limit loop on the measured current (mc/current_limit.h) against
 * an independent double-precision R-L model of the paper-001 motor
 * (R 0.225 ohm, L 3.8 mH, exact zero-order-hold discretisation, no
 * back-EMF) at 20 kHz with w_c = 2513 rad/s; the "controller" commands a
 * constant voltage whose steady current is 3x the limit.
 *
 * Along the current's direction the loop is (kp + ki/s)/(L s + R) = w_c/s
 * (mc/current_limit.h): from the steady state at 3 I_lim (the plant's slow
 * pole R/L is then not excited) the excess current |i| - I_lim decays as
 * exp(-w_c t).
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/current_limit.h"
#include "paper001_motor.h"

#define LIMIT_A 12.0
#define WC      2513.0
#define TS      P001_TS_S
#define DIR_RAD 0.7 /* direction of the commanded voltage (both axes used) */

static mc_current_limit_params_t paper_params(void)
{
    return (mc_current_limit_params_t){
        .limit_A = (float)LIMIT_A,
        .R_ohm = (float)P001_R_OHM,
        .L_H = (float)P001_L_H,
        .bandwidth_rad_s = (float)WC,
        .Ts_s = (float)TS,
    };
}

static void init_paper(mc_current_limit_f32_t *cl)
{
    const mc_current_limit_params_t p = paper_params();
    assert_int_equal(mc_current_limit_init_f32(cl, &p), MC_OK);
}

/* The plant: L di/dt = v - R i per axis (no rotation, no back-EMF), v held
 * over the sample: i <- a i + (1 - a)/R v, a = exp(-R Ts / L). */
typedef struct {
    double a, b;
    double i[2];
} rl_plant_t;

static rl_plant_t plant(double i_d, double i_q)
{
    const double a = exp(-P001_R_OHM * TS / P001_L_H);
    return (rl_plant_t){ .a = a, .b = (1.0 - a) / P001_R_OHM, .i = { i_d, i_q } };
}

static void plant_step(rl_plant_t *p, float v_d, float v_q)
{
    p->i[0] = p->a * p->i[0] + p->b * (double)v_d;
    p->i[1] = p->a * p->i[1] + p->b * (double)v_q;
}

/* One closed-loop sample: the limiter sees the plant's current (float) and
 * corrects the command v0; the corrected command drives the plant. */
static bool loop_step(mc_current_limit_f32_t *cl, rl_plant_t *p, double v0)
{
    float v_d = (float)(v0 * cos(DIR_RAD));
    float v_q = (float)(v0 * sin(DIR_RAD));
    const bool acts = mc_current_limit_step_f32(cl, (float)p->i[0], (float)p->i[1], &v_d, &v_q);
    plant_step(p, v_d, v_q);
    return acts;
}

static double mag(const rl_plant_t *p)
{
    return hypot(p->i[0], p->i[1]);
}

/* Direction of the current against the commanded voltage's. Bound: the
 * correction is along i, so in exact arithmetic i stays on the command's
 * line. Float rounding of v_d, v_q (half an ulp of |v| < 16.2 V: 9.5e-7 V)
 * enters each sample; the perpendicular current is damped at least by R
 * (time constant L/R), so it stays below 9.5e-7 V / R = 4.2e-6 A, i.e.
 * 4.2e-6 / |i| rad; the float conversion of i adds 6e-8 rad. At |i| >=
 * 0.5 I_lim = 6 A: 7.1e-7 rad; tolerance 1e-6 rad. */
#define DIR_TOL_RAD 1e-6

static void assert_direction_kept(const rl_plant_t *p)
{
    assert_near(remainder(atan2(p->i[1], p->i[0]) - DIR_RAD, MC_TEST_TWO_PI), 0.0, DIR_TOL_RAD);
}

/* Steady state of the float loop: the integral stops moving once
 * ki Ts |e| is below half an ulp of u_I (u_I = 2 R I_lim = 5.4 V: ulp
 * 4.8e-7 V): |e| < 2.4e-7 / (R w_c Ts = 0.0283) = 8.4e-6 A; |i| in float
 * (i^2 summed and square-rooted) is off by <= 2 ulp(12 A) = 1.9e-6 A.
 * Bound 1.03e-5 A; tolerance 1.1e-5 A. */
#define SS_TOL_A 1.1e-5

/* (a) Below the limit (and at it: "above" is strict) with the integral at
 * zero the command passes bit-unchanged, the function returns false and
 * the state does not change. */
static void test_below_limit_passes_unchanged(void **state)
{
    (void)state;
    mc_current_limit_f32_t cl;
    init_paper(&cl);
    const float L = (float)LIMIT_A;
    const float cur[][2] = {
        { 0.0f, 0.0f },   { 1.0f, -2.0f },   { -8.0f, 8.0f },    { 11.999f, 0.0f },
        { L, 0.0f },      { 0.0f, -L },      { -L, 0.0f },       { 0.0f, nextafterf(L, 0.0f) },
        { 7.2f, -9.59f }, { -0.0f, 1e-30f }, { 8.485f, 8.485f }, /* |i| = 11.9996 */
    };
    const float cmd[][2] = {
        { 0.0f, 0.0f }, { 10.0f, -3.5f }, { -0.0f, 1e-40f }, { 1e30f, -1e30f }, { NAN, INFINITY },
    };
    for (size_t i = 0; i < sizeof cur / sizeof cur[0]; ++i) {
        for (size_t j = 0; j < sizeof cmd / sizeof cmd[0]; ++j) {
            float v[2] = { cmd[j][0], cmd[j][1] };
            const mc_current_limit_f32_t before = cl;
            const bool acts = mc_current_limit_step_f32(&cl, cur[i][0], cur[i][1], &v[0], &v[1]);
            assert_false(acts);
            assert_memory_equal(v, cmd[j], sizeof v);
            assert_memory_equal(&cl, &before, sizeof cl);
        }
    }
    /* One ulp above the limit: it acts and pulls the command back. */
    float v[2] = { 10.0f, 0.0f };
    assert_true(mc_current_limit_step_f32(&cl, nextafterf(L, 100.0f), 0.0f, &v[0], &v[1]));
    assert_true(v[0] < 10.0f);
    assert_true(cl.u_int_V > 0.0f);
}

/* The 1/e and 1/e^2 points of the excess current, from the samples by
 * log-linear interpolation (exact for a geometric sequence). */
static double crossing_time(const double *e, int n, double level)
{
    for (int k = 1; k < n; ++k) {
        if (e[k] <= level) {
            return TS * ((k - 1) + log(e[k - 1] / level) / log(e[k - 1] / e[k]));
        }
    }
    return NAN;
}

/* (b) From the steady state of a command that drives 3 I_lim: the excess
 * decays first order with time constant 1/w_c, |i| converges to the limit,
 * the direction is kept.
 *
 * Expected excess time constant: the discrete loop (ZOH plant, backward-
 * Euler integral) has the dominant pole z1 = 1 - b (kp + ki Ts) = 1 - w_c
 * Ts (1 + R Ts / 2L) (the other pole nearly cancels the PI zero), so
 * tau_d = -Ts / ln z1 = 1/w_c - Ts/2 - w_c Ts^2/12 - (R Ts / 2L) / w_c:
 * the zero-order hold advances the response by half a sample. Expected
 * t63 = 1/w_c - Ts/2; the remaining terms: x Ts/12 = 0.0105 Ts (x = w_c
 * Ts = 0.126), the gain term 0.0015 * 7.5 Ts = 0.011 Ts, the residual of
 * the near cancellation (pole a vs zero 1/(1 + R Ts/L): 4.4e-6) < 1e-3 Ts,
 * float rounding of the correction (1e-7 relative) < 1e-5 Ts: 0.023 Ts;
 * tolerance 0.03 Ts. The 1/e^2 point: 2 tau_d, so twice the deviation;
 * tolerance 0.06 Ts. */
static void test_converges_first_order_from_3x(void **state)
{
    (void)state;
    mc_current_limit_f32_t cl;
    init_paper(&cl);
    const double v0 = 3.0 * P001_R_OHM * LIMIT_A;
    rl_plant_t p = plant(3.0 * LIMIT_A * cos(DIR_RAD), 3.0 * LIMIT_A * sin(DIR_RAD));
    enum { N = 5000 }; /* 0.25 s: 100 / w_c and 15 L/R */
    static double e[N];
    for (int k = 0; k < N; ++k) {
        e[k] = mag(&p) - LIMIT_A;
        (void)loop_step(&cl, &p, v0);
        assert_direction_kept(&p);
    }
    const double e0 = 2.0 * LIMIT_A;
    const double t63 = crossing_time(e, N, e0 * exp(-1.0));
    const double t86 = crossing_time(e, N, e0 * exp(-2.0));
    print_message("t63 = %.4f Ts (1/w_c = %.4f Ts), t86 = %.4f Ts\n", t63 / TS, 1.0 / WC / TS,
                  t86 / TS);
    assert_near(t63, 1.0 / WC - 0.5 * TS, 0.03 * TS);
    assert_near(t86, 2.0 * (1.0 / WC - 0.5 * TS), 0.06 * TS);
    /* Converged: the last 0.1 s within the float steady-state bound. */
    double worst = 0.0;
    for (int k = N - 2000; k < N; ++k) {
        worst = fmax(worst, fabs(e[k]));
    }
    print_message("steady |e| <= %.3g A\n", worst);
    assert_near(worst, 0.0, SS_TOL_A);
}

/* Winding back after the command drops to v1 (steady current I1 < I_lim):
 * the plant voltage along i is at most v1 while u_I >= 0, so |i(t)| <=
 * I1 + (I_lim - I1) exp(-R t / L), e(t) <= -(I_lim - I1)(1 - exp(-R t/L)),
 * and u_I(t) <= u_0 - R w_c (I_lim - I1) (t - (L/R)(1 - exp(-R t/L))). The
 * discrete sum (backward Euler: the right end of each interval, where e is
 * lower) winds at least as fast. The sample by which u_I must be 0: the
 * root T of that bound, ceil(T/Ts), plus one sample for the float sums. */
static int wind_back_bound(double u0, double i1)
{
    const double tau = P001_L_H / P001_R_OHM;
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 200; ++it) {
        const double t = 0.5 * (lo + hi);
        const double wound = P001_R_OHM * WC * (LIMIT_A - i1) * (t - tau * (1.0 - exp(-t / tau)));
        if (wound >= u0) {
            hi = t;
        } else {
            lo = t;
        }
    }
    return (int)ceil(hi / TS) + 1;
}

/* (b) from rest and (c): a command that would drive 3 I_lim from i = 0:
 * |i| converges to the limit in its direction; then the command drops to
 * one that drives I_lim / 2: the integral winds back to exactly 0 within the
 * derived bound and from then on the command passes unchanged. */
static void test_from_rest_then_command_drops(void **state)
{
    (void)state;
    mc_current_limit_f32_t cl;
    init_paper(&cl);
    rl_plant_t p = plant(0.0, 0.0);
    const double v0 = 3.0 * P001_R_OHM * LIMIT_A;
    bool acted = false;
    for (int k = 0; k < 5000; ++k) { /* 0.25 s: 15 L/R */
        acted |= loop_step(&cl, &p, v0);
        if (mag(&p) > 1.0) {
            assert_direction_kept(&p);
        }
    }
    assert_true(acted);
    print_message("from rest: |i| - I_lim = %.3g A, u_I = %.6f V (2 R I_lim = %.6f)\n",
                  mag(&p) - LIMIT_A, (double)cl.u_int_V, 2.0 * P001_R_OHM * LIMIT_A);
    assert_near(mag(&p), LIMIT_A, SS_TOL_A);
    /* Steady state: the integral carries the excess command: u_I = v0 -
     * R |i| - kp e = 2 R I_lim - (R + kp) e with |e| <= SS_TOL_A: within
     * (R + L w_c) SS_TOL_A = 1.07e-4 V, plus the float command (9.5e-7 V):
     * tolerance 1.1e-4 V. */
    assert_near(cl.u_int_V, 2.0 * P001_R_OHM * LIMIT_A, 1.1e-4);

    const double i1 = 0.5 * LIMIT_A, v1 = P001_R_OHM * i1;
    const int bound = wind_back_bound((double)cl.u_int_V, i1);
    int k_zero = -1;
    float u_prev = cl.u_int_V;
    for (int k = 0; k < 4000; ++k) {
        const bool acts = loop_step(&cl, &p, v1);
        if (k > 0) {
            assert_true(cl.u_int_V <= u_prev); /* winding back, never up */
        }
        u_prev = cl.u_int_V;
        if (k_zero < 0 && cl.u_int_V == 0.0f) {
            k_zero = k;
        }
        if (k_zero >= 0 && k > k_zero) {
            /* Passes unchanged: not acting, the command bit-exact, no
             * state change. */
            const float v_in[2] = { (float)(v1 * cos(DIR_RAD)), (float)(v1 * sin(DIR_RAD)) };
            float v[2] = { v_in[0], v_in[1] };
            const mc_current_limit_f32_t before = cl;
            assert_false(acts);
            assert_false(
                mc_current_limit_step_f32(&cl, (float)p.i[0], (float)p.i[1], &v[0], &v[1]));
            assert_memory_equal(v, v_in, sizeof v);
            assert_memory_equal(&cl, &before, sizeof cl);
        }
    }
    print_message("u_I = 0 after %d samples (bound %d)\n", k_zero + 1, bound);
    assert_true(k_zero >= 0);
    assert_true(k_zero + 1 <= bound);
    /* And the plant settles at the new command's current: 4000 samples =
     * 11.8 L/R from at most I_lim: |i - I1| < (I_lim - I1) e^-11.8 = 4.5e-5. */
    assert_near(mag(&p), i1, 5e-5);
}

/* (d) init: non-finite values, limit <= 0, w_c Ts > 0.5 and the motor's
 * ranges are rejected, *cl untouched. */
static void test_init_rejects(void **state)
{
    (void)state;
    const mc_current_limit_params_t ok = paper_params();
    mc_current_limit_f32_t cl;
    memset(&cl, 0x5a, sizeof cl);
    mc_current_limit_f32_t pattern;
    memset(&pattern, 0x5a, sizeof pattern);
    const struct {
        size_t offset;
        float value;
        mc_status_t expected;
    } cases[] = {
#define CL_OFF(f) offsetof(mc_current_limit_params_t, f)
        { CL_OFF(limit_A), NAN, MC_ERR_NONFINITE },
        { CL_OFF(limit_A), INFINITY, MC_ERR_NONFINITE },
        { CL_OFF(R_ohm), NAN, MC_ERR_NONFINITE },
        { CL_OFF(L_H), -INFINITY, MC_ERR_NONFINITE },
        { CL_OFF(bandwidth_rad_s), INFINITY, MC_ERR_NONFINITE },
        { CL_OFF(Ts_s), NAN, MC_ERR_NONFINITE },
        { CL_OFF(limit_A), 0.0f, MC_ERR_PARAM },
        { CL_OFF(limit_A), -12.0f, MC_ERR_PARAM },
        { CL_OFF(bandwidth_rad_s), 10010.0f, MC_ERR_PARAM }, /* w_c Ts = 0.5005 */
        { CL_OFF(bandwidth_rad_s), 0.0f, MC_ERR_PARAM },
        { CL_OFF(Ts_s), 0.0f, MC_ERR_PARAM },
        { CL_OFF(Ts_s), -5e-5f, MC_ERR_PARAM },
        { CL_OFF(R_ohm), -0.01f, MC_ERR_PARAM },
        { CL_OFF(L_H), 0.0f, MC_ERR_PARAM },
        /* accepted: w_c Ts = 0.4995, R = 0, a tiny limit */
        { CL_OFF(bandwidth_rad_s), 9990.0f, MC_OK },
        { CL_OFF(R_ohm), 0.0f, MC_OK },
        { CL_OFF(limit_A), 1e-3f, MC_OK },
#undef CL_OFF
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        mc_current_limit_params_t p = ok;
        memcpy((unsigned char *)&p + cases[i].offset, &cases[i].value, sizeof(float));
        memset(&cl, 0x5a, sizeof cl);
        const mc_status_t got = mc_current_limit_init_f32(&cl, &p);
        if (got != cases[i].expected) {
            fail_msg("case %zu: got %d, expected %d", i, (int)got, (int)cases[i].expected);
        }
        if (got != MC_OK) {
            assert_memory_equal(&cl, &pattern, sizeof cl);
        } else {
            assert_true(cl.u_int_V == 0.0f); /* reset */
        }
    }
}

/* (e) A non-finite current while the loop acts propagates into the command
 * (non-finite, not a silent zero or a pass-through: NaN, or Inf/Inf = NaN
 * for an infinite current), and the command stays non-finite until the
 * loop is reset; an infinite current from rest as well. */
static void test_nonfinite_current_propagates(void **state)
{
    (void)state;
    mc_current_limit_f32_t cl;
    float v[2];
    /* from rest (the integral at 0): a NaN current is not taken for "below
     * the limit" */
    init_paper(&cl);
    v[0] = 5.0f;
    v[1] = 5.0f;
    (void)mc_current_limit_step_f32(&cl, NAN, 1.0f, &v[0], &v[1]);
    assert_false(isfinite(v[0]) || isfinite(v[1]));
    const float nonfinite[] = { NAN, INFINITY, -INFINITY };
    for (size_t n = 0; n < 3; ++n) {
        for (int axis = 0; axis < 2; ++axis) {
            /* the loop acting (u_I > 0) */
            init_paper(&cl);
            v[0] = 5.0f;
            v[1] = 5.0f;
            assert_true(mc_current_limit_step_f32(&cl, 15.0f, 0.0f, &v[0], &v[1]));
            assert_true(cl.u_int_V > 0.0f);
            v[0] = 5.0f;
            v[1] = 5.0f;
            (void)mc_current_limit_step_f32(&cl, axis == 0 ? nonfinite[n] : 1.0f,
                                            axis == 1 ? nonfinite[n] : 1.0f, &v[0], &v[1]);
            assert_true(isnan(v[0]) && isnan(v[1]));
            /* a finite current below the limit next: still non-finite */
            v[0] = 5.0f;
            v[1] = 5.0f;
            (void)mc_current_limit_step_f32(&cl, 1.0f, 1.0f, &v[0], &v[1]);
            assert_false(isfinite(v[0]) || isfinite(v[1]));
            /* ... until reset */
            mc_current_limit_reset_f32(&cl);
            v[0] = 5.0f;
            v[1] = 5.0f;
            assert_false(mc_current_limit_step_f32(&cl, 1.0f, 1.0f, &v[0], &v[1]));
            assert_true(v[0] == 5.0f && v[1] == 5.0f);
        }
    }
    /* An infinite current with the integral at zero: NaN command. */
    for (size_t n = 1; n < 3; ++n) {
        init_paper(&cl);
        v[0] = 5.0f;
        v[1] = 5.0f;
        (void)mc_current_limit_step_f32(&cl, 0.0f, nonfinite[n], &v[0], &v[1]);
        assert_true(isnan(v[0]) && isnan(v[1]));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_below_limit_passes_unchanged),
        cmocka_unit_test(test_converges_first_order_from_3x),
        cmocka_unit_test(test_from_rest_then_command_drops),
        cmocka_unit_test(test_init_rejects),
        cmocka_unit_test(test_nonfinite_current_propagates),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
