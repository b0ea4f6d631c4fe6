/*
 * What a run will cost, stated before it starts: simulated time, PWM
 * periods, the wall time and the size of the CSV trace.
 *
 * The CSV size follows from the scenario (duration, PWM rate, trace
 * decimation) and the column set: rows times the bytes of a row with every
 * number at full precision (trace_csv_row_bytes()), an upper estimate.
 *
 * The wall time is measured, not modelled: what a PWM period costs depends
 * on the plant's integrator (the exact step or RK4 substeps, as the
 * model's features select: plant.h), the build and the machine. A run
 * longer than RUN_ESTIMATE_PILOT_PERIODS first runs that many periods of
 * the same scenario (same build, its CSV formatted into /dev/null) and
 * extrapolates their wall time per period to the whole run. The pilot
 * covers the start of the run (offset calibration, the first of the
 * alignment or of the profile), so a later phase of a different cost makes
 * the figure approximate; the progress lines of the run give the measured
 * rate as it goes.
 */
#ifndef PMSM_SIM_RUN_ESTIMATE_H
#define PMSM_SIM_RUN_ESTIMATE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "sim/scenario.h"

#define RUN_ESTIMATE_PILOT_PERIODS 10000u

/* A run is long, and its estimate printed, above either of these. */
#define RUN_ESTIMATE_LONG_WALL_S    60.0
#define RUN_ESTIMATE_LONG_CSV_BYTES 1e9

typedef struct {
    double sim_s;
    double f_pwm_Hz;
    uint64_t periods;
    uint64_t csv_rows; /* data rows; 0 without a trace */
    size_t csv_row_bytes;
    double csv_bytes;         /* header included */
    uint64_t pilot_periods;   /* 0: no pilot (the run is no longer than one) */
    double wall_per_period_s; /* measured on the pilot */
    double wall_s;            /* extrapolated; NAN without a pilot; with
                                 realtime at least sim_s */
    bool realtime;            /* paced to wall time (run_estimate_realtime) */
} run_estimate_t;

/* The estimate of s, with a CSV trace or without, with the metric series
 * kept (run) or not (bench), as the run will do. False with msg when the
 * pilot fails (the run would fail the same way). */
bool run_estimate(const scenario_t *s, bool with_csv, bool keep_series, run_estimate_t *e,
                  char *msg, size_t msg_size);

/* The run is paced to wall time: it takes the simulated time, or the
 * pilot's extrapolation when the machine is slower than real time. */
void run_estimate_realtime(run_estimate_t *e);

/* With a pilot: the wall time per PWM period over the period (above 1:
 * the machine simulates slower than real time); NAN without a pilot. */
double run_estimate_load(const run_estimate_t *e);

bool run_estimate_is_long(const run_estimate_t *e);

/* One paragraph on f: what the run simulates, its wall time, its CSV. */
void run_estimate_print(FILE *f, const run_estimate_t *e);

#endif /* PMSM_SIM_RUN_ESTIMATE_H */
