/*
 * CSV trace of a closed-loop run, one row per recorded PWM period. The
 * columns (name, meaning, unit in the name) are the table in trace_csv.c,
 * the one place they are defined: the header row and every data row are
 * written from it, and the plot (tools/plot_trace.py) reads columns by
 * name. "True" values are the plant state; the others are what the
 * firmware sees or commands.
 */
#ifndef PMSM_SIM_TRACE_CSV_H
#define PMSM_SIM_TRACE_CSV_H

#include <stddef.h>
#include <stdio.h>

#include "sim_engine.h"

/* The header row: the column names separated by commas. */
void trace_csv_header(FILE *f);

/* One data row of the sample. */
void trace_csv_row(FILE *f, const sim_trace_sample_t *smp);

/* The bytes of a data row formatted like trace_csv_row() with every number
 * at its full precision (-1.333...) and every integer column (state,
 * faults, outputs_on) one digit wide: the size estimate of a trace. */
size_t trace_csv_row_bytes(void);

/* Column i (i < trace_csv_column_count()): its name and meaning. */
size_t trace_csv_column_count(void);
const char *trace_csv_column_name(size_t i);
const char *trace_csv_column_meaning(size_t i);

#endif /* PMSM_SIM_TRACE_CSV_H */
