/*
 * The drive's per-sample supervision (mc/supervisor.h): overspeed, stall,
 * the I^2 t thermal model, the current-sensor sum check, the sustained
 * current limit, against the rules
 * of the header written out here (thresholds: the drive's defaults,
 * firmware/app/config.c) and the analytic solution of the thermal model
 * x' = |i|^2 - i_cont^2 (x >= 0), fault while x > (i_peak^2 - i_cont^2)
 * t_peak.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "mc/supervisor.h"

#define F_PWM_HZ 20000.0
#define TS       (1.0 / F_PWM_HZ)
/* A period of 2^-14 s (16384 Hz): with i_cont^2, |i|^2 and t_peak chosen
 * as small integers every step of the thermal model is exact in float
 * (the state is an integer multiple of 2^-14 A^2 s below 2^24 of them), so
 * the analytic sample index is met exactly, not only to rounding. */
#define TS_EXACT (1.0 / 16384.0)

static mc_fault_limits_t limits(void)
{
    return (mc_fault_limits_t){
        .i_trip_A = 20.0f,
        .v_dc_max_V = 60.0f,
        .v_dc_min_V = 20.0f,
        .i_offset_max_A = 2.0f,
        .estimate_omega_max_rad_s = 80.0f,
        .estimate_tau_max_Nm = 15.0f,
        .overspeed_rad_s = 48.0f,
        .stall_current_A = 7.0f,
        .stall_speed_rad_s = 1.0f,
        .stall_time_s = 0.5f,
        .current_limit_A = 11.0f,
        .current_limit_time_s = 0.1f,
        .i2t_continuous_A = 5.0f,
        .i2t_peak_A = 10.0f,
        .i2t_peak_time_s = 2.0f,
        .current_sum_max_A = 1.0f,
        .current_sum_time_s = 0.001f,
    };
}

static void sv_init(mc_supervisor_t *sv, const mc_fault_limits_t *lim, double Ts)
{
    assert_int_equal(mc_supervisor_init(sv, lim, (float)Ts), MC_OK);
}

static mc_telemetry_t sample(float i_d, float i_q, float omega)
{
    mc_telemetry_t t;
    memset(&t, 0, sizeof t);
    t.i_d_A = i_d;
    t.i_q_A = i_q;
    t.omega_m_rad_s = omega;
    return t;
}

typedef enum { IDLE_S, ALIGN_S, RUN_S } pstate_t; /* not powered / powered / running */

static uint32_t step(mc_supervisor_t *sv, const mc_telemetry_t *t, pstate_t st)
{
    return mc_supervisor_step(sv, t, st == RUN_S, st != IDLE_S, false);
}

/* ---- (a) overspeed ------------------------------------------------------- */

/* |omega| just above the threshold (one float ulp) faults, at it not
 * ("above" is strict), either sign; in RUN and ALIGN, never when not
 * powered. Nothing else fires (zero currents). */
static void test_overspeed(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    mc_supervisor_t sv;
    sv_init(&sv, &lim, TS);
    const float th = lim.overspeed_rad_s;
    const struct {
        float omega;
        bool over;
    } c[] = {
        { th, false },
        { -th, false },
        { nextafterf(th, 0.0f), false },
        { nextafterf(th, INFINITY), true },
        { -nextafterf(th, INFINITY), true },
        { 0.0f, false },
        { 1e6f, true },
        { -INFINITY, true },
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; ++i) {
        const mc_telemetry_t t = sample(0.0f, 0.0f, c[i].omega);
        const uint32_t expected = c[i].over ? (uint32_t)MC_FAULT_OVERSPEED : 0u;
        assert_int_equal(step(&sv, &t, RUN_S), expected);
        assert_int_equal(step(&sv, &t, ALIGN_S), expected);
        assert_int_equal(step(&sv, &t, IDLE_S), 0u);
    }
}

/* ---- (b) stall ----------------------------------------------------------- */

static bool stall(mc_supervisor_t *sv, const mc_telemetry_t *t, pstate_t st)
{
    return (step(sv, t, st) & MC_FAULT_STALL) != 0u;
}

