/*
 * Paper 001, Fig. 11: the paper's scheme (flux observer + I&I observer +
 * IDA-PBC, "TAC") against the NAM baseline (the same flux observer + PLL
 * speed/load estimator + cascaded PI speed and current loops), both on the
 * Section 5.1 benchmark with nominal parameters.
 */
#include "mc_test.h"

#include "test_p001_bench.h"

static void test_paper_beats_nam_on_load_steps(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    bench_fw_config(&pc, &fc, MC_CONTROLLER_FOC_PI);
    const bench_result_t nam = bench_run(&pc, &fc, "NAM nominal");
    bench_fw_config(&pc, &fc, MC_CONTROLLER_IDAPBC);
    const bench_result_t tac = bench_run(&pc, &fc, "paper nominal");
    assert_int_equal(nam.faults, 0u);
    assert_int_equal(tac.faults, 0u);
    assert_true(tac.dip_load_1s_rpm < nam.dip_load_1s_rpm);
    assert_true(tac.dip_load_5s_rpm < nam.dip_load_5s_rpm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paper_beats_nam_on_load_steps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
