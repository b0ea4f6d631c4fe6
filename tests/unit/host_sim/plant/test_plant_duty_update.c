/* Duties that change at the middle of the period (plant_advance_split, the
 * inverter's half-period update): with the same duties in both halves it is
 * plant_advance, bit for bit; with a step at the middle of the period on a
 * locked R-L load it follows the piecewise-exponential solution of
 * L di/dt + R i = v within the RK4 error of its step size. */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "plant.h"
#include "plant_test_support.h"

#define V_DC 48.0

/* Both plants hold the same state, bit for bit. */
static void expect_same_state(const plant_t *a, const plant_t *b, int period)
{
    if (memcmp(a->x, b->x, sizeof a->x) != 0) {
        fail_msg("period %d: the integrated states differ", period);
    }
    assert_true(a->t_s == b->t_s);
    assert_true(a->n_periods == b->n_periods);
    assert_memory_equal(a->phase_state, b->phase_state, sizeof a->phase_state);
    assert_true(a->constraint_J == b->constraint_J);
    const plant_true_state_t *sa = plant_true_state(a);
    const plant_true_state_t *sb = plant_true_state(b);
    assert_memory_equal(sa->i_abc_A, sb->i_abc_A, sizeof sa->i_abc_A);
    assert_memory_equal(sa->v_abc_V, sb->v_abc_V, sizeof sa->v_abc_V);
    assert_memory_equal(&sa->energy, &sb->energy, sizeof sa->energy);
    assert_true(sa->tau_e_Nm == sb->tau_e_Nm && sa->v_dc_V == sb->v_dc_V);
    assert_true(sa->outputs_enabled == sb->outputs_enabled);
    assert_true(sa->open_circuit == sb->open_circuit);
    assert_true(sa->rectifying == sb->rectifying);
    assert_true(sa->i_bridge_A == sb->i_bridge_A);
}

/* 60 periods of random duties on a turning rotor (200 rpm, load and
 * friction), the outputs off in periods 30..44 (the currents freewheel
 * and extinguish), through plant_advance and through plant_advance_split
 * with both halves equal. */
static void run_equal_halves(const plant_config_t *c)
{
    plant_t a, b;
    assert_int_equal(plant_init(&a, c), PLANT_OK);
    assert_int_equal(plant_init(&b, c), PLANT_OK);
    uint64_t rng = 0x5eed5eedu;
    bool saw_open = false;
    for (int k = 0; k < 60; ++k) {
        double d[3];
        for (int x = 0; x < 3; ++x)
            d[x] = test_uniform(&rng, 0.2, 0.8);
        const bool on = k < 30 || k >= 45;
        plant_advance(&a, d, on);
        plant_advance_split(&b, d, on, d, on);
        expect_same_state(&a, &b, k);
        saw_open = saw_open || plant_true_state(&a)->open_circuit;
    }
    assert_true(saw_open); /* the disabled stretch reached the open circuit */
}

static plant_config_t turning_config(void)
{
    plant_config_t c;
    plant_config_default(&c);
    c.omega_m0_rad_s = 200.0 * MC_TEST_RAD_S_PER_RPM; /* back-EMF below the bus */
    c.theta_m0_rad = 0.4;
    c.motor.B_Nm_s_rad = 1e-3;
    sim_profile_set_constant(&c.load_torque_Nm, 0.5);
    return c;
}

static void test_equal_halves_are_plant_advance(void **state)
{
    (void)state;
    plant_config_t c = turning_config();
    run_equal_halves(&c);       /* ideal inverter */
    c.inverter.t_dead_s = 2e-6; /* dead time, hard sign(i) */
    c.inverter.v_device_drop_V = 0.7;
    run_equal_halves(&c);
    c.inverter.dead_time_current_band_A = 0.2; /* dead time, linear zone */
    run_equal_halves(&c);
    c.substeps_per_period = PLANT_SUBSTEPS_FAST;
    run_equal_halves(&c);
}

