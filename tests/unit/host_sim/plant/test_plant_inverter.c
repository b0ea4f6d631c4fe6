/* Inverter average model: dead-time sign and magnitude, device drop, linear
 * zone, common mode, duty clamping, outputs disabled (diode bridge). */
#include "mc_test.h"

#include <math.h>

#include "plant.h"
#include "plant_test_support.h"

#define V_DC  48.0
#define R_OHM 0.225

static plant_config_t locked_config(double t_dead_s, double v_drop_V, double band_A)
{
    plant_config_t c;
    plant_config_default(&c);
    c.locked_rotor = true;
    c.inverter.t_dead_s = t_dead_s;
    c.inverter.v_device_drop_V = v_drop_V;
    c.inverter.dead_time_current_band_A = band_A;
    return c;
}

static const plant_true_state_t *run_locked(plant_t *p, const plant_config_t *c, double v_d,
                                            int periods)
{
    assert_int_equal(plant_init(p, c), PLANT_OK);
    double duty[3];
    test_duties_for_alpha_beta(v_d, 0.0, V_DC, duty);
    for (int k = 0; k < periods; ++k)
        plant_advance(p, duty, true);
    return plant_true_state(p);
}

/* Per-phase terminal error -sign(i) (t_dead f_pwm v_dc + v_drop). At
 * theta_e = 0 with i_a > 0 and i_b = i_c < 0 the star point removes the
 * mean: v_a loses 4/3 v_err, v_b and v_c gain 2/3 v_err, so the locked-rotor
 * steady current is (V - 4/3 v_err) / R. Reversed command: reversed error. */
static void test_dead_time_sign_and_magnitude(void **state)
{
    (void)state;
    const double t_dead = 2e-6, v_drop = 0.7;
    const double v_err = t_dead * 20000.0 * V_DC + v_drop; /* 2.62 V */
    const plant_config_t c = locked_config(t_dead, v_drop, 0.0);
    plant_t p;
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        const double v_cmd = sgn * 6.0;
        const plant_true_state_t *s = run_locked(&p, &c, v_cmd, 8000); /* 0.4 s = 24 L/R */
        const double v_a = v_cmd - sgn * 4.0 / 3.0 * v_err;
        assert_near(s->i_d_A, v_a / R_OHM, 1e-6 * fabs(v_a / R_OHM));
        assert_near(s->v_abc_V[0], v_a, 1e-9);
        assert_near(s->v_abc_V[1], -0.5 * v_cmd + sgn * 2.0 / 3.0 * v_err, 1e-9);
        assert_near(s->v_abc_V[2], -0.5 * v_cmd + sgn * 2.0 / 3.0 * v_err, 1e-9);
        /* line voltage a-b loses exactly 2 v_err: one v_err per phase leg */
        assert_near(s->v_abc_V[0] - s->v_abc_V[1], 1.5 * v_cmd - sgn * 2.0 * v_err, 1e-9);
        /* the dead time draws from the bus what it does not deliver */
        assert_true(s->energy.bus_J > s->energy.electrical_J);
    }
}

/* Linear zone: with |i| << band the error is -v_err i / band per phase, a
 * resistance v_err / band in series with R: i = V / (R + v_err / band). */
static void test_dead_time_linear_zone(void **state)
{
    (void)state;
    const double t_dead = 1e-6, band = 100.0;
    const double v_err = t_dead * 20000.0 * V_DC;
    const plant_config_t c = locked_config(t_dead, 0.0, band);
    plant_t p;
    const plant_true_state_t *s = run_locked(&p, &c, 3.0, 8000);
    const double want = 3.0 / (R_OHM + v_err / band);
    assert_true(want < band);
    assert_near(s->i_d_A, want, 1e-6 * want);
}

/* plant_set_dead_time: a dead time changed at run time (config 0 -> 3 us)
 * acts from the next advance with the magnitude the config would have
 * given it (the locked-rotor current of test_dead_time_sign_and_magnitude,
 * (V - 4/3 t_d f v_dc) / R), and back to 0 restores V / R. Out-of-range
 * dead times are refused and leave it unchanged. */
static void test_dead_time_set_at_run_time(void **state)
{
    (void)state;
    const double t_dead = 3e-6, v_cmd = 6.0;
    const plant_config_t c = locked_config(0.0, 0.0, 0.0);
    plant_t p;
    const plant_true_state_t *s = run_locked(&p, &c, v_cmd, 8000);
    assert_near(s->i_d_A, v_cmd / R_OHM, 1e-6 * v_cmd / R_OHM);
    assert_int_equal(plant_set_dead_time(&p, t_dead), PLANT_OK);
    assert_int_equal(plant_set_dead_time(&p, -1e-9), PLANT_ERR_ARGUMENT);
    assert_int_equal(plant_set_dead_time(&p, 0.5 / 20000.0), PLANT_ERR_ARGUMENT);
    assert_int_equal(plant_set_dead_time(&p, NAN), PLANT_ERR_ARGUMENT);
    double duty[3];
    test_duties_for_alpha_beta(v_cmd, 0.0, V_DC, duty);
    for (int k = 0; k < 8000; ++k)
        plant_advance(&p, duty, true);
    const double v_a = v_cmd - 4.0 / 3.0 * t_dead * 20000.0 * V_DC;
    assert_near(s->i_d_A, v_a / R_OHM, 1e-6 * v_a / R_OHM);
    assert_near(s->v_abc_V[0], v_a, 1e-9);
    assert_int_equal(plant_set_dead_time(&p, 0.0), PLANT_OK);
    for (int k = 0; k < 8000; ++k)
        plant_advance(&p, duty, true);
    assert_near(s->i_d_A, v_cmd / R_OHM, 1e-6 * v_cmd / R_OHM);
}

