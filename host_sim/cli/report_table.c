/* The metrics table of a run (see report.h). */
#include <math.h>

#include "drive_names.h"
#include "report.h"
#include "sim/text_escape.h"

static void print_value(FILE *f, const char *label, double value, sim_metrics_status_t status,
                        const char *unit)
{
    if (status == SIM_METRICS_OK) {
        fprintf(f, "  %-32s %14.6g  %s\n", label, value, unit);
    } else {
        fprintf(f, "  %-32s %14s  (%s)\n", label, "n/a", sim_metrics_status_str(status));
    }
}

/* A peak of a phase; NaN when the plant state was not finite. */
static void print_peak(FILE *f, const char *label, double value, const char *unit)
{
    if (isfinite(value)) {
        fprintf(f, "  %-32s %14.6g  %s\n", label, value, unit);
    } else {
        fprintf(f, "  %-32s %14s  (%s)\n", label, "n/a", REPORT_NONFINITE_PEAK);
    }
}

/* Peaks by phase of the run, in simulated time (run_phases.h). */
static void print_phases(FILE *f, const run_result_t *res)
{
    fprintf(f, "  peaks by phase of the run (simulated time; true |i_abc|, |v_abc|):\n");
    for (int p = 0; p < RUN_PHASE_COUNT; p++) {
        const run_phase_stats_t *ph = &res->phases[p];
        char label[64];
        if (ph->samples == 0) {
            snprintf(label, sizeof(label), "  %s", run_phase_meaning((run_phase_t)p));
            fprintf(f, "  %-32s %14s\n", label, "not reached");
            continue;
        }
        fprintf(f, "    %s [%g, %g] s:\n", run_phase_meaning((run_phase_t)p), ph->t_first_s,
                ph->t_last_s);
        print_peak(f, "    peak phase current", ph->i_peak_A, "A");
        print_peak(f, "    peak phase voltage", ph->v_peak_V, "V");
    }
}

/* The latched faults; the first one's time in simulated time and, when the
 * scenario has a time offset, in profile time too. */
static void print_faults(FILE *f, const run_result_t *res, double time_offset_s)
{
    char faults[160];
    drive_faults_text(res->faults_latched, faults, sizeof(faults));
    if (isnan(res->first_fault_sim_s)) {
        fprintf(f, "  %-32s %14s\n", "faults", faults);
    } else if (time_offset_s == 0.0) {
        fprintf(f, "  %-32s %s (first at t = %.6f s, final state %s)\n", "faults", faults,
                res->first_fault_sim_s, drive_state_name(res->final_state));
    } else {
        fprintf(f,
                "  %-32s %s (first at simulated t = %.6f s = profile time %.6f s, final "
                "state %s)\n",
                "faults", faults, res->first_fault_sim_s, res->first_fault_sim_s - time_offset_s,
                drive_state_name(res->final_state));
    }
}

/* --realtime: the pacing and its missed periods (run.h). */
static void print_realtime(FILE *f, const run_result_t *res)
{
    fprintf(f, "  realtime: paced to wall time in batches of %u PWM periods; missed periods %llu\n",
            (unsigned)res->rt_batch_periods, (unsigned long long)res->missed_periods);
    fprintf(f, "            (reached over one period late; latest %.3f ms after its due time)\n",
            1e3 * res->max_late_s);
}

/* --can: the bridge's and the node's counts. */
static void print_can(FILE *f, const run_result_t *res)
{
    char ifname[4 * HAL_SOCKETCAN_IFNAME_MAX];
    text_escape(res->can_ifname, ifname, sizeof(ifname));
    const hal_socketcan_counters_t *l = &res->can_link;
    fprintf(f,
            "  CAN %s, node %u: %llu frames in, %llu out; lost: %llu (drive queue full), %llu "
            "(kernel), %llu out; %llu bus errors; %llu dropped at the start\n",
            ifname, (unsigned)res->can_node_id, (unsigned long long)l->rx,
            (unsigned long long)l->tx, (unsigned long long)l->rx_refused,
            (unsigned long long)l->rx_overflow_drops, (unsigned long long)l->tx_dropped,
            (unsigned long long)l->bus_errors, (unsigned long long)l->rx_flushed);
    const mc_can_counters_t *n = &res->can_node;
    uint32_t rejected = 0;
    for (unsigned c = 1; c < MC_CAN_REJ_COUNT; c++) {
        rejected += n->rejected[c];
    }
    fprintf(f,
            "  CAN node: %u frames taken, %u valid commands, %u rejected, %u sent, %u send "
            "drops, %u command timeouts\n",
            (unsigned)n->rx_frames, (unsigned)n->rx_accepted, (unsigned)rejected,
            (unsigned)n->tx_frames, (unsigned)n->tx_drops, (unsigned)n->timeouts);
}

void report_print_table(FILE *f, const scenario_t *s, const run_result_t *res, const report_t *rep)
{
    char name[4 * SCENARIO_NAME_MAX];
    text_escape(s->name, name, sizeof(name));
    if (res->can) {
        fprintf(f,
                "scenario %s: commands over CAN, %.3f s simulated in %.2f s wall (%llu PWM "
                "periods)\n",
                name, res->sim_s, res->wall_s, (unsigned long long)res->periods);
        fprintf(f, "  (no metrics against the scenario's reference: the drive did not get it)\n");
    } else {
        fprintf(f, "scenario %s: %s control, %.3f s simulated in %.2f s wall (%llu PWM periods)\n",
                name, scenario_mode_name(s->reference.mode), res->sim_s, res->wall_s,
                (unsigned long long)res->periods);
    }
    if (rep->time_offset_s != 0.0) {
        fprintf(f, "  (times below in profile time = simulated time - %g s)\n", rep->time_offset_s);
    }
    fprintf(f, "  %-32s %14s  %s\n", "metric", "value", "unit");
    for (size_t i = 0; i < rep->n_items; i++) {
        const report_item_t *it = &rep->items[i];
        print_value(f, it->label, it->value, it->status, it->unit);
    }
    for (size_t i = 0; i < rep->n_dips; i++) {
        char label[64];
        snprintf(label, sizeof(label), "max dip after load step %.3g s", rep->dips[i].t_s);
        print_value(f, label, rep->dips[i].max_dip, rep->dips[i].status, s->reference.display_unit);
        if (rep->dips[i].has_recovery) {
            snprintf(label, sizeof(label), "recovery time (+-%g %s)", s->metrics.recovery_band,
                     s->reference.display_unit);
            print_value(f, label, rep->dips[i].recovery_time_s, rep->dips[i].recovery_status, "s");
        }
    }
    for (size_t i = 0; i < rep->n_windows; i++) {
        const report_window_t *w = &rep->windows[i];
        fprintf(f, "  window %s [%g, %g] s:\n", w->name, w->t0_s, w->t1_s);
        for (size_t j = 0; j < w->n_items; j++) {
            char label[sizeof w->items[j].label + 2u];
            snprintf(label, sizeof(label), "  %s", w->items[j].label);
            print_value(f, label, w->items[j].value, w->items[j].status, w->items[j].unit);
        }
    }
    print_phases(f, res);
    fprintf(f, "  %-32s %6.2f / %-6.2f  us (host wall time)\n", "ISR cost mean / max",
            1e6 * res->isr_cost_mean_s, 1e6 * res->isr_cost_max_s);
    print_faults(f, res, rep->time_offset_s);
    if (res->realtime) {
        print_realtime(f, res);
    }
    if (res->can) {
        print_can(f, res);
    }
}
