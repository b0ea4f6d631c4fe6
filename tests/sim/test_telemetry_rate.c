/*
 * The drive with timing.telemetry_every_isr off (mc/timing.h: its steady
 * RUN ISRs between slow ticks do not write the telemetry record and keep
 * the blocks' values in a scratch record instead) against the same drive
 * with it on, in closed loop on shipped scenarios, one per controller and
 * estimator: two engines on the same plant (noise seeds included) step
 * side by side.
 *
 * Expectation (the same mathematics, only the record's stores differ):
 *   - the plant's state, the duties and the outputs of the two are equal
 *     bit for bit at every period;
 *   - every record the second one writes equals the first one's record of
 *     that ISR bit for bit (the ISR's cost and the overrun count aside:
 *     host wall time);
 *   - the second one leaves the record untouched in N - 1 of every N RUN
 *     ISRs (N: the slow decimation) less 1 % of them (an ISR over its
 *     deadline in host wall time sends the next one to the instance that
 *     writes), so the comparison covers the path that does not write it;
 *   - a NaN phase current injected into an ISR between two slow ticks
 *     latches MC_FAULT_NONFINITE in that same ISR in both, with equal
 *     fault events (the sample's currents, bus and speed).
 */
#include "mc_test.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shipped_scenario.h"

/* The RUN ISRs compared before the fault is injected. */
#define RUN_ISRS_COMPARED 4000u

typedef struct {
    sim_engine_t *every; /* telemetry_every_isr on (the bench's) */
    sim_engine_t *lean;  /* off */
    scenario_t scn;
    uint32_t run_isrs;      /* RUN ISRs of the lean engine so far */
    uint32_t run_untouched; /* ... that left the record as it was */
} twins_t;

static void assert_same_plant(const plant_true_state_t *a, const plant_true_state_t *b)
{
    const double va[] = { a->t_s,           a->i_abc_A[0],  a->i_abc_A[1], a->i_abc_A[2],
                          a->omega_m_rad_s, a->theta_m_rad, a->v_abc_V[0], a->v_abc_V[1],
                          a->v_abc_V[2],    a->v_dc_V };
    const double vb[] = { b->t_s,           b->i_abc_A[0],  b->i_abc_A[1], b->i_abc_A[2],
                          b->omega_m_rad_s, b->theta_m_rad, b->v_abc_V[0], b->v_abc_V[1],
                          b->v_abc_V[2],    b->v_dc_V };
    assert_memory_equal(va, vb, sizeof va);
    assert_int_equal(a->outputs_enabled, b->outputs_enabled);
}

/* The record bit for bit, but for the wall-time fields. */
static void assert_same_record(mc_telemetry_t a, mc_telemetry_t b)
{
    a.isr_cost_s = b.isr_cost_s = 0.0f;
    a.isr_cost_max_s = b.isr_cost_max_s = 0.0f;
    a.isr_overruns = b.isr_overruns = 0u;
    assert_memory_equal(&a, &b, sizeof a);
}

/* One period of both; the lean engine's record compared when it wrote one. */
static void step_twins(twins_t *w, const mc_command_t *cmd)
{
    const uint32_t published_before = sim_engine_last(w->lean)->fw.isr_count;
    const mc_state_t state_before = sim_engine_last(w->every)->fw.state;
    assert_int_equal(sim_engine_step(w->every, cmd), SIM_ENGINE_OK);
    assert_int_equal(sim_engine_step(w->lean, cmd), SIM_ENGINE_OK);
    const sim_trace_sample_t *a = sim_engine_last(w->every);
    const sim_trace_sample_t *b = sim_engine_last(w->lean);
    assert_same_plant(&a->plant, &b->plant);
    assert_memory_equal(a->duty_applied, b->duty_applied, sizeof a->duty_applied);
    assert_int_equal(a->outputs_applied, b->outputs_applied);
    const bool written = b->fw.isr_count != published_before;
    if (written) {
        assert_same_record(a->fw, b->fw);
    }
    if (state_before == MC_STATE_RUN && a->fw.state == MC_STATE_RUN) {
        w->run_isrs++;
        if (!written) {
            /* only a steady RUN ISR between slow ticks leaves it */
            assert_false(a->fw.slow_loop_ran);
            w->run_untouched++;
        }
    }
}

static void twins_init(twins_t *w, const char *file)
{
    w->every = shipped_scenario_engine(file, NULL, 0, &w->scn);
    mc_config_t fc = w->scn.firmware;
    assert_true(fc.timing.telemetry_every_isr); /* the bench's */
    fc.timing.telemetry_every_isr = false;
    w->lean = malloc(sizeof *w->lean);
    assert_non_null(w->lean);
    assert_int_equal(sim_engine_init(w->lean, &w->scn.plant, &fc), SIM_ENGINE_OK);
    for (size_t i = 0; i < w->scn.n_injections; ++i) {
        assert_int_equal(sim_engine_add_injection(w->lean, &w->scn.injections[i]), SIM_ENGINE_OK);
    }
    w->run_isrs = 0u;
    w->run_untouched = 0u;
}

