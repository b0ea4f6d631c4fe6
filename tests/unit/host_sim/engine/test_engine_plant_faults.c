/*
 * Plant-side fault injections (sim_engine.h): the engine sets the plant's
 * runtime faults (plant_set_phase_open / _rotor_locked / _source_connected)
 * for the periods whose sample is in the window, and back to the normal
 * state after it. The plant applies a request at the start of the next
 * advance, so the true state of sample k shows what was set at sample
 * k - 1: a window whose first active sample is k0 and last k1 shows in the
 * true state of samples k0 + 1 .. k1 + 1. Checked on the true state (the
 * plant's fault flags and their physical consequence):
 *   phase_open: the open phase carries exactly 0 A (it carried 2.6 A
 *     before), the other two carry equal and opposite currents;
 *     overlapping windows on one phase keep it open over their union;
 *   rotor_lock: omega_m is exactly 0 and theta_m held while locked, the
 *     rotor (driven by 0.5 A of i_q) turned before and accelerates from
 *     rest again at every sample after the release; with locked_rotor in the
 *     plant config the rotor stays locked after the window (the normal
 *     state);
 *   bus_source_loss: no source current while lost, the link capacitor
 *     discharges into the drive, and recharges after; refused on a stiff
 *     bus;
 *   dead_time: the plant's dead time over the window, its inverter loss
 *     against v_err sum |i_x|.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_engine.h"

static sim_engine_t *engine; /* about 6.5 kB: on the heap */
static plant_config_t pc;
static mc_config_t fc;

static int setup(void **state)
{
    (void)state;
    engine = malloc(sizeof *engine);
    return engine == NULL ? -1 : 0;
}

static int teardown(void **state)
{
    (void)state;
    free(engine);
    return 0;
}

/* Default plant (fast integrator) and firmware; the caller adjusts pc. */
static void default_configs(void)
{
    plant_config_default(&pc);
    pc.substeps_per_period = PLANT_SUBSTEPS_FAST;
    mc_config_init_default(&fc);
}

static void start(void)
{
    sim_engine_firmware_from_plant(&pc, &fc);
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
}

static void add(const sim_injection_t *inj)
{
    assert_int_equal(sim_engine_add_injection(engine, inj), SIM_ENGINE_OK);
}

/* One period of the current loop at i_q_ref_A. */
static const sim_trace_sample_t *step_current(float i_q_ref_A)
{
    const mc_command_t cmd = { .enable = true, .mode = MC_MODE_CURRENT, .i_q_ref_A = i_q_ref_A };
    assert_int_equal(sim_engine_step(engine, &cmd), SIM_ENGINE_OK);
    return sim_engine_last(engine);
}

/* Sample k's true state shows the faults set at sample k - 1. */
static bool set_at_previous(const sim_injection_t *inj, const sim_trace_sample_t *s)
{
    const double t_previous_s = s->t_s - sim_engine_period_s(engine);
    return s->k > 0u && t_previous_s >= inj->t_start_s && t_previous_s < inj->t_end_s;
}

static void phase_open_cuts_the_phase_over_its_windows(void **state)
{
    (void)state;
    default_configs();
    pc.locked_rotor = true; /* theta_e = 0: 3 A of i_q is +2.6 A in b */
    start();
    /* two overlapping windows on phase b: open over samples 2001 .. 2400 */
    const sim_injection_t first = {
        .kind = SIM_INJECT_PHASE_OPEN, .t_start_s = 0.10002, .t_end_s = 0.11002, .phase = 1u
    };
    const sim_injection_t second = {
        .kind = SIM_INJECT_PHASE_OPEN, .t_start_s = 0.10502, .t_end_s = 0.12002, .phase = 1u
    };
    add(&first);
    add(&second);
    int n_open = 0;
    for (int k = 0; k < 2600; ++k) {
        const sim_trace_sample_t *s = step_current(3.0f);
        const bool open = set_at_previous(&first, s) || set_at_previous(&second, s);
        assert_int_equal(s->plant.phase_open[1], open);
        assert_false(s->plant.phase_open[0] || s->plant.phase_open[2]);
        if (k == 2001) { /* the last sample before the phase opens */
            assert_false(open);
            assert_int_equal(s->fw.state, MC_STATE_RUN);
            assert_true(fabs(s->plant.i_abc_A[1] - 2.6) < 0.1);
        }
        if (open) {
            assert_true(s->plant.i_abc_A[1] == 0.0);
            assert_true(fabs(s->plant.i_abc_A[0] + s->plant.i_abc_A[2]) < 1e-9);
            n_open++;
        }
    }
    assert_int_equal(n_open, 400); /* samples 2002 .. 2401 */
}

