/*
 * pmsm-gpio-bench end to end on a fake libgpiod (fake_gpiod.c, bound with
 * -Wl,--wrap): the real command line, libgpiod calls, edge pairing,
 * statistics and reports; the expected numbers are computed here from the
 * script of edges, independently of the tool.
 */
#define _POSIX_C_SOURCE 200809L

#include "mc_test.h"

#include "fake_gpiod.h"
#include "gb_main.h"

#include <errno.h>
#include <gpiod.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- running the tool, its output captured ---- */

typedef struct {
    int code;
    char out[16384];
    char err[4096];
} run_t;

static void read_all(FILE *f, char *buf, size_t len)
{
    rewind(f);
    const size_t n = fread(buf, 1, len - 1, f);
    buf[n] = '\0';
    fclose(f);
}

static run_t run_argv(int argc, char **argv)
{
    run_t r;
    FILE *out = tmpfile();
    FILE *err = tmpfile();
    assert_non_null(out);
    assert_non_null(err);
    r.code = gb_main(argc, argv, out, err);
    read_all(out, r.out, sizeof(r.out));
    read_all(err, r.err, sizeof(r.err));
    return r;
}

#define RUN(...)                                                                                   \
    run_argv((int)(sizeof((char *[]){ __VA_ARGS__ }) / sizeof(char *)), (char *[]){ __VA_ARGS__ })

static int setup(void **state)
{
    (void)state;
    fake_reset();
    return 0;
}

/* Every object the tool made was freed, the request released, the chip
 * closed. */
static void assert_clean(void)
{
    assert_int_equal(fake.objects_live, 0);
    assert_int_equal(fake.chips_open, 0);
    assert_int_equal(fake.releases, fake.requests - (fake.request_errno != 0 ? 1 : 0));
}

/* ---- the ISR script: period 100 us with a known jitter pattern ---- */

#define PERIOD_NS         100000LL
#define NPULSES           50
#define LOST_PULSE        20 /* its falling edge is lost (a seqno gap) */
#define HIGH_GLITCH_AFTER 30 /* a 100 ns high glitch 50 us after this pulse */
#define LOW_GLITCH_IN     40 /* a 100 ns low glitch 5 us into this pulse */

static const int64_t jitter_pattern[8] = { 0, 300, -200, 100, 0, -400, 200, 0 };

static int64_t rise_ns(int k)
{
    return FAKE_T0_NS + 1000000LL + k * PERIOD_NS + jitter_pattern[k % 8];
}

static int64_t duration_ns(int k)
{
    return 20000 + 100 * (k % 5);
}

/* Emits the script; seqnos count every edge the kernel saw, emitted or
 * lost. */
static void script_isr(void)
{
    unsigned long seq = 0;
#define EMIT(type, ts)                                                                             \
    do {                                                                                           \
        seq++;                                                                                     \
        fake_add_event((type), (uint64_t)(ts), seq, seq);                                          \
    } while (0)
    /* the capture begins inside a pulse: a lone falling edge first */
    EMIT(GPIOD_EDGE_EVENT_FALLING_EDGE, rise_ns(0) - 50000);
    for (int k = 0; k < NPULSES; k++) {
        EMIT(GPIOD_EDGE_EVENT_RISING_EDGE, rise_ns(k));
        if (k == LOW_GLITCH_IN) {
            EMIT(GPIOD_EDGE_EVENT_FALLING_EDGE, rise_ns(k) + 5000);
            EMIT(GPIOD_EDGE_EVENT_RISING_EDGE, rise_ns(k) + 5100);
        }
        if (k == LOST_PULSE) {
            seq++; /* the kernel dropped this falling edge */
        } else {
            EMIT(GPIOD_EDGE_EVENT_FALLING_EDGE, rise_ns(k) + duration_ns(k));
        }
        if (k == HIGH_GLITCH_AFTER) {
            EMIT(GPIOD_EDGE_EVENT_RISING_EDGE, rise_ns(k) + 50000);
            EMIT(GPIOD_EDGE_EVENT_FALLING_EDGE, rise_ns(k) + 50100);
        }
    }
#undef EMIT
}

/* What the summary must say, computed from the script by the documented
 * rules: the lost falling edge drops pulse 20, and the periods ending at
 * rising edges 20 (unconfirmed pulse) and 21 (across the gap); glitches
 * change nothing else. */
typedef struct {
    size_t n_dur, n_per;
    int64_t dur[NPULSES], per[NPULSES];
} expect_t;

