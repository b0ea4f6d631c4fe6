/*
 * plant_rk4.h - the classic RK4 step of the plant ODE (plant_derivatives),
 * shared by the event-locating integrator (plant.c) and the exact
 * integrator's fall-back substeps (plant_exact.c). Internal to sim_plant.
 */
#ifndef SIM_PLANT_RK4_H
#define SIM_PLANT_RK4_H

#include <stddef.h>

#include "plant_dynamics.h"

/* Classic RK4 step of length h from (t_s, x), in place, on the first n
 * state elements (n is a constant at both call sites). The profiles are
 * evaluated on the piece of the step's midpoint. */
static inline void plant_rk4_step_n(const plant_t *p, const plant_source_t *src, double t_s,
                                    double h, double x[PX_LEN], int n)
{
    double k1[PX_LEN], k2[PX_LEN], k3[PX_LEN], k4[PX_LEN], xs[PX_LEN];
    const double t_mid = t_s + 0.5 * h;
    plant_derivatives(p, src, t_s, t_mid, x, k1, NULL);
    for (int j = 0; j < n; ++j)
        xs[j] = x[j] + 0.5 * h * k1[j];
    plant_derivatives(p, src, t_mid, t_mid, xs, k2, NULL);
    for (int j = 0; j < n; ++j)
        xs[j] = x[j] + 0.5 * h * k2[j];
    plant_derivatives(p, src, t_mid, t_mid, xs, k3, NULL);
    for (int j = 0; j < n; ++j)
        xs[j] = x[j] + h * k3[j];
    plant_derivatives(p, src, t_s + h, t_mid, xs, k4, NULL);
    for (int j = 0; j < n; ++j) {
        x[j] += (h / 6.0) * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]);
    }
}

/* One RK4 step on the state elements in use (the link elements only with a
 * capacitance). */
static inline void plant_rk4_step(const plant_t *p, const plant_source_t *src, double t_s, double h,
                                  double x[PX_LEN])
{
    if (p->link_dynamic) {
        plant_rk4_step_n(p, src, t_s, h, x, PX_LEN);
    } else {
        plant_rk4_step_n(p, src, t_s, h, x, PX_STIFF_LEN);
    }
}

#endif /* SIM_PLANT_RK4_H */
