/* The JSON metrics file of a run (see report.h). */
#include <math.h>
#include <stdlib.h>

#include <cjson/cJSON.h>

#include "drive_names.h"
#include "report.h"

#include "hal_host.h"

/* value, or null when unavailable (the reason goes to `unavailable`). */
static void add_metric(cJSON *metrics, cJSON *unavailable, const char *key, double value,
                       sim_metrics_status_t status)
{
    if (status == SIM_METRICS_OK) {
        cJSON_AddNumberToObject(metrics, key, value);
    } else {
        cJSON_AddNullToObject(metrics, key);
        cJSON_AddStringToObject(unavailable, key, sim_metrics_status_str(status));
    }
}

/* "windows": {name: {t0_s, t1_s, <metrics>, unavailable}} (profile time). */
static void add_windows(cJSON *root, const report_t *rep)
{
    cJSON *windows = cJSON_AddObjectToObject(root, "windows");
    for (size_t i = 0; i < rep->n_windows; i++) {
        const report_window_t *w = &rep->windows[i];
        cJSON *o = cJSON_AddObjectToObject(windows, w->name);
        cJSON_AddNumberToObject(o, "t0_s", w->t0_s);
        cJSON_AddNumberToObject(o, "t1_s", w->t1_s);
        cJSON *unavailable = cJSON_CreateObject();
        for (size_t j = 0; j < w->n_items; j++) {
            add_metric(o, unavailable, w->items[j].key, w->items[j].value, w->items[j].status);
        }
        cJSON_AddItemToObject(o, "unavailable", unavailable);
    }
}

/* A phase peak, or null with the reason under `unavailable`. */
static void add_peak(cJSON *o, cJSON *unavailable, const char *key, double value)
{
    if (isfinite(value)) {
        cJSON_AddNumberToObject(o, key, value);
    } else {
        cJSON_AddNullToObject(o, key);
        cJSON_AddStringToObject(unavailable, key, REPORT_NONFINITE_PEAK);
    }
}

/* "phases": {start, hold, profile, fault}: peaks by phase of the run (run_phases.h),
 * in simulated time; null for a phase the run never reached. */
static void add_phases(cJSON *root, const run_result_t *res)
{
    cJSON *phases = cJSON_AddObjectToObject(root, "phases");
    for (int p = 0; p < RUN_PHASE_COUNT; p++) {
        const run_phase_stats_t *ph = &res->phases[p];
        const char *name = run_phase_name((run_phase_t)p);
        if (ph->samples == 0) {
            cJSON_AddNullToObject(phases, name);
            continue;
        }
        cJSON *o = cJSON_AddObjectToObject(phases, name);
        cJSON_AddNumberToObject(o, "from_sim_time_s", ph->t_first_s);
        cJSON_AddNumberToObject(o, "to_sim_time_s", ph->t_last_s);
        cJSON *unavailable = cJSON_CreateObject();
        add_peak(o, unavailable, "peak_phase_current_A", ph->i_peak_A);
        add_peak(o, unavailable, "peak_phase_voltage_V", ph->v_peak_V);
        cJSON_AddItemToObject(o, "unavailable", unavailable);
    }
}

/* "faults": the latched bits and names, the first fault's time in both
 * time bases, the final state. */
static void add_faults(cJSON *root, const run_result_t *res, double time_offset_s)
{
    cJSON *faults = cJSON_AddObjectToObject(root, "faults");
    cJSON_AddNumberToObject(faults, "latched_bits", (double)res->faults_latched);
    cJSON *latched = cJSON_AddArrayToObject(faults, "latched");
    for (size_t i = 0; i < drive_fault_count(); i++) {
        uint32_t bit;
        const char *name = drive_fault_name(i, &bit);
        if (res->faults_latched & bit) {
            cJSON_AddItemToArray(latched, cJSON_CreateString(name));
        }
    }
    if (isnan(res->first_fault_sim_s)) {
        cJSON_AddNullToObject(faults, "first_fault_sim_time_s");
        cJSON_AddNullToObject(faults, "first_fault_profile_time_s");
    } else {
        cJSON_AddNumberToObject(faults, "first_fault_sim_time_s", res->first_fault_sim_s);
        cJSON_AddNumberToObject(faults, "first_fault_profile_time_s",
                                res->first_fault_sim_s - time_offset_s);
    }
    cJSON_AddStringToObject(faults, "final_state", drive_state_name(res->final_state));
}

/* "realtime": {batch_periods, missed_periods, max_late_s}, null without. */
static void add_realtime(cJSON *root, const run_result_t *res)
{
    if (!res->realtime) {
        cJSON_AddNullToObject(root, "realtime");
        return;
    }
    cJSON *rt = cJSON_AddObjectToObject(root, "realtime");
    cJSON_AddNumberToObject(rt, "batch_periods", (double)res->rt_batch_periods);
    cJSON_AddNumberToObject(rt, "missed_periods", (double)res->missed_periods);
    cJSON_AddNumberToObject(rt, "max_late_s", res->max_late_s);
}

