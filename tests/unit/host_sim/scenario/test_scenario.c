/* Scenario loading (format 2): a valid document maps to the expected
 * structs, every class of invalid input gives its documented error,
 * overrides apply; format 1 is refused with a message; the "firmware"
 * section takes its keys from the firmware's parameter table. */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mc/config.h"
#include "sim/json_reader.h"
#include "sim/scenario.h"

/* The first key of every format-2 document written here. */
#define V2 "\"format_version\": 2, "

static const char *const valid_doc =
    "{\n"
    "  \"format_version\": 2,\n"
    "  \"name\": \"unit\",\n"
    "  \"duration_s\": 2.0,\n"
    "  \"motor\": {\"R_ohm\": 0.5, \"Ld_H\": 0.004, \"psi_Wb\": 0.17, \"pole_pairs\": 3,\n"
    "            \"J_kgm2\": 0.012},\n"
    "  \"inverter\": {\"f_pwm_Hz\": 10000, \"v_dc_V\": 48, \"dead_time_s\": 2e-6},\n"
    "  \"sensors\": {\"current\": {\"offset_A\": [0.1, -0.2, 0], \"adc_bits\": 12,\n"
    "                            \"full_scale_A\": 25},\n"
    "              \"encoder\": {\"lines\": 1000}, \"seed\": 7},\n"
    "  \"disturbances\": {\n"
    "    \"load_torque_Nm\": {\"points\": [[0, 0], [1, 0], [1, 1.5]],\n"
    "                       \"sines\": [{\"amplitude\": 1, \"freq_Hz\": 25,\n"
    "                                  \"t_start_s\": 1.5}]},\n"
    "    \"mismatch\": {\"R\": 1.5}},\n"
    "  \"firmware\": {\"foc_pi\": {\"speed_bandwidth_rad_s\": 40}},\n"
    "  \"reference\": {\"mode\": \"speed\",\n"
    "                \"speed_rpm\": {\"points\": [[0, 0], [1, 60], [2, 60]]}},\n"
    "  \"metrics\": {\"steady_window_s\": [1.5, 2.0], \"load_steps_s\": [1.0]},\n"
    "  \"output\": {\"trace_decimation\": 5}\n"
    "}\n";

static scenario_t scn; /* large: keep it off the stack */
static scn_error_t err;

static bool load(const char *text, const char *const *overrides, size_t n)
{
    return scenario_load_text(text, "t.json", overrides, n, &scn, &err);
}

static void valid_document_maps_to_structs(void **state)
{
    (void)state;
    assert_true(load(valid_doc, NULL, 0));
    assert_int_equal(err.code, SCN_OK);
    assert_string_equal(scn.name, "unit");
    assert_true(scn.duration_s == 2.0);

    const plant_config_t *p = &scn.plant;
    assert_true(p->motor.R_ohm == 0.5);
    assert_true(p->motor.Lq_H == 0.004); /* Lq defaults to Ld */
    assert_int_equal(p->motor.pole_pairs, 3);
    assert_true(p->mismatch.R == 1.5);
    assert_true(p->mismatch.L == 1.0);
    assert_true(p->inverter.f_pwm_Hz == 10000.0);
    assert_true(p->inverter.t_dead_s == 2e-6);
    assert_true(sim_profile_eval(&p->inverter.v_dc_V, 0.3) == 48.0);
    assert_true(p->sensors.current.offset_A[1] == -0.2);
    assert_true(p->sensors.current.gain[0] == 1.0);
    assert_int_equal(p->sensors.current.adc_bits, 12);
    assert_int_equal(p->sensors.encoder.lines, 1000);
    assert_int_equal(p->sensors.seed, 7);
    /* load: 0 before 1 s, step to 1.5, plus sin(2 pi 25 (t - 1.5)) after 1.5 s */
    assert_true(fabs(sim_profile_eval(&p->load_torque_Nm, 0.5)) < 1e-12);
    assert_true(fabs(sim_profile_eval(&p->load_torque_Nm, 1.2) - 1.5) < 1e-12);
    assert_true(fabs(sim_profile_eval(&p->load_torque_Nm, 1.51) - 2.5) < 1e-9);

    assert_int_equal(p->inverter.duty_update, PLANT_DUTY_UPDATE_NEXT_PERIOD); /* default */

    /* the firmware gets the nominal motor (no mismatch), the plant's PWM
     * rate and encoder resolution, and the keys of the "firmware" section */
    const mc_config_t *c = &scn.firmware;
    assert_true(c->motor.R_ohm == 0.5f);
    assert_true(c->motor.Lq_H == 0.004f);
    assert_int_equal(c->motor.pole_pairs, 3);
    assert_true(c->timing.f_pwm_Hz == 10000.0f);
    assert_int_equal(c->encoder.counts_per_rev, 4000);
    assert_true(c->foc_pi.speed_bandwidth_rad_s == 40.0f);
    assert_int_equal(c->controller, MC_CONTROLLER_FOC_PI);
    assert_int_equal(c->estimator, MC_ESTIMATOR_ENCODER);

    /* 30 rpm at t = 0.5 s is pi rad/s */
    assert_int_equal(scn.reference.mode, MC_MODE_SPEED);
    assert_true(fabs(sim_profile_eval(&scn.reference.value, 0.5) - MC_TEST_PI) < 1e-12);
    assert_string_equal(scn.reference.display_unit, "rpm");
    assert_true(fabs(scn.reference.display_per_si - 30.0 / MC_TEST_PI) < 1e-12);

    assert_false(scn.metrics.has_step);
    assert_true(scn.metrics.has_steady_window);
    assert_true(scn.metrics.steady_t0_s == 1.5 && scn.metrics.steady_t1_s == 2.0);
    assert_true(scn.metrics.tracking_t0_s == 0.0 && scn.metrics.tracking_t1_s == 2.0);
    assert_int_equal(scn.metrics.n_load_steps, 1);
    assert_true(scn.metrics.dip_window_s == 0.5);
    assert_int_equal(scn.trace_decimation, 5);
}

/* Expect an error of class code at path; expected/found contain the given
 * fragments (NULL: not checked). */
static void expect_error(const char *text, scn_status_t code, const char *path,
                         const char *expected_part, const char *found_part)
{
    assert_false(load(text, NULL, 0));
    assert_int_equal(err.code, code);
    assert_string_equal(err.path, path);
    if (expected_part != NULL) {
        assert_non_null(strstr(err.expected, expected_part));
    }
    if (found_part != NULL) {
        assert_non_null(strstr(err.found, found_part));
    }
}

static void missing_key(void **state)
{
    (void)state;
    expect_error("{" V2 "\"duration_s\": 1, \"motor\": {\"Ld_H\": 0.001}}", SCN_ERR_MISSING,
                 "motor.R_ohm", "number in (0, 1000]", NULL);
    expect_error("{" V2 "\"motor\": {}}", SCN_ERR_MISSING, "duration_s", NULL, NULL);
}

static void wrong_type(void **state)
{
    (void)state;
    expect_error("{" V2 "\"duration_s\": 1, \"motor\": {\"R_ohm\": \"abc\"}}", SCN_ERR_TYPE,
                 "motor.R_ohm", "number", "string \"abc\"");
    expect_error("{" V2 "\"duration_s\": 1, \"motor\": [1]}", SCN_ERR_TYPE, "motor", "object",
                 "array");
    expect_error("[1, 2]", SCN_ERR_TYPE, "(root)", "object", "array");
    expect_error("{" V2 "\"duration_s\": 1, \"motor\": {\"R_ohm\": 1, \"Ld_H\": 1, \"psi_Wb\": 1,"
                 " \"pole_pairs\": 2.5}}",
                 SCN_ERR_TYPE, "motor.pole_pairs", "whole number in [1, 64]", "2.5");
}

