/*
 * pmsm-gpio-bench: the commands (sto, isr) from a command line to an exit
 * code (gb_args.h).
 */
#ifndef GB_MAIN_H
#define GB_MAIN_H

#include "gb_args.h"
#include "gb_edges.h"

#include <stdio.h>

/* The whole tool: out gets the results, err the messages. */
int gb_main(int argc, char **argv, FILE *out, FILE *err);

/* isr: capture, summary into *s (text to out, JSON to a->json), criteria.
 * Returns an exit code. */
int gb_isr_run(const gb_args_t *a, gb_summary_t *s, FILE *out, FILE *err);

#endif /* GB_MAIN_H */
