/*
 * pmsm-gpio-bench: edge pairing, statistics and histogram (pure C).
 */
#include "gb_edges.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int samples_push(gb_samples_t *s, int64_t v)
{
    if (s->n == s->cap) {
        const size_t cap = (s->cap == 0) ? 1024 : 2 * s->cap;
        int64_t *nv = realloc(s->v, cap * sizeof(*nv));
        if (nv == NULL) {
            return -1;
        }
        s->v = nv;
        s->cap = cap;
    }
    s->v[s->n++] = v;
    return 0;
}

void gb_edges_init(gb_edges_t *e, int64_t glitch_ns)
{
    memset(e, 0, sizeof(*e));
    e->glitch_ns = (glitch_ns > 0) ? glitch_ns : 0;
}

void gb_edges_free(gb_edges_t *e)
{
    free(e->durations.v);
    free(e->periods.v);
    memset(&e->durations, 0, sizeof(e->durations));
    memset(&e->periods, 0, sizeof(e->periods));
}

/* The complete pulse (cand) counts: its duration, and the period from the
 * previous counted rising edge when nothing was lost in between. */
static int commit_candidate(gb_edges_t *e)
{
    e->have_cand = false;
    if (e->oom) {
        return -1;
    }
    if (samples_push(&e->durations, (int64_t)(e->cand_fall_ts - e->cand_rise_ts)) != 0) {
        e->oom = true;
        return -1;
    }
    if (e->have_prev_rise &&
        samples_push(&e->periods, (int64_t)(e->cand_rise_ts - e->prev_rise_ts)) != 0) {
        e->oom = true;
        return -1;
    }
    e->prev_rise_ts = e->cand_rise_ts;
    e->have_prev_rise = true;
    return 0;
}

/* Nothing measured across this point. */
static void break_chain(gb_edges_t *e)
{
    e->have_pending = false;
    e->have_cand = false;
    e->have_prev_rise = false;
}

static bool seq_gap(unsigned long seq, bool have, unsigned long last, uint64_t *lost)
{
    const unsigned long expected = have ? last + 1ul : 1ul; /* the kernel counts from 1 */
    if (seq > expected) {
        *lost += seq - expected;
        return true;
    }
    return have && seq < expected; /* went back: a gap of unknown size */
}

int gb_edges_push(gb_edges_t *e, gb_edge_kind_t kind, uint64_t ts_ns, unsigned long global_seqno,
                  unsigned long line_seqno)
{
    e->edges++;
    if (kind == GB_EDGE_RISING) {
        e->rising++;
    } else {
        e->falling++;
    }

    bool gap = seq_gap(line_seqno, e->have_seq, e->last_line_seq, &e->lost_line);
    gap = seq_gap(global_seqno, e->have_seq, e->last_global_seq, &e->lost_global) || gap;
    e->have_seq = true;
    e->last_line_seq = line_seqno;
    e->last_global_seq = global_seqno;
    if (e->have_last && ts_ns < e->last_ts) {
        e->backwards++;
        gap = true;
    }
    if (gap) {
        break_chain(e);
        e->have_last = false;
    }

    int rc = 0;
    if (kind == GB_EDGE_RISING) {
        if (e->have_last && e->last_kind == GB_EDGE_RISING) {
            e->seq_errors++; /* a falling edge missed */
            break_chain(e);
        }
        if (e->have_cand && (int64_t)(ts_ns - e->cand_fall_ts) < e->glitch_ns) {
            /* a low glitch inside a pulse: the pulse goes on */
            e->glitches++;
            e->have_cand = false;
            e->have_pending = true;
            e->pending_ts = e->cand_rise_ts;
        } else {
            if (e->have_cand) {
                rc = commit_candidate(e);
            }
            e->have_pending = true;
            e->pending_ts = ts_ns;
        }
    } else {
        if (e->have_last && e->last_kind == GB_EDGE_FALLING) {
            e->seq_errors++; /* a rising edge missed */
            break_chain(e);
        }
        if (e->have_pending) {
            if ((int64_t)(ts_ns - e->pending_ts) < e->glitch_ns) {
                e->glitches++; /* a high glitch: not a pulse, not a period start */
            } else {
                e->have_cand = true;
                e->cand_rise_ts = e->pending_ts;
                e->cand_fall_ts = ts_ns;
            }
            e->have_pending = false;
        }
    }
    e->have_last = true;
    e->last_kind = kind;
    e->last_ts = ts_ns;
    return (rc != 0 || e->oom) ? -1 : 0;
}