/* The star point floats: adding the same offset to all duties changes
 * nothing; duties beyond [0, 1] are clamped. */
static void test_common_mode_and_clamp(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.omega_m0_rad_s = 10.0;
    plant_t a, b, d;
    assert_int_equal(plant_init(&a, &c), PLANT_OK);
    assert_int_equal(plant_init(&b, &c), PLANT_OK);
    assert_int_equal(plant_init(&d, &c), PLANT_OK);
    const double base[3] = { 0.6, 0.45, 0.3 };
    const double shifted[3] = { 0.7, 0.55, 0.4 };
    const double over[3] = { 1.7, 0.0, -0.4 };
    const double clamped[3] = { 1.0, 0.0, 0.0 };
    for (int k = 0; k < 200; ++k) {
        plant_advance(&a, base, true);
        plant_advance(&b, shifted, true);
    }
    assert_near(plant_true_state(&b)->i_q_A, plant_true_state(&a)->i_q_A, 1e-9);
    assert_near(plant_true_state(&b)->i_d_A, plant_true_state(&a)->i_d_A, 1e-9);
    assert_true(fabs(plant_true_state(&a)->i_q_A) > 0.1);
    plant_t e;
    assert_int_equal(plant_init(&e, &c), PLANT_OK);
    for (int k = 0; k < 20; ++k) {
        plant_advance(&d, over, true);
        plant_advance(&e, clamped, true);
    }
    assert_true(plant_true_state(&d)->i_d_A == plant_true_state(&e)->i_d_A);
    /* ideal inverter average: v_a = v_dc (d_a - mean d) */
    assert_near(plant_true_state(&e)->v_abc_V[0], V_DC * (1.0 - 1.0 / 3.0), 1e-9);
}

/* Outputs off below the bus: the currents are driven to exactly zero
 * through the diodes (returning energy to the bus), then stay zero. */
static void test_disabled_currents_extinguish(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.omega_m0_rad_s = 40.0; /* line back-EMF peak sqrt(3) 0.17 * 120 = 35 V */
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double on[3] = { 0.5, 0.5, 0.5 }; /* short the windings: braking current */
    for (int k = 0; k < 100; ++k)
        plant_advance(&p, on, true);
    const plant_true_state_t *s = plant_true_state(&p);
    const double i0 = fmax(fabs(s->i_abc_A[0]), fmax(fabs(s->i_abc_A[1]), fabs(s->i_abc_A[2])));
    assert_true(i0 > 5.0);
    const double bus_before = s->energy.bus_J;
    int k_off = -1;
    for (int k = 0; k < 2000; ++k) {
        plant_advance(&p, on, false);
        if (s->open_circuit && k_off < 0)
            k_off = k;
        if (k_off >= 0) {
            assert_true(s->i_d_A == 0.0 && s->i_q_A == 0.0);
            assert_true(s->i_abc_A[0] == 0.0 && s->i_abc_A[1] == 0.0 && s->i_abc_A[2] == 0.0);
        }
    }
    /* every conducting loop (two windings, 2L) sees at least the bus minus
     * the peak line EMF against its current: extinct within
     * 2 L i0 / (v_dc - sqrt(3) psi omega_e) */
    const double t_bound = 2.0 * 3.8e-3 * i0 / (V_DC - sqrt(3.0) * 0.17 * 120.0);
    assert_true(k_off >= 0 && (k_off + 1) / 20000.0 <= t_bound);
    assert_true(s->energy.bus_J < bus_before); /* energy went back to the bus */
    assert_false(s->rectifying);
    assert_false(s->outputs_enabled);
    for (int x = 0; x < 3; ++x)
        assert_int_equal(s->phase_state[x], PLANT_PHASE_BLOCKING);
    assert_near(s->tau_e_Nm, 0.0, 0.0);
}

/* Above the bus the diodes rectify (this used to be flagged as unmodelled):
 * from rest currents, the pair with the largest line back-EMF starts to
 * conduct at once, the bridge returns current to the bus (i_bridge < 0,
 * bus energy < 0) and the torque brakes the rotor. The rectified current
 * itself is checked against the analytic bridge in test_plant_diode_bridge. */
static void test_rectification_above_bus(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.omega_m0_rad_s = 200.0; /* line EMF peak 177 V > 48 V */
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double duty[3] = { 0.5, 0.5, 0.5 };
    plant_advance(&p, duty, false);
    const plant_true_state_t *s = plant_true_state(&p);
    assert_true(s->rectifying && !s->open_circuit);
    assert_true(s->i_bridge_A < 0.0);
    assert_true(s->energy.bus_J < 0.0);
    assert_true(s->tau_e_Nm < 0.0);
    assert_near(s->i_abc_A[0] + s->i_abc_A[1] + s->i_abc_A[2], 0.0, 1e-12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dead_time_sign_and_magnitude),
        cmocka_unit_test(test_dead_time_linear_zone),
        cmocka_unit_test(test_dead_time_set_at_run_time),
        cmocka_unit_test(test_common_mode_and_clamp),
        cmocka_unit_test(test_disabled_currents_extinguish),
        cmocka_unit_test(test_rectification_above_bus),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
