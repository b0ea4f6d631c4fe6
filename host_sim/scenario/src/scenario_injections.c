/* Scenario section "fault_injections": timed faults handed to the engine
 * (sim_engine_add_injection). Each entry names its kind and only the keys
 * that kind uses:
 *   {"kind": "current_nan",         "phase": "a", "t_start_s": .., "t_end_s": ..}
 *   {"kind": "current_offset",      "phase": "b", "offset_A": .., "t_start_s": ..}
 *   {"kind": "vdc_measured",        "v_dc_V": .., "t_start_s": ..}
 *   {"kind": "fault_input",         "t_start_s": ..}
 *   {"kind": "encoder_slip",        "angle_e_rad": .., "t_start_s": ..}
 *   {"kind": "encoder_frozen",      "t_start_s": ..}
 *   {"kind": "encoder_count_loss",  "lost_fraction": .., "t_start_s": ..}
 *   {"kind": "current_offset_ramp", "phase": "a", "rate_A_s": .., "t_start_s": ..}
 *   {"kind": "current_stuck",       "phase": "c", "value_A": .., "t_start_s": ..}
 *   {"kind": "phase_open",          "phase": "a", "t_start_s": ..}
 *   {"kind": "rotor_lock",          "t_start_s": ..}
 *   {"kind": "bus_source_loss",     "t_start_s": ..}
 *   {"kind": "current_gain",        "phase": "a", "gain": .., "t_start_s": ..}
 *   {"kind": "dead_time",           "dead_time_s": .., "t_start_s": ..}
 * (the meaning of each kind: sim_inject_kind_t in sim_engine.h).
 * t_end_s is optional (default: until the end of the run); an injection that
 * starts after the end of the run never becomes active. */
#include <math.h>
#include <stdio.h>

#include "scenario_sections.h"

/* Names in the order of sim_inject_kind_t. */
static const char *const kind_names[] = {
    "current_nan",    "current_offset",     "vdc_measured",        "fault_input",   "encoder_slip",
    "encoder_frozen", "encoder_count_loss", "current_offset_ramp", "current_stuck", "phase_open",
    "rotor_lock",     "bus_source_loss",    "current_gain",        "dead_time"
};
static const char *const phase_names[] = { "a", "b", "c" };

#define N_NAMES(a)  (sizeof(a) / sizeof((a)[0]))
#define TIME_RANGE  JR_CLOSED(0.0, SCENARIO_MAX_DURATION_S)
#define VALUE_RANGE JR_CLOSED(-1e5, 1e5) /* A or V */

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
    case SIM_INJECT_CURRENT_NAN:
    case SIM_INJECT_PHASE_OPEN: return read_phase(o, inj);
    case SIM_INJECT_CURRENT_OFFSET:
        return read_phase(o, inj) && jr_number(o, "offset_A", VALUE_RANGE, &inj->value);
    case SIM_INJECT_VDC_MEASURED: return jr_number(o, "v_dc_V", VALUE_RANGE, &inj->value);
    case SIM_INJECT_FAULT_INPUT:
    case SIM_INJECT_ENCODER_FROZEN:
    case SIM_INJECT_ROTOR_LOCK:
    case SIM_INJECT_BUS_SOURCE_LOSS: return true;
    case SIM_INJECT_ENCODER_SLIP:
        return jr_number(o, "angle_e_rad", JR_CLOSED(-1e3, 1e3), &inj->angle_e_rad);
    case SIM_INJECT_ENCODER_COUNT_LOSS:
        return jr_number(o, "lost_fraction", ((jr_range_t){ 0.0, 1.0, true, true }),
                         &inj->lost_fraction);
    case SIM_INJECT_CURRENT_OFFSET_RAMP:
        return read_phase(o, inj) && jr_number(o, "rate_A_s", JR_CLOSED(-1e6, 1e6), &inj->rate_A_s);
    case SIM_INJECT_CURRENT_STUCK:
        return read_phase(o, inj) && jr_number(o, "value_A", VALUE_RANGE, &inj->value);
    case SIM_INJECT_CURRENT_GAIN: /* the range of sensors.current.gain */
        return read_phase(o, inj) && jr_number(o, "gain", JR_POSITIVE(10.0), &inj->value);
    case SIM_INJECT_DEAD_TIME: /* the range of inverter.dead_time_s */
        return jr_number(o, "dead_time_s", JR_CLOSED(0.0, 1e-4), &inj->value);
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
