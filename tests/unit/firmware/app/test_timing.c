/*
 * The drive's timing record (mc_timing_init, mc/timing.h): what it holds
 * for the default configuration, where the delay comes from, and every
 * rejection (the record is left untouched then).
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/config.h"
#include "mc/timing.h"

#define TS_NOM (1.0 / 20000.0)

static mc_timing_config_t defaults(void)
{
    mc_config_t c;
    mc_config_init_default(&c);
    return c.timing;
}

/* mc_timing_init on a record pre-filled with a pattern; on error the
 * record must still hold the pattern. */
static mc_status_t timing_init(mc_timing_t *tm, const mc_timing_config_t *c, double realised_s,
                               float hal_delay)
{
    memset(tm, 0xA5, sizeof *tm);
    mc_timing_t pattern;
    memset(&pattern, 0xA5, sizeof pattern);
    const mc_status_t st = mc_timing_init(tm, c, (float)realised_s, hal_delay);
    if (st != MC_OK) {
        assert_memory_equal(tm, &pattern, sizeof pattern);
    }
    return st;
}

static void test_default_record(void **state)
{
    (void)state;
    const mc_timing_config_t c = defaults();
    assert_near(c.f_pwm_Hz, 20000.0, 0.0);
    assert_near(c.slow_loop_Hz, 2000.0, 0.0);
    assert_near(c.calib_time_s, 0.0256, 1e-9);
    assert_near(c.delay_periods, 0.0, 0.0);
    mc_timing_t tm;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.5f), MC_OK);
    assert_true(tm.Ts_s == (float)TS_NOM); /* the realised period itself */
    assert_int_equal(tm.slow_decimation, 10u);
    assert_near(tm.Ts_slow_s, 10.0 * TS_NOM, 1e-7 * 10.0 * TS_NOM);
    assert_int_equal(tm.calib_samples, 512u);
    assert_int_equal(tm.isr_overrun_limit, c.isr_overrun_limit);
    assert_int_equal(tm.isr_overrun_limit, 3u);
    assert_true(tm.delay_compensation);
    assert_true(tm.telemetry_every_isr);
    assert_near(tm.delay_periods, 1.5, 0.0);
    mc_timing_config_t off = c;
    off.delay_compensation = false;
    assert_int_equal(timing_init(&tm, &off, TS_NOM, 1.5f), MC_OK);
    assert_false(tm.delay_compensation);
    assert_true(tm.telemetry_every_isr);
    off = c;
    off.telemetry_every_isr = false;
    assert_int_equal(timing_init(&tm, &off, TS_NOM, 1.5f), MC_OK);
    assert_false(tm.telemetry_every_isr);
    assert_true(tm.delay_compensation);
}

/* delay_periods = 0: the HAL's delay; otherwise the override, whatever
 * the HAL reports (finite). */
static void test_delay_source(void **state)
{
    (void)state;
    mc_timing_config_t c = defaults();
    mc_timing_t tm;
    const float hal[] = { 0.5f, 1.0f, 1.25f, 1.5f };
    for (size_t i = 0; i < sizeof hal / sizeof hal[0]; ++i) {
        assert_int_equal(timing_init(&tm, &c, TS_NOM, hal[i]), MC_OK);
        assert_true(tm.delay_periods == hal[i]);
    }
    c.delay_periods = 1.2f;
    const float any[] = { 0.5f, 1.5f, 0.3f, 2.0f, 0.0f };
    for (size_t i = 0; i < sizeof any / sizeof any[0]; ++i) {
        assert_int_equal(timing_init(&tm, &c, TS_NOM, any[i]), MC_OK);
        assert_true(tm.delay_periods == 1.2f);
    }
}

/* Delay in use outside [0.5, 1.5]: from the HAL or from the override. */
static void test_delay_range(void **state)
{
    (void)state;
    mc_timing_config_t c = defaults();
    mc_timing_t tm;
    const float bad[] = { 0.49f, 1.51f, 0.4f, 1.6f, -1.0f, 0.0f };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(timing_init(&tm, &c, TS_NOM, bad[i]), MC_ERR_PARAM);
    }
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        if (bad[i] == 0.0f) {
            continue; /* 0 means "the HAL's" */
        }
        c.delay_periods = bad[i];
        assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_ERR_PARAM);
    }
    c.delay_periods = 0.5f;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_OK);
    c.delay_periods = 1.5f;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_OK);
}

/* Realised period within 0.1 % of 1 / f_pwm; the record holds it and
 * derives the slow period and the calibration count from it. */
static void test_realised_period(void **state)
{
    (void)state;
    const mc_timing_config_t c = defaults();
    mc_timing_t tm;
    const double bad[] = { 0.002, -0.002, 0.0012, -0.0012, -1.0 };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(timing_init(&tm, &c, TS_NOM * (1.0 + bad[i]), 1.0f), MC_ERR_PARAM);
    }
    assert_int_equal(timing_init(&tm, &c, -TS_NOM, 1.0f), MC_ERR_PARAM);
    const double good[] = { 0.0005, -0.0005, 0.0009, -0.0009 };
    for (size_t i = 0; i < sizeof good / sizeof good[0]; ++i) {
        const double Ts = TS_NOM * (1.0 + good[i]);
        assert_int_equal(timing_init(&tm, &c, Ts, 1.0f), MC_OK);
        assert_true(tm.Ts_s == (float)Ts);
        assert_int_equal(tm.slow_decimation, 10u);
        assert_near(tm.Ts_slow_s, 10.0 * Ts, 1e-7 * 10.0 * Ts);
        assert_int_equal(tm.calib_samples, (uint32_t)lround(0.0256 / Ts));
    }
}

