/*
 * Measurement-side sensor faults (sim_engine.h): what the firmware is given
 * (the trace's meas) against the truth.
 *
 * Encoder kinds: the rotor coasts (outputs off, no friction, no load), and a
 * second plant with the same configuration, stepped alongside with the same
 * inverter inputs, gives the count the plant's encoder reports for the true
 * angle without any injection (its state is checked bit-equal to the
 * engine's true state). The default plant has n_p = 3 and 2500 lines
 * (cpr = 10000):
 *   encoder_slip reports (true + N) mod cpr with N = round(angle_e / n_p
 *     * cpr / (2 pi)): 90 deg electrical = 30 deg mechanical = 833.3 ->
 *     833 counts, 180 deg = 1666.7 -> 1667, -90 deg -> -833 = 9167 mod
 *     cpr, 90 deg + one mechanical turn (6 pi electrical) -> 833;
 *   encoder_frozen reports the true count of its first active sample while
 *     the rotor turns on;
 *   encoder_count_loss reports (1 - f) of the true increments, rounded down,
 *     over ten turns forward and backward.
 * Current kinds: the drive runs a current loop on a locked rotor (ideal
 * sensors: the plant measures the true current exactly), and the measured
 * current of the injected phase is the true one with the offset ramp
 * rate * (t_k - t_start) added or the stuck value in place; the other
 * phases stay exact. Every kind is inactive outside t_start <= t_k < t_end.
 * sim_engine_add_injection rejects each kind's invalid fields by name.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_engine.h"

#define CPR 10000u /* 4 x the default 2500 lines */

static sim_engine_t *engine; /* about 6.5 kB: on the heap */
static plant_t *reference;   /* the plant without injections */
static plant_config_t pc;
static mc_config_t fc;

static int setup(void **state)
{
    (void)state;
    engine = malloc(sizeof *engine);
    reference = malloc(sizeof *reference);
    return (engine == NULL || reference == NULL) ? -1 : 0;
}

static int teardown(void **state)
{
    (void)state;
    free(engine);
    free(reference);
    return 0;
}

static bool in_window(const sim_injection_t *inj, double t_s)
{
    return t_s >= inj->t_start_s && t_s < inj->t_end_s;
}

/* ---- Encoder kinds: a coasting rotor ------------------------------------ */

/* Default plant (fast integrator) coasting at omega_m0 from theta_m0, the
 * engine on it with the default firmware, and the reference plant. At
 * 5 rev/s the peak line back-EMF (28 V) stays below the 48 V bus, so the
 * open inverter conducts nothing and the rotor keeps its speed. */
static void start_coasting(double theta_m0_rad, double omega_m0_rad_s)
{
    plant_config_default(&pc);
    pc.substeps_per_period = PLANT_SUBSTEPS_FAST;
    pc.theta_m0_rad = theta_m0_rad;
    pc.omega_m0_rad_s = omega_m0_rad_s;
    mc_config_init_default(&fc);
    sim_engine_firmware_from_plant(&pc, &fc);
    assert_int_equal(fc.encoder.counts_per_rev, CPR);
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
    assert_int_equal(plant_init(reference, &pc), PLANT_OK);
}

/* One period of both; returns the engine's trace sample and sets *true_count
 * to the reference plant's count at the same instant. */
static const sim_trace_sample_t *coast_step(uint32_t *true_count)
{
    const mc_command_t off = { .enable = false, .mode = MC_MODE_CURRENT };
    const plant_true_state_t *r = plant_true_state(reference);
    plant_measurement_t m;
    plant_sample(reference, &m);
    assert_int_equal(sim_engine_step(engine, &off), SIM_ENGINE_OK);
    const sim_trace_sample_t *s = sim_engine_last(engine);
    /* the same plant state at the same instant */
    assert_true(s->t_s == r->t_s && s->plant.theta_m_rad == r->theta_m_rad &&
                s->plant.omega_m_rad_s == r->omega_m_rad_s);
    assert_false(s->outputs_applied);
    assert_true(s->meas.encoder_count < CPR);
    plant_advance(reference, s->duty_applied, s->outputs_applied);
    *true_count = m.encoder_count;
    return s;
}

