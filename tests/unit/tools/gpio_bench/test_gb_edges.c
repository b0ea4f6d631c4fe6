/*
 * Edge pairing, statistics and histogram of pmsm-gpio-bench (gb_edges.c):
 * the rules of gb_edges.h one at a time, on hand-made edge sequences.
 */
#include "mc_test.h"

#include "gb_edges.h"

#include <string.h>

#define R GB_EDGE_RISING
#define F GB_EDGE_FALLING

typedef struct {
    gb_edge_kind_t kind;
    uint64_t ts;
    unsigned long seq; /* line and global */
} edge_t;

static gb_summary_t run(const edge_t *e, size_t n, int64_t glitch_ns, int64_t expect_ns)
{
    gb_edges_t an;
    gb_edges_init(&an, glitch_ns);
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(gb_edges_push(&an, e[i].kind, e[i].ts, e[i].seq, e[i].seq), 0);
    }
    gb_summary_t s;
    assert_int_equal(gb_edges_summarize(&an, expect_ns, 0, &s), 0);
    gb_edges_free(&an);
    return s;
}

#define RUN(edges, glitch, expect) run((edges), sizeof(edges) / sizeof((edges)[0]), glitch, expect)

static void test_clean_pulses(void **state)
{
    (void)state;
    const edge_t e[] = { { R, 1000, 1 }, { F, 1300, 2 }, { R, 2000, 3 },
                         { F, 2400, 4 }, { R, 3100, 5 }, { F, 3300, 6 } };
    const gb_summary_t s = RUN(e, 0, 1000);
    assert_int_equal(s.duration.count, 3);
    assert_int_equal(s.duration.min, 200);
    assert_int_equal(s.duration.max, 400);
    assert_near(s.duration.mean, 300.0, 1e-12);
    assert_int_equal(s.period.count, 2);
    assert_int_equal(s.period.min, 1000);
    assert_int_equal(s.period.max, 1100);
    assert_near(s.period.mean, 1050.0, 1e-12);
    assert_int_equal(s.jitter.min, 0);
    assert_int_equal(s.jitter.max, 100);
    assert_near(s.jitter.rms, sqrt((0.0 + 100.0 * 100.0) / 2.0), 1e-9);
}

static void test_leading_falling_edge_ignored(void **state)
{
    (void)state;
    const edge_t e[] = {
        { F, 500, 1 }, { R, 1000, 2 }, { F, 1300, 3 }, { R, 2000, 4 }, { F, 2300, 5 }
    };
    const gb_summary_t s = RUN(e, 0, 0);
    assert_int_equal(s.seq_errors, 0);
    assert_int_equal(s.duration.count, 2);
    assert_int_equal(s.period.count, 1);
    assert_int_equal(s.period.min, 1000);
    assert_int_equal(s.jitter_ref_ns, 1000); /* the mean */
}

static void test_gap_breaks_measurements(void **state)
{
    (void)state;
    /* seqno 4 (F of the second pulse) lost */
    const edge_t e[] = { { R, 1000, 1 }, { F, 1300, 2 }, { R, 2000, 3 }, { R, 3000, 5 },
                         { F, 3300, 6 }, { R, 4000, 7 }, { F, 4300, 8 } };
    const gb_summary_t s = RUN(e, 0, 0);
    assert_int_equal(s.lost_line, 1);
    assert_int_equal(s.lost_global, 1);
    assert_int_equal(s.seq_errors, 0); /* R after R across a gap is no error */
    assert_int_equal(s.duration.count, 3);
    assert_int_equal(s.period.count, 1); /* only 3000 -> 4000 */
    assert_int_equal(s.period.min, 1000);
}

static void test_lost_before_first_event(void **state)
{
    (void)state;
    const edge_t e[] = { { R, 1000, 3 }, { F, 1300, 4 } };
    const gb_summary_t s = RUN(e, 0, 0);
    assert_int_equal(s.lost_line, 2);
    assert_int_equal(s.duration.count, 1);
}

static void test_sequence_error(void **state)
{
    (void)state;
    /* a falling edge missed without a gap: R R */
    const edge_t e[] = { { R, 1000, 1 }, { F, 1300, 2 }, { R, 2000, 3 }, { R, 3000, 4 },
                         { F, 3300, 5 }, { R, 4000, 6 }, { F, 4300, 7 } };
    const gb_summary_t s = RUN(e, 0, 0);
    assert_int_equal(s.seq_errors, 1);
    assert_int_equal(s.duration.count, 3); /* 1000, 3000 and 4000 */
    assert_int_equal(s.period.count, 1);   /* 3000 -> 4000 */
}