static expect_t expected(void)
{
    expect_t x;
    memset(&x, 0, sizeof(x));
    for (int k = 0; k < NPULSES; k++) {
        if (k != LOST_PULSE) {
            x.dur[x.n_dur++] = duration_ns(k);
        }
        if (k >= 1 && k != LOST_PULSE && k != LOST_PULSE + 1) {
            x.per[x.n_per++] = rise_ns(k) - rise_ns(k - 1);
        }
    }
    return x;
}

static void expect_stats(const gb_stats_t *st, const int64_t *v, size_t n, int64_t offset)
{
    int64_t mn = v[0] - offset, mx = v[0] - offset, sum = 0;
    for (size_t i = 0; i < n; i++) {
        mn = (v[i] - offset < mn) ? v[i] - offset : mn;
        mx = (v[i] - offset > mx) ? v[i] - offset : mx;
        sum += v[i] - offset;
    }
    assert_int_equal(st->count, n);
    assert_int_equal(st->min, mn);
    assert_int_equal(st->max, mx);
    assert_near(st->mean, (double)sum / (double)n, 1e-9);
}

static void test_isr_summary_against_expected_period(void **state)
{
    (void)state;
    script_isr();
    gb_args_t a;
    char why[160];
    char *argv[] = {
        "pmsm-gpio-bench",    "isr", "--chip", "/dev/gpiochip0", "--line", "5", "--seconds", "0.01",
        "--expect-period-us", "100"
    };
    assert_int_equal(gb_args_parse(10, argv, &a, why, sizeof(why)), GB_EXIT_OK);
    FILE *out = tmpfile();
    gb_summary_t s;
    assert_int_equal(gb_isr_run(&a, &s, out, stderr), GB_EXIT_OK);
    fclose(out);

    /* the request: one input line, both edges, monotonic timestamps */
    assert_string_equal(fake.opened_path, "/dev/gpiochip0");
    assert_int_equal(fake.requests, 1);
    assert_int_equal(fake.num_offsets, 1);
    assert_int_equal(fake.offset, 5);
    assert_int_equal(fake.direction, GPIOD_LINE_DIRECTION_INPUT);
    assert_int_equal(fake.edge, GPIOD_LINE_EDGE_BOTH);
    assert_int_equal(fake.clock, GPIOD_LINE_CLOCK_MONOTONIC);
    assert_false(fake.active_low);
    assert_string_equal(fake.consumer, "pmsm-gpio-bench");
    assert_int_equal(fake.event_buffer_size, 1024);
    assert_int_equal(fake.next_event, fake.nevents); /* every edge read */
    assert_clean();

    /* counts: 1 lone falling + 50 pulses - 1 lost + 2 glitches of 2 edges */
    assert_int_equal(s.edges, 1 + 2 * NPULSES - 1 + 4);
    assert_int_equal(s.rising, NPULSES + 2);
    assert_int_equal(s.falling, 1 + NPULSES - 1 + 2);
    assert_int_equal(s.lost_line, 1);
    assert_int_equal(s.lost_global, 1);
    assert_int_equal(s.glitches, 2);
    assert_int_equal(s.seq_errors, 0);
    assert_int_equal(s.backwards, 0);

    const expect_t x = expected();
    expect_stats(&s.duration, x.dur, x.n_dur, 0);
    expect_stats(&s.period, x.per, x.n_per, 0);
    assert_true(s.jitter_vs_expected);
    assert_int_equal(s.jitter_ref_ns, PERIOD_NS);
    expect_stats(&s.jitter, x.per, x.n_per, PERIOD_NS);
    /* the pattern's differences: jitter from -500 to +600 ns */
    assert_int_equal(s.jitter.min, -500);
    assert_int_equal(s.jitter.max, 600);

    /* histogram: adaptive 1 us bins [-1, 0) and [0, 1) us */
    assert_true(s.hist_ok);
    assert_int_equal(s.hist.width_ns, 1000);
    assert_int_equal(s.hist.lo_ns, -1000);
    assert_int_equal(s.hist.nbins, 2);
    size_t neg = 0;
    for (size_t i = 0; i < x.n_per; i++) {
        neg += (x.per[i] < PERIOD_NS) ? 1u : 0u;
    }
    assert_int_equal(s.hist.count[0], neg);
    assert_int_equal(s.hist.count[1], x.n_per - neg);
}