/* Consecutive stall samples until the fault: returns the 1-based index of
 * the first sample with MC_FAULT_STALL, or 0 within max samples. */
static long stall_after(mc_supervisor_t *sv, const mc_telemetry_t *t, long max)
{
    for (long k = 1; k <= max; ++k) {
        if (stall(sv, t, RUN_S)) {
            return k;
        }
    }
    return 0;
}

/* |i| > I_stall and |omega| < w_stall in RUN: the fault on exactly the
 * round(stall_time / Ts)-th consecutive sample (rounded in double here:
 * 0.5 s -> 10000; 10.4 Ts -> 10; 10.6 Ts -> 11). */
static void test_stall_fires_after_exact_count(void **state)
{
    (void)state;
    const double times_s[] = { 0.5, 10.4 * TS, 10.6 * TS };
    for (size_t i = 0; i < 3; ++i) {
        mc_fault_limits_t lim = limits();
        lim.stall_time_s = (float)times_s[i];
        const long n = lround((double)lim.stall_time_s / TS);
        mc_supervisor_t sv;
        sv_init(&sv, &lim, TS);
        const mc_telemetry_t t = sample(-2.0f, 7.0f, 0.5f); /* |i| = 7.28 A */
        assert_int_equal(stall_after(&sv, &t, 2 * n + 10), n);
        for (int k = 0; k < 5; ++k) {
            assert_true(stall(&sv, &t, RUN_S)); /* stays */
        }
    }
    /* either sign of the speed */
    const mc_fault_limits_t lim = limits();
    mc_supervisor_t sv;
    sv_init(&sv, &lim, TS);
    const mc_telemetry_t t = sample(0.0f, -7.5f, -0.99f);
    assert_int_equal(stall_after(&sv, &t, 30000), 10000);
}

/* Any interruption restarts the count: n-1 stall samples, one that is not
 * (current at the threshold or below, speed at the threshold or above, not
 * RUN), then the fault only n samples later. In ALIGN never. */
static void test_stall_interruptions_restart(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    const long n = lround((double)lim.stall_time_s / TS);
    const mc_telemetry_t on = sample(0.0f, 7.5f, 0.0f);
    const struct {
        mc_telemetry_t t;
        pstate_t st;
    } breaks[] = {
        { sample(0.0f, 7.0f, 0.0f), RUN_S },   /* |i| = I_stall: not above */
        { sample(3.0f, 6.0f, 0.0f), RUN_S },   /* |i| = 6.7 A */
        { sample(0.0f, 7.5f, 1.0f), RUN_S },   /* |omega| = w_stall: not below */
        { sample(0.0f, 7.5f, -1.5f), RUN_S },  /* turning */
        { sample(0.0f, 7.5f, 0.0f), ALIGN_S }, /* powered, not RUN */
        { sample(0.0f, 7.5f, 0.0f), IDLE_S },  /* not powered */
    };
    for (size_t b = 0; b < sizeof breaks / sizeof breaks[0]; ++b) {
        mc_supervisor_t sv;
        sv_init(&sv, &lim, TS);
        for (long k = 0; k < n - 1; ++k) {
            assert_false(stall(&sv, &on, RUN_S));
        }
        assert_false(stall(&sv, &breaks[b].t, breaks[b].st));
        if (stall_after(&sv, &on, 2 * n) != n) {
            fail_msg("interruption %zu did not restart the count", b);
        }
    }
    /* ALIGN: the same samples for 3 n never stall */
    mc_supervisor_t sv;
    sv_init(&sv, &lim, TS);
    for (long k = 0; k < 3 * n; ++k) {
        assert_false(stall(&sv, &on, ALIGN_S));
    }
}

/* ---- (c) I^2 t ----------------------------------------------------------- */

static bool i2t(mc_supervisor_t *sv, const mc_telemetry_t *t, pstate_t st)
{
    return (step(sv, t, st) & MC_FAULT_I2T) != 0u;
}

/* 1-based index of the first sample with the I2T bit, 0 within max. */
static long i2t_after(mc_supervisor_t *sv, const mc_telemetry_t *t, pstate_t st, long max)
{
    for (long k = 1; k <= max; ++k) {
        if (i2t(sv, t, st)) {
            return k;
        }
    }
    return 0;
}