static void rotor_lock_holds_the_rotor_over_its_window(void **state)
{
    (void)state;
    default_configs();
    start();
    const sim_injection_t lock = { .kind = SIM_INJECT_ROTOR_LOCK,
                                   .t_start_s = 0.10002,
                                   .t_end_s = 0.12002 };
    add(&lock);
    double theta_held_rad = NAN;
    double omega_before_rad_s = 0.0;
    double omega_previous_rad_s = 0.0;
    int n_locked = 0;
    for (int k = 0; k < 3000; ++k) {                      /* 0.15 s */
        const sim_trace_sample_t *s = step_current(0.5f); /* 0.38 N m: it accelerates */
        const bool locked = set_at_previous(&lock, s);
        assert_int_equal(s->plant.rotor_locked, locked);
        if (k == 2001) {
            omega_before_rad_s = s->plant.omega_m_rad_s;
        }
        if (locked) {
            if (isnan(theta_held_rad)) {
                theta_held_rad = s->plant.theta_m_rad;
            }
            assert_true(s->plant.omega_m_rad_s == 0.0);
            assert_true(s->plant.theta_m_rad == theta_held_rad);
            n_locked++;
        } else if (n_locked > 0) {
            /* released: from rest, accelerating again */
            assert_true(s->plant.omega_m_rad_s > omega_previous_rad_s);
        }
        omega_previous_rad_s = s->plant.omega_m_rad_s;
    }
    assert_int_equal(n_locked, 400);       /* samples 2002 .. 2401 */
    assert_true(omega_before_rad_s > 1.0); /* it was turning */
}

static void rotor_lock_ends_in_the_configured_state(void **state)
{
    (void)state;
    default_configs();
    pc.locked_rotor = true;
    start();
    const sim_injection_t lock = { .kind = SIM_INJECT_ROTOR_LOCK,
                                   .t_start_s = 0.01002,
                                   .t_end_s = 0.02002 };
    add(&lock);
    for (int k = 0; k < 1000; ++k) {
        const sim_trace_sample_t *s = step_current(0.5f);
        assert_true(s->plant.rotor_locked);
        assert_true(s->plant.omega_m_rad_s == 0.0);
    }
}

static void bus_source_loss_discharges_the_link(void **state)
{
    (void)state;
    default_configs();
    pc.locked_rotor = true;
    pc.dc_link.capacitance_F = 1e-3;
    pc.dc_link.source_resistance_ohm = 0.05;
    start();
    const sim_injection_t loss = { .kind = SIM_INJECT_BUS_SOURCE_LOSS,
                                   .t_start_s = 0.10002,
                                   .t_end_s = 0.12002 };
    add(&loss);
    double v_lost_V = NAN; /* link voltage when the source went */
    double v_min_V = INFINITY;
    int n_lost = 0;
    bool recharging = false;
    for (int k = 0; k < 2600; ++k) {
        const sim_trace_sample_t *s = step_current(3.0f);
        const bool lost = set_at_previous(&loss, s);
        assert_int_equal(s->plant.source_connected, !lost);
        if (lost) {
            if (isnan(v_lost_V)) {
                v_lost_V = s->plant.v_dc_V;
            }
            assert_true(s->plant.i_source_A == 0.0);
            v_min_V = fmin(v_min_V, s->plant.v_dc_V);
            n_lost++;
        } else if (n_lost > 0 && !recharging) {
            /* the first sample after: the source recharges the link */
            assert_true(s->plant.i_source_A > 0.0);
            recharging = true;
        }
    }
    assert_int_equal(n_lost, 400); /* samples 2002 .. 2401 */
    assert_true(recharging);
    /* 3 W of copper loss for 20 ms from 1 mF at 48 V: about 1.2 V */
    assert_true(v_lost_V - v_min_V > 0.5);
}

