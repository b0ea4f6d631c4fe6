/*
 * Sensorless start from any rotor angle: the acceptance of
 * p001_start_sweep.h for one controller and one half of the angles,
 * chosen at build time (tests/sim/CMakeLists.txt):
 *   P001_SWEEP_NAM   0: the paper's scheme (IDA-PBC), 1: the NAM baseline
 *                    (flux observer + PLL + cascaded PI, paper 001 Fig. 11)
 *   P001_SWEEP_HALF  0: angles k = 0..6, 1: k = 7..P001_SWEEP_N - 1
 */
#include "mc_test.h"

#include "p001_start_sweep.h"

#if !defined(P001_SWEEP_NAM) || !defined(P001_SWEEP_HALF)
#error "define P001_SWEEP_NAM and P001_SWEEP_HALF"
#endif

#define SWEEP_SPLIT 7u

static void test_starts_from_any_angle(void **state)
{
    (void)state;
    const mc_controller_t c = P001_SWEEP_NAM ? MC_CONTROLLER_FOC_PI : MC_CONTROLLER_IDAPBC;
    if (P001_SWEEP_HALF == 0) {
        p001_sweep_assert_range(c, 0u, SWEEP_SPLIT);
    } else {
        p001_sweep_assert_range(c, SWEEP_SPLIT, P001_SWEEP_N);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_starts_from_any_angle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
