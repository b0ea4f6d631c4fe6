/* Profile evaluation against hand-computed values, derivative, validation. */
#include "mc_test.h"

#include <math.h>

#include "plant_test_support.h"
#include "profile.h"

static void test_empty_is_zero_and_constant(void **state)
{
    (void)state;
    sim_profile_t p;
    sim_profile_clear(&p);
    assert_int_equal(sim_profile_validate(&p, NULL), SIM_PROFILE_OK);
    assert_true(sim_profile_eval(&p, 1.7) == 0.0);
    sim_profile_set_constant(&p, 48.0);
    assert_true(sim_profile_eval(&p, -3.0) == 48.0);
    assert_true(sim_profile_eval(&p, 1e3) == 48.0);
    assert_true(sim_profile_deriv(&p, 2.0) == 0.0);
}

/* 0 until 0.1 s, step to 2 at 0.1 s, ramp to 5 at 0.4 s, hold. */
static void step_then_ramp(sim_profile_t *p)
{
    sim_profile_clear(p);
    const sim_profile_point_t pts[] = { { 0.0, 0.0 }, { 0.1, 0.0 }, { 0.1, 2.0 }, { 0.4, 5.0 } };
    for (uint32_t i = 0; i < 4; ++i)
        p->points[i] = pts[i];
    p->n_points = 4;
}

static void test_step_and_ramp(void **state)
{
    (void)state;
    sim_profile_t p;
    step_then_ramp(&p);
    const char *msg = NULL;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_OK);
    assert_string_equal(msg, "ok");
    assert_true(sim_profile_eval(&p, -1.0) == 0.0);
    assert_true(sim_profile_eval(&p, 0.0999999) == 0.0);
    assert_true(sim_profile_eval(&p, 0.1) == 2.0);       /* right-continuous step */
    assert_near(sim_profile_eval(&p, 0.25), 3.5, 1e-12); /* 2 + 10*0.15 */
    assert_true(sim_profile_eval(&p, 0.4) == 5.0);
    assert_true(sim_profile_eval(&p, 9.0) == 5.0);
    assert_near(sim_profile_deriv(&p, 0.25), 10.0, 1e-12);
    assert_true(sim_profile_deriv(&p, 0.05) == 0.0);
    assert_true(sim_profile_deriv(&p, 0.5) == 0.0);
}

/* Evaluation on the piece active at another time: the piece's own formula,
 * extended past its ends (hand-computed). */
static void test_eval_on_piece(void **state)
{
    (void)state;
    sim_profile_t p;
    step_then_ramp(&p);
    p.sines[0] = (sim_profile_sine_t){
        .amplitude = 0.5, .freq_Hz = 1.0, .phase_rad = 0.0, .t_start_s = 0.1
    };
    p.n_sines = 1;
    assert_int_equal(sim_profile_validate(&p, NULL), SIM_PROFILE_OK);
    const double eps = 1e-15; /* a step time rounded a few ulp off */
    /* before the step, on the piece after it: the ramp 2 + 10 (t - 0.1)
     * extended back, plus the sine that starts with that piece */
    const double t_before = 0.1 - eps;
    assert_near(sim_profile_eval_on_piece(&p, t_before, 0.1 + 5e-6),
                2.0 + 10.0 * (t_before - 0.1) + 0.5 * sin(MC_TEST_TWO_PI * (t_before - 0.1)),
                1e-12);
    /* after the step, on the piece before it: still 0, no sine yet */
    assert_true(sim_profile_eval_on_piece(&p, 0.1 + eps, 0.1 - 5e-6) == 0.0);
    /* the ramp extended past its end at 0.4 s */
    assert_near(sim_profile_eval_on_piece(&p, 0.41, 0.39),
                2.0 + 10.0 * 0.31 + 0.5 * sin(MC_TEST_TWO_PI * 0.31), 1e-12);
    /* on its own time it is sim_profile_eval */
    for (double t = -0.05; t < 0.6; t += 0.013) {
        assert_true(sim_profile_eval_on_piece(&p, t, t) == sim_profile_eval(&p, t));
    }
}