static void test_isr_jitter_against_mean_fine_bins(void **state)
{
    (void)state;
    script_isr();
    gb_args_t a;
    char why[160];
    char *argv[] = {
        "pmsm-gpio-bench", "isr", "--line", "5", "--seconds", "0.01", "--bin-us", "0.1"
    };
    assert_int_equal(gb_args_parse(8, argv, &a, why, sizeof(why)), GB_EXIT_OK);
    FILE *out = tmpfile();
    gb_summary_t s;
    assert_int_equal(gb_isr_run(&a, &s, out, stderr), GB_EXIT_OK);
    fclose(out);

    const expect_t x = expected();
    int64_t sum = 0;
    for (size_t i = 0; i < x.n_per; i++) {
        sum += x.per[i];
    }
    const int64_t ref = llround((double)sum / (double)x.n_per);
    assert_false(s.jitter_vs_expected);
    assert_int_equal(s.jitter_ref_ns, ref);
    expect_stats(&s.jitter, x.per, x.n_per, ref);

    /* 100 ns bins, each count from the script */
    assert_true(s.hist_ok);
    assert_int_equal(s.hist.width_ns, 100);
    for (size_t b = 0; b < s.hist.nbins; b++) {
        const int64_t lo = s.hist.lo_ns + (int64_t)b * 100;
        uint64_t c = 0;
        for (size_t i = 0; i < x.n_per; i++) {
            const int64_t j = x.per[i] - ref;
            c += (j >= lo && j < lo + 100) ? 1u : 0u;
        }
        assert_int_equal(s.hist.count[b], c);
    }
    assert_clean();
}

static void test_isr_text_and_json(void **state)
{
    (void)state;
    script_isr();
    char dir[] = "/tmp/gb_test_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char json[64];
    snprintf(json, sizeof(json), "%s/isr.json", dir);
    const run_t r = RUN("pmsm-gpio-bench", "isr", "--line", "5", "--seconds", "0.01",
                        "--expect-period-us", "100", "--json", json);
    assert_int_equal(r.code, GB_EXIT_OK);
    assert_non_null(strstr(r.out, "edges lost     : 1 "));
    assert_non_null(strstr(r.out, "glitches       : 2 "));
    assert_non_null(strstr(r.out, "jitter histogram (1.000 us bins):"));
    assert_non_null(strstr(r.out, "result: ok"));

    char text[8192];
    FILE *f = fopen(json, "r");
    assert_non_null(f);
    read_all(f, text, sizeof(text));
    assert_non_null(strstr(text, "\"lost\": {\"line_seqno\": 1, \"global_seqno\": 1}"));
    assert_non_null(strstr(text, "\"glitches\": 2,"));
    assert_non_null(strstr(text, "\"jitter\": {\"count\": 47, \"min\": -500,"));
    assert_non_null(strstr(text, "\"passed\": true"));
    char tmp[80];
    snprintf(tmp, sizeof(tmp), "%s.tmp", json);
    assert_int_equal(access(tmp, F_OK), -1); /* renamed into place */
    assert_int_equal(remove(json), 0);
    assert_int_equal(rmdir(dir), 0);
}

static void test_isr_criteria(void **state)
{
    (void)state;
    script_isr();
    run_t r = RUN("pmsm-gpio-bench", "isr", "--line", "5", "--seconds", "0.01",
                  "--expect-period-us", "100", "--max-lost", "0");
    assert_int_equal(r.code, GB_EXIT_FAIL);
    assert_non_null(strstr(r.out, "result: FAIL: 1 edges lost"));

    fake_reset();
    script_isr();
    r = RUN("pmsm-gpio-bench", "isr", "--line", "5", "--seconds", "0.01", "--expect-period-us",
            "100", "--max-jitter-us", "0.5");
    assert_int_equal(r.code, GB_EXIT_FAIL);
    assert_non_null(strstr(r.out, "jitter 0.600 us exceeds"));

    fake_reset();
    script_isr();
    r = RUN("pmsm-gpio-bench", "isr", "--line", "5", "--seconds", "0.01", "--expect-period-us",
            "100", "--max-jitter-us", "0.6", "--max-lost", "1");
    assert_int_equal(r.code, GB_EXIT_OK);
}

static void test_isr_no_edges_fails(void **state)
{
    (void)state;
    const run_t r = RUN("pmsm-gpio-bench", "isr", "--line", "3", "--seconds", "0.5");
    assert_int_equal(r.code, GB_EXIT_FAIL);
    assert_non_null(strstr(r.out, "no ISR period measured (0 edges seen)"));
    /* the capture lasted its 0.5 s of (fake) time */
    assert_true(fake.release_t_ns - fake.request_t_ns >= 500000000LL);
    assert_clean();
}

