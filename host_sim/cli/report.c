/* Metrics of a run (see report.h). */
#include "report.h"

#include <math.h>
#include <string.h>

report_item_t *report_add_item(report_item_t *items, size_t *n, const char *key,
                               const char *unit_suffix, const char *label, const char *unit)
{
    report_item_t *it = &items[(*n)++];
    if (unit_suffix != NULL) {
        snprintf(it->key, sizeof(it->key), "%s_%s", key, unit_suffix);
    } else {
        snprintf(it->key, sizeof(it->key), "%s", key);
    }
    snprintf(it->label, sizeof(it->label), "%s", label);
    snprintf(it->unit, sizeof(it->unit), "%s", unit);
    it->value = NAN;
    return it;
}

static report_item_t *add_item(report_t *rep, const char *key, const char *unit_suffix,
                               const char *label, const char *unit)
{
    return report_add_item(rep->items, &rep->n_items, key, unit_suffix, label, unit);
}

/* Step metrics on the samples up to metrics.step.t_end_s (later events such
 * as load steps do not count as overshoot or late settling). */
static void compute_step(const scenario_t *s, const sim_signal_t *whole, report_t *rep)
{
    const scenario_metrics_t *m = &s->metrics;
    sim_signal_t until_end = *whole;
    while (until_end.n > 0 && until_end.t[until_end.n - 1] > m->step_end_s) {
        until_end.n--;
    }
    const sim_signal_t *sig = &until_end;
    const sim_step_t step = { .t_step_s = m->step_t_s,
                              .y_initial = m->step_initial,
                              .y_final = m->step_final };
    report_item_t *it = add_item(rep, "rise_time_s", NULL, "rise time (10-90 %)", "s");
    it->status = sim_metrics_rise_time(sig, &step, &it->value);
    it = add_item(rep, "settling_time_s", NULL, "settling time", "s");
    it->status = sim_metrics_settling_time(sig, &step, m->settling_band, &it->value);
    it = add_item(rep, "overshoot_percent", NULL, "overshoot", "%");
    it->status = sim_metrics_overshoot(sig, &step, &it->value);
}

static void compute_steady(const scenario_t *s, const sim_signal_t *sig, const double *ref,
                           report_t *rep)
{
    const scenario_metrics_t *m = &s->metrics;
    const char *u = s->reference.display_unit;
    report_item_t *it = add_item(rep, "offset_error", u, "offset error (mean y - ref)", u);
    it->status = sim_metrics_offset_error(sig, ref, m->steady_t0_s, m->steady_t1_s, &it->value);
    report_item_t *fl = add_item(rep, "fluctuation", u, "fluctuation (max - min)/2", u);
    fl->status = sim_metrics_fluctuation(sig, m->steady_t0_s, m->steady_t1_s, &fl->value, NULL);
    report_item_t *rate = add_item(rep, "fluctuation_rate_percent", NULL, "fluctuation rate", "%");
    rate->status = sim_metrics_fluctuation(sig, m->steady_t0_s, m->steady_t1_s, NULL, &rate->value);
}

void report_compute(const scenario_t *s, const run_result_t *res, report_t *rep)
{
    const run_series_t *ser = &res->series;
    const scenario_metrics_t *m = &s->metrics;
    const char *u = s->reference.display_unit;
    const sim_signal_t y = { .t = ser->t_s, .y = ser->y, .n = ser->n };
    memset(rep, 0, sizeof(*rep));
    rep->time_offset_s = s->time_offset_s;
    if (res->can) {
        return; /* the commands came over CAN, not from the reference */
    }

    if (m->has_step) {
        compute_step(s, &y, rep);
    }
    if (m->has_steady_window) {
        compute_steady(s, &y, ser->ref, rep);
    }
    report_item_t *it = add_item(rep, "rms_tracking_error", u, "RMS tracking error", u);
    it->status =
        sim_metrics_rms_error(&y, ser->ref, m->tracking_t0_s, m->tracking_t1_s, &it->value);

    for (size_t i = 0; i < m->n_load_steps; i++) {
        report_dip_t *d = &rep->dips[rep->n_dips++];
        d->t_s = m->load_step_t_s[i] - s->time_offset_s;
        d->max_dip = NAN;
        d->dip_time_s = NAN;
        d->status = sim_metrics_max_dip(&y, ser->ref, m->load_step_t_s[i], m->dip_window_s,
                                        &d->max_dip, &d->dip_time_s);
        d->dip_time_s -= s->time_offset_s;
        d->has_recovery = m->recovery_band > 0.0;
        d->recovery_time_s = NAN;
        if (d->has_recovery) {
            d->recovery_status =
                sim_metrics_recovery_time(&y, ser->ref, m->load_step_t_s[i], m->dip_window_s,
                                          m->recovery_band, &d->recovery_time_s, NULL);
        }
    }
    report_compute_windows(s, ser, rep);
}
