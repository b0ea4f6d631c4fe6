/*
 * mc_align_init_f32 rejects a timeout whose sample count does not fit the
 * uint32_t counters (before the fix it was rounded into uint32_t and wrapped
 * to a wrong, shorter timeout), and accepts the largest allowed count.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "mc/align.h"

static mc_align_params_t params(float Ts_s, float timeout_s)
{
    const mc_align_params_t p = {
        .i_align_A = 2.0f, .ramp_s = 0.1f, .timeout_s = timeout_s,
        .angle_e_rad = 0.0f, .damping_ratio = 1.0f, .i_q_max_A = 2.0f,
        .settle_speed_e_rad_s = 0.002f, .settle_time_s = 0.05f,
        .R_ohm = 0.225f, .L_H = 3.8e-3f, .psi_Wb = 0.17f, .J_kgm2 = 0.012f,
        .kt_Nm_per_A = 0.765f, .pole_pairs = 3u, .Ts_s = Ts_s,
    };
    return p;
}

static void test_timeout_count_beyond_uint32_is_rejected(void **state)
{
    (void)state;
    mc_align_f32_t a;
    /* 1e9 s at 20 kHz: 2e13 samples, far beyond uint32_t */
    const mc_align_params_t p = params(5e-5f, 1e9f);
    assert_int_equal(mc_align_init_f32(&a, &p), MC_ERR_PARAM);
    /* just above the limit of 2^30 samples */
    const mc_align_params_t q = params(1.0f / 1024.0f, 1048577.0f);
    assert_int_equal(mc_align_init_f32(&a, &q), MC_ERR_PARAM);
}

static void test_timeout_count_at_limit_is_accepted(void **state)
{
    (void)state;
    mc_align_f32_t a;
    const mc_align_params_t p = params(1.0f / 1024.0f, 1048576.0f);
    assert_int_equal(mc_align_init_f32(&a, &p), MC_OK);
    assert_int_equal(a.timeout_n, 1073741824u);
    const mc_align_params_t d = params(5e-5f, 2.0f); /* the app default */
    assert_int_equal(mc_align_init_f32(&a, &d), MC_OK);
    assert_int_equal(a.timeout_n, 40000u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_timeout_count_beyond_uint32_is_rejected),
        cmocka_unit_test(test_timeout_count_at_limit_is_accepted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
