/*
 * Paper 001 sensorless scheme (flux observer (12)-(14), I&I speed/load
 * observer (15)-(16), IDA-PBC (11)) on the Section 5.1 benchmark, nominal
 * parameters.
 *
 * Acceptance (the project's reading of Figs. 2-4: exact tracking at
 * constant reference, negligible observer errors): RMS speed error at
 * 120 rpm <= 0.05 rpm, dip after each 1 N m load step <= 20 rpm, RMS
 * electrical angle error at 50 and 120 rpm <= 1e-3 rad, RMS load estimate
 * error at 120 rpm <= 1e-3 N m, peak phase current <= 3 A (the 2 A
 * alignment included; 1 N m needs 1.31 A), no fault.
 */
#include "mc_test.h"

#include <stdbool.h>
#include <stdio.h>

#include "test_p001_bench.h"

static void assert_acceptance(const bench_result_t *r)
{
    assert_int_equal(r->faults, 0u);
    assert_true(r->rms_speed_err_120_rpm <= 0.05);
    assert_true(r->dip_load_1s_rpm <= 20.0);
    assert_true(r->dip_load_5s_rpm <= 20.0);
    assert_true(r->rms_angle_err_50_rad <= 1e-3);
    assert_true(r->rms_angle_err_120_rad <= 1e-3);
    assert_true(r->rms_tau_err_120_Nm <= 1e-3);
    assert_true(r->peak_current_A <= 3.0);
}

static bench_result_t run_nominal(bool delay_comp, const char *label)
{
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    fc.timing.delay_compensation = delay_comp;
    return bench_run(&pc, &fc, label);
}

/* Delay compensation on (the default) meets the acceptance. Off, the
 * voltage lands 1.5 n_p w Ts behind the angle it was computed for
 * (2.8 mrad at 120 rpm): IDA-PBC (11) has no integral action, so the
 * rotated voltage leaves a steady speed error, larger than with the
 * compensation; the flux observer still gets the applied voltage, so the
 * estimates stay within the acceptance. */
static void test_nominal_and_delay_compensation(void **state)
{
    (void)state;
    const bench_result_t on = run_nominal(true, "paper nominal");
    assert_acceptance(&on);
    const bench_result_t off = run_nominal(false, "paper, no delay comp");
    assert_int_equal(off.faults, 0u);
    assert_true(off.rms_speed_err_120_rpm > on.rms_speed_err_120_rpm);
    assert_true(off.rms_angle_err_50_rad <= 1e-3);
    assert_true(off.rms_angle_err_120_rad <= 1e-3);
    assert_true(off.rms_tau_err_120_Nm <= 1e-3);
    printf("delay compensation off / on: RMS speed error at 120 rpm x%.3g, "
           "at 50 rpm x%.3g\n",
           off.rms_speed_err_120_rpm / on.rms_speed_err_120_rpm,
           off.rms_speed_err_50_rpm / on.rms_speed_err_50_rpm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nominal_and_delay_compensation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
