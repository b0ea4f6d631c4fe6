/* pmsm-sim keys: the scenario's firmware keys and the trace columns, from
 * the tables they are defined by (mc_config_params(), trace_csv.c). */
#ifndef PMSM_SIM_KEYS_H
#define PMSM_SIM_KEYS_H

#include <stdio.h>

void keys_print(FILE *f);

#endif /* PMSM_SIM_KEYS_H */
