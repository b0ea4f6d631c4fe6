/* Runtime faults (plant_set_phase_open / _rotor_locked /
 * _source_connected): an open phase carries exactly zero current in every
 * mode, the other two opposite currents; on a locked rotor the two-phase
 * loop is the R-L circuit of the loop inductance (salient too); the
 * torque is that of the remaining currents; the cut current's magnetic
 * energy is accounted; a locked rotor holds omega = 0 and theta exactly
 * and is free again when released; bad requests are refused. */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "plant.h"
#include "plant_test_support.h"

#define V_DC   48.0
#define N_P    3.0
#define PSI_WB 0.17
#define R_OHM  0.225

/* The test's own amplitude-invariant Clarke + Park. */
static void abc_to_dq(const double i_abc[3], double theta_e, double *d, double *q)
{
    const double alpha = (2.0 * i_abc[0] - i_abc[1] - i_abc[2]) / 3.0;
    const double beta = (i_abc[1] - i_abc[2]) / sqrt(3.0);
    *d = cos(theta_e) * alpha + sin(theta_e) * beta;
    *q = -sin(theta_e) * alpha + cos(theta_e) * beta;
}

static double torque_Nm(const double i_abc[3], double theta_e, double ld, double lq)
{
    double d, q;
    abc_to_dq(i_abc, theta_e, &d, &q);
    return 1.5 * N_P * (PSI_WB * q + (ld - lq) * d * q);
}

/* Flux linkage lambda_a - lambda_b per ampere of the loop current I in
 * a (i_a = I, i_b = -I, i_c = 0) at rotor angle theta_e (PM flux aside):
 * dq currents, lambda_d = Ld i_d, lambda_q = Lq i_q, back to abc. */
static double loop_inductance_H(double theta_e, double ld, double lq)
{
    const double i_abc[3] = { 1.0, -1.0, 0.0 };
    double d, q;
    abc_to_dq(i_abc, theta_e, &d, &q);
    const double l_d = ld * d, l_q = lq * q;
    const double l_alpha = cos(theta_e) * l_d - sin(theta_e) * l_q;
    const double l_beta = sin(theta_e) * l_d + cos(theta_e) * l_q;
    const double l_a = l_alpha;
    const double l_b = -0.5 * l_alpha + 0.5 * sqrt(3.0) * l_beta;
    return l_a - l_b;
}

/* Locked rotor at theta_e = 0.9 rad, phase c open, ideal inverter with
 * duties (0.6, 0.4, 0.5): the a-b loop sees v_ab = 0.2 v_dc over 2R and
 * L_loop (2L for a surface machine), so
 *   i_a = v_ab / (2R) (1 - exp(-2R t / L_loop)),  i_b = -i_a,  i_c = 0.
 * RK4 (z = 2R h / L_loop < 1e-4) and the per-substep projection onto
 * i_c = 0 keep it to rounding: 1e-9 of the current. The floating phase c
 * has no current and (locked) no back-EMF; with Ld = Lq its flux is
 * L i_c = 0 too, so its voltage to the star point is 0. */
