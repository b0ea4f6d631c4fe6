/* Scenario section "metrics": the windows in which the CLI evaluates the
 * paper metrics (sim/metrics.h). */
#include <stdio.h>
#include <string.h>

#include "scenario_sections.h"

#define TIME_RANGE JR_CLOSED(0.0, SCENARIO_MAX_DURATION_S)

/* Optional [t0_s, t1_s] with 0 <= t0 < t1. */
static bool read_window(jr_object_t *o, const char *key, bool *present, double *t0_s,
                        double *t1_s)
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
    if (!jr_array_number(&arr, 0, TIME_RANGE, &t0) ||
        !jr_array_number(&arr, 1, TIME_RANGE, &t1)) {
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
        !jr_number_opt(&step, "t_end_s", TIME_RANGE, duration_s,
                       &m->step_end_s) ||
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
           jr_finish(&o);
}
