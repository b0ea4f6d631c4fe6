/*
 * The sensor-fault and plant-fault kinds of the scenario's
 * "fault_injections" (scenario_injections.c): each maps to its engine
 * injection (sim_engine.h) with its own keys only, every bad key is
 * reported by its path, and a loaded scenario's injections change what the
 * firmware measures (the engine's trace meas) or the plant as the kinds
 * say, checked against the true plant state:
 *   rotor at rest at theta_m = 0 (true count 0, true currents 0, outputs
 *   off), n_p = 3, 1000 lines (cpr 4000): an encoder_slip of 180 deg
 *   electrical = 60 deg mechanical = 666.7 -> 667 counts; current_stuck
 *   reports its value_A; current_offset_ramp rate * (t_k - t_start);
 *   rotor coasting at 5 rev/s: encoder_frozen holds its first count while
 *   the true angle moves; encoder_count_loss advances by (1 - f) of the
 *   true advance (the true angle in counts, which is within one count of
 *   the true count's advance, so within 1 + (1 - f) counts); a rotor_lock
 *   stops it (omega_m exactly 0 from the sample after the window's first);
 * a bus_source_loss on the scenario's stiff bus is refused by the engine.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim/scenario.h"
#include "sim_engine.h"

#define CPR 4000u /* 4 x 1000 lines */

/* A small valid document: the paper 001 motor (n_p = 3; the back-EMF at
 * 5 rev/s, 28 V line peak, stays below the 48 V bus), 1000 lines, the rotor
 * at rest at theta_m = 0, fast integrator. */
static const char *const base_doc =
    "{\"format_version\": 2, \"name\": \"injections\", \"duration_s\": 1.0,\n"
    " \"motor\": {\"R_ohm\": 0.225, \"Ld_H\": 0.0038, \"psi_Wb\": 0.17, \"pole_pairs\": 3,\n"
    "           \"J_kgm2\": 0.012},\n"
    " \"sensors\": {\"encoder\": {\"lines\": 1000}},\n"
    " \"solver\": {\"substeps_per_period\": 4},\n"
    " \"reference\": {\"mode\": \"current\", \"i_q_A\": 0}}\n";

static scenario_t scn; /* large: keep it off the stack */
static scn_error_t err;
static sim_engine_t *engine;

static int setup(void **state)
{
    (void)state;
    engine = malloc(sizeof *engine);
    return engine == NULL ? -1 : 0;
}

static int teardown(void **state)
{
    (void)state;
    free(engine);
    return 0;
}

/* Load base_doc with these overrides; fail the test with the error line. */
static void load_ok(const char *const *overrides, size_t n)
{
    if (!scenario_load_text(base_doc, "t.json", overrides, n, &scn, &err)) {
        char line[1024];
        scenario_error_format(&err, line, sizeof line);
        fail_msg("%s", line);
    }
}