static void test_high_and_low_glitches(void **state)
{
    (void)state;
    const edge_t e[] = {
        { R, 1000, 1 }, { F, 1300, 2 },  /* pulse */
        { R, 1500, 3 }, { F, 1550, 4 },  /* high glitch 50 ns */
        { R, 2000, 5 }, { F, 2100, 6 },  /* pulse, low glitch 80 ns: */
        { R, 2180, 7 }, { F, 2400, 8 },  /* ... it goes on to 2400 */
        { R, 3000, 9 }, { F, 3200, 10 }, /* pulse */
    };
    const gb_summary_t s = RUN(e, 100, 1000);
    assert_int_equal(s.glitches, 2);
    assert_int_equal(s.duration.count, 3);
    assert_int_equal(s.duration.min, 200);
    assert_int_equal(s.duration.max, 400);
    assert_int_equal(s.period.count, 2);
    assert_int_equal(s.period.min, 1000);
    assert_int_equal(s.period.max, 1000);
}

static void test_backwards_timestamp(void **state)
{
    (void)state;
    /* time going back is a gap: the pulse before it is not confirmed (its
     * next rising edge comes after the gap), the ones after it count */
    const edge_t e[] = { { R, 1000, 1 }, { F, 1300, 2 }, { R, 900, 3 },
                         { F, 1200, 4 }, { R, 2000, 5 }, { F, 2300, 6 } };
    const gb_summary_t s = RUN(e, 0, 0);
    assert_int_equal(s.backwards, 1);
    assert_int_equal(s.duration.count, 2);
    assert_int_equal(s.period.count, 1);
    assert_int_equal(s.period.min, 1100);
}

static void test_histogram_adaptive_and_negative(void **state)
{
    (void)state;
    gb_hist_t h;
    const int64_t v[] = { -1500, -1000, -1, 0, 999, 1000, 2500 };
    assert_int_equal(gb_hist_build(&h, v, 7, 0), 0);
    assert_int_equal(h.width_ns, 1000);
    assert_int_equal(h.lo_ns, -2000);
    assert_int_equal(h.nbins, 5);
    const uint64_t want[5] = { 1, 2, 2, 1, 1 };
    for (size_t k = 0; k < 5; k++) {
        assert_int_equal(h.count[k], want[k]);
    }
    /* a span of 100 us: 1-2-5 steps up to 5 us bins (20 + 1 bins) */
    const int64_t w[] = { -50000, 50000, 1 };
    assert_int_equal(gb_hist_build(&h, w, 3, 0), 0);
    assert_int_equal(h.width_ns, 5000);
    assert_int_equal(h.nbins, 21);
    /* a given width too fine for 40 bins */
    assert_int_equal(gb_hist_build(&h, w, 3, 1000), -1);
    assert_int_equal(gb_hist_build(&h, NULL, 0, 0), 0);
    assert_int_equal(h.nbins, 0);
}

static void test_stats_empty_and_many(void **state)
{
    (void)state;
    const gb_stats_t z = gb_stats_of(NULL, 0);
    assert_int_equal(z.count, 0);
    /* many samples: the arrays grow past their first 1024 */
    gb_edges_t an;
    gb_edges_init(&an, 0);
    unsigned long seq = 0;
    for (int k = 0; k < 5000; k++) {
        const uint64_t t = (uint64_t)k * 50000u;
        assert_int_equal(gb_edges_push(&an, R, t, seq + 1, seq + 1), 0);
        assert_int_equal(gb_edges_push(&an, F, t + 7000u, seq + 2, seq + 2), 0);
        seq += 2;
    }
    gb_summary_t s;
    assert_int_equal(gb_edges_summarize(&an, 50000, 0, &s), 0);
    gb_edges_free(&an);
    assert_int_equal(s.duration.count, 5000);
    assert_int_equal(s.period.count, 4999);
    assert_int_equal(s.jitter.min, 0);
    assert_int_equal(s.jitter.max, 0);
    assert_int_equal(s.hist.nbins, 1);
    assert_int_equal(s.hist.count[0], 4999);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clean_pulses),
        cmocka_unit_test(test_leading_falling_edge_ignored),
        cmocka_unit_test(test_gap_breaks_measurements),
        cmocka_unit_test(test_lost_before_first_event),
        cmocka_unit_test(test_sequence_error),
        cmocka_unit_test(test_high_and_low_glitches),
        cmocka_unit_test(test_backwards_timestamp),
        cmocka_unit_test(test_histogram_adaptive_and_negative),
        cmocka_unit_test(test_stats_empty_and_many),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
