/*
 * Clarke transforms against the space-vector definition in double:
 *   alpha + j beta = 2/3 (a + b e^{j 2pi/3} + c e^{j 4pi/3}).
 */
#include "mc_test.h"

#include <math.h>

#include "mc/clarke.h"
#include "test_rng.h"

#define N_RANDOM 200000

/* Float rounding allowance: a few float epsilons of the input scale. */
static double tol_for(double scale)
{
    return 4.0 * 1.1920929e-7 * scale;
}

static void space_vector_ref(double a, double b, double c, double *alpha, double *beta)
{
    const double w = MC_TEST_TWO_PI / 3.0;
    *alpha = 2.0 / 3.0 * (a + b * cos(w) + c * cos(2.0 * w));
    *beta = 2.0 / 3.0 * (b * sin(w) + c * sin(2.0 * w));
}

static void test_clarke_matches_space_vector_definition(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(1);
    for (int n = 0; n < N_RANDOM; n++) {
        /* arbitrary sets, including a zero-sequence component */
        const float a = (float)test_rng_range(&rng, -100.0, 100.0);
        const float b = (float)test_rng_range(&rng, -100.0, 100.0);
        const float c = (float)test_rng_range(&rng, -100.0, 100.0);
        float alpha, beta;
        mc_clarke_f32(a, b, c, &alpha, &beta);
        double alpha_ref, beta_ref;
        space_vector_ref(a, b, c, &alpha_ref, &beta_ref);
        const double tol = tol_for(fabs(a) + fabs(b) + fabs(c));
        assert_true(fabs(alpha - alpha_ref) <= tol);
        assert_true(fabs(beta - beta_ref) <= tol);
    }
}

/* Balanced set of amplitude A at angle phi -> (A cos phi, A sin phi):
 * amplitude invariance, for both the 3- and the 2-input form. */
static void test_clarke_balanced_set_is_amplitude_invariant(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(2);
    for (int n = 0; n < N_RANDOM; n++) {
        const double amp = test_rng_range(&rng, 0.0, 50.0);
        const double phi = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        const double a = amp * cos(phi);
        const double b = amp * cos(phi - MC_TEST_TWO_PI / 3.0);
        const double c = amp * cos(phi + MC_TEST_TWO_PI / 3.0);
        float alpha3, beta3, alpha2, beta2;
        mc_clarke_f32((float)a, (float)b, (float)c, &alpha3, &beta3);
        mc_clarke2_f32((float)a, (float)b, &alpha2, &beta2);
        const double tol = tol_for(3.0 * amp);
        assert_true(fabs(alpha3 - amp * cos(phi)) <= tol);
        assert_true(fabs(beta3 - amp * sin(phi)) <= tol);
        assert_true(fabs(alpha2 - amp * cos(phi)) <= tol);
        assert_true(fabs(beta2 - amp * sin(phi)) <= tol);
        assert_true(fabs(hypot(alpha3, beta3) - amp) <= tol);
    }
}

static void test_inv_clarke_gives_balanced_set(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(3);
    for (int n = 0; n < N_RANDOM; n++) {
        const double amp = test_rng_range(&rng, 0.0, 50.0);
        const double phi = test_rng_range(&rng, -MC_TEST_PI, MC_TEST_PI);
        float a, b, c;
        mc_inv_clarke_f32((float)(amp * cos(phi)), (float)(amp * sin(phi)), &a, &b, &c);
        const double tol = tol_for(2.0 * amp);
        assert_true(fabs(a - amp * cos(phi)) <= tol);
        assert_true(fabs(b - amp * cos(phi - MC_TEST_TWO_PI / 3.0)) <= tol);
        assert_true(fabs(c - amp * cos(phi + MC_TEST_TWO_PI / 3.0)) <= tol);
    }
}

/* Round trips: abc -> ab -> abc removes exactly the zero sequence;
 * ab -> abc -> ab is the identity. */
static void test_clarke_round_trips(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(4);
    for (int n = 0; n < N_RANDOM; n++) {
        const float a = (float)test_rng_range(&rng, -100.0, 100.0);
        const float b = (float)test_rng_range(&rng, -100.0, 100.0);
        const float c = (float)test_rng_range(&rng, -100.0, 100.0);
        float alpha, beta, a2, b2, c2;
        mc_clarke_f32(a, b, c, &alpha, &beta);
        mc_inv_clarke_f32(alpha, beta, &a2, &b2, &c2);
        const double zero_seq = ((double)a + b + c) / 3.0;
        const double tol = tol_for(2.0 * (fabs(a) + fabs(b) + fabs(c)));
        assert_true(fabs(a2 - (a - zero_seq)) <= tol);
        assert_true(fabs(b2 - (b - zero_seq)) <= tol);
        assert_true(fabs(c2 - (c - zero_seq)) <= tol);

        float alpha3, beta3;
        mc_clarke_f32(a2, b2, c2, &alpha3, &beta3);
        assert_true(fabs(alpha3 - alpha) <= tol);
        assert_true(fabs(beta3 - beta) <= tol);
    }
}

/* Power: va ia + vb ib + vc ic = 1.5 (v_alpha i_alpha + v_beta i_beta) for
 * zero-sequence-free sets (amplitude-invariant transform). */
static void test_clarke_power_factor_three_halves(void **state)
{
    (void)state;
    test_rng_t rng = test_rng_seed(5);
    for (int n = 0; n < N_RANDOM; n++) {
        double v[3], i[3];
        /* arbitrary zero-sequence-free sets (not necessarily sinusoidal) */
        for (int k = 0; k < 2; k++) {
            v[k] = test_rng_range(&rng, -400.0, 400.0);
            i[k] = test_rng_range(&rng, -30.0, 30.0);
        }
        v[2] = -v[0] - v[1];
        i[2] = -i[0] - i[1];
        const double p_abc = v[0] * i[0] + v[1] * i[1] + v[2] * i[2];
        float va, vb, ia, ib;
        mc_clarke_f32((float)v[0], (float)v[1], (float)v[2], &va, &vb);
        mc_clarke_f32((float)i[0], (float)i[1], (float)i[2], &ia, &ib);
        const double p_ab = 1.5 * ((double)va * ia + (double)vb * ib);
        const double scale =
            (fabs(v[0]) + fabs(v[1]) + fabs(v[2])) * (fabs(i[0]) + fabs(i[1]) + fabs(i[2]));
        assert_true(fabs(p_ab - p_abc) <= 1e-6 * scale);
    }
}

static void test_clarke_propagates_non_finite(void **state)
{
    (void)state;
    float alpha, beta;
    mc_clarke_f32(NAN, 0.0f, 0.0f, &alpha, &beta);
    assert_true(isnan(alpha));
    mc_clarke2_f32(0.0f, INFINITY, &alpha, &beta);
    assert_false(isfinite(beta));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clarke_matches_space_vector_definition),
        cmocka_unit_test(test_clarke_balanced_set_is_amplitude_invariant),
        cmocka_unit_test(test_inv_clarke_gives_balanced_set),
        cmocka_unit_test(test_clarke_round_trips),
        cmocka_unit_test(test_clarke_power_factor_three_halves),
        cmocka_unit_test(test_clarke_propagates_non_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
