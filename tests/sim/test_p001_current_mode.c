/*
 * IDA-PBC drive (paper 001, sensorless) switching from speed to current
 * mode: the FOC current loop takes over from (11) (firmware/app/fast_isr.c
 * references()). Its integrators are restarted at (11)'s last voltage
 * (mc_current_loop_preset_f32), so the transfer is bumpless even when they
 * hold a stale state from an earlier current-mode phase.
 *
 * Scenario on the benchmark plant (load 1 N m from tb = 1 s): speed mode
 * to 50 rpm; at tb = 0.9 s, 10 ms of current mode at i_q_ref = -3 A (the
 * current loop's q integrator then holds about -R 3 A = -0.68 V); speed mode
 * again until tb = 2.0 s (steady at 50 rpm, i_q = 1 N m / kt = 1.31 A);
 * then current mode with i_q_ref = the mean measured i_q of the last 1 ms
 * and i_d_ref = 0.
 *
 * Bound (analytic): even a loop restarted from ZERO integrators would lack
 * only the resistive drop D = R |i_q_ref| (the feed-forward carries the
 * back-EMF); through the designed first-order loop (kp = L w_c,
 * ki = R w_c) a voltage step D gives the current error
 * D / ((L s + R)(s + w_c)), whose peak is below D / (L w_c)
 * = 0.225 * 1.31 / (3.8e-3 * 2513) = 0.031 A. The bumpless restart must
 * stay within it over the first 40 periods (2 ms = 5 / w_c); the stale
 * state of the earlier phase (about R (3 + 1.31) A = 0.97 V off) exceeds
 * it: measured 0.086 A without the restart, 0.029 A with a zero restart,
 * 2.4e-7 A with the bumpless one.
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_p001_bench.h"

static void run_speed_until(sim_engine_t *e, mc_command_t *cmd, double tb_end)
{
    cmd->mode = MC_MODE_SPEED;
    while (sim_engine_time_s(e) - BENCH_T0_S < tb_end) {
        cmd->omega_m_ref_rad_s =
            (float)(bench_ref_rpm(sim_engine_time_s(e) - BENCH_T0_S) / BENCH_RPM_PER_RAD_S);
        assert_int_equal(sim_engine_step(e, cmd), SIM_ENGINE_OK);
    }
}

static void test_speed_to_current_bumpless(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    run_speed_until(e, &cmd, 0.9);
    assert_int_equal(sim_engine_last(e)->fw.state, MC_STATE_RUN);
    /* an earlier current-mode phase leaves the loop's integrators stale */
    cmd.mode = MC_MODE_CURRENT;
    cmd.i_d_ref_A = 0.0f;
    cmd.i_q_ref_A = -3.0f;
    fixture_run_until(e, &cmd, BENCH_T0_S + 0.91);
    run_speed_until(e, &cmd, 2.0 - 1e-3);
    /* mean i_q of the last 1 ms (20 periods) in speed mode */
    double sum = 0.0;
    for (int k = 0; k < 20; ++k) {
        run_speed_until(e, &cmd, sim_engine_time_s(e) - BENCH_T0_S + 1e-9);
        sum += (double)sim_engine_last(e)->fw.i_q_A;
    }
    const double i_q_ref = sum / 20.0;
    cmd.mode = MC_MODE_CURRENT;
    cmd.i_d_ref_A = 0.0f;
    cmd.i_q_ref_A = (float)i_q_ref;
    double max_dev = 0.0;
    for (int k = 0; k < 40; ++k) {
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        const sim_trace_sample_t *s = sim_engine_last(e);
        assert_int_equal(s->fw.faults_latched, 0u);
        assert_int_equal(s->fw.mode, MC_MODE_CURRENT);
        max_dev = fmax(max_dev, fabs((double)s->fw.i_q_A - i_q_ref));
    }
    free(e);
    const double w_c = (double)fc.current.bandwidth_rad_s;
    const double bound = (double)fc.motor.R_ohm * fabs(i_q_ref) / ((double)fc.motor.Lq_H * w_c);
    printf("speed -> current mode at i_q_ref %.4g A: max |i_q - i_q_ref| "
           "over 40 periods %.4g A (bound R |i_q| / (L w_c) = %.4g A)\n",
           i_q_ref, max_dev, bound);
    /* 1 N m of load on the paper's machine: kt = 1.5 n_p psi (psi the
     * plant's, 0.17 / sqrt(3/2) Wb: motor_convention.h) */
    const double kt = 1.5 * (double)fc.motor.pole_pairs * (double)fc.motor.psi_Wb;
    assert_true(fabs(i_q_ref - 1.0 / kt) < 0.05);
    assert_true(max_dev <= bound);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_speed_to_current_bumpless),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
