/* The DC link with a capacitance (plant.h): charged by the rectifying
 * bridge at the analytic rate, the energy balances of motor and link over a
 * decelerating run (diode bridge and switching), the inverter legs'
 * clamp of a link driven below -v_f, held without load,
 * discharged by the brake chopper as exp(-t / (R_b C)) down to brake_off_V,
 * the chopper's hysteresis cycle against a source, the source charging
 * through R_s and its series diode. */
#include "mc_test.h"

#include <float.h>
#include <math.h>

#include "plant.h"
#include "plant_test_support.h"

#define T_PWM_S 50e-6
#define PSI_WB  0.17
#define N_P     3.0

static const double duty_any[3] = { 0.5, 0.5, 0.5 }; /* unused: the outputs are off */

/* Default motor at rest, outputs to be off, a 1 mF link fed by 48 V. */
static plant_config_t link_config(void)
{
    plant_config_t c;
    plant_config_default(&c);
    c.dc_link.capacitance_F = 1e-3;
    c.dc_link.source_resistance_ohm = 2.0;
    return c;
}

/* ---- Charging by the rectifier -------------------------------------------
 * The resistive machine of test_plant_diode_bridge (R = 10 ohm, L = 10 uH,
 * constant speed, theta_e(0) = pi/6: no pulse is cut by the window) charges
 * C = 1 F from v0 = 0.95 E with the source lost. Over one electrical period
 * T the link rises by dv = Q / C with Q the period's six pulses. The
 * resistive pulse current (E cos(phi) - v) / (2R) falls with v, so with v
 * between v0 and v1 = v0 + dv, i_avg(v1) T <= Q <= i_avg(v0) T; the
 * inductive lag can only lower Q, by at most the relative bound of
 * test_plant_diode_bridge. dv / T = i_avg / C to the bracket's width,
 * 6e-4 here. */
