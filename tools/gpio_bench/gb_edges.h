/*
 * pmsm-gpio-bench: the ISR debug pin's edges turned into measurements (pure:
 * no GPIO). The firmware raises the pin at ISR entry and lowers it at exit,
 * so a high pulse is one ISR: rising -> falling is its duration, rising ->
 * rising the ISR period.
 *
 * Rules (README.md, "How edges are paired"):
 *  - a lost edge is a gap in the kernel's sequence numbers (line seqno for
 *    the line, global seqno for the request); no duration or period is
 *    measured across a gap;
 *  - a high pulse shorter than glitch_ns is a glitch: counted, its duration
 *    dropped, and its rising edge is not a period start (the period runs from
 *    the previous real rising edge to the next one); a low pulse shorter than
 *    glitch_ns (inside an ISR pulse) is a glitch too: the pulse goes on;
 *  - two edges of the same kind in a row (an edge the kernel missed without a
 *    gap) are a sequence error: the pulse and the period around it are
 *    dropped;
 *  - a pulse counts (its duration, and the period that ends at its rising
 *    edge) once the next rising edge shows it was no low glitch, or at the
 *    end of the capture; a falling edge first in the capture (the capture
 *    began inside a pulse) is ignored.
 */
#ifndef GB_EDGES_H
#define GB_EDGES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum { GB_EDGE_RISING = 1, GB_EDGE_FALLING = 2 } gb_edge_kind_t;

/* A growing array of int64 samples (ns). */
typedef struct {
    int64_t *v;
    size_t n;
    size_t cap;
} gb_samples_t;

typedef struct {
    int64_t glitch_ns; /* high pulses shorter than this are glitches (0: none) */

    /* counts */
    uint64_t edges;       /* events seen */
    uint64_t rising;      /* of which rising */
    uint64_t falling;     /* of which falling */
    uint64_t lost_line;   /* line seqno gaps, summed */
    uint64_t lost_global; /* global seqno gaps, summed */
    uint64_t glitches;
    uint64_t seq_errors;
    uint64_t backwards; /* timestamps that went back (dropped like a gap) */

    /* measurements */
    gb_samples_t durations; /* rising -> falling, ns */
    gb_samples_t periods;   /* rising -> rising, ns */

    /* state */
    bool have_seq;
    unsigned long last_line_seq;
    unsigned long last_global_seq;
    bool have_last;
    gb_edge_kind_t last_kind;
    uint64_t last_ts;
    bool have_pending; /* a rising edge waiting for its falling edge */
    uint64_t pending_ts;
    bool have_cand; /* a complete pulse waiting for the next rising edge */
    uint64_t cand_rise_ts;
    uint64_t cand_fall_ts;
    bool have_prev_rise; /* the last confirmed rising edge, no gap since */
    uint64_t prev_rise_ts;
    bool oom;
} gb_edges_t;

void gb_edges_init(gb_edges_t *e, int64_t glitch_ns);
void gb_edges_free(gb_edges_t *e);

/* One edge event as the kernel reported it. Returns 0, or -1 when out of
 * memory (e->oom is then set and later edges are only counted). */
int gb_edges_push(gb_edges_t *e, gb_edge_kind_t kind, uint64_t ts_ns, unsigned long global_seqno,
                  unsigned long line_seqno);

/* min / mean / max / rms of a set of samples (count 0: all zero). */
typedef struct {
    size_t count;
    int64_t min;
    int64_t max;
    double mean;
    double rms; /* sqrt(mean of squares): for jitter, its RMS */
} gb_stats_t;

gb_stats_t gb_stats_of(const int64_t *v, size_t n);

/* A histogram of samples in bins [lo + k w, lo + (k+1) w), lo a multiple of
 * w. With width_ns 0 the width is adaptive: 1 us, widened along 1-2-5 steps
 * until the samples span at most GB_HIST_MAX_BINS bins. */
#define GB_HIST_MAX_BINS 40
typedef struct {
    int64_t width_ns;
    int64_t lo_ns; /* left edge of bin 0 */
    size_t nbins;
    uint64_t count[GB_HIST_MAX_BINS];
} gb_hist_t;

/* Returns 0, or -1 when a given width_ns would need more than
 * GB_HIST_MAX_BINS bins (the histogram is then left empty). */
int gb_hist_build(gb_hist_t *h, const int64_t *v, size_t n, int64_t width_ns);

/* Everything the report shows. */
typedef struct {
    uint64_t edges, rising, falling;
    uint64_t lost_line, lost_global;
    uint64_t glitches, seq_errors, backwards;
    gb_stats_t duration;
    gb_stats_t period;
    bool jitter_vs_expected; /* reference: the expected period (else the mean) */
    int64_t jitter_ref_ns;   /* the reference period, ns (the mean rounded) */
    gb_stats_t jitter;       /* period - reference */
    gb_hist_t hist;          /* of the jitter */
    bool hist_ok;
} gb_summary_t;

/* The summary of what was pushed (the last complete pulse counts from
 * here on). expect_period_ns 0: jitter against the mean period (rounded to
 * 1 ns). bin_ns: as gb_hist_build. Returns 0, or -1 out of memory. */
int gb_edges_summarize(gb_edges_t *e, int64_t expect_period_ns, int64_t bin_ns, gb_summary_t *s);

#endif /* GB_EDGES_H */