/* The shorter way from count a to count b (-cpr/2 < d <= cpr/2). */
static int32_t count_step(uint32_t a, uint32_t b)
{
    int32_t d = (int32_t)((b + CPR - a) % CPR);
    return d > (int32_t)(CPR / 2u) ? d - (int32_t)CPR : d;
}

typedef struct {
    double angle_e_rad;
    uint32_t slip_counts; /* expected, worked out by hand (file header) */
} slip_case_t;

static void encoder_slip_shifts_by_whole_counts(void **state)
{
    (void)state;
    const slip_case_t cases[] = {
        { 0.5 * MC_TEST_PI, 833u },
        { MC_TEST_PI, 1667u },
        { -0.5 * MC_TEST_PI, 9167u },
        { 6.5 * MC_TEST_PI, 833u },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        /* 5 rev/s from just before the index: the count wraps in the window */
        start_coasting(2.0 * MC_TEST_PI - 0.2, 10.0 * MC_TEST_PI);
        const sim_injection_t slip = { .kind = SIM_INJECT_ENCODER_SLIP,
                                       .t_start_s = 0.00202, /* between samples */
                                       .t_end_s = 0.03002,
                                       .phase = 99u, /* not a current kind: unused */
                                       .angle_e_rad = cases[c].angle_e_rad };
        assert_int_equal(sim_engine_add_injection(engine, &slip), SIM_ENGINE_OK);
        int n_active = 0;
        int n_wrapped = 0;              /* active samples with true + slip >= cpr */
        for (int k = 0; k < 800; ++k) { /* 40 ms */
            uint32_t true_count;
            const sim_trace_sample_t *s = coast_step(&true_count);
            const bool active = in_window(&slip, s->t_s);
            assert_int_equal(s->injections_active, active ? 1u : 0u);
            const uint32_t expected =
                active ? (true_count + cases[c].slip_counts) % CPR : true_count;
            assert_int_equal(s->meas.encoder_count, expected);
            if (active) {
                n_wrapped += (true_count + cases[c].slip_counts >= CPR) ? 1 : 0;
                n_active++;
            }
        }
        assert_int_equal(n_active, 560); /* samples 41 .. 600 */
        /* both sides of the wrap at cpr */
        assert_true(n_wrapped > 0 && n_wrapped < n_active);
    }
}

static void encoder_frozen_holds_the_first_active_count(void **state)
{
    (void)state;
    start_coasting(1.0, 10.0 * MC_TEST_PI);
    const sim_injection_t frozen = { .kind = SIM_INJECT_ENCODER_FROZEN,
                                     .t_start_s = 0.01002, /* between samples */
                                     .t_end_s = 0.25002 };
    assert_int_equal(sim_engine_add_injection(engine, &frozen), SIM_ENGINE_OK);
    bool started = false;
    uint32_t held = 0u;
    double theta_at_start_rad = 0.0;
    double t_last_s = 0.0;
    const sim_trace_sample_t *s = NULL;
    for (int k = 0; k < 6000; ++k) { /* 0.3 s */
        uint32_t true_count;
        s = coast_step(&true_count);
        const bool active = in_window(&frozen, s->t_s);
        assert_int_equal(s->injections_active, active ? 1u : 0u);
        if (active && !started) {
            started = true;
            assert_true(fabs(s->t_s - 0.01005) < 1e-12); /* sample 201 */
            held = true_count;
            theta_at_start_rad = s->plant.theta_m_rad;
        }
        assert_int_equal(s->meas.encoder_count, active ? held : true_count);
        if (active) {
            t_last_s = s->t_s;
        }
    }
    assert_true(started);
    assert_true(fabs(t_last_s - 0.25) < 1e-12); /* sample 5000 */
    /* more than a turn while frozen */
    const double turns = (s->plant.theta_m_rad - theta_at_start_rad) / (2.0 * MC_TEST_PI);
    assert_true(turns > 1.4);
}

typedef struct {
    double lost_fraction;
    double omega_m_rad_s;
} loss_case_t;

