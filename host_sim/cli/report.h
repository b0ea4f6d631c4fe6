/*
 * Metrics of a run (sim/metrics.h applied to the run's series in the
 * scenario's windows), printed as a table and written as JSON.
 *
 * Which metrics appear:
 *   metrics.step given          rise_time_s, settling_time_s, overshoot_percent
 *                               (samples from step.t_s to step.t_end_s)
 *   metrics.steady_window_s     offset_error_<u>, fluctuation_<u>,
 *                               fluctuation_rate_percent (paper 002, Sec. IV-A)
 *   always                      rms_tracking_error_<u> (metrics.tracking_window_s,
 *                               default the whole run), peak_phase_current_A,
 *                               peak_phase_voltage_V
 *   metrics.load_steps_s        one max_dip_<u> per load step
 * <u> is the reference's display unit: rpm, rad_s, rad or A.
 * A metric that cannot be computed is null in JSON, with the reason under
 * "unavailable" (for a load step: in its own "unavailable" member), and
 * "n/a (reason)" in the table.
 */
#ifndef PMSM_SIM_REPORT_H
#define PMSM_SIM_REPORT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "run.h"
#include "sim/metrics.h"
#include "sim/scenario.h"

#define REPORT_MAX_ITEMS 16
#define REPORT_KEY_MAX 48

typedef struct {
    char key[REPORT_KEY_MAX];   /* JSON key, unit in the name */
    char label[64];             /* table label */
    char unit[8];               /* table unit */
    double value;
    sim_metrics_status_t status; /* not OK: value unavailable */
} report_item_t;

typedef struct {
    double t_s;
    double max_dip;             /* display unit */
    double dip_time_s;
    sim_metrics_status_t status;
} report_dip_t;

typedef struct {
    report_item_t items[REPORT_MAX_ITEMS];
    size_t n_items;
    report_dip_t dips[SCENARIO_MAX_LOAD_STEPS];
    size_t n_dips;
} report_t;

void report_compute(const scenario_t *s, const run_result_t *res, report_t *rep);

void report_print_table(FILE *f, const scenario_t *s, const run_result_t *res,
                        const report_t *rep);

/* Write the JSON metrics file; false with msg on an I/O error. */
bool report_write_json(const char *file, const char *scenario_file, const scenario_t *s,
                       const run_result_t *res, const report_t *rep, char *msg,
                       size_t msg_size);

#endif /* PMSM_SIM_REPORT_H */
