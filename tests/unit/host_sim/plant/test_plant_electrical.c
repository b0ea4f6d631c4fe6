/* Electrical dynamics: locked-rotor current steps against the analytic first-
 * order response, RK4 convergence order, fast option vs the 1 us reference. */
#include "mc_test.h"

#include <math.h>

#include "plant.h"
#include "plant_test_support.h"

#define V_DC 48.0

static plant_config_t locked_config(void)
{
    plant_config_t c;
    plant_config_default(&c);
    c.locked_rotor = true;
    c.theta_m0_rad = 0.0; /* d axis on phase a */
    return c;
}

/* Constant d-axis voltage at theta_e = 0 through the duties; the plant uses
 * nominal * mismatch (R x1.5, L x1.5): i_d = V/R (1 - exp(-R t / L)). */
static void test_locked_rotor_d_step_with_mismatch(void **state)
{
    (void)state;
    plant_config_t c = locked_config();
    c.mismatch.R = 1.5;
    c.mismatch.L = 1.5;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double v_d = 6.0, r = 0.225 * 1.5, l = 3.8e-3 * 1.5;
    double duty[3];
    test_duties_for_alpha_beta(v_d, 0.0, V_DC, duty);
    for (int k = 1; k <= 2000; ++k) { /* 0.1 s = 4.4 L/R */
        plant_advance(&p, duty, true);
        const plant_true_state_t *s = plant_true_state(&p);
        const double t = k * plant_period_s(&p);
        const double want = v_d / r * (1.0 - exp(-r * t / l));
        assert_near(s->t_s, t, 1e-12);
        assert_near(s->i_d_A, want, 1e-6 * want);
        assert_near(s->i_q_A, 0.0, 1e-9);
        /* phase currents: i_a = i_d, i_b = i_c = -i_d / 2 at theta_e = 0 */
        assert_near(s->i_abc_A[0], want, 1e-6 * want);
        assert_near(s->i_abc_A[1], -0.5 * want, 1e-6 * want);
        assert_near(s->omega_m_rad_s, 0.0, 0.0);
    }
}

/* Salient motor (Lq = 2 Ld): a beta-axis voltage at theta_e = 0 is a pure
 * q-axis voltage and must rise with the q-axis time constant Lq / R. */
static void test_locked_rotor_q_step_salient(void **state)
{
    (void)state;
    plant_config_t c = locked_config();
    c.motor.Lq_H = 2.0 * c.motor.Ld_H;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double v_q = -4.0, r = 0.225, lq = 7.6e-3;
    double duty[3];
    test_duties_for_alpha_beta(0.0, v_q, V_DC, duty);
    for (int k = 1; k <= 2000; ++k) {
        plant_advance(&p, duty, true);
        const plant_true_state_t *s = plant_true_state(&p);
        const double want = v_q / r * (1.0 - exp(-r * s->t_s / lq));
        assert_near(s->i_q_A, want, 1e-6 * fabs(want));
        assert_near(s->i_d_A, 0.0, 1e-9);
        /* locked, so the reluctance + PM torque is the analytic 1.5 n_p psi i_q */
        assert_near(s->tau_e_Nm, 1.5 * 3.0 * 0.17 * want, 1e-6 * fabs(1.5 * 3.0 * 0.17 * want));
    }
}

/* Spinning salient motor, random duties held per period (a fixed sequence).
 * Returns the state after n_periods with the given substeps. */
static void spin_run(uint32_t substeps, double f_pwm_Hz, int n_periods, double out[4])
{
    plant_config_t c;
    plant_config_default(&c);
    c.motor.Lq_H = 1.6 * c.motor.Ld_H;
    c.motor.B_Nm_s_rad = 1e-3;
    c.inverter.f_pwm_Hz = f_pwm_Hz;
    c.omega_m0_rad_s = 100.0;
    c.substeps_per_period = substeps;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    uint64_t rng = 7u;
    double duty[3];
    for (int k = 0; k < n_periods; ++k) {
        for (int x = 0; x < 3; ++x)
            duty[x] = test_uniform(&rng, 0.2, 0.8);
        plant_advance(&p, duty, true);
    }
    const plant_true_state_t *s = plant_true_state(&p);
    out[0] = s->i_d_A;
    out[1] = s->i_q_A;
    out[2] = s->omega_m_rad_s;
    out[3] = s->theta_m_rad;
}

/* Global error of classic RK4 scales as h^4: halving h divides it by ~16.
 * 1 kHz periods make h large enough that the error is far above rounding. */