/* dead_time: the inverter's dead time is the injection's over the periods
 * of its window and the config's (0) outside; the firmware keeps its own
 * (0: nothing compensated). Physical check: the inverter's loss bus_J -
 * electrical_J, which is v_err sum_x |i_x| per unit time with the per-leg
 * error v_err = t_d f_pwm v_dc (plant.h, Inverter), grows at that rate in
 * the window (integrated from the sampled currents, within 2 %: the
 * currents move little over a period) and not at all outside it. */
static void dead_time_changes_over_its_window(void **state)
{
    (void)state;
    default_configs();
    pc.locked_rotor = true;
    start();
    const double t_d = 2e-6;
    const double v_err = t_d * pc.inverter.f_pwm_Hz * 48.0; /* 1.92 V */
    const sim_injection_t dt = {
        .kind = SIM_INJECT_DEAD_TIME, .t_start_s = 0.10002, .t_end_s = 0.12002, .value = t_d
    };
    assert_int_equal(sim_engine_add_injection(engine, &dt), SIM_ENGINE_OK);
    const double period = 1.0 / pc.inverter.f_pwm_Hz;
    double loss_prev = 0.0;
    double expected = 0.0;
    double measured = 0.0;
    int n_on = 0;
    bool was_on = false;             /* the period that ends at this sample ran with it */
    for (int k = 0; k < 2800; ++k) { /* 0.14 s */
        const sim_trace_sample_t *s = step_current(2.0);
        const double loss = s->plant.energy.bus_J - s->plant.energy.electrical_J;
        const double d_loss = loss - loss_prev;
        loss_prev = loss;
        if (was_on) {
            measured += d_loss;
            expected +=
                v_err * period *
                (fabs(s->plant.i_abc_A[0]) + fabs(s->plant.i_abc_A[1]) + fabs(s->plant.i_abc_A[2]));
            n_on++;
        } else {
            assert_true(fabs(d_loss) < 1e-12);
        }
        /* set at this sample for the period that starts */
        const bool on = s->t_s >= dt.t_start_s && s->t_s < dt.t_end_s;
        assert_true(engine->plant.faults.t_dead_s == (on ? t_d : 0.0));
        was_on = on;
    }
    assert_int_equal(n_on, 400);
    assert_true(expected > 0.01); /* about 2.6 A x 2 x 1.9 V x 20 ms */
    assert_near(measured, expected, 0.02 * expected);
    assert_true(fc.deadtime.dead_time_s == 0.0f);
}

static void bad_plant_faults_are_rejected(void **state)
{
    (void)state;
    default_configs();
    start(); /* a stiff bus */
    const sim_injection_t loss = { .kind = SIM_INJECT_BUS_SOURCE_LOSS, .t_end_s = 1.0 };
    assert_int_equal(sim_engine_add_injection(engine, &loss), SIM_ENGINE_ERR_INJECTION);
    assert_non_null(strstr(sim_engine_message(engine), "dc_link.capacitance_F"));
    const sim_injection_t open = { .kind = SIM_INJECT_PHASE_OPEN, .t_end_s = 1.0, .phase = 3u };
    assert_int_equal(sim_engine_add_injection(engine, &open), SIM_ENGINE_ERR_INJECTION);
    assert_non_null(strstr(sim_engine_message(engine), "phase"));
    assert_int_equal(engine->n_injections, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(phase_open_cuts_the_phase_over_its_windows),
        cmocka_unit_test(rotor_lock_holds_the_rotor_over_its_window),
        cmocka_unit_test(rotor_lock_ends_in_the_configured_state),
        cmocka_unit_test(bus_source_loss_discharges_the_link),
        cmocka_unit_test(dead_time_changes_over_its_window),
        cmocka_unit_test(bad_plant_faults_are_rejected),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
