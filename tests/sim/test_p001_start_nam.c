/*
 * The NAM baseline (flux observer + PLL + cascaded PI, paper 001 Fig. 11)
 * started from any rotor angle: the acceptance of p001_start_sweep.h.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "p001_start_sweep.h"

static void test_nam_starts_from_any_angle(void **state)
{
    (void)state;
    p001_sweep_assert_all(MC_CONTROLLER_FOC_PI);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nam_starts_from_any_angle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
