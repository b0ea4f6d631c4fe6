/* A firmware configuration that mc_config_validate() rejects names the keys
 * of the rule it breaks (firmware_blame.h), never a key unrelated to it:
 * the NAM rule "speed bandwidth <= half the PLL bandwidth" and each rule
 * between blocks of firmware/app/config.c. Each suggested value is checked
 * against the rule's bound computed here, and loading with it alone must
 * succeed. */
#include "mc_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/scenario.h"

/* The paper 001 motor (amplitude-invariant), default plant and firmware
 * limits: i_max 10 A, current limit 11 A, trip 20 A, omega_max 40 rad/s,
 * overspeed 48 rad/s, v_dc_max 60 V, PLL 100 rad/s, speed loop 50 rad/s. */
#define PSI_WB     0.17
#define POLE_PAIRS 3.0
#define SQRT3      1.7320508075688772

static const char *doc(const char *estimator)
{
    static char text[512];
    snprintf(text, sizeof text,
             "{\"format_version\": 2, \"duration_s\": 1,"
             " \"motor\": {\"R_ohm\": 0.225, \"Ld_H\": 0.0038, \"psi_Wb\": 0.17,"
             " \"pole_pairs\": 3, \"J_kgm2\": 0.012},"
             " \"firmware\": {\"controller\": \"foc_pi\", \"estimator\": \"%s\"},"
             " \"reference\": {\"mode\": \"speed\", \"speed_rad_s\": 0}}",
             estimator);
    return text;
}

static scenario_t scn; /* large: off the stack */
static scn_error_t err;

static bool load(const char *estimator, const char *const *set, size_t n)
{
    return scenario_load_text(doc(estimator), "b.json", set, n, &scn, &err);
}

/* The value the message suggests for key ("... e.g. <key> = <v> or ..."). */
static double suggested(const char *key)
{
    char pattern[96];
    snprintf(pattern, sizeof pattern, " %s = ", key);
    const char *at = strstr(err.expected, pattern);
    if (at == NULL) {
        fail_msg("no value suggested for %s in: %s", key, err.expected);
    }
    return strtod(at + strlen(pattern), NULL);
}

/* The rejected set with key changed to the suggested value loads. */
static void suggestion_is_valid(const char *estimator, const char *const *set, size_t n,
                                const char *key, double value)
{
    char assignment[128];
    snprintf(assignment, sizeof assignment, "firmware.%s=%.9g", key, value);
    const char *changed[8];
    assert_true(n < 8);
    memcpy(changed, set, n * sizeof set[0]);
    changed[n] = assignment; /* a later --set wins */
    if (!scenario_load_text(doc(estimator), "b.json", changed, n + 1, &scn, &err)) {
        char line[2048];
        scenario_error_format(&err, line, sizeof line);
        fail_msg("%s alone should make it valid: %s", assignment, line);
    }
}

static void rejected_at(const char *estimator, const char *const *set, size_t n, const char *path)
{
    assert_false(load(estimator, set, n));
    assert_int_equal(err.code, SCN_ERR_INVALID);
    assert_string_equal(err.path, path);
    assert_null(strstr(err.path, "estimator"));
    assert_null(strstr(err.path, "controller"));
}

/* NAM (foc_pi + flux_pll): w_s <= 0.5 w_pll. Speed 60, PLL 80: neither
 * default alone (50, 100) satisfies the rule, so the old reader blamed
 * firmware.estimator (the encoder would be valid). */
static void nam_bandwidth_rule_names_both_keys(void **state)
{
    (void)state;
    const char *set[] = { "firmware.foc_pi.speed_bandwidth_rad_s=60",
                          "firmware.flux_pll.bandwidth_rad_s=80" };
    rejected_at("flux_pll", set, 2,
                "firmware.foc_pi.speed_bandwidth_rad_s, firmware.flux_pll.bandwidth_rad_s");
    assert_string_equal(err.found,
                        "foc_pi.speed_bandwidth_rad_s = 60, flux_pll.bandwidth_rad_s = 80");
    const double w_s = suggested("foc_pi.speed_bandwidth_rad_s");
    const double w_pll = suggested("flux_pll.bandwidth_rad_s");
    assert_true(w_s <= 0.5 * 80.0 && w_s >= 0.9 * 0.5 * 80.0);     /* near the bound, 40 */
    assert_true(w_pll >= 60.0 / 0.5 && w_pll <= 1.1 * 60.0 / 0.5); /* 120 */
    suggestion_is_valid("flux_pll", set, 2, "foc_pi.speed_bandwidth_rad_s", w_s);
    suggestion_is_valid("flux_pll", set, 2, "flux_pll.bandwidth_rad_s", w_pll);
    /* only the speed loop given: the PLL key is named too, as a default */
    const char *speed_only[] = { "firmware.foc_pi.speed_bandwidth_rad_s=60" };
    rejected_at("flux_pll", speed_only, 1,
                "firmware.foc_pi.speed_bandwidth_rad_s, firmware.flux_pll.bandwidth_rad_s");
    assert_string_equal(err.found, "foc_pi.speed_bandwidth_rad_s = 60, "
                                   "flux_pll.bandwidth_rad_s = 100 (default)");
}

