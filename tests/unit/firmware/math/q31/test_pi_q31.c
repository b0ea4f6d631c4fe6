/*
 * Q31 PI controller: step response against the analytic discrete solution,
 * windup and recovery, saturation at the extremes, parameter checks, random
 * sequences against an independent long double model of the scheme in
 * mc/pi.h, and agreement with mc_pi_f32.
 *
 * Gains are quantised by the test itself: g = frac 2^shift / 2^31 with the
 * smallest shift that keeps frac below 2^31. The expectations use those
 * quantised gains exactly (long double holds frac * e, 62 bits, exactly).
 *
 * Q31 bound after k + 1 samples (LSB = 2^-31): the P product and each of
 * the k + 1 integrator increments are rounded once to Q47 (1/2 of 2^-16
 * LSB each), the output once to Q31 (1/2 LSB); the clamps are 1-Lipschitz:
 *   |u_q31 - u_exact| <= 1/2 + (k + 2) 2^-17.
 * float32 bound (u = 2^-24), accumulated sample by sample: p = kp e costs
 * 3 u |kp e| (gain, error conversion, product); the integrator either
 * takes the increment path (previous error + 3 u |ki e| + u |I|) or the
 * to-limit path (3 u |kp e| + u |I|), and since rule 1 only selects with
 * min/max, its error is at most the larger of the two; the output sum adds
 * u |u_k|. The float gains are the quantised ones rounded to float
 * (included in the 3 u). First order in u, times 1.01.
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/pi.h"
#include "mc/pi_q31.h"
#include "q31_test_util.h"

#define F32_MARGIN 1.01

typedef struct {
    int32_t frac;
    uint8_t shift;
} gain_q_t;

static gain_q_t quantise_gain(double g)
{
    gain_q_t q = { 0, 0U };
    while (ldexp(g, -(int)q.shift) >= 1.0) {
        ++q.shift;
    }
    double frac = nearbyint(ldexp(g, 31 - (int)q.shift));
    if (frac >= 2147483648.0) { /* rounded up to 1.0: next exponent */
        ++q.shift;
        frac = nearbyint(ldexp(g, 31 - (int)q.shift));
    }
    q.frac = (int32_t)frac;
    return q;
}

static long double gain_value(gain_q_t g)
{
    return ldexpl((long double)g.frac, (int)g.shift - 31);
}

/* Independent model of mc/pi.h's scheme in long double (per unit). */
typedef struct {
    long double kp, ki_ts, lo, hi, integ;
} pi_model_t;

static long double clampl(long double x, long double lo, long double hi)
{
    return x > hi ? hi : (x < lo ? lo : x);
}

/* Rule 1 makes the new integrator a continuous, 1-Lipschitz function of
 * the state and the products (min/max/clamp only), so rounding errors pass
 * through without amplification and no decision is ill-conditioned. */
static long double model_step(pi_model_t *m, long double e)
{
    const long double p = m->kp * e;
    long double integ = m->integ + m->ki_ts * e;
    if (e > 0.0L && p + integ > m->hi) {
        integ = fmaxl(m->hi - p, m->integ);
    } else if (e < 0.0L && p + integ < m->lo) {
        integ = fminl(m->lo - p, m->integ);
    }
    m->integ = clampl(integ, m->lo, m->hi);
    return clampl(p + m->integ, m->lo, m->hi);
}

typedef struct {
    mc_pi_q31_t q;
    mc_pi_f32_t f;
    pi_model_t m;
    double f_err_integ; /* float bound on the integrator, per unit */
} pi_trio_t;

static void trio_init(pi_trio_t *t, double kp, double ki_ts, double lo, double hi)
{
    const gain_q_t gp = quantise_gain(kp), gi = quantise_gain(ki_ts);
    const int32_t lo_q = real_to_q31_sat(lo), hi_q = real_to_q31_sat(hi);
    assert_int_equal(mc_pi_init_q31(&t->q, gp.frac, gp.shift, gi.frac, gi.shift, lo_q, hi_q),
                     MC_OK);
    t->m.kp = gain_value(gp);
    t->m.ki_ts = gain_value(gi);
    t->m.lo = ldexpl((long double)lo_q, -31);
    t->m.hi = ldexpl((long double)hi_q, -31);
    t->m.integ = clampl(0.0L, t->m.lo, t->m.hi);
    /* float PI with Ts = 1 so that ki_per_s * Ts = ki_ts */
    assert_int_equal(mc_pi_init_f32(&t->f, (float)t->m.kp, (float)t->m.ki_ts, 1.0f, (float)t->m.lo,
                                    (float)t->m.hi),
                     MC_OK);
    t->f_err_integ = 0.0;
}

