/* Physical inputs bounded over the whole run (scenario_bounds.c): the load
 * torque within 1000 x the motor's torque at the drive's trip current, the
 * bus voltage within the format's 1e5 V, each checked on the largest value
 * the profile can reach in the run (points, sines, polynomial, noise). */
#include "mc_test.h"

#include <stdio.h>
#include <string.h>

#include "sim/scenario.h"

/* Paper 001 motor, amplitude-invariant: 1.5 n_p psi i_trip = 1.5 x 3 x
 * 0.17 Wb x 20 A (the default trip) = 15.3 N m; the bound 15300 N m. */
#define TAU_BOUND_NM (1000.0 * 1.5 * 3.0 * 0.17 * 20.0)

static const char *doc(double duration_s, const char *load)
{
    static char text[768];
    snprintf(text, sizeof text,
             "{\"format_version\": 2, \"duration_s\": %g,"
             " \"motor\": {\"R_ohm\": 0.225, \"Ld_H\": 0.0038, \"psi_Wb\": 0.17,"
             " \"pole_pairs\": 3, \"J_kgm2\": 0.012},"
             " \"disturbances\": {\"load_torque_Nm\": %s},"
             " \"reference\": {\"mode\": \"speed\", \"speed_rad_s\": 0}}",
             duration_s, load);
    return text;
}

static scenario_t scn;
static scn_error_t err;

static bool load(double duration_s, const char *load_profile, const char *set)
{
    const char *overrides[] = { set };
    return scenario_load_text(doc(duration_s, load_profile), "b.json", overrides,
                              set != NULL ? 1u : 0u, &scn, &err);
}

static void expect_load_rejected(double duration_s, const char *profile, const char *reach)
{
    assert_false(load(duration_s, profile, NULL));
    assert_int_equal(err.code, SCN_ERR_RANGE);
    assert_string_equal(err.path, "disturbances.load_torque_Nm");
    char bound[64];
    snprintf(bound, sizeof bound, "within +-%.4g N m over the run", TAU_BOUND_NM);
    assert_non_null(strstr(err.expected, bound));
    assert_non_null(strstr(err.expected, "trip current"));
    assert_non_null(strstr(err.found, reach));
}

static void load_torque_bound(void **state)
{
    (void)state;
    /* the reported value, and just above the bound */
    expect_load_rejected(1.0, "9e24", "can reach 9e+24 N m");
    expect_load_rejected(1.0, "15301", "can reach 1.53e+04 N m");
    assert_true(load(1.0, "15300", NULL));
    assert_true(load(1.0, "-15300", NULL));
    /* parts add up: 10000 + a 6000 N m sine can reach 16000 N m */
    expect_load_rejected(1.0,
                         "{\"points\": [[0, 10000]], \"sines\": [{\"amplitude\": -6000,"
                         " \"freq_Hz\": 1}]}",
                         "can reach 1.6e+04 N m");
    /* 10 t^2 N m from t = 1 s: 10 x (30 - 1)^2 = 8410 N m within 30 s,
     * 10 x (50 - 1)^2 = 24010 N m within 50 s */
    const char *poly = "{\"poly\": {\"coeffs\": [0, 0, 10], \"t_start_s\": 1}}";
    assert_true(load(30.0, poly, NULL));
    expect_load_rejected(50.0, poly, "can reach 2.401e+04 N m");
    /* noise peaks at rms sqrt(2 x 16 tones): 3000 N m rms -> 16971 N m */
    expect_load_rejected(1.0, "{\"noise\": {\"rms\": 3000, \"cutoff_Hz\": 50}}",
                         "can reach 1.697e+04 N m");
    /* the bound follows the trip current: 16 A instead of 20 A */
    assert_false(load(1.0, "13000", "firmware.protection.i_trip_A=16"));
    assert_string_equal(err.path, "disturbances.load_torque_Nm");
    char bound[64];
    snprintf(bound, sizeof bound, "within +-%.4g N m", TAU_BOUND_NM * 16.0 / 20.0);
    assert_non_null(strstr(err.expected, bound));
}

static void bus_voltage_bound(void **state)
{
    (void)state;
    assert_true(load(1.0, "0", "inverter.v_dc_V=1e5"));
    assert_false(load(1.0, "0", "inverter.v_dc_V=1.0001e5"));
    assert_int_equal(err.code, SCN_ERR_RANGE);
    assert_string_equal(err.path, "inverter.v_dc_V");
    assert_non_null(strstr(err.expected, "within +-1e+05 V over the run"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(load_torque_bound),
        cmocka_unit_test(bus_voltage_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