static void test_rk4_order_four(void **state)
{
    (void)state;
    double ref[4], e[3];
    spin_run(512u, 1000.0, 40, ref);
    const uint32_t steps[3] = { 4u, 8u, 16u };
    for (int j = 0; j < 3; ++j) {
        double x[4];
        spin_run(steps[j], 1000.0, 40, x);
        e[j] = 0.0;
        for (int k = 0; k < 2; ++k) { /* current error [A] */
            const double d = fabs(x[k] - ref[k]);
            e[j] = d > e[j] ? d : e[j];
        }
    }
    print_message("RK4 current errors h, h/2, h/4: %.3e %.3e %.3e\n", e[0], e[1], e[2]);
    assert_true(e[2] > 1e-11); /* still well above rounding */
    for (int j = 0; j < 2; ++j) {
        const double ratio = e[j] / e[j + 1];
        assert_true(ratio > 13.0 && ratio < 19.0);
    }
}

/* The fast option (PLANT_SUBSTEPS_FAST) against the 1 us reference over a
 * run with random duties around the back-EMF, dead time with a current band
 * (the hard sign is a discontinuity that no fixed step resolves). */
static void fast_vs_reference(double rpm, int n_periods, double max_dev[3])
{
    plant_config_t c;
    plant_config_default(&c);
    sim_profile_set_constant(&c.inverter.v_dc_V, 400.0);
    c.inverter.t_dead_s = 2e-6;
    c.inverter.dead_time_current_band_A = 0.5;
    c.omega_m0_rad_s = rpm * MC_TEST_RAD_S_PER_RPM;
    plant_t ref, fast;
    c.substeps_per_period = PLANT_DEFAULT_SUBSTEPS;
    assert_int_equal(plant_init(&ref, &c), PLANT_OK);
    c.substeps_per_period = PLANT_SUBSTEPS_FAST;
    assert_int_equal(plant_init(&fast, &c), PLANT_OK);
    const double omega_e = 3.0 * c.omega_m0_rad_s, e = omega_e * 0.17;
    uint64_t rng = 99u;
    double duty[3];
    max_dev[0] = max_dev[1] = max_dev[2] = 0.0;
    for (int k = 0; k < n_periods; ++k) {
        const double th = omega_e * k / 20000.0;
        test_duties_for_alpha_beta(-e * sin(th), e * cos(th), 400.0, duty);
        for (int x = 0; x < 3; ++x)
            duty[x] += test_uniform(&rng, -0.025, 0.025);
        plant_advance(&ref, duty, true);
        plant_advance(&fast, duty, true);
        const plant_true_state_t *a = plant_true_state(&ref), *b = plant_true_state(&fast);
        const double d[3] = { fmax(fabs(a->i_d_A - b->i_d_A), fabs(a->i_q_A - b->i_q_A)),
                              fabs(a->omega_m_rad_s - b->omega_m_rad_s),
                              fabs(a->theta_m_rad - b->theta_m_rad) };
        for (int j = 0; j < 3; ++j)
            max_dev[j] = fmax(max_dev[j], d[j]);
    }
}

/* The fast solver within 1e-5 A, 1e-7 rad/s and 1e-8 rad of the reference
 * over n_periods at this speed. */
static void check_fast_matches_reference(double rpm, int n_periods)
{
    double dev[3];
    fast_vs_reference(rpm, n_periods, dev);
    print_message("%.0f rpm, %.2g s: max |di| %.2e A, |domega| %.2e rad/s, |dtheta| %.2e rad\n",
                  rpm, n_periods / 20000.0, dev[0], dev[1], dev[2]);
    assert_true(dev[0] < 1e-5);
    assert_true(dev[1] < 1e-7);
    assert_true(dev[2] < 1e-8);
}

static void test_fast_option_matches_reference_3000rpm(void **state)
{
    (void)state;
    check_fast_matches_reference(3000.0, 20000); /* 1 s */
}

static void test_fast_option_matches_reference_120rpm(void **state)
{
    (void)state;
    check_fast_matches_reference(120.0, 10000); /* 0.5 s */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_locked_rotor_d_step_with_mismatch),
        cmocka_unit_test(test_locked_rotor_q_step_salient),
        cmocka_unit_test(test_rk4_order_four),
        cmocka_unit_test(test_fast_option_matches_reference_3000rpm),
        cmocka_unit_test(test_fast_option_matches_reference_120rpm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
