/* The firmware keys of a scenario and the CSV trace columns (keys.h). */
#include "keys.h"

#include <string.h>

#include "mc/config.h"
#include "sim/scenario.h"
#include "trace_csv.h"

/* "name1 | name2 | ..." of a list parameter. */
static void print_names(FILE *f, mc_param_type_t type)
{
    const int n = type == MC_PARAM_CONTROLLER ? (int)MC_CONTROLLER_COUNT : (int)MC_ESTIMATOR_COUNT;
    for (int i = 0; i < n; i++) {
        fprintf(f, "%s%s", i > 0 ? " | " : "",
                type == MC_PARAM_CONTROLLER ? mc_controller_name((mc_controller_t)i)
                                            : mc_estimator_name((mc_estimator_t)i));
    }
}

static void print_field(FILE *f, const mc_param_block_t *b, const mc_param_t *p,
                        const mc_config_t *defaults)
{
    const unsigned char *at = (const unsigned char *)defaults + b->offset + p->offset;
    char key[96];
    snprintf(key, sizeof(key), "firmware.%s%s%s", b->name, b->name[0] != '\0' ? "." : "", p->name);
    fprintf(f, "  %-48s ", key);
    float f32;
    uint32_t u32;
    bool flag;
    mc_controller_t ctl;
    mc_estimator_t est;
    switch (p->type) {
    case MC_PARAM_F32:
        memcpy(&f32, at, sizeof f32);
        fprintf(f, "number   default %g\n", (double)f32);
        break;
    case MC_PARAM_U32:
        memcpy(&u32, at, sizeof u32);
        fprintf(f, "integer  default %u\n", (unsigned)u32);
        break;
    case MC_PARAM_BOOL:
        memcpy(&flag, at, sizeof flag);
        fprintf(f, "boolean  default %s\n", flag ? "true" : "false");
        break;
    case MC_PARAM_CONTROLLER:
        memcpy(&ctl, at, sizeof ctl);
        fputs("one of ", f);
        print_names(f, p->type);
        fprintf(f, "  default %s\n", mc_controller_name(ctl));
        break;
    case MC_PARAM_ESTIMATOR:
        memcpy(&est, at, sizeof est);
        fputs("one of ", f);
        print_names(f, p->type);
        fprintf(f, "  default %s\n", mc_estimator_name(est));
        break;
    }
}

void keys_print(FILE *f)
{
    mc_config_t defaults;
    mc_config_init_default(&defaults);
    fputs("Firmware keys of a scenario (\"firmware\" section; meaning, unit and range in the\n"
          "header of each block under firmware/include/mc; the nominal motor, the PWM rate\n"
          "and the encoder resolution come from the plant sections):\n",
          f);
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; b++) {
        for (const mc_param_t *p = b->params; p->name != NULL; p++) {
            if (!scenario_firmware_from_plant(b->name, p->name)) {
                print_field(f, b, p, &defaults);
            }
        }
    }
    fputs("\nColumns of the CSV trace (--csv):\n", f);
    for (size_t i = 0; i < trace_csv_column_count(); i++) {
        fprintf(f, "  %-20s %s\n", trace_csv_column_name(i), trace_csv_column_meaning(i));
    }
}