static void encoder_count_loss_keeps_the_fraction(void **state)
{
    (void)state;
    const loss_case_t cases[] = {
        { 0.3, 10.0 * MC_TEST_PI },   /* 5 rev/s forward */
        { 0.75, -10.0 * MC_TEST_PI }, /* backward */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        start_coasting(0.5, cases[c].omega_m_rad_s);
        const sim_injection_t loss = { .kind = SIM_INJECT_ENCODER_COUNT_LOSS,
                                       .t_start_s = 0.01002,
                                       .t_end_s = 2.02002,
                                       .lost_fraction = cases[c].lost_fraction };
        assert_int_equal(sim_engine_add_injection(engine, &loss), SIM_ENGINE_OK);
        const double kept = 1.0 - cases[c].lost_fraction;
        bool started = false;
        int64_t true_advance = 0;     /* counts since the first active sample */
        int64_t reported_advance = 0; /* likewise, what the firmware got */
        uint32_t true_prev = 0u;
        uint32_t reported_prev = 0u;
        double theta_at_start_rad = 0.0;
        for (int k = 0; k < 40800; ++k) { /* 2.04 s */
            uint32_t true_count;
            const sim_trace_sample_t *s = coast_step(&true_count);
            const bool active = in_window(&loss, s->t_s);
            assert_int_equal(s->injections_active, active ? 1u : 0u);
            if (!active) {
                assert_int_equal(s->meas.encoder_count, true_count);
                continue;
            }
            if (!started) {
                started = true;
                assert_int_equal(s->meas.encoder_count, true_count); /* nothing lost yet */
                theta_at_start_rad = s->plant.theta_m_rad;
            } else {
                true_advance += count_step(true_prev, true_count);
                reported_advance += count_step(reported_prev, s->meas.encoder_count);
            }
            true_prev = true_count;
            reported_prev = s->meas.encoder_count;
            /* the reference counts the true angle (within a count) */
            const double true_counts =
                (s->plant.theta_m_rad - theta_at_start_rad) * CPR / (2.0 * MC_TEST_PI);
            assert_true(fabs((double)true_advance - true_counts) < 1.0);
            /* the kept share of the increments, rounded down: within one
             * count below it (1e-9: kept = 1 - f is not exact in binary) */
            const double short_by = kept * (double)true_advance - (double)reported_advance;
            assert_true(short_by > -1e-9 && short_by < 1.0 + 1e-9);
        }
        assert_true(started);
        /* ten turns (100000 counts) in the window */
        assert_true(llabs(true_advance) > 10 * (int64_t)CPR - 10);
    }
}

/* ---- Current kinds: a current loop on a locked rotor --------------------- */

#define I_Q_REF_A 3.0f

/* The drive runs 3 A of i_q on the locked rotor at theta_e = 0: phase b
 * carries 3 sin(120 deg) = +2.6 A, phase c -2.6 A, phase a none. */
static void start_current_loop(void)
{
    plant_config_default(&pc);
    pc.substeps_per_period = PLANT_SUBSTEPS_FAST;
    pc.locked_rotor = true;
    mc_config_init_default(&fc);
    sim_engine_firmware_from_plant(&pc, &fc);
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
}

static const sim_trace_sample_t *current_step(void)
{
    const mc_command_t cmd = { .enable = true, .mode = MC_MODE_CURRENT, .i_q_ref_A = I_Q_REF_A };
    assert_int_equal(sim_engine_step(engine, &cmd), SIM_ENGINE_OK);
    return sim_engine_last(engine);
}

/* The phases other than `phase` measure their true current exactly. */
static void others_exact(const sim_trace_sample_t *s, uint32_t phase)
{
    for (uint32_t x = 0u; x < 3u; ++x) {
        if (x != phase) {
            assert_true(s->meas.i_abc_A[x] == s->plant.i_abc_A[x]);
        }
    }
}

