/*
 * mc_align_init_f32 rejects a timeout whose sample count does not fit the
 * uint32_t counters (before the fix it was rounded into uint32_t and wrapped
 * to a wrong, shorter timeout), and accepts the largest allowed count.
 * The block also bounds the timeout itself (MC_ALIGN_TIMEOUT_MAX_S, a rule
 * that lived in the application's configuration check before), so the
 * count limit of 2^30 samples is reached with a short period: 8 s at
 * Ts = 2^-27 s.
 */
#include "mc_test.h"

#include "mc/align.h"

static mc_align_params_t params(float Ts_s, float timeout_s)
{
    const mc_align_params_t p = {
        .cfg = { .current_A = 2.0f,
                 .ramp_s = 0.1f,
                 .timeout_s = timeout_s,
                 .angle_e_rad = 0.0f,
                 .damping_ratio = 1.0f,
                 .i_q_max_A = 2.0f,
                 .settle_speed_e_rad_s = 0.002f,
                 .settle_time_s = 0.05f },
        .R_ohm = 0.225f,
        .L_H = 3.8e-3f,
        .psi_Wb = 0.17f,
        .J_kgm2 = 0.012f,
        .kt_Nm_per_A = 0.765f,
        .pole_pairs = 3u,
        .Ts_s = Ts_s,
    };
    return p;
}

#define TS_SHORT (1.0f / 134217728.0f) /* 2^-27 s */

static void test_timeout_count_beyond_uint32_is_rejected(void **state)
{
    (void)state;
    mc_align_f32_t a;
    /* 1e9 s at 20 kHz: 2e13 samples, far beyond uint32_t (and beyond the
     * 10 s limit) */
    const mc_align_params_t p = params(5e-5f, 1e9f);
    assert_int_equal(mc_align_init_f32(&a, &p), MC_ERR_PARAM);
    /* just above the limit of 2^30 samples: 8 s + 1 ulp (2^-20 s) at
     * 2^-27 s = 2^30 + 128 samples; and 8 s at a period 1 ulp short */
    const mc_align_params_t q = params(TS_SHORT, 8.00000095367431640625f);
    assert_int_equal(mc_align_init_f32(&a, &q), MC_ERR_PARAM);
    const mc_align_params_t r = params(TS_SHORT * (1.0f - 5.9604645e-8f), 8.0f);
    assert_true(r.Ts_s < TS_SHORT);
    assert_int_equal(mc_align_init_f32(&a, &r), MC_ERR_PARAM);
}

static void test_timeout_count_at_limit_is_accepted(void **state)
{
    (void)state;
    mc_align_f32_t a;
    const mc_align_params_t p = params(TS_SHORT, 8.0f);
    assert_int_equal(mc_align_init_f32(&a, &p), MC_OK);
    assert_int_equal(a.timeout_n, 1073741824u);
    const mc_align_params_t d = params(5e-5f, 2.0f); /* the app default */
    assert_int_equal(mc_align_init_f32(&a, &d), MC_OK);
    assert_int_equal(a.timeout_n, 40000u);
}

/* The timeout range (0, MC_ALIGN_TIMEOUT_MAX_S = 10 s]: the former limit
 * case (2^30 samples of 1/1024 s = 1048576 s) is now out of range. */
static void test_timeout_range(void **state)
{
    (void)state;
    mc_align_f32_t a;
    const mc_align_params_t at = params(5e-5f, 10.0f);
    assert_int_equal(mc_align_init_f32(&a, &at), MC_OK);
    assert_int_equal(a.timeout_n, 200000u);
    const mc_align_params_t above = params(5e-5f, 10.001f);
    assert_int_equal(mc_align_init_f32(&a, &above), MC_ERR_PARAM);
    const mc_align_params_t old_limit = params(1.0f / 1024.0f, 1048576.0f);
    assert_int_equal(mc_align_init_f32(&a, &old_limit), MC_ERR_PARAM);
    const mc_align_params_t zero = params(5e-5f, 0.0f);
    assert_int_equal(mc_align_init_f32(&a, &zero), MC_ERR_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_timeout_count_beyond_uint32_is_rejected),
        cmocka_unit_test(test_timeout_count_at_limit_is_accepted),
        cmocka_unit_test(test_timeout_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
