/*
 * Sensorless start protection (paper 001 scheme in the app): the settle
 * timeout of the damped two-phase ALIGN (mc/align.h) and the
 * MC_FAULT_ESTIMATE fault in RUN. The start from any rotor angle is
 * test_p001_start_sweep.c.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "test_p001_bench.h"

/* Run from enable until FAULT or t_end_s; asserts RUN is never entered.
 * Returns the last sample (engine freed by the caller). */
static const sim_trace_sample_t *run_to_fault(sim_engine_t *e, double t_end_s)
{
    const mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    const sim_trace_sample_t *s = NULL;
    do {
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        s = sim_engine_last(e);
        assert_int_not_equal(s->fw.state, MC_STATE_RUN);
    } while (s->fw.state != MC_STATE_FAULT && s->t_s < t_end_s);
    return s;
}

/* A rotor that cannot settle in time ends in a fault, never in RUN: the
 * plant's inertia 100x the controller's (omega_n 1.96 rad/s instead of
 * 19.6, damping ratio 0.1 instead of 1) swings far longer than a 0.5 s
 * timeout: MC_FAULT_ESTIMATE at calibration + align.timeout_s (to one
 * period), PWM off. (With the 2 s default timeout this rotor passes the
 * settle check at a slow turning point, 0.9 s, 0.17 rad off: the check
 * assumes the plant inertia is at most cfg J, see mc/align.h.) */
static void test_unsettled_rotor_times_out(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    pc.mismatch.J = 100.0;
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    fc.align.timeout_s = 0.5f;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const double Ts = sim_engine_period_s(e);
    const sim_trace_sample_t *s = run_to_fault(e, 3.0);
    const double t_expect =
        ((double)mc_app_timing(&e->app)->calib_samples + 1.0) * Ts + (double)fc.align.timeout_s;
    print_message("fault 0x%x at %.4f s (expected %.4f s), w %.3g rad/s\n",
                  (unsigned)s->fw.faults_latched, s->t_s, t_expect, s->plant.omega_m_rad_s);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_int_equal(s->fw.faults_latched, MC_FAULT_ESTIMATE);
    assert_false(s->fw.outputs_enabled);
    assert_true(fabs(s->t_s - t_expect) <= 2.0 * Ts);
    free(e);
}

/* A constant 2 N m load, larger than the largest alignment torque
 * (kt I_a = 1.53 N m), drags the rotor round: it never settles, the drive
 * ends in a fault (which one depends on what trips first) and never in
 * RUN. */
static void test_load_beyond_alignment_torque_faults(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    sim_profile_clear(&pc.load_torque_Nm);
    pc.load_torque_Nm.points[0] = (sim_profile_point_t){ 0.0, 2.0 };
    pc.load_torque_Nm.n_points = 1u;
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const sim_trace_sample_t *s = run_to_fault(e, 3.0);
    print_message("fault 0x%x at %.4f s, w %.3g rad/s\n", (unsigned)s->fw.faults_latched, s->t_s,
                  s->plant.omega_m_rad_s);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_int_not_equal(s->fw.faults_latched, 0u);
    assert_false(s->fw.outputs_enabled);
    free(e);
}

/* An implausible estimate is a fault, not a run-away: with the speed bound
 * set to 2 rad/s and a 50 rpm (5.2 rad/s) reference, the I&I speed
 * estimate crosses the bound while the true speed passes about 2 rad/s;
 * MC_FAULT_ESTIMATE latches on the next slow tick (the plausibility test,
 * mc/est_flux_front.h: at most 0.45 ms later) and the PWM goes off in
 * that ISR. */
static void test_estimate_out_of_bounds_faults(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    fc.protection.estimate_omega_max_rad_s = 2.0f;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    fixture_run_until(e, &cmd, BENCH_T0_S);
    assert_int_equal(sim_engine_last(e)->fw.state, MC_STATE_RUN);
    cmd.omega_m_ref_rad_s = (float)(50.0 / BENCH_RPM_PER_RAD_S);
    const sim_trace_sample_t *s = sim_engine_last(e);
    while (s->fw.state == MC_STATE_RUN && sim_engine_time_s(e) < BENCH_T0_S + 1.4) {
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        s = sim_engine_last(e);
    }
    print_message("fault 0x%x at true speed %.3f rad/s\n", (unsigned)s->fw.faults_latched,
                  s->plant.omega_m_rad_s);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_int_equal(s->fw.faults_latched, MC_FAULT_ESTIMATE);
    assert_false(s->fw.outputs_enabled);
    assert_true(fabs(s->plant.omega_m_rad_s - 2.0) < 0.2);
    free(e);
}

/* With the under-voltage check off (v_dc_min_V = 0), a measured bus of
 * 0 V in RUN cannot be modulated by the paper's controller either: the
 * fault is DC_UNDERVOLTAGE (as on the FOC path), latched in the sample the
 * bus drops, PWM off. */
static void test_zero_bus_with_check_off_is_undervoltage(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    fc.protection.v_dc_min_V = 0.0f;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const double t_drop = BENCH_T0_S + 0.1;
    const sim_injection_t inj = {
        .kind = SIM_INJECT_VDC_MEASURED, .t_start_s = t_drop, .t_end_s = INFINITY, .value = 0.0
    };
    assert_int_equal(sim_engine_add_injection(e, &inj), SIM_ENGINE_OK);
    const mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED, .omega_m_ref_rad_s = 1.0f };
    fixture_run_until(e, &cmd, t_drop); /* the next sample is at t_drop */
    assert_int_equal(sim_engine_last(e)->fw.state, MC_STATE_RUN);
    assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
    const sim_trace_sample_t *s = sim_engine_last(e);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_int_equal(s->fw.faults_latched, MC_FAULT_DC_UNDERVOLTAGE);
    assert_false(s->outputs_applied);
    free(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unsettled_rotor_times_out),
        cmocka_unit_test(test_load_beyond_alignment_torque_faults),
        cmocka_unit_test(test_estimate_out_of_bounds_faults),
        cmocka_unit_test(test_zero_bus_with_check_off_is_undervoltage),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