static void current_offset_ramp_grows_at_its_rate(void **state)
{
    (void)state;
    start_current_loop();
    const double rate_A_s = 200.0;
    const sim_injection_t ramp = { .kind = SIM_INJECT_CURRENT_OFFSET_RAMP,
                                   .t_start_s = 0.10002, /* between samples */
                                   .t_end_s = 0.12002,
                                   .phase = 1u,
                                   .rate_A_s = rate_A_s };
    /* a fixed offset on the same phase over part of the ramp: both add */
    const sim_injection_t offset = { .kind = SIM_INJECT_CURRENT_OFFSET,
                                     .t_start_s = 0.11002,
                                     .t_end_s = 0.11502,
                                     .phase = 1u,
                                     .value = 0.5 };
    assert_int_equal(sim_engine_add_injection(engine, &ramp), SIM_ENGINE_OK);
    assert_int_equal(sim_engine_add_injection(engine, &offset), SIM_ENGINE_OK);
    int n_ramp = 0;
    for (int k = 0; k < 2600; ++k) { /* 0.13 s */
        const sim_trace_sample_t *s = current_step();
        const bool ramp_on = in_window(&ramp, s->t_s);
        const bool offset_on = in_window(&offset, s->t_s);
        assert_int_equal(s->injections_active, (ramp_on ? 1u : 0u) | (offset_on ? 2u : 0u));
        others_exact(s, 1u);
        if (!ramp_on) {
            assert_true(s->meas.i_abc_A[1] == s->plant.i_abc_A[1]);
            continue;
        }
        /* sample 2001 + n is at 0.10005 + n 50 us: the ramp is 200 A/s *
         * (30 us + n 50 us) = 6 mA + n 10 mA */
        const double expected_ramp_A = 0.006 + 0.01 * n_ramp;
        const double expected_A =
            s->plant.i_abc_A[1] + expected_ramp_A + (offset_on ? offset.value : 0.0);
        assert_true(fabs(s->meas.i_abc_A[1] - expected_A) < 1e-9);
        if (n_ramp == 0) {
            /* the drive is running a real current when the ramp starts */
            assert_int_equal(s->fw.state, MC_STATE_RUN);
            assert_true(fabs(s->plant.i_abc_A[1] - 2.6) < 0.1);
        }
        n_ramp++;
    }
    assert_int_equal(n_ramp, 400); /* samples 2001 .. 2400 */
}

typedef struct {
    uint32_t phase;
    double value_A;
} stuck_case_t;

static void current_stuck_reports_its_value(void **state)
{
    (void)state;
    const stuck_case_t cases[] = {
        { 2u, 0.0 }, /* stuck at zero */
        { 1u, -7.25 },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        start_current_loop();
        const sim_injection_t stuck = { .kind = SIM_INJECT_CURRENT_STUCK,
                                        .t_start_s = 0.10002,
                                        .t_end_s = 0.11002,
                                        .phase = cases[c].phase,
                                        .value = cases[c].value_A };
        assert_int_equal(sim_engine_add_injection(engine, &stuck), SIM_ENGINE_OK);
        int n_active = 0;
        double true_spread_A = 0.0;      /* largest |true - stuck value| while stuck */
        for (int k = 0; k < 2400; ++k) { /* 0.12 s */
            const sim_trace_sample_t *s = current_step();
            const bool active = in_window(&stuck, s->t_s);
            assert_int_equal(s->injections_active, active ? 1u : 0u);
            others_exact(s, stuck.phase);
            const double i_true_A = s->plant.i_abc_A[stuck.phase];
            assert_true(s->meas.i_abc_A[stuck.phase] == (active ? stuck.value : i_true_A));
            if (active) {
                true_spread_A = fmax(true_spread_A, fabs(i_true_A - stuck.value));
                n_active++;
            }
        }
        assert_int_equal(n_active, 200);  /* samples 2001 .. 2200 */
        assert_true(true_spread_A > 2.0); /* the true current differed */
    }
}

/* current_gain then current_offset on one phase (paper 002 Case II's
 * phase a: gain 1.05, offset -0.5 A; here on phase b, which carries the
 * current at theta_e = 0): the measurement is 1.05 i - 0.5 in their window,
 * in the order they were added; a gain on another phase (c: 0.96) scales
 * that phase alone. */