/* i_max <= the current-limit level (11 A) and below the trip (20 A). */
static void current_limit_rule(void **state)
{
    (void)state;
    const char *set[] = { "firmware.limits.i_max_A=15" };
    rejected_at("encoder", set, 1, "firmware.limits.i_max_A, firmware.protection.current_limit_A");
    const double i_max = suggested("limits.i_max_A");
    const double limit = suggested("protection.current_limit_A");
    assert_true(i_max <= 11.0 && i_max >= 10.0);
    assert_true(limit >= 15.0 && limit < 20.0);
    suggestion_is_valid("encoder", set, 1, "limits.i_max_A", i_max);
    suggestion_is_valid("encoder", set, 1, "protection.current_limit_A", limit);
    /* the current limit above the trip level */
    const char *over_trip[] = { "firmware.protection.current_limit_A=25" };
    rejected_at("encoder", over_trip, 1,
                "firmware.protection.current_limit_A, firmware.protection.i_trip_A");
    assert_true(suggested("protection.current_limit_A") < 20.0);
    assert_true(suggested("protection.i_trip_A") > 25.0);
}

/* Overspeed above omega_max, and its line back-EMF sqrt(3) n_p psi w below
 * the over-voltage trip. */
static void overspeed_rules(void **state)
{
    (void)state;
    const double w_bus = 60.0 / (SQRT3 * POLE_PAIRS * PSI_WB); /* 67.9 rad/s */
    const char *low[] = { "firmware.protection.overspeed_rad_s=35" };
    rejected_at("encoder", low, 1,
                "firmware.protection.overspeed_rad_s, firmware.limits.omega_max_rad_s");
    const double over = suggested("protection.overspeed_rad_s");
    assert_true(over > 40.0 && over < w_bus);
    assert_true(suggested("limits.omega_max_rad_s") < 35.0);
    suggestion_is_valid("encoder", low, 1, "protection.overspeed_rad_s", over);
    const char *high[] = { "firmware.protection.overspeed_rad_s=70" };
    rejected_at("encoder", high, 1,
                "firmware.protection.overspeed_rad_s, firmware.protection.v_dc_max_V");
    const double over_max = suggested("protection.overspeed_rad_s");
    const double v_dc_max = suggested("protection.v_dc_max_V");
    assert_true(over_max < w_bus && over_max > 0.99 * w_bus);
    assert_true(v_dc_max > SQRT3 * POLE_PAIRS * PSI_WB * 70.0); /* 61.8 V */
    suggestion_is_valid("encoder", high, 1, "protection.v_dc_max_V", v_dc_max);
}

/* Sensorless: the alignment vector and its damping current within i_max:
 * current_A^2 + i_q_max_A^2 <= i_max^2. */
static void alignment_current_rule(void **state)
{
    (void)state;
    const char *set[] = { "firmware.align.current_A=9", "firmware.align.i_q_max_A=5" };
    rejected_at("flux_pll", set, 2,
                "firmware.align.current_A, firmware.align.i_q_max_A, firmware.limits.i_max_A");
    const double current = suggested("align.current_A");
    const double i_q_max = suggested("align.i_q_max_A");
    const double i_max = suggested("limits.i_max_A");
    assert_true(current * current + 25.0 <= 100.0);
    assert_true(81.0 + i_q_max * i_q_max <= 100.0);
    assert_true(i_max * i_max >= 81.0 + 25.0 && i_max <= 11.0);
    suggestion_is_valid("flux_pll", set, 2, "align.current_A", current);
    suggestion_is_valid("flux_pll", set, 2, "align.i_q_max_A", i_q_max);
    suggestion_is_valid("flux_pll", set, 2, "limits.i_max_A", i_max);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(nam_bandwidth_rule_names_both_keys),
        cmocka_unit_test(current_limit_rule),
        cmocka_unit_test(overspeed_rules),
        cmocka_unit_test(alignment_current_rule),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