/* From cold at a constant |i| = I > i_cont: the fault after
 * t_star = (i_peak^2 - i_cont^2) t_peak / (I^2 - i_cont^2) (150 A^2 s here).
 * With the exact period the state after k samples is k (I^2 - i_cont^2) Ts
 * exactly, so the first sample above the limit is floor(t_star / Ts) + 1, within
 * one sample of the analytic time; the peak current for exactly t_peak is
 * the documented rating. */
static void test_i2t_from_cold_exact(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    const float cur[][2] = { { -6.0f, 8.0f }, { 0.0f, 7.0f }, { 13.0f, 0.0f }, { 0.0f, -19.0f } };
    for (size_t i = 0; i < sizeof cur / sizeof cur[0]; ++i) {
        mc_supervisor_t sv;
        sv_init(&sv, &lim, TS_EXACT);
        const double I2 = (double)cur[i][0] * cur[i][0] + (double)cur[i][1] * cur[i][1];
        const double t_star = (100.0 - 25.0) * 2.0 / (I2 - 25.0);
        const mc_telemetry_t t = sample(cur[i][0], cur[i][1], 0.0f);
        const long k = i2t_after(&sv, &t, RUN_S, (long)(2.0 * t_star / TS_EXACT) + 10);
        print_message("|i| = %g A: I2T at sample %ld, analytic %.3f\n", sqrt(I2), k,
                      t_star / TS_EXACT);
        assert_near((double)k, t_star / TS_EXACT, 1.0);
        assert_int_equal(k, (long)floor(t_star / TS_EXACT) + 1);
    }
}

/* The thermal state's float rounding at 20 kHz, in samples of fault time.
 * The state is a compensated (Kahan) sum: its accumulated error is at most
 * 2 u |sum| + O(n u^2) (u = FLT_EPSILON / 2), i.e. 2 u n increments; each
 * increment's own rounding: |i|^2 rounded (u of |i|^2, amplified by the
 * cancellation in |i|^2 - i_cont^2 to u |i|^2 / (|i|^2 - i_cont^2) of the
 * increment), the subtraction and the product by Ts (u each); the grid one
 * sample. */
static double i2t_rounding_bound_samples(double I2, double inc, double limit)
{
    const double n = limit / inc;
    return (2.0 + 2.0 + I2 / (I2 - 25.0)) * 0.5 * FLT_EPSILON * n + 1.0;
}

/* At the drive's 20 kHz the same from-cold time holds to the state's float
 * rounding, down to currents just above the continuous rating, where each
 * increment is some 1e-7 of the state (a plain float sum stalls there:
 * 5.01 A never tripped, 5.5 A tripped 3434 samples late). */
static void test_i2t_from_cold_20khz(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    const float I[] = { 5.1f, 5.5f, 10.0f, 15.0f, 19.0f };
    for (size_t i = 0; i < sizeof I / sizeof I[0]; ++i) {
        mc_supervisor_t sv;
        sv_init(&sv, &lim, TS);
        const double I2 = (double)I[i] * I[i];
        const double t_star = 150.0 / (I2 - 25.0);
        const double bound = i2t_rounding_bound_samples(I2, (I2 - 25.0) * TS, 150.0);
        const mc_telemetry_t t = sample(0.0f, I[i], 0.0f);
        const long k = i2t_after(&sv, &t, RUN_S, (long)(2.0 * t_star / TS));
        print_message("20 kHz, |i| = %g A: I2T at sample %ld, analytic %.2f, bound +-%.1f\n",
                      (double)I[i], k, t_star / TS, bound);
        assert_near((double)k, t_star / TS, bound);
    }
}

/* At or below i_cont the state never leaves 0 (and so never faults). */
static void test_i2t_not_below_continuous(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    const float cur[][2] = { { 0.0f, 5.0f }, { 3.0f, -4.0f }, { 0.0f, 4.99f }, { 0.0f, 0.0f } };
    for (size_t i = 0; i < sizeof cur / sizeof cur[0]; ++i) {
        mc_supervisor_t sv;
        sv_init(&sv, &lim, TS);
        const mc_telemetry_t t = sample(cur[i][0], cur[i][1], 0.0f);
        for (long k = 0; k < 200000; ++k) { /* 10 s: 5 t_peak */
            assert_false(i2t(&sv, &t, RUN_S));
            assert_true(sv.i2t_A2s == 0.0f);
        }
    }
}

