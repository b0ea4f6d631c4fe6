/*
 * pmsm-gpio-bench: the ISR summary as text and JSON, and the pass criteria
 * (pure: no GPIO).
 */
#ifndef GB_REPORT_H
#define GB_REPORT_H

#include "gb_args.h"
#include "gb_edges.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/* Whether the summary meets the criteria of the command line: at least one
 * period measured, lost edges <= --max-lost, |jitter| <= --max-jitter-us.
 * Returns true, or false with the first reason in why. */
bool gb_criteria_met(const gb_args_t *a, const gb_summary_t *s, char *why, size_t why_len);

/* The summary as text (README.md, "Example summary"). */
void gb_report_text(FILE *out, const gb_args_t *a, const gb_summary_t *s, double capture_s);

/* The summary as JSON to FILE: written to FILE.tmp, then renamed (never left
 * half written). Returns 0, or -1 with errno set. */
int gb_report_json(const char *path, const gb_args_t *a, const gb_summary_t *s, double capture_s,
                   bool passed);

#endif /* GB_REPORT_H */
