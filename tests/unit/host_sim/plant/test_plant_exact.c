/* The exact integrator (PLANT_SOLVER_EXACT) against the closed-form
 * solution of the stator equation, written here independently of the
 * plant: with the inverter's voltage v_ab held (constant duties, no dead
 * time) and the speed constant (locked rotor, or an inertia so large that
 * the torque cannot change the speed measurably), in alpha-beta
 *   L di/dt = v_ab - R i - j omega_e psi exp(j theta_e(t)),
 *   theta_e(t) = theta_e0 + omega_e t, lambda = R / L:
 *   i(t) = exp(-lambda t) i0 + (v_ab / L) (1 - exp(-lambda t)) / lambda
 *          - j (omega_e psi / L) exp(j theta_e0)
 *            (exp(j omega_e t) - exp(-lambda t)) / (lambda + j omega_e),
 * ((1 - exp(-lambda t)) / lambda = t for R = 0), and i_dq = exp(-j theta_e) i.
 * The exact step is exact for this case up to rounding, so the bound is
 * 1e-10 of the current's scale; leaving out the back-EMF's response (1e-3 A
 * a 1 us substep) or the input's gain would miss it by far more. */
#include "mc_test.h"

#include <complex.h>
#include <math.h>

#include "plant.h"

#define V_DC_V        48.0
#define MAX_REL_ERR   1e-10
#define HUGE_J_KGM2   1e12 /* torques of a few N m move omega by < 1e-12 rad/s */
#define TEST_PERIODS  400u /* 20 ms: a longer time than L / R = 17 ms */
#define CHECK_EVERY_N 37u

static const double duty_test[3] = { 0.55, 0.45, 0.5 };

/* The phase voltages' alpha-beta vector for duty_test on V_DC_V. */
static double complex applied_voltage_V(void)
{
    double v[3];
    for (int k = 0; k < 3; ++k) {
        v[k] = duty_test[k] * V_DC_V;
    }
    const double v_alpha = (2.0 * v[0] - v[1] - v[2]) / 3.0;
    const double v_beta = (v[1] - v[2]) / sqrt(3.0);
    return v_alpha + I * v_beta;
}

/* i_dq at time t (closed form above) from i_ab0 = 0. */
static double complex closed_form_i_dq_A(const plant_config_t *c, double omega_m_rad_s, double t_s)
{
    const double r = c->motor.R_ohm;
    const double l = c->motor.Ld_H;
    const double psi = c->motor.psi_Wb;
    const double n_p = (double)c->motor.pole_pairs;
    const double lambda = r / l;
    const double w_e = n_p * omega_m_rad_s;
    const double theta_e0 = n_p * c->theta_m0_rad;
    const double decay = exp(-lambda * t_s);
    const double charge_s = lambda > 0.0 ? -expm1(-lambda * t_s) / lambda : t_s;
    double complex i_ab = applied_voltage_V() / l * charge_s;
    if (w_e != 0.0) {
        i_ab -= I * (w_e * psi / l) * cexp(I * theta_e0) * (cexp(I * w_e * t_s) - decay) /
                (lambda + I * w_e);
    }
    return cexp(-I * (theta_e0 + w_e * t_s)) * i_ab;
}

/* Runs the plant TEST_PERIODS periods at constant duties from zero current
 * and compares i_d, i_q with the closed form every CHECK_EVERY_N periods;
 * returns the largest error relative to the largest current. */
static double max_rel_error(const plant_config_t *c, double omega_m_rad_s)
{
    plant_t p;
    assert_int_equal(plant_init(&p, c), PLANT_OK);
    double err_A = 0.0;
    double scale_A = 0.0;
    for (uint32_t n = 1u; n <= TEST_PERIODS; ++n) {
        plant_advance(&p, duty_test, true);
        if (n % CHECK_EVERY_N != 0u && n != TEST_PERIODS) {
            continue;
        }
        const plant_true_state_t *s = plant_true_state(&p);
        const double complex want = closed_form_i_dq_A(c, omega_m_rad_s, s->t_s);
        err_A = fmax(err_A, cabs((s->i_d_A + I * s->i_q_A) - want));
        scale_A = fmax(scale_A, cabs(want));
        assert_true(fabs(s->omega_m_rad_s - omega_m_rad_s) <= 1e-9);
    }
    assert_true(scale_A > 1.0); /* the case drives a real current */
    return err_A / scale_A;
}

static plant_config_t exact_config(uint32_t substeps)
{
    plant_config_t c;
    plant_config_default(&c);
    sim_profile_set_constant(&c.inverter.v_dc_V, V_DC_V);
    c.inverter.t_dead_s = 0.0;
    c.inverter.v_device_drop_V = 0.0;
    c.substeps_per_period = substeps;
    c.solver_method = PLANT_SOLVER_EXACT;
    c.theta_m0_rad = 0.3;
    return c;
}

static void test_locked_rotor_constant_voltage(void **state)
{
    (void)state;
    plant_config_t c = exact_config(PLANT_DEFAULT_SUBSTEPS);
    c.locked_rotor = true;
    const double err = max_rel_error(&c, 0.0);
    print_message("locked rotor, R %.3f ohm: max relative error %.2e\n", c.motor.R_ohm, err);
    assert_true(err <= MAX_REL_ERR);
}

static void test_locked_rotor_without_resistance(void **state)
{
    (void)state;
    plant_config_t c = exact_config(PLANT_DEFAULT_SUBSTEPS);
    c.locked_rotor = true;
    c.motor.R_ohm = 0.0; /* allowed: the current ramps at v / L */
    const double err = max_rel_error(&c, 0.0);
    print_message("locked rotor, R 0: max relative error %.2e\n", err);
    assert_true(err <= MAX_REL_ERR);
}

/* 1 us substeps: the rotor turns 1.2e-4 rad a substep (the series of the
 * back-EMF's response); 12.5 us: 1.5e-3 rad (its division form). */
static void test_constant_speed_with_back_emf(void **state)
{
    (void)state;
    const uint32_t substeps[2] = { PLANT_DEFAULT_SUBSTEPS, PLANT_SUBSTEPS_FAST };
    const double omega_m_rad_s = 40.0;
    for (int k = 0; k < 2; ++k) {
        plant_config_t c = exact_config(substeps[k]);
        c.motor.J_kgm2 = HUGE_J_KGM2;
        c.omega_m0_rad_s = omega_m_rad_s;
        const double err = max_rel_error(&c, omega_m_rad_s);
        print_message("omega_m %.0f rad/s, %u substeps: max relative error %.2e\n", omega_m_rad_s,
                      (unsigned)substeps[k], err);
        assert_true(err <= MAX_REL_ERR);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_locked_rotor_constant_voltage),
        cmocka_unit_test(test_locked_rotor_without_resistance),
        cmocka_unit_test(test_constant_speed_with_back_emf),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
