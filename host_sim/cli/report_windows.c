/* Windowed metrics of a run (metrics.windows, see report.h): tracking, the
 * controller's angle error and the load-torque estimate error per window. */
#include <stdio.h>

#include "report.h"

static void tracking(const scenario_t *s, const run_series_t *ser, double t0, double t1,
                     report_window_t *w)
{
    const char *u = s->reference.display_unit;
    const char *mode = scenario_mode_name(s->reference.mode);
    const sim_signal_t y = { .t = ser->t_s, .y = ser->y, .n = ser->n };
    char key[REPORT_KEY_MAX];
    char label[64];
    report_item_t *it =
        report_add_item(w->items, &w->n_items, "rms_error", u, "RMS tracking error", u);
    it->status = sim_metrics_rms_error(&y, ser->ref, t0, t1, &it->value);
    it = report_add_item(w->items, &w->n_items, "max_abs_error", u, "max |y - ref|", u);
    it->status = sim_metrics_max_dip(&y, ser->ref, t0, t1 - t0, &it->value, NULL);
    snprintf(key, sizeof(key), "max_abs_%s", mode);
    snprintf(label, sizeof(label), "max |%s|", mode);
    it = report_add_item(w->items, &w->n_items, key, u, label, u);
    it->status = sim_metrics_peak_abs(&y, t0, t1, &it->value);
}

static void angle(const run_series_t *ser, double t0, double t1, report_window_t *w)
{
    const sim_signal_t e = { .t = ser->t_s, .y = ser->angle_err_e_rad, .n = ser->n };
    report_item_t *it = report_add_item(w->items, &w->n_items, "rms_angle_error_e_rad", NULL,
                                        "RMS angle error (electrical)", "rad");
    it->status = sim_metrics_rms_error(&e, ser->zero, t0, t1, &it->value);
    it = report_add_item(w->items, &w->n_items, "max_angle_error_e_rad", NULL,
                         "max |angle error| (electrical)", "rad");
    it->status = sim_metrics_peak_abs(&e, t0, t1, &it->value);
}

static void load_estimate(const run_series_t *ser, double t0, double t1, report_window_t *w)
{
    const sim_signal_t hat = { .t = ser->t_s, .y = ser->tau_load_hat_Nm, .n = ser->n };
    report_item_t *it = report_add_item(w->items, &w->n_items, "rms_load_estimate_error_Nm", NULL,
                                        "RMS load estimate error", "N m");
    it->status = sim_metrics_rms_error(&hat, ser->tau_load_Nm, t0, t1, &it->value);
    it = report_add_item(w->items, &w->n_items, "max_load_estimate_error_Nm", NULL,
                         "max |load estimate error|", "N m");
    it->status = sim_metrics_max_dip(&hat, ser->tau_load_Nm, t0, t1 - t0, &it->value, NULL);
}

void report_compute_windows(const scenario_t *s, const run_series_t *ser, report_t *rep)
{
    const bool has_load_estimate = mc_config_estimator_info(&s->firmware).provides_load;
    for (size_t i = 0; i < s->metrics.n_windows; i++) {
        const scenario_window_t *sw = &s->metrics.windows[i];
        report_window_t *w = &rep->windows[rep->n_windows++];
        snprintf(w->name, sizeof(w->name), "%s", sw->name);
        w->t0_s = sw->t0_s - s->time_offset_s;
        w->t1_s = sw->t1_s - s->time_offset_s;
        tracking(s, ser, sw->t0_s, sw->t1_s, w);
        angle(ser, sw->t0_s, sw->t1_s, w);
        if (has_load_estimate) {
            load_estimate(ser, sw->t0_s, sw->t1_s, w);
        }
    }
}
