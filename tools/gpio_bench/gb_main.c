/*
 * pmsm-gpio-bench: command dispatch, the isr summary and its criteria.
 */
#include "gb_main.h"

#include "gb_gpio.h"
#include "gb_report.h"

#include <errno.h>
#include <string.h>

int gb_isr_run(const gb_args_t *a, gb_summary_t *s, FILE *out, FILE *err)
{
    memset(s, 0, sizeof(*s));
    gb_edges_t e;
    gb_edges_init(&e, a->glitch_ns);
    double capture_s = 0.0;
    int code = gb_gpio_isr_capture(a, &e, &capture_s, err);
    if (code == GB_EXIT_OK && gb_edges_summarize(&e, a->expect_period_ns, a->bin_ns, s) != 0) {
        fprintf(err, "pmsm-gpio-bench: out of memory for the summary\n");
        code = GB_EXIT_FAIL;
    }
    gb_edges_free(&e);
    if (code != GB_EXIT_OK) {
        return code;
    }
    char why[160];
    const bool passed = gb_criteria_met(a, s, why, sizeof(why));
    gb_report_text(out, a, s, capture_s);
    if (a->json != NULL && gb_report_json(a->json, a, s, capture_s, passed) != 0) {
        fprintf(err, "pmsm-gpio-bench: cannot write %s: %s\n", a->json, strerror(errno));
        return GB_EXIT_FAIL;
    }
    if (!passed) {
        fprintf(out, "result: FAIL: %s\n", why);
        return GB_EXIT_FAIL;
    }
    fprintf(out, "result: ok\n");
    return GB_EXIT_OK;
}

int gb_main(int argc, char **argv, FILE *out, FILE *err)
{
    gb_args_t a;
    char why[160];
    if (gb_args_parse(argc, argv, &a, why, sizeof(why)) != GB_EXIT_OK) {
        fprintf(err, "pmsm-gpio-bench: %s\n%s", why, gb_args_usage());
        return GB_EXIT_USAGE;
    }
    switch (a.cmd) {
    case GB_CMD_HELP: fputs(gb_args_usage(), out); return GB_EXIT_OK;
    case GB_CMD_STO: return gb_gpio_sto(&a, out, err);
    case GB_CMD_ISR: {
        gb_summary_t s;
        return gb_isr_run(&a, &s, out, err);
    }
    case GB_CMD_NONE: break;
    }
    return GB_EXIT_USAGE;
}
