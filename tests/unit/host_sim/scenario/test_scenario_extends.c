/* Scenario files that extend another one: the base's values come through,
 * the file's "set" entries and then the command-line overrides apply, name
 * and description are the extending file's, and every error class of
 * sim/scenario_extends.h is reported where it happened. The files are
 * written to WORK_DIR (a fresh directory of the build tree). */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sim/scenario.h"
#include "sim/scenario_document.h"
#include "sim/scenario_extends.h"

/* A valid base in WORK_DIR/base/base.json. */
static const char *const base_doc =
    "{\n"
    "  \"format_version\": 2,\n"
    "  \"name\": \"base_name\",\n"
    "  \"description\": \"base description\",\n"
    "  \"duration_s\": 2.0,\n"
    "  \"motor\": {\"R_ohm\": 0.5, \"Ld_H\": 0.004, \"psi_Wb\": 0.17, \"pole_pairs\": 3,\n"
    "            \"J_kgm2\": 0.012},\n"
    "  \"inverter\": {\"f_pwm_Hz\": 10000},\n"
    "  \"disturbances\": {\"mismatch\": {\"R\": 1.2}},\n"
    "  \"firmware\": {\"foc_pi\": {\"speed_bandwidth_rad_s\": 40}},\n"
    "  \"reference\": {\"mode\": \"speed\",\n"
    "                \"speed_rpm\": {\"points\": [[0, 0], [1, 60], [2, 60]]}}\n"
    "}\n";

static scenario_t scn; /* large: keep it off the stack */
static scn_error_t err;

static void write_file(const char *name, const char *text)
{
    char path[1024];
    snprintf(path, sizeof(path), "%s/%s", WORK_DIR, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fputs(text, f) >= 0, 1);
    assert_int_equal(fclose(f), 0);
}

static const char *path_of(const char *name)
{
    static char path[1024];
    snprintf(path, sizeof(path), "%s/%s", WORK_DIR, name);
    return path;
}

static bool load(const char *name, const char *const *overrides, size_t n)
{
    return scenario_load(path_of(name), overrides, n, &scn, &err);
}

static void load_ok(const char *name, const char *const *overrides, size_t n)
{
    if (!load(name, overrides, n)) {
        char line[2048];
        scenario_error_format(&err, line, sizeof(line));
        fail_msg("%s", line);
    }
}

/* The error of loading name: class, file (a name in WORK_DIR) and key path. */
static void expect_error(const char *name, scn_status_t code, const char *file, const char *path)
{
    assert_false(load(name, NULL, 0));
    assert_int_equal(err.code, code);
    assert_string_equal(err.file, path_of(file));
    assert_string_equal(err.path, path);
}

static int setup(void **state)
{
    (void)state;
    write_file("base/base.json", base_doc);
    return 0;
}

static void base_values_come_through(void **state)
{
    (void)state;
    write_file("plain.json", "{\"extends\": \"base/base.json\"}");
    load_ok("plain.json", NULL, 0);
    assert_true(scn.duration_s == 2.0);
    assert_true(scn.plant.motor.R_ohm == 0.5);
    assert_true(scn.plant.mismatch.R == 1.2);
    assert_true(scn.plant.inverter.f_pwm_Hz == 10000.0);
    assert_true(scn.firmware.foc_pi.speed_bandwidth_rad_s == 40.0f);
    assert_true(scn.firmware.timing.f_pwm_Hz == 10000.0f); /* the plant's */
    assert_true(fabs(sim_profile_eval(&scn.reference.value, 1.5) - 60.0 * MC_TEST_RAD_S_PER_RPM) <
                1e-12);
    /* the name is not inherited: the report uses the extending file's name */
    assert_string_equal(scn.name, "plain");
}

