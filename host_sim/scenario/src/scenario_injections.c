/* Scenario section "fault_injections": timed faults handed to the engine
 * (sim_engine_add_injection). Each entry names its kind and only the keys
 * that kind uses:
 *   {"kind": "current_nan",    "phase": "a", "t_start_s": .., "t_end_s": ..}
 *   {"kind": "current_offset", "phase": "b", "offset_A": ..,  "t_start_s": ..}
 *   {"kind": "vdc_measured",   "v_dc_V": ..,  "t_start_s": ..}
 *   {"kind": "fault_input",    "t_start_s": ..}
 * t_end_s is optional (default: until the end of the run); an injection that
 * starts after the end of the run never becomes active. */
#include <math.h>
#include <stdio.h>

#include "scenario_sections.h"

/* Names in the order of sim_inject_kind_t. */
static const char *const kind_names[] = { "current_nan", "current_offset", "vdc_measured",
                                          "fault_input" };
static const char *const phase_names[] = { "a", "b", "c" };

#define N_NAMES(a) (sizeof(a) / sizeof((a)[0]))
#define TIME_RANGE JR_CLOSED(0.0, SCENARIO_MAX_DURATION_S)

static bool read_phase(jr_object_t *o, sim_injection_t *inj)
{
    size_t phase;
    if (!jr_enum(o, "phase", phase_names, N_NAMES(phase_names), &phase)) {
        return false;
    }
    inj->phase = (uint32_t)phase;
    return true;
}

static bool read_kind_keys(jr_object_t *o, sim_injection_t *inj)
{
    switch (inj->kind) {
    case SIM_INJECT_CURRENT_NAN: return read_phase(o, inj);
    case SIM_INJECT_CURRENT_OFFSET:
        return read_phase(o, inj) && jr_number(o, "offset_A", JR_CLOSED(-1e5, 1e5), &inj->value);
    case SIM_INJECT_VDC_MEASURED: return jr_number(o, "v_dc_V", JR_CLOSED(-1e5, 1e5), &inj->value);
    case SIM_INJECT_FAULT_INPUT: return true;
    }
    return false;
}

static bool read_injection(jr_array_t *arr, size_t i, sim_injection_t *inj)
{
    jr_object_t o;
    size_t kind;
    *inj = (sim_injection_t){ .t_end_s = INFINITY };
    if (!jr_array_object(arr, i, &o) ||
        !jr_enum(&o, "kind", kind_names, N_NAMES(kind_names), &kind)) {
        return false;
    }
    inj->kind = (sim_inject_kind_t)kind;
    if (!jr_number(&o, "t_start_s", TIME_RANGE, &inj->t_start_s) ||
        !jr_number_opt(&o, "t_end_s", TIME_RANGE, INFINITY, &inj->t_end_s) ||
        !read_kind_keys(&o, inj)) {
        return false;
    }
    if (inj->t_end_s < inj->t_start_s) {
        char found[32];
        snprintf(found, sizeof(found), "%g", inj->t_end_s);
        jr_fail(&o, "t_end_s", SCN_ERR_INVALID, "t_end_s >= t_start_s", found);
        return false;
    }
    return jr_finish(&o);
}

bool scenario_read_injections(jr_object_t *root, sim_injection_t *out, size_t *n_out)
{
    jr_array_t arr;
    *n_out = 0;
    if (!jr_array_opt(root, "fault_injections", 1, SIM_ENGINE_MAX_INJECTIONS, &arr)) {
        return false;
    }
    for (size_t i = 0; i < arr.size; i++) {
        if (!read_injection(&arr, i, &out[i])) {
            return false;
        }
    }
    *n_out = arr.size;
    return true;
}