gb_stats_t gb_stats_of(const int64_t *v, size_t n)
{
    gb_stats_t s;
    memset(&s, 0, sizeof(s));
    if (n == 0) {
        return s;
    }
    int64_t sum = 0;
    long double sq = 0.0L;
    s.min = v[0];
    s.max = v[0];
    for (size_t i = 0; i < n; i++) {
        s.min = (v[i] < s.min) ? v[i] : s.min;
        s.max = (v[i] > s.max) ? v[i] : s.max;
        sum += v[i];
        sq += (long double)v[i] * (long double)v[i];
    }
    s.count = n;
    s.mean = (double)sum / (double)n;
    s.rms = (double)sqrtl(sq / (long double)n);
    return s;
}

static int64_t floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    if ((a % b != 0) && ((a < 0) != (b < 0))) {
        q--;
    }
    return q;
}

int gb_hist_build(gb_hist_t *h, const int64_t *v, size_t n, int64_t width_ns)
{
    memset(h, 0, sizeof(*h));
    if (n == 0) {
        h->width_ns = (width_ns > 0) ? width_ns : 1000;
        return 0;
    }
    const gb_stats_t s = gb_stats_of(v, n);
    int64_t w = width_ns;
    if (w <= 0) {
        static const int64_t steps[3] = { 1, 2, 5 };
        int64_t decade = 1000;
        for (int k = 0;; k = (k + 1) % 3) {
            w = steps[k] * decade;
            if (floor_div(s.max, w) - floor_div(s.min, w) + 1 <= GB_HIST_MAX_BINS) {
                break;
            }
            if (k == 2) {
                decade *= 10;
            }
        }
    }
    h->width_ns = w;
    const int64_t k0 = floor_div(s.min, w);
    const int64_t nb = floor_div(s.max, w) - k0 + 1;
    if (nb > GB_HIST_MAX_BINS) {
        return -1;
    }
    h->lo_ns = k0 * w;
    h->nbins = (size_t)nb;
    for (size_t i = 0; i < n; i++) {
        h->count[floor_div(v[i], w) - k0]++;
    }
    return 0;
}

int gb_edges_summarize(gb_edges_t *e, int64_t expect_period_ns, int64_t bin_ns, gb_summary_t *s)
{
    memset(s, 0, sizeof(*s));
    if (e->have_cand) {
        (void)commit_candidate(e); /* the last pulse: no low glitch can follow now */
    }
    s->edges = e->edges;
    s->rising = e->rising;
    s->falling = e->falling;
    s->lost_line = e->lost_line;
    s->lost_global = e->lost_global;
    s->glitches = e->glitches;
    s->seq_errors = e->seq_errors;
    s->backwards = e->backwards;
    s->duration = gb_stats_of(e->durations.v, e->durations.n);
    s->period = gb_stats_of(e->periods.v, e->periods.n);
    s->jitter_vs_expected = (expect_period_ns > 0);
    s->jitter_ref_ns = s->jitter_vs_expected ? expect_period_ns : llround(s->period.mean);

    const size_t n = e->periods.n;
    int64_t *j = NULL;
    if (n > 0) {
        j = malloc(n * sizeof(*j));
        if (j == NULL) {
            return -1;
        }
        for (size_t i = 0; i < n; i++) {
            j[i] = e->periods.v[i] - s->jitter_ref_ns;
        }
    }
    s->jitter = gb_stats_of(j, n);
    s->hist_ok = (gb_hist_build(&s->hist, j, n, bin_ns) == 0);
    free(j);
    return e->oom ? -1 : 0;
}