static void each_kind_maps_to_its_injection(void **state)
{
    (void)state;
    const char *set[] = {
        "fault_injections=["
        "{\"kind\": \"encoder_slip\", \"angle_e_rad\": -1.5, \"t_start_s\": 0.1, \"t_end_s\": 0.2},"
        "{\"kind\": \"encoder_frozen\", \"t_start_s\": 0.3},"
        "{\"kind\": \"encoder_count_loss\", \"lost_fraction\": 0.25, \"t_start_s\": 0.4},"
        "{\"kind\": \"current_offset_ramp\", \"phase\": \"c\", \"rate_A_s\": -40,"
        " \"t_start_s\": 0.5, \"t_end_s\": 0.6},"
        "{\"kind\": \"current_stuck\", \"phase\": \"b\", \"value_A\": 0, \"t_start_s\": 0.7}]",
    };
    load_ok(set, 1);
    assert_int_equal(scn.n_injections, 5);
    const sim_injection_t *inj = scn.injections;
    assert_int_equal(inj[0].kind, SIM_INJECT_ENCODER_SLIP);
    assert_true(inj[0].angle_e_rad == -1.5);
    assert_true(inj[0].t_start_s == 0.1 && inj[0].t_end_s == 0.2);
    assert_int_equal(inj[1].kind, SIM_INJECT_ENCODER_FROZEN);
    assert_true(inj[1].t_start_s == 0.3 && isinf(inj[1].t_end_s));
    assert_int_equal(inj[2].kind, SIM_INJECT_ENCODER_COUNT_LOSS);
    assert_true(inj[2].lost_fraction == 0.25);
    assert_int_equal(inj[3].kind, SIM_INJECT_CURRENT_OFFSET_RAMP);
    assert_int_equal(inj[3].phase, 2);
    assert_true(inj[3].rate_A_s == -40.0);
    assert_true(inj[3].t_start_s == 0.5 && inj[3].t_end_s == 0.6);
    assert_int_equal(inj[4].kind, SIM_INJECT_CURRENT_STUCK);
    assert_int_equal(inj[4].phase, 1);
    assert_true(inj[4].value == 0.0);

    const char *plant_side[] = {
        "fault_injections=["
        "{\"kind\": \"phase_open\", \"phase\": \"c\", \"t_start_s\": 0.1, \"t_end_s\": 0.2},"
        "{\"kind\": \"rotor_lock\", \"t_start_s\": 0.3, \"t_end_s\": 0.4},"
        "{\"kind\": \"bus_source_loss\", \"t_start_s\": 0.5}]",
    };
    load_ok(plant_side, 1);
    assert_int_equal(scn.n_injections, 3);
    assert_int_equal(inj[0].kind, SIM_INJECT_PHASE_OPEN);
    assert_int_equal(inj[0].phase, 2);
    assert_true(inj[0].t_start_s == 0.1 && inj[0].t_end_s == 0.2);
    assert_int_equal(inj[1].kind, SIM_INJECT_ROTOR_LOCK);
    assert_true(inj[1].t_start_s == 0.3 && inj[1].t_end_s == 0.4);
    assert_int_equal(inj[2].kind, SIM_INJECT_BUS_SOURCE_LOSS);
    assert_true(inj[2].t_start_s == 0.5 && isinf(inj[2].t_end_s));

    /* paper 002 Case II's changes */
    const char *case2[] = {
        "fault_injections=["
        "{\"kind\": \"current_gain\", \"phase\": \"b\", \"gain\": 0.96, \"t_start_s\": 0.2},"
        "{\"kind\": \"dead_time\", \"dead_time_s\": 7e-6, \"t_start_s\": 0.2, \"t_end_s\": 0.3}]",
    };
    load_ok(case2, 1);
    assert_int_equal(scn.n_injections, 2);
    assert_int_equal(inj[0].kind, SIM_INJECT_CURRENT_GAIN);
    assert_int_equal(inj[0].phase, 1);
    assert_true(inj[0].value == 0.96);
    assert_true(inj[0].t_start_s == 0.2 && isinf(inj[0].t_end_s));
    assert_int_equal(inj[1].kind, SIM_INJECT_DEAD_TIME);
    assert_true(inj[1].value == 7e-6);
    assert_true(inj[1].t_start_s == 0.2 && inj[1].t_end_s == 0.3);
}

typedef struct {
    const char *injections; /* the override "fault_injections=[...]" */
    scn_status_t code;
    const char *path;
    const char *expected_part; /* NULL: not checked */
} error_case_t;

/* Two valid entries, then the one under test at index 2. */
#define TWO_VALID                                                                                  \
    "fault_injections=[{\"kind\": \"encoder_frozen\", \"t_start_s\": 0},"                          \
    "{\"kind\": \"fault_input\", \"t_start_s\": 0}, "

