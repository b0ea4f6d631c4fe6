/*
 * PI controller: closed-form step response, anti-windup recovery bound,
 * limits that change every sample, parameter validation.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mc/pi.h"
#include "test_rng.h"

/* Constant error e from a zero integrator, no saturation: backward-Euler
 * integrator I_k = (k+1) ki Ts e, so u_k = kp e + ki Ts e (k+1). */
static void test_pi_step_response_closed_form(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(51);
    for (int trial = 0; trial < 2000; trial++) {
        const double kp = test_rng_range(&rng, 0.0, 20.0);
        const double ki = test_rng_range(&rng, 1.0, 5000.0);
        const double Ts = test_rng_range(&rng, 1e-5, 1e-3);
        const double e = test_rng_range(&rng, -2.0, 2.0);
        mc_pi_f32_t pi;
        assert_int_equal(mc_pi_init_f32(&pi, (float)kp, (float)ki, (float)Ts, -1e9f, 1e9f), MC_OK);
        const double ki_Ts = (double)(float)ki * (double)(float)Ts;
        double u_scale = 0.0;
        for (int k = 0; k < 1000; k++) {
            const double u_ref = (double)(float)kp * (float)e + ki_Ts * (float)e * (k + 1);
            const float u = mc_pi_step_f32(&pi, (float)e);
            u_scale = fmax(u_scale, fabs(u_ref));
            /* each sample rounds ki*Ts*e, the sum and the output:
             * at most (k + 3) half-ulps of the largest magnitude */
            assert_true(fabs(u - u_ref) <= (k + 3) * FLT_EPSILON * u_scale);
        }
    }
}

/* Saturated high for a long time (the error keeps pushing), then the error
 * reverses: the output leaves the limit on the FIRST reversed sample (the
 * bound of the header's scheme), and the integrator never left the limits. */
static void test_pi_windup_recovery_one_sample(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(52);
    for (int trial = 0; trial < 1000; trial++) {
        const float kp = (float)test_rng_range(&rng, 0.0, 5.0);
        /* ki Ts |e_push| >= 0.01 per sample: 20000 samples integrate at
         * least 200 > 2 lim, so the output certainly saturates */
        const float ki = (float)test_rng_range(&rng, 100.0, 2000.0);
        const float lim = (float)test_rng_range(&rng, 0.5, 50.0);
        mc_pi_f32_t pi;
        assert_int_equal(mc_pi_init_f32(&pi, kp, ki, 1e-4f, -lim, lim), MC_OK);
        const float sign = (trial % 2) ? 1.0f : -1.0f;
        const float e_push = sign * (float)test_rng_range(&rng, 1.0, 10.0);
        for (int k = 0; k < 20000; k++) {
            const float u = mc_pi_step_f32(&pi, e_push);
            assert_true(u >= -lim && u <= lim);
            assert_true(pi.integrator >= -lim && pi.integrator <= lim);
        }
        /* at the limit (within the rounding of kp e + (lim - kp e)) */
        const float u_sat = mc_pi_step_f32(&pi, e_push);
        assert_true(fabsf(u_sat - sign * lim) <= 2.0f * FLT_EPSILON * lim);
        /* a small reversal, far too small to matter for a wound-up
         * integrator (naive I would be ~ 20000 ki Ts |e_push|) */
        const float u = mc_pi_step_f32(&pi, -sign * 1e-3f);
        assert_true(sign * u < lim);
    }
}

/* While the error pushes the output into a limit, the integrator stops
 * where the output meets the limit (conditional integration). */
static void test_pi_conditional_integration_freezes(void **state)
{
    (void)state;
    mc_pi_f32_t pi;
    assert_int_equal(mc_pi_init_f32(&pi, 2.0f, 100.0f, 1e-3f, -10.0f, 10.0f), MC_OK);
    /* kp e = 8 leaves room 2 for the integrator (ki Ts e = 0.4 a sample):
     * it stops at exactly 10 - 8 = 2, the output at exactly 10 */
    float u = 0.0f;
    for (int k = 0; k < 1000; k++) {
        u = mc_pi_step_f32(&pi, 4.0f);
    }
    assert_true(u == 10.0f);
    assert_true(pi.integrator == 2.0f);
    /* error back to 0: the output is the integrator alone */
    u = mc_pi_step_f32(&pi, 0.0f);
    assert_true(u == 2.0f);
    /* kp e alone beyond the limit: the integrator is not moved back */
    u = mc_pi_step_f32(&pi, 7.0f);
    assert_true(u == 10.0f && pi.integrator == 2.0f);
}

/* Limits changed every sample (random, shrinking and growing): the output
 * and the integrator stay inside the current limits; bumpless reset. */