static void current_gain_scales_in_order(void **state)
{
    (void)state;
    start_current_loop();
    const sim_injection_t gain_b = { .kind = SIM_INJECT_CURRENT_GAIN,
                                     .t_start_s = 0.10002,
                                     .t_end_s = 0.11002,
                                     .phase = 1u,
                                     .value = 1.05 };
    const sim_injection_t offset_b = { .kind = SIM_INJECT_CURRENT_OFFSET,
                                       .t_start_s = 0.10002,
                                       .t_end_s = 0.11002,
                                       .phase = 1u,
                                       .value = -0.5 };
    const sim_injection_t gain_c = { .kind = SIM_INJECT_CURRENT_GAIN,
                                     .t_start_s = 0.10502,
                                     .t_end_s = INFINITY,
                                     .phase = 2u,
                                     .value = 0.96 };
    assert_int_equal(sim_engine_add_injection(engine, &gain_b), SIM_ENGINE_OK);
    assert_int_equal(sim_engine_add_injection(engine, &offset_b), SIM_ENGINE_OK);
    assert_int_equal(sim_engine_add_injection(engine, &gain_c), SIM_ENGINE_OK);
    int n_b = 0;
    int n_c = 0;
    for (int k = 0; k < 2400; ++k) { /* 0.12 s */
        const sim_trace_sample_t *s = current_step();
        const bool b_on = in_window(&gain_b, s->t_s);
        const bool c_on = in_window(&gain_c, s->t_s);
        const double i_b = s->plant.i_abc_A[1];
        const double i_c = s->plant.i_abc_A[2];
        assert_true(fabs(s->meas.i_abc_A[1] - (b_on ? 1.05 * i_b - 0.5 : i_b)) < 1e-12);
        assert_true(fabs(s->meas.i_abc_A[2] - (c_on ? 0.96 * i_c : i_c)) < 1e-12);
        assert_true(s->meas.i_abc_A[0] == s->plant.i_abc_A[0]);
        if (b_on) {
            assert_true(fabs(i_b) > 1.0); /* a real current is scaled */
            n_b++;
        }
        if (c_on) {
            assert_true(fabs(i_c) > 1.0);
            n_c++;
        }
    }
    assert_int_equal(n_b, 200); /* samples 2001 .. 2200 */
    assert_int_equal(n_c, 299); /* samples 2101 .. 2399 */
}

/* ---- Validation ---------------------------------------------------------- */

typedef struct {
    sim_injection_t inj;
    const char *field; /* the message names it */
} bad_case_t;

