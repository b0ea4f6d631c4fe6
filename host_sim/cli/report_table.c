/* The metrics table of a run (see report.h). */
#include <math.h>

#include "drive_names.h"
#include "report.h"

static void print_value(FILE *f, const char *label, double value, sim_metrics_status_t status,
                        const char *unit)
{
    if (status == SIM_METRICS_OK) {
        fprintf(f, "  %-32s %14.6g  %s\n", label, value, unit);
    } else {
        fprintf(f, "  %-32s %14s  (%s)\n", label, "n/a", sim_metrics_status_str(status));
    }
}

void report_print_table(FILE *f, const scenario_t *s, const run_result_t *res, const report_t *rep)
{
    fprintf(f, "scenario %s: %s control, %.3f s simulated in %.2f s wall (%llu PWM periods)\n",
            s->name, scenario_mode_name(s->reference.mode), res->sim_s, res->wall_s,
            (unsigned long long)res->periods);
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
    fprintf(f, "  %-32s %6.2f / %-6.2f  us (host CPU time)\n", "ISR cost mean / max",
            1e6 * res->isr_cost_mean_s, 1e6 * res->isr_cost_max_s);
    char faults[160];
    drive_faults_text(res->faults_latched, faults, sizeof(faults));
    if (isnan(res->first_fault_t_s)) {
        fprintf(f, "  %-32s %14s\n", "faults", faults);
    } else {
        fprintf(f, "  %-32s %s (first at %.6f s, final state %s)\n", "faults", faults,
                res->first_fault_t_s, drive_state_name(res->final_state));
    }
}