static void test_sines_and_polynomial(void **state)
{
    (void)state;
    sim_profile_t p;
    sim_profile_set_constant(&p, 1.0);
    p.sines[0] = (sim_profile_sine_t){
        .amplitude = 0.5, .freq_Hz = 2.0, .phase_rad = 0.3, .t_start_s = 0.0
    };
    p.sines[1] = (sim_profile_sine_t){
        .amplitude = 3.0, .freq_Hz = 10.0, .phase_rad = 0.0, .t_start_s = 1.0
    };
    p.n_sines = 2;
    p.poly.coeffs[0] = 1.0;
    p.poly.coeffs[1] = -2.0;
    p.poly.coeffs[2] = 0.25;
    p.poly.n_coeffs = 3;
    p.poly.t_start_s = 0.5;
    assert_int_equal(sim_profile_validate(&p, NULL), SIM_PROFILE_OK);
    /* t = 0.2: constant + first sine only */
    assert_near(sim_profile_eval(&p, 0.2), 1.0 + 0.5 * sin(MC_TEST_TWO_PI * 2.0 * 0.2 + 0.3),
                1e-12);
    /* t = 1.3: everything; polynomial in tau = 0.8 */
    const double tau = 0.8;
    const double want = 1.0 + 0.5 * sin(MC_TEST_TWO_PI * 2.0 * 1.3 + 0.3) +
                        3.0 * sin(MC_TEST_TWO_PI * 10.0 * 0.3) +
                        (1.0 - 2.0 * tau + 0.25 * tau * tau);
    assert_near(sim_profile_eval(&p, 1.3), want, 1e-12);
    const double want_d = 0.5 * 4.0 * MC_TEST_PI * cos(MC_TEST_TWO_PI * 2.0 * 1.3 + 0.3) +
                          3.0 * 20.0 * MC_TEST_PI * cos(MC_TEST_TWO_PI * 10.0 * 0.3) +
                          (-2.0 + 0.5 * tau);
    assert_near(sim_profile_deriv(&p, 1.3), want_d, 1e-9);
}

/* Band-limited noise: RMS as configured, zero mean, no energy above the
 * cutoff (checked via the derivative bound), deterministic per seed. */
static void test_noise_statistics(void **state)
{
    (void)state;
    sim_profile_t p;
    sim_profile_clear(&p);
    p.noise = (sim_profile_noise_t){ .rms = 0.4, .cutoff_Hz = 50.0, .seed = 12345u };
    assert_int_equal(sim_profile_validate(&p, NULL), SIM_PROFILE_OK);
    const int n = 200000;
    const double dt = 1e-3; /* 200 s window: > 1000 periods of the lowest tone band */
    double sum = 0.0, sum2 = 0.0, max_abs_d = 0.0;
    for (int k = 0; k < n; ++k) {
        const double v = sim_profile_eval(&p, k * dt);
        sum += v;
        sum2 += v * v;
        const double d = fabs(sim_profile_deriv(&p, k * dt));
        max_abs_d = d > max_abs_d ? d : max_abs_d;
    }
    const double mean = sum / n;
    const double rms = sqrt(sum2 / n);
    assert_true(fabs(mean) < 0.02);
    assert_true(fabs(rms - 0.4) < 0.02);
    /* each tone has amplitude a = rms sqrt(2/N) and omega <= 2 pi cutoff */
    const double a = 0.4 * sqrt(2.0 / SIM_PROFILE_NOISE_TONES);
    assert_true(max_abs_d <= SIM_PROFILE_NOISE_TONES * a * MC_TEST_TWO_PI * 50.0);
    /* derivative consistent with the values (central difference) */
    const double t = 3.21, h = 1e-6;
    const double fd = (sim_profile_eval(&p, t + h) - sim_profile_eval(&p, t - h)) / (2.0 * h);
    assert_near(sim_profile_deriv(&p, t), fd, 1e-5);
    /* determinism: same seed same value, other seed different */
    sim_profile_t q = p;
    assert_true(sim_profile_eval(&q, 7.7) == sim_profile_eval(&p, 7.7));
    q.noise.seed = 54321u;
    assert_true(sim_profile_eval(&q, 7.7) != sim_profile_eval(&p, 7.7));
}

static void test_invalid_profiles(void **state)
{
    (void)state;
    sim_profile_t p;
    const char *msg = NULL;
    assert_int_equal(sim_profile_validate(NULL, &msg), SIM_PROFILE_ERR_NULL);

    sim_profile_clear(&p);
    p.n_points = SIM_PROFILE_MAX_POINTS + 1u;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_TOO_MANY);
    assert_non_null(msg);

    sim_profile_clear(&p);
    p.points[0] = (sim_profile_point_t){ 1.0, 0.0 };
    p.points[1] = (sim_profile_point_t){ 0.5, 1.0 };
    p.n_points = 2;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_TIME_ORDER);

    sim_profile_set_constant(&p, NAN);
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_NONFINITE);

    sim_profile_clear(&p);
    p.n_sines = 1;
    p.sines[0].freq_Hz = -1.0;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_NEGATIVE);
    p.sines[0].freq_Hz = 1.0;
    p.sines[0].amplitude = INFINITY;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_NONFINITE);

    sim_profile_clear(&p);
    p.poly.n_coeffs = SIM_PROFILE_MAX_POLY_COEFFS + 1u;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_TOO_MANY);

    sim_profile_clear(&p);
    p.noise.rms = 1.0;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_NOISE_CUTOFF);
    p.noise.rms = -1.0;
    p.noise.cutoff_Hz = 10.0;
    assert_int_equal(sim_profile_validate(&p, &msg), SIM_PROFILE_ERR_NEGATIVE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_empty_is_zero_and_constant),
        cmocka_unit_test(test_step_and_ramp),
        cmocka_unit_test(test_eval_on_piece),
        cmocka_unit_test(test_sines_and_polynomial),
        cmocka_unit_test(test_noise_statistics),
        cmocka_unit_test(test_invalid_profiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