/* After the fault the state cools at i_cont^2 per second (|i| = 0): heated
 * at i_peak to 225 A^2 s (3 s at 75 A^2), the bit clears when x <= 150
 * A^2 s, (225 - 150) / 25 = 3 s later; with the drive not powered (the
 * state of a faulted drive), the bit is reported and the cooling is the
 * same. */
static void test_i2t_cools_at_continuous_rate(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    const pstate_t cool_states[] = { IDLE_S, RUN_S };
    for (size_t s = 0; s < 2; ++s) {
        mc_supervisor_t sv;
        sv_init(&sv, &lim, TS_EXACT);
        const mc_telemetry_t hot = sample(0.0f, 10.0f, 0.0f);
        const mc_telemetry_t zero = sample(0.0f, 0.0f, 0.0f);
        const long n_heat = 3L * 16384L; /* 3 s: x = 225 A^2 s */
        for (long k = 1; k <= n_heat; ++k) {
            assert_int_equal(i2t(&sv, &hot, RUN_S), k > 2L * 16384L);
        }
        const double t_cool = (225.0 - 150.0) / 25.0;
        long cleared = 0;
        for (long j = 1; j <= 2L * (long)(t_cool / TS_EXACT); ++j) {
            if (!i2t(&sv, &zero, cool_states[s])) {
                cleared = j;
                break;
            }
        }
        print_message("cooling (%s): clear after %ld samples, analytic %.1f\n",
                      cool_states[s] == IDLE_S ? "not powered" : "RUN", cleared, t_cool / TS_EXACT);
        assert_near((double)cleared, t_cool / TS_EXACT, 1.0);
    }
}

/* The state survives samples without power: heated to 100 A^2 s (4/3 s
 * at 75 A^2/s), then 1 s not powered at |i| = i_cont (no change), then
 * heated again: the fault after (150 - 100) / 75 s more, not from cold. */
static void test_i2t_survives_not_powered(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    mc_supervisor_t sv;
    sv_init(&sv, &lim, TS_EXACT);
    const mc_telemetry_t hot = sample(-6.0f, 8.0f, 0.0f);
    const mc_telemetry_t warm = sample(0.0f, 5.0f, 0.0f);
    const long n1 = 4L * 16384L / 3L; /* 21845 samples: x = 21845 * 75 / 16384 */
    for (long k = 0; k < n1; ++k) {
        assert_false(i2t(&sv, &hot, RUN_S));
    }
    for (long k = 0; k < 16384L; ++k) {
        assert_false(i2t(&sv, &warm, IDLE_S));
    }
    const double x1 = (double)n1 * 75.0 * TS_EXACT;
    const double expected = (150.0 - x1) / 75.0 / TS_EXACT;
    const long k = i2t_after(&sv, &hot, RUN_S, 100000);
    print_message("after the pause: I2T at %ld, analytic %.2f\n", k, expected);
    assert_near((double)k, expected, 1.0);
}

/* A non-finite current (or one whose square overflows) leaves the thermal
 * state as it was: it neither heats nor cools, so the fault comes exactly
 * that many samples later than without them. */
static void test_i2t_nonfinite_current_keeps_state(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    mc_supervisor_t sv;
    sv_init(&sv, &lim, TS_EXACT);
    const mc_telemetry_t hot = sample(-6.0f, 8.0f, 0.0f);
    const mc_telemetry_t bad[] = { sample(NAN, 8.0f, 0.0f), sample(0.0f, INFINITY, 0.0f),
                                   sample(-INFINITY, 0.0f, 0.0f), sample(1e20f, 0.0f, 0.0f) };
    long k = 0, n_bad = 0;
    for (; k < 16384L; ++k) {
        assert_false(i2t(&sv, &hot, RUN_S));
    }
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; ++b) {
        const float x = sv.i2t_A2s;
        for (int j = 0; j < 25; ++j, ++n_bad) {
            assert_false(i2t(&sv, &bad[b], RUN_S));
            assert_true(sv.i2t_A2s == x);
        }
    }
    const long rest = i2t_after(&sv, &hot, RUN_S, 100000);
    /* from cold at i_peak: sample 2 * 16384 + 1 (test_i2t_from_cold_exact) */
    assert_int_equal(k + rest, 2L * 16384L + 1);
    assert_int_equal(n_bad, 100);
}