static void out_of_range(void **state)
{
    (void)state;
    expect_error("{" V2 "\"duration_s\": 1, \"motor\": {\"R_ohm\": -1}}", SCN_ERR_RANGE,
                 "motor.R_ohm", "number in (0, 1000]", "-1");
    expect_error("{" V2 "\"duration_s\": 0}", SCN_ERR_RANGE, "duration_s", "(0,", "0");
}

static void non_finite(void **state)
{
    (void)state;
    /* cJSON parses 1e999 as inf */
    expect_error("{" V2 "\"duration_s\": 1, \"motor\": {\"R_ohm\": 1e999}}", SCN_ERR_NONFINITE,
                 "motor.R_ohm", "finite number", "inf");
}

static void unknown_key_lists_known_keys(void **state)
{
    (void)state;
    assert_false(load("{" V2
                      "\"duration_s\": 1, \"motor\": {\"R_ohm\": 1, \"R_ohms\": 1, \"Ld_H\": 1,"
                      " \"psi_Wb\": 1, \"pole_pairs\": 2, \"J_kgm2\": 1}}",
                      NULL, 0));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "motor.R_ohms");
    assert_non_null(strstr(err.expected, "\"R_ohm\""));
    assert_non_null(strstr(err.expected, "\"B_Nm_s_rad\""));
    /* in a nested optional object, after a valid plant */
    const char *overrides[] = { "sensors.encoder.linez=5" };
    assert_false(load(valid_doc, overrides, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "sensors.encoder.linez");
}

static void duplicate_key(void **state)
{
    (void)state;
    char doc[4096];
    snprintf(doc, sizeof(doc), "{\"output\": {\"trace_decimation\": 2, \"trace_decimation\": 3},%s",
             valid_doc + 1);
    assert_false(load(doc, NULL, 0));
    assert_int_equal(err.code, SCN_ERR_DUPLICATE_KEY);
    assert_string_equal(err.path, "output.trace_decimation");
}

static void malformed_json_has_line_and_column(void **state)
{
    (void)state;
    /* line 3 is `  "motor": {"R_ohm": 1x}`: the 'x' is the 23rd character */
    assert_false(load("{\n  \"duration_s\": 1,\n  \"motor\": {\"R_ohm\": 1x}\n}\n", NULL, 0));
    assert_int_equal(err.code, SCN_ERR_SYNTAX);
    assert_int_equal(err.line, 3);
    assert_int_equal(err.column, 23);
    assert_string_equal(err.found, "'x}'");
    /* truncated document */
    assert_false(load("{\"duration_s\": 1,", NULL, 0));
    assert_int_equal(err.code, SCN_ERR_SYNTAX);
    assert_int_equal(err.line, 1);
    assert_int_equal(err.column, 18);
    assert_string_equal(err.found, "end of input");
}

