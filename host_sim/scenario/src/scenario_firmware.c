/* Scenario section "firmware" -> firmware configuration (mc/config.h).
 * The keys are the firmware's own parameter table (mc_config_params():
 * "firmware.<block>.<field>", and "firmware.controller" /
 * "firmware.estimator" by the names of the firmware's lists); absent keys
 * keep the values of mc_config_init_default(). The values the plant
 * determines (the nominal motor, the PWM rate, the inverter's dead time and
 * device drop, the encoder resolution) come
 * from the plant sections (sim_engine_firmware_from_plant) and are not keys
 * here, nor is the telemetry rate the bench needs (every ISR's record). Ranges: the firmware's
 * validation is the one judge; a rejected configuration names the keys that can make it valid
 * (firmware_blame.h). */
#include <float.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "firmware_blame.h"
#include "scenario_sections.h"

#define MAX_BLOCKS 32
#define MAX_NAMES  16

bool scenario_firmware_from_plant(const char *block, const char *field)
{
    return strcmp(block, "motor") == 0 ||
           (strcmp(block, "timing") == 0 &&
            (strcmp(field, "f_pwm_Hz") == 0 || strcmp(field, "telemetry_every_isr") == 0)) ||
           (strcmp(block, "deadtime") == 0 &&
            (strcmp(field, "dead_time_s") == 0 || strcmp(field, "device_drop_V") == 0)) ||
           (strcmp(block, "encoder") == 0 && strcmp(field, "counts_per_rev") == 0);
}

/* The list names of an enum parameter. */
static size_t list_names(mc_param_type_t type, const char **names)
{
    size_t n = 0;
    if (type == MC_PARAM_CONTROLLER) {
        for (int i = 0; i < (int)MC_CONTROLLER_COUNT && n < MAX_NAMES; i++) {
            names[n++] = mc_controller_name((mc_controller_t)i);
        }
    } else {
        for (int i = 0; i < (int)MC_ESTIMATOR_COUNT && n < MAX_NAMES; i++) {
            names[n++] = mc_estimator_name((mc_estimator_t)i);
        }
    }
    return n;
}

static bool read_field(jr_object_t *o, const mc_param_t *p, unsigned char *field)
{
    union {
        float f32;
        uint32_t u32;
        bool flag;
        mc_controller_t controller;
        mc_estimator_t estimator;
    } v;
    memcpy(&v, field, mc_param_size(p->type));
    bool ok = false;
    double d = 0.0;
    size_t index = 0;
    const char *names[MAX_NAMES];
    switch (p->type) {
    case MC_PARAM_F32:
        ok = jr_number_opt(o, p->name, JR_CLOSED(-FLT_MAX, FLT_MAX), (double)v.f32, &d);
        v.f32 = (float)d;
        break;
    case MC_PARAM_U32: ok = jr_u32_opt(o, p->name, 0u, UINT32_MAX, v.u32, &v.u32); break;
    case MC_PARAM_BOOL: ok = jr_bool_opt(o, p->name, v.flag, &v.flag); break;
    case MC_PARAM_CONTROLLER:
        ok = jr_enum_opt(o, p->name, names, list_names(p->type, names), (size_t)v.controller,
                         &index);
        v.controller = (mc_controller_t)index;
        break;
    case MC_PARAM_ESTIMATOR:
        ok =
            jr_enum_opt(o, p->name, names, list_names(p->type, names), (size_t)v.estimator, &index);
        v.estimator = (mc_estimator_t)index;
        break;
    }
    if (ok) {
        memcpy(field, &v, mc_param_size(p->type));
    }
    return ok;
}

/* The fields of one block that the scenario sets. */
static bool read_block(jr_object_t *o, const mc_param_block_t *b, mc_config_t *cfg)
{
    unsigned char *base = (unsigned char *)cfg + b->offset;
    for (const mc_param_t *p = b->params; p->name != NULL; p++) {
        if (!scenario_firmware_from_plant(b->name, p->name) &&
            !read_field(o, p, base + p->offset)) {
            return false;
        }
    }
    return true;
}

/* An estimator that reads the encoder needs one: sensors.encoder.lines 0
 * (no encoder) is for the sensorless estimators. */
static bool encoder_present(jr_object_t *root, const plant_config_t *plant, const mc_config_t *cfg)
{
    if (plant->sensors.encoder.lines != 0u || mc_config_estimator_info(cfg).sensorless) {
        return true;
    }
    char expected[160];
    snprintf(expected, sizeof(expected),
             "%u..%u lines with firmware.estimator \"%s\", which reads the encoder (0, no "
             "encoder, is for a sensorless estimator)",
             (unsigned)SCENARIO_ENCODER_LINES_MIN, (unsigned)SCENARIO_ENCODER_LINES_MAX,
             mc_estimator_name(cfg->estimator));
    jr_fail(root, "sensors.encoder.lines", SCN_ERR_INVALID, expected, "0");
    return false;
}

bool scenario_read_firmware(jr_object_t *root, const plant_config_t *plant, mc_config_t *cfg)
{
    jr_object_t fw;
    jr_object_t objects[MAX_BLOCKS];
    sim_engine_firmware_from_plant(plant, cfg);
    if (!jr_object_opt(root, "firmware", &fw)) {
        return false;
    }
    size_t i = 0;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; b++, i++) {
        if (i >= MAX_BLOCKS) {
            jr_fail(&fw, b->name, SCN_ERR_INVALID, "at most 32 firmware blocks", "more");
            return false;
        }
        if (strcmp(b->name, "motor") == 0) {
            objects[i] = (jr_object_t){ .err = fw.err };
            continue;
        }
        jr_object_t *o = &objects[i];
        const bool top = (b->name[0] == '\0');
        if (top) {
            *o = fw;
        } else if (!jr_object_opt(&fw, b->name, o)) {
            return false;
        }
        if (!read_block(top ? &fw : o, b, cfg) || (!top && !jr_finish(o))) {
            return false;
        }
        if (top) {
            *o = fw;
        }
    }
    if (!jr_finish(&fw) || !encoder_present(root, plant, cfg)) {
        return false;
    }
    const mc_status_t st = mc_config_validate(cfg);
    if (st != MC_OK) {
        scenario_firmware_blame(&fw, objects, cfg, st);
        return false;
    }
    return true;
}