/* ---- (d) current sum ----------------------------------------------------- */

static bool sum_fault(mc_supervisor_t *sv, float a, float b, float c, pstate_t st)
{
    mc_telemetry_t t = sample(0.0f, 0.0f, 0.0f);
    t.i_abc_A[0] = a;
    t.i_abc_A[1] = b;
    t.i_abc_A[2] = c;
    return (step(sv, &t, st) & MC_FAULT_CURRENT_SENSOR) != 0u;
}

/* |i_a + i_b + i_c| above 1 A for round(1 ms / Ts) = 20 samples faults on
 * the 20th; 19 and then a plausible sample do not; at the threshold
 * never; in ALIGN too; never when not powered (which also restarts the
 * count). */
static void test_current_sum(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    const long n = lround((double)lim.current_sum_time_s / TS);
    assert_int_equal(n, 20);
    const float bad[][3] = { { 0.6f, 0.6f, -0.1f },
                             { -0.6f, -0.6f, 0.1f },
                             { 5.0f, -2.0f, -1.9f } };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        for (int st = ALIGN_S; st <= RUN_S; ++st) {
            mc_supervisor_t sv;
            sv_init(&sv, &lim, TS);
            for (long k = 1; k <= n + 3; ++k) {
                assert_int_equal(sum_fault(&sv, bad[i][0], bad[i][1], bad[i][2], (pstate_t)st),
                                 k >= n);
            }
        }
        /* one sample less, a plausible one, then again one less: never */
        mc_supervisor_t sv;
        sv_init(&sv, &lim, TS);
        for (int rep = 0; rep < 3; ++rep) {
            for (long k = 1; k < n; ++k) {
                assert_false(sum_fault(&sv, bad[i][0], bad[i][1], bad[i][2], RUN_S));
            }
            assert_false(sum_fault(&sv, 3.0f, -2.0f, -1.0f, RUN_S)); /* sum 0 */
        }
        /* not powered: never, and the count restarts */
        for (long k = 1; k < n; ++k) {
            assert_false(sum_fault(&sv, bad[i][0], bad[i][1], bad[i][2], RUN_S));
        }
        for (long k = 0; k < 3 * n; ++k) {
            assert_false(sum_fault(&sv, bad[i][0], bad[i][1], bad[i][2], IDLE_S));
        }
        for (long k = 1; k <= n; ++k) {
            assert_int_equal(sum_fault(&sv, bad[i][0], bad[i][1], bad[i][2], RUN_S), k == n);
        }
    }
    /* |sum| exactly at the threshold (0.5 + 0.25 + 0.25 = 1 in float) */
    mc_supervisor_t sv;
    sv_init(&sv, &lim, TS);
    for (long k = 0; k < 3 * n; ++k) {
        assert_false(sum_fault(&sv, 0.5f, 0.25f, 0.25f, RUN_S));
        assert_false(sum_fault(&sv, -0.5f, -0.25f, -0.25f, RUN_S));
    }
}

/* ---- sustained current limit --------------------------------------------- */

static bool limit_fault(mc_supervisor_t *sv, bool limiting, pstate_t st)
{
    const mc_telemetry_t t = sample(0.0f, 0.0f, 10.0f);
    return (mc_supervisor_step(sv, &t, st == RUN_S, st != IDLE_S, limiting) &
            MC_FAULT_CURRENT_LIMIT) != 0u;
}

/* The limit loop acting for round(0.1 s / Ts) = 2000 samples in a row
 * faults on the 2000th (and on while it acts); a break restarts the count;
 * only in RUN (in ALIGN and when not powered the count restarts). */