static void set_entries_apply_in_order_name_replaced(void **state)
{
    (void)state;
    write_file("ext.json",
               "{\"extends\": \"base/base.json\", \"name\": \"ext_name\",\n"
               " \"description\": \"ext description\",\n"
               " \"set\": [\"motor.R_ohm=0.7\", \"disturbances.mismatch.L=1.5\",\n"
               "         \"motor.R_ohm=0.8\", \"reference.speed_rpm.points[2][1]=90\"]}");
    load_ok("ext.json", NULL, 0);
    assert_string_equal(scn.name, "ext_name");
    assert_true(scn.plant.motor.R_ohm == 0.8); /* the later entry wins */
    assert_true(scn.firmware.motor.R_ohm == 0.8f);
    assert_true(scn.plant.mismatch.L == 1.5);
    assert_true(scn.plant.mismatch.R == 1.2); /* the base's, untouched */
    /* 60 rpm at 1 s, 90 rpm at 2 s */
    assert_true(fabs(sim_profile_eval(&scn.reference.value, 2.0) - 90.0 * MC_TEST_RAD_S_PER_RPM) <
                1e-12);
}

/* The merged document carries the extending file's name and description, or
 * none (never the base's). */
static void name_and_description_replace_the_base(void **state)
{
    (void)state;
    write_file("described.json", "{\"extends\": \"base/base.json\", \"name\": \"n\","
                                 " \"description\": \"mine\"}");
    write_file("bare.json", "{\"extends\": \"base/base.json\"}");
    cJSON *doc = scenario_document_load(path_of("described.json"), &err);
    assert_non_null(doc);
    doc = scenario_extends_resolve(doc, path_of("described.json"), &err);
    assert_non_null(doc);
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(doc, "name")->valuestring, "n");
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(doc, "description")->valuestring, "mine");
    assert_string_equal(err.file, path_of("described.json"));
    cJSON_Delete(doc);
    doc = scenario_extends_resolve(scenario_document_load(path_of("bare.json"), &err),
                                   path_of("bare.json"), &err);
    assert_non_null(doc);
    assert_null(cJSON_GetObjectItemCaseSensitive(doc, "name"));
    assert_null(cJSON_GetObjectItemCaseSensitive(doc, "description"));
    assert_non_null(cJSON_GetObjectItemCaseSensitive(doc, "motor"));
    cJSON_Delete(doc);
}

static void command_line_overrides_apply_after_the_files(void **state)
{
    (void)state;
    write_file("ext.json", "{\"extends\": \"base/base.json\", \"set\": [\"motor.R_ohm=0.7\"]}");
    const char *cli[] = { "motor.R_ohm=0.9", "duration_s=1.5" };
    load_ok("ext.json", cli, 2);
    assert_true(scn.plant.motor.R_ohm == 0.9);
    assert_true(scn.duration_s == 1.5);
}

/* Format-2 firmware keys in set entries: they change the base's firmware
 * section (the base's other keys stay), the command line comes last. */
static void set_entries_reach_the_firmware_section(void **state)
{
    (void)state;
    write_file("fw.json", "{\"extends\": \"base/base.json\",\n"
                          " \"set\": [\"firmware.estimator=flux_pll\",\n"
                          "         \"firmware.flux_pll.bandwidth_rad_s=120\",\n"
                          "         \"firmware.limits.i_max_A=8\"]}");
    load_ok("fw.json", NULL, 0);
    assert_int_equal(scn.firmware.estimator, MC_ESTIMATOR_FLUX_PLL);
    assert_true(scn.firmware.flux_pll.bandwidth_rad_s == 120.0f);
    assert_true(scn.firmware.limits.i_max_A == 8.0f);
    assert_true(scn.firmware.foc_pi.speed_bandwidth_rad_s == 40.0f); /* the base's */
    const char *cli[] = { "firmware.foc_pi.speed_bandwidth_rad_s=45" };
    load_ok("fw.json", cli, 1);
    assert_true(scn.firmware.foc_pi.speed_bandwidth_rad_s == 45.0f);
    /* a rejected firmware value names the loaded file and the key */
    const char *too_fast[] = { "firmware.foc_pi.speed_bandwidth_rad_s=1000" };
    assert_false(load("fw.json", too_fast, 1));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.file, path_of("fw.json"));
    assert_string_equal(err.path, "firmware.foc_pi.speed_bandwidth_rad_s");
}