static void test_pi_changing_limits(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(53);
    mc_pi_f32_t pi;
    assert_int_equal(mc_pi_init_f32(&pi, 0.5f, 200.0f, 1e-4f, -1.0f, 1.0f), MC_OK);
    for (int k = 0; k < 200000; k++) {
        const float hi = (float)test_rng_range(&rng, 0.01, 30.0);
        const float lo = -(float)test_rng_range(&rng, 0.01, 30.0);
        assert_int_equal(mc_pi_set_limits_f32(&pi, lo, hi), MC_OK);
        const float u = mc_pi_step_f32(&pi, (float)test_rng_range(&rng, -50.0, 50.0));
        assert_true(u >= lo && u <= hi);
        assert_true(pi.integrator >= lo && pi.integrator <= hi);
    }
    mc_pi_reset_f32(&pi, 0.25f);
    assert_int_equal(mc_pi_set_limits_f32(&pi, -1.0f, 1.0f), MC_OK);
    assert_true(mc_pi_step_f32(&pi, 0.0f) == 0.25f);
}

static void test_pi_non_finite_error(void **state)
{
    (void)state;
    mc_pi_f32_t pi;
    assert_int_equal(mc_pi_init_f32(&pi, 1.0f, 10.0f, 1e-3f, -5.0f, 5.0f), MC_OK);
    (void)mc_pi_step_f32(&pi, 1.0f);
    const mc_pi_f32_t before = pi;
    assert_true(isnan(mc_pi_step_f32(&pi, NAN)));
    assert_true(isnan(mc_pi_step_f32(&pi, INFINITY)));
    assert_memory_equal(&pi, &before, sizeof pi);
    /* a non-finite integrator (bad reset) is never turned into a number */
    mc_pi_reset_f32(&pi, NAN);
    assert_true(isnan(mc_pi_step_f32(&pi, 0.5f)));
}

/* The PI of the random-limits tests below: kp 0.5, ki 200, Ts 1e-4 s,
 * limits -+1 until a test sets its own. */
static mc_pi_f32_t random_limits_pi(void)
{
    mc_pi_f32_t pi;
    assert_int_equal(mc_pi_init_f32(&pi, 0.5f, 200.0f, 1e-4f, -1.0f, 1.0f), MC_OK);
    return pi;
}

/* The unchecked steps (ISR paths): for a finite error the checked step's
 * output and state, bit for bit, on the stored or on passed limits, and
 * at_limit exactly when the output sits on a limit; a NaN or infinite
 * error gives NaN (never the finite limit the output clamp makes of an
 * infinity), whatever the gains and the integrator. */
static void test_pi_unchecked(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(57);
    mc_pi_f32_t checked = random_limits_pi();
    mc_pi_f32_t stored = checked;
    mc_pi_f32_t passed = checked;
    for (int k = 0; k < 200000; k++) {
        const float hi = (float)test_rng_range(&rng, -5.0, 30.0);
        const float lo = hi - (float)test_rng_range(&rng, 1e-3, 30.0);
        const float e = (float)test_rng_range(&rng, -50.0, 50.0);
        assert_int_equal(mc_pi_set_limits_f32(&checked, lo, hi), MC_OK);
        mc_pi_set_limits_unchecked_f32(&stored, lo, hi);
        const float u = mc_pi_step_f32(&checked, e);
        const float u_stored = mc_pi_step_unchecked_f32(&stored, e);
        bool at_limit;
        const float u_passed = mc_pi_step_within_unchecked_f32(&passed, e, lo, hi, &at_limit);
        assert_memory_equal(&u_stored, &u, sizeof u);
        assert_memory_equal(&u_passed, &u, sizeof u);
        assert_true(at_limit == (u <= lo || u >= hi));
        assert_memory_equal(&stored, &checked, sizeof checked);
        assert_memory_equal(&passed.integrator, &checked.integrator, sizeof(float));
    }
    const float gains[][2] = { { 1.0f, 10.0f }, { 0.0f, 10.0f }, { 1.0f, 0.0f } };
    const float integrators[] = { -5.0f, 0.0f, 5.0f };
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (size_t g = 0; g < sizeof gains / sizeof gains[0]; g++) {
        for (size_t i = 0; i < sizeof integrators / sizeof integrators[0]; i++) {
            for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
                mc_pi_f32_t pi;
                assert_int_equal(mc_pi_init_f32(&pi, gains[g][0], gains[g][1], 1e-3f, -5.0f, 5.0f),
                                 MC_OK);
                mc_pi_reset_f32(&pi, integrators[i]);
                mc_pi_f32_t pi2 = pi;
                bool at_limit;
                assert_true(isnan(mc_pi_step_unchecked_f32(&pi, bad[b])));
                assert_true(
                    isnan(mc_pi_step_within_unchecked_f32(&pi2, bad[b], -5.0f, 5.0f, &at_limit)));
            }
        }
    }
}

/* The centred step (limits centre -+ half, its common case as two
 * |x - centre| tests) against mc_pi_step_within_unchecked_f32 on the
 * limits it rounds to, with limits, errors and integrators that saturate
 * about half of the time: the same output, integrator and at_limit bit
 * for bit but where the limits' rounding decides (then within an ulp of
 * the limit, counted); NaN for a non-finite error. */