/* One sample of all three; checks q31 against the model (tight bound after
 * k + 1 samples) and, if check_float, against the float PI. */
static void trio_step(pi_trio_t *t, int32_t e_q, long k, int check_float)
{
    const long double e = ldexpl((long double)e_q, -31);
    const double q_bound = 0.5 + (double)(k + 2) * ldexp(1.0, -17);
    const long double integ_before = t->m.integ;
    const long double u_ref = model_step(&t->m, e);
    const int32_t u_q = mc_pi_step_q31(&t->q, e_q);
    const double err = fabs((double)((long double)u_q - ldexpl(u_ref, 31)));
    if (err > q_bound) {
        fail_msg("sample %ld: q31 %ld vs exact %.3Lf LSB: %.4f > %.4f", k, (long)u_q,
                 ldexpl(u_ref, 31), err, q_bound);
    }
    assert_true(t->q.integrator_q47 <= t->q.out_max_q47);
    assert_true(t->q.integrator_q47 >= t->q.out_min_q47);

    const float u_f = mc_pi_step_f32(&t->f, (float)e);
    const double u = U_F32;
    const double p = fabs((double)(t->m.kp * e));
    /* float integrator: either the increment path (previous error + 3 u on
     * the increment + u on the sum) or the to-limit path (3 u on p + u on
     * the difference), whichever the min/max selects: at most the larger */
    const double e_increment = t->f_err_integ + 3.0 * u * fabs((double)(t->m.ki_ts * e)) +
                               u * fabs((double)integ_before + (double)(t->m.ki_ts * e));
    const double e_to_limit = 3.0 * u * p + u * fabs((double)t->m.integ);
    t->f_err_integ = F32_MARGIN * fmax(e_increment, e_to_limit);
    if (check_float) {
        const double f_bound =
            t->f_err_integ + F32_MARGIN * (3.0 * u * p + u * fabs((double)u_ref));
        const double err_f = fabs((double)u_q - (double)u_f * Q31_SCALE);
        if (err_f > q_bound + f_bound * Q31_SCALE) {
            fail_msg("sample %ld: q31 %ld vs f32 %.2f: %.2f > %.2f", k, (long)u_q,
                     (double)u_f * Q31_SCALE, err_f, q_bound + f_bound * Q31_SCALE);
        }
    }
}

/* Step response from I = 0, unsaturated: u_k = kp e + ki Ts e (k + 1). The
 * closed form is checked here directly (not through the model). */
static void test_pi_step_response_analytic(void **state)
{
    (void)state;
    static const double gains[][2] = {
        { 0.5, 1e-3 }, { 3.7, 2e-4 },   { 0.0, 0.01 },
        { 1.0, 0.0 },  { 120.0, 0.07 }, { 0.013, 1.5e-6 },
    };
    static const double errors[] = { 0.001, -0.002, 0.0004, -1e-6, 3e-5 };
    for (size_t g = 0; g < sizeof gains / sizeof gains[0]; ++g) {
        for (size_t j = 0; j < sizeof errors / sizeof errors[0]; ++j) {
            pi_trio_t t;
            trio_init(&t, gains[g][0], gains[g][1], -0.99, 0.99);
            const int32_t e_q = real_to_q31_sat(errors[j]);
            const long double e = ldexpl((long double)e_q, -31);
            for (long k = 0; k < 2000; ++k) {
                const long double u_exact = t.m.kp * e + t.m.ki_ts * e * (long double)(k + 1);
                if (fabsl(u_exact) > 0.98L) {
                    break; /* stay clear of the limits here */
                }
                const int32_t u_q = mc_pi_step_q31(&t.q, e_q);
                const double bound = 0.5 + (double)(k + 2) * ldexp(1.0, -17);
                assert_true(fabs((double)((long double)u_q - ldexpl(u_exact, 31))) <= bound);
            }
        }
    }
}

