/*
 * pmsm-gpio-bench: command-line parsing (pure: no GPIO, no global state).
 */
#include "gb_args.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char usage_text[] =
    "usage: pmsm-gpio-bench sto --line OFFSET [--chip PATH] [--active-low] [--hold S]\n"
    "                           (assert | release | pulse MS)\n"
    "       pmsm-gpio-bench isr --line OFFSET --seconds S [--chip PATH] [--active-low]\n"
    "                           [--expect-period-us P] [--json FILE] [--glitch-ns N]\n"
    "                           [--bin-us W] [--max-lost N] [--max-jitter-us J]\n"
    "       pmsm-gpio-bench --help\n"
    "\n"
    "sto: drive the drive's STO / fault input (asserted: the firmware latches\n"
    "     MC_FAULT_EXTERNAL). assert / release hold the level for --hold S seconds,\n"
    "     or until SIGINT / SIGTERM when --hold is 0 (the default); pulse MS asserts\n"
    "     for MS milliseconds, then releases and exits.\n"
    "isr: timestamp both edges of the ISR debug pin for S seconds (kernel edge\n"
    "     timestamps, monotonic ns); print ISR duration, period, jitter (against P,\n"
    "     or the mean period) with a histogram, edges, lost edges, glitches.\n"
    "\n"
    "  --chip PATH         GPIO chip (default " GB_DEFAULT_CHIP ")\n"
    "  --line OFFSET       line offset on the chip\n"
    "  --active-low        the line is active low (sto: asserted = low; isr: the\n"
    "                      ISR pulse is low)\n"
    "  --glitch-ns N       a pulse (high or low) shorter than N ns is a glitch\n"
    "                      (default 250)\n"
    "  --bin-us W          histogram bin width (default: 1 us, wider past 40 bins)\n"
    "  --max-lost N        fail (exit 1) when more than N edges were lost\n"
    "  --max-jitter-us J   fail (exit 1) when |jitter| exceeds J us\n"
    "\n"
    "exit codes: 0 ok, 1 measurement failed / criterion not met / GPIO error,\n"
    "            2 usage, 77 no GPIO chip on this machine\n";

const char *gb_args_usage(void)
{
    return usage_text;
}

static int fail(char *err, size_t err_len, const char *fmt, ...)
{
    if (err != NULL && err_len > 0) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, err_len, fmt, ap);
        va_end(ap);
    }
    return GB_EXIT_USAGE;
}

/* A finite decimal number in [lo, hi], the whole string. */
static bool parse_double(const char *s, double lo, double hi, double *out)
{
    if (s == NULL || *s == '\0') {
        return false;
    }
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if (errno != 0 || end == s || *end != '\0' || !isfinite(v) || v < lo || v > hi) {
        return false;
    }
    *out = v;
    return true;
}

/* A decimal integer in [lo, hi], the whole string. */
static bool parse_long(const char *s, long lo, long hi, long *out)
{
    if (s == NULL || *s == '\0') {
        return false;
    }
    char *end = NULL;
    errno = 0;
    const long v = strtol(s, &end, 10);
    if (errno != 0 || end == s || *end != '\0' || v < lo || v > hi) {
        return false;
    }
    *out = v;
    return true;
}

static void defaults(gb_args_t *a)
{
    memset(a, 0, sizeof(*a));
    a->cmd = GB_CMD_NONE;
    a->chip = GB_DEFAULT_CHIP;
    a->glitch_ns = GB_DEFAULT_GLITCH_NS;
    a->max_lost = -1;
    a->max_jitter_ns = -1;
}