static void test_pi_centred(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(58);
    mc_pi_f32_t a = random_limits_pi();
    mc_pi_f32_t b = a;
    long boundary = 0;
    long saturated = 0;
    for (int k = 0; k < 200000; k++) {
        const float centre = (float)test_rng_range(&rng, -30.0, 30.0);
        const float half = (float)test_rng_range(&rng, 1e-3, 30.0);
        const float e = (float)test_rng_range(&rng, -50.0, 50.0);
        bool lim_a, lim_b;
        const float u_a = mc_pi_step_centred_unchecked_f32(&a, e, centre, half, &lim_a);
        const float u_b =
            mc_pi_step_within_unchecked_f32(&b, e, centre - half, centre + half, &lim_b);
        saturated += lim_b ? 1 : 0;
        if (memcmp(&u_a, &u_b, sizeof u_a) != 0 || lim_a != lim_b ||
            memcmp(&a.integrator, &b.integrator, sizeof(float)) != 0) {
            const float lim = fmaxf(fabsf(centre - half), fabsf(centre + half));
            assert_true(fabsf(u_a - u_b) <= 2.0f * FLT_EPSILON * lim);
            assert_true(fabsf(a.integrator - b.integrator) <= 2.0f * FLT_EPSILON * lim);
            boundary++;
            a = b;
        }
    }
    printf("centred PI: %ld of 200000 steps saturated, %ld decided by the limits' rounding\n",
           saturated, boundary);
    assert_true(saturated > 40000 && saturated < 160000);
    assert_true(boundary < 200);
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        bool at_limit;
        mc_pi_f32_t c = a;
        assert_true(isnan(mc_pi_step_centred_unchecked_f32(&c, bad[i], 1.0f, 5.0f, &at_limit)));
    }
}

static void assert_init_rejected(float kp, float ki, float Ts, float lo, float hi,
                                 mc_status_t expected)
{
    mc_pi_f32_t pi;
    memset(&pi, 0x5A, sizeof pi);
    mc_pi_f32_t before;
    memcpy(&before, &pi, sizeof pi);
    assert_int_equal(mc_pi_init_f32(&pi, kp, ki, Ts, lo, hi), expected);
    assert_memory_equal(&pi, &before, sizeof pi);
}

static void test_pi_rejects_bad_parameters(void **state)
{
    (void)state;
    assert_init_rejected(NAN, 1.0f, 1e-4f, -1.0f, 1.0f, MC_ERR_NONFINITE);
    assert_init_rejected(1.0f, INFINITY, 1e-4f, -1.0f, 1.0f, MC_ERR_NONFINITE);
    assert_init_rejected(1.0f, 1.0f, NAN, -1.0f, 1.0f, MC_ERR_NONFINITE);
    assert_init_rejected(1.0f, 1.0f, 1e-4f, -INFINITY, 1.0f, MC_ERR_NONFINITE);
    assert_init_rejected(1.0f, 1.0f, 1e-4f, -1.0f, NAN, MC_ERR_NONFINITE);
    assert_init_rejected(-1.0f, 1.0f, 1e-4f, -1.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(1.0f, -1.0f, 1e-4f, -1.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(0.0f, 0.0f, 1e-4f, -1.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(0.0f, 1e-30f, 1e-30f, -1.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(1.0f, 1.0f, 0.0f, -1.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(1.0f, 1.0f, -1e-4f, -1.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(1.0f, 1.0f, 1e-4f, 1.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(1.0f, 1.0f, 1e-4f, 2.0f, 1.0f, MC_ERR_PARAM);
    assert_init_rejected(1.0f, 3e38f, 10.0f, -1.0f, 1.0f, MC_ERR_PARAM);

    mc_pi_f32_t pi;
    assert_int_equal(mc_pi_init_f32(&pi, 1.0f, 0.0f, 1e-4f, 2.0f, 3.0f), MC_OK);
    assert_true(pi.integrator == 2.0f); /* zero clamped into the limits */
    const mc_pi_f32_t before = pi;
    assert_int_equal(mc_pi_set_limits_f32(&pi, 1.0f, 1.0f), MC_ERR_PARAM);
    assert_int_equal(mc_pi_set_limits_f32(&pi, NAN, 1.0f), MC_ERR_NONFINITE);
    assert_int_equal(mc_pi_set_limits_f32(&pi, 0.0f, INFINITY), MC_ERR_NONFINITE);
    assert_memory_equal(&pi, &before, sizeof pi);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pi_step_response_closed_form),
        cmocka_unit_test(test_pi_windup_recovery_one_sample),
        cmocka_unit_test(test_pi_conditional_integration_freezes),
        cmocka_unit_test(test_pi_changing_limits),
        cmocka_unit_test(test_pi_non_finite_error),
        cmocka_unit_test(test_pi_unchecked),
        cmocka_unit_test(test_pi_centred),
        cmocka_unit_test(test_pi_rejects_bad_parameters),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
