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
 *                               default the whole run)
 *   metrics.load_steps_s        one max_dip_<u> per load step, and with
 *                               metrics.recovery_band its recovery_time_s
 *   metrics.windows             per named window: rms_error_<u>,
 *                               max_abs_error_<u>, max_abs_<mode>_<u> (|y|:
 *                               the zero-speed report), rms_angle_error_e_rad,
 *                               max_angle_error_e_rad (controller theta_e vs
 *                               the true one, wrapped) and, with the
 *                               sensorless angle source (which estimates the
 *                               load), rms_load_estimate_error_Nm and
 *                               max_load_estimate_error_Nm (vs the true load)
 *   always, by phase of the run the peak phase current and voltage (true
 *   |i_abc|, |v_abc|) of the start (calibration, alignment), the hold
 *   before the profile, the run under the profile and after a fault
 *   (run_phases.h); JSON "phases": {start, hold, profile, fault}, each with
 *   from_sim_time_s, to_sim_time_s (its first and last sample),
 *   peak_phase_current_A, peak_phase_voltage_V, or null when the run never
 *   reached it
 * <u> is the reference's display unit: rpm, rad_s, rad or A. Times (load
 * steps, windows, dip times) are reported in profile time, t - time_offset_s,
 * as the scenario writes them. Where a time could be read either way its
 * name says which: the phases in simulated time (*_sim_time_s), the first
 * fault in both (faults.first_fault_sim_time_s and
 * faults.first_fault_profile_time_s; the table prints both when they
 * differ).
 * A metric that cannot be computed is null in JSON, with the reason under
 * "unavailable" (for a load step: in its own "unavailable" member), and
 * "n/a (reason)" in the table.
 * A run with --can (the commands came over CAN, not from the reference)
 * has none of the metrics against the reference (no items, load steps or
 * windows: the table says so, JSON "command_source": "can" and empty
 * "metrics", "load_steps", "windows"); its phases, ISR cost and faults are
 * reported, and its CAN counts: JSON "can": {interface, node_id, link
 * (the bridge's hal_socketcan_counters_t), node (mc_can_counters_t)},
 * null without --can. --realtime adds JSON "realtime": {batch_periods,
 * missed_periods, max_late_s} (run.h), null without it; the table has a
 * line for each.
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
/* Why a phase peak is unavailable (table and JSON). */
#define REPORT_NONFINITE_PEAK "non-finite: the plant state diverged"
#define REPORT_KEY_MAX        48

typedef struct {
    char key[REPORT_KEY_MAX]; /* JSON key, unit in the name */
    char label[64];           /* table label */
    char unit[8];             /* table unit */
    double value;
    sim_metrics_status_t status; /* not OK: value unavailable */
} report_item_t;

typedef struct {
    double t_s;
    double max_dip; /* display unit */
    double dip_time_s;
    sim_metrics_status_t status;
    bool has_recovery; /* metrics.recovery_band > 0 */
    double recovery_time_s;
    sim_metrics_status_t recovery_status;
} report_dip_t;

#define REPORT_WINDOW_ITEMS 8

typedef struct {
    char name[SCENARIO_WINDOW_NAME_MAX];
    double t0_s, t1_s; /* profile time */
    report_item_t items[REPORT_WINDOW_ITEMS];
    size_t n_items;
} report_window_t;

typedef struct {
    double time_offset_s; /* profile time = simulated time - this */
    report_item_t items[REPORT_MAX_ITEMS];
    size_t n_items;
    report_dip_t dips[SCENARIO_MAX_LOAD_STEPS];
    size_t n_dips;
    report_window_t windows[SCENARIO_MAX_WINDOWS];
    size_t n_windows;
} report_t;

/* Append an item (value NAN) to items[*n] and return it; key gets "_<suffix>"
 * unless unit_suffix is NULL. The caller guarantees the room. */
report_item_t *report_add_item(report_item_t *items, size_t *n, const char *key,
                               const char *unit_suffix, const char *label, const char *unit);

/* The metrics.windows part of report_compute(). */
void report_compute_windows(const scenario_t *s, const run_series_t *ser, report_t *rep);

void report_compute(const scenario_t *s, const run_result_t *res, report_t *rep);

void report_print_table(FILE *f, const scenario_t *s, const run_result_t *res, const report_t *rep);

/* Write the JSON metrics file; false with msg on an I/O error. */
bool report_write_json(const char *file, const char *scenario_file, const scenario_t *s,
                       const run_result_t *res, const report_t *rep, char *msg, size_t msg_size);

#endif /* PMSM_SIM_REPORT_H */
