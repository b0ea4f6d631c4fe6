/*
 * Sensorless start and its protection (paper 001 scheme in the app):
 * the ALIGN phase and the MC_FAULT_ESTIMATE fault.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "test_p001_bench.h"

/* CALIBRATING -> ALIGN -> RUN: ALIGN lasts align_time_s (to one period),
 * the TRUE d current (rotor frame) follows the commanded ramp
 * i_align min(1, t / t_ramp) within 5 % of i_align once past the current
 * loop's rise (2 / w_c = 0.8 ms), the q current stays below 2 % of i_align
 * (the rotor at theta = 0 is already aligned, so nothing turns: |w| stays
 * below 0.1 rad/s), and the outputs are on throughout. */
static void test_align_phase(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&fc, MC_CONTROLLER_IDAPBC);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    const double Ts = sim_engine_period_s(e);
    const double i_al = (double)fc.align_current_A;
    const double t_ramp = (double)fc.align_ramp_s;
    double t_align_start = -1.0, t_run = -1.0;
    double id_err_max = 0.0, iq_max = 0.0, w_max = 0.0;
    while (t_run < 0.0 && sim_engine_time_s(e) < 1.0) {
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        const sim_trace_sample_t *s = sim_engine_last(e);
        assert_int_equal(s->fw.faults_latched, 0u);
        if (s->fw.state == MC_STATE_ALIGN) {
            if (t_align_start < 0.0) {
                t_align_start = s->t_s;
            }
            assert_true(s->fw.outputs_enabled);
            const double ta = s->t_s - t_align_start;
            if (ta > 1e-3) {
                const double id_ref = i_al * fmin(1.0, ta / t_ramp);
                id_err_max = fmax(id_err_max, fabs(s->plant.i_d_A - id_ref));
            }
            iq_max = fmax(iq_max, fabs(s->plant.i_q_A));
            w_max = fmax(w_max, fabs(s->plant.omega_m_rad_s));
        } else if (s->fw.state == MC_STATE_RUN) {
            t_run = s->t_s;
        }
    }
    print_message("ALIGN %.4f s, max |i_d - ramp| %.4f A, max |i_q| %.4f A, "
                  "max |w| %.3g rad/s\n", t_run - t_align_start, id_err_max,
                  iq_max, w_max);
    assert_true(t_align_start > 0.0 && t_run > 0.0);
    assert_true(fabs(t_run - t_align_start - (double)fc.align_time_s) <=
                1.01 * Ts);
    assert_true(id_err_max <= 0.05 * i_al);
    assert_true(iq_max <= 0.02 * i_al);
    assert_true(w_max < 0.1);
    free(e);
}

/* An implausible estimate is a fault, not a run-away: with the speed bound
 * set to 2 rad/s and a 50 rpm (5.2 rad/s) reference, the I&I speed
 * estimate crosses the bound while the true speed passes about 2 rad/s;
 * MC_FAULT_ESTIMATE latches and the PWM goes off in that ISR. */
static void test_estimate_out_of_bounds_faults(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&fc, MC_CONTROLLER_IDAPBC);
    fc.est_omega_max_rad_s = 2.0f;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    fixture_run_until(e, &cmd, BENCH_T0_S);
    assert_int_equal(sim_engine_last(e)->fw.state, MC_STATE_RUN);
    cmd.omega_m_ref_rad_s = (float)(50.0 / BENCH_RPM_PER_RAD_S);
    const sim_trace_sample_t *s = sim_engine_last(e);
    while (s->fw.state == MC_STATE_RUN && sim_engine_time_s(e) < 2.0) {
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        s = sim_engine_last(e);
    }
    print_message("fault 0x%x at true speed %.3f rad/s\n",
                  (unsigned)s->fw.faults_latched, s->plant.omega_m_rad_s);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_int_equal(s->fw.faults_latched, MC_FAULT_ESTIMATE);
    assert_false(s->fw.outputs_enabled);
    assert_true(fabs(s->plant.omega_m_rad_s - 2.0) < 0.2);
    free(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_align_phase),
        cmocka_unit_test(test_estimate_out_of_bounds_faults),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