/* The slow loop rate divides the PWM rate: N = f_pwm / slow_loop_Hz an
 * integer (within 1e-3) in [1, 1000]. */
static void test_slow_loop_rate(void **state)
{
    (void)state;
    mc_timing_config_t c = defaults();
    mc_timing_t tm;
    const struct {
        float slow_Hz;
        mc_status_t st;
        uint32_t n;
    } cases[] = {
        { 3000.0f, MC_ERR_PARAM, 0u },  /* 6.67 */
        { 2003.0f, MC_ERR_PARAM, 0u },  /* 9.985 */
        { 30000.0f, MC_ERR_PARAM, 0u }, /* 0.67 */
        { 40000.0f, MC_ERR_PARAM, 0u }, /* 0.5 */
        { 10.0f, MC_ERR_PARAM, 0u },    /* 2000 > 1000 */
        { 0.0f, MC_ERR_PARAM, 0u },     { -2000.0f, MC_ERR_PARAM, 0u }, { 4000.0f, MC_OK, 5u },
        { 20000.0f, MC_OK, 1u },        { 20.0f, MC_OK, 1000u },        { 2000.0f, MC_OK, 10u },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        c.slow_loop_Hz = cases[i].slow_Hz;
        const mc_status_t st = timing_init(&tm, &c, TS_NOM, 1.0f);
        if (st != cases[i].st) {
            fail_msg("slow loop %g Hz: got %d, expected %d", (double)cases[i].slow_Hz, (int)st,
                     (int)cases[i].st);
        }
        if (st == MC_OK) {
            assert_int_equal(tm.slow_decimation, cases[i].n);
            assert_near(tm.Ts_slow_s, cases[i].n * TS_NOM, 1e-7 * cases[i].n * TS_NOM);
        }
    }
}

/* PWM rate, calibration count and overrun limit ranges. */
static void test_ranges(void **state)
{
    (void)state;
    mc_timing_t tm;
    mc_timing_config_t c = defaults();
    c.isr_overrun_limit = 0u;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_ERR_PARAM);
    c.isr_overrun_limit = 101u;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_ERR_PARAM);
    c.isr_overrun_limit = 1u;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_OK);
    assert_int_equal(tm.isr_overrun_limit, 1u);
    c.isr_overrun_limit = 100u;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_OK);
    assert_int_equal(tm.isr_overrun_limit, 100u);

    c = defaults();
    c.calib_time_s = 0.0f;
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_ERR_PARAM);
    c.calib_time_s = 1e-5f; /* 0.2 samples */
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_ERR_PARAM);
    c.calib_time_s = 5e-5f; /* 1 sample */
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_OK);
    assert_int_equal(tm.calib_samples, 1u);
    c.calib_time_s = 3.2768f; /* 65536 samples */
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_OK);
    assert_int_equal(tm.calib_samples, 65536u);
    c.calib_time_s = 3.3f; /* 66000 */
    assert_int_equal(timing_init(&tm, &c, TS_NOM, 1.0f), MC_ERR_PARAM);

    /* f_pwm in [1 kHz, 100 kHz] (slow loop and realised period to match). */
    const struct {
        float f_Hz;
        mc_status_t st;
    } f[] = {
        { 999.0f, MC_ERR_PARAM },
        { 1000.0f, MC_OK },
        { 100000.0f, MC_OK },
        { 100100.0f, MC_ERR_PARAM },
    };
    for (size_t i = 0; i < sizeof f / sizeof f[0]; ++i) {
        c = defaults();
        c.f_pwm_Hz = f[i].f_Hz;
        c.slow_loop_Hz = f[i].f_Hz / 10.0f;
        assert_int_equal(timing_init(&tm, &c, 1.0 / f[i].f_Hz, 1.0f), f[i].st);
    }
}

/* Any non-finite input: MC_ERR_NONFINITE. */
static void test_non_finite(void **state)
{
    (void)state;
    const float nf[] = { NAN, INFINITY, -INFINITY };
    mc_timing_t tm;
    for (size_t i = 0; i < 3u; ++i) {
        for (int field = 0; field < 6; ++field) {
            mc_timing_config_t c = defaults();
            double Ts = TS_NOM;
            float hal = 1.0f;
            switch (field) {
            case 0: c.f_pwm_Hz = nf[i]; break;
            case 1: c.slow_loop_Hz = nf[i]; break;
            case 2: c.calib_time_s = nf[i]; break;
            case 3: c.delay_periods = nf[i]; break;
            case 4: Ts = (double)nf[i]; break;
            default: hal = nf[i]; break;
            }
            const mc_status_t st = timing_init(&tm, &c, Ts, hal);
            if (st != MC_ERR_NONFINITE) {
                fail_msg("input %d = %g: got %d", field, (double)nf[i], (int)st);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_record), cmocka_unit_test(test_delay_source),
        cmocka_unit_test(test_delay_range),    cmocka_unit_test(test_realised_period),
        cmocka_unit_test(test_slow_loop_rate), cmocka_unit_test(test_ranges),
        cmocka_unit_test(test_non_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
