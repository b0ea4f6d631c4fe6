/*
 * plant_exact.h - the exact (exponential) integrator of the switching plant
 * (solver method PLANT_SOLVER_EXACT; the method, where it applies and its
 * error bound are in plant.h, "Integrators"). Internal to sim_plant.
 */
#ifndef SIM_PLANT_EXACT_H
#define SIM_PLANT_EXACT_H

#include <stdbool.h>
#include <stdint.h>

#include "plant.h"
#include "plant_inverter.h"

/* The constants of p->exact for p's substep h_s and motor (after the
 * motor constants and h_s of plant_init are set). */
void plant_exact_init(plant_t *p);

/* True when the substeps under src may use the exact step: the method is
 * selected, the motor is non-salient, the inverter switches (outputs on)
 * with every phase driven, and the bus is stiff. */
bool plant_exact_applies(const plant_t *p, const plant_source_t *src);

/* Substeps j0 .. j1 - 1 of the current period (from p->t_s) under src, for
 * which plant_exact_applies() holds. A substep in which a phase current
 * enters or leaves the dead-time model's linear zone (or crosses zero with
 * the hard sign) is integrated by RK4 instead. */
void plant_exact_substeps(plant_t *p, const plant_source_t *src, uint32_t j0, uint32_t j1);

#endif /* SIM_PLANT_EXACT_H */