static void test_charging_rate_is_the_rectifier_current(void **state)
{
    (void)state;
    const double r_ohm = 10.0, l_H = 10e-6, c_F = 1.0;
    const int periods_e = 400; /* 20 ms */
    const double omega_e = MC_TEST_TWO_PI / (periods_e * T_PWM_S);
    const double e_V = sqrt(3.0) * PSI_WB * omega_e;
    plant_config_t c = link_config();
    c.motor.R_ohm = r_ohm;
    c.motor.Ld_H = l_H;
    c.motor.Lq_H = l_H;
    c.motor.J_kgm2 = 1e9;
    c.omega_m0_rad_s = omega_e / N_P;
    c.theta_m0_rad = MC_TEST_PI / 6.0 / N_P;
    c.substeps_per_period = 100u;
    c.dc_link.capacitance_F = c_F;
    c.dc_link.v0_given = true;
    c.dc_link.v0_V = 0.95 * e_V;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_int_equal(plant_set_source_connected(&p, false), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    for (int k = 0; k < periods_e; ++k) {
        plant_advance(&p, duty_any, false);
        assert_false(s->source_connected);
        assert_true(s->i_source_A == 0.0);
    }
    const double v0 = c.dc_link.v0_V, v1 = s->v_dc_V;
    const double t_e = periods_e * T_PWM_S;
    const double rate = (v1 - v0) * c_F / t_e; /* C dv/dt [A] */
    const double i0 = test_six_pulse_current_A(e_V, v0, r_ohm);
    const double i1 = test_six_pulse_current_A(e_V, v1, r_ohm);
    const double phi1 = acos(v1 / e_V), wt = omega_e * l_H / r_ohm;
    const double lag = wt * wt * sin(phi1) / (4.0 * (sin(phi1) - phi1 * cos(phi1)));
    print_message("C dv/dt %.10f A in [%.10f, %.10f] A (i_avg at v1, v0)\n", rate, i1, i0);
    assert_true(i1 < i0 && (i0 - i1) / i0 < 1e-3); /* a narrow bracket */
    assert_true(rate <= i0 * (1.0 + 1e-9));
    assert_true(rate >= i1 * (1.0 - lag - 1e-9));
    /* the charge went into the capacitor: C (v1^2 - v0^2) / 2 = -bus_J */
    assert_near(s->energy.capacitor_J, 0.5 * c_F * (v1 * v1 - v0 * v0), 1e-12 * v0 * v0);
    assert_near(s->energy.capacitor_J, -s->energy.bus_J, 1e-9 * s->energy.capacitor_J);
}

/* ---- Energy balances ------------------------------------------------------
 * Motor side: electrical_J = copper + friction + load + cogging +
 * constraint + change of magnetic (0.75 (Ld i_d^2 + Lq i_q^2)) and kinetic
 * (0.5 J omega^2) energy. Link side: source_J = source_resistor_J +
 * capacitor_J + brake_J + bus_J + link_clamp_J. bus_J - electrical_J: the inverter's
 * (diodes', dead time's) loss, >= 0. Every term is integrated by the same
 * RK4 as the state (the events located), so the balances close to the RK4
 * error: measured 4e-14 of the energies at 50 substeps, 1.3e-10 at 4
 * (fourth order: 12.5^4 = 24000 apart); 1e-9 bounds both. */
#define BALANCE_REL 1e-9

typedef struct {
    double motor_J, link_J, mech_lost_J;
} balance_t;

static balance_t balances(const plant_config_t *c, const plant_true_state_t *s, double omega0)
{
    const double j = c->motor.J_kgm2, ld = c->motor.Ld_H, lq = c->motor.Lq_H;
    const plant_energy_t *e = &s->energy;
    const double w_mag = 0.75 * (ld * s->i_d_A * s->i_d_A + lq * s->i_q_A * s->i_q_A);
    const double ke_lost = 0.5 * j * (omega0 * omega0 - s->omega_m_rad_s * s->omega_m_rad_s);
    balance_t b;
    b.motor_J = e->copper_J + e->friction_J + e->load_J + e->cogging_J + e->constraint_J + w_mag -
                ke_lost - e->electrical_J;
    b.link_J = e->source_resistor_J + e->capacitor_J + e->brake_J + e->bus_J + e->link_clamp_J -
               e->source_J;
    b.mech_lost_J = ke_lost;
    return b;
}

/* Outputs off at 300 rad/s (line back-EMF 265 V) on a 470 uF link at 48 V
 * with the source lost, a 20 ohm brake at 200 / 180 V, 0.8 V diodes, a
 * salient rotor with friction and cogging: the rotor decelerates, the link
 * charges and the chopper cycles. The kinetic energy lost is copper +
 * friction + cogging + diodes + capacitor + brake (+ magnetic, constraint). */
static void run_decelerating_balance(uint32_t substeps)
{
    plant_config_t c;
    plant_config_default(&c);
    c.motor.Lq_H = 1.5 * c.motor.Ld_H;
    c.motor.B_Nm_s_rad = 1e-4;
    c.motor.cogging = (plant_cogging_t){
        .slots = 9u, .n_harmonics = 1u, .amplitude_Nm = { 0.02 }, .phase_rad = { 0.3 }
    };
    c.inverter.v_device_drop_V = 0.8;
    c.omega_m0_rad_s = 300.0;
    c.substeps_per_period = substeps;
    c.dc_link = (plant_dc_link_t){ .capacitance_F = 470e-6,
                                   .source_resistance_ohm = 0.1,
                                   .brake_resistance_ohm = 20.0,
                                   .brake_on_V = 200.0,
                                   .brake_off_V = 180.0,
                                   .v0_given = true,
                                   .v0_V = 48.0 };
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_int_equal(plant_set_source_connected(&p, false), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    int toggles = 0;
    bool brake = s->brake_on;
    for (int k = 0; k < 10000; ++k) { /* 0.5 s */
        plant_advance(&p, duty_any, false);
        toggles += s->brake_on != brake;
        brake = s->brake_on;
    }
    const balance_t b = balances(&c, s, 300.0);
    const plant_energy_t *e = &s->energy;
    const double diodes_J = e->bus_J - e->electrical_J;
    print_message("%u substeps: kinetic energy lost %.9f J = copper %.6f + capacitor %.6f + brake "
                  "%.6f + diodes %.6f + friction %.6f + cogging %.6f; residuals %.2e, %.2e J\n",
                  substeps, b.mech_lost_J, e->copper_J, e->capacitor_J, e->brake_J, diodes_J,
                  e->friction_J, e->cogging_J, b.motor_J, b.link_J);
    assert_true(s->omega_m_rad_s < 0.9 * 300.0);
    assert_true(toggles >= 4 && e->capacitor_J > 1.0 && e->brake_J > 10.0 && diodes_J > 0.1);
    assert_true(e->source_J == 0.0 && e->source_resistor_J == 0.0);
    assert_near(b.motor_J, 0.0, BALANCE_REL * b.mech_lost_J);
    assert_near(b.link_J, 0.0, BALANCE_REL * b.mech_lost_J);
    assert_near(b.mech_lost_J,
                e->copper_J + e->capacitor_J + e->brake_J + diodes_J + e->friction_J +
                    e->cogging_J + e->load_J + e->constraint_J +
                    0.75 *
                        (c.motor.Ld_H * s->i_d_A * s->i_d_A + c.motor.Lq_H * s->i_q_A * s->i_q_A),
                2.0 * BALANCE_REL * b.mech_lost_J);
    /* the zero-current clamps removed no more than their rounding */
    assert_true(fabs(e->constraint_J) < 1e-9);
}

static void test_energy_balance_decelerating_rectifier(void **state)
{
    (void)state;
    run_decelerating_balance(PLANT_DEFAULT_SUBSTEPS);
    run_decelerating_balance(PLANT_SUBSTEPS_FAST);
}

/* Switching on a capacitive link: random duties around the back-EMF with
 * dead time; the source is lost for the middle third. The bridge draws
 * sum d_x i_x from the link; both balances close. */
static void test_energy_balance_switching_on_link(void **state)
{
    (void)state;
    plant_config_t c = link_config();
    c.dc_link.source_resistance_ohm = 0.05;
    c.dc_link.brake_resistance_ohm = 10.0;
    c.dc_link.brake_on_V = 52.0;
    c.dc_link.brake_off_V = 50.0;
    c.inverter.t_dead_s = 1e-6;
    c.inverter.dead_time_current_band_A = 0.2;
    c.motor.B_Nm_s_rad = 1e-3;
    c.omega_m0_rad_s = 50.0;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    uint64_t rng = 5u;
    double v_min = 48.0;
    for (int k = 0; k < 6000; ++k) { /* 0.3 s */
        if (k == 2000 || k == 4000) {
            assert_int_equal(plant_set_source_connected(&p, k == 4000), PLANT_OK);
        }
        const double th = N_P * s->theta_m_rad, e = N_P * s->omega_m_rad_s * PSI_WB;
        double d[3];
        test_duties_for_alpha_beta(-e * sin(th) - 3.0 * sin(th), e * cos(th) + 3.0 * cos(th),
                                   s->v_dc_V, d);
        for (int x = 0; x < 3; ++x)
            d[x] += test_uniform(&rng, -0.02, 0.02);
        plant_advance(&p, d, true);
        if (k >= 2000 && k < 4000) {
            assert_true(s->i_source_A == 0.0);
            v_min = fmin(v_min, s->v_dc_V);
        }
    }
    const balance_t b = balances(&c, s, 50.0);
    const plant_energy_t *e = &s->energy;
    print_message("switching: source %.6f J, bus %.6f J, electrical %.6f J, residuals %.2e, %.2e "
                  "J, link minimum %.3f V\n",
                  e->source_J, e->bus_J, e->electrical_J, b.motor_J, b.link_J, v_min);
    assert_true(e->bus_J > 1.0 && v_min < 47.0); /* the drive drew from the link */
    assert_true(e->bus_J >= e->electrical_J);    /* dead time dissipates */
    assert_near(b.motor_J, 0.0, BALANCE_REL * e->bus_J);
    assert_near(b.link_J, 0.0, BALANCE_REL * e->bus_J);
}

/* Switching on, source lost, the drive keeps drawing: locked rotor, duties
 * (0.9, 0.1, 0.5) on a 100 uF link from 48 V with 0.7 V devices. The
 * inductive current empties the link and would drive it negative; the
 * legs clamp it at -v_f (held exactly while clamped, never below), taking
 * the current (energy in link_clamp_J, balance closed). Reconnected, the
 * source lifts the link off the clamp at once. */
static void test_link_clamped_by_the_legs(void **state)
{
    (void)state;
    const double v_f = 0.7;
    plant_config_t c = link_config();
    c.locked_rotor = true;
    c.inverter.v_device_drop_V = v_f;
    c.inverter.dead_time_current_band_A = 0.2; /* smooth: the balance to RK4 accuracy */
    c.dc_link.capacitance_F = 100e-6;
    c.dc_link.source_resistance_ohm = 0.1;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_int_equal(plant_set_source_connected(&p, false), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    const double d[3] = { 0.9, 0.1, 0.5 };
    int n_clamped = 0;
    double v_clamp = NAN;
    for (int k = 0; k < 400; ++k) { /* 20 ms */
        plant_advance(&p, d, true);
        assert_true(s->v_dc_V >= -v_f - 1e-9);
        if (s->link_clamped) {
            v_clamp = isnan(v_clamp) ? s->v_dc_V : v_clamp;
            assert_true(s->v_dc_V == v_clamp);
            n_clamped++;
        }
    }
    assert_true(n_clamped > 100);
    assert_near(v_clamp, -v_f, 1e-9);
    const plant_energy_t *e = &s->energy;
    const balance_t b = balances(&c, s, 0.0);
    print_message("clamped %d periods at %.12f V; legs %.6f J, residuals %.2e, %.2e J\n", n_clamped,
                  v_clamp, e->link_clamp_J, b.motor_J, b.link_J);
    assert_true(e->link_clamp_J > 0.0);
    assert_near(b.link_J, 0.0, BALANCE_REL * e->bus_J);
    assert_near(b.motor_J, 0.0, BALANCE_REL * e->bus_J);
    assert_int_equal(plant_set_source_connected(&p, true), PLANT_OK);
    plant_advance(&p, d, true);
    assert_false(s->link_clamped);
    assert_true(s->v_dc_V > 0.0 && s->i_source_A > 0.0);
}

/* ---- Link alone ------------------------------------------------------------ */

/* Rotor at rest, outputs off, source lost: nothing moves the link, inside
 * the chopper's hysteresis band neither. */
static void test_link_held_without_load(void **state)
{
    (void)state;
    plant_config_t c = link_config();
    c.dc_link.brake_resistance_ohm = 10.0;
    c.dc_link.brake_on_V = 70.0;
    c.dc_link.brake_off_V = 65.0;
    c.dc_link.v0_given = true;
    c.dc_link.v0_V = 68.0; /* between off and on: the brake starts off */
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_int_equal(plant_set_source_connected(&p, false), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    assert_false(s->brake_on);
    for (int k = 0; k < 2000; ++k) {
        plant_advance(&p, duty_any, false);
        assert_true(s->v_dc_V == 68.0);
        assert_true(s->i_source_A == 0.0 && s->i_bridge_A == 0.0 && s->i_brake_A == 0.0);
        assert_false(s->brake_on);
    }
}

/* v0 = 80 V above brake_on = 75 V: the brake connects R_b = 10 ohm across
 * C = 1 mF, v = v0 exp(-t / (R_b C)) until it falls below brake_off = 60 V
 * at t* = R_b C ln(80 / 60) (located), then it is held there. RK4 on
 * v' = -v / tau with z = h / tau = 1e-4 errs by z^5 / 120 per step; what
 * remains is rounding, ~1e-16 v per step over 3000 steps: 1e-10 V. */
static void test_brake_exponential_down_to_brake_off(void **state)
{
    (void)state;
    const double c_F = 1e-3, r_b = 10.0, v0 = 80.0, v_on = 75.0, v_off = 60.0;
    plant_config_t c = link_config();
    c.dc_link.brake_resistance_ohm = r_b;
    c.dc_link.brake_on_V = v_on;
    c.dc_link.brake_off_V = v_off;
    c.dc_link.v0_given = true;
    c.dc_link.v0_V = v0;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_int_equal(plant_set_source_connected(&p, false), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    assert_true(s->brake_on);
    const double tau = r_b * c_F, t_star = tau * log(v0 / v_off);
    double v_held = NAN;
    for (int k = 1; k <= 400; ++k) { /* 20 ms */
        plant_advance(&p, duty_any, false);
        const double t = k * T_PWM_S;
        if (t < t_star) {
            assert_true(s->brake_on);
            assert_near(s->v_dc_V, v0 * exp(-t / tau), 1e-10);
            assert_near(s->i_brake_A, s->v_dc_V / r_b, 1e-12);
        } else {
            assert_false(s->brake_on);
            if (isnan(v_held)) {
                v_held = s->v_dc_V;
            }
            assert_true(s->v_dc_V == v_held);
            assert_true(s->i_brake_A == 0.0);
        }
    }
    print_message("brake off at t* = %.6f ms, held at %.12f V\n", 1e3 * t_star, v_held);
    assert_near(v_held, v_off, 1e-9);
    assert_near(s->energy.brake_J, 0.5 * c_F * (v0 * v0 - v_held * v_held), 1e-9);
    assert_near(s->energy.capacitor_J, -s->energy.brake_J, 1e-12);
}

/* The chopper against a source above brake_on: v_s = 90 V through R_s =
 * 5 ohm, R_b = 5 ohm, on 75 V, off 60 V. Brake off, v charges towards 90 V
 * with tau = R_s C; on, towards v_eq = 45 V with tau = (R_s || R_b) C. The
 * cycle: 60 -> 75 in R_s C ln(30 / 15), 75 -> 60 in (R_s || R_b) C
 * ln(30 / 15); v never leaves [60, 75] once it reached 75. */
static void test_brake_hysteresis_cycle(void **state)
{
    (void)state;
    const double c_F = 1e-3, r_s = 5.0, r_b = 5.0;
    plant_config_t c = link_config();
    sim_profile_set_constant(&c.inverter.v_dc_V, 90.0);
    c.dc_link.source_resistance_ohm = r_s;
    c.dc_link.brake_resistance_ohm = r_b;
    c.dc_link.brake_on_V = 75.0;
    c.dc_link.brake_off_V = 60.0;
    c.dc_link.v0_given = true;
    c.dc_link.v0_V = 0.0;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    const double cycle_s = (r_s + r_s * r_b / (r_s + r_b)) * c_F * log(2.0);
    int first_on = -1, last_on = -1, n_on = 0;
    bool brake = false;
    for (int k = 1; k <= 4000; ++k) { /* 200 ms */
        plant_advance(&p, duty_any, false);
        if (s->brake_on && !brake) {
            first_on = first_on < 0 ? k : first_on;
            last_on = k;
            n_on++;
        }
        brake = s->brake_on;
        if (first_on > 0) {
            assert_true(s->v_dc_V >= 60.0 - 1e-9 && s->v_dc_V <= 75.0 + 1e-9);
        }
    }
    const double measured_s = (last_on - first_on) * T_PWM_S / (n_on - 1);
    print_message("chopper cycle %.6f ms (analytic %.6f ms) over %d cycles\n", 1e3 * measured_s,
                  1e3 * cycle_s, n_on - 1);
    assert_true(n_on > 30);
    /* the switch-on instants are seen at period ends: +-1 period */
    assert_near(measured_s, cycle_s, T_PWM_S / (n_on - 1));
}

/* The source through R_s = 2 ohm charges C = 1 mF from 20 V:
 * v = 48 - 28 exp(-t / (R_s C)) (outputs off, rotor at rest). After the
 * source steps down to 30 V at 20 ms its diode blocks: no current, v held;
 * lost, likewise. Link balance: source_J = source_resistor_J + capacitor_J. */
static void test_source_charges_through_resistor_and_diode(void **state)
{
    (void)state;
    plant_config_t c = link_config();
    c.inverter.v_dc_V.points[1] = (sim_profile_point_t){ .t_s = 0.02, .value = 48.0 };
    c.inverter.v_dc_V.points[2] = (sim_profile_point_t){ .t_s = 0.02, .value = 30.0 };
    c.inverter.v_dc_V.n_points = 3u;
    c.dc_link.v0_given = true;
    c.dc_link.v0_V = 20.0;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    const double tau = 2.0 * 1e-3;
    double v_held = NAN;
    for (int k = 1; k <= 800; ++k) { /* 40 ms */
        if (k == 601) {
            assert_int_equal(plant_set_source_connected(&p, false), PLANT_OK);
        }
        plant_advance(&p, duty_any, false);
        const double t = k * T_PWM_S;
        if (k < 400) {
            const double want = 48.0 - 28.0 * exp(-t / tau);
            assert_near(s->v_dc_V, want, 1e-10);
            assert_near(s->i_source_A, (48.0 - s->v_dc_V) / 2.0, 1e-12);
            assert_true(s->source_connected && s->v_source_V == 48.0);
        } else { /* from t = 20 ms (k = 400) the source is at 30 V */
            assert_true(s->v_source_V == 30.0);
            v_held = isnan(v_held) ? s->v_dc_V : v_held;
            assert_true(s->i_source_A == 0.0 && s->v_dc_V == v_held);
            assert_true(s->source_connected == (k <= 600));
        }
    }
    assert_near(v_held, 48.0 - 28.0 * exp(-0.02 / tau), 1e-10);
    const plant_energy_t *e = &s->energy;
    assert_near(e->source_J, e->source_resistor_J + e->capacitor_J, 1e-12);
    assert_near(e->capacitor_J, 0.5e-3 * (v_held * v_held - 400.0), 1e-9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_charging_rate_is_the_rectifier_current),
        cmocka_unit_test(test_energy_balance_decelerating_rectifier),
        cmocka_unit_test(test_energy_balance_switching_on_link),
        cmocka_unit_test(test_link_clamped_by_the_legs),
        cmocka_unit_test(test_link_held_without_load),
        cmocka_unit_test(test_brake_exponential_down_to_brake_off),
        cmocka_unit_test(test_brake_hysteresis_cycle),
        cmocka_unit_test(test_source_charges_through_resistor_and_diode),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