static void test_current_limit_sustained(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = limits();
    const long n = lround((double)lim.current_limit_time_s / TS);
    assert_int_equal(n, 2000);
    mc_supervisor_t sv;
    sv_init(&sv, &lim, TS);
    for (long k = 1; k <= n + 5; ++k) {
        assert_int_equal(limit_fault(&sv, true, RUN_S), k >= n);
    }
    for (int brk = 0; brk < 3; ++brk) {
        const pstate_t st_break[] = { RUN_S, ALIGN_S, IDLE_S };
        if (st_break[brk] == RUN_S) {
            assert_false(limit_fault(&sv, false, RUN_S)); /* not acting */
        } else {
            assert_false(limit_fault(&sv, true, st_break[brk]));
        }
        for (long k = 1; k < n; ++k) {
            assert_false(limit_fault(&sv, true, RUN_S));
        }
        assert_true(limit_fault(&sv, true, RUN_S));
    }
}

/* ---- init ---------------------------------------------------------------- */

/* Times that round to no sample, and a thermal limit that is not positive
 * or overflows, are rejected (*sv untouched); one sample is accepted. */
static void test_init_rejects(void **state)
{
    (void)state;
    const struct {
        size_t off;
        float value;
        mc_status_t expected;
    } c[] = {
#define LIM(f) offsetof(mc_fault_limits_t, f)
        { LIM(stall_time_s), (float)(0.4 * TS), MC_ERR_PARAM },
        { LIM(stall_time_s), 0.0f, MC_ERR_PARAM },
        { LIM(stall_time_s), (float)TS, MC_OK },
        { LIM(current_sum_time_s), (float)(0.4 * TS), MC_ERR_PARAM },
        { LIM(current_sum_time_s), (float)TS, MC_OK },
        { LIM(current_limit_time_s), (float)(0.4 * TS), MC_ERR_PARAM },
        { LIM(current_limit_time_s), (float)TS, MC_OK },
        { LIM(i2t_peak_A), 5.0f, MC_ERR_PARAM },  /* = i_cont: limit 0 */
        { LIM(i2t_peak_A), 1e20f, MC_ERR_PARAM }, /* peak^2 overflows */
        { LIM(i2t_peak_time_s), 0.0f, MC_ERR_PARAM },
#undef LIM
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; ++i) {
        mc_fault_limits_t lim = limits();
        memcpy((unsigned char *)&lim + c[i].off, &c[i].value, sizeof(float));
        mc_supervisor_t sv, pattern;
        memset(&sv, 0x5a, sizeof sv);
        memset(&pattern, 0x5a, sizeof pattern);
        const mc_status_t got = mc_supervisor_init(&sv, &lim, (float)TS);
        if (got != c[i].expected) {
            fail_msg("case %zu: got %d, expected %d", i, (int)got, (int)c[i].expected);
        }
        if (got != MC_OK) {
            assert_memory_equal(&sv, &pattern, sizeof sv);
        } else {
            assert_true(sv.i2t_A2s == 0.0f); /* cold */
        }
    }
    /* the period of the steps: > 0 and finite */
    const float steps[] = { 0.0f, -1e-3f, NAN, INFINITY };
    const mc_fault_limits_t lim = limits();
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; ++i) {
        mc_supervisor_t sv;
        assert_int_equal(mc_supervisor_init(&sv, &lim, steps[i]), MC_ERR_PARAM);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_overspeed),
        cmocka_unit_test(test_stall_fires_after_exact_count),
        cmocka_unit_test(test_stall_interruptions_restart),
        cmocka_unit_test(test_i2t_from_cold_exact),
        cmocka_unit_test(test_i2t_from_cold_20khz),
        cmocka_unit_test(test_i2t_not_below_continuous),
        cmocka_unit_test(test_i2t_cools_at_continuous_rate),
        cmocka_unit_test(test_i2t_survives_not_powered),
        cmocka_unit_test(test_i2t_nonfinite_current_keeps_state),
        cmocka_unit_test(test_current_sum),
        cmocka_unit_test(test_current_limit_sustained),
        cmocka_unit_test(test_init_rejects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
