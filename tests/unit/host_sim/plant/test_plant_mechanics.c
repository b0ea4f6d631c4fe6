/* Mechanics and energy: steady state of the dq equations with viscous
 * friction and load, energy balance, cogging, time-varying inertia. */
#include "mc_test.h"

#include <math.h>

#include "plant.h"
#include "plant_test_support.h"

/* Steady state for v_d = 0, constant v_q, surface motor, friction B, load
 * tau_L:  i_q = (B w + tau_L) / Kt,  i_d = n_p w L i_q / R,
 *         v_q = R i_q + n_p w (L i_d + psi),  Kt = 1.5 n_p psi.
 * Solved for w by Newton here, independently of the plant. */
static double steady_residual(double w, double v_q, double r, double l, double psi, double np,
                              double b, double tau_l)
{
    const double i_q = (b * w + tau_l) / (1.5 * np * psi);
    const double i_d = np * w * l * i_q / r;
    return r * i_q + np * w * (l * i_d + psi) - v_q;
}

static void test_steady_speed_and_torque_balance(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.motor.B_Nm_s_rad = 0.02;
    sim_profile_set_constant(&c.load_torque_Nm, 0.3);
    c.substeps_per_period = 10u;
    const double v_q = 10.0, r = 0.225, l = 3.8e-3, psi = 0.17, np = 3.0, b = 0.02, tau_l = 0.3;
    double w = v_q / (np * psi);
    for (int it = 0; it < 50; ++it) {
        const double h = 1e-6;
        const double f = steady_residual(w, v_q, r, l, psi, np, b, tau_l);
        const double df = (steady_residual(w + h, v_q, r, l, psi, np, b, tau_l) - f) / h;
        w -= f / df;
    }
    assert_near(steady_residual(w, v_q, r, l, psi, np, b, tau_l), 0.0, 1e-12);
    const double i_q = (b * w + tau_l) / (1.5 * np * psi);
    const double i_d = np * w * l * i_q / r;

    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    for (int k = 0; k < 12000; ++k) { /* 0.6 s: > 30 electrical time constants */
        plant_advance_vdq(&p, 0.0, v_q);
    }
    const plant_true_state_t *s = plant_true_state(&p);
    assert_near(s->omega_m_rad_s, w, 1e-6 * w);
    assert_near(s->i_q_A, i_q, 1e-6 * i_q);
    assert_near(s->i_d_A, i_d, 1e-6 * i_d);
    /* torque balance at steady state: tau_e = B w + tau_L */
    assert_near(s->tau_e_Nm, b * w + tau_l, 1e-6 * (b * w + tau_l));
    assert_near(s->tau_friction_Nm, b * w, 1e-6 * b * w);
    assert_near(s->tau_load_Nm, tau_l, 0.0);
}

/* Electrical input = copper + change of magnetic energy 0.75 (Ld id^2 +
 * Lq iq^2) + change of kinetic energy + friction + load + cogging work, over
 * random duties, with saliency, dead time, Coulomb friction, cogging and a
 * sinusoidal load. */
static void test_energy_balance_random_run(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.motor.Lq_H = 1.5 * c.motor.Ld_H;
    c.motor.B_Nm_s_rad = 2e-3;
    c.motor.tau_coulomb_Nm = 0.05;
    c.motor.coulomb_eps_rad_s = 0.5;
    c.motor.cogging = (plant_cogging_t){
        .slots = 9u, .n_harmonics = 2u, .amplitude_Nm = { 0.08, 0.03 }, .phase_rad = { 0.4, -1.0 }
    };
    c.inverter.t_dead_s = 1e-6;
    c.inverter.dead_time_current_band_A = 0.2;
    sim_profile_set_constant(&c.load_torque_Nm, 0.2);
    c.load_torque_Nm.sines[0] = (sim_profile_sine_t){ .amplitude = 0.1, .freq_Hz = 7.0 };
    c.load_torque_Nm.n_sines = 1u;
    c.omega_m0_rad_s = 30.0;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    const double ld = c.motor.Ld_H, lq = c.motor.Lq_H, j = c.motor.J_kgm2;
    const double w_mag0 = 0.75 * (ld * s->i_d_A * s->i_d_A + lq * s->i_q_A * s->i_q_A);
    const double ke0 = 0.5 * j * s->omega_m_rad_s * s->omega_m_rad_s;
    uint64_t rng = 3u;
    double duty[3];
    for (int k = 0; k < 4000; ++k) { /* 0.2 s, a new random duty set every 2.5 ms */
        if (k % 50 == 0) {
            for (int x = 0; x < 3; ++x)
                duty[x] = test_uniform(&rng, 0.4, 0.6);
        }
        plant_advance(&p, duty, true);
    }
    const double w_mag = 0.75 * (ld * s->i_d_A * s->i_d_A + lq * s->i_q_A * s->i_q_A);
    const double ke = 0.5 * j * s->omega_m_rad_s * s->omega_m_rad_s;
    const plant_energy_t *e = &s->energy;
    const double out =
        e->copper_J + (w_mag - w_mag0) + (ke - ke0) + e->friction_J + e->load_J + e->cogging_J;
    print_message("E_in %.6f J, copper %.6f, friction %.6f, load %.6f, cog %.6f\n", e->electrical_J,
                  e->copper_J, e->friction_J, e->load_J, e->cogging_J);
    assert_true(e->copper_J > 1.0 && fabs(e->electrical_J) > 1.0); /* not a trivial run */
    assert_true(e->friction_J > 0.0 && fabs(e->load_J) > 0.0 && fabs(e->cogging_J) > 0.0);
    assert_near(out, e->electrical_J, 1e-6 * fabs(e->electrical_J));
    /* the inverter's dead time dissipates: bus energy >= motor input */
    assert_true(e->bus_J >= e->electrical_J);
}