int gb_args_parse(int argc, char **argv, gb_args_t *a, char *err, size_t err_len)
{
    defaults(a);
    if (err != NULL && err_len > 0) {
        err[0] = '\0';
    }
    if (argc < 2) {
        return fail(err, err_len, "a command is required (sto or isr)");
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0) {
        a->cmd = GB_CMD_HELP;
        return GB_EXIT_OK;
    }
    if (strcmp(cmd, "sto") == 0) {
        a->cmd = GB_CMD_STO;
    } else if (strcmp(cmd, "isr") == 0) {
        a->cmd = GB_CMD_ISR;
    } else {
        return fail(err, err_len, "unknown command '%s' (sto or isr)", cmd);
    }
    const bool sto = (a->cmd == GB_CMD_STO);

    bool have_line = false;
    bool have_seconds = false;
    bool have_action = false;
    for (int i = 2; i < argc; i++) {
        const char *opt = argv[i];
        const char *val = (i + 1 < argc) ? argv[i + 1] : NULL;
        double d = 0.0;
        long l = 0;
        if (strcmp(opt, "-h") == 0 || strcmp(opt, "--help") == 0) {
            a->cmd = GB_CMD_HELP;
            return GB_EXIT_OK;
        } else if (strcmp(opt, "--active-low") == 0) {
            a->active_low = true;
            continue;
        } else if (strcmp(opt, "--chip") == 0) {
            if (val == NULL || *val == '\0') {
                return fail(err, err_len, "--chip needs a path");
            }
            a->chip = val;
        } else if (strcmp(opt, "--line") == 0) {
            if (!parse_long(val, 0, 65535, &l)) {
                return fail(err, err_len, "--line needs an offset 0..65535");
            }
            a->line = (unsigned int)l;
            have_line = true;
        } else if (sto && strcmp(opt, "--hold") == 0) {
            if (!parse_double(val, 0.0, GB_MAX_HOLD_S, &d)) {
                return fail(err, err_len, "--hold needs seconds 0..%.0f", GB_MAX_HOLD_S);
            }
            a->hold_s = d;
        } else if (sto && (strcmp(opt, "assert") == 0 || strcmp(opt, "release") == 0 ||
                           strcmp(opt, "pulse") == 0)) {
            if (have_action) {
                return fail(err, err_len, "one action only (assert, release or pulse MS)");
            }
            have_action = true;
            if (strcmp(opt, "assert") == 0) {
                a->sto_action = GB_STO_ASSERT;
                continue;
            }
            if (strcmp(opt, "release") == 0) {
                a->sto_action = GB_STO_RELEASE;
                continue;
            }
            if (!parse_long(val, 1, GB_MAX_PULSE_MS, &l)) {
                return fail(err, err_len, "pulse needs a width MS 1..%ld", GB_MAX_PULSE_MS);
            }
            a->sto_action = GB_STO_PULSE;
            a->pulse_ms = l;
        } else if (!sto && strcmp(opt, "--seconds") == 0) {
            if (!parse_double(val, 1e-3, GB_MAX_SECONDS, &d)) {
                return fail(err, err_len, "--seconds needs a duration 0.001..%.0f", GB_MAX_SECONDS);
            }
            a->seconds = d;
            have_seconds = true;
        } else if (!sto && strcmp(opt, "--expect-period-us") == 0) {
            if (!parse_double(val, 1e-3, GB_MAX_EXPECT_PERIOD_US, &d)) {
                return fail(err, err_len, "--expect-period-us needs a period 0.001..%.0f",
                            GB_MAX_EXPECT_PERIOD_US);
            }
            a->expect_period_ns = llround(d * 1e3);
        } else if (!sto && strcmp(opt, "--json") == 0) {
            if (val == NULL || *val == '\0') {
                return fail(err, err_len, "--json needs a file name");
            }
            a->json = val;
        } else if (!sto && strcmp(opt, "--glitch-ns") == 0) {
            if (!parse_long(val, 0, 1000000000L, &l)) {
                return fail(err, err_len, "--glitch-ns needs ns 0..1000000000");
            }
            a->glitch_ns = l;
        } else if (!sto && strcmp(opt, "--bin-us") == 0) {
            if (!parse_double(val, 1e-3, 1e6, &d)) {
                return fail(err, err_len, "--bin-us needs a width 0.001..1000000");
            }
            a->bin_ns = llround(d * 1e3);
        } else if (!sto && strcmp(opt, "--max-lost") == 0) {
            if (!parse_long(val, 0, 1000000000L, &l)) {
                return fail(err, err_len, "--max-lost needs a count 0..1000000000");
            }
            a->max_lost = l;
        } else if (!sto && strcmp(opt, "--max-jitter-us") == 0) {
            if (!parse_double(val, 0.0, 1e6, &d)) {
                return fail(err, err_len, "--max-jitter-us needs us 0..1000000");
            }
            a->max_jitter_ns = llround(d * 1e3);
        } else {
            return fail(err, err_len, "%s: unknown argument '%s'", cmd, opt);
        }
        i++; /* the option's value */
    }
    if (!have_line) {
        return fail(err, err_len, "%s: --line OFFSET is required", cmd);
    }
    if (sto && !have_action) {
        return fail(err, err_len, "sto: an action is required (assert, release or pulse MS)");
    }
    if (sto && a->sto_action == GB_STO_PULSE && a->hold_s > 0.0) {
        return fail(err, err_len, "sto: --hold applies to assert and release, not pulse");
    }
    if (!sto && !have_seconds) {
        return fail(err, err_len, "isr: --seconds S is required");
    }
    return GB_EXIT_OK;
}
