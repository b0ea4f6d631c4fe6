/*
 * Closed-loop tests on a shipped scenario file (host_sim/scenarios): load
 * it with --set-style overrides and build its engine, failing the calling
 * test with the loader's message when the file is rejected.
 */
#ifndef SIM_SHIPPED_SCENARIO_H
#define SIM_SHIPPED_SCENARIO_H

#include <stddef.h>

#include "sim/scenario.h"
#include "sim_engine.h"

/* Loads host_sim/scenarios/<file> with the overrides set[0 .. n_set-1]
 * into *scn and returns an engine (malloc, the caller frees it) on its
 * plant and firmware with its fault injections added. */
sim_engine_t *shipped_scenario_engine(const char *file, const char *const *set, size_t n_set,
                                      scenario_t *scn);

#endif /* SIM_SHIPPED_SCENARIO_H */