static void test_isr_capture_ends_at_deadline(void **state)
{
    (void)state;
    script_isr();
    /* 3 ms from the start: the edges up to the deadline, no more */
    gb_args_t a;
    char why[160];
    char *argv[] = { "pmsm-gpio-bench", "isr", "--line", "5", "--seconds", "0.003" };
    assert_int_equal(gb_args_parse(6, argv, &a, why, sizeof(why)), GB_EXIT_OK);
    FILE *out = tmpfile();
    gb_summary_t s;
    assert_int_equal(gb_isr_run(&a, &s, out, stderr), GB_EXIT_OK);
    fclose(out);
    size_t before = 0;
    for (size_t i = 0; i < fake.nevents; i++) {
        before += (fake.events[i].ts_ns <= (uint64_t)(FAKE_T0_NS + 3000000LL)) ? 1u : 0u;
    }
    assert_int_equal(s.edges, before);
    assert_int_equal(s.lost_line, 0);
}

/* ---- sto ---- */

static void test_sto_pulse_timing(void **state)
{
    (void)state;
    const run_t r =
        RUN("pmsm-gpio-bench", "sto", "--chip", "/dev/gpiochip1", "--line", "17", "pulse", "50");
    assert_int_equal(r.code, GB_EXIT_OK);
    assert_string_equal(fake.opened_path, "/dev/gpiochip1");
    assert_int_equal(fake.offset, 17);
    assert_int_equal(fake.direction, GPIOD_LINE_DIRECTION_OUTPUT);
    assert_false(fake.active_low);
    /* asserted by the request itself, released 50 ms later, nothing else */
    assert_int_equal(fake.output_value, GPIOD_LINE_VALUE_ACTIVE);
    assert_int_equal(fake.nsets, 1);
    assert_int_equal(fake.sets[0].value, GPIOD_LINE_VALUE_INACTIVE);
    assert_int_equal(fake.sets[0].t_ns - fake.request_t_ns, 50000000LL);
    assert_int_equal(fake.release_t_ns, fake.sets[0].t_ns);
    assert_non_null(strstr(r.out, "asserted (high) for 50.000 ms (pulse 50 ms), released (low)"));
    assert_clean();
}

static void test_sto_assert_active_low_hold(void **state)
{
    (void)state;
    const run_t r =
        RUN("pmsm-gpio-bench", "sto", "--line", "4", "--active-low", "--hold", "2", "assert");
    assert_int_equal(r.code, GB_EXIT_OK);
    assert_string_equal(fake.opened_path, "/dev/gpiochip0");
    assert_true(fake.active_low);
    assert_int_equal(fake.output_value, GPIOD_LINE_VALUE_ACTIVE);
    assert_int_equal(fake.nsets, 0);
    assert_int_equal(fake.release_t_ns - fake.request_t_ns, 2000000000LL);
    assert_non_null(strstr(r.out, "asserted (low); holding 2.000 s"));
    assert_clean();
}

static void test_sto_release_until_sigint(void **state)
{
    (void)state;
    struct sigaction before;
    assert_int_equal(sigaction(SIGINT, NULL, &before), 0);
    fake.sigint_at_sleep = 3; /* Ctrl-C in the third 100 ms sleep */
    const run_t r = RUN("pmsm-gpio-bench", "sto", "--line", "4", "release");
    assert_int_equal(r.code, GB_EXIT_OK);
    assert_int_equal(fake.output_value, GPIOD_LINE_VALUE_INACTIVE);
    assert_int_equal(fake.nsets, 0);
    assert_int_equal(fake.sleeps, 3);
    assert_int_equal(fake.release_t_ns - fake.request_t_ns, 200000000LL);
    assert_non_null(strstr(r.out, "holding until Ctrl-C"));
    /* the disposition from before is back (SIG_DFL, or SIG_IGN in a
     * background job) */
    struct sigaction after;
    assert_int_equal(sigaction(SIGINT, NULL, &after), 0);
    assert_true(after.sa_handler == before.sa_handler);
    assert_clean();
}

static void test_sto_line_busy(void **state)
{
    (void)state;
    fake.request_errno = EBUSY;
    const run_t r = RUN("pmsm-gpio-bench", "sto", "--line", "4", "pulse", "10");
    assert_int_equal(r.code, GB_EXIT_FAIL);
    assert_non_null(strstr(r.err, "cannot request line 4 of /dev/gpiochip0"));
    assert_non_null(strstr(r.err, "used by another consumer"));
    assert_clean();
}