static const error_case_t error_cases[] = {
    { TWO_VALID "{\"kind\": \"encoder_count_loss\", \"lost_fraction\": 1, \"t_start_s\": 0}]",
      SCN_ERR_RANGE, "fault_injections[2].lost_fraction", "(0, 1)" },
    { TWO_VALID "{\"kind\": \"encoder_count_loss\", \"lost_fraction\": 0, \"t_start_s\": 0}]",
      SCN_ERR_RANGE, "fault_injections[2].lost_fraction", "(0, 1)" },
    { TWO_VALID "{\"kind\": \"encoder_count_loss\", \"t_start_s\": 0}]", SCN_ERR_MISSING,
      "fault_injections[2].lost_fraction", NULL },
    { TWO_VALID "{\"kind\": \"encoder_slip\", \"t_start_s\": 0}]", SCN_ERR_MISSING,
      "fault_injections[2].angle_e_rad", NULL },
    { TWO_VALID "{\"kind\": \"encoder_slip\", \"angle_e_rad\": 1e999, \"t_start_s\": 0}]",
      SCN_ERR_NONFINITE, "fault_injections[2].angle_e_rad", NULL },
    { TWO_VALID "{\"kind\": \"encoder_slip\", \"angle_e_rad\": 2000, \"t_start_s\": 0}]",
      SCN_ERR_RANGE, "fault_injections[2].angle_e_rad", "[-1000, 1000]" },
    { TWO_VALID "{\"kind\": \"current_offset_ramp\", \"rate_A_s\": 1, \"t_start_s\": 0}]",
      SCN_ERR_MISSING, "fault_injections[2].phase", NULL },
    { TWO_VALID "{\"kind\": \"current_offset_ramp\", \"phase\": \"d\", \"rate_A_s\": 1,"
                " \"t_start_s\": 0}]",
      SCN_ERR_RANGE, "fault_injections[2].phase", NULL },
    { TWO_VALID "{\"kind\": \"current_offset_ramp\", \"phase\": \"a\", \"rate_A_s\": \"fast\","
                " \"t_start_s\": 0}]",
      SCN_ERR_TYPE, "fault_injections[2].rate_A_s", NULL },
    { TWO_VALID "{\"kind\": \"current_stuck\", \"phase\": \"a\", \"t_start_s\": 0}]",
      SCN_ERR_MISSING, "fault_injections[2].value_A", NULL },
    { TWO_VALID "{\"kind\": \"current_stuck\", \"phase\": \"a\", \"value_A\": 1e6,"
                " \"t_start_s\": 0}]",
      SCN_ERR_RANGE, "fault_injections[2].value_A", NULL },
    /* each kind takes only its own keys */
    { TWO_VALID "{\"kind\": \"current_stuck\", \"phase\": \"a\", \"value_A\": 1, \"offset_A\": 1,"
                " \"t_start_s\": 0}]",
      SCN_ERR_UNKNOWN_KEY, "fault_injections[2].offset_A", NULL },
    { TWO_VALID "{\"kind\": \"encoder_frozen\", \"angle_e_rad\": 1, \"t_start_s\": 0}]",
      SCN_ERR_UNKNOWN_KEY, "fault_injections[2].angle_e_rad", NULL },
    { TWO_VALID "{\"kind\": \"encoder_slip\", \"phase\": \"a\", \"angle_e_rad\": 1,"
                " \"t_start_s\": 0}]",
      SCN_ERR_UNKNOWN_KEY, "fault_injections[2].phase", NULL },
    { TWO_VALID "{\"kind\": \"encoder_count_loss\", \"lost_fraction\": 0.5, \"rate_A_s\": 1,"
                " \"t_start_s\": 0}]",
      SCN_ERR_UNKNOWN_KEY, "fault_injections[2].rate_A_s", NULL },
    { TWO_VALID "{\"kind\": \"phase_open\", \"t_start_s\": 0}]", SCN_ERR_MISSING,
      "fault_injections[2].phase", NULL },
    { TWO_VALID "{\"kind\": \"rotor_lock\", \"phase\": \"a\", \"t_start_s\": 0}]",
      SCN_ERR_UNKNOWN_KEY, "fault_injections[2].phase", NULL },
    { TWO_VALID "{\"kind\": \"bus_source_loss\", \"v_dc_V\": 0, \"t_start_s\": 0}]",
      SCN_ERR_UNKNOWN_KEY, "fault_injections[2].v_dc_V", NULL },
    { TWO_VALID "{\"kind\": \"current_gain\", \"phase\": \"a\", \"gain\": 0, \"t_start_s\": 0}]",
      SCN_ERR_RANGE, "fault_injections[2].gain", "(0, 10]" },
    { TWO_VALID "{\"kind\": \"current_gain\", \"gain\": 1.05, \"t_start_s\": 0}]", SCN_ERR_MISSING,
      "fault_injections[2].phase", NULL },
    { TWO_VALID "{\"kind\": \"dead_time\", \"dead_time_s\": 2e-4, \"t_start_s\": 0}]",
      SCN_ERR_RANGE, "fault_injections[2].dead_time_s", "[0, 0.0001]" },
    { TWO_VALID "{\"kind\": \"dead_time\", \"phase\": \"a\", \"dead_time_s\": 1e-6,"
                " \"t_start_s\": 0}]",
      SCN_ERR_UNKNOWN_KEY, "fault_injections[2].phase", NULL },
    { TWO_VALID "{\"kind\": \"encoder_lost\", \"t_start_s\": 0}]", SCN_ERR_RANGE,
      "fault_injections[2].kind", "encoder_count_loss" },
    { TWO_VALID "{\"kind\": \"current_stuck\", \"phase\": \"a\", \"value_A\": 1, \"t_start_s\": 2,"
                " \"t_end_s\": 1}]",
      SCN_ERR_INVALID, "fault_injections[2].t_end_s", NULL },
};

