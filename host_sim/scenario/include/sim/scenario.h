/*
 * A validated simulation scenario: plant configuration, firmware
 * configuration, reference, fault injections, metric windows and output
 * options, read from a
 * JSON document (format: host_sim/scenarios/README.md).
 *
 * All values are SI inside the structs. The reference may be written in rpm
 * ("speed_rpm"); it is converted to rad/s here and the metrics are reported
 * in the unit the scenario used (reference.display_unit).
 */
#ifndef SIM_SCENARIO_H
#define SIM_SCENARIO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cjson/cJSON.h>

#include "mc/app.h"
#include "mc/encoder_tracker.h"
#include "plant.h"
#include "profile.h"
#include "sim/scenario_error.h"
#include "sim_engine.h"

#define SCENARIO_FORMAT_VERSION  2
#define SCENARIO_NAME_MAX        64
#define SCENARIO_DESCRIPTION_MAX 1024
#define SCENARIO_MAX_DURATION_S  36000.0
#define SCENARIO_MAX_LOAD_STEPS  8
#define SCENARIO_MAX_WINDOWS     8
#define SCENARIO_WINDOW_NAME_MAX 32

/* sensors.encoder.lines: the firmware counts 4 x lines per revolution (x4
 * quadrature) within [MC_ENCODER_CPR_MIN, MC_ENCODER_CPR_MAX] (1 to
 * 2,097,152 lines); 0 is no encoder, for a sensorless estimator only.
 * README and `pmsm-sim keys` state this range from these constants. */
#define SCENARIO_ENCODER_LINES_MIN ((MC_ENCODER_CPR_MIN + 3u) / 4u)
#define SCENARIO_ENCODER_LINES_MAX (MC_ENCODER_CPR_MAX / 4u)

typedef struct {
    mc_mode_t mode;
    sim_profile_t value;      /* omega_m_ref [rad/s], theta_m_ref [rad] or i_q_ref [A] */
    sim_profile_t i_d_A;      /* MC_MODE_CURRENT: d-axis reference; else 0 */
    const char *display_unit; /* "rpm", "rad_s", "rad" or "A" */
    double display_per_si;    /* display value = SI value * display_per_si */
} scenario_reference_t;

/* A named window of the windowed metrics (metrics.windows). */
typedef struct {
    char name[SCENARIO_WINDOW_NAME_MAX]; /* [A-Za-z0-9_]+, unique */
    double t0_s, t1_s;
} scenario_window_t;

/* Metric windows; values (step levels) in the reference's display unit.
 * All times here are SIMULATED time (time_offset_s already added).
 * Times are not bounded by duration_s (a shortened run, --set duration_s=..,
 * keeps its windows): samples outside the run simply do not exist, and a
 * metric whose window holds none is reported as unavailable. */
typedef struct {
    bool has_step;
    double step_t_s;
    double step_end_s; /* step metrics use the samples up to here */
    double step_initial;
    double step_final;
    double settling_band; /* fraction of the step (0.02 = 2 %) */
    bool has_steady_window;
    double steady_t0_s, steady_t1_s;
    double tracking_t0_s, tracking_t1_s;
    size_t n_load_steps;
    double load_step_t_s[SCENARIO_MAX_LOAD_STEPS];
    double dip_window_s;
    double recovery_band; /* display unit; 0: no recovery time */
    size_t n_windows;
    scenario_window_t windows[SCENARIO_MAX_WINDOWS];
} scenario_metrics_t;

typedef struct {
    char name[SCENARIO_NAME_MAX];
    double duration_s;    /* simulated time, offset included */
    double time_offset_s; /* simulated t = profile time + offset: the
                             reference, the load torque and the metric
                             windows are shifted by it (already applied
                             to the structs below) */
    plant_config_t plant;
    mc_config_t firmware; /* the drive's configuration */
    scenario_reference_t reference;
    scenario_metrics_t metrics;
    sim_injection_t injections[SIM_ENGINE_MAX_INJECTIONS];
    size_t n_injections;
    uint32_t trace_decimation; /* one CSV row every N PWM periods */
} scenario_t;

/* True for a firmware field the bench takes from the plant sections (the
 * nominal motor, timing.f_pwm_Hz, encoder.counts_per_rev): not a key of the
 * scenario's "firmware" section. block is a mc_param_block_t name. */
bool scenario_firmware_from_plant(const char *block, const char *field);

/* "current", "speed" or "position": the reference.mode names. */
const char *scenario_mode_name(mc_mode_t mode);

/* The drive's command at simulated time t_s: enabled, in the reference's
 * mode, its profile's value (and i_d in current mode). */
mc_command_t scenario_command_at(const scenario_reference_t *ref, double t_s);

/* Map a parsed document into *out. err->file should already name the source.
 * Returns false with the first error (key path, expected, found). */
bool scenario_from_json(const cJSON *root, scenario_t *out, scn_error_t *err);

/* Load file, resolve its "extends" (sim/scenario_extends.h: base + the
 * file's "set"), apply the "KEY.PATH=VALUE" overrides in order, validate,
 * map. */
bool scenario_load(const char *file, const char *const *overrides, size_t n_overrides,
                   scenario_t *out, scn_error_t *err);

/* Same from a string (tests). file may be NULL; a relative "extends" is
 * taken from file's directory. */
bool scenario_load_text(const char *text, const char *file, const char *const *overrides,
                        size_t n_overrides, scenario_t *out, scn_error_t *err);

#endif /* SIM_SCENARIO_H */
