/*
 * pmsm-gpio-bench: the one file that talks to libgpiod (v2 API). Everything
 * it measures goes to gb_edges; the unit tests replace libgpiod here by a
 * fake through link-time wrapping (tests/unit/tools/gpio_bench).
 */
#ifndef GB_GPIO_H
#define GB_GPIO_H

#include "gb_args.h"
#include "gb_edges.h"

#include <stdio.h>

/* sto: drive the STO / fault input line as a->sto_action says. Returns an
 * exit code (gb_args.h); messages to out / err. */
int gb_gpio_sto(const gb_args_t *a, FILE *out, FILE *err);

/* isr: push every edge of the line for a->seconds (or until SIGINT /
 * SIGTERM) into e; *capture_s is the time captured. Returns an exit code;
 * messages to err. */
int gb_gpio_isr_capture(const gb_args_t *a, gb_edges_t *e, double *capture_s, FILE *err);

#endif /* GB_GPIO_H */