static void check_locked_open_phase(double lq_over_ld)
{
    const double ld = 3.8e-3, lq = lq_over_ld * ld, theta_e = 0.9;
    plant_config_t c;
    plant_config_default(&c);
    c.motor.Lq_H = lq;
    c.locked_rotor = true;
    c.theta_m0_rad = theta_e / N_P;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_int_equal(plant_set_phase_open(&p, 2u, true), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    const double duty[3] = { 0.6, 0.4, 0.5 };
    const double v_ab = 0.2 * V_DC;
    const double l_loop = loop_inductance_H(theta_e, ld, lq);
    for (int k = 1; k <= 2000; ++k) { /* 0.1 s */
        plant_advance(&p, duty, true);
        const double want = v_ab / (2.0 * R_OHM) * (1.0 - exp(-2.0 * R_OHM * s->t_s / l_loop));
        assert_near(s->i_abc_A[0], want, 1e-9 * fabs(want));
        assert_true(s->i_abc_A[1] == -s->i_abc_A[0]);
        assert_true(s->i_abc_A[2] == 0.0);
        assert_int_equal(s->phase_state[2], PLANT_PHASE_OPEN);
        assert_true(s->phase_open[2] && !s->phase_open[0] && !s->phase_open[1]);
        assert_near(s->tau_e_Nm, torque_Nm(s->i_abc_A, theta_e, ld, lq),
                    1e-12 * fabs(s->tau_e_Nm) + 1e-15);
        if (lq_over_ld == 1.0) {
            /* phase c: no current, no back-EMF (locked), no mutual flux
             * (the loop's flux cancels on its axis): 0 V to the star */
            assert_near(s->v_abc_V[2], 0.0, 1e-9);
        }
    }
    print_message("Lq/Ld %.1f: L_loop %.6f mH, i_a %.9f A\n", lq_over_ld, 1e3 * l_loop,
                  s->i_abc_A[0]);
}

static void test_open_phase_locked_rl_loop(void **state)
{
    (void)state;
    check_locked_open_phase(1.0);
    check_locked_open_phase(2.0); /* salient: the floating voltage solves the dq model */
}

/* Switching at speed with random duties around a rotating field; phase b
 * opens in period 200 and is reconnected in period 600. While open:
 * i_b = 0 exactly, i_a = -i_c exactly, the torque is that of (i_a, 0, i_c)
 * (salient machine). When it opens, the current it carried is cut: the
 * magnetic energy 0.75 (Ld i_d^2 + Lq i_q^2) drops from the state before
 * to the projected state (i_a - i_c)/2 * (1, 0, -1), into constraint_J. */
static void test_open_phase_switching_and_reconnect(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    const double ld = c.motor.Ld_H, lq = 1.4 * ld;
    c.motor.Lq_H = lq;
    c.omega_m0_rad_s = 40.0;
    c.inverter.t_dead_s = 1e-6;
    c.inverter.dead_time_current_band_A = 0.2;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    uint64_t rng = 17u;
    double i_b_max_after = 0.0;
    for (int k = 0; k < 1000; ++k) {
        if (k == 200) {
            assert_int_equal(plant_set_phase_open(&p, 1u, true), PLANT_OK);
            /* the cut: the view holds the state the projection starts from */
            const double th = s->theta_e_rad;
            const double i_loop = 0.5 * (s->i_abc_A[0] - s->i_abc_A[2]);
            const double cut[3] = { i_loop, 0.0, -i_loop };
            double d, q;
            abc_to_dq(cut, th, &d, &q);
            const double w_before = 0.75 * (ld * s->i_d_A * s->i_d_A + lq * s->i_q_A * s->i_q_A);
            const double w_after = 0.75 * (ld * d * d + lq * q * q);
            assert_true(fabs(s->i_abc_A[1]) > 0.5); /* a real cut */
            const double c0 = s->energy.constraint_J;
            plant_advance(&p, (const double[3]){ 0.5, 0.5, 0.5 }, true);
            assert_near(s->energy.constraint_J - c0, w_before - w_after,
                        1e-12 * (w_before - w_after));
            continue;
        }
        if (k == 600) {
            assert_int_equal(plant_set_phase_open(&p, 1u, false), PLANT_OK);
        }
        const double th = N_P * s->theta_m_rad, e = N_P * s->omega_m_rad_s * PSI_WB + 4.0;
        double d[3];
        test_duties_for_alpha_beta(-e * sin(th), e * cos(th), V_DC, d);
        for (int x = 0; x < 3; ++x)
            d[x] += test_uniform(&rng, -0.03, 0.03);
        plant_advance(&p, d, true);
        if (k > 200 && k < 600) {
            assert_true(s->i_abc_A[1] == 0.0);
            assert_true(s->i_abc_A[0] == -s->i_abc_A[2]);
            assert_int_equal(s->phase_state[1], PLANT_PHASE_OPEN);
            assert_near(s->tau_e_Nm, torque_Nm(s->i_abc_A, N_P * s->theta_m_rad, ld, lq),
                        1e-12 * fabs(s->tau_e_Nm) + 1e-15);
        } else if (k >= 600) {
            assert_int_equal(s->phase_state[1], PLANT_PHASE_DRIVEN);
            assert_false(s->phase_open[1]);
            i_b_max_after = fmax(i_b_max_after, fabs(s->i_abc_A[1]));
        }
    }
    assert_true(i_b_max_after > 0.5); /* reconnected, it conducts again */
}

/* The outputs switched off with a phase open at speed: the other two
 * freewheel into the bus and then rectify; the open phase stays at
 * exactly 0 A. */
static void test_open_phase_with_outputs_off(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.omega_m0_rad_s = 150.0; /* line back-EMF 132 V > 48 V */
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    const double on[3] = { 0.5, 0.5, 0.5 };
    for (int k = 0; k < 50; ++k)
        plant_advance(&p, on, true); /* short: currents build up */
    assert_true(fabs(s->i_abc_A[0]) > 1.0);
    assert_int_equal(plant_set_phase_open(&p, 0u, true), PLANT_OK);
    bool rectified = false;
    for (int k = 0; k < 2000; ++k) {
        plant_advance(&p, on, false);
        assert_true(s->i_abc_A[0] == 0.0);
        assert_true(s->i_abc_A[1] == -s->i_abc_A[2]);
        assert_int_equal(s->phase_state[0], PLANT_PHASE_OPEN);
        rectified = rectified || s->rectifying;
    }
    assert_true(rectified && s->energy.bus_J < 0.0);
}

/* Locked mid-run (the drive pushing 5 A of i_q): from the next period
 * omega_m is exactly 0 and theta_m the value at the lock, the kinetic
 * energy 0.5 J omega^2 went to constraint_J; released, the rotor
 * accelerates again. */
static void test_rotor_lock_and_release(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    const plant_true_state_t *s = plant_true_state(&p);
    double d[3];
    for (int k = 0; k < 3000; ++k) {
        if (k == 1000) {
            assert_int_equal(plant_set_rotor_locked(&p, true), PLANT_OK);
            const double omega = s->omega_m_rad_s, theta = s->theta_m_rad;
            const double c0 = s->energy.constraint_J;
            assert_true(omega > 1.0);
            assert_false(s->rotor_locked);
            test_duties_for_alpha_beta(0.0, 5.0 * R_OHM, V_DC, d);
            plant_advance(&p, d, true);
            assert_true(s->rotor_locked);
            assert_true(s->omega_m_rad_s == 0.0 && s->theta_m_rad == theta);
            assert_near(s->energy.constraint_J - c0, 0.5 * 0.012 * omega * omega,
                        1e-12 * omega * omega);
            continue;
        }
        if (k == 2000) {
            assert_int_equal(plant_set_rotor_locked(&p, false), PLANT_OK);
        }
        const double th = N_P * s->theta_m_rad;
        const double v_q = 5.0 * R_OHM + N_P * s->omega_m_rad_s * PSI_WB;
        test_duties_for_alpha_beta(-v_q * sin(th), v_q * cos(th), V_DC, d);
        const double theta_before = s->theta_m_rad, omega_before = s->omega_m_rad_s;
        plant_advance(&p, d, true);
        if (k > 1000 && k < 2000) {
            assert_true(s->omega_m_rad_s == 0.0 && s->theta_m_rad == theta_before);
            assert_true(s->tau_e_Nm > 1.0); /* torque, but no motion */
        } else if (k >= 2001) {
            assert_false(s->rotor_locked);
            assert_true(s->omega_m_rad_s > omega_before);
        }
    }
}

/* config.locked_rotor is the initial state; released, the rotor is free. */
static void test_configured_lock_released(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    c.locked_rotor = true;
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_true(plant_true_state(&p)->rotor_locked);
    double d[3];
    test_duties_for_alpha_beta(0.0, 2.0, V_DC, d); /* a q-axis push at theta = 0 */
    for (int k = 0; k < 100; ++k)
        plant_advance(&p, d, true);
    assert_true(plant_true_state(&p)->omega_m_rad_s == 0.0);
    assert_int_equal(plant_set_rotor_locked(&p, false), PLANT_OK);
    plant_advance(&p, d, true);
    assert_false(plant_true_state(&p)->rotor_locked);
    assert_true(plant_true_state(&p)->omega_m_rad_s > 0.0);
}

static void test_bad_requests_refused(void **state)
{
    (void)state;
    plant_config_t c;
    plant_config_default(&c);
    plant_t p;
    assert_int_equal(plant_init(&p, &c), PLANT_OK);
    assert_int_equal(plant_set_source_connected(&p, false), PLANT_ERR_DC_LINK);
    assert_non_null(strstr(plant_error_message(&p), "capacitance_F"));
    assert_int_equal(plant_set_phase_open(&p, 3u, true), PLANT_ERR_ARGUMENT);
    assert_non_null(strstr(plant_error_message(&p), "phase"));
    /* nothing changed */
    const double d[3] = { 0.5, 0.5, 0.5 };
    plant_advance(&p, d, false);
    const plant_true_state_t *s = plant_true_state(&p);
    assert_true(s->source_connected);
    assert_false(s->phase_open[0] || s->phase_open[1] || s->phase_open[2]);
    assert_int_equal(plant_set_phase_open(NULL, 0u, true), PLANT_ERR_NULL);
    assert_int_equal(plant_set_rotor_locked(NULL, true), PLANT_ERR_NULL);
    assert_int_equal(plant_set_source_connected(NULL, true), PLANT_ERR_NULL);
    c.motor.R_ohm = -1.0;
    assert_int_equal(plant_init(&p, &c), PLANT_ERR_MOTOR);
    assert_int_equal(plant_set_phase_open(&p, 0u, true), PLANT_ERR_STATE);
    assert_int_equal(plant_set_rotor_locked(&p, true), PLANT_ERR_STATE);
    assert_int_equal(plant_set_source_connected(&p, true), PLANT_ERR_STATE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_phase_locked_rl_loop),
        cmocka_unit_test(test_open_phase_switching_and_reconnect),
        cmocka_unit_test(test_open_phase_with_outputs_off),
        cmocka_unit_test(test_rotor_lock_and_release),
        cmocka_unit_test(test_configured_lock_released),
        cmocka_unit_test(test_bad_requests_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