/* ---- no chip ---- */

static void test_no_chip_is_77(void **state)
{
    (void)state;
    fake.chip_present = false;
    fake.open_errno = ENOENT;
    run_t r = RUN("pmsm-gpio-bench", "isr", "--chip", "/nonexistent-gb-test/gpiochip0", "--line",
                  "1", "--seconds", "1");
    assert_int_equal(r.code, GB_EXIT_NO_GPIO);
    assert_int_equal(r.code, 77);
    assert_non_null(strstr(r.err, "no GPIO chip /nonexistent-gb-test/gpiochip0: No such file or "
                                  "directory (this machine has no GPIO; run on the bench host)"));
    assert_int_equal(fake.requests, 0);

    r = RUN("pmsm-gpio-bench", "sto", "--chip", "/nonexistent-gb-test/gpiochip0", "--line", "1",
            "assert");
    assert_int_equal(r.code, 77);
    assert_int_equal(fake.requests, 0);
    assert_clean();
}

static void test_wrong_chip_among_others_is_usage(void **state)
{
    (void)state;
    char dir[] = "/tmp/gb_test_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char other[64], wanted[64];
    snprintf(other, sizeof(other), "%s/gpiochip3", dir);
    snprintf(wanted, sizeof(wanted), "%s/gpiochip0", dir);
    FILE *f = fopen(other, "w");
    assert_non_null(f);
    fclose(f);
    fake.chip_present = false;
    fake.open_errno = ENOENT;
    const run_t r = RUN("pmsm-gpio-bench", "sto", "--chip", wanted, "--line", "1", "assert");
    assert_int_equal(r.code, GB_EXIT_USAGE);
    assert_non_null(strstr(r.err, "(chips there: gpiochip3)"));
    assert_int_equal(remove(other), 0);
    assert_int_equal(rmdir(dir), 0);
}

static void test_not_a_chip_and_permission(void **state)
{
    (void)state;
    fake.chip_present = false;
    fake.open_errno = ENODEV;
    run_t r = RUN("pmsm-gpio-bench", "sto", "--chip", "/dev/null", "--line", "1", "assert");
    assert_int_equal(r.code, GB_EXIT_USAGE);
    assert_non_null(strstr(r.err, "/dev/null is not a GPIO chip"));

    fake.open_errno = EACCES;
    r = RUN("pmsm-gpio-bench", "sto", "--line", "1", "assert");
    assert_int_equal(r.code, GB_EXIT_FAIL);
    assert_non_null(strstr(r.err, "root or group gpio"));
}

static void test_usage_and_help(void **state)
{
    (void)state;
    run_t r = RUN("pmsm-gpio-bench", "isr", "--line", "1");
    assert_int_equal(r.code, GB_EXIT_USAGE);
    assert_non_null(strstr(r.err, "isr: --seconds S is required"));
    assert_non_null(strstr(r.err, "usage: pmsm-gpio-bench"));
    r = RUN("pmsm-gpio-bench", "--help");
    assert_int_equal(r.code, GB_EXIT_OK);
    assert_non_null(strstr(r.out, "77 no GPIO chip"));
    assert_null(strstr(fake.opened_path, "gpiochip")); /* no chip opened */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_isr_summary_against_expected_period, setup),
        cmocka_unit_test_setup(test_isr_jitter_against_mean_fine_bins, setup),
        cmocka_unit_test_setup(test_isr_text_and_json, setup),
        cmocka_unit_test_setup(test_isr_criteria, setup),
        cmocka_unit_test_setup(test_isr_no_edges_fails, setup),
        cmocka_unit_test_setup(test_isr_capture_ends_at_deadline, setup),
        cmocka_unit_test_setup(test_sto_pulse_timing, setup),
        cmocka_unit_test_setup(test_sto_assert_active_low_hold, setup),
        cmocka_unit_test_setup(test_sto_release_until_sigint, setup),
        cmocka_unit_test_setup(test_sto_line_busy, setup),
        cmocka_unit_test_setup(test_no_chip_is_77, setup),
        cmocka_unit_test_setup(test_wrong_chip_among_others_is_usage, setup),
        cmocka_unit_test_setup(test_not_a_chip_and_permission, setup),
        cmocka_unit_test_setup(test_usage_and_help, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