static void invalid_cross_key_rules(void **state)
{
    (void)state;
    const char *decreasing[] = { "reference.speed_rpm.points[2][0]=0.5" };
    assert_false(load(valid_doc, decreasing, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "reference.speed_rpm.points[2][0]");
    assert_non_null(strstr(err.expected, "time >= 1"));

    const char *both_units[] = { "reference.speed_rad_s=3" };
    assert_false(load(valid_doc, both_units, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "reference.speed_rad_s");

    const char *window[] = { "metrics.steady_window_s=[1.9, 1.2]" };
    assert_false(load(valid_doc, window, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "metrics.steady_window_s");

    const char *bad_mode[] = { "reference.mode=torque" };
    assert_false(load(valid_doc, bad_mode, 1));
    assert_int_equal(err.code, SCN_ERR_RANGE);
    assert_string_equal(err.path, "reference.mode");
    assert_non_null(strstr(err.expected, "\"speed\""));

    const char *short_pair[] = { "disturbances.load_torque_Nm.points[1]=[1]" };
    assert_false(load(valid_doc, short_pair, 1));
    assert_int_equal(err.code, SCN_ERR_RANGE);
    assert_string_equal(err.path, "disturbances.load_torque_Nm.points[1]");
}

static void overrides_apply_before_validation(void **state)
{
    (void)state;
    const char *overrides[] = {
        "duration_s=0.2",
        "motor.R_ohm=0.3",
        "reference.speed_rpm.points[1][1]=90",
        "disturbances.mismatch.L=1.5", /* existing optional object */
        "initial.omega_m_rad_s=2",     /* object created by the override */
        "firmware.controller=foc_pi",  /* not JSON: taken as a string */
        "metrics.steady_window_s=[0.1, 0.2]",
        "metrics.load_steps_s=[0.1]",
    };
    assert_true(load(valid_doc, overrides, sizeof(overrides) / sizeof(overrides[0])));
    assert_true(scn.duration_s == 0.2);
    assert_true(scn.plant.motor.R_ohm == 0.3);
    assert_true(scn.firmware.motor.R_ohm == 0.3f);
    assert_true(fabs(sim_profile_eval(&scn.reference.value, 1.0) - 3.0 * MC_TEST_PI) < 1e-12);
    assert_true(scn.plant.mismatch.L == 1.5);
    assert_true(scn.plant.mismatch.R == 1.5); /* untouched sibling */
    assert_true(scn.plant.omega_m0_rad_s == 2.0);
    assert_int_equal(scn.firmware.controller, MC_CONTROLLER_FOC_PI);
    assert_true(scn.metrics.tracking_t1_s == 0.2);
    assert_true(scn.metrics.load_step_t_s[0] == 0.1);

    /* a shortened run keeps windows and load steps beyond its end (their
     * metrics are then unavailable, not an error) */
    const char *shortened[] = { "duration_s=0.2" };
    assert_true(load(valid_doc, shortened, 1));
    assert_true(scn.metrics.steady_t0_s == 1.5 && scn.metrics.load_step_t_s[0] == 1.0);

    /* the overridden value is validated like one from the file */
    const char *inf_value[] = { "motor.R_ohm=1e999" };
    assert_false(load(valid_doc, inf_value, 1));
    assert_int_equal(err.code, SCN_ERR_NONFINITE);
    assert_string_equal(err.path, "motor.R_ohm");
}

static void fault_injections_and_step_window(void **state)
{
    (void)state;
    const char *overrides[] = {
        "fault_injections=[{\"kind\": \"current_offset\", \"phase\": \"b\", \"offset_A\": 3,"
        " \"t_start_s\": 1.0, \"t_end_s\": 1.2}, {\"kind\": \"fault_input\", \"t_start_s\": 1.5}]",
        "metrics.step={\"t_s\": 0.5, \"t_end_s\": 0.9, \"initial\": 30, \"final\": 60}",
    };
    assert_true(load(valid_doc, overrides, 2));
    assert_int_equal(scn.n_injections, 2);
    assert_int_equal(scn.injections[0].kind, SIM_INJECT_CURRENT_OFFSET);
    assert_int_equal(scn.injections[0].phase, 1);
    assert_true(scn.injections[0].value == 3.0);
    assert_true(scn.injections[0].t_start_s == 1.0 && scn.injections[0].t_end_s == 1.2);
    assert_int_equal(scn.injections[1].kind, SIM_INJECT_FAULT_INPUT);
    assert_true(isinf(scn.injections[1].t_end_s));
    assert_true(scn.metrics.has_step);
    assert_true(scn.metrics.step_t_s == 0.5 && scn.metrics.step_end_s == 0.9);
    assert_true(scn.metrics.step_initial == 30.0 && scn.metrics.step_final == 60.0);
    assert_true(scn.metrics.settling_band == 0.02);

    /* keys of one kind are unknown to another */
    const char *wrong_key[] = {
        "fault_injections=[{\"kind\": \"vdc_measured\", \"offset_A\": 3, \"v_dc_V\": 1,"
        " \"t_start_s\": 0}]",
    };
    assert_false(load(valid_doc, wrong_key, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "fault_injections[0].offset_A");

    const char *zero_step[] = { "metrics.step={\"t_s\": 0.5, \"initial\": 30, \"final\": 30}" };
    assert_false(load(valid_doc, zero_step, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "metrics.step.final");
}

static void reference_modes_and_units(void **state)
{
    (void)state;
    const char *current[] = { "reference={\"mode\": \"current\", \"i_q_A\": 2, \"i_d_A\": -1}" };
    assert_true(load(valid_doc, current, 1));
    assert_int_equal(scn.reference.mode, MC_MODE_CURRENT);
    assert_true(sim_profile_eval(&scn.reference.value, 0.3) == 2.0);
    assert_true(sim_profile_eval(&scn.reference.i_d_A, 0.3) == -1.0);
    assert_string_equal(scn.reference.display_unit, "A");

    const char *position[] = {
        "reference={\"mode\": \"position\", \"position_rad\": {\"points\": [[0, 0], [1, 3]]}}"
    };
    assert_true(load(valid_doc, position, 1));
    assert_int_equal(scn.reference.mode, MC_MODE_POSITION);
    assert_true(fabs(sim_profile_eval(&scn.reference.value, 0.5) - 1.5) < 1e-12);
    assert_string_equal(scn.reference.display_unit, "rad");

    const char *rad_s[] = { "reference={\"mode\": \"speed\", \"speed_rad_s\": 5}" };
    assert_true(load(valid_doc, rad_s, 1));
    assert_true(sim_profile_eval(&scn.reference.value, 0.5) == 5.0);
    assert_string_equal(scn.reference.display_unit, "rad_s");
    assert_true(scn.reference.display_per_si == 1.0);

    /* a key of another mode is unknown in this one */
    const char *mixed[] = { "reference.position_rad=1" };
    assert_false(load(valid_doc, mixed, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "reference.position_rad");
}

/* mc_config_validate() rejects: the number keys that alone can make the
 * configuration valid are named (firmware_blame.h), with a value that
 * does; "firmware" when no single key can. */
static void rejected_firmware_names_the_key(void **state)
{
    (void)state;
    /* speed bandwidth above 0.2 x the default current bandwidth (2513 rad/s)
     * and w_s Ts_slow = 0.5 > 0.2: valid up to 0.2 / Ts_slow = 400 rad/s
     * (2 kHz slow loop), and no other key alone helps */
    const char *too_fast[] = { "firmware.foc_pi.speed_bandwidth_rad_s=1000" };
    assert_false(load(valid_doc, too_fast, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.foc_pi.speed_bandwidth_rad_s");
    assert_non_null(strstr(err.expected, "mc_config_validate() accepts"));
    assert_non_null(strstr(err.expected, "e.g. foc_pi.speed_bandwidth_rad_s = 400"));
    assert_string_equal(err.found, "foc_pi.speed_bandwidth_rad_s = 1000");
    /* trip level below the default current limit (10 A) */
    const char *low_trip[] = { "firmware.protection.i_trip_A=5" };
    assert_false(load(valid_doc, low_trip, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.protection.i_trip_A");
    /* a 2 kHz PWM is too slow for the default current loop (w_c Ts = 1.26
     * > 0.5): the current bandwidth, not given, is named with a valid
     * value, w_c <= 0.5 / Ts = 1000 rad/s */
    const char *slow_pwm[] = { "inverter.f_pwm_Hz=2000" };
    assert_false(load(valid_doc, slow_pwm, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.current.bandwidth_rad_s");
    assert_non_null(strstr(err.expected, "e.g. current.bandwidth_rad_s = 1000"));
    assert_string_equal(err.found, "current.bandwidth_rad_s = 2513 (default)");
    /* no single firmware key can help at 1 kHz: the slow loop (2 kHz)
     * must divide the PWM rate and the current loop slow down, both */
    const char *slowest_pwm[] = { "inverter.f_pwm_Hz=1000" };
    assert_false(load(valid_doc, slowest_pwm, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware");
    assert_non_null(strstr(err.found, "rejected combination"));
    /* the same without a "firmware" section */
    const char *no_section[] = { "inverter.f_pwm_Hz=1000", "firmware={}" };
    assert_false(load(valid_doc, no_section, 2));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware");
    /* the timing block is validated whatever the estimator; no range of
     * its own in the reader (was SCN_ERR_RANGE in format 1) */
    const char *delay[] = { "firmware.timing.delay_periods=2" };
    assert_false(load(valid_doc, delay, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.timing.delay_periods");
    const char *overruns[] = { "firmware.timing.isr_overrun_limit=0" };
    assert_false(load(valid_doc, overruns, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.timing.isr_overrun_limit");
    /* IDA-PBC needs an estimator with a load estimate: the default
     * controller (foc_pi) would be valid */
    const char *idapbc_encoder[] = { "firmware.controller=idapbc" };
    assert_false(load(valid_doc, idapbc_encoder, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.controller");
}

/* Only the selected estimator's and controller's blocks are validated. A
 * value that only a sensorless estimator (or IDA-PBC) rejects is reported
 * at its own key, not at the selection key whose default (encoder, foc_pi)
 * would also make the configuration valid: the reader tries the selection
 * last. */
static void sensorless_rules_blame_the_value(void **state)
{
    (void)state;
    /* the alignment current must stay below i_max (10 A by default) */
    const char *align_encoder[] = { "firmware.align.current_A=12" };
    assert_true(load(valid_doc, align_encoder, 1));
    assert_true(scn.firmware.align.current_A == 12.0f);
    const char *align[] = { "firmware.estimator=flux_pll", "firmware.align.current_A=12" };
    assert_false(load(valid_doc, align, 2));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.align.current_A");
    /* the ramp within the alignment timeout (2 s): either key alone */
    const char *ramp_encoder[] = { "firmware.align.ramp_s=2.5" };
    assert_true(load(valid_doc, ramp_encoder, 1));
    const char *ramp[] = { "firmware.estimator=flux_ii", "firmware.align.ramp_s=2.5" };
    assert_false(load(valid_doc, ramp, 2));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.align.ramp_s, firmware.align.timeout_s");
    /* flux ratio bounds: ratio_min in (0, 1) (was SCN_ERR_RANGE in format 1) */
    const char *ratio_encoder[] = { "firmware.flux_obs.ratio_min=1.2" };
    assert_true(load(valid_doc, ratio_encoder, 1));
    const char *ratio[] = { "firmware.estimator=flux_pll", "firmware.flux_obs.ratio_min=1.2" };
    assert_false(load(valid_doc, ratio, 2));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.flux_obs.ratio_min");
    /* The IDA-PBC integral action (beyond the paper) designs its gains for
     * a well-damped IDA-PBC pair: r = 0.5 ohm is below critical here and
     * is rejected with the integral on: its default (0, critical) would be
     * valid, and so would foc_pi, which is tried last. */
    const char *underdamped[] = {
        "firmware.controller=idapbc",
        "firmware.estimator=flux_ii",
        "firmware.idapbc.r_ohm=0.5",
        "firmware.idapbc.integral_enabled=true",
    };
    assert_false(load(valid_doc, underdamped, sizeof(underdamped) / sizeof(underdamped[0])));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "firmware.idapbc.r_ohm");
    /* with the critical damping (r_ohm = 0, the default) it is accepted */
    const char *integral[] = {
        "firmware.controller=idapbc",
        "firmware.estimator=flux_ii",
        "firmware.idapbc.integral_enabled=true",
        "firmware.idapbc.integral_pole_rad_s=15",
        "firmware.idapbc.integral_tau_max_Nm=2",
    };
    assert_true(load(valid_doc, integral, sizeof(integral) / sizeof(integral[0])));
    assert_true(scn.firmware.idapbc.integral_enabled &&
                scn.firmware.idapbc.integral_pole_rad_s == 15.0f &&
                scn.firmware.idapbc.integral_tau_max_Nm == 2.0f);
}

/* The sensorless keys (paper 001) map onto mc_config_t; the result passes
 * mc_config_validate() with IDA-PBC and the flux observer + I&I. */
static void sensorless_firmware_keys(void **state)
{
    (void)state;
    const char *keys[] = {
        "firmware.controller=idapbc",
        "firmware.estimator=flux_ii",
        "firmware.flux_obs.gamma=4000",
        "firmware.flux_ii.a1=25",
        "firmware.flux_ii.a2=7",
        "firmware.flux_pll.bandwidth_rad_s=120",
        "firmware.protection.estimate_omega_max_rad_s=70",
        "firmware.protection.estimate_tau_max_Nm=12",
        "firmware.flux_obs.ratio_min=0.6",
        "firmware.flux_obs.ratio_max=1.4",
        "firmware.timing.delay_compensation=false",
        "firmware.timing.delay_periods=1.0",
        "firmware.idapbc.r_ohm=0.5",
        "firmware.align.current_A=3",
        "firmware.align.ramp_s=0.2",
        "firmware.align.timeout_s=0.6",
        "firmware.align.angle_e_rad=1.0",
        "firmware.align.damping_ratio=0.7",
        "firmware.align.i_q_max_A=1.5",
        "firmware.align.settle_speed_e_rad_s=0.01",
        "firmware.align.settle_time_s=0.1",
    };
    assert_true(load(valid_doc, keys, sizeof(keys) / sizeof(keys[0])));
    const mc_config_t *c = &scn.firmware;
    assert_int_equal(c->controller, MC_CONTROLLER_IDAPBC);
    assert_int_equal(c->estimator, MC_ESTIMATOR_FLUX_II);
    assert_true(c->flux_obs.gamma == 4000.0f && c->flux_ii.a1 == 25.0f && c->flux_ii.a2 == 7.0f);
    assert_true(c->flux_pll.bandwidth_rad_s == 120.0f);
    assert_true(c->protection.estimate_omega_max_rad_s == 70.0f &&
                c->protection.estimate_tau_max_Nm == 12.0f);
    assert_true(c->flux_obs.ratio_min == 0.6f && c->flux_obs.ratio_max == 1.4f);
    assert_false(c->timing.delay_compensation);
    assert_true(c->timing.delay_periods == 1.0f && c->idapbc.r_ohm == 0.5f);
    assert_true(c->align.current_A == 3.0f && c->align.ramp_s == 0.2f &&
                c->align.timeout_s == 0.6f && c->align.angle_e_rad == 1.0f);
    assert_true(c->align.damping_ratio == 0.7f && c->align.i_q_max_A == 1.5f &&
                c->align.settle_speed_e_rad_s == 0.01f && c->align.settle_time_s == 0.1f);
    /* the values the plant determines are still the plant's */
    assert_true(c->motor.R_ohm == 0.5f && c->timing.f_pwm_Hz == 10000.0f);
    assert_int_equal(c->encoder.counts_per_rev, 4000);
}

/* A format-1 document is refused at "format_version" with a message that
 * says what changed; a document without format_version and without the old
 * section lacks a required key. */
static void format_1_is_refused(void **state)
{
    (void)state;
    static const char body[] = "\"duration_s\": 1,"
                               " \"motor\": {\"R_ohm\": 0.225, \"Ld_H\": 0.0038, \"psi_Wb\": 0.17,"
                               " \"pole_pairs\": 3, \"J_kgm2\": 0.012},"
                               " \"reference\": {\"mode\": \"speed\", \"speed_rad_s\": 0}";
    char doc[1024];
    snprintf(doc, sizeof doc, "{\"format_version\": 1, \"controller\": {\"type\": \"foc_pi\"}, %s}",
             body);
    expect_error(doc, SCN_ERR_INVALID, "format_version", "firmware", "format_version 1");
    assert_non_null(strstr(err.expected, "format_version 2"));
    assert_non_null(strstr(err.expected, "firmware.current.bandwidth_rad_s"));
    /* format_version 1 alone is enough */
    snprintf(doc, sizeof doc, "{\"format_version\": 1, %s}", body);
    expect_error(doc, SCN_ERR_INVALID, "format_version", "firmware", "format_version 1");
    /* no format_version, but the format-1 section */
    snprintf(doc, sizeof doc, "{\"controller\": {\"type\": \"foc_pi\"}, %s}", body);
    expect_error(doc, SCN_ERR_INVALID, "format_version", "firmware", "a \"controller\" section");
    /* neither: a missing required key */
    snprintf(doc, sizeof doc, "{%s}", body);
    expect_error(doc, SCN_ERR_MISSING, "format_version", "whole number in [2, 2]", NULL);
    /* any other version is out of range */
    snprintf(doc, sizeof doc, "{\"format_version\": 3, %s}", body);
    expect_error(doc, SCN_ERR_RANGE, "format_version", "whole number in [2, 2]", "3");
    /* format 2 with the old section: an unknown key */
    snprintf(doc, sizeof doc, "{" V2 "\"controller\": {\"type\": \"foc_pi\"}, %s}", body);
    expect_error(doc, SCN_ERR_UNKNOWN_KEY, "controller", "\"firmware\"", NULL);
    /* and this body as format 2 is valid */
    snprintf(doc, sizeof doc, "{" V2 "%s}", body);
    assert_true(load(doc, NULL, 0));
}

/* ---- The "firmware" section and the firmware's parameter table ---------- */

/* Controller and estimator of a minimal document: each pair validates a
 * different set of blocks. */
typedef enum {
    CTX_ENCODER = 0,
    CTX_FLUX_PLL,
    CTX_FLUX_II,
    CTX_EEO,
    CTX_CDOBC,
    CTX_COUNT
} context_t;

static const struct {
    const char *controller;
    const char *estimator;
} contexts[CTX_COUNT] = {
    [CTX_ENCODER] = { "foc_pi", "encoder" },   /* foc_pi, encoder, timing, ... */
    [CTX_FLUX_PLL] = { "foc_pi", "flux_pll" }, /* + align, flux_obs, flux_pll */
    [CTX_FLUX_II] = { "idapbc", "flux_ii" },   /* + idapbc, flux_ii */
    [CTX_EEO] = { "eeo", "encoder" },          /* + eeo */
    [CTX_CDOBC] = { "cdobc", "encoder" },      /* + cdobc */
};

/* A minimal valid document (the paper 001 motor, default plant) with this
 * controller and estimator. */
static const char *minimal_doc(context_t ctx)
{
    static char doc[1024];
    snprintf(doc, sizeof doc,
             "{" V2 "\"duration_s\": 1,"
             " \"motor\": {\"R_ohm\": 0.225, \"Ld_H\": 0.0038, \"psi_Wb\": 0.17,"
             " \"pole_pairs\": 3, \"J_kgm2\": 0.012},"
             " \"firmware\": {\"controller\": \"%s\", \"estimator\": \"%s\"},"
             " \"reference\": {\"mode\": \"speed\", \"speed_rad_s\": 0}}",
             contexts[ctx].controller, contexts[ctx].estimator);
    return doc;
}

/* For every settable field of the table: a value other than the default
 * that the firmware accepts in the context where its block is validated. */
typedef struct {
    const char *key; /* "<block>.<field>" */
    context_t ctx;
    double value; /* bool: 0 or 1 */
} field_case_t;

static const field_case_t field_cases[] = {
    { "timing.slow_loop_Hz", CTX_ENCODER, 4000.0 },
    { "timing.calib_time_s", CTX_ENCODER, 0.05 },
    { "timing.isr_overrun_limit", CTX_ENCODER, 5.0 },
    { "timing.delay_periods", CTX_ENCODER, 1.0 },
    { "timing.delay_compensation", CTX_ENCODER, 0.0 },
    { "limits.i_max_A", CTX_ENCODER, 8.0 },
    { "limits.omega_max_rad_s", CTX_ENCODER, 45.0 },
    { "protection.i_trip_A", CTX_ENCODER, 25.0 },
    { "protection.v_dc_max_V", CTX_ENCODER, 70.0 },
    { "protection.v_dc_min_V", CTX_ENCODER, 15.0 },
    { "protection.i_offset_max_A", CTX_ENCODER, 1.5 },
    { "protection.estimate_omega_max_rad_s", CTX_ENCODER, 90.0 },
    { "protection.estimate_tau_max_Nm", CTX_ENCODER, 12.0 },
    { "protection.overspeed_rad_s", CTX_ENCODER, 44.0 },
    { "protection.stall_current_A", CTX_ENCODER, 6.0 },
    { "protection.stall_speed_rad_s", CTX_ENCODER, 2.0 },
    { "protection.stall_time_s", CTX_ENCODER, 0.3 },
    { "protection.current_limit_A", CTX_ENCODER, 12.0 },
    { "protection.current_limit_time_s", CTX_ENCODER, 0.2 },
    { "protection.i2t_continuous_A", CTX_ENCODER, 4.0 },
    { "protection.i2t_peak_A", CTX_ENCODER, 9.0 },
    { "protection.i2t_peak_time_s", CTX_ENCODER, 3.0 },
    { "protection.current_sum_max_A", CTX_ENCODER, 0.5 },
    { "protection.current_sum_time_s", CTX_ENCODER, 0.002 },
    { "emf_check.filter_s", CTX_ENCODER, 0.03 },
    { "emf_check.check_time_s", CTX_ENCODER, 0.2 },
    { "emf_check.min_V", CTX_ENCODER, 0.8 },
    { "emf_check.min_speed_e_rad_s", CTX_ENCODER, 5.0 },
    { "emf_check.angle_max_rad", CTX_ENCODER, 1.0 },
    { "emf_check.ratio_low", CTX_FLUX_PLL, 0.4 },
    { "emf_check.ratio_high", CTX_ENCODER, 3.0 },
    { "current.bandwidth_rad_s", CTX_ENCODER, 3000.0 },
    { "current.modulation_margin", CTX_ENCODER, 0.9 },
    { "deadtime.current_band_A", CTX_ENCODER, 0.3 },
    { "deadtime.compensation", CTX_ENCODER, 0.0 },
    { "position.kp_per_s", CTX_ENCODER, 10.0 },
    { "align.current_A", CTX_FLUX_PLL, 3.0 },
    { "align.ramp_s", CTX_FLUX_PLL, 0.2 },
    { "align.timeout_s", CTX_FLUX_PLL, 3.0 },
    { "align.angle_e_rad", CTX_FLUX_PLL, 1.0 },
    { "align.damping_ratio", CTX_FLUX_PLL, 0.7 },
    { "align.i_q_max_A", CTX_FLUX_PLL, 1.5 },
    { "align.settle_speed_e_rad_s", CTX_FLUX_PLL, 0.01 },
    { "align.settle_time_s", CTX_FLUX_PLL, 0.1 },
    { "flux_obs.gamma", CTX_FLUX_PLL, 4000.0 },
    { "flux_obs.ratio_min", CTX_FLUX_PLL, 0.6 },
    { "flux_obs.ratio_max", CTX_FLUX_PLL, 1.4 },
    { "foc_pi.speed_bandwidth_rad_s", CTX_ENCODER, 40.0 },
    { "idapbc.r_ohm", CTX_FLUX_II, 0.5 },
    { "idapbc.integral_enabled", CTX_FLUX_II, 1.0 },
    { "idapbc.integral_pole_rad_s", CTX_FLUX_II, 15.0 },
    { "idapbc.integral_tau_max_Nm", CTX_FLUX_II, 2.0 },
    { "idapbc.paper_rotation", CTX_FLUX_II, 1.0 },
    { "eeo.kappa", CTX_EEO, 500.0 },
    { "eeo.b_bar_Nm_per_Vs", CTX_EEO, 15.0 },
    { "eeo.k1", CTX_EEO, -2.0 },
    { "eeo.k2", CTX_EEO, -4.0 },
    { "eeo.k3", CTX_EEO, -4.0 },
    { "eeo.N_V", CTX_EEO, 1e6 },
    { "eeo.g3_bound_per_kgm2", CTX_EEO, 40.0 },
    { "eeo.g3_amplitude_per_kgm2", CTX_EEO, 20.0 },
    { "eeo.g3_omega_rad_s", CTX_EEO, 2.0 },
    { "eeo.g3_phase_rad", CTX_EEO, 0.5 },
    { "eeo.matched_start", CTX_EEO, 0.0 },
    { "cdobc.poly_order", CTX_CDOBC, 1 },
    { "cdobc.dead_time_model", CTX_CDOBC, 0 },
    { "cdobc.cogging_order", CTX_CDOBC, 16 },
    { "cdobc.sensor_offset_model", CTX_CDOBC, 1 },
    { "cdobc.sensor_gain_model", CTX_CDOBC, 1 },
    { "cdobc.robust_placement", CTX_CDOBC, 0 },
    { "cdobc.harm_zeta", CTX_CDOBC, 0.2 },
    { "cdobc.sensor_zeta", CTX_CDOBC, 0.3 },
    { "cdobc.ctl_pole_rad_s", CTX_CDOBC, 150 },
    { "cdobc.ref_pole_rad_s", CTX_CDOBC, 250 },
    { "cdobc.obs_pole_rad_s", CTX_CDOBC, 600 },
    { "cdobc.kp_d_V_A", CTX_CDOBC, 60 },
    { "cdobc.ki_d_V_As", CTX_CDOBC, 120 },
    { "cdobc.v_max_V", CTX_CDOBC, 150 },
    { "cdobc.omega_min_rad_s", CTX_CDOBC, 20 },
    { "cdobc.design_speed_rad_s", CTX_CDOBC, 40 },
    { "cdobc.redesign_rel_tol", CTX_CDOBC, 0.01 },
    { "cdobc.pid", CTX_CDOBC, 1 },
    { "cdobc.pid_kp_V_s", CTX_CDOBC, 2 },
    { "cdobc.pid_ki_V", CTX_CDOBC, 20 },
    { "cdobc.pid_kd_V_s2", CTX_CDOBC, 0.002 },
    { "cdobc.pid_feedforward", CTX_CDOBC, 1 },
    { "cdobc.count_periods", CTX_CDOBC, 2 },
    { "encoder.offset_e_rad", CTX_ENCODER, 0.5 },
    { "encoder.pll_bandwidth_rad_s", CTX_ENCODER, 800.0 },
    { "flux_ii.a1", CTX_FLUX_II, 25.0 },
    { "flux_ii.a2", CTX_FLUX_II, 7.0 },
    { "flux_pll.bandwidth_rad_s", CTX_FLUX_PLL, 120.0 },
};

#define N_FIELD_CASES (sizeof(field_cases) / sizeof(field_cases[0]))

/* The values the plant determines: not keys of the "firmware" section (the
 * brief of format 2: the nominal motor, timing.f_pwm_Hz and
 * encoder.counts_per_rev). */
static bool from_plant(const char *block, const char *field)
{
    return strcmp(block, "motor") == 0 ||
           (strcmp(block, "timing") == 0 &&
            (strcmp(field, "f_pwm_Hz") == 0 || strcmp(field, "telemetry_every_isr") == 0)) ||
           (strcmp(block, "deadtime") == 0 &&
            (strcmp(field, "dead_time_s") == 0 || strcmp(field, "device_drop_V") == 0)) ||
           (strcmp(block, "encoder") == 0 && strcmp(field, "counts_per_rev") == 0);
}

static const unsigned char *field_of(const mc_config_t *c, const mc_param_block_t *b,
                                     const mc_param_t *p)
{
    return (const unsigned char *)c + b->offset + p->offset;
}

/* The test value of a field as it must land in the config, and as text. */
static void encode_value(const mc_param_t *p, double value, unsigned char *bytes, char *text,
                         size_t size)
{
    if (p->type == MC_PARAM_F32) {
        const float f = (float)value;
        memcpy(bytes, &f, sizeof f);
        snprintf(text, size, "%.9g", (double)f);
    } else if (p->type == MC_PARAM_U32) {
        const uint32_t u = (uint32_t)value;
        memcpy(bytes, &u, sizeof u);
        snprintf(text, size, "%u", (unsigned)u);
    } else {
        const bool flag = value != 0.0;
        memcpy(bytes, &flag, sizeof flag);
        snprintf(text, size, "%s", flag ? "true" : "false");
    }
}

static mc_config_t baseline[CTX_COUNT];

static void load_ok(const char *text, const char *const *overrides, size_t n)
{
    if (!load(text, overrides, n)) {
        char line[2048];
        scenario_error_format(&err, line, sizeof(line));
        fail_msg("%s", line);
    }
}

/* Every F32/U32/BOOL field of mc_config_params() (but the plant's) is a key
 * "firmware.<block>.<field>" that lands in scenario_t.firmware at the
 * table's place and nowhere else: the reader takes its keys from the
 * firmware's table. */
static void every_table_field_is_a_key(void **state)
{
    (void)state;
    mc_config_t defaults;
    mc_config_init_default(&defaults);
    for (int ctx = 0; ctx < CTX_COUNT; ctx++) {
        load_ok(minimal_doc((context_t)ctx), NULL, 0);
        baseline[ctx] = scn.firmware;
    }
    bool used[N_FIELD_CASES] = { false };
    size_t n_fields = 0;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; b++) {
        for (const mc_param_t *p = b->params; p->name != NULL; p++) {
            /* the reader's own predicate agrees with the list above */
            assert_int_equal(scenario_firmware_from_plant(b->name, p->name),
                             from_plant(b->name, p->name));
            if (b->name[0] == '\0' || from_plant(b->name, p->name)) {
                continue; /* the lists (below) and the plant's values */
            }
            assert_true(p->type == MC_PARAM_F32 || p->type == MC_PARAM_U32 ||
                        p->type == MC_PARAM_BOOL);
            char key[96];
            snprintf(key, sizeof key, "%s.%s", b->name, p->name);
            const field_case_t *fc = NULL;
            for (size_t i = 0; i < N_FIELD_CASES; i++) {
                if (strcmp(field_cases[i].key, key) == 0) {
                    assert_false(used[i]);
                    used[i] = true;
                    fc = &field_cases[i];
                }
            }
            if (fc == NULL) {
                fail_msg("no test value for the firmware parameter %s", key);
            }
            n_fields++;
            const size_t size = mc_param_size(p->type);
            unsigned char want[8];
            char text[64];
            encode_value(p, fc->value, want, text, sizeof text);
            if (memcmp(want, field_of(&defaults, b, p), size) == 0 ||
                memcmp(want, field_of(&baseline[fc->ctx], b, p), size) == 0) {
                fail_msg("%s: the test value %s is the default", key, text);
            }
            char assignment[256];
            snprintf(assignment, sizeof assignment, "firmware.%s=%s", key, text);
            const char *overrides[] = { assignment };
            load_ok(minimal_doc(fc->ctx), overrides, 1);
            /* the field holds the value; every other field is the context's */
            for (const mc_param_block_t *b2 = mc_config_params(); b2->name != NULL; b2++) {
                for (const mc_param_t *p2 = b2->params; p2->name != NULL; p2++) {
                    const unsigned char *got = field_of(&scn.firmware, b2, p2);
                    const bool target = (b2 == b && p2 == p);
                    const unsigned char *expect =
                        target ? want : field_of(&baseline[fc->ctx], b2, p2);
                    if (memcmp(got, expect, mc_param_size(p2->type)) != 0) {
                        fail_msg("%s: firmware field %s.%s is not as expected", assignment,
                                 b2->name, p2->name);
                    }
                }
            }
        }
    }
    assert_int_equal(n_fields, N_FIELD_CASES);
    for (size_t i = 0; i < N_FIELD_CASES; i++) {
        if (!used[i]) {
            fail_msg("%s is not a field of mc_config_params()", field_cases[i].key);
        }
    }
}

/* The values the plant determines are not keys: the whole "motor" block,
 * timing.f_pwm_Hz and encoder.counts_per_rev are unknown keys. */
static void plant_values_are_not_firmware_keys(void **state)
{
    (void)state;
    size_t n_motor = 0;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; b++) {
        if (strcmp(b->name, "motor") != 0) {
            continue;
        }
        for (const mc_param_t *p = b->params; p->name != NULL; p++) {
            char assignment[96];
            snprintf(assignment, sizeof assignment, "firmware.motor.%s=1", p->name);
            const char *overrides[] = { assignment };
            assert_false(load(valid_doc, overrides, 1));
            assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
            /* the block itself is the unknown key of the section */
            assert_string_equal(err.path, "firmware.motor");
            assert_non_null(strstr(err.expected, "\"foc_pi\""));
            assert_null(strstr(err.expected, "\"motor\""));
            n_motor++;
        }
    }
    assert_true(n_motor >= 7);
    const char *f_pwm[] = { "firmware.timing.f_pwm_Hz=10000" };
    assert_false(load(valid_doc, f_pwm, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "firmware.timing.f_pwm_Hz");
    assert_non_null(strstr(err.expected, "\"slow_loop_Hz\""));
    assert_null(strstr(err.expected, "\"f_pwm_Hz\""));
    /* the bench reads the record after every ISR: not a key either */
    const char *every_isr[] = { "firmware.timing.telemetry_every_isr=false" };
    assert_false(load(valid_doc, every_isr, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "firmware.timing.telemetry_every_isr");
    assert_null(strstr(err.expected, "\"telemetry_every_isr\""));
    const char *cpr[] = { "firmware.encoder.counts_per_rev=4000" };
    assert_false(load(valid_doc, cpr, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "firmware.encoder.counts_per_rev");
    assert_non_null(strstr(err.expected, "\"pll_bandwidth_rad_s\""));
    assert_null(strstr(err.expected, "\"counts_per_rev\""));
    /* other misspellings in the section */
    const char *block[] = { "firmware.speed={\"bandwidth_rad_s\": 40}" };
    assert_false(load(valid_doc, block, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "firmware.speed");
    const char *field[] = { "firmware.foc_pi.speed_bw_rad_s=40" };
    assert_false(load(valid_doc, field, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
    assert_string_equal(err.path, "firmware.foc_pi.speed_bw_rad_s");
    const char *not_object[] = { "firmware.foc_pi=40" };
    assert_false(load(valid_doc, not_object, 1));
    assert_int_equal(err.code, SCN_ERR_TYPE);
    assert_string_equal(err.path, "firmware.foc_pi");
    const char *bool_type[] = { "firmware.timing.delay_compensation=1" };
    assert_false(load(valid_doc, bool_type, 1));
    assert_int_equal(err.code, SCN_ERR_TYPE);
    assert_string_equal(err.path, "firmware.timing.delay_compensation");
    const char *u32_type[] = { "firmware.timing.isr_overrun_limit=2.5" };
    assert_false(load(valid_doc, u32_type, 1));
    assert_int_equal(err.code, SCN_ERR_TYPE);
    assert_string_equal(err.path, "firmware.timing.isr_overrun_limit");
    const char *inf[] = { "firmware.current.bandwidth_rad_s=1e999" };
    assert_false(load(valid_doc, inf, 1));
    assert_int_equal(err.code, SCN_ERR_NONFINITE);
    assert_string_equal(err.path, "firmware.current.bandwidth_rad_s");
}

/* firmware.controller / firmware.estimator take exactly the names of the
 * firmware's lists; another string is out of range (json_reader.c
 * enum_impl: SCN_ERR_RANGE), another type a wrong type. */
static void controller_and_estimator_names(void **state)
{
    (void)state;
    assert_int_equal(MC_CONTROLLER_COUNT, 4);
    assert_string_equal(mc_controller_name(MC_CONTROLLER_CDOBC), "cdobc");
    assert_string_equal(mc_controller_name(MC_CONTROLLER_EEO), "eeo");
    assert_string_equal(mc_controller_name(MC_CONTROLLER_FOC_PI), "foc_pi");
    assert_string_equal(mc_controller_name(MC_CONTROLLER_IDAPBC), "idapbc");
    assert_int_equal(MC_ESTIMATOR_COUNT, 3);
    assert_string_equal(mc_estimator_name(MC_ESTIMATOR_ENCODER), "encoder");
    assert_string_equal(mc_estimator_name(MC_ESTIMATOR_FLUX_II), "flux_ii");
    assert_string_equal(mc_estimator_name(MC_ESTIMATOR_FLUX_PLL), "flux_pll");
    char assignment[2][64];
    const char *overrides[] = { assignment[0], assignment[1] };
    /* every controller (with flux_ii, which every controller but the
     * encoder-only eeo accepts; eeo with the encoder) */
    for (int i = 0; i < (int)MC_CONTROLLER_COUNT; i++) {
        snprintf(assignment[0], sizeof assignment[0], "firmware.controller=%s",
                 mc_controller_name((mc_controller_t)i));
        const bool eeo = (i == (int)MC_CONTROLLER_EEO);
        snprintf(assignment[1], sizeof assignment[1], "firmware.estimator=%s",
                 eeo ? "encoder" : "flux_ii");
        load_ok(valid_doc, overrides, 2);
        assert_int_equal(scn.firmware.controller, i);
        assert_int_equal(scn.firmware.estimator, eeo ? MC_ESTIMATOR_ENCODER : MC_ESTIMATOR_FLUX_II);
    }
    /* every estimator (with foc_pi, which works with any) */
    for (int i = 0; i < (int)MC_ESTIMATOR_COUNT; i++) {
        snprintf(assignment[0], sizeof assignment[0], "firmware.estimator=%s",
                 mc_estimator_name((mc_estimator_t)i));
        snprintf(assignment[1], sizeof assignment[1], "firmware.controller=foc_pi");
        load_ok(valid_doc, overrides, 2);
        assert_int_equal(scn.firmware.estimator, i);
        assert_int_equal(scn.firmware.controller, MC_CONTROLLER_FOC_PI);
    }
    const char *bad_controllers[] = { "FOC_PI", "foc", "pid", "idapbc ", "" };
    for (size_t i = 0; i < sizeof bad_controllers / sizeof bad_controllers[0]; i++) {
        snprintf(assignment[0], sizeof assignment[0], "firmware.controller=\"%s\"",
                 bad_controllers[i]);
        assert_false(load(valid_doc, overrides, 1));
        assert_int_equal(err.code, SCN_ERR_RANGE);
        assert_string_equal(err.path, "firmware.controller");
        assert_string_equal(err.expected, "one of \"foc_pi\", \"idapbc\", \"eeo\", \"cdobc\"");
    }
    /* format 1's angle_source names are not estimators */
    const char *bad_estimators[] = { "flux_observer", "hall", "Encoder", "flux" };
    for (size_t i = 0; i < sizeof bad_estimators / sizeof bad_estimators[0]; i++) {
        snprintf(assignment[0], sizeof assignment[0], "firmware.estimator=%s", bad_estimators[i]);
        assert_false(load(valid_doc, overrides, 1));
        assert_int_equal(err.code, SCN_ERR_RANGE);
        assert_string_equal(err.path, "firmware.estimator");
        assert_string_equal(err.expected, "one of \"encoder\", \"flux_ii\", \"flux_pll\"");
    }
    snprintf(assignment[0], sizeof assignment[0], "firmware.controller=1");
    assert_false(load(valid_doc, overrides, 1));
    assert_int_equal(err.code, SCN_ERR_TYPE);
    assert_string_equal(err.path, "firmware.controller");
}

/* inverter.duty_update: when the inverter latches the ISR's duties. */
static void inverter_duty_update(void **state)
{
    (void)state;
    load_ok(valid_doc, NULL, 0);
    assert_int_equal(scn.plant.inverter.duty_update, PLANT_DUTY_UPDATE_NEXT_PERIOD);
    const char *next[] = { "inverter.duty_update=next_period" };
    load_ok(valid_doc, next, 1);
    assert_int_equal(scn.plant.inverter.duty_update, PLANT_DUTY_UPDATE_NEXT_PERIOD);
    const char *half[] = { "inverter.duty_update=half_period" };
    load_ok(valid_doc, half, 1);
    assert_int_equal(scn.plant.inverter.duty_update, PLANT_DUTY_UPDATE_HALF_PERIOD);
    assert_true(scn.plant.inverter.f_pwm_Hz == 10000.0); /* siblings kept */
    assert_true(scn.plant.inverter.t_dead_s == 2e-6);
    const char *bad[] = { "inverter.duty_update=quarter_period" };
    assert_false(load(valid_doc, bad, 1));
    assert_int_equal(err.code, SCN_ERR_RANGE);
    assert_string_equal(err.path, "inverter.duty_update");
    assert_string_equal(err.expected, "one of \"next_period\", \"half_period\"");
    assert_string_equal(err.found, "string \"quarter_period\"");
    const char *number[] = { "inverter.duty_update=1" };
    assert_false(load(valid_doc, number, 1));
    assert_int_equal(err.code, SCN_ERR_TYPE);
    assert_string_equal(err.path, "inverter.duty_update");
    /* the duties change at the middle of the period: an even substep count */
    const char *odd[] = { "inverter.duty_update=half_period", "solver.substeps_per_period=5" };
    assert_false(load(valid_doc, odd, 2));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "solver.substeps_per_period");
    assert_string_equal(err.found, "5");
    const char *even[] = { "inverter.duty_update=half_period", "solver.substeps_per_period=6" };
    load_ok(valid_doc, even, 2);
    assert_int_equal(scn.plant.substeps_per_period, 6);
}

/* motor.convention: the parameters' frame, converted once to the plant's
 * (motor_convention.h): power-invariant psi is the plant's times sqrt(3/2)
 * (power and torque invariant, currents sqrt(3/2) larger); the firmware
 * takes the converted value; the other parameters and the mismatch are
 * untouched. */
static void motor_convention(void **state)
{
    (void)state;
    load_ok(valid_doc, NULL, 0);
    assert_true(scn.plant.motor.psi_Wb == 0.17); /* amplitude-invariant */
    const char *amp[] = { "motor.convention=amplitude_invariant" };
    load_ok(valid_doc, amp, 1);
    assert_true(scn.plant.motor.psi_Wb == 0.17);
    const char *pow[] = { "motor.convention=power_invariant" };
    load_ok(valid_doc, pow, 1);
    const double psi = 0.17 * sqrt(2.0 / 3.0);
    assert_true(fabs(scn.plant.motor.psi_Wb - psi) <= 1e-15);
    assert_true(scn.firmware.motor.psi_Wb == (float)scn.plant.motor.psi_Wb);
    /* the same machine: torque per A of the paper's current (n_p Phi)
     * times the paper's current per plant current (sqrt(3/2)) is the
     * plant's 1.5 n_p psi */
    assert_true(fabs(3.0 * 0.17 * sqrt(1.5) - 1.5 * 3.0 * scn.plant.motor.psi_Wb) <= 1e-12);
    assert_true(scn.plant.motor.R_ohm == 0.5 && scn.plant.motor.Ld_H == 0.004 &&
                scn.plant.motor.J_kgm2 == 0.012 && scn.plant.mismatch.R == 1.5);
    const char *bad[] = { "motor.convention=two_phase" };
    assert_false(load(valid_doc, bad, 1));
    assert_int_equal(err.code, SCN_ERR_RANGE);
    assert_string_equal(err.path, "motor.convention");
    assert_string_equal(err.expected, "one of \"amplitude_invariant\", \"power_invariant\"");
}

/* time_offset_s moves the reference, the load and the metric windows (not
 * the fault injections or duration_s) from profile to simulated time. */
static void time_offset_shifts_profiles_and_windows(void **state)
{
    (void)state;
    const char *shift[] = {
        "time_offset_s=0.5",
        "fault_injections=[{\"kind\": \"fault_input\", \"t_start_s\": 1.0}]",
        "metrics.windows=[{\"name\": \"w1\", \"t_s\": [1.0, 1.5]}]",
    };
    assert_true(load(valid_doc, shift, sizeof(shift) / sizeof(shift[0])));
    assert_true(scn.time_offset_s == 0.5 && scn.duration_s == 2.0);
    /* reference 0 -> 60 rpm over profile time [0, 1]: 30 rpm at t = 1.0 */
    assert_true(fabs(sim_profile_eval(&scn.reference.value, 1.0) - MC_TEST_PI) < 1e-12);
    assert_true(sim_profile_eval(&scn.reference.value, 0.4) == 0.0);
    /* load: step to 1.5 at profile 1 s (t = 1.5), sine from profile 1.5 s */
    const sim_profile_t *tl = &scn.plant.load_torque_Nm;
    assert_true(sim_profile_eval(tl, 1.49) == 0.0);
    assert_true(fabs(sim_profile_eval(tl, 1.7) - 1.5) < 1e-12);
    assert_true(fabs(sim_profile_eval(tl, 2.01) - 2.5) < 1e-9);
    const scenario_metrics_t *m = &scn.metrics;
    assert_true(m->steady_t0_s == 2.0 && m->steady_t1_s == 2.5);
    assert_true(m->tracking_t0_s == 0.5 && m->tracking_t1_s == 2.5);
    assert_true(m->load_step_t_s[0] == 1.5);
    assert_int_equal(m->n_windows, 1);
    assert_string_equal(m->windows[0].name, "w1");
    assert_true(m->windows[0].t0_s == 1.5 && m->windows[0].t1_s == 2.0);
    assert_true(scn.injections[0].t_start_s == 1.0);

    const char *negative[] = { "time_offset_s=-1" };
    assert_false(load(valid_doc, negative, 1));
    assert_int_equal(err.code, SCN_ERR_RANGE);
    assert_string_equal(err.path, "time_offset_s");
}

static void named_window_errors(void **state)
{
    (void)state;
    const char *dup[] = { "metrics.windows=[{\"name\": \"a\", \"t_s\": [0, 1]},"
                          " {\"name\": \"a\", \"t_s\": [1, 2]}]" };
    assert_false(load(valid_doc, dup, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "metrics.windows[1].name");
    const char *bad_name[] = { "metrics.windows=[{\"name\": \"a b\", \"t_s\": [0, 1]}]" };
    assert_false(load(valid_doc, bad_name, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "metrics.windows[0].name");
    const char *no_name[] = { "metrics.windows=[{\"t_s\": [0, 1]}]" };
    assert_false(load(valid_doc, no_name, 1));
    assert_int_equal(err.code, SCN_ERR_MISSING);
    assert_string_equal(err.path, "metrics.windows[0].name");
    const char *no_times[] = { "metrics.windows=[{\"name\": \"a\"}]" };
    assert_false(load(valid_doc, no_times, 1));
    assert_int_equal(err.code, SCN_ERR_MISSING);
    assert_string_equal(err.path, "metrics.windows[0].t_s");
    const char *reversed[] = { "metrics.windows=[{\"name\": \"a\", \"t_s\": [2, 1]}]" };
    assert_false(load(valid_doc, reversed, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, "metrics.windows[0].t_s");
    const char *extra[] = { "metrics.windows=[{\"name\": \"a\", \"t_s\": [0, 1], \"x\": 1}]" };
    assert_false(load(valid_doc, extra, 1));
    assert_int_equal(err.code, SCN_ERR_UNKNOWN_KEY);
}

static void bad_override_syntax(void **state)
{
    (void)state;
    const char *cases[] = {
        "motor.R_ohm",                        /* no '=' */
        "=3",                                 /* no path */
        "motor..R_ohm=1",                     /* empty key */
        "motor.R_ohm.x=1",                    /* through a number */
        "reference.speed_rpm.points[7][0]=1", /* index beyond the array */
        "motor[0]=1",                         /* index into an object */
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        assert_false(load(valid_doc, &cases[i], 1));
        assert_int_equal(err.code, SCN_ERR_OVERRIDE);
    }
}

static void unreadable_file(void **state)
{
    (void)state;
    assert_false(scenario_load("no/such/scenario.json", NULL, 0, &scn, &err));
    assert_int_equal(err.code, SCN_ERR_IO);
    assert_string_equal(err.file, "no/such/scenario.json");
}

static void error_line_names_file_path_expected_found(void **state)
{
    (void)state;
    char line[1024];
    assert_false(load("{" V2 "\"duration_s\": 1, \"motor\": {\"R_ohm\": -1}}", NULL, 0));
    scenario_error_format(&err, line, sizeof(line));
    assert_string_equal(
        line, "t.json: motor.R_ohm: out of range: expected number in (0, 1000], found -1");
    assert_false(load("{\n  \"duration_s\": 1,\n  \"motor\": {\"R_ohm\": 1x}\n}\n", NULL, 0));
    scenario_error_format(&err, line, sizeof(line));
    assert_string_equal(line, "t.json:3:23: malformed JSON: expected JSON value, found 'x}'");
}

/* The reader tracks at most JR_MAX_KEYS keys per object: reading one more
 * is reported at that key as a reader limit, not accepted silently and
 * not blamed on the document as an unknown key. */
static void reader_key_limit_is_an_error(void **state)
{
    (void)state;
    char text[32 * (JR_MAX_KEYS + 1) + 8] = "{";
    char key_names[JR_MAX_KEYS + 1][16];
    size_t n = 1;
    for (int k = 0; k <= (int)JR_MAX_KEYS; ++k) {
        snprintf(key_names[k], sizeof key_names[k], "k%d", k);
        n += (size_t)snprintf(text + n, sizeof text - n, "%s\"k%d\": %d", k ? ", " : "", k, k);
    }
    snprintf(text + n, sizeof text - n, "}");
    cJSON *json = cJSON_Parse(text);
    assert_non_null(json);
    scn_error_t e = { 0 };
    jr_object_t root;
    assert_true(jr_root(&root, json, &e));
    double v = -1.0;
    for (int k = 0; k < (int)JR_MAX_KEYS; ++k) {
        assert_true(jr_number(&root, key_names[k], JR_ANY_FINITE, &v));
        assert_true(v == (double)k);
    }
    assert_false(jr_number(&root, key_names[JR_MAX_KEYS], JR_ANY_FINITE, &v));
    assert_int_equal(e.code, SCN_ERR_INVALID);
    assert_string_equal(e.path, key_names[JR_MAX_KEYS]);
    cJSON_Delete(json);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(valid_document_maps_to_structs),
        cmocka_unit_test(missing_key),
        cmocka_unit_test(wrong_type),
        cmocka_unit_test(out_of_range),
        cmocka_unit_test(non_finite),
        cmocka_unit_test(unknown_key_lists_known_keys),
        cmocka_unit_test(duplicate_key),
        cmocka_unit_test(malformed_json_has_line_and_column),
        cmocka_unit_test(invalid_cross_key_rules),
        cmocka_unit_test(overrides_apply_before_validation),
        cmocka_unit_test(fault_injections_and_step_window),
        cmocka_unit_test(reference_modes_and_units),
        cmocka_unit_test(rejected_firmware_names_the_key),
        cmocka_unit_test(sensorless_rules_blame_the_value),
        cmocka_unit_test(sensorless_firmware_keys),
        cmocka_unit_test(format_1_is_refused),
        cmocka_unit_test(every_table_field_is_a_key),
        cmocka_unit_test(plant_values_are_not_firmware_keys),
        cmocka_unit_test(controller_and_estimator_names),
        cmocka_unit_test(inverter_duty_update),
        cmocka_unit_test(motor_convention),
        cmocka_unit_test(time_offset_shifts_profiles_and_windows),
        cmocka_unit_test(named_window_errors),
        cmocka_unit_test(bad_override_syntax),
        cmocka_unit_test(unreadable_file),
        cmocka_unit_test(error_line_names_file_path_expected_found),
        cmocka_unit_test(reader_key_limit_is_an_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
