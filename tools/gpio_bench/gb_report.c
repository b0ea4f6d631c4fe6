/*
 * pmsm-gpio-bench: text and JSON reports, criteria.
 */
#include "gb_report.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BAR_WIDTH 50

bool gb_criteria_met(const gb_args_t *a, const gb_summary_t *s, char *why, size_t why_len)
{
    if (why != NULL && why_len > 0) {
        why[0] = '\0';
    }
    if (s->period.count == 0) {
        snprintf(why, why_len, "no ISR period measured (%" PRIu64 " edges seen)", s->edges);
        return false;
    }
    if (a->max_lost >= 0 && s->lost_line > (uint64_t)a->max_lost) {
        snprintf(why, why_len, "%" PRIu64 " edges lost (--max-lost %ld)", s->lost_line,
                 a->max_lost);
        return false;
    }
    if (a->max_jitter_ns >= 0) {
        const int64_t worst = (-s->jitter.min > s->jitter.max) ? -s->jitter.min : s->jitter.max;
        if (worst > a->max_jitter_ns) {
            snprintf(why, why_len, "jitter %.3f us exceeds --max-jitter-us %.3f",
                     (double)worst / 1e3, (double)a->max_jitter_ns / 1e3);
            return false;
        }
    }
    return true;
}

static double us(int64_t ns)
{
    return (double)ns / 1e3;
}

static void stats_line(FILE *out, const char *name, const gb_stats_t *st)
{
    if (st->count == 0) {
        fprintf(out, "%-15s: none\n", name);
        return;
    }
    fprintf(out, "%-15s: n %zu  min %.3f  mean %.3f  max %.3f us\n", name, st->count, us(st->min),
            st->mean / 1e3, us(st->max));
}

void gb_report_text(FILE *out, const gb_args_t *a, const gb_summary_t *s, double capture_s)
{
    fprintf(out, "pmsm-gpio-bench isr: %s line %u%s, %.3f s\n", a->chip, a->line,
            a->active_low ? " (active low)" : "", capture_s);
    fprintf(out, "%-15s: %" PRIu64 " (%" PRIu64 " rising, %" PRIu64 " falling)\n", "edges",
            s->edges, s->rising, s->falling);
    fprintf(out, "%-15s: %" PRIu64 " (line seqno gaps; global seqno gaps %" PRIu64 ")\n",
            "edges lost", s->lost_line, s->lost_global);
    fprintf(out, "%-15s: %" PRIu64 " (shorter than %" PRId64 " ns)\n", "glitches", s->glitches,
            a->glitch_ns);
    fprintf(out, "%-15s: %" PRIu64 " (same edge twice)", "sequence errs", s->seq_errors);
    if (s->backwards > 0) {
        fprintf(out, ", %" PRIu64 " timestamps went back", s->backwards);
    }
    fputc('\n', out);
    stats_line(out, "ISR duration", &s->duration);
    stats_line(out, "period", &s->period);
    if (s->jitter.count == 0) {
        fprintf(out, "%-15s: none\n", "jitter");
        return;
    }
    fprintf(out, "%-15s: vs %s %.3f us: min %+.3f  max %+.3f  rms %.3f us\n", "jitter",
            s->jitter_vs_expected ? "expected" : "mean", us(s->jitter_ref_ns), us(s->jitter.min),
            us(s->jitter.max), s->jitter.rms / 1e3);
    if (!s->hist_ok) {
        fprintf(out, "histogram: more than %d bins of %.3f us; choose a wider --bin-us\n",
                GB_HIST_MAX_BINS, us(s->hist.width_ns));
        return;
    }
    uint64_t peak = 0;
    for (size_t k = 0; k < s->hist.nbins; k++) {
        peak = (s->hist.count[k] > peak) ? s->hist.count[k] : peak;
    }
    fprintf(out, "jitter histogram (%.3f us bins):\n", us(s->hist.width_ns));
    for (size_t k = 0; k < s->hist.nbins; k++) {
        const int64_t lo = s->hist.lo_ns + (int64_t)k * s->hist.width_ns;
        const uint64_t c = s->hist.count[k];
        int bar = (peak > 0) ? (int)((c * BAR_WIDTH + peak - 1) / peak) : 0;
        fprintf(out, "  [%+9.3f, %+9.3f) us %10" PRIu64 "%s%.*s\n", us(lo),
                us(lo + s->hist.width_ns), c, (bar > 0) ? " " : "", bar,
                "##################################################");
    }
}