/* tau_cog = sum_k A_k cos(k Q theta + phi_k): value at a point, zero mean
 * over a revolution; with no current and no friction the cogging work equals
 * the potential difference U(theta1) - U(theta0),
 * U = sum_k A_k / (k Q) sin(k Q theta + phi_k). */
static const plant_cogging_t k_cog = { .slots = 12u,
                                       .n_harmonics = 3u,
                                       .amplitude_Nm = { 0.1, 0.04, 0.02 },
                                       .phase_rad = { 0.3, 1.1, -0.7 } };

static double cog_ref(double th)
{
    double t = 0.0;
    for (int k = 0; k < 3; ++k)
        t += k_cog.amplitude_Nm[k] * cos((k + 1) * 12.0 * th + k_cog.phase_rad[k]);
    return t;
}

static double cog_potential(double th)
{
    double u = 0.0;
    for (int k = 0; k < 3; ++k) {
        u += k_cog.amplitude_Nm[k] / ((k + 1) * 12.0) *
             sin((k + 1) * 12.0 * th + k_cog.phase_rad[k]);
    }
    return u;
}

static void test_cogging_value_and_zero_mean(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.motor.cogging = k_cog;
    plant_t p;
    const int m = 1000;
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
        c.theta_m0_rad = MC_TEST_TWO_PI * (i + 0.37) / m;
        assert_int_equal(plant_init(&p, &c), PLANT_OK);
        const double tau = plant_true_state(&p)->tau_cog_Nm;
        assert_near(tau, cog_ref(c.theta_m0_rad), 1e-12);
        sum += tau;
    }
    assert_near(sum / m, 0.0, 1e-12);
}

static void test_cogging_work_is_potential_difference(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.motor.cogging = k_cog;
    c.omega_m0_rad_s = 20.0; /* line back-EMF 17.7 V < 48 V: stays open */
    c.theta_m0_rad = 0.2;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double duty[3] = { 0.5, 0.5, 0.5 };
    for (int k = 0; k < 4000; ++k)
        plant_advance(&p, duty, false);
    const plant_true_state_t *s = plant_true_state(&p);
    assert_true(s->open_circuit); /* all phases blocking: no diode conducts */
    assert_near(s->i_d_A, 0.0, 0.0);
    assert_near(s->energy.cogging_J, cog_potential(s->theta_m_rad) - cog_potential(0.2), 1e-9);
    /* no friction: kinetic energy + cogging potential conserved */
    const double ke = 0.5 * 0.012 * s->omega_m_rad_s * s->omega_m_rad_s;
    assert_near(ke + cog_potential(s->theta_m_rad), 0.5 * 0.012 * 400.0 + cog_potential(0.2), 1e-9);
}

/* Paper 000 section 6: g3 = 1/J + A sin(Omega t). With no electrical torque
 * (psi = 0, outputs off) and a constant load tau_L:
 * w(t) = w0 - tau_L (t / J + A (1 - cos(Omega t)) / Omega). */
static void test_time_varying_inertia(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.motor.psi_Wb = 0.0;
    const double j = 0.012, a = 0.5 / j, om = 20.0, tau_l = 0.05, w0 = 30.0;
    c.motor.g3_amplitude_per_kgm2 = a;
    c.motor.g3_omega_rad_s = om;
    sim_profile_set_constant(&c.load_torque_Nm, tau_l);
    c.omega_m0_rad_s = w0;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const double duty[3] = { 0.5, 0.5, 0.5 };
    for (int k = 1; k <= 4000; ++k) {
        plant_advance(&p, duty, false);
        if (k % 100 == 0) {
            const double t = plant_true_state(&p)->t_s;
            const double want = w0 - tau_l * (t / j + a * (1.0 - cos(om * t)) / om);
            assert_near(plant_true_state(&p)->omega_m_rad_s, want, 1e-9);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_steady_speed_and_torque_balance),
        cmocka_unit_test(test_energy_balance_random_run),
        cmocka_unit_test(test_cogging_value_and_zero_mean),
        cmocka_unit_test(test_cogging_work_is_potential_difference),
        cmocka_unit_test(test_time_varying_inertia),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
