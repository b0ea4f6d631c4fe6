/*
 * The PWM duty contract of the simulator mailbox binding
 * (hal/sim_mailbox/hal_sim_accessors.h, hal/include/hal/pwm.h): whatever
 * the firmware computed, the compare registers hold a duty in [0, 1]: a
 * duty inside passes unchanged (bit for bit), one below 0 or -Inf becomes
 * 0, one above 1 or +Inf becomes 1, a NaN 0.5 (zero voltage).
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "hal/pwm.h"
#include "hal_sim_mailbox.h"

static float expected(float d)
{
    if (d != d) {
        return 0.5f;
    }
    return (d < 0.0f) ? 0.0f : ((d > 1.0f) ? 1.0f : d);
}

static void test_duties_saturate(void **state)
{
    (void)state;
    static hal_sim_mailbox_t mb;
    hal_sim_mailbox_reset(&mb);
    hal_sim_bind(&mb);
    const float v[] = { 0.0f,      -0.0f,   FLT_MIN, 0.3f,     0.5f,    1.0f - FLT_EPSILON,
                        1.0f,      1.0001f, 2.0f,    INFINITY, -1e-9f,  -0.5f,
                        -INFINITY, NAN,     -NAN,    FLT_MAX,  -FLT_MAX };
    const size_t n = sizeof v / sizeof v[0];
    for (size_t k = 0; k < n * n * n; ++k) {
        const float d[3] = { v[k % n], v[(k / n) % n], v[k / (n * n)] };
        hal_pwm_set_duties(d);
        for (int x = 0; x < 3; ++x) {
            const float want = expected(d[x]);
            assert_memory_equal(&mb.duty_abc[x], &want, sizeof want);
        }
    }
    hal_sim_bind(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_duties_saturate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
