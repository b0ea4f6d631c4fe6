/* Scenario keys of the DC link (host_sim/scenario/src/scenario_plant.c):
 * inverter.dc_link maps to plant_config_t.dc_link; absent it is the stiff
 * bus; invalid combinations are reported at the offending key. */
#include "mc_test.h"

#include <string.h>

#include "sim/scenario.h"

/* A minimal valid document; overrides ("--set" form) add the dc_link keys. */
static const char *const base_doc =
    "{\"format_version\": 2, \"name\": \"link\", \"duration_s\": 0.1,\n"
    " \"motor\": {\"R_ohm\": 0.225, \"Ld_H\": 0.0038, \"psi_Wb\": 0.17, \"pole_pairs\": 3,\n"
    "           \"J_kgm2\": 0.012},\n"
    " \"inverter\": {\"v_dc_V\": 48, \"device_drop_V\": 0.7},\n"
    " \"reference\": {\"mode\": \"speed\", \"speed_rpm\": 0}}\n";

static scenario_t scn; /* large: keep it off the stack */
static scn_error_t err;

static bool load(const char *const *overrides, size_t n)
{
    return scenario_load_text(base_doc, "t.json", overrides, n, &scn, &err);
}

static void expect_error(const char *const *overrides, size_t n, scn_status_t code,
                         const char *path, const char *expected_part)
{
    assert_false(load(overrides, n));
    print_message("%s: expected %s, found %s\n", err.path, err.expected, err.found);
    assert_int_equal(err.code, code);
    assert_string_equal(err.path, path);
    assert_non_null(strstr(err.expected, expected_part));
}

static void test_absent_is_stiff_bus(void **state)
{
    (void)state;
    assert_true(load(NULL, 0));
    const plant_dc_link_t *l = &scn.plant.dc_link;
    assert_true(l->capacitance_F == 0.0 && l->source_resistance_ohm == 0.0);
    assert_true(l->brake_resistance_ohm == 0.0 && !l->v0_given);
    const char *zero[] = { "inverter.dc_link.capacitance_F=0" };
    assert_true(load(zero, 1));
    assert_true(scn.plant.dc_link.capacitance_F == 0.0);
}

static void test_full_link_maps_to_config(void **state)
{
    (void)state;
    const char *set[] = { "inverter.dc_link={\"capacitance_F\": 0.002, "
                          "\"source_resistance_ohm\": 0.05, \"brake_resistance_ohm\": 12, "
                          "\"brake_on_V\": 60, \"brake_off_V\": 56, \"v0_V\": 30}" };
    assert_true(load(set, 1));
    const plant_dc_link_t *l = &scn.plant.dc_link;
    assert_true(l->capacitance_F == 0.002 && l->source_resistance_ohm == 0.05);
    assert_true(l->brake_resistance_ohm == 12.0 && l->brake_on_V == 60.0);
    assert_true(l->brake_off_V == 56.0 && l->v0_given && l->v0_V == 30.0);
    assert_true(scn.plant.inverter.v_device_drop_V == 0.7); /* siblings kept */
    /* without v0_V the link starts at the source voltage */
    const char *no_v0[] = { "inverter.dc_link.capacitance_F=0.002",
                            "inverter.dc_link.source_resistance_ohm=0.05" };
    assert_true(load(no_v0, 2));
    assert_false(scn.plant.dc_link.v0_given);
    assert_true(scn.plant.dc_link.brake_resistance_ohm == 0.0);
}

static void test_invalid_links_name_the_key(void **state)
{
    (void)state;
    const char *no_rs[] = { "inverter.dc_link.capacitance_F=0.002" };
    expect_error(no_rs, 1, SCN_ERR_MISSING, "inverter.dc_link.source_resistance_ohm", "(0, 1000]");
    const char *rs_zero[] = { "inverter.dc_link.capacitance_F=0.002",
                              "inverter.dc_link.source_resistance_ohm=0" };
    expect_error(rs_zero, 2, SCN_ERR_RANGE, "inverter.dc_link.source_resistance_ohm", "(0, 1000]");
    const char *rs_stiff[] = { "inverter.dc_link.source_resistance_ohm=0.1" };
    expect_error(rs_stiff, 1, SCN_ERR_INVALID, "inverter.dc_link.source_resistance_ohm",
                 "capacitance_F > 0");
    const char *v0_stiff[] = { "inverter.dc_link.v0_V=20" };
    expect_error(v0_stiff, 1, SCN_ERR_INVALID, "inverter.dc_link.v0_V", "capacitance_F > 0");
    const char *c_neg[] = { "inverter.dc_link.capacitance_F=-1" };
    expect_error(c_neg, 1, SCN_ERR_RANGE, "inverter.dc_link.capacitance_F", "[0, 100]");
    const char *hyst[] = { "inverter.dc_link={\"capacitance_F\": 0.002, "
                           "\"source_resistance_ohm\": 0.05, \"brake_resistance_ohm\": 12, "
                           "\"brake_on_V\": 60, \"brake_off_V\": 60}" };
    expect_error(hyst, 1, SCN_ERR_INVALID, "inverter.dc_link.brake_off_V",
                 "below brake_on_V = 60 V");
    const char *no_on[] = { "inverter.dc_link={\"capacitance_F\": 0.002, "
                            "\"source_resistance_ohm\": 0.05, \"brake_resistance_ohm\": 12}" };
    expect_error(no_on, 1, SCN_ERR_MISSING, "inverter.dc_link.brake_on_V", "(0, 100000]");
    const char *no_brake[] = { "inverter.dc_link={\"capacitance_F\": 0.002, "
                               "\"source_resistance_ohm\": 0.05, \"brake_on_V\": 60}" };
    expect_error(no_brake, 1, SCN_ERR_INVALID, "inverter.dc_link.brake_on_V",
                 "brake_resistance_ohm > 0");
    /* a misspelt key: the known ones are listed, stiff or not */
    const char *unknown[] = { "inverter.dc_link.capacitance_uF=1" };
    expect_error(unknown, 1, SCN_ERR_UNKNOWN_KEY, "inverter.dc_link.capacitance_uF",
                 "\"brake_off_V\", \"v0_V\"");
    const char *unknown_c[] = { "inverter.dc_link.capacitance_F=0.002",
                                "inverter.dc_link.source_resistance_ohm=0.05",
                                "inverter.dc_link.v_0_V=10" };
    expect_error(unknown_c, 3, SCN_ERR_UNKNOWN_KEY, "inverter.dc_link.v_0_V",
                 "\"brake_off_V\", \"v0_V\"");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_absent_is_stiff_bus),
        cmocka_unit_test(test_full_link_maps_to_config),
        cmocka_unit_test(test_invalid_links_name_the_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
