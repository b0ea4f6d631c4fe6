/*
 * IDA-PBC integral action (beyond paper 001; mc/idapbc.h,
 * mc_config_t.idapbc.integral_enabled, default pole 10 1/s) on the
 * Section 5.1 benchmark, metrics from the true plant state.
 *
 * 1. Mismatch (plant R x1.5, flux x1.15; controller nominal): without it,
 *    (11) leaves a steady 120 rpm speed offset (measured RMS 1.47 rpm and
 *    7.7 rpm) while the speed ESTIMATE is unbiased (the angle error is
 *    constant): asserted |mean(w_hat - w)| <= 2 % of |mean(ref - w)|. An
 *    integrator on w_ref - w_hat then removes the true offset: asserted RMS
 *    <= 0.05 rpm (the nominal acceptance) and <= OFF / 10; no fault while
 *    moving. Zero speed (tb >= 9 s): the paper reports diverging estimates
 *    under R +50 %; printed (bench_run), their accuracy not asserted, but
 *    no fault at all (no false trip, as in test_p001_robust), integral on
 *    or off.
 * 2. Nominal: the acceptance of test_p001_nominal holds with it on (RMS
 *    speed error at 120 rpm <= 0.05 rpm, dips <= 20 rpm, angle RMS <= 1e-3
 *    rad, load estimate RMS <= 1e-3 N m, peak current <= 3 A, no fault).
 */
#include "mc_test.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>

#include "test_p001_bench.h"

static bench_result_t run_case(double m_R, double m_psi, bool integral, const char *label)
{
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, m_R, 1.0, m_psi);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    fc.idapbc.integral_enabled = integral;
    return bench_run(&pc, &fc, label);
}

static void assert_offset_removed(double m_R, double m_psi, const char *off_label,
                                  const char *on_label)
{
    const bench_result_t off = run_case(m_R, m_psi, false, off_label);
    const bench_result_t on = run_case(m_R, m_psi, true, on_label);
    /* the claim the integral action rests on */
    assert_true(fabs(off.mean_speed_est_err_120_rpm) <= 0.02 * fabs(off.mean_speed_err_120_rpm));
    assert_int_equal(off.faults, 0u);
    assert_int_equal(on.faults, 0u);
    assert_true(on.rms_speed_err_120_rpm <= 0.05);
    assert_true(on.rms_speed_err_120_rpm <= 0.1 * off.rms_speed_err_120_rpm);
    assert_true(on.max_speed_err_moving_rpm <= 20.0);
    assert_true(on.peak_current_A <= 10.0); /* i_max of the defaults */
    printf("[%s] RMS speed error at 120 rpm: off %.4g rpm, on %.4g rpm; "
           "dips off %.4g / %.4g rpm, on %.4g / %.4g rpm\n",
           on_label, off.rms_speed_err_120_rpm, on.rms_speed_err_120_rpm, off.dip_load_1s_rpm,
           off.dip_load_5s_rpm, on.dip_load_1s_rpm, on.dip_load_5s_rpm);
}

static void test_resistance_plus_50(void **state)
{
    (void)state;
    assert_offset_removed(1.5, 1.0, "R +50 %, integral off", "R +50 %, integral on");
}

static void test_flux_plus_15(void **state)
{
    (void)state;
    assert_offset_removed(1.0, 1.15, "flux +15 %, integral off", "flux +15 %, integral on");
}

static void test_nominal_acceptance(void **state)
{
    (void)state;
    const bench_result_t r = run_case(1.0, 1.0, true, "nominal, integral on");
    assert_int_equal(r.faults, 0u);
    assert_true(r.rms_speed_err_120_rpm <= 0.05);
    assert_true(r.dip_load_1s_rpm <= 20.0);
    assert_true(r.dip_load_5s_rpm <= 20.0);
    assert_true(r.rms_angle_err_50_rad <= 1e-3);
    assert_true(r.rms_angle_err_120_rad <= 1e-3);
    assert_true(r.rms_tau_err_120_Nm <= 1e-3);
    assert_true(r.peak_current_A <= 3.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_resistance_plus_50),
        cmocka_unit_test(test_flux_plus_15),
        cmocka_unit_test(test_nominal_acceptance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