/* The same step responses, q31 against the float PI (and the model). */
static void test_pi_step_response_vs_f32(void **state)
{
    (void)state;
    pi_trio_t t;
    trio_init(&t, 2.5, 1e-3, -0.9, 0.9);
    const int32_t e_q = real_to_q31_sat(0.01);
    for (long k = 0; k < 5000; ++k) {
        trio_step(&t, e_q, k, 1);
    }
}

/* Windup and recovery: a large error for many samples keeps the output at
 * out_max with the integrator at out_max - kp e (never beyond the limit);
 * the first sample with the opposite error brings the output strictly
 * inside, to out_max - kp e_1 + (kp + ki Ts) e_2 (e_1 > 0 the windup error,
 * e_2 < 0 the new one). */
static void test_pi_windup_recovery(void **state)
{
    (void)state;
    pi_trio_t t;
    trio_init(&t, 0.8, 0.05, -0.5, 0.5);
    const int32_t hi_q = real_to_q31_sat(0.5), lo_q = real_to_q31_sat(-0.5);
    const int32_t e1_q = real_to_q31_sat(0.3), e2_q = real_to_q31_sat(-0.01);
    const long double e1 = ldexpl((long double)e1_q, -31);
    const long double e2 = ldexpl((long double)e2_q, -31);
    long k = 0;
    for (; k < 3000; ++k) {
        trio_step(&t, e1_q, k, 1);
    }
    assert_int_equal(mc_pi_step_q31(&t.q, e1_q), hi_q);
    (void)model_step(&t.m, e1);
    (void)mc_pi_step_f32(&t.f, (float)e1);
    ++k;
    /* integrator at hi - kp e1, within the P rounding (1/2 of 2^-16 LSB) */
    assert_true(fabsl((long double)t.q.integrator_q47 - ldexpl(t.m.hi - t.m.kp * e1, 47)) <= 0.5L);

    const mc_pi_q31_t before = t.q;
    const int32_t u_q = mc_pi_step_q31(&t.q, e2_q);
    assert_true(u_q < hi_q);
    const long double u_exact = t.m.hi - t.m.kp * e1 + (t.m.kp + t.m.ki_ts) * e2;
    /* P and increment and the stored P: three 2^-17 terms, output 1/2 */
    assert_true(fabs((double)((long double)u_q - ldexpl(u_exact, 31))) <=
                0.5 + 3.0 * ldexp(1.0, -17));
    /* and the sequence continues down, matching model and float */
    t.q = before;
    for (long n = 0; n < 3000; ++n, ++k) {
        trio_step(&t, e2_q, k, 1);
    }
    /* negative windup, then recovery from out_min */
    for (long n = 0; n < 3000; ++n, ++k) {
        trio_step(&t, real_to_q31_sat(-0.4), k, 1);
    }
    assert_true(t.q.integrator_q47 >= t.q.out_min_q47);
    assert_int_equal(mc_pi_step_q31(&t.q, real_to_q31_sat(-0.4)), lo_q);
    assert_true(mc_pi_step_q31(&t.q, real_to_q31_sat(0.001)) > lo_q);
}

/* Full-scale errors with the largest gains and full-scale limits: every
 * output is the saturated value, nothing wraps (UBSan traps signed
 * overflow), the integrator stays inside the limits. */
static void test_pi_extremes_saturate(void **state)
{
    (void)state;
    mc_pi_q31_t pi;
    assert_int_equal(mc_pi_init_q31(&pi, INT32_MAX, MC_PI_Q31_MAX_SHIFT, INT32_MAX,
                                    MC_PI_Q31_MAX_SHIFT, INT32_MIN, INT32_MAX),
                     MC_OK);
    for (int n = 0; n < 1000; ++n) {
        assert_int_equal(mc_pi_step_q31(&pi, INT32_MAX), INT32_MAX);
        assert_true(pi.integrator_q47 <= pi.out_max_q47);
    }
    /* kp e = -2^14 dominates whatever the integrator holds */
    assert_int_equal(mc_pi_step_q31(&pi, INT32_MIN), INT32_MIN);
    for (int n = 0; n < 1000; ++n) {
        assert_int_equal(mc_pi_step_q31(&pi, INT32_MIN), INT32_MIN);
        assert_true(pi.integrator_q47 >= pi.out_min_q47);
    }
    /* alternating extremes */
    for (int n = 0; n < 1000; ++n) {
        const int32_t e = (n & 1) ? INT32_MIN : INT32_MAX;
        assert_int_equal(mc_pi_step_q31(&pi, e), e);
    }
    /* a reset far outside the limits is clamped by the next step */
    assert_int_equal(mc_pi_set_limits_q31(&pi, -(1 << 29), 1 << 29), MC_OK);
    mc_pi_reset_q31(&pi, INT32_MAX);
    assert_int_equal(mc_pi_step_q31(&pi, 0), 1 << 29);
    mc_pi_reset_q31(&pi, INT32_MIN);
    assert_int_equal(mc_pi_step_q31(&pi, 0), -(1 << 29));
}

