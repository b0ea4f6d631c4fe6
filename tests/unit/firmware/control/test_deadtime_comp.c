/*
 * Dead-time compensation (mc/deadtime_comp.h) against the inverter's
 * period-average leg model written out here (the plant's, host_sim/plant/
 * plant.h): v_term = d v_dc - s(i) (t_d f v_dc + v_f). Outside the band
 * the compensated duty must deliver the commanded d v_dc exactly (to float
 * rounding); inside it the correction is linear in i; the configuration's
 * ranges; limiting at 0 and 1 reported; NaN propagated (the output check
 * faults on it).
 */
#include "mc_test.h"

#include <math.h>

#include "mc/deadtime_comp.h"

#define TS   5e-5
#define TD   1e-6
#define VF   0.8
#define BAND 0.2

static mc_deadtime_comp_f32_t make(bool on, double td, double vf)
{
    const mc_deadtime_config_t c = { .dead_time_s = (float)td,
                                     .device_drop_V = (float)vf,
                                     .current_band_A = (float)BAND,
                                     .compensation = on };
    mc_deadtime_comp_f32_t dc;
    assert_int_equal(mc_deadtime_comp_init_f32(&dc, &c, (float)TS, 20.0f), MC_OK);
    return dc;
}

/* the leg model: average terminal voltage of duty d at current i */
static double leg_V(double d, double i, double v_dc)
{
    const double s = (i > 0.0) ? 1.0 : ((i < 0.0) ? -1.0 : 0.0);
    return d * v_dc - s * (TD / TS * v_dc + VF);
}

/* Outside the band the average terminal voltage equals the command: on
 * 48 V and 24 V, currents of either sign, duties across the range. */
static void test_delivers_command_outside_band(void **state)
{
    (void)state;
    const mc_deadtime_comp_f32_t dc = make(true, TD, VF);
    const float v_dcs[] = { 48.0f, 24.0f };
    const float currents[][3] = { { 3.0f, -1.0f, -2.0f }, { -0.25f, 5.0f, -4.75f } };
    const float duties[][3] = { { 0.5f, 0.2f, 0.8f }, { 0.1f, 0.9f, 0.45f } };
    for (int v = 0; v < 2; ++v) {
        for (int c = 0; c < 2; ++c) {
            for (int k = 0; k < 2; ++k) {
                float duty[3] = { duties[k][0], duties[k][1], duties[k][2] };
                assert_false(mc_deadtime_comp_apply_f32(&dc, currents[c], v_dcs[v], duty));
                for (int x = 0; x < 3; ++x) {
                    const double got = leg_V(duty[x], currents[c][x], v_dcs[v]);
                    const double want = (double)duties[k][x] * v_dcs[v];
                    assert_near(got, want, 4e-7 * v_dcs[v]); /* float duties */
                }
            }
        }
    }
}

/* Inside +-band the correction is (i / band) times the full one; at zero
 * current none. */
static void test_linear_band(void **state)
{
    (void)state;
    const mc_deadtime_comp_f32_t dc = make(true, TD, VF);
    const float v_dc = 48.0f;
    const double full = TD / TS + VF / v_dc;
    const float i[3] = { 0.05f, -0.1f, 0.0f };
    float duty[3] = { 0.5f, 0.5f, 0.5f };
    assert_false(mc_deadtime_comp_apply_f32(&dc, i, v_dc, duty));
    for (int x = 0; x < 3; ++x) {
        assert_near(duty[x], 0.5 + (double)i[x] / BAND * full, 1e-7);
    }
}

/* Off, or nothing to compensate: duties untouched. */
static void test_inactive(void **state)
{
    (void)state;
    const mc_deadtime_comp_f32_t off = make(false, TD, VF);
    const mc_deadtime_comp_f32_t none = make(true, 0.0, 0.0);
    const float i[3] = { 3.0f, -1.0f, -2.0f };
    for (int k = 0; k < 2; ++k) {
        float duty[3] = { 0.3f, 0.6f, 0.9f };
        assert_false(mc_deadtime_comp_apply_f32(k == 0 ? &off : &none, i, 48.0f, duty));
        assert_true(duty[0] == 0.3f && duty[1] == 0.6f && duty[2] == 0.9f);
    }
}

/* Pushed past 0 or 1: limited there, reported. A NaN current gives NaN
 * duties (not a silent 0). */
static void test_limits_and_nan(void **state)
{
    (void)state;
    const mc_deadtime_comp_f32_t dc = make(true, TD, VF);
    const float i[3] = { 2.0f, -2.0f, 0.0f };
    float duty[3] = { 0.99f, 0.01f, 0.5f };
    assert_true(mc_deadtime_comp_apply_f32(&dc, i, 48.0f, duty));
    assert_true(duty[0] == 1.0f && duty[1] == 0.0f && duty[2] == 0.5f);
    const float i_nan[3] = { NAN, 1.0f, -1.0f };
    float d2[3] = { 0.5f, 0.5f, 0.5f };
    (void)mc_deadtime_comp_apply_f32(&dc, i_nan, 48.0f, d2);
    assert_true(isnan(d2[0]));
}

/* Ranges: finite; t_d, v_f >= 0; band > 0; t_d / Ts + v_f / v_dc_min <=
 * 0.1 (5 us at 20 kHz is exactly 0.1); a drop needs a positive lowest
 * bus. *dc untouched on error. */
static void test_ranges(void **state)
{
    (void)state;
    const struct {
        float td, vf, band, v_min;
        mc_status_t want;
    } c[] = {
        { 1e-6f, 0.8f, 0.2f, 20.0f, MC_OK },
        { 5e-6f, 0.0f, 0.2f, 20.0f, MC_OK },
        { 5.1e-6f, 0.0f, 0.2f, 20.0f, MC_ERR_PARAM },
        { 4e-6f, 0.5f, 0.2f, 20.0f, MC_ERR_PARAM }, /* 0.08 + 0.025 */
        { -1e-9f, 0.0f, 0.2f, 20.0f, MC_ERR_PARAM },
        { 0.0f, -0.1f, 0.2f, 20.0f, MC_ERR_PARAM },
        { 0.0f, 0.0f, 0.0f, 20.0f, MC_ERR_PARAM },
        { 0.0f, 0.5f, 0.2f, 0.0f, MC_ERR_PARAM },
        { 1e-6f, 0.0f, 0.2f, 0.0f, MC_OK }, /* no drop: any bus */
        { NAN, 0.0f, 0.2f, 20.0f, MC_ERR_NONFINITE },
        { 0.0f, 0.0f, INFINITY, 20.0f, MC_ERR_NONFINITE },
    };
    for (size_t k = 0; k < sizeof c / sizeof c[0]; ++k) {
        const mc_deadtime_config_t cfg = { c[k].td, c[k].vf, c[k].band, true };
        mc_deadtime_comp_f32_t dc = { .duty_time = 123.0f };
        const mc_status_t st = mc_deadtime_comp_init_f32(&dc, &cfg, (float)TS, c[k].v_min);
        if (st != c[k].want) {
            fail_msg("case %zu: got %d, expected %d", k, (int)st, (int)c[k].want);
        }
        if (st != MC_OK) {
            assert_true(dc.duty_time == 123.0f);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_delivers_command_outside_band),
        cmocka_unit_test(test_linear_band),
        cmocka_unit_test(test_inactive),
        cmocka_unit_test(test_limits_and_nan),
        cmocka_unit_test(test_ranges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