/* A format-1 base is refused like a format-1 file, naming the loaded file. */
static void format_1_base_is_refused(void **state)
{
    (void)state;
    write_file("base/old.json", "{\"format_version\": 1, \"duration_s\": 1,\n"
                                " \"motor\": {\"R_ohm\": 0.5, \"Ld_H\": 0.004, \"psi_Wb\": 0.17,\n"
                                "           \"pole_pairs\": 3, \"J_kgm2\": 0.012},\n"
                                " \"controller\": {\"speed_bandwidth_rad_s\": 40},\n"
                                " \"reference\": {\"mode\": \"speed\", \"speed_rpm\": 60}}\n");
    write_file("on_old.json", "{\"extends\": \"base/old.json\"}");
    expect_error("on_old.json", SCN_ERR_INVALID, "on_old.json", "format_version");
    assert_non_null(strstr(err.expected, "firmware"));
    assert_string_equal(err.found, "format_version 1");
}

/* a extends b extends the base; a's set applies after b's, and a's name. */
static void chain_of_files_relative_to_each_file(void **state)
{
    (void)state;
    write_file("base/mid.json", "{\"extends\": \"base.json\", \"name\": \"mid\","
                                " \"set\": [\"motor.R_ohm=0.6\", \"motor.psi_Wb=0.2\"]}");
    write_file("top.json", "{\"extends\": \"base/mid.json\", \"set\": [\"motor.R_ohm=0.65\"]}");
    load_ok("top.json", NULL, 0);
    assert_string_equal(scn.name, "top");
    assert_true(scn.plant.motor.R_ohm == 0.65);
    assert_true(scn.plant.motor.psi_Wb == 0.2);
    assert_true(scn.plant.motor.J_kgm2 == 0.012);
}

static void missing_base_names_the_extending_file(void **state)
{
    (void)state;
    write_file("orphan.json", "{\"extends\": \"base/nothing.json\"}");
    expect_error("orphan.json", SCN_ERR_IO, "orphan.json", "extends");
    assert_non_null(strstr(err.found, "base/nothing.json"));
    assert_non_null(strstr(err.expected, "readable"));
}

static void malformed_base_names_the_base(void **state)
{
    (void)state;
    write_file("base/broken.json", "{\n  \"duration_s\": 1x\n}\n");
    write_file("on_broken.json", "{\"extends\": \"base/broken.json\"}");
    assert_false(load("on_broken.json", NULL, 0));
    assert_int_equal(err.code, SCN_ERR_SYNTAX);
    assert_string_equal(err.file, path_of("base/broken.json"));
    assert_int_equal(err.line, 2);
}

static void cycles_are_errors(void **state)
{
    (void)state;
    write_file("self.json", "{\"extends\": \"self.json\"}");
    expect_error("self.json", SCN_ERR_INVALID, "self.json", "extends");
    assert_non_null(strstr(err.expected, "twice"));
    write_file("cycle_a.json", "{\"extends\": \"base/../cycle_b.json\"}");
    write_file("cycle_b.json", "{\"extends\": \"cycle_a.json\"}");
    /* found through another spelling of the same file */
    expect_error("cycle_a.json", SCN_ERR_INVALID, "base/../cycle_b.json", "extends");
    assert_non_null(strstr(err.found, "cycle_a.json -> "));
}

/* d0 -> d1 -> ... -> d<n> -> base: n + 1 links. */
static void write_chain(int links)
{
    for (int i = 0; i < links; i++) {
        char name[32];
        char text[128];
        snprintf(name, sizeof(name), "d%d.json", i);
        if (i == links - 1) {
            snprintf(text, sizeof(text), "{\"extends\": \"base/base.json\"}");
        } else {
            snprintf(text, sizeof(text), "{\"extends\": \"d%d.json\"}", i + 1);
        }
        write_file(name, text);
    }
}

static void depth_limit(void **state)
{
    (void)state;
    write_chain(SCENARIO_EXTENDS_MAX_DEPTH);
    load_ok("d0.json", NULL, 0);
    assert_true(scn.plant.motor.R_ohm == 0.5);
    write_chain(SCENARIO_EXTENDS_MAX_DEPTH + 1);
    char last[32];
    snprintf(last, sizeof(last), "d%d.json", SCENARIO_EXTENDS_MAX_DEPTH);
    expect_error("d0.json", SCN_ERR_INVALID, last, "extends");
    assert_non_null(strstr(err.expected, "at most 4 levels"));
}