static void run_file(const char *file)
{
    static twins_t w;
    twins_init(&w, file);
    const double Ts = sim_engine_period_s(w.every);
    /* RUN_ISRS_COMPARED RUN ISRs of the scenario's command */
    uint32_t guard = 0u;
    while (w.run_isrs < RUN_ISRS_COMPARED) {
        const mc_command_t cmd = scenario_command_at(&w.scn.reference, sim_engine_time_s(w.every));
        step_twins(&w, &cmd);
        assert_int_equal(sim_engine_last(w.every)->fw.faults_latched, 0u);
        assert_true(++guard < 20u * RUN_ISRS_COMPARED + 200000u); /* RUN reached */
    }
    const uint32_t n_slow = mc_app_timing(&w.lean->app)->slow_decimation;
    assert_true(n_slow >= 4u); /* the fault below falls between two ticks */
    assert_true(w.run_untouched + w.run_isrs / n_slow + w.run_isrs / 100u >= w.run_isrs);
    /* Up to a RUN ISR that wrote the record (a slow tick), then a NaN
     * phase current in the third ISR after it, which does not write it. */
    bool written = false;
    do {
        const uint32_t before = sim_engine_last(w.lean)->fw.isr_count;
        const mc_command_t cmd = scenario_command_at(&w.scn.reference, sim_engine_time_s(w.every));
        step_twins(&w, &cmd);
        written = sim_engine_last(w.lean)->fw.isr_count != before;
    } while (!written || sim_engine_last(w.lean)->fw.state != MC_STATE_RUN);
    const uint64_t k_fault = sim_engine_last(w.every)->k + 3u;
    const sim_injection_t nan_a = { .kind = SIM_INJECT_CURRENT_NAN,
                                    .t_start_s = ((double)k_fault - 0.25) * Ts,
                                    .t_end_s = ((double)k_fault + 0.75) * Ts,
                                    .phase = 0u };
    assert_int_equal(sim_engine_add_injection(w.every, &nan_a), SIM_ENGINE_OK);
    assert_int_equal(sim_engine_add_injection(w.lean, &nan_a), SIM_ENGINE_OK);
    const uint32_t published = sim_engine_last(w.lean)->fw.isr_count;
    for (int n = 0; n < 6; ++n) {
        const mc_command_t cmd = scenario_command_at(&w.scn.reference, sim_engine_time_s(w.every));
        step_twins(&w, &cmd);
        /* the faulting ISR is the third that leaves the record; the
         * ISRs in FAULT write it */
        assert_int_equal(sim_engine_last(w.lean)->fw.isr_count == published, n < 3);
    }
    const sim_trace_sample_t *a = sim_engine_last(w.every);
    assert_int_equal(a->fw.state, MC_STATE_FAULT);
    assert_int_equal(a->fw.first_fault, MC_FAULT_NONFINITE);
    mc_fault_event_t ev[2][2];
    uint32_t n_ev[2];
    assert_int_equal(mc_app_fault_history(&w.every->app, ev[0], 2u, &n_ev[0]), MC_OK);
    assert_int_equal(mc_app_fault_history(&w.lean->app, ev[1], 2u, &n_ev[1]), MC_OK);
    assert_int_equal(n_ev[0], 1u);
    assert_int_equal(n_ev[1], 1u);
    assert_int_equal(ev[0][0].isr_count, (uint32_t)k_fault + 1u);
    assert_true(isnan(ev[0][0].i_abc_A[0]));
    assert_memory_equal(&ev[0][0], &ev[1][0], sizeof ev[0][0]);
    printf("%s: %u RUN ISRs equal, %u of them without the record's stores; the NaN "
           "at ISR %u latched alike\n",
           file, (unsigned)w.run_isrs, (unsigned)w.run_untouched, (unsigned)ev[0][0].isr_count);
    free(w.every);
    free(w.lean);
}

/* state: the scenario file */
static void test_scenario(void **state)
{
    run_file((const char *)*state);
}

int main(void)
{
    /* one per controller and estimator */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_prestate(test_scenario, "paper001_benchmark_foc.json"),
        cmocka_unit_test_prestate(test_scenario, "paper001_benchmark_idapbc.json"),
        cmocka_unit_test_prestate(test_scenario, "paper001_benchmark_nam.json"),
        cmocka_unit_test_prestate(test_scenario, "paper000_eeo_case2.json"),
        cmocka_unit_test_prestate(test_scenario, "paper002_case1_cdobc.json"),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
