/*
 * Readers of the scenario sections (private to sim_scenario). Each reads its
 * keys from the root object into the target struct, which holds the
 * defaults on entry, and returns false after the first error.
 */
#ifndef SIM_SCENARIO_SECTIONS_H
#define SIM_SCENARIO_SECTIONS_H

#include <stdbool.h>

#include "mc/app.h"
#include "plant.h"
#include "sim/json_reader.h"
#include "sim/scenario.h"

/* motor, inverter, sensors, disturbances, initial, solver -> plant config. */
bool scenario_read_plant(jr_object_t *root, plant_config_t *plant);

/* firmware -> firmware config; nominal motor values, PWM rate and encoder
 * resolution from the plant (the controller believes the nominal motor;
 * mismatch stays in the plant). */
bool scenario_read_firmware(jr_object_t *root, const plant_config_t *plant, mc_config_t *cfg);

/* reference -> mode and profile (SI). */
bool scenario_read_reference(jr_object_t *root, scenario_reference_t *ref);

/* metrics windows; duration_s gives the defaults (tracking window, step end). */
bool scenario_read_metrics(jr_object_t *root, double duration_s, scenario_metrics_t *metrics);

/* time_offset_s: shift the reference, the load torque and the metric
 * windows from profile time to simulated time (after all sections). */
void scenario_apply_time_offset(scenario_t *s);

/* The load torque and the bus voltage stay physically meaningful over the
 * whole run (scenario_bounds.c); after the time offset is applied. */
bool scenario_check_bounds(jr_object_t *root, const scenario_t *s);

/* fault_injections -> engine injections. */
bool scenario_read_injections(jr_object_t *root, sim_injection_t *out, size_t *n_out);

#endif /* SIM_SCENARIO_SECTIONS_H */