/* Locked rotor, Ld = Lq = L, ideal inverter: every phase is an R-L branch
 * with its own voltage v_x = v_dc (d_x - mean(d)), so over a half period
 * of constant v the exact current is
 *   i(t0 + T/2) = v/R + (i(t0) - v/R) exp(-R T / (2 L)).
 * R = 10 ohm, L = 1 mH: tau = 100 us, two PWM periods (20 kHz, 50 us). */
#define R_OHM     10.0
#define L_H       1e-3
#define N_SUB     50u
#define N_PERIODS 8

static void phase_voltages(const double d[3], double v[3])
{
    const double mean = (d[0] + d[1] + d[2]) / 3.0;
    for (int x = 0; x < 3; ++x)
        v[x] = V_DC * (d[x] - mean);
}

/* The exact R-L current after time dt at constant v. */
static double rl_current(double i0, double v, double dt)
{
    return v / R_OHM + (i0 - v / R_OHM) * exp(-dt * R_OHM / L_H);
}

static void test_mid_period_step_is_piecewise_exponential(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.locked_rotor = true;
    c.theta_m0_rad = 0.3; /* d axis away from phase a: abc != dq */
    c.motor.R_ohm = R_OHM;
    c.motor.Ld_H = L_H;
    c.motor.Lq_H = L_H;
    c.substeps_per_period = N_SUB;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double T = plant_period_s(&p);
    const double h = T / (double)N_SUB;
    /* RK4 on i' = -(i - v/R) / tau advances i - v/R by the polynomial
     * R4(-z), z = h / tau; e^-z - R4(-z) = -z^5/120 + z^6/720 - ..., at most
     * z^5/120 for 0 < z < 1. |R4(-z)| < 1 carries earlier errors without
     * growth, so after n steps |error| <= n z^5/120 max|i - v/R|; plus
     * rounding, a few ulps of the current per step. */
    const double z = h * R_OHM / L_H;
    const double n_steps = (double)N_SUB * N_PERIODS;
    double i[3] = { 0.0, 0.0, 0.0 }; /* the analytic currents */
    double dev_max = 0.0;            /* max |i - v/R| at a half start */
    double i_max = 0.0;
    uint64_t rng = 77u;
    for (int k = 0; k < N_PERIODS; ++k) {
        double d1[3], d2[3], v1[3], v2[3];
        for (int x = 0; x < 3; ++x) {
            d1[x] = test_uniform(&rng, 0.1, 0.9);
            d2[x] = test_uniform(&rng, 0.1, 0.9);
        }
        phase_voltages(d1, v1);
        phase_voltages(d2, v2);
        plant_advance_split(&p, d1, true, d2, true);
        double late[3]; /* the same with the step one substep late */
        for (int x = 0; x < 3; ++x) {
            dev_max = fmax(dev_max, fabs(i[x] - v1[x] / R_OHM));
            const double mid = rl_current(i[x], v1[x], 0.5 * T);
            dev_max = fmax(dev_max, fabs(mid - v2[x] / R_OHM));
            late[x] = rl_current(rl_current(i[x], v1[x], 0.5 * T + h), v2[x], 0.5 * T - h);
            i[x] = rl_current(mid, v2[x], 0.5 * T);
            i_max = fmax(i_max, fabs(i[x]));
        }
        const double tol =
            n_steps * pow(z, 5) / 120.0 * dev_max + 64.0 * n_steps * DBL_EPSILON * i_max;
        const plant_true_state_t *s = plant_true_state(&p);
        for (int x = 0; x < 3; ++x) {
            assert_near(s->i_abc_A[x], i[x], tol);
            /* the tolerance tells the middle from one substep later */
            assert_true(fabs(late[x] - i[x]) > 100.0 * tol || fabs(v2[x] - v1[x]) < 1.0);
            /* the period's mean phase voltage: half of each */
            assert_near(s->v_abc_V[x], 0.5 * (v1[x] + v2[x]), 1e-12 * V_DC);
        }
        assert_near(s->i_abc_A[0] + s->i_abc_A[1] + s->i_abc_A[2], 0.0, 1e-12);
    }
    /* the currents moved: the check was not on values near zero */
    assert_true(i_max > 0.5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_equal_halves_are_plant_advance),
        cmocka_unit_test(test_mid_period_step_is_piecewise_exponential),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