static void bad_keys_are_reported_by_path(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof error_cases / sizeof error_cases[0]; ++i) {
        const error_case_t *c = &error_cases[i];
        assert_false(scenario_load_text(base_doc, "t.json", &c->injections, 1, &scn, &err));
        assert_int_equal(err.code, c->code);
        assert_string_equal(err.path, c->path);
        if (c->expected_part != NULL) {
            assert_non_null(strstr(err.expected, c->expected_part));
        }
    }
}

/* The engine on the loaded scenario with its injections. */
static void start_engine(void)
{
    assert_int_equal(sim_engine_init(engine, &scn.plant, &scn.firmware), SIM_ENGINE_OK);
    for (size_t i = 0; i < scn.n_injections; ++i) {
        assert_int_equal(sim_engine_add_injection(engine, &scn.injections[i]), SIM_ENGINE_OK);
    }
}

/* One period with the outputs off. */
static const sim_trace_sample_t *step_off(void)
{
    const mc_command_t off = { .enable = false, .mode = MC_MODE_CURRENT };
    assert_int_equal(sim_engine_step(engine, &off), SIM_ENGINE_OK);
    const sim_trace_sample_t *s = sim_engine_last(engine);
    assert_false(s->outputs_applied);
    return s;
}

static bool active(const sim_trace_sample_t *s, uint32_t i)
{
    return (s->injections_active & (1u << i)) != 0u;
}

static void faults_at_rest_reach_the_measurement(void **state)
{
    (void)state;
    const char *set[] = {
        "fault_injections=["
        "{\"kind\": \"encoder_slip\", \"angle_e_rad\": 3.141592653589793,"
        " \"t_start_s\": 0.01002, \"t_end_s\": 0.02002},"
        "{\"kind\": \"current_stuck\", \"phase\": \"a\", \"value_A\": 1.5,"
        " \"t_start_s\": 0.00502, \"t_end_s\": 0.01502},"
        "{\"kind\": \"current_offset_ramp\", \"phase\": \"c\", \"rate_A_s\": 100,"
        " \"t_start_s\": 0.00002, \"t_end_s\": 0.02502}]",
    };
    load_ok(set, 1);
    start_engine();
    int n_active[3] = { 0 };
    for (int k = 0; k < 600; ++k) { /* 30 ms */
        const sim_trace_sample_t *s = step_off();
        /* the truth: at rest at 0, no current */
        assert_true(s->plant.theta_m_rad == 0.0);
        for (int x = 0; x < 3; ++x) {
            assert_true(s->plant.i_abc_A[x] == 0.0);
        }
        /* samples 201 .. 400: 180 deg electrical = 667 counts */
        const bool slip = k >= 201 && k <= 400;
        assert_int_equal(active(s, 0u), slip);
        assert_int_equal(s->meas.encoder_count, slip ? 667u : 0u);
        /* samples 101 .. 300: stuck at 1.5 A */
        const bool stuck = k >= 101 && k <= 300;
        assert_int_equal(active(s, 1u), stuck);
        assert_true(s->meas.i_abc_A[0] == (stuck ? 1.5 : 0.0));
        assert_true(s->meas.i_abc_A[1] == 0.0);
        /* samples 1 .. 500: 100 A/s from 20 us: 3 mA at sample 1, then
         * 5 mA more per sample */
        const bool ramp = k >= 1 && k <= 500;
        assert_int_equal(active(s, 2u), ramp);
        const double ramp_A = ramp ? 0.003 + 0.005 * (k - 1) : 0.0;
        assert_true(fabs(s->meas.i_abc_A[2] - ramp_A) < 1e-12);
        for (uint32_t i = 0; i < 3; ++i) {
            n_active[i] += active(s, i) ? 1 : 0;
        }
    }
    assert_int_equal(n_active[0], 200);
    assert_int_equal(n_active[1], 200);
    assert_int_equal(n_active[2], 500);
}

/* The true angle in counts, theta_m * cpr / (2 pi) (encoder offset 0),
 * unwrapped. */
static double angle_counts(const sim_trace_sample_t *s)
{
    return s->plant.theta_m_rad * CPR / (2.0 * MC_TEST_PI);
}

/* How far count a is ahead of the reported count, the shorter way round
 * the wheel: (-cpr/2, cpr/2]. */
static double counts_above_reported(double a, const sim_trace_sample_t *s)
{
    const double d = fmod(a - (double)s->meas.encoder_count, CPR);
    return d > 0.5 * CPR ? d - CPR : (d <= -0.5 * CPR ? d + CPR : d);
}

