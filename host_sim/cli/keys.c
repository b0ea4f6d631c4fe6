/* The firmware keys of a scenario and the CSV trace columns (keys.h). */
#include "keys.h"

#include <string.h>

#include "mc/config.h"
#include "mc/encoder_tracker.h"
#include "mc/motor.h"
#include "mc/timing.h"
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

/* The plant keys whose range is the firmware's, from the same constants
 * the scenario reader checks them with (the other plant keys:
 * host_sim/scenarios/README.md). */
static void print_plant_ranges(FILE *f)
{
    fputs("\nPlant keys whose range is the firmware's (all plant keys: "
          "host_sim/scenarios/README.md):\n",
          f);
    fprintf(f, "  %-48s integer  1..%u (MC_MOTOR_POLE_PAIRS_MAX)\n", "motor.pole_pairs",
            (unsigned)MC_MOTOR_POLE_PAIRS_MAX);
    fprintf(f, "  %-48s number   [%g, %g] (MC_TIMING_F_PWM_MIN_HZ, MC_TIMING_F_PWM_MAX_HZ)\n",
            "inverter.f_pwm_Hz", (double)MC_TIMING_F_PWM_MIN_HZ, (double)MC_TIMING_F_PWM_MAX_HZ);
    fprintf(f,
            "  %-48s integer  %u..%u, or 0 (no encoder: sensorless estimators only); the\n"
            "  %-48s          firmware counts 4 x lines per revolution, at most\n"
            "  %-48s          MC_ENCODER_CPR_MAX = %u\n",
            "sensors.encoder.lines", (unsigned)SCENARIO_ENCODER_LINES_MIN,
            (unsigned)SCENARIO_ENCODER_LINES_MAX, "", "", (unsigned)MC_ENCODER_CPR_MAX);
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
    print_plant_ranges(f);
    fputs("\nColumns of the CSV trace (--csv):\n", f);
    for (size_t i = 0; i < trace_csv_column_count(); i++) {
        fprintf(f, "  %-20s %s\n", trace_csv_column_name(i), trace_csv_column_meaning(i));
    }
}