static void json_stats(FILE *f, const char *name, const gb_stats_t *st, bool rms, bool last)
{
    fprintf(f, "  \"%s\": {\"count\": %zu, \"min\": %" PRId64 ", \"mean\": %.3f, \"max\": %" PRId64,
            name, st->count, st->min, st->mean, st->max);
    if (rms) {
        fprintf(f, ", \"rms\": %.3f", st->rms);
    }
    fprintf(f, "}%s\n", last ? "" : ",");
}

/* A JSON string: quotes, backslashes and control characters escaped. */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p != '\0'; p++) {
        if (*p == '"' || *p == '\\') {
            fprintf(f, "\\%c", *p);
        } else if (*p < 0x20) {
            fprintf(f, "\\u%04x", *p);
        } else {
            fputc(*p, f);
        }
    }
    fputc('"', f);
}

int gb_report_json(const char *path, const gb_args_t *a, const gb_summary_t *s, double capture_s,
                   bool passed)
{
    const size_t len = strlen(path) + 5;
    char *tmp = malloc(len);
    if (tmp == NULL) {
        return -1;
    }
    snprintf(tmp, len, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (f == NULL) {
        const int e = errno;
        free(tmp);
        errno = e;
        return -1;
    }
    fprintf(f, "{\n  \"tool\": \"pmsm-gpio-bench\",\n  \"command\": \"isr\",\n  \"chip\": ");
    json_string(f, a->chip);
    fprintf(f, ",\n  \"line\": %u,\n  \"active_low\": %s,\n  \"seconds\": %.6f,\n", a->line,
            a->active_low ? "true" : "false", capture_s);
    fprintf(f, "  \"units\": \"ns\",\n");
    fprintf(f,
            "  \"edges\": {\"total\": %" PRIu64 ", \"rising\": %" PRIu64 ", \"falling\": %" PRIu64
            "},\n",
            s->edges, s->rising, s->falling);
    fprintf(f, "  \"lost\": {\"line_seqno\": %" PRIu64 ", \"global_seqno\": %" PRIu64 "},\n",
            s->lost_line, s->lost_global);
    fprintf(f,
            "  \"glitches\": %" PRIu64 ",\n  \"glitch_ns\": %" PRId64
            ",\n  \"sequence_errors\": %" PRIu64 ",\n  \"timestamps_back\": %" PRIu64 ",\n",
            s->glitches, a->glitch_ns, s->seq_errors, s->backwards);
    json_stats(f, "isr_duration", &s->duration, false, false);
    json_stats(f, "period", &s->period, false, false);
    fprintf(f, "  \"jitter_reference\": \"%s\",\n  \"jitter_reference_period\": %" PRId64 ",\n",
            s->jitter_vs_expected ? "expected" : "mean", s->jitter_ref_ns);
    json_stats(f, "jitter", &s->jitter, true, false);
    fprintf(f, "  \"histogram\": {\"bin\": %" PRId64 ", \"complete\": %s, \"bins\": [",
            s->hist.width_ns, s->hist_ok ? "true" : "false");
    for (size_t k = 0; k < s->hist.nbins; k++) {
        fprintf(f, "%s{\"lo\": %" PRId64 ", \"count\": %" PRIu64 "}", (k == 0) ? "" : ", ",
                s->hist.lo_ns + (int64_t)k * s->hist.width_ns, s->hist.count[k]);
    }
    fprintf(f, "]},\n  \"passed\": %s\n}\n", passed ? "true" : "false");

    const bool write_err = (ferror(f) != 0);
    const int close_rc = fclose(f);
    if (write_err || close_rc != 0 || rename(tmp, path) != 0) {
        const int e = (errno != 0) ? errno : EIO;
        remove(tmp);
        free(tmp);
        errno = e;
        return -1;
    }
    free(tmp);
    return 0;
}
