/* Top-level "time_offset_s": the reference, the load torque and the metric
 * windows are written in profile time tb; the run's simulated time is
 * t = tb + time_offset_s (paper 001's benchmark starts after the offset
 * calibration and the rotor alignment). Applied once, after every section
 * has been read. */
#include "scenario_sections.h"

/* Points, sines and the polynomial move by dt (they are defined relative
 * to their own times); the noise is stationary and stays as it is. */
static void shift_profile(sim_profile_t *p, double dt)
{
    for (uint32_t k = 0; k < p->n_points; k++) {
        p->points[k].t_s += dt;
    }
    for (uint32_t k = 0; k < p->n_sines; k++) {
        p->sines[k].t_start_s += dt;
    }
    p->poly.t_start_s += dt;
}

static void shift_metrics(scenario_metrics_t *m, double dt)
{
    m->step_t_s += dt;
    m->step_end_s += dt;
    m->steady_t0_s += dt;
    m->steady_t1_s += dt;
    m->tracking_t0_s += dt;
    m->tracking_t1_s += dt;
    for (size_t i = 0; i < m->n_load_steps; i++) {
        m->load_step_t_s[i] += dt;
    }
    for (size_t i = 0; i < m->n_windows; i++) {
        m->windows[i].t0_s += dt;
        m->windows[i].t1_s += dt;
    }
}

void scenario_apply_time_offset(scenario_t *s)
{
    const double dt = s->time_offset_s;
    if (dt == 0.0) {
        return;
    }
    shift_profile(&s->reference.value, dt);
    shift_profile(&s->reference.i_d_A, dt);
    shift_profile(&s->plant.load_torque_Nm, dt);
    shift_metrics(&s->metrics, dt);
}