static void bad_set_entries_name_their_index(void **state)
{
    (void)state;
    write_file("bad_set.json",
               "{\"extends\": \"base/base.json\", \"set\": [\"motor.R_ohm=1\", \"motor.R_ohm\"]}");
    expect_error("bad_set.json", SCN_ERR_OVERRIDE, "bad_set.json", "set[1]");
    assert_string_equal(err.expected, "KEY.PATH=VALUE");
    write_file("bad_set.json", "{\"extends\": \"base/base.json\", \"set\": [\"motor.R_ohm.x=1\"]}");
    expect_error("bad_set.json", SCN_ERR_OVERRIDE, "bad_set.json", "set[0]");
    assert_non_null(strstr(err.found, "motor.R_ohm.x"));
    write_file("bad_set.json", "{\"extends\": \"base/base.json\", \"set\": [\"a=1\", 3]}");
    expect_error("bad_set.json", SCN_ERR_TYPE, "bad_set.json", "set[1]");
    write_file("bad_set.json", "{\"extends\": \"base/base.json\", \"set\": \"motor.R_ohm=1\"}");
    expect_error("bad_set.json", SCN_ERR_TYPE, "bad_set.json", "set");
}

static void extending_file_takes_only_its_keys(void **state)
{
    (void)state;
    write_file("extra.json", "{\"extends\": \"base/base.json\", \"duration_s\": 3}");
    expect_error("extra.json", SCN_ERR_UNKNOWN_KEY, "extra.json", "duration_s");
    assert_non_null(strstr(err.expected, "\"extends\""));
    write_file("extra.json", "{\"extends\": \"base/base.json\", \"name\": \"a\", \"name\": \"b\"}");
    expect_error("extra.json", SCN_ERR_DUPLICATE_KEY, "extra.json", "name");
    write_file("extra.json", "{\"extends\": 3}");
    expect_error("extra.json", SCN_ERR_TYPE, "extra.json", "extends");
    write_file("extra.json", "{\"extends\": \"\"}");
    expect_error("extra.json", SCN_ERR_INVALID, "extra.json", "extends");
}

/* The merged document is validated as a whole; its errors name the loaded
 * file and the key path (not the file the value came from). */
static void merged_document_errors_name_the_key_path(void **state)
{
    (void)state;
    write_file("neg.json", "{\"extends\": \"base/base.json\", \"set\": [\"motor.R_ohm=-1\"]}");
    expect_error("neg.json", SCN_ERR_RANGE, "neg.json", "motor.R_ohm");
    char line[1024];
    scenario_error_format(&err, line, sizeof(line));
    char expected[1200];
    snprintf(expected, sizeof(expected),
             "%s: motor.R_ohm: out of range: expected number in (0, 1000], found -1",
             path_of("neg.json"));
    assert_string_equal(line, expected);
    write_file("typo.json", "{\"extends\": \"base/base.json\", \"set\": [\"motor.R_onm=1\"]}");
    expect_error("typo.json", SCN_ERR_UNKNOWN_KEY, "typo.json", "motor.R_onm");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(base_values_come_through),
        cmocka_unit_test(set_entries_apply_in_order_name_replaced),
        cmocka_unit_test(name_and_description_replace_the_base),
        cmocka_unit_test(command_line_overrides_apply_after_the_files),
        cmocka_unit_test(set_entries_reach_the_firmware_section),
        cmocka_unit_test(format_1_base_is_refused),
        cmocka_unit_test(chain_of_files_relative_to_each_file),
        cmocka_unit_test(missing_base_names_the_extending_file),
        cmocka_unit_test(malformed_base_names_the_base),
        cmocka_unit_test(cycles_are_errors),
        cmocka_unit_test(depth_limit),
        cmocka_unit_test(bad_set_entries_name_their_index),
        cmocka_unit_test(extending_file_takes_only_its_keys),
        cmocka_unit_test(merged_document_errors_name_the_key_path),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