static void test_pi_params(void **state)
{
    (void)state;
    mc_pi_q31_t pi, before;
    memset(&pi, 0x3C, sizeof pi);
    before = pi;
    const int32_t one_half = 1 << 30;
    assert_int_equal(mc_pi_init_q31(&pi, -1, 0U, one_half, 0U, -one_half, one_half), MC_ERR_PARAM);
    assert_int_equal(mc_pi_init_q31(&pi, one_half, 0U, -1, 0U, -one_half, one_half), MC_ERR_PARAM);
    assert_int_equal(
        mc_pi_init_q31(&pi, one_half, MC_PI_Q31_MAX_SHIFT + 1U, one_half, 0U, -one_half, one_half),
        MC_ERR_PARAM);
    assert_int_equal(
        mc_pi_init_q31(&pi, one_half, 0U, one_half, MC_PI_Q31_MAX_SHIFT + 1U, -one_half, one_half),
        MC_ERR_PARAM);
    assert_int_equal(mc_pi_init_q31(&pi, 0, 3U, 0, 2U, -one_half, one_half), MC_ERR_PARAM);
    assert_int_equal(mc_pi_init_q31(&pi, one_half, 0U, one_half, 0U, one_half, one_half),
                     MC_ERR_PARAM);
    assert_memory_equal(&pi, &before, sizeof pi);

    /* integrator starts at 0 clamped into the limits: [0.25, 0.5] -> 0.25 */
    assert_int_equal(mc_pi_init_q31(&pi, one_half, 0U, one_half, 0U, 1 << 29, one_half), MC_OK);
    assert_int_equal(mc_pi_step_q31(&pi, 0), 1 << 29);
    before = pi;
    assert_int_equal(mc_pi_set_limits_q31(&pi, 5, 5), MC_ERR_PARAM);
    assert_int_equal(mc_pi_set_limits_q31(&pi, 6, 5), MC_ERR_PARAM);
    assert_memory_equal(&pi, &before, sizeof pi);
    /* bumpless: reset to the wanted output, zero error returns it */
    assert_int_equal(mc_pi_set_limits_q31(&pi, -one_half, one_half), MC_OK);
    mc_pi_reset_q31(&pi, -12345);
    assert_int_equal(mc_pi_step_q31(&pi, 0), -12345);
}

/* Random error sequences through saturation and back, against the model. */
static void test_pi_random_vs_model(void **state)
{
    (void)state;
    uint64_t seed = 0x9119ULL;
    for (int run = 0; run < 40; ++run) {
        pi_trio_t t;
        const double kp = prng_uniform(&seed, 0.0, 20.0);
        const double ki = prng_uniform(&seed, 1e-5, 0.2);
        const double lim = prng_uniform(&seed, 0.05, 1.0);
        trio_init(&t, kp, ki, -lim * prng_uniform(&seed, 0.2, 1.0), lim);
        double bias = 0.0;
        for (long k = 0; k < 4000; ++k) {
            if (k % 500 == 0) {
                bias = prng_uniform(&seed, -0.05, 0.05);
            }
            const double e = bias + prng_uniform(&seed, -0.01, 0.01);
            trio_step(&t, real_to_q31_sat(e), k, 1);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pi_step_response_analytic),
        cmocka_unit_test(test_pi_step_response_vs_f32),
        cmocka_unit_test(test_pi_windup_recovery),
        cmocka_unit_test(test_pi_extremes_saturate),
        cmocka_unit_test(test_pi_params),
        cmocka_unit_test(test_pi_random_vs_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
