#include "shipped_scenario.h"

#include "mc_test.h"

#include <stdio.h>
#include <stdlib.h>

sim_engine_t *shipped_scenario_engine(const char *file, const char *const *set, size_t n_set,
                                      scenario_t *scn)
{
    char path[1024];
    (void)snprintf(path, sizeof path, "%s/%s", SCENARIOS_DIR, file);
    scn_error_t err;
    if (!scenario_load(path, set, n_set, scn, &err)) {
        char line[2048];
        scenario_error_format(&err, line, sizeof line);
        fail_msg("%s", line);
    }
    sim_engine_t *e = malloc(sizeof *e);
    assert_non_null(e);
    assert_int_equal(sim_engine_init(e, &scn->plant, &scn->firmware), SIM_ENGINE_OK);
    for (size_t i = 0; i < scn->n_injections; ++i) {
        assert_int_equal(sim_engine_add_injection(e, &scn->injections[i]), SIM_ENGINE_OK);
    }
    return e;
}