/* "can": {interface, node_id, link, node}, null without --can. */
static void add_can(cJSON *root, const run_result_t *res)
{
    if (!res->can) {
        cJSON_AddNullToObject(root, "can");
        return;
    }
    static const char *const causes[MC_CAN_REJ_COUNT] = { NULL,
                                                          "unknown_message",
                                                          "wrong_dlc",
                                                          "bad_value",
                                                          "refused_state",
                                                          "unknown_param",
                                                          "wrong_param_type" };
    cJSON *can = cJSON_AddObjectToObject(root, "can");
    cJSON_AddStringToObject(can, "interface", res->can_ifname);
    cJSON_AddNumberToObject(can, "node_id", (double)res->can_node_id);
    const hal_socketcan_counters_t *l = &res->can_link;
    cJSON *link = cJSON_AddObjectToObject(can, "link");
    cJSON_AddNumberToObject(link, "rx", (double)l->rx);
    cJSON_AddNumberToObject(link, "rx_refused", (double)l->rx_refused);
    cJSON_AddNumberToObject(link, "rx_flushed", (double)l->rx_flushed);
    cJSON_AddNumberToObject(link, "rx_overflow_drops", (double)l->rx_overflow_drops);
    cJSON_AddNumberToObject(link, "bus_errors", (double)l->bus_errors);
    cJSON_AddNumberToObject(link, "tx", (double)l->tx);
    cJSON_AddNumberToObject(link, "tx_dropped", (double)l->tx_dropped);
    const mc_can_counters_t *n = &res->can_node;
    cJSON *node = cJSON_AddObjectToObject(can, "node");
    cJSON_AddNumberToObject(node, "rx_frames", (double)n->rx_frames);
    cJSON_AddNumberToObject(node, "rx_accepted", (double)n->rx_accepted);
    cJSON *rejected = cJSON_AddObjectToObject(node, "rejected");
    for (unsigned c = 1; c < MC_CAN_REJ_COUNT; c++) {
        cJSON_AddNumberToObject(rejected, causes[c], (double)n->rejected[c]);
    }
    cJSON_AddNumberToObject(node, "tx_frames", (double)n->tx_frames);
    cJSON_AddNumberToObject(node, "tx_drops", (double)n->tx_drops);
    cJSON_AddNumberToObject(node, "timeouts", (double)n->timeouts);
}

static cJSON *build_json(const char *scenario_file, const scenario_t *s, const run_result_t *res,
                         const report_t *rep)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "scenario", s->name);
    cJSON_AddStringToObject(root, "scenario_file", scenario_file);
    cJSON_AddStringToObject(root, "mode", scenario_mode_name(s->reference.mode));
    cJSON_AddStringToObject(root, "command_source", res->can ? "can" : "scenario");
    cJSON_AddStringToObject(root, "display_unit", s->reference.display_unit);
    cJSON_AddNumberToObject(root, "duration_s", res->sim_s);
    cJSON_AddNumberToObject(root, "pwm_periods", (double)res->periods);
    cJSON_AddNumberToObject(root, "wall_time_s", res->wall_s);
    cJSON_AddNumberToObject(root, "time_offset_s", rep->time_offset_s);

    cJSON *metrics = cJSON_AddObjectToObject(root, "metrics");
    cJSON *unavailable = cJSON_AddObjectToObject(root, "unavailable");
    for (size_t i = 0; i < rep->n_items; i++) {
        const report_item_t *it = &rep->items[i];
        add_metric(metrics, unavailable, it->key, it->value, it->status);
    }
    cJSON *dips = cJSON_AddArrayToObject(root, "load_steps");
    char dip_key[REPORT_KEY_MAX];
    snprintf(dip_key, sizeof(dip_key), "max_dip_%s", s->reference.display_unit);
    for (size_t i = 0; i < rep->n_dips; i++) {
        const report_dip_t *dip = &rep->dips[i];
        cJSON *d = cJSON_CreateObject();
        cJSON_AddNumberToObject(d, "t_s", dip->t_s);
        if (dip->status == SIM_METRICS_OK) {
            cJSON_AddNumberToObject(d, dip_key, dip->max_dip);
            cJSON_AddNumberToObject(d, "dip_time_s", dip->dip_time_s);
        } else {
            cJSON_AddNullToObject(d, dip_key);
            cJSON_AddStringToObject(d, "unavailable", sim_metrics_status_str(dip->status));
        }
        if (dip->has_recovery) {
            if (dip->recovery_status == SIM_METRICS_OK) {
                cJSON_AddNumberToObject(d, "recovery_time_s", dip->recovery_time_s);
            } else {
                cJSON_AddNullToObject(d, "recovery_time_s");
                cJSON_AddStringToObject(d, "recovery_unavailable",
                                        sim_metrics_status_str(dip->recovery_status));
            }
        }
        cJSON_AddItemToArray(dips, d);
    }

    add_windows(root, rep);

    cJSON *isr = cJSON_AddObjectToObject(root, "isr_cost");
    cJSON_AddNumberToObject(isr, "mean_s", res->isr_cost_mean_s);
    cJSON_AddNumberToObject(isr, "max_s", res->isr_cost_max_s);
    cJSON_AddStringToObject(isr, "method", hal_host_cycle_counter_method());

    add_phases(root, res);
    add_faults(root, res, rep->time_offset_s);
    add_realtime(root, res);
    add_can(root, res);
    return root;
}

bool report_write_json(const char *file, const char *scenario_file, const scenario_t *s,
                       const run_result_t *res, const report_t *rep, char *msg, size_t msg_size)
{
    cJSON *root = build_json(scenario_file, s, res, rep);
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    FILE *f = text != NULL ? fopen(file, "w") : NULL;
    bool ok = f != NULL && fputs(text, f) >= 0 && fputc('\n', f) != EOF;
    if (f != NULL && fclose(f) != 0) {
        ok = false;
    }
    free(text);
    if (!ok) {
        snprintf(msg, msg_size, "cannot write the JSON metrics file %.1000s", file);
    }
    return ok;
}
