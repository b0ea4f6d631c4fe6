/* Scenario section "metrics": the windows in which the CLI evaluates the
 * paper metrics (sim/metrics.h). */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "scenario_sections.h"

#define TIME_RANGE JR_CLOSED(0.0, SCENARIO_MAX_DURATION_S)

/* Optional [t0_s, t1_s] with 0 <= t0 < t1. */
static bool read_window(jr_object_t *o, const char *key, bool *present, double *t0_s, double *t1_s)
{
    jr_array_t arr;
    if (!jr_array_opt(o, key, 2, 2, &arr)) {
        return false;
    }
    *present = arr.size == 2;
    if (!*present) {
        return true;
    }
    double t0;
    double t1;
    if (!jr_array_number(&arr, 0, TIME_RANGE, &t0) || !jr_array_number(&arr, 1, TIME_RANGE, &t1)) {
        return false;
    }
    if (!(t1 > t0)) {
        char found[64];
        snprintf(found, sizeof(found), "[%g, %g]", t0, t1);
        jr_fail(o, key, SCN_ERR_INVALID, "[t0, t1] with t0 < t1", found);
        return false;
    }
    *t0_s = t0;
    *t1_s = t1;
    return true;
}

/* [A-Za-z0-9_]+: usable as a JSON key and a file-name part. */
static bool valid_window_name(const char *name)
{
    if (name[0] == '\0') {
        return false;
    }
    for (const char *c = name; *c != '\0'; c++) {
        if (!isalnum((unsigned char)*c) && *c != '_') {
            return false;
        }
    }
    return true;
}

/* windows[i] = {"name": ..., "t_s": [t0, t1]}, names unique. */
static bool read_named_window(jr_array_t *arr, size_t i, scenario_metrics_t *m)
{
    jr_object_t w;
    bool present;
    scenario_window_t *win = &m->windows[i];
    if (!jr_array_object(arr, i, &w) ||
        !jr_string_opt(&w, "name", "", win->name, sizeof(win->name))) {
        return false;
    }
    if (!valid_window_name(win->name)) {
        jr_fail(&w, "name", win->name[0] == '\0' ? SCN_ERR_MISSING : SCN_ERR_INVALID,
                "a name of letters, digits and _ (1-31 chars)",
                win->name[0] == '\0' ? "none" : win->name);
        return false;
    }
    for (size_t j = 0; j < i; j++) {
        if (strcmp(m->windows[j].name, win->name) == 0) {
            jr_fail(&w, "name", SCN_ERR_INVALID, "a name no other window has", win->name);
            return false;
        }
    }
    if (!read_window(&w, "t_s", &present, &win->t0_s, &win->t1_s) || !jr_finish(&w)) {
        return false;
    }
    if (!present) {
        jr_fail(&w, "t_s", SCN_ERR_MISSING, "[t0, t1] with t0 < t1", "nothing");
        return false;
    }
    return true;
}

static bool read_named_windows(jr_object_t *o, scenario_metrics_t *m)
{
    jr_array_t arr;
    if (!jr_array_opt(o, "windows", 1, SCENARIO_MAX_WINDOWS, &arr)) {
        return false;
    }
    for (size_t i = 0; i < arr.size; i++) {
        if (!read_named_window(&arr, i, m)) {
            return false;
        }
    }
    m->n_windows = arr.size;
    return true;
}

static bool read_step(jr_object_t *o, double duration_s, scenario_metrics_t *m)
{
    jr_object_t step;
    double band_percent;
    if (!jr_object_opt(o, "step", &step) || step.json == NULL) {
        return jr_ok(o);
    }
    if (!jr_number(&step, "t_s", TIME_RANGE, &m->step_t_s) ||
        !jr_number(&step, "initial", JR_ANY_FINITE, &m->step_initial) ||
        !jr_number(&step, "final", JR_ANY_FINITE, &m->step_final) ||
        !jr_number_opt(&step, "t_end_s", TIME_RANGE, duration_s, &m->step_end_s) ||
        !jr_number_opt(&step, "band_percent", JR_POSITIVE(50.0), 2.0, &band_percent) ||
        !jr_finish(&step)) {
        return false;
    }
    if (!(m->step_end_s > m->step_t_s)) {
        char found[32];
        snprintf(found, sizeof(found), "%g", m->step_end_s);
        jr_fail(&step, "t_end_s", SCN_ERR_INVALID, "t_end_s > t_s", found);
        return false;
    }
    if (m->step_initial == m->step_final) {
        jr_fail(&step, "final", SCN_ERR_INVALID, "a value different from initial", "the same");
        return false;
    }
    m->has_step = true;
    m->settling_band = band_percent / 100.0;
    return true;
}

bool scenario_read_metrics(jr_object_t *root, double duration_s, scenario_metrics_t *m)
{
    jr_object_t o;
    jr_array_t steps;
    bool has_tracking;
    memset(m, 0, sizeof(*m));
    m->tracking_t1_s = duration_s;
    if (!jr_object_opt(root, "metrics", &o) || !read_step(&o, duration_s, m) ||
        !read_window(&o, "steady_window_s", &m->has_steady_window, &m->steady_t0_s,
                     &m->steady_t1_s) ||
        !read_window(&o, "tracking_window_s", &has_tracking, &m->tracking_t0_s,
                     &m->tracking_t1_s) ||
        !jr_array_opt(&o, "load_steps_s", 1, SCENARIO_MAX_LOAD_STEPS, &steps)) {
        return false;
    }
    for (size_t i = 0; i < steps.size; i++) {
        if (!jr_array_number(&steps, i, TIME_RANGE, &m->load_step_t_s[i])) {
            return false;
        }
    }
    m->n_load_steps = steps.size;
    return jr_number_opt(&o, "dip_window_s", JR_POSITIVE(1e3), 0.5, &m->dip_window_s) &&
           jr_number_opt(&o, "recovery_band", JR_CLOSED(0.0, 1e9), 0.0, &m->recovery_band) &&
           read_named_windows(&o, m) && jr_finish(&o);
}