static void encoder_faults_on_a_coasting_rotor(void **state)
{
    (void)state;
    const char *set[] = {
        "initial.omega_m_rad_s=31.41592653589793", /* 5 rev/s */
        "fault_injections=["
        "{\"kind\": \"encoder_frozen\", \"t_start_s\": 0.01002, \"t_end_s\": 0.05002},"
        "{\"kind\": \"encoder_count_loss\", \"lost_fraction\": 0.4, \"t_start_s\": 0.06002,"
        " \"t_end_s\": 0.49002}]",
    };
    load_ok(set, 2);
    start_engine();
    uint32_t held = 0u;
    double theta_frozen_rad = 0.0;
    uint32_t loss_start_count = 0u;
    double loss_start_angle_counts = 0.0;
    double loss_turns = 0.0;
    for (int k = 0; k <= 10000; ++k) { /* to 0.5 s */
        const sim_trace_sample_t *s = step_off();
        if (k == 201) { /* the first frozen sample */
            assert_int_equal(s->injections_active, 1u);
            held = s->meas.encoder_count;
            theta_frozen_rad = s->plant.theta_m_rad;
        }
        if (active(s, 0u)) {
            assert_in_range(k, 201, 1000);
            assert_int_equal(s->meas.encoder_count, held);
            /* the true angle moves on: 0.2 turns while frozen */
            if (k == 1000) {
                const double turns = (s->plant.theta_m_rad - theta_frozen_rad) / (2.0 * MC_TEST_PI);
                assert_true(fabs(turns - 0.2) < 1e-3);
            }
        }
        if (k == 1201) { /* the first count-loss sample */
            assert_int_equal(s->injections_active, 2u);
            loss_start_count = s->meas.encoder_count;
            loss_start_angle_counts = angle_counts(s);
        }
        if (active(s, 1u)) {
            const double true_advance = angle_counts(s) - loss_start_angle_counts;
            const double expected = loss_start_count + 0.6 * true_advance;
            assert_true(fabs(counts_above_reported(expected, s)) < 1.6);
            loss_turns = true_advance / CPR;
        }
        if (s->injections_active == 0u) {
            /* the true count: the angle in counts rounded down */
            const double above = counts_above_reported(angle_counts(s), s);
            assert_true(above > -1e-9 && above < 1.0);
        }
    }
    assert_true(loss_turns > 2.1); /* samples 1201 .. 9800 */
}

static void plant_faults_from_the_scenario(void **state)
{
    (void)state;
    const char *lock[] = {
        "initial.omega_m_rad_s=31.41592653589793", /* 5 rev/s */
        "fault_injections=[{\"kind\": \"rotor_lock\", \"t_start_s\": 0.01002,"
        " \"t_end_s\": 0.02002}]",
    };
    load_ok(lock, 2);
    start_engine();
    int n_locked = 0;
    for (int k = 0; k < 600; ++k) {
        const sim_trace_sample_t *s = step_off();
        /* set at samples 201 .. 400, in the true state of 202 .. 401 */
        const bool locked = k >= 202 && k <= 401;
        assert_int_equal(s->plant.rotor_locked, locked);
        if (locked) {
            assert_true(s->plant.omega_m_rad_s == 0.0);
            n_locked++;
        } else {
            /* coasting (before) or free again from rest (after) */
            assert_true(s->plant.omega_m_rad_s == (k < 202 ? 10.0 * MC_TEST_PI : 0.0));
        }
    }
    assert_int_equal(n_locked, 200);

    /* the scenario's bus is stiff (no dc_link capacitance) */
    const char *loss[] = { "fault_injections=[{\"kind\": \"bus_source_loss\", \"t_start_s\": 0}]" };
    load_ok(loss, 1);
    assert_int_equal(sim_engine_init(engine, &scn.plant, &scn.firmware), SIM_ENGINE_OK);
    assert_int_equal(sim_engine_add_injection(engine, &scn.injections[0]),
                     SIM_ENGINE_ERR_INJECTION);
    assert_non_null(strstr(sim_engine_message(engine), "dc_link.capacitance_F"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(each_kind_maps_to_its_injection),
        cmocka_unit_test(bad_keys_are_reported_by_path),
        cmocka_unit_test(faults_at_rest_reach_the_measurement),
        cmocka_unit_test(encoder_faults_on_a_coasting_rotor),
        cmocka_unit_test(plant_faults_from_the_scenario),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