static void invalid_fields_are_rejected_by_name(void **state)
{
    (void)state;
    start_coasting(0.0, 0.0);
    const bad_case_t bad[] = {
        { { .kind = SIM_INJECT_ENCODER_SLIP, .t_end_s = 1.0, .angle_e_rad = NAN }, "angle_e_rad" },
        { { .kind = SIM_INJECT_ENCODER_SLIP, .t_end_s = 1.0, .angle_e_rad = INFINITY },
          "angle_e_rad" },
        { { .kind = SIM_INJECT_ENCODER_COUNT_LOSS, .t_end_s = 1.0, .lost_fraction = 0.0 },
          "lost_fraction" },
        { { .kind = SIM_INJECT_ENCODER_COUNT_LOSS, .t_end_s = 1.0, .lost_fraction = 1.0 },
          "lost_fraction" },
        { { .kind = SIM_INJECT_ENCODER_COUNT_LOSS, .t_end_s = 1.0, .lost_fraction = -0.5 },
          "lost_fraction" },
        { { .kind = SIM_INJECT_ENCODER_COUNT_LOSS, .t_end_s = 1.0, .lost_fraction = NAN },
          "lost_fraction" },
        { { .kind = SIM_INJECT_CURRENT_OFFSET_RAMP, .t_end_s = 1.0, .rate_A_s = NAN }, "rate_A_s" },
        { { .kind = SIM_INJECT_CURRENT_OFFSET_RAMP, .t_end_s = 1.0, .phase = 3u }, "phase" },
        { { .kind = SIM_INJECT_CURRENT_STUCK, .t_end_s = 1.0, .value = -INFINITY }, "value" },
        { { .kind = SIM_INJECT_CURRENT_STUCK, .t_end_s = 1.0, .phase = 3u }, "phase" },
        { { .kind = SIM_INJECT_ENCODER_FROZEN, .t_start_s = 2.0, .t_end_s = 1.0 }, "start" },
        { { .kind = SIM_INJECT_CURRENT_GAIN, .t_end_s = 1.0, .value = 0.0 }, "gain" },
        { { .kind = SIM_INJECT_CURRENT_GAIN, .t_end_s = 1.0, .value = NAN }, "gain" },
        { { .kind = SIM_INJECT_CURRENT_GAIN, .t_end_s = 1.0, .value = 1.0, .phase = 3u }, "phase" },
        { { .kind = SIM_INJECT_DEAD_TIME, .t_end_s = 1.0, .value = -1e-6 }, "dead_time_s" },
        { { .kind = SIM_INJECT_DEAD_TIME, .t_end_s = 1.0, .value = INFINITY }, "dead_time_s" },
        /* half the default 50 us period */
        { { .kind = SIM_INJECT_DEAD_TIME, .t_end_s = 1.0, .value = 25e-6 }, "dead_time_s" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(sim_engine_add_injection(engine, &bad[i].inj), SIM_ENGINE_ERR_INJECTION);
        assert_non_null(strstr(sim_engine_message(engine), bad[i].field));
    }
    assert_int_equal(engine->n_injections, 0u);
    /* the fields each kind does not use are not checked */
    const sim_injection_t frozen = { .kind = SIM_INJECT_ENCODER_FROZEN,
                                     .t_end_s = INFINITY,
                                     .phase = 7u,
                                     .value = NAN,
                                     .rate_A_s = NAN };
    assert_int_equal(sim_engine_add_injection(engine, &frozen), SIM_ENGINE_OK);
    assert_string_equal(sim_engine_message(engine), "ok");

    /* an encoder fault needs an encoder: a sensorless drive without one */
    plant_config_default(&pc);
    pc.sensors.encoder.lines = 0u;
    mc_config_init_default(&fc);
    sim_engine_firmware_from_plant(&pc, &fc);
    fc.estimator = MC_ESTIMATOR_FLUX_PLL;
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
    const sim_inject_kind_t encoder_kinds[] = { SIM_INJECT_ENCODER_SLIP, SIM_INJECT_ENCODER_FROZEN,
                                                SIM_INJECT_ENCODER_COUNT_LOSS };
    for (size_t i = 0; i < 3; ++i) {
        const sim_injection_t inj = {
            .kind = encoder_kinds[i], .t_end_s = 1.0, .angle_e_rad = 1.0, .lost_fraction = 0.5
        };
        assert_int_equal(sim_engine_add_injection(engine, &inj), SIM_ENGINE_ERR_INJECTION);
        assert_non_null(strstr(sim_engine_message(engine), "encoder.lines"));
    }
    /* the current kinds are fine there */
    const sim_injection_t stuck = { .kind = SIM_INJECT_CURRENT_STUCK, .t_end_s = 1.0 };
    assert_int_equal(sim_engine_add_injection(engine, &stuck), SIM_ENGINE_OK);

    /* an engine whose init failed takes no injection */
    pc.substeps_per_period = 0u;
    assert_int_not_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
    assert_int_equal(sim_engine_add_injection(engine, &stuck), SIM_ENGINE_ERR_STATE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(encoder_slip_shifts_by_whole_counts),
        cmocka_unit_test(encoder_frozen_holds_the_first_active_count),
        cmocka_unit_test(encoder_count_loss_keeps_the_fraction),
        cmocka_unit_test(current_offset_ramp_grows_at_its_rate),
        cmocka_unit_test(current_stuck_reports_its_value),
        cmocka_unit_test(current_gain_scales_in_order),
        cmocka_unit_test(invalid_fields_are_rejected_by_name),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
