/*
 * Paper 001, Section 5.1 robustness cases (Figs. 5-10): the plant's R, L
 * or flux differs from the controller's nominal value (R +50 %, L +50 %,
 * flux +15 %), the controller (paper scheme, delay compensation on) stays
 * nominal.
 *
 * Expectations (paper Section 5.1): L +50 % tracks like nominal (RMS speed
 * error at 120 rpm <= 0.05 rpm, dips <= 20 rpm); R +50 % and flux +15 %
 * achieve speed tracking "whereas w* remains away from zero": here, no
 * fault and a bounded speed error while the reference is non-zero (tb in
 * [0.5, 8.5) s): 25 rpm, the nominal dip acceptance (20 rpm) with room
 * for the steady offset and the slower load response a mismatch brings
 * (on the paper's machine: 20.5 rpm at the load release under R +50 %,
 * 15.9 rpm under flux +15 %); phase current within i_max. The paper's
 * figures for these cases are test_p001_paper_figures.
 * At zero speed (tb >= 9 s) the paper reports diverging estimates: their
 * accuracy there is not asserted (bench_run prints it), but the drive's
 * protection must not trip on any of these cases (no false trip: every
 * fault class of mc/faults.h stays clear over the whole run).
 */
#include "mc_test.h"

#include "test_p001_bench.h"

static void assert_bounded_while_moving(const bench_result_t *r)
{
    assert_int_equal(r->faults, 0u);
    assert_true(r->max_speed_err_moving_rpm <= 25.0);
    assert_true(r->peak_current_A <= 10.0); /* i_max of the defaults */
}

static bench_result_t run_case(double m_R, double m_L, double m_psi, const char *label)
{
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, m_R, m_L, m_psi);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    return bench_run(&pc, &fc, label);
}

static void test_inductance_plus_50(void **state)
{
    (void)state;
    const bench_result_t r = run_case(1.0, 1.5, 1.0, "L +50 %");
    assert_int_equal(r.faults, 0u);
    assert_true(r.rms_speed_err_120_rpm <= 0.05);
    assert_true(r.dip_load_1s_rpm <= 20.0);
    assert_true(r.dip_load_5s_rpm <= 20.0);
}

static void test_resistance_plus_50(void **state)
{
    (void)state;
    const bench_result_t r = run_case(1.5, 1.0, 1.0, "R +50 %");
    assert_bounded_while_moving(&r);
}

static void test_flux_plus_15(void **state)
{
    (void)state;
    const bench_result_t r = run_case(1.0, 1.0, 1.15, "flux +15 %");
    assert_bounded_while_moving(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inductance_plus_50),
        cmocka_unit_test(test_resistance_plus_50),
        cmocka_unit_test(test_flux_plus_15),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
