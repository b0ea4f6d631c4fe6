/* Scenario section "firmware" -> firmware configuration (mc/config.h).
 * The keys are the firmware's own parameter table (mc_config_params():
 * "firmware.<block>.<field>", and "firmware.controller" /
 * "firmware.estimator" by the names of the firmware's lists); absent keys
 * keep the values of mc_config_init_default(). The values the plant
 * determines (the nominal motor, the PWM rate, the encoder resolution) come
 * from the plant sections (sim_engine_firmware_from_plant) and are not keys
 * here. Ranges: the firmware's validation is the one judge; a rejected
 * configuration names the key whose default would make it valid. */
#include <float.h>
#include <stddef.h>
#include <string.h>

#include "scenario_sections.h"

#define MAX_BLOCKS 32
#define MAX_NAMES  16

bool scenario_firmware_from_plant(const char *block, const char *field)
{
    return strcmp(block, "motor") == 0 ||
           (strcmp(block, "timing") == 0 && strcmp(field, "f_pwm_Hz") == 0) ||
           (strcmp(block, "encoder") == 0 && strcmp(field, "counts_per_rev") == 0);
}

static size_t field_size(mc_param_type_t type)
{
    switch (type) {
    case MC_PARAM_F32: return sizeof(float);
    case MC_PARAM_U32: return sizeof(uint32_t);
    case MC_PARAM_BOOL: return sizeof(bool);
    case MC_PARAM_CONTROLLER: return sizeof(mc_controller_t);
    case MC_PARAM_ESTIMATOR: return sizeof(mc_estimator_t);
    }
    return 0;
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
    memcpy(&v, field, field_size(p->type));
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
        memcpy(field, &v, field_size(p->type));
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

/* The first given key of block b whose firmware default makes cfg valid. */
static const char *blame_in_block(jr_object_t *o, const mc_param_block_t *b, const mc_config_t *cfg,
                                  const mc_config_t *defaults)
{
    for (const mc_param_t *p = b->params; p->name != NULL; p++) {
        if (scenario_firmware_from_plant(b->name, p->name) || jr_peek(o, p->name) == NULL) {
            continue;
        }
        mc_config_t trial = *cfg;
        const size_t at = b->offset + p->offset;
        memcpy((unsigned char *)&trial + at, (const unsigned char *)defaults + at,
               field_size(p->type));
        if (mc_config_validate(&trial) == MC_OK) {
            return p->name;
        }
    }
    return NULL;
}

/* The first given key whose firmware default makes cfg valid; its block
 * object in *where. The selection (controller, estimator: the top-level
 * block) is tried last: choosing another controller or estimator switches
 * off the checks of the selected one's blocks, so it would "fix" any value
 * those blocks reject and hide the key that is really wrong. */
static const char *blame(jr_object_t *objects, const mc_config_t *cfg, jr_object_t **where)
{
    mc_config_t defaults;
    mc_config_init_default(&defaults);
    const mc_param_block_t *top = NULL;
    jr_object_t *top_object = NULL;
    size_t i = 0;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL && i < MAX_BLOCKS;
         b++, i++) {
        if (b->name[0] == '\0') {
            top = b;
            top_object = &objects[i];
            continue;
        }
        if (strcmp(b->name, "motor") == 0) {
            continue;
        }
        const char *key = blame_in_block(&objects[i], b, cfg, &defaults);
        if (key != NULL) {
            *where = &objects[i];
            return key;
        }
    }
    if (top == NULL) {
        return NULL;
    }
    *where = top_object;
    return blame_in_block(top_object, top, cfg, &defaults);
}

/* mc_config_validate() rejected cfg: name the key if one alone is the cause. */
static void report_rejected(jr_object_t *fw, jr_object_t *objects, const mc_config_t *cfg,
                            mc_status_t st)
{
    const char *expected =
        "a configuration mc_config_validate() accepts (each block's ranges in its header "
        "under firmware/include/mc, loop bandwidths stable at the sampling rate, limits "
        "consistent with the motor, the PWM rate and each other)";
    const char *found = st == MC_ERR_NONFINITE ? "a non-finite value" : "a rejected value";
    jr_object_t *where = NULL;
    const char *key = blame(objects, cfg, &where);
    if (key != NULL) {
        jr_fail(where, key, SCN_ERR_INVALID, expected, found);
        return;
    }
    scenario_error_set(fw->err, SCN_ERR_INVALID, fw->path, expected,
                       "a rejected combination of motor, inverter, encoder and firmware "
                       "values");
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
    if (!jr_finish(&fw)) {
        return false;
    }
    const mc_status_t st = mc_config_validate(cfg);
    if (st != MC_OK) {
        report_rejected(&fw, objects, cfg, st);
        return false;
    }
    return true;
}
